"""Integrators, chosen by name, outside the model: fixed-step RK4 (numpy) and adaptive
(scipy's DOP853 / RK45). The compiled RK4 lives in :mod:`hydrokit.simulate.compiled`; both do
the arithmetic of the one RK4 law, :mod:`hydrokit.core.integrate`."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.core.integrate import rk4_stage, rk4_update
from hydrokit.errors import SimulationError

Rhs = Callable[[float, np.ndarray], np.ndarray]


def rk4_step(
    f: Callable[..., np.ndarray], t: float, x: np.ndarray, h: float, *, u: np.ndarray | None = None
) -> np.ndarray:
    """One classical Runge–Kutta step of ẋ = f(t, x), or of ẋ = f(t, x, u) with u held.

    The one RK4 step of the package: the open-loop driver calls it without ``u``, the
    closed loop with the thrust τ it holds over the step (zero-order hold).

    Parameters
    ----------
    f : callable
        ``f(t, x) -> ẋ``, or ``f(t, x, u) -> ẋ`` when ``u`` is given; t in s, x and ẋ in the
        state's units (e.g. m, rad, m/s, rad/s and their rates).
    t : float
        Time at the start of the step, s.
    x : ndarray
        State at t.
    h : float
        Step length, s.
    u : ndarray or None, keyword-only
        Input held constant over the step (e.g. τ in N and N·m); None: f takes (t, x).
        Keyword-only so that a call written for the old ``(f, t, x, u, h)`` order fails
        loudly instead of swapping the step and the input.

    Returns
    -------
    ndarray
        State at t + h.
    """
    if u is not None:
        g = f
        f = lambda s, y: g(s, y, u)  # u held over the step (zero-order hold)
    # the arithmetic of core.integrate on whole arrays: the same bits as the compiled integrators
    k1 = f(t, x)
    k2 = f(t + 0.5 * h, rk4_stage(x, k1, 0.5 * h))
    k3 = f(t + 0.5 * h, rk4_stage(x, k2, 0.5 * h))
    k4 = f(t + h, rk4_stage(x, k3, h))
    return rk4_update(x, k1, k2, k3, k4, h)


def rk4(
    f: Rhs, x0: np.ndarray, dt: float, n_steps: int, every: int = 1, progress: Callable[[int], None] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Fixed-step RK4 from t = 0; returns (times, states) of every ``every``-th step.

    Raises SimulationError at the first non-finite state, naming the time.
    """
    n_out = n_steps // every + 1
    out = np.empty((n_out, x0.size))
    times = np.empty(n_out)
    x = np.asarray(x0, float).copy()
    out[0] = x
    times[0] = 0.0
    j = 1
    report = max(1, n_steps // 100)
    for k in range(n_steps):
        x = rk4_step(f, k * dt, x, dt)
        if not np.all(np.isfinite(x)):
            raise SimulationError(
                f"the state became non-finite at t = {(k + 1) * dt:.6g} s (step {k + 1}); "
                "check the coefficients' signs and the step size"
            )
        if (k + 1) % every == 0:
            out[j] = x
            times[j] = (k + 1) * dt
            j += 1
        if progress is not None and k % report == 0:
            progress(k)
    return times[:j], out[:j]


def adaptive(
    f: Rhs,
    x0: np.ndarray,
    duration: float,
    t_eval: np.ndarray,
    method: str = "DOP853",
    rtol: float = 1e-8,
    atol: float = 1e-10,
) -> tuple[np.ndarray, np.ndarray]:
    """scipy.integrate.solve_ivp (DOP853 or RK45) sampled at ``t_eval``."""
    from scipy.integrate import solve_ivp

    def event(t: float, x: np.ndarray) -> float:
        return 1.0 if np.all(np.isfinite(x)) and np.max(np.abs(x)) < 1e12 else -1.0

    event.terminal = True  # type: ignore[attr-defined]
    with quiet("scipy solve_ivp", streams=False):  # overflow warnings: into the log; the error below says it
        sol = solve_ivp(
            f, (0.0, duration), np.asarray(x0, float), method=method, t_eval=t_eval, rtol=rtol, atol=atol, events=event
        )
    if sol.status == 1 or not sol.success or not np.all(np.isfinite(sol.y)):
        t_bad = float(sol.t[-1]) if sol.t.size else math.nan
        raise SimulationError(f"the state became non-finite near t = {t_bad:.6g} s ({sol.message})")
    return sol.t, sol.y.T
