"""Rigid-body matrices against independent constructions."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hydrokit.core.rigid_body import move_matrix, parallel_axis, rigid_body_mass_matrix, shift_matrix, skew

vec = st.lists(st.floats(-2, 2, allow_nan=False), min_size=3, max_size=3)


@given(vec, vec)
def test_skew_is_cross_product(a, b) -> None:
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b), atol=1e-12)


@given(vec)
@settings(max_examples=50)
def test_shift_back_is_identity(r) -> None:
    M = np.diag([3.0, 4, 5, 0.5, 0.6, 0.7])
    np.testing.assert_allclose(move_matrix(move_matrix(M, r), -np.asarray(r)), M, atol=1e-10)
    np.testing.assert_allclose(shift_matrix(r) @ shift_matrix(-np.asarray(r)), np.eye(6), atol=1e-12)


def test_mass_matrix_equals_moving_a_point_mass() -> None:
    # M_RB of a body with CG at r_g equals its CG matrix diag(m,m,m,I) moved by H(r_g):
    # two constructions (Fossen eq. 3.44 vs eq. 7.13) must agree.
    m, I = 7.0, np.diag([0.3, 0.4, 0.5])
    r = np.array([0.1, -0.2, 0.3])
    M_cg = np.zeros((6, 6))
    M_cg[:3, :3] = m * np.eye(3)
    M_cg[3:, 3:] = I
    np.testing.assert_allclose(rigid_body_mass_matrix(m, I, r), move_matrix(M_cg, r), atol=1e-12)


def test_parallel_axis_scalar_case() -> None:
    # I_zz about a point 0.5 m away along x: I + m d² (textbook Steiner).
    I = parallel_axis(np.diag([1.0, 1.0, 1.0]), 2.0, [0.5, 0, 0])
    assert np.isclose(I[2, 2], 1.0 + 2.0 * 0.25)
    assert np.isclose(I[0, 0], 1.0)


def test_principal_moments_give_the_diagonal_tensor_and_steiner() -> None:
    # three principal values are the 3×3 diagonal tensor; moving by d along y adds m d² to I_xx
    # and I_zz (Steiner), not to I_yy
    from hydrokit.core.rigid_body import inertia_tensor

    np.testing.assert_array_equal(inertia_tensor([1.0, 2.0, 3.0]), np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(np.diag(parallel_axis([1.0, 2.0, 3.0], 4.0, [0, 0.5, 0])), [2.0, 2.0, 4.0])
