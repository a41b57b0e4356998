"""The one law of the rotation matrices (core.kinematics.rotation_zyx_entries and
quaternion_rotation_entries), as Python and compiled, against elementary rotations."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

from hydrokit.core.kinematics import (
    euler_to_quaternion,
    quaternion_rotation_entries,
    quaternion_to_rotation,
    rotation_zyx,
    rotation_zyx_into,
    rotation_zyx_many,
)
from hydrokit.simulate import compiled, transport
from hydrokit.simulate.compiled import quaternion_rotation_compiled, rotation_zyx_into_compiled


def _elementary(phi: float, theta: float, psi: float) -> np.ndarray:
    """R_z(ψ) R_y(θ) R_x(φ), each an elementary rotation (Fossen 2011 eqs. 2.14–2.16)."""
    c, s = math.cos, math.sin
    Rx = np.array([[1, 0, 0], [0, c(phi), -s(phi)], [0, s(phi), c(phi)]])
    Ry = np.array([[c(theta), 0, s(theta)], [0, 1, 0], [-s(theta), 0, c(theta)]])
    Rz = np.array([[c(psi), -s(psi), 0], [s(psi), c(psi), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def _angles(n: int) -> np.ndarray:
    rng = np.random.default_rng(29)
    a = rng.uniform(-math.pi, math.pi, (n, 3))
    a[:, 1] = rng.uniform(-math.pi / 2, math.pi / 2, n)
    return a


def test_rotation_zyx_is_the_product_of_elementary_rotations() -> None:
    for phi, theta, psi in _angles(200):
        R = rotation_zyx(phi, theta, psi)
        # the product rounds differently (three matrix products): a few ulps of 1
        np.testing.assert_allclose(R, _elementary(phi, theta, psi), rtol=0, atol=4e-16 * 4)
        np.testing.assert_allclose(R @ R.T, np.eye(3), rtol=0, atol=1e-15 * 4)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)


#: entries lie in [−1, 1]: a few ulps of 1. The compiled law against the Python one, and numpy's
#: array sin/cos (SIMD kernels chosen per CPU) against libm's, are two implementations each:
#: they may round the last bit differently on another machine.
ULPS = 4 * np.finfo(float).eps


def test_compiled_and_array_forms_are_the_law() -> None:
    A = _angles(100)
    many = rotation_zyx_many(A)
    Rc, Rp = np.empty((3, 3)), np.empty((3, 3))
    for k, (phi, theta, psi) in enumerate(A):
        rotation_zyx_into_compiled(phi, theta, psi, Rc)
        rotation_zyx_into(phi, theta, psi, Rp)
        # the same Python law on the same math.cos/sin: bit for bit
        np.testing.assert_array_equal(rotation_zyx(phi, theta, psi), Rp)
        np.testing.assert_allclose(Rc, Rp, rtol=0, atol=ULPS)
        np.testing.assert_allclose(many[k], Rp, rtol=0, atol=ULPS)


def test_quaternion_rotation_is_the_same_rotation() -> None:
    for phi, theta, psi in _angles(100):
        q = euler_to_quaternion(phi, theta, psi)
        R = np.array(quaternion_rotation_entries(*q)).reshape(3, 3)
        np.testing.assert_allclose(R, _elementary(phi, theta, psi), rtol=0, atol=1e-14)
        np.testing.assert_allclose(np.array(quaternion_rotation_compiled(*q)).reshape(3, 3), R, rtol=0, atol=ULPS)
        np.testing.assert_array_equal(quaternion_to_rotation(q), R)  # the same Python law


def test_kernels_hold_no_rotation_arithmetic_of_their_own() -> None:
    # R(Θ)'s entries are written only in core.kinematics; the kernels call the compiled law
    assert not hasattr(transport, "_rot")
    src = inspect.getsource(getattr(compiled.deriv, "py_func", compiled.deriv))
    assert "cp * ct" not in src and "1 - 2 * (" not in src
    assert "rotation_zyx_entries_compiled" in src and "quaternion_rotation_compiled" in src
