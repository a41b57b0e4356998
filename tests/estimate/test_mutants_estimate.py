"""Geometry coefficients against second methods (issue #13: mutants bench/mutation.py found alive).

Each test pins a formula a deliberate mutation changed without any test noticing: the solid
inertia tensors, the spheroid's added inertia, the cylinder's strip-theory pitch/yaw added
inertia and its short-body axial limit, and the Reynolds-number check.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.estimate.shapes import cylinder, solid_inertia, sphere_drag_coefficient, spheroid

GRID = 120  # midpoints per axis of the box enclosing the body


def grid_inertia(inside, half: tuple[float, float, float], mass: float) -> np.ndarray:
    """Second method: the inertia tensor of a uniform solid by a midpoint rule on a 3-D grid."""
    axes = [(np.arange(GRID) + 0.5) / GRID * 2 * h - h for h in half]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    w = inside(x, y, z).astype(float)
    w *= mass / w.sum()
    return np.diag([np.sum(w * (y * y + z * z)), np.sum(w * (x * x + z * z)), np.sum(w * (x * x + y * y))])


@pytest.mark.parametrize(
    "shape,dims,inside,half",
    [
        ("sphere", {"diameter": 0.4}, lambda x, y, z: x * x + y * y + z * z <= 0.04, (0.2, 0.2, 0.2)),
        (
            "spheroid",
            {"length": 0.8, "diameter": 0.3},
            lambda x, y, z: (x / 0.4) ** 2 + (y * y + z * z) / 0.15**2 <= 1,
            (0.4, 0.15, 0.15),
        ),
        (
            "cylinder",
            {"length": 0.6, "diameter": 0.2},
            lambda x, y, z: (y * y + z * z <= 0.01) & (np.abs(x) <= 0.3),
            (0.3, 0.1, 0.1),
        ),
        (
            "block",
            {"length": 0.5, "width": 0.3, "height": 0.2},
            lambda x, y, z: np.ones_like(x, bool),
            (0.25, 0.15, 0.1),
        ),
    ],
)
def test_solid_inertia_equals_a_grid_integration(shape, dims, inside, half):
    mass = 7.0
    got = solid_inertia(shape, mass, dims)
    ref = grid_inertia(inside, half, mass)
    # 120 cells across: the staircase surface of a curved body errs by ~1 % (the block by 1e-4)
    np.testing.assert_allclose(got, ref, rtol=0.015, atol=1e-12)


def test_spheroid_added_mass_uses_lambs_printed_coefficients():
    # Lamb (1932) §373 for a/b = 4 (SPEC §8): k1 = 0.08156, k2 = 0.85976, k′ = 0.60794;
    # A11 = k1 ρV, A22 = A33 = k2 ρV, A55 = A66 = k′ (ρV/5)(a² + b²), V = 4/3 π a b²
    rho, a, b = 1025.0, 0.4, 0.1
    rv = rho * 4 / 3 * math.pi * a * b * b
    MA = spheroid(2 * a, 2 * b, density=rho).added_mass
    expected = [0.08156 * rv, 0.85976 * rv, 0.85976 * rv, 0.0]
    expected += [0.60794 * rv / 5 * (a * a + b * b)] * 2
    # the coefficients are printed to 5 digits
    np.testing.assert_allclose(np.diag(MA), expected, rtol=1e-4)


def test_cylinder_pitch_added_inertia_is_the_strip_integral():
    # strip theory: each slice dx at x carries the 2-D added mass ρ C_a π D²/4 dx, so
    # A55 = ∫ x² dA22 over −L/2…L/2 = A22 L²/12 (DNV-RP-H103 §A; SPEC §2.3)
    L, D = 1.2, 0.2
    MA = cylinder(L, D).added_mass
    x = np.linspace(-L / 2, L / 2, 20001)
    per_length = MA[1, 1] / L
    strip = float(np.sum(0.5 * (x[1:] ** 2 + x[:-1] ** 2) * np.diff(x))) * per_length
    # trapezoid rule on 20 000 intervals of x²: relative error ~1e-9
    assert MA[4, 4] == pytest.approx(strip, rel=1e-7)
    assert MA[5, 5] == pytest.approx(strip, rel=1e-7)


def test_short_cylinder_axial_added_mass_meets_the_sphere_limit():
    # L/D ≤ 1 takes the sphere's k1 = ½ (Lamb §92); longer bodies Lamb's spheroid k1, which
    # tends to ½ as a/b → 1: the two sides agree at L/D = 1
    rho, D = 1000.0, 0.2
    short = cylinder(D, D, density=rho, axial_model="spheroid")
    V = math.pi * D**2 / 4 * D
    assert short.added_mass[0, 0] == pytest.approx(0.5 * rho * V, rel=1e-12)
    longer = cylinder(1.001 * D, D, density=rho, axial_model="spheroid")
    assert longer.added_mass[0, 0] / (rho * 1.001 * V) == pytest.approx(0.5, rel=2e-3)


def test_sphere_drag_needs_a_positive_reynolds_number():
    with pytest.raises(InputError, match="Reynolds number = 0"):
        sphere_drag_coefficient(0.0)


def test_composite_centres_are_mass_and_volume_weighted_means():
    # two parts, the second turned 90° in yaw: its own r_B = (0.1, 0, 0) points along common y
    from hydrokit.estimate.composite import Part, combine

    yaw90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    a = Part(
        "a", 2.0, 0.002, np.eye(3) * 0.01, np.zeros((6, 6)), r_b=np.array([0, 0, 0.1]), position=np.array([1.0, 0, 0])
    )
    b = Part(
        "b",
        6.0,
        0.006,
        np.eye(3) * 0.03,
        np.zeros((6, 6)),
        r_g=np.array([0.1, 0, 0]),
        r_b=np.array([0.1, 0, 0]),
        position=np.array([0, 2.0, 0]),
        rotation=yaw90,
    )
    comp = combine([a, b])
    cb_a, cb_b = np.array([1.0, 0, 0.1]), np.array([0, 2.1, 0])
    cg_a, cg_b = np.array([1.0, 0, 0]), np.array([0, 2.1, 0])
    np.testing.assert_allclose(comp.r_b, (0.002 * cb_a + 0.006 * cb_b) / 0.008, rtol=1e-12)
    np.testing.assert_allclose(comp.r_g, (2.0 * cg_a + 6.0 * cg_b) / 8.0, rtol=1e-12)
    # Steiner: I = Σ I_i + m_i (|d_i|² 1 − d_i d_iᵀ) about the composite CG
    I = np.zeros((3, 3))
    for m, Ii, c in ((2.0, 0.01, cg_a), (6.0, 0.03, cg_b)):
        d = c - comp.r_g
        I += np.eye(3) * Ii + m * (d @ d * np.eye(3) - np.outer(d, d))
    np.testing.assert_allclose(comp.inertia_cg, I, rtol=1e-12, atol=1e-15)


# --- second batch (issue #13): survivors of the seed-13 sample -------------------------------

CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
# outward quads of the unit cube (counter-clockwise seen from outside), 0-based
CUBE_Q = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]


def test_obj_quads_with_relative_indices_read_as_the_closed_unit_cube(tmp_path):
    # OBJ faces: 1-based, or negative = counted back from the last vertex so far; quads are
    # fanned into two triangles. Closed form: volume 1, 12 triangles, no open edge.
    from hydrokit.estimate.mesh import check_mesh, read_mesh

    lines = ["# a unit cube", "", *(f"v {x} {y} {z}" for x, y, z in CUBE_V), "vt 0 0", "vn 0 0 1"]
    for k, q in enumerate(CUBE_Q):
        # alternate absolute ("i/vt/vn") and relative indices
        idx = [f"{i + 1}/1/1" for i in q] if k % 2 == 0 else [str(i - len(CUBE_V)) for i in q]
        lines.append("f " + " ".join(idx))
    path = tmp_path / "cube.obj"
    path.write_text("\n".join(lines) + "\n")
    mesh = read_mesh(path)
    assert mesh.volume() == pytest.approx(1.0, rel=1e-12)
    assert len(mesh.triangles()) == 12
    check_mesh(mesh)


def _binary_stl(tris: np.ndarray) -> bytes:
    import struct

    out = bytearray(b"\0" * 80 + struct.pack("<I", len(tris)))
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0) + struct.pack("<9f", *np.asarray(t, float).ravel()) + b"\0\0"
    return bytes(out)


def test_binary_stl_tetrahedron_and_a_truncated_one(tmp_path):
    # the corner tetrahedron of the unit cube: volume 1/6 (closed form)
    from hydrokit.estimate.mesh import read_mesh

    o, x, y, z = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
    tris = np.array([(o, y, x), (o, x, z), (o, z, y), (x, y, z)], float)
    data = _binary_stl(tris)
    good = tmp_path / "tet.stl"
    good.write_bytes(data)
    assert read_mesh(good).volume() == pytest.approx(1 / 6, rel=1e-7)  # float32 vertices, exact here
    cut = tmp_path / "cut.stl"
    cut.write_bytes(data[:-30])  # the last triangle's record cut short
    with pytest.raises(InputError, match="announces 4 triangles but is truncated"):
        read_mesh(cut)


@pytest.mark.parametrize("scale", [1e-10, 1e-3, 1e6])
def test_closed_mesh_check_does_not_depend_on_the_length_unit(scale):
    # a closed triangle soup (every corner repeated per face) stays closed at any scale: the
    # vertex merge must be relative to the mesh size, not to one metre
    from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

    V = np.array(CUBE_V, float)
    tris = np.array([[V[q[0]], V[q[i]], V[q[i + 1]]] for q in CUBE_Q for i in (1, 2)]) * scale
    soup = SurfaceMesh(tris.reshape(-1, 3), np.arange(tris.shape[0] * 3).reshape(-1, 3), "soup")
    check_mesh(soup)
    assert soup.volume() == pytest.approx(scale**3, rel=1e-9)


def test_named_cylinder_mesh_has_the_cylinder_volume():
    # closed form π D² L / 4; an n-gon cross-section of the same radius has the area
    # (n/2) r² sin(2π/n), so with n = 48 panels around the volume is exact to rounding
    from hydrokit.estimate.bem import shape_mesh

    L, D, n = 0.8, 0.2, 48
    mesh = shape_mesh("cylinder", n, length=L, diameter=D)
    r = D / 2
    assert mesh.volume() == pytest.approx(n / 2 * r * r * math.sin(2 * math.pi / n) * L, rel=1e-9)
    assert mesh.volume() == pytest.approx(math.pi * D * D / 4 * L, rel=0.01)
    # the volume cannot see where a flat cap's fan meets or whether panels are planar: every
    # panel must lie on the side (radius r) or on one end cap (x = ±L/2, inside the disc),
    # and the mesh must be closed and outward for the BEM
    from hydrokit.estimate.mesh import check_mesh

    check_mesh(mesh)
    radius = np.hypot(mesh.vertices[:, 1], mesh.vertices[:, 2])
    assert radius.max() == pytest.approx(r, rel=1e-12)
    for face in mesh.faces:
        x, rad = mesh.vertices[face, 0], radius[face]
        on_cap = np.allclose(x, x[0], atol=1e-12) and abs(abs(x[0]) - L / 2) < 1e-12
        assert on_cap or np.allclose(rad, r, rtol=1e-12), face


@pytest.mark.parametrize("n", [6, 7, 24, 49])
@pytest.mark.parametrize(("length", "diameter"), [(0.5, 0.5), (8.0, 2.0), (0.2, 1.0)])
def test_sphere_and_spheroid_meshes_face_outwards_as_built(n, length, diameter):
    # the generated spheroid (a sphere when length = diameter) is closed and outward with no
    # reorientation: its volume is positive and tends to the ellipsoid's π L D² / 6
    from hydrokit.estimate.bem import shape_mesh
    from hydrokit.estimate.mesh import check_mesh

    mesh = shape_mesh("spheroid", n, length=length, diameter=diameter)
    check_mesh(mesh)
    exact = math.pi * length * diameter**2 / 6
    assert 0.5 * exact < mesh.volume() <= exact * (1 + 1e-12)  # inscribed panels: a little less


def test_an_edge_shared_by_three_faces_is_refused():
    # two tetrahedra glued along one edge plus a fin triangle on it: every edge has at least
    # two faces (closed), but the shared edge has three: not a simple hull
    from hydrokit.errors import InputError
    from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

    v = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], float)
    faces = np.array([(0, 2, 1, 1), (0, 1, 3, 3), (0, 3, 2, 2), (1, 2, 3, 3)])
    check_mesh(SurfaceMesh(v, faces, "tet.stl"))  # the tetrahedron alone is a simple closed hull
    fin = np.vstack([faces, [(0, 1, 2, 2), (0, 2, 1, 1)]])  # the base face twice more, both ways
    with pytest.raises(InputError, match=r"edge\(s\) shared by more than two faces; expected a simple closed hull"):
        check_mesh(SurfaceMesh(v, fin, "fin.stl"))
    # two tetrahedra either side of one face, kept once (an inner wall): closed, with exactly three
    # faces on each of that face's three edges
    wall = np.vstack([faces, [(0, 1, 4, 4), (1, 2, 4, 4), (2, 0, 4, 4)]])
    with pytest.raises(InputError, match=r"wall.stl: 3 edge\(s\) shared by more than two faces"):
        check_mesh(SurfaceMesh(np.vstack([v, [(0, 0, -1)]]), wall, "wall.stl"))


def test_force_fit_curves_are_the_chin_and_morison_laws():
    # synthetic F = K_L U + K_Q |U| U, fitted exactly; the Morison law is K_D |U| U
    from hydrokit.estimate.forces import fit_forces

    U = np.array([-1.2, -0.6, -0.2, 0.3, 0.7, 1.1, 1.5])
    fit = fit_forces(U, 4.0 * U + 30.0 * np.abs(U) * U, area=0.1, density=1000.0)
    assert fit.K_L == pytest.approx(4.0, rel=1e-9)
    assert fit.K_Q == pytest.approx(30.0, rel=1e-9)
    u = np.array([-0.9, 0.5, 1.3])
    np.testing.assert_allclose(fit.chin(u), 4.0 * u + 30.0 * np.abs(u) * u, rtol=1e-9)
    np.testing.assert_allclose(fit.morison(u), fit.K_D * np.abs(u) * u, rtol=1e-12)
    assert fit.morison(np.array([-2.0]))[0] == pytest.approx(-4.0 * fit.K_D, rel=1e-12)


def test_lander_dimensional_added_inertia_of_lingyun():
    # SPEC §2.2 (LI2021 eq. 7): M'_qdot = −1.33745e−2 and N'_rdot = −5.6888e−3 are divided by
    # ½ρL⁵, X'_udot = −5.8589e−2 by ½ρL³; Lingyun L = 1.25 m
    from hydrokit.estimate.lander import dimensional_added_mass

    rho, L = 1025.0, 1.25
    nd = {"X_udot": -5.8589e-2, "Y_vdot": -0.38083, "Z_wdot": -0.11718, "M_qdot": -1.33745e-2, "N_rdot": -5.6888e-3}
    out = dimensional_added_mass(nd, rho, L)
    assert out[0] == pytest.approx(5.8589e-2 * 0.5 * rho * L**3, rel=1e-12)
    assert out[4] == pytest.approx(1.33745e-2 * 0.5 * rho * L**5, rel=1e-12)
    assert out[5] == pytest.approx(5.6888e-3 * 0.5 * rho * L**5, rel=1e-12)


# DNV-RP-H103 (2010) Table A-2, flat rectangular plate, every row: C_A by b/a, V_R = π a² b / 4
PLATE_ROWS = [
    (1.0, 0.579), (1.25, 0.642), (1.5, 0.690), (1.59, 0.704), (2.0, 0.757), (2.5, 0.801), (3.0, 0.830),
    (3.17, 0.840), (4.0, 0.872), (5.0, 0.897), (6.25, 0.917), (8.0, 0.934), (10.0, 0.947),
]  # fmt: skip


@pytest.mark.parametrize("ratio,ca", PLATE_ROWS)
def test_plate_added_mass_rows_of_dnv_table_a2(ratio, ca):
    from hydrokit.estimate.shapes import flat_plate

    rho, a = 1000.0, 0.2
    p = flat_plate(length=ratio * a, width=a, density=rho)
    assert p.added_mass[0, 0] == pytest.approx(rho * ca * math.pi * a * a * (ratio * a) / 4, rel=1e-12)


def test_plate_added_mass_between_rows_is_linear_and_the_table_has_no_other_rows():
    from hydrokit.estimate import shapes

    assert [r for r in shapes.PLATE_CA if r[0] < 1e8] == PLATE_ROWS
    # half way between the 6.25 and 8.0 rows (an earlier transcription invented a 7.0 row here)
    p = shapes.flat_plate(length=7.125, width=1.0, density=1.0)
    assert p.added_mass[0, 0] / (math.pi * 7.125 / 4) == pytest.approx((0.917 + 0.934) / 2, rel=1e-12)


def test_coefficient_tables_are_ordered_and_tend_to_the_strip_limit():
    # np.interp needs strictly increasing ratios; C_A of a plate or a transverse cylinder and the
    # finite-length drag factor κ grow with the aspect ratio towards the 2-D strip value 1
    from hydrokit.estimate import shapes

    for table in (shapes.PLATE_CA, shapes.CYL_TRANSVERSE_CA, shapes.CYL_KAPPA):
        x = np.array([r for r, _ in table])
        c = np.array([v for _, v in table])
        assert np.all(np.diff(x) > 0)
        assert np.all(np.diff(c) >= 0) and c[-1] == 1.0 and np.all(c <= 1.0)
    x = np.array([r for r, _ in shapes.BLOCK_CA])
    assert np.all(np.diff(x) > 0)


@pytest.mark.parametrize(
    "ratio,kappa",
    [
        (1.0, 0.58),
        (2.0, 0.58),
        (5.0, 0.62),
        (10.0, 0.68),
        (20.0, 0.74),
        (40.0, 0.82),
        (50.0, 0.87),
        (100.0, 0.98),
        (200.0, 0.99),
        (400.0, 0.995),
    ],
)
def test_cylinder_transverse_drag_uses_the_finite_length_factor(ratio, kappa):
    # DNV-RP-C205 (2010) Table 6-2 (after Hoerner 1965), reduction factor κ for a cylinder of
    # finite length with free ends, subcritical flow: 0.58, 0.62, 0.68, 0.74, 0.82, 0.87, 0.98 at
    # λ = L/D = 2, 5, 10, 20, 40, 50, 100 (held below λ = 2), 1 for λ = ∞; the module takes
    # C_D = 1.05 κ. Beyond λ = 100 it goes linearly in 1/λ to the infinite limit:
    # κ = 1 − 0.02 · 100/λ (0.99 at 200, 0.995 at 400)
    D = 0.05
    c = cylinder(ratio * D, D)
    assert c.drag_coefficient[1] == pytest.approx(1.05 * kappa, rel=1e-12)
    assert c.drag_coefficient[2] == pytest.approx(1.05 * kappa, rel=1e-12)


def test_rehman_cylinder_transverse_drag_is_within_two_percent_of_table_1():
    # REHMAN Table 1: C_D = 0.65 across its 1 m × Ø0.25 m cylinder (L/D = 4); DNV κ(4) is
    # 0.58 + (0.62 − 0.58)·(4 − 2)/(5 − 2) = 0.6067, so 1.05 κ = 0.637
    c = cylinder(1.0, 0.25)
    assert c.drag_coefficient[1] == pytest.approx(1.05 * (0.58 + 0.04 * 2 / 3), rel=1e-12)
    assert abs(c.drag_coefficient[1] / 0.65 - 1) < 0.021  # 2.0 % under
    assert cylinder(1.0, 0.25, drag_transverse=0.65).sources["drag_coefficient"].endswith("0.650 (given)")


def test_lander_added_mass_magnitudes_are_positive_for_negative_derivatives():
    # hydrodynamic derivatives X_u̇ … are negative; the magnitudes are −X_u̇ ½ρL³ (forces) and
    # −M_q̇ ½ρL⁵ (moments), roll not given
    from hydrokit.estimate.lander import dimensional_added_mass

    nd = {"X_udot": -0.01, "Y_vdot": -0.02, "Z_wdot": -0.03, "M_qdot": -0.004, "N_rdot": -0.005}
    rho, L = 1025.0, 2.0
    q3, q5 = 0.5 * rho * 8.0, 0.5 * rho * 32.0
    assert dimensional_added_mass(nd, rho, L) == pytest.approx(
        [0.01 * q3, 0.02 * q3, 0.03 * q3, 0.0, 0.004 * q5, 0.005 * q5]
    )


def test_flat_plate_drag_runs_from_the_square_to_the_strip_and_only_normal():
    from hydrokit.estimate.shapes import flat_plate

    square = flat_plate(1.0, 1.0)
    assert square.drag_coefficient.tolist() == [1.17, 0.0, 0.0]  # Hoerner's square plate; in-plane none
    assert flat_plate(2.0, 0.5).reference_area.tolist() == [1.0, 0.0, 0.0]  # the face, normal to x only
    assert flat_plate(2.0, 1.0).drag_coefficient[0] == pytest.approx(1.17 + 0.83 * 0.5)
    assert flat_plate(1000.0, 1.0).drag_coefficient[0] == pytest.approx(2.0, abs=1e-3)  # 2-D strip


def test_thin_block_is_the_plate_of_its_other_two_sides():
    # DNV-RP-H103 Table A-2: a plate a × b moving normal to itself has m_a = ρ C_a(b/a) π a² b / 4;
    # a 1 cm thick block of 1 m × 2 m moving along its thickness is that plate (square prisms
    # cover only bodies longer along the motion than across)
    from hydrokit.estimate.shapes import block, flat_plate

    thin = block(0.01, 1.0, 2.0, density=1000.0)
    plate = flat_plate(2.0, 1.0, density=1000.0)
    assert thin.added_mass[0, 0] == pytest.approx(plate.added_mass[0, 0], rel=1e-12)
    # a 0.5 m × 2 m plate (b/a = 4: C_a = 0.872): ρ C_a π a² b / 4
    narrow = block(0.01, 0.5, 2.0, density=1000.0).added_mass[0, 0]
    assert narrow == pytest.approx(flat_plate(2.0, 0.5, density=1000.0).added_mass[0, 0], rel=1e-12)
    assert narrow == pytest.approx(1000.0 * 0.872 * math.pi * 0.25 * 2.0 / 4, rel=1e-3)
    assert thin.added_mass[0, 0] == pytest.approx(
        1000.0 * 0.757 * math.pi * 1.0 * 2.0 / 4, rel=1e-3
    )  # Table A-2: C_a(2) = 0.757
    # a cube uses the square prism's C_a = 0.68 with V_R = a³ in all three directions
    np.testing.assert_allclose(np.diag(block(1.0, 1.0, 1.0, density=1000.0).added_mass)[:3], 680.0)


def test_force_fit_standard_errors_match_curve_fit_and_nan_is_named():
    from scipy.optimize import curve_fit

    from hydrokit.estimate.forces import fit_forces

    rng = np.random.default_rng(4)
    U = np.linspace(-1.5, 1.5, 13)
    F = 3.0 * U + 20.0 * np.abs(U) * U + rng.normal(0.0, 0.5, U.size)
    fit = fit_forces(U, F, 0.1, 1000.0)
    p, pcov = curve_fit(lambda u, a, b: a * u + b * np.abs(u) * u, U, F, p0=(1.0, 1.0))  # s² (JᵀJ)⁻¹
    assert [fit.K_L, fit.K_Q] == pytest.approx(p, rel=1e-6)
    assert [fit.K_L_se, fit.K_Q_se] == pytest.approx(np.sqrt(np.diag(pcov)), rel=1e-5)
    # the one-coefficient Morison fit F = K_D |U|U: s² (JᵀJ)⁻¹ with n − 1 degrees of freedom
    (kd,), kd_cov = curve_fit(lambda u, k: k * np.abs(u) * u, U, F, p0=(1.0,))
    assert fit.K_D == pytest.approx(kd, rel=1e-6)
    assert fit.K_D_se == pytest.approx(math.sqrt(kd_cov[0, 0]), rel=1e-5)
    # R² = 1 − SSR/SST of each fit, by numpy
    sst = float(np.sum((F - F.mean()) ** 2))
    assert fit.r2_chin == pytest.approx(1 - float(np.sum((F - fit.chin(U)) ** 2)) / sst, rel=1e-12)
    assert fit.r2_morison == pytest.approx(1 - float(np.sum((F - fit.morison(U)) ** 2)) / sst, rel=1e-12)
    bad = U.copy()
    bad[2] = np.nan
    with pytest.raises(InputError) as err:
        fit_forces(bad, F, 0.1, 1000.0)
    assert (
        str(err.value) == "column 'speed' (m/s) holds nan at sample 2 (of 13 samples; 1 bad): expected finite numbers"
    )
    assert "force" not in repr(fit) and "speed" not in repr(fit)  # the data arrays stay out of the repr


def test_sphere_drag_defaults_to_sea_water_viscosity_and_parts_default_to_bem():
    # ν = 1.05e-6 m²/s (sea water near 18 °C): the default Re of a 0.1 m sphere at 1 m/s is 95 238
    from hydrokit.estimate.geometry import GeometryPart
    from hydrokit.estimate.shapes import sphere

    # (below Re = 1.2e5 the Mikhailov–Freire correlation)
    cd = sphere(0.1).drag_coefficient[0]
    assert cd == pytest.approx(sphere_drag_coefficient(0.1 / 1.05e-6, "Mikhailov-Freire"), rel=1e-12)
    assert cd != pytest.approx(sphere_drag_coefficient(0.1 / 1.0e-6, "Mikhailov-Freire"), rel=1e-6)
    assert GeometryPart(None, {}, "sphere", {"diameter": 0.1}).bem is True


def test_a_composite_of_parts_without_volume_has_its_buoyancy_centre_at_the_origin():
    # no displaced volume, no buoyancy: r_b is the origin (3 coordinates), r_g the mass centre
    from hydrokit.estimate.composite import Part, combine

    parts = [
        Part("a", 2.0, 0.0, np.eye(3), np.zeros((6, 6)), position=np.array([1.0, 0.0, 0.0])),
        Part("b", 2.0, 0.0, np.eye(3), np.zeros((6, 6)), position=np.array([-1.0, 2.0, 0.0])),
    ]
    c = combine(parts)
    assert np.asarray(c.r_b).tolist() == [0.0, 0.0, 0.0]
    assert np.asarray(c.r_g) == pytest.approx([0.0, 1.0, 0.0])


@pytest.mark.parametrize(
    ("ratio", "ca"),
    [(1.0, 0.68), (2.0, 0.36), (3.0, 0.24), (4.0, 0.19), (5.0, 0.15), (6.0, 0.13), (7.0, 0.11), (10.0, 0.08)],
)
def test_block_added_mass_is_dnv_table_a2_square_prisms(ratio, ca):
    # DNV-RP-H103 (2010) Table A-2, square prism moving along its length b (side a): C_A with
    # V_R = a² b, as transcribed in shapes.BLOCK_CA (the same numbers as quoted from memory of the
    # printed table; not yet checked against the page). A non-square section too: a = √(w h)
    from hydrokit.estimate.shapes import block

    assert block(ratio, 1.0, 1.0, density=1000.0).added_mass[0, 0] == pytest.approx(1000.0 * ca * ratio, rel=1e-12)
    w, h = 0.5, 2.0  # √(w h) = 1: the same table entry
    assert block(ratio, w, h, density=1000.0).added_mass[0, 0] == pytest.approx(1000.0 * ca * ratio, rel=1e-12)
    # the table is in b/a: a block of side 0.4 m and length 0.4·ratio m reads the same row
    small = block(0.4 * ratio, 0.4, 0.4, density=1000.0).added_mass[0, 0]
    assert small == pytest.approx(1000.0 * ca * 0.4**3 * ratio, rel=1e-12)


def test_short_cylinder_axial_added_mass_is_lambs_spheroid():
    # along its axis a cylinder of L/D = 1.5 takes the k1 of the spheroid with the same ratio
    # (Lamb's coefficient, SPEC §8), V_R = the cylinder's volume; a disc-like one (L/D ≤ 1) takes 0.5
    from hydrokit.estimate.shapes import lamb_coefficients

    c = cylinder(1.5, 1.0, density=1000.0)
    k1 = lamb_coefficients(0.75, 0.5)[0]
    assert c.added_mass[0, 0] == pytest.approx(1000.0 * k1 * math.pi / 4 * 1.5, rel=1e-12)
    assert 0.2 < k1 < 0.5


def test_parser_words_are_kept_unless_meshio_says_nothing():
    from hydrokit.estimate.mesh import _why

    assert _why(ValueError("bad facet"), "STL") == "ValueError: bad facet"
    assert _why(ValueError(""), "STL") == "ValueError"
    assert _why(ValueError("x\n  y"), "OBJ") == "ValueError: x y"
    # cut to 160 characters: "ValueError: " is 12, so 148 words' characters stay whole, 149 are cut
    assert _why(ValueError("y" * 148), "OBJ") == "ValueError: " + "y" * 148
    assert _why(ValueError("y" * 149), "OBJ").endswith("(161 characters)")


def test_estimate_results_are_immutable():
    import dataclasses

    from hydrokit.estimate.composite import Composite, Part
    from hydrokit.estimate.forces import ForceFit
    from hydrokit.estimate.geometry import Estimate
    from hydrokit.estimate.mesh import SurfaceMesh
    from hydrokit.estimate.shapes import ShapeCoefficients

    for cls in (Composite, Part, Estimate, ForceFit, SurfaceMesh, ShapeCoefficients):
        assert dataclasses.fields(cls)  # a dataclass
        assert cls.__dataclass_params__.frozen, cls  # type: ignore[attr-defined]


def test_rotated_drag_warning_only_for_parts_with_drag():
    # a part with per-axis drag turned by 30°: |R| turns it only approximately, and that is said;
    # a part without drag turned the same way has nothing to approximate
    from hydrokit.estimate.composite import Part, combine, rotation_from_degrees

    R = rotation_from_degrees(yaw=30.0)
    dragged = Part("fin", 1.0, 0.001, np.eye(3), np.zeros((6, 6)), quadratic_damping=np.diag([5.0] * 6), rotation=R)
    bare = Part("box", 1.0, 0.001, np.eye(3), np.zeros((6, 6)), rotation=R)
    warned = [w for w in combine([dragged, bare]).warnings if "not a multiple of 90°" in w]
    assert len(warned) == 1 and warned[0].startswith("part fin:")


@pytest.mark.parametrize("mode", ["elements", "rehman"])
def test_off_diagonal_quadratic_damping_is_named_only_where_there_is_some(mode):
    # drag laws are per axis: a part's off-diagonal quadratic damping (here Y from |u|u) is dropped
    # and that is said, for that part alone; the "shifted" mode moves whole matrices (Hᵀ D H)
    from hydrokit.estimate.composite import Part, combine

    cross = np.diag([5.0] * 6)
    cross[1, 0] = 2.0
    coupled = Part("hull", 1.0, 0.001, np.eye(3), np.zeros((6, 6)), quadratic_damping=cross)
    plain = Part("fin", 1.0, 0.001, np.eye(3), np.zeros((6, 6)), quadratic_damping=np.diag([5.0] * 6))
    warned = [w for w in combine([coupled, plain], mode).warnings if "off-diagonal" in w]
    assert warned == ["part hull: off-diagonal quadratic damping ignored (a drag law per axis)"]
    assert not [w for w in combine([coupled, plain], "shifted").warnings if "off-diagonal" in w]


def test_a_shape_part_without_speed_takes_the_documented_one_metre_per_second():
    # the geometry file's `speed` defaults to 1.0 m/s (io/geometry.py); the Python API alike:
    # a sphere's Reynolds-dependent drag then equals the one at 1 m/s, not at 2 m/s
    from hydrokit.estimate.geometry import shape_part

    def ball(**kw):
        gp = shape_part(
            "ball", "sphere", 30.0, {"diameter": 0.5}, np.zeros(3), np.eye(3), density=1025.0, gravity=9.81, **kw
        )
        return np.diag(gp.part.quadratic_damping)

    np.testing.assert_array_equal(ball(), ball(speed=1.0))
    assert not np.array_equal(ball(), ball(speed=2.0))


@pytest.mark.parametrize("axial_model", ["spheroid", "rehman"])
def test_a_circular_cylinder_has_no_roll_added_mass(axial_model):
    # turning a circular section about its own axis displaces no fluid (ideal flow): K_ṗ = 0,
    # while pitch and yaw have the strip-theory value ρ C_a (π D²/4) L³/12 and the matrix is diagonal
    from hydrokit.estimate.shapes import cylinder

    MA = cylinder(length=1.2, diameter=0.2, density=1025.0, axial_model=axial_model).added_mass
    assert MA[3, 3] == 0.0 and MA[4, 4] == MA[5, 5] > 0
    np.testing.assert_array_equal(MA, np.diag(np.diag(MA)))


def test_a_closed_mesh_enclosing_no_volume_is_named():
    # a tetrahedron squashed flat (all four vertices in z = 0): every edge shared by two faces,
    # volume exactly 0 (neither outward nor inward)
    from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, 0.3, 0.0]])
    f = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    with pytest.raises(InputError) as err:
        check_mesh(SurfaceMesh(v, f, "sheet.obj"))
    assert str(err.value) == "sheet.obj: the mesh encloses no volume"


def test_a_millimetre_scale_part_keeps_its_inertia_in_the_written_vehicle(tmp_path):
    # a 15 mm sphere of 3.7 g (a tank model's float): I = 2/5 m r² = 8.325e-8 kg·m² and
    # m_a = ½ ρ V (closed forms); the vehicle document must carry them to 1e-9 of themselves,
    # which fixed decimals (round(x, 9) → 8.3e-8) would not
    from hydrokit.estimate.geometry import estimate_geometry
    from hydrokit.io.geometry import parse_geometry

    d, m, rho = 0.015, 0.0037, 1025.0
    geo = parse_geometry(
        {"name": "float", "fluid": {"density": rho}, "parts": [{"shape": "sphere", "diameter": d, "mass": m}]},
        tmp_path / "float.yaml",
    )
    doc = estimate_geometry(geo).to_dict()
    r = d / 2
    inertia = np.asarray(doc["inertia"])
    np.testing.assert_allclose(np.diag(inertia), [0.4 * m * r * r] * 3, rtol=1e-9)
    volume = 4 / 3 * math.pi * r**3
    assert doc["volume"] == pytest.approx(volume, rel=1e-9)
    np.testing.assert_allclose(np.diag(np.asarray(doc["added_mass"]))[:3], [0.5 * rho * volume] * 3, rtol=1e-9)


@pytest.mark.parametrize("field", ["area", "density"])
@pytest.mark.parametrize("value", [0.0, -0.1, math.inf, math.nan])
def test_force_fit_needs_a_positive_finite_area_and_density(field, value):
    from hydrokit.estimate.forces import fit_forces

    U = np.array([0.5, 1.0, 1.5, 2.0])
    args = {"area": 0.1, "density": 1000.0, field: value}
    with pytest.raises(InputError, match=rf"^{field} = {value}: expected a positive number$"):
        fit_forces(U, 20.0 * U * U, **args)


def test_a_force_fit_from_coefficients_alone_is_immutable_and_has_no_rows():
    # a fit rebuilt from its JSON (coefficients, no data) tabulates nothing and stays as read
    import dataclasses

    from hydrokit.estimate.forces import ForceFit

    fit = ForceFit(3.0, 20.0, 0.1, 0.2, 0.99, 22.0, 0.3, 0.44, 0.98, 13)
    assert fit.table() == (["speed", "force", "chin", "morison"], [])
    with pytest.raises(dataclasses.FrozenInstanceError):
        fit.K_D = 0.0  # type: ignore[misc]


def test_a_spheroid_with_equal_axes_is_refused_not_divided_by_zero():
    from hydrokit.estimate.shapes import lamb_coefficients

    with pytest.raises(InputError, match=r"prolate spheroid needs a > b \(a = 1\.0, b = 1\.0 m\)"):
        lamb_coefficients(1.0, 1.0)
    k1, k2, _ = lamb_coefficients(1.0 + 1e-6, 1.0)  # the sphere limit: k1 = k2 = ½
    assert (k1, k2) == (pytest.approx(0.5, abs=1e-5), pytest.approx(0.5, abs=1e-5))


def test_block_drag_acts_on_the_face_across_each_motion():
    # a 0.6 × 0.3 × 0.2 m block: surge sees the 0.3 × 0.2 face, sway 0.6 × 0.2, heave 0.6 × 0.3;
    # K_Q = ½ ρ C_D A per axis
    from hydrokit.estimate.shapes import block

    rho, cd = 1025.0, 1.05
    c = block(0.6, 0.3, 0.2, density=rho, drag_coefficient=cd)
    np.testing.assert_allclose(
        c.quadratic_damping(rho)[:3], [0.5 * rho * cd * A for A in (0.06, 0.12, 0.18)], rtol=1e-12
    )


def test_estimate_table_has_one_row_per_dof_with_the_closed_form_sphere():
    # a 0.5 m sphere in sea water: ½ ρ V in each translation, nothing in rotation, no linear damping
    from pathlib import Path

    from hydrokit.core.names import DOF_NAMES
    from hydrokit.estimate.geometry import estimate_geometry
    from hydrokit.io.geometry import parse_geometry

    geo = parse_geometry({"parts": [{"shape": "sphere", "diameter": 0.5, "mass": 130.0}]}, Path("payload.yaml"))
    cols, rows = estimate_geometry(geo).table()
    assert cols[:4] == ["dof", "added_mass", "added_mass_diagonal_only", "linear_damping"]
    assert [r[0] for r in rows] == list(DOF_NAMES)
    half = 0.5 * 1025.0 * math.pi / 6 * 0.5**3
    np.testing.assert_allclose([r[1] for r in rows], [half] * 3 + [0.0] * 3, atol=1e-12)
    assert [r[3] for r in rows] == [0.0] * 6


@pytest.mark.parametrize("model", ["elements", "rehman", "shifted"])
def test_an_element_at_the_origin_keeps_its_linear_drag_in_every_model(model):
    # a point element at the body origin with linear drag in surge only (3 N·s/m) and quadratic
    # drag (5 N·s²/m²): in pure surge every model must give F = −(3u + 5u|u|), whether the
    # element is folded into the diagonals or kept as an element
    from hydrokit.core.drag import DragElement, drag_wrench, pack_elements
    from hydrokit.estimate.composite import Part, combine

    el = pack_elements([DragElement("probe", (0.0, 0.0, 0.0), (3.0, 0.0, 0.0), (5.0, 0.0, 0.0))])
    part = Part("probe", 1.0, 0.001, 0.01 * np.eye(3), np.zeros((6, 6)), drag_elements=el)
    comp = combine([part], model)
    for u in (0.5, -1.2):
        nu = np.array([u, 0, 0, 0, 0, 0])
        f = -comp.linear_damping[0] @ nu - comp.quadratic_damping[0, 0] * u * abs(u)
        if len(comp.drag_elements):
            f += drag_wrench(comp.drag_elements, nu)[0]
        assert f == pytest.approx(-(3.0 * u + 5.0 * u * abs(u)), rel=1e-12)


def test_shape_volumes_are_the_closed_forms():
    from hydrokit.estimate.shapes import block, flat_plate

    assert block(0.6, 0.3, 0.2).volume == pytest.approx(0.036, rel=1e-12)
    assert flat_plate(0.6, 0.3).volume == 0.0  # an ideal plate displaces nothing
    assert flat_plate(0.6, 0.3, thickness=0.01).volume == pytest.approx(0.0018, rel=1e-12)


def test_spheroid_reference_areas_are_its_silhouettes():
    # a prolate spheroid of length 2a along x and diameter 2b: seen along x a circle π b², seen
    # along y or z an ellipse π a b (the drag force ½ ρ C_D A u² uses these)
    from hydrokit.estimate.shapes import spheroid

    s = spheroid(length=1.2, diameter=0.3, density=1000.0)
    np.testing.assert_allclose(s.reference_area, [math.pi * 0.15**2, math.pi * 0.6 * 0.15, math.pi * 0.6 * 0.15])


@pytest.mark.parametrize("resolution, ok", [(5, False), (6, True), (200, True), (201, False)])
def test_shape_mesh_resolution_runs_from_6_to_200(resolution, ok):
    from hydrokit.errors import InputError
    from hydrokit.estimate.bem import MAX_RESOLUTION, shape_mesh
    from hydrokit.estimate.mesh import check_mesh

    assert MAX_RESOLUTION == 200
    if ok:
        check_mesh(shape_mesh("cylinder", resolution, length=1.0, diameter=0.2))
    else:
        with pytest.raises(InputError, match=rf"resolution = {resolution}: expected from 6 to 200 panels around"):
            shape_mesh("cylinder", resolution, length=1.0, diameter=0.2)


def test_a_face_pointing_one_past_the_last_vertex_is_refused():
    from hydrokit.errors import InputError
    from hydrokit.estimate.bem import shape_mesh
    from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

    m = shape_mesh("sphere", 8, diameter=1.0)
    faces = np.array(m.faces, copy=True)
    faces[0, 0] = len(m.vertices)  # vertices are numbered 0 … n − 1
    with pytest.raises(InputError, match="a face refers to a vertex that does not exist"):
        check_mesh(SurfaceMesh(m.vertices, faces, "bad.stl"))


@pytest.mark.parametrize(("length", "diameter"), [(3.0, 0.4), (0.5, 0.8)])
def test_cylinder_mesh_side_panels_are_nearly_square(length, diameter):
    # the side is cut into rings of panels as long (along x) as they are wide (2πr/n around),
    # the shape a panel method resolves best; L ≠ 1 m so that n·L and n/L differ
    from hydrokit.estimate.bem import shape_mesh

    n = 24
    m = shape_mesh("cylinder", n, length=length, diameter=diameter)
    V, F = np.asarray(m.vertices), np.asarray(m.faces)
    r = np.hypot(V[:, 1], V[:, 2])
    side = F[np.all(np.isclose(r[F], diameter / 2), axis=1)]
    assert len(side) % n == 0 and len(side) >= 2 * n
    axial = np.ptp(V[side][:, :, 0], axis=1)
    assert np.allclose(axial, length / (len(side) // n))
    around = 2 * math.pi * (diameter / 2) / n
    assert axial[0] == pytest.approx(around, rel=0.1)
    assert m.volume() == pytest.approx(length * n / 2 * (diameter / 2) ** 2 * math.sin(2 * math.pi / n), rel=1e-9)


def test_drag_defaults_are_the_documented_ones():
    # shapes.py docstrings: a block takes C_D 1.05 (a cube, Hoerner) in every direction; a
    # spheroid 0.1 along its axis (streamlined) and 0.6 across it
    from hydrokit.estimate.shapes import block

    np.testing.assert_array_equal(block(1.0, 0.5, 0.4).drag_coefficient, [1.05, 1.05, 1.05])
    np.testing.assert_array_equal(spheroid(2.0, 0.5).drag_coefficient, [0.1, 0.6, 0.6])


def test_the_cylinder_table_between_its_last_two_finite_rows_is_linear():
    # CYL_TRANSVERSE_CA: (5.0, 0.90), (9.0, 0.96), then the 1e9 limit row. At L/D = 7 (between the
    # last two finite rows) the value is the plain linear 0.93; only beyond 9 does the reciprocal
    # extrapolation towards the limit apply: at 18, 1.0 + (0.96 − 1.0)·9/18 = 0.98
    from hydrokit.estimate.shapes import CYL_TRANSVERSE_CA, _interp

    assert _interp(CYL_TRANSVERSE_CA, 7.0) == pytest.approx(0.93, rel=1e-12)
    assert _interp(CYL_TRANSVERSE_CA, 18.0) == pytest.approx(0.98, rel=1e-12)


def test_the_cylinder_table_starts_at_its_first_dnv_row():
    # DNV-RP-H103 (2010) Table A-2, circular cylinder with free ends: C_A = 0.62 at L/D = 1.2 and
    # 0.78 at 2.5; between them the linear 0.70 at L/D = 1.85
    from hydrokit.estimate.shapes import CYL_TRANSVERSE_CA, _interp

    assert _interp(CYL_TRANSVERSE_CA, 1.2) == pytest.approx(0.62, rel=1e-12)
    assert _interp(CYL_TRANSVERSE_CA, 1.85) == pytest.approx(0.70, rel=1e-12)


@pytest.mark.parametrize(
    ("shape", "dims"), [("sphere", {"diameter": 0.4}), ("spheroid", {"length": 1.2, "diameter": 0.3})]
)
def test_a_generated_body_uses_every_vertex_and_closes_at_both_tips(shape, dims):
    # the polar caps are fans from the tip vertices (0 and the last): every vertex is a corner of
    # some face, both tips are, and the surface is closed and outward
    from hydrokit.estimate.bem import shape_mesh
    from hydrokit.estimate.mesh import check_mesh

    mesh = shape_mesh(shape, 12, **dims)
    used = set(np.unique(mesh.faces).tolist())
    assert used == set(range(len(mesh.vertices)))
    check_mesh(mesh)
    last = len(mesh.vertices) - 1
    for tip in (0, last):
        assert int(np.sum(np.any(mesh.faces == tip, axis=1))) == 12  # one cap triangle per panel around


def test_a_mesh_part_with_a_given_buoyancy_displaces_b_over_rho_g():
    # buoyancy overrides the mesh volume: V = B / (ρ g); 100 N in water of 1000 kg/m³ at
    # 9.81 m/s² is 10.19 L, and the part's buoyancy reads back 100 N
    from hydrokit.estimate.bem import shape_mesh
    from hydrokit.estimate.geometry import mesh_part

    mesh = shape_mesh("sphere", 12, diameter=0.3)
    part = mesh_part("hull", mesh, 8.0, np.zeros(3), np.eye(3), density=1000.0, gravity=9.81, buoyancy=100.0).part
    assert part.volume == pytest.approx(100.0 / (1000.0 * 9.81), rel=1e-12)
    # combined (one part), the body's weight is m g = 78.48 N and its buoyancy reads back 100 N
    import dataclasses

    from hydrokit.estimate.composite import combine

    body = combine([part])
    assert body.buoyancy(1000.0, 9.81) == pytest.approx(100.0, rel=1e-12)
    assert body.weight(9.81) == pytest.approx(8.0 * 9.81, rel=1e-12)
    for frozen in (part, body):
        with pytest.raises(dataclasses.FrozenInstanceError):
            frozen.mass = 1.0  # type: ignore[misc]


def test_sphere_drag_below_reynolds_one_is_stokes_like():
    # creeping flow is a valid regime, not an error: at Re = 0.5 Mikhailov–Freire's curve gives
    # C_D above Stokes' 24/Re = 48 (Oseen's correction adds ~ 3/16 Re · 24/Re)
    cd = sphere_drag_coefficient(0.5, "Mikhailov-Freire")
    assert 48.0 < cd < 48.0 * 1.2


@pytest.mark.parametrize("bad", [0, 0.0, -0.5, float("nan"), float("inf"), "1", True])
def test_shape_dimensions_must_be_positive_finite_numbers(bad):
    # a sphere of diameter 0 has no volume to scale C_a by: refused, naming the dimension (m)
    from hydrokit.estimate.shapes import sphere

    with pytest.raises(InputError, match=r"diameter = .*: expected a positive dimension \(m\)"):
        sphere(bad, density=1025.0)
