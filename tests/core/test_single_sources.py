"""Each formula and name list exists once, in core; the other layers use that one."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.core import kinematics, names
from hydrokit.core.coriolis import coriolis_force, coriolis_matrix


def test_wrap_angle_is_the_core_function() -> None:
    from hydrokit.model import control

    assert control.wrap_angle is kinematics.wrap_angle


@pytest.mark.parametrize(
    ("a", "expected"),
    [
        (0.0, 0.0),
        (math.pi + 0.1, -math.pi + 0.1),
        (-math.pi - 0.1, math.pi - 0.1),
        (3 * math.pi / 2, -math.pi / 2),
        (7.0, 7.0 - 2 * math.pi),
        (math.pi, -math.pi),
        (-math.pi, -math.pi),
    ],
)
def test_wrap_angle_values(a: float, expected: float) -> None:
    # [−π, π): +π maps to −π, and a whole turn is removed, never a half turn
    assert kinematics.wrap_angle(a) == pytest.approx(expected, abs=1e-15)


def test_coriolis_symmetric_flag_skips_only_the_symmetrisation() -> None:
    rng = np.random.default_rng(5)
    A = rng.normal(size=(6, 6))
    M = A @ A.T + 6 * np.eye(6)  # symmetric positive definite
    nu = rng.normal(size=6)
    # on a symmetric M the flag changes nothing, bit for bit
    np.testing.assert_array_equal(coriolis_force(M, nu, symmetric=True), coriolis_force(M, nu))
    np.testing.assert_array_equal(coriolis_matrix(M, nu, symmetric=True), coriolis_matrix(M, nu))
    # on an asymmetric M the default uses the symmetric part (Theorem 3.2 needs M = Mᵀ)
    B = M.copy()
    B[0, 4] += 0.5
    np.testing.assert_allclose(
        coriolis_force(B, nu), coriolis_force(0.5 * (B + B.T), nu, symmetric=True), rtol=1e-14, atol=1e-14
    )
    # C(ν) ν by hand for a diagonal mass: [ω × (m v); v × (m v) + ω × (I ω)]
    m, I = 10.0, np.array([1.0, 2.0, 3.0])
    D = np.diag([m, m, m, *I])
    v, w = np.array([1.0, 0.5, -0.2]), np.array([0.1, -0.3, 0.2])
    expected = np.concatenate([np.cross(w, m * v), np.cross(w, I * w)])
    np.testing.assert_allclose(coriolis_force(D, np.concatenate([v, w])), expected, rtol=1e-14, atol=1e-15)


def test_name_lists_come_from_core_names() -> None:
    from hydrokit.model import allocation, terms

    assert allocation.DOF_NAMES is names.DOF_NAMES
    assert terms.DOFS == "XYZKMN" and terms.VELS == "uvwpqr"
    # the term grammar indexes DOFs and velocities in core.names' order
    t = terms.parse_term("N_r|r|")
    assert names.FORCE_SYMBOLS[t.dof] == "N" and names.DOF_NAMES[t.dof] == "yaw"
    assert names.VELOCITY_SYMBOLS[t.factors[0].indices[0]] == "r"
