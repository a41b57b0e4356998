"""The one rig integrator's forward sensitivities against central differences of its state.

simulate_normalised (12 augmented states: q, q̇ and ∂/∂(ω², b, g, q0, v0)) and simulate_extended
(18: ∂/∂(ω², b, g, d, a3, a5, q0, v0)) run the same compiled RK4 of the state and its
sensitivity equations; the second method here is the difference of two solutions of the state
alone (jacobian=False integrates only q and q̇), for every restoring shape, so each shape's
slope ρ'(q) enters the check.
"""

from __future__ import annotations

import numpy as np
import pytest

from hydrokit.identify.rig_model import SINE, Restoring, simulate_extended, simulate_normalised

SHAPES = {
    "linear": Restoring(),
    "sine": Restoring(SINE),
    "polynomial": Restoring.polynomial(1.0, -0.4, 0.05),
    # a GZ-like curve (rad, m): the swing from 0.5 rad crosses its knots
    "table": Restoring.table([0.0, 0.2, 0.4, 0.7], [0.0, 0.19, 0.33, 0.42])[0],
}
T = np.arange(301) / 100.0  # s
Q0, V0 = 0.5, 0.1  # rad, rad/s


def _central_differences(solve, x: np.ndarray) -> np.ndarray:
    """∂q/∂x_k by (q(x + h e_k) − q(x − h e_k)) / 2h, one column per k."""
    cols = []
    for k in range(x.size):
        h = 1e-6 * max(abs(x[k]), 1.0)
        up, dn = x.copy(), x.copy()
        up[k] += h
        dn[k] -= h
        cols.append((solve(up) - solve(dn)) / (2 * h))
    return np.column_stack(cols)


def _agree(J: np.ndarray, fd: np.ndarray) -> None:
    # central differences err by ~h² q''' ≈ 1e-12 and round by ~1e-16 / h ≈ 1e-10 of |q|; the RK4
    # steps (h = 2.5 ms) are the same in both, so the sensitivities are those of the discrete map
    # up to that rounding: 1e-7 of each column's scale leaves a margin of 100 above it
    for k in range(J.shape[1]):
        np.testing.assert_allclose(J[:, k], fd[:, k], rtol=1e-5, atol=1e-7 * np.abs(fd[:, k]).max())


@pytest.mark.parametrize("name", list(SHAPES))
def test_normalised_sensitivities_are_central_differences_of_the_state(name):
    shape = SHAPES[name]
    x = np.array([9.0, 0.2, 0.8, Q0, V0])  # ω² 1/s², b 1/s, g 1/rad, q0 rad, v0 rad/s

    def solve(y: np.ndarray) -> np.ndarray:
        return simulate_normalised(T, y[0], y[1], y[2], y[3], y[4], restoring=shape)[0]

    _, _, J = simulate_normalised(T, *x, jacobian=True, restoring=shape)
    assert J.shape == (T.size, 5)
    _agree(J, _central_differences(solve, x))


@pytest.mark.parametrize("name", list(SHAPES))
def test_extended_sensitivities_are_central_differences_of_the_state(name):
    shape = SHAPES[name]
    # ω², b, g, d (s/rad²), a3 (1/rad²), a5 (1/rad⁴), q0, v0: every term non-zero
    x = np.array([9.0, 0.2, 0.8, 0.3, -0.2, 0.05, Q0, V0])

    def solve(y: np.ndarray) -> np.ndarray:
        return simulate_extended(T, y[:6], y[6], y[7], restoring=shape)[0]

    _, _, J = simulate_extended(T, x[:6], Q0, V0, restoring=shape, jacobian=True)
    assert J.shape == (T.size, 8)
    _agree(J, _central_differences(solve, x))
