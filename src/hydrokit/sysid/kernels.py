"""Compiled loops of identification (issue #50: bench/sysid.py under 15 s): the rotor lag over a
run's rows and nodes, the table thrust curves, the samples of the simulated states, the
forward-difference Jacobian columns (the batch RK4 of many vehicles, one force table shared or one
each, is :func:`hydrokit.simulate.compiled.rk4_batch`).
Each loop only calls the laws of :mod:`hydrokit.model.thrusters` compiled by ``compile_law``
(:mod:`hydrokit.simulate.compiled`) and the RK4 run of the batch integrator — no law is written
here. The serial loops release the GIL (``nogil``).
"""

from __future__ import annotations

import numpy as np

from hydrokit._numba import njit
from hydrokit.simulate.compiled import (
    rotor_lag_compiled,
    table_interp_compiled,
)


@njit(nogil=True)
def rotor_rows(target, t, time_constants, out):  # noqa: ANN001, ANN201
    """The rotor state at every row (``out``, (n, m), command unit): row 0 is given, row k follows
    from row k − 1 by :func:`~hydrokit.model.thrusters.rotor_lag` towards the held ``target`` of
    row k − 1 ((n, m), already within the command limits) over t_k − t_(k−1) (s); τ =
    ``time_constants`` (m,) s."""
    n, m = target.shape
    for k in range(1, n):
        h = t[k] - t[k - 1]
        for i in range(m):
            out[k, i] = rotor_lag_compiled(out[k - 1, i], target[k - 1, i], h, time_constants[i])


@njit(nogil=True)
def rotor_nodes(c, target, h, time_constants, out):  # noqa: ANN001, ANN201
    """``out[j, i]`` = :func:`~hydrokit.model.thrusters.rotor_lag` from ``c[j, i]`` towards
    ``target[j, i]`` (command unit) over ``h[j]`` (s) with τ = ``time_constants[i]`` (s)."""
    k, m = c.shape
    for j in range(k):
        for i in range(m):
            out[j, i] = rotor_lag_compiled(c[j, i], target[j, i], h[j], time_constants[i])


@njit(nogil=True)
def table_thrusts(x, xs, ys, out):  # noqa: ANN001, ANN201
    """``out[j]`` = :func:`~hydrokit.model.thrusters.table_interp` of the table (xs, ys) at x[j]."""
    n = xs.shape[0]
    for j in range(x.shape[0]):
        out[j] = table_interp_compiled(x[j], xs, ys, n)


@njit(nogil=True)
def sample_states(out, state, i0, w, pred):  # noqa: ANN001, ANN201
    """``pred[v, j]`` = the state ``state[j]`` of vehicle v linearly interpolated between the
    integration steps ``i0[j]`` and ``i0[j] + 1`` of ``out`` (nv, steps, 12) with weight ``w[j]``
    (–): ``x[i0] (1 − w) + x[i0 + 1] w``, the samples of a run's channels."""
    for v in range(out.shape[0]):
        for j in range(i0.shape[0]):
            a = out[v, i0[j], state[j]]
            b = out[v, i0[j] + 1, state[j]]
            pred[v, j] = a * (1 - w[j]) + b * w[j]


@njit(nogil=True)
def difference_columns(pred, w, cols, J):  # noqa: ANN001, ANN201
    """The forward-difference Jacobian of weighted residuals r = (y − pred) w per 1e-6 of a
    scaled variable: ``J[i, cols[k − 1]] = −(pred[k, i] − pred[0, i]) w[i] / 1e-6`` for every
    perturbed vehicle k ≥ 1 (vehicle 0 is the nominal)."""
    for i in range(pred.shape[1]):
        for k in range(1, pred.shape[0]):
            J[i, cols[k - 1]] = -(pred[k, i] - pred[0, i]) * w[i] / 1e-6


def as_array(values: object) -> np.ndarray:
    """A curve's table or polynomial as a contiguous float array (the kernels' argument)."""
    return np.ascontiguousarray(np.asarray(values, dtype=float))


__all__ = [
    "difference_columns",
    "rotor_nodes",
    "rotor_rows",
    "sample_states",
    "table_thrusts",
]
