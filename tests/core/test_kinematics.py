from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hydrokit.core.coriolis import coriolis_force, coriolis_matrix
from hydrokit.core.kinematics import (
    J_euler,
    euler_rate_matrix,
    euler_to_quaternion,
    quaternion_rate,
    quaternion_to_euler,
    quaternion_to_rotation,
    rotation_zyx,
)

angle = st.floats(-math.pi, math.pi)
pitch = st.floats(-1.5, 1.5)


@given(angle, pitch, angle)
def test_rotation_orthonormal(phi, theta, psi):
    R = rotation_zyx(phi, theta, psi)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(R) - 1) < 1e-12


@given(angle, pitch, angle)
def test_quaternion_round_trip_and_same_rotation(phi, theta, psi):
    q = euler_to_quaternion(phi, theta, psi)
    assert abs(np.linalg.norm(q) - 1) < 1e-12
    np.testing.assert_allclose(quaternion_to_rotation(q), rotation_zyx(phi, theta, psi), atol=1e-12)
    back = quaternion_to_euler(q)
    np.testing.assert_allclose(rotation_zyx(*back), rotation_zyx(phi, theta, psi), atol=1e-9)


@settings(max_examples=50)
@given(angle, st.floats(-1.3, 1.3), angle, st.lists(st.floats(-1, 1), min_size=3, max_size=3))
def test_euler_rates_consistent_with_quaternion_rates(phi, theta, psi, w):
    # Θ̇ = T(Θ) ω and q̇ = ½Ω(ω)q describe the same motion: advance both by a tiny step
    w = np.array(w)
    h = 1e-6
    th = np.array([phi, theta, psi]) + h * (euler_rate_matrix(phi, theta) @ w)
    q = euler_to_quaternion(phi, theta, psi)
    q2 = q + h * quaternion_rate(q, w)
    np.testing.assert_allclose(rotation_zyx(*th), quaternion_to_rotation(q2 / np.linalg.norm(q2)), atol=1e-9)


def test_J_block_structure():
    eta = np.array([1, 2, 3, 0.1, 0.2, 0.3])
    J = J_euler(eta)
    np.testing.assert_allclose(J[:3, 3:], 0)
    np.testing.assert_allclose(J[:3, :3], rotation_zyx(0.1, 0.2, 0.3))
    np.testing.assert_allclose(J[3:, :3], 0)
    # the lower block is T at (φ, θ) = (0.1, 0.2): checked by the quaternion test above
    np.testing.assert_array_equal(J[3:, 3:], euler_rate_matrix(0.1, 0.2))


@given(st.lists(st.floats(-2, 2), min_size=6, max_size=6))
def test_coriolis_is_skew_and_workless(nu):
    rng = np.random.default_rng(0)
    A = rng.normal(size=(6, 6))
    M = A @ A.T + 6 * np.eye(6)
    nu = np.array(nu)
    C = coriolis_matrix(M, nu)
    np.testing.assert_allclose(C, -C.T, atol=1e-12)
    assert abs(nu @ C @ nu) < 1e-9
    np.testing.assert_allclose(coriolis_force(M, nu), C @ nu, atol=1e-9)


def test_rotation_zyx_many_equals_the_scalar_one_row_by_row():
    from hydrokit.core.kinematics import rotation_zyx, rotation_zyx_many

    rng = np.random.default_rng(3)
    A = rng.uniform(-3, 3, (50, 3))
    R = rotation_zyx_many(A)
    for k in range(len(A)):
        assert np.allclose(R[k], rotation_zyx(*A[k]), rtol=0, atol=1e-15)


def test_quaternion_to_euler_ignores_the_quaternion_length() -> None:
    # an integrated quaternion drifts off unit length: the angles of q and 3 q are the same,
    # and equal those it was built from
    from hydrokit.core.kinematics import euler_to_quaternion, quaternion_to_euler

    angles = np.array([0.3, -0.4, 2.0])
    q = euler_to_quaternion(*angles)
    np.testing.assert_allclose(quaternion_to_euler(q), angles, atol=1e-12)
    np.testing.assert_allclose(quaternion_to_euler(3.0 * q), angles, atol=1e-12)
