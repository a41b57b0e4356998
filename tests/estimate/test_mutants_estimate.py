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
