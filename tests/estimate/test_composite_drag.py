"""Quadratic damping of composite bodies (issue #11): point drag elements, REHMAN's d·r³
diagonal and the dimensionally wrong Hᵀ D H shift kept for comparison."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hydrokit.core.drag import DragElement, drag_wrench
from hydrokit.errors import InputError
from hydrokit.estimate.composite import (
    QUADRATIC_DAMPING_MODELS,
    Part,
    combine,
    rotation_from_degrees,
    single_axis_diagonal,
)

# REHMAN Table 1 (SPEC §2.1): cylinder 1 m long, Ø0.25 m; quadratic damping axial 21.88 and
# transverse 83.28 N·s²/m²; the manipulator's centre at 0.75 m from the payload (SPEC §2.3).
Q_AXIAL, Q_TRANS, ARM = 21.88, 83.28, 0.75


def manipulator(y: float = ARM) -> Part:
    """A REHMAN manipulator: cylinder axis = part x, turned 90° in yaw onto the common y axis."""
    return Part(
        "manipulator",
        450 / 9.81,
        503 / (1025 * 9.81),
        np.eye(3),
        np.zeros((6, 6)),
        quadratic_damping=np.diag([Q_AXIAL, Q_TRANS, Q_TRANS, 0, 0, 0]),
        position=np.array([0.0, y, 0.0]),
        rotation=rotation_from_degrees(0, 0, 90),
    )


def total_wrench(comp, nu) -> np.ndarray:
    """Diagonal quadratic damping plus drag elements at the relative velocity ``nu``."""
    nu = np.asarray(nu, float)
    return -np.diag(comp.quadratic_damping) * np.abs(nu) * nu + drag_wrench(comp.drag_elements, nu)


def test_rehman_table1_yaw_damping_is_d_r_cubed():
    # REHMAN Table 1 / SPEC §2.3: cylinder pitch/yaw quadratic damping printed 35.1 = 83.28·0.75³
    # (its added inertia 24.1 = 42.8·0.75² goes with r², its drag moment with r³)
    reh = combine([manipulator()], "rehman")
    assert reh.quadratic_damping[5, 5] == pytest.approx(Q_TRANS * ARM**3, rel=1e-12)
    assert reh.quadratic_damping[5, 5] == pytest.approx(35.1, abs=0.05)  # printed to 3 digits
    assert reh.quadratic_damping[3, 3] == pytest.approx(35.1, abs=0.05)  # roll: heave drag at 0.75 m
    assert reh.quadratic_damping[4, 4] == 0.0  # the arm lies on the pitch axis
    assert reh.drag_elements.shape == (0, 9) and not reh.warnings


def test_shifted_model_keeps_the_old_d_r_squared_for_comparison():
    shifted = combine([manipulator()], "shifted")
    # the bug (issue #11), kept only for comparison: Hᵀ D H gives d·r² (kg·m) — exact arithmetic
    assert shifted.quadratic_damping[5, 5] == pytest.approx(Q_TRANS * ARM**2, rel=1e-12)
    assert shifted.quadratic_damping[5, 5] != pytest.approx(35.1, abs=1.0)
    assert len(shifted.warnings) == 1 and "dimensionally wrong" in shifted.warnings[0]


@pytest.mark.parametrize("omega", [-1.3, -0.2, 0.5, 2.0])
def test_elements_yaw_moment_is_rehman_35_1(omega):
    comp = combine([manipulator()])
    assert comp.drag_element_names == ("manipulator",)
    np.testing.assert_allclose(comp.drag_elements[0, :3], [0, ARM, 0], atol=1e-15)
    nu = [0, 0, 0, 0, 0, omega]
    N = drag_wrench(comp.drag_elements, nu)[5]
    # the element at 0.75 m moves at 0.75 ω across its axis: moment −83.28·0.75³·|ω|ω
    # (REHMAN Table 1: 35.1); rel 1e-12: the same arithmetic done two ways
    assert N == pytest.approx(-Q_TRANS * ARM**3 * abs(omega) * omega, rel=1e-12)
    assert N == pytest.approx(-35.1 * abs(omega) * omega, rel=2e-3)  # printed to 3 digits
    reh = combine([manipulator()], "rehman")
    assert total_wrench(comp, nu)[5] == pytest.approx(-reh.quadratic_damping[5, 5] * abs(omega) * omega, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(
    r=st.lists(st.floats(-3, 3), min_size=3, max_size=3),
    Q=st.lists(st.floats(0, 500), min_size=3, max_size=3),
    axis=st.integers(0, 2),
    omega=st.floats(-3, 3),
)
def test_single_axis_diagonal_is_the_element_moment_about_that_axis(r, Q, axis, omega):
    # the d·r³ formula (REHMAN's diagonal) against the element model's own moment for a
    # rotation about one axis through the origin: equal exactly (up to round-off)
    packed = np.array([[*r, 0, 0, 0, *Q]])
    nu = np.zeros(6)
    nu[3 + axis] = omega
    M = drag_wrench(packed, nu)[3 + axis]
    want = -single_axis_diagonal(packed)[3 + axis] * abs(omega) * omega
    assert M == pytest.approx(want, rel=1e-9, abs=1e-9)


def parts_for_comparison() -> list[Part]:
    vehicle = Part(
        "vehicle",
        460.0,
        0.45,
        np.diag([95.0, 94.0, 50.0]),
        np.zeros((6, 6)),
        quadratic_damping=np.diag([292.0, 584, 635, 84, 148, 100]),
        position=np.array([0.3, -1.85, 0.1]),
        rotation=rotation_from_degrees(0, 0, 90),
    )
    return [manipulator(), manipulator(-ARM), vehicle]


@pytest.mark.parametrize("nu_t", [[1.0, 0, 0], [0, -0.7, 0], [0.3, 0.5, -0.9]])
def test_translational_drag_equal_across_models(nu_t):
    nu = np.array([*nu_t, 0, 0, 0])
    forces = [total_wrench(combine(parts_for_comparison(), m), nu)[:3] for m in QUADRATIC_DAMPING_MODELS]
    # pure translation: every point moves at v, so Σ −Q∘|v|v for all three (90° turns are exact)
    for f in forces[1:]:
        np.testing.assert_allclose(f, forces[0], rtol=1e-12)
    want = -np.array([Q_TRANS * 2 + 584, Q_AXIAL * 2 + 292, Q_TRANS * 2 + 635]) * np.abs(nu[:3]) * nu[:3]
    np.testing.assert_allclose(forces[0], want, rtol=1e-12)


def test_rotated_part_maps_qx_to_qy():
    p = Part(
        "p",
        1.0,
        0.0,
        np.eye(3),
        np.zeros((6, 6)),
        quadratic_damping=np.diag([1.0, 2, 3, 4, 5, 6]),
        position=np.array([1.0, 0, 0]),
        rotation=rotation_from_degrees(0, 0, 90),
    )
    comp = combine([p])
    # part x → common y: Qx ↔ Qy for the element, K ↔ M for the part's own rotational drag
    np.testing.assert_allclose(comp.drag_elements[0, 6:9], [2, 1, 3], atol=1e-12)
    np.testing.assert_allclose(np.diag(comp.quadratic_damping), [0, 0, 0, 5, 4, 6], atol=1e-12)
    reh = combine([p], "rehman")
    # rehman: element at r = (1, 0, 0) with common Q = (2, 1, 3): M += Qz|rx|³, N += Qy|rx|³
    np.testing.assert_allclose(np.diag(reh.quadratic_damping), [2, 1, 3, 5, 4 + 3, 6 + 1], atol=1e-12)
    assert not comp.warnings


def test_part_at_the_common_origin_stays_in_the_diagonal():
    # at r = 0 an element sees v_P = v and gives no moment: the diagonal is the same law
    sphere = Part("payload", 130.0, 0.065, np.eye(3), np.zeros((6, 6)), quadratic_damping=np.diag([46.2] * 3 + [0] * 3))
    comp = combine([sphere, manipulator()])
    np.testing.assert_allclose(np.diag(comp.quadratic_damping)[:3], 46.2, rtol=1e-15)
    assert comp.drag_element_names == ("manipulator",)


def test_linear_damping_moved_with_h_is_the_linear_element_law():
    # a linear law is linear in v + ω × r, so Hᵀ D H is exact: compare with a linear element
    r, L = np.array([0.4, -1.1, 0.3]), np.array([29.0, 41, 254])
    p = Part("p", 1.0, 0.0, np.eye(3), np.zeros((6, 6)), linear_damping=np.diag([*L, 0, 0, 0]), position=r)
    nu = np.array([0.3, -0.2, 0.5, 0.7, -0.4, 1.1])
    for m in QUADRATIC_DAMPING_MODELS:
        comp = combine([p], m)
        np.testing.assert_allclose(-comp.linear_damping @ nu, drag_wrench([[*r, *L, 0, 0, 0]], nu), rtol=1e-12)


def _plain_vehicle(**extra):
    """A 10 kg vehicle with no added mass or damping of its own (``extra``: e.g. drag_elements)."""
    return SimpleNamespace(
        mass=10.0,
        volume=0.01,
        inertia=np.eye(3),
        M_A=np.zeros((6, 6)),
        D_L=np.zeros((6, 6)),
        D_Q=np.zeros(6),
        r_g=np.zeros(3),
        r_b=np.zeros(3),
        **extra,
    )


def test_vehicle_part_moves_its_own_elements():
    from hydrokit.estimate.geometry import vehicle_part

    vehicle = _plain_vehicle(drag_elements=(DragElement("arm", (1.0, 0.0, 0.0), (3.0, 0.0, 0.0), (5.0, 7.0, 0.0)),))
    gp = vehicle_part("rov", vehicle, np.array([0.0, 2.0, 0.0]), rotation_from_degrees(0, 0, 90), "test")
    comp = combine([gp.part])
    assert comp.drag_element_names == ("rov/arm",)
    # part x → common y: the element at part (1, 0, 0) sits at common (0, 2 + 1, 0); L, Q turn
    np.testing.assert_allclose(comp.drag_elements[0], [0, 3, 0, 0, 3, 0, 7, 5, 0], atol=1e-12)
    reh = combine([gp.part], "rehman")
    # rehman: element linear drag moved exactly into D_L (Hᵀ diag(L) H: yaw gets Ly·rx² = 0 here,
    # roll gets Ly·rz² = 0, sway 3); quadratic as d·r³: yaw += Qx|ry|³ = 7·27
    assert reh.linear_damping[1, 1] == pytest.approx(3.0)
    assert reh.quadratic_damping[5, 5] == pytest.approx(7 * 27)


def test_unknown_model_names_the_choices():
    with pytest.raises(InputError, match=r"'diagonal'.*elements, rehman, shifted"):
        combine([manipulator()], "diagonal")


def test_rehman_assembly_writes_elements_the_vehicle_reader_accepts():
    import hydrokit.io.vehicle as io_vehicle
    from hydrokit.data import geometry_file
    from hydrokit.estimate.geometry import estimate_geometry
    from hydrokit.io.geometry import load_geometry

    geo = load_geometry(geometry_file("rehman_assembly"))
    est = estimate_geometry(geo)
    doc = est.to_dict()
    names = [e["name"] for e in doc["drag_elements"]]
    assert names == ["manipulator-1", "manipulator-2", "minerva-1", "minerva-2"]
    assert doc["drag_elements"][0]["position"] == [0.0, -0.75, 0.0]
    assert any("quadratic damping model: elements" in s for s in doc["sources"])
    # rehman writes the single-axis equivalent of the same elements into the diagonal
    reh = estimate_geometry(geo, quadratic_damping="rehman")
    assert "drag_elements" not in reh.to_dict()
    np.testing.assert_allclose(
        np.diag(reh.composite.quadratic_damping), est.composite.quadratic_damping_single_axis, rtol=1e-12
    )
    with pytest.raises(InputError, match="'r3'"):
        estimate_geometry(geo, quadratic_damping="r3")
    if "drag_elements" not in io_vehicle.KNOWN:
        pytest.skip("the vehicle reader does not know drag_elements yet (issue #11, part 1)")
    v = io_vehicle.parse_vehicle(doc, "estimate")
    assert not v.warnings
    np.testing.assert_allclose(v.drag_packed, est.composite.drag_elements, atol=1e-9)


def test_shifted_model_moves_a_parts_own_drag_elements_with_h_transpose_d_h():
    # a part at (0, 0.6, 0) with its own element 0.4 m ahead of its origin, quadratic drag
    # (c_x, c_y, c_z): at the common origin the element sits at r = (0.4, 0.6, 0). Hᵀ diag(c) H
    # (the shifted model, d·r² kept for comparison) gives by hand, with v = ν₁ + ω × r:
    # surge c_x, sway c_y, heave c_z, roll c_z·r_y², pitch c_z·r_x², yaw c_x·r_y² + c_y·r_x²
    cx, cy, cz, rx, ry = 3.0, 5.0, 7.0, 0.4, 0.6
    element = np.array([[rx, 0, 0, 0, 0, 0, cx, cy, cz]])
    part = Part(
        "arm", 2.0, 0.002, np.eye(3), np.zeros((6, 6)), position=np.array([0.0, ry, 0.0]), drag_elements=element
    )
    got = np.diag(combine([part], "shifted").quadratic_damping)
    want = [cx, cy, cz, cz * ry**2, cz * rx**2, cx * ry**2 + cy * rx**2]
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)


def test_a_vehicle_without_drag_elements_joins_one_with_them():
    # a vehicle part with no point elements carries an empty packed table (0 × PACKED_WIDTH)
    # that stacks with another part's elements
    from hydrokit.core.drag import PACKED_WIDTH
    from hydrokit.estimate.geometry import vehicle_part

    plain = _plain_vehicle()
    with_arm = SimpleNamespace(
        **vars(plain), drag_elements=(DragElement("arm", (1.0, 0.0, 0.0), (3.0, 0.0, 0.0), (5.0, 7.0, 0.0)),)
    )
    bare = vehicle_part("bare", plain, np.zeros(3), rotation_from_degrees(), "test").part
    assert bare.drag_elements.shape == (0, PACKED_WIDTH) == (0, 9)
    other = vehicle_part("rov", with_arm, np.array([0.0, 2.0, 0.0]), rotation_from_degrees(), "test").part
    comp = combine([bare, other])
    assert comp.drag_element_names == ("rov/arm",)
    np.testing.assert_allclose(comp.drag_elements[0], [1, 2, 0, 3, 0, 0, 5, 7, 0], atol=1e-12)


def test_rotation_from_degrees_turns_about_each_axis_alone():
    # each angle alone is the elementary rotation about its own axis (the others default to 0)
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    np.testing.assert_allclose(rotation_from_degrees(), np.eye(3), atol=0)
    np.testing.assert_allclose(rotation_from_degrees(roll=30), [[1, 0, 0], [0, c, -s], [0, s, c]], atol=1e-15)
    np.testing.assert_allclose(rotation_from_degrees(pitch=30), [[c, 0, s], [0, 1, 0], [-s, 0, c]], atol=1e-15)
    np.testing.assert_allclose(rotation_from_degrees(yaw=30), [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-15)
