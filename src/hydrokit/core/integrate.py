"""The classical Runge–Kutta (RK4) step, written once (issue #50: every law once).

x_{n+1} = x_n + h/6 (k1 + 2 k2 + 2 k3 + k4), with k1 = f(t, x), k2 = f(t + h/2, x + h/2 k1),
k3 = f(t + h/2, x + h/2 k2), k4 = f(t + h, x + h k3) (Hairer, Nørsett & Wanner 1993, §II.1,
table 1.2 "the" Runge–Kutta method). The right-hand side is not part of the law: each integrator
evaluates its own f between the stages and calls these for the arithmetic.

:func:`rk4_stage` and :func:`rk4_update` are the arithmetic, on plain floats (or, unchanged, on
numpy arrays elementwise: :func:`hydrokit.simulate.integrators.rk4_step` calls them so);
:func:`rk4_stage_into` and :func:`rk4_combine_into` apply them to each element of a state vector
in place, without allocating, for the compiled integrators (``compile_law`` in
:mod:`hydrokit.simulate.compiled`). The order of operations is fixed here, so that every
integrator of the package — compiled or numpy — gives the same bits on the same f.
"""

from __future__ import annotations

import math
from typing import Any


def rk4_stage(x: Any, k: Any, h: Any) -> Any:  # noqa: ANN401 — a float or an array alike
    """The state at which a stage evaluates f: x + h k.

    Parameters
    ----------
    x : float or ndarray
        State at the start of the step (its own units, e.g. m, rad, m/s).
    k : float or ndarray
        Slope of the previous stage, state units per s.
    h : float
        Offset of the stage, s: h/2 for k2 and k3, h for k4 (pass ``0.5 * dt``, computed once).

    Returns
    -------
    float or ndarray
        x + h k.
    """
    return x + h * k


def rk4_update(x: Any, k1: Any, k2: Any, k3: Any, k4: Any, dt: float) -> Any:  # noqa: ANN401
    """The state after one step: x + dt/6 (k1 + 2 k2 + 2 k3 + k4), summed left to right.

    Parameters
    ----------
    x : float or ndarray
        State at the start of the step.
    k1, k2, k3, k4 : float or ndarray
        The four stage slopes, state units per s.
    dt : float
        Step, s.

    Returns
    -------
    float or ndarray
        State at t + dt.
    """
    return x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def rk4_stage_into(x: Any, k: Any, h: float, out: Any) -> None:  # noqa: ANN401
    """``out[i] = rk4_stage(x[i], k[i], h)`` for every element of the 1-D arrays x, k, out."""
    for i in range(x.shape[0]):
        out[i] = rk4_stage(x[i], k[i], h)


def rk4_combine_into(x: Any, k1: Any, k2: Any, k3: Any, k4: Any, dt: float) -> bool:  # noqa: ANN401
    """x (1-D) advanced in place by :func:`rk4_update`; False when any new element is not finite
    (every element is still updated, so the caller sees the state that failed)."""
    finite = True
    for i in range(x.shape[0]):
        x[i] = rk4_update(x[i], k1[i], k2[i], k3[i], k4[i], dt)
        if not math.isfinite(x[i]):
            finite = False
    return finite
