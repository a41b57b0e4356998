from __future__ import annotations

import numpy as np
import pytest

from hydrokit.core.rigid_body import move_matrix
from hydrokit.errors import InputError
from hydrokit.estimate.composite import Part, combine, move, rotation_from_degrees
from hydrokit.estimate.forces import fit_forces
from hydrokit.estimate.shapes import spheroid


def test_shift_and_back_is_identity():
    MA = spheroid(2.0, 0.5, 1000).added_mass
    r = np.array([0.3, -1.2, 0.4])
    there = move_matrix(MA, r)
    back = move_matrix(there, -r)
    np.testing.assert_allclose(back, MA, atol=1e-10 * np.abs(MA).max())
    R = rotation_from_degrees(10, 20, 30)
    np.testing.assert_allclose(move(move(MA, R, r), R.T, -R.T @ r), MA, atol=1e-9 * np.abs(MA).max())


def test_two_spheres_on_a_rod_inertia_by_direct_integration():
    # two 1 kg spheres of radius 0.1 m at x = ±0.5 m, massless rod: I_yy by integrating the solid
    # spheres on a grid, compared with the parallel-axis combination
    parts = [
        Part(f"s{k}", 1.0, 0.0, np.eye(3) * 0.4 * 1.0 * 0.1**2, np.zeros((6, 6)), position=np.array([x, 0, 0]))
        for k, x in enumerate((-0.5, 0.5))
    ]
    comp = combine(parts)
    g = np.linspace(-0.1, 0.1, 81)
    X, Y, Z = np.meshgrid(g, g, g, indexing="ij")
    inside = X**2 + Y**2 + Z**2 <= 0.01
    rho = 1.0 / inside.sum()
    Iyy = sum(rho * np.sum(((X + x0) ** 2 + Z**2)[inside]) for x0 in (-0.5, 0.5))
    Ixx = 2 * rho * np.sum((Y**2 + Z**2)[inside])
    assert comp.inertia_cg[1, 1] == pytest.approx(Iyy, rel=5e-3)  # grid integration error ~0.3 %
    assert comp.inertia_cg[0, 0] == pytest.approx(Ixx, rel=5e-3)
    np.testing.assert_allclose(comp.r_g, 0, atol=1e-15)


def test_offset_part_gets_off_diagonal_coupling():
    MA = np.diag([10.0, 20, 30, 0, 0, 0])
    comp = combine([Part("p", 1.0, 1e-3, np.eye(3), MA, position=np.array([0, 2.0, 0]))])
    # surge added mass 10 kg at y = 2 m: yaw coupling −10·2 and yaw added inertia 10·4
    assert comp.added_mass[0, 5] == pytest.approx(-20.0)
    assert comp.added_mass[5, 5] == pytest.approx(40.0)
    assert comp.added_mass_diagonal_only[5, 5] == 0.0


def test_force_fit_recovers_truth_within_standard_errors():
    rng = np.random.default_rng(4)
    U = np.linspace(0.2, 2.0, 30)
    F = 1.2 * U + 40.0 * U * U + rng.normal(0, 0.5, U.size)
    fit = fit_forces(U, F, area=0.05, density=998.2)
    assert abs(fit.K_L - 1.2) < 3 * fit.K_L_se
    assert abs(fit.K_Q - 40.0) < 3 * fit.K_Q_se
    assert fit.K_D == pytest.approx(0.5 * 998.2 * fit.C_D * 0.05, rel=1e-12)  # K_D = ½ρC_D A
    assert fit.r2_chin > 0.99


def test_cely2019_table5_implies_reference_areas(published):
    t5 = published["cely2019"]["table5_cfd"]
    half_rho_a = [kd / cd for kd, cd in zip(t5["K_D"], t5["C_D"])]
    # CELY2019 Table 5: ½ρA_ref = 24.69 (x), 45.20 (y, z) → A_ref ≈ 0.0495 and 0.0906 m² at ρ = 998.2
    assert half_rho_a == pytest.approx([24.69, 45.20, 45.20], abs=0.01)
    assert [2 * h / 998.2 for h in half_rho_a] == pytest.approx([0.0495, 0.0906, 0.0906], abs=5e-5)


def test_force_fit_needs_points():
    with pytest.raises(InputError, match="only 1 point"):
        fit_forces(np.array([1.0]), np.array([2.0]), 0.1, 1000.0)


@pytest.mark.parametrize(
    ("speed", "force"),
    [
        (np.linspace(0.2, 1.0, 5), np.linspace(1.0, 9.0, 4)),  # 1-D, lengths differ
        (np.ones((3, 2)), np.ones((3, 2))),  # equal shapes, but a table, not pairs
        (np.ones(6), np.ones((6, 1))),  # a column of forces
    ],
)
def test_force_fit_needs_two_1d_arrays_of_equal_length(speed, force):
    with pytest.raises(InputError) as err:
        fit_forces(speed, force, 0.1, 1000.0)
    assert str(err.value) == f"speed and force must be 1-D of equal length, got {np.shape(speed)} and {np.shape(force)}"


def test_diagonal_only_added_mass_sums_each_parts_turned_diagonal():
    # REHMAN's diagonal-only rule: each part's own diagonal, turned into the common axes, summed
    # with no shift. Part A unturned, diagonal (1 … 6); part B turned 90° about z, diagonal
    # (10 … 60), so its surge/sway and roll/pitch entries swap: (20, 10, 30, 50, 40, 60)
    a = Part("a", 1.0, 1e-3, np.eye(3), np.diag([1.0, 2, 3, 4, 5, 6]), position=np.array([0.0, 1.0, 0.0]))
    b = Part(
        "b",
        1.0,
        1e-3,
        np.eye(3),
        np.diag([10.0, 20, 30, 40, 50, 60]),
        position=np.array([0.5, 0.0, 0.0]),
        rotation=rotation_from_degrees(0, 0, 90),
    )
    comp = combine([a, b])
    np.testing.assert_allclose(comp.added_mass_diagonal_only, np.diag([21.0, 12, 33, 54, 45, 66]), atol=1e-12)


def test_a_composite_built_by_hand_has_no_single_axis_drag_on_any_of_six_axes():
    # the docstring: quadratic_damping_single_axis is (6,); by default all zero
    from hydrokit.estimate.composite import Composite

    z3, z6 = np.zeros(3), np.zeros((6, 6))
    comp = Composite(1.0, 1e-3, np.eye(3), z3, z3, z6, z6, z6, z6, ("p",))
    assert comp.quadratic_damping_single_axis.shape == (6,) and not np.any(comp.quadratic_damping_single_axis)


@pytest.mark.parametrize("masses", [(0.0,), (0.0, 0.0), (2.0, -2.0)])
def test_parts_of_no_total_mass_are_refused(masses):
    # the centre of gravity divides by the total mass: zero (or less) is refused in words
    parts = [Part(f"p{k}", m, 1e-3, np.eye(3), np.zeros((6, 6))) for k, m in enumerate(masses)]
    with pytest.raises(InputError, match=r"total mass = 0(\.0)?: expected a positive mass"):
        combine(parts)
