"""The projected Levenberg–Marquardt fit of output-error identification (issue #44, #48): one
implementation for whole runs (:mod:`hydrokit.sysid.fit`) and windows
(:mod:`hydrokit.sysid.window`), which differ only in when they stop.

The fit works in the scaled variables z/scale. ``bounds`` (lower, upper) of the parameters
(SI, ±inf where free) keep them feasible: a parameter on its bound whose gradient points out
of the box is held there for that step (active set), the others take the Levenberg–Marquardt
step of the reduced problem, and the new point is projected onto the box (projected
Levenberg–Marquardt; Kanzow, Yamashita & Fukushima 2004, J. Comput. Appl. Math. 172).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

#: a parameter this many (scaled) units from its start has run away: the fit diverged
RUNAWAY = 1e3


class Diverged(Exception):
    """The fit left the region where the runs can be simulated, or a parameter ran away;
    ``z`` is the point (scaled variables) where it happened."""

    def __init__(self, z: np.ndarray):
        super().__init__("the fit diverged")
        self.z = z


class Problem(Protocol):
    """What the fit needs of a problem: its free parameters and its weighted residuals."""

    params: Any

    def evaluate(
        self, z: np.ndarray, scale: np.ndarray, jac: bool
    ) -> tuple[np.ndarray, np.ndarray | None, bool]: ...  # pragma: no cover


def projected_lm(
    problem: Problem,
    z0: np.ndarray,
    scale: np.ndarray,
    max_iter: int,
    progress: Callable[[int, float], None] | None,
    bounds: tuple[np.ndarray, np.ndarray] | None = None,
    start: tuple[np.ndarray, np.ndarray] | None = None,
    chi2_tol: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Levenberg–Marquardt with bounds (module docstring); returns z, residuals, J, iterations.

    Parameters
    ----------
    problem : its ``evaluate(z, scale, jac)`` gives the weighted residuals (–), their Jacobian
        per unit of z/scale and whether the simulation succeeded; ``params`` the free parameters
        (the first ``len(params)`` entries of z)
    z0 : (n,) start, SI; scale : (n,) scale of each variable, SI
    max_iter : int — accepted iterations at most
    progress : callable(iteration, cost) or None — called after every accepted iteration
    bounds : (lower, upper), each (p,) SI, or None — the parameters' box
    start : (residuals, Jacobian) at ``z0`` (already inside the box), or None — spares the
        first evaluation
    chi2_tol : float or None — stop when an accepted step lowers the weighted cost χ² by less
        than this (–; a change of χ² by 1 moves an estimate by one σ), or when a step the fit
        rejects was promised less than this by the linear model (the Jacobian's — approximate
        when its columns come from a coarser step — cannot take the cost lower by more than
        that: raising the damping would only spend evaluations); None: stop when the relative
        drop is below 1e-9 or every step is below 1e-3 of its standard error

    Raises
    ------
    Diverged
        The start cannot be simulated, or a parameter moved more than :data:`RUNAWAY` scaled
        units from its start.
    """
    p = len(problem.params)
    lo = np.full(z0.size, -np.inf)
    hi = np.full(z0.size, np.inf)
    if bounds is not None:
        lo[:p], hi[:p] = bounds
    z = np.clip(z0, lo, hi)
    r, J0, ok = (start[0], start[1], True) if start is not None else problem.evaluate(z, scale, True)
    if not ok or J0 is None:
        raise Diverged(z)
    J: np.ndarray = J0
    cost = float(r @ r)
    lam = 1e-3
    it = 0
    for it in range(1, max_iter + 1):
        g = J.T @ r
        A = J.T @ J
        d2 = np.clip(np.diag(A), 1e-300, None)
        tiny = 1e-12 * scale
        free = ~(((z <= lo + tiny) & (g > 0)) | ((z >= hi - tiny) & (g < 0)))
        J_new = None
        while lam < 1e10:
            step = np.zeros_like(z)
            step[free] = -np.linalg.solve(A[np.ix_(free, free)] + lam * np.diag(d2[free]), g[free])
            z_new = np.clip(z + step * scale, lo, hi)
            r_new, J_new, ok = problem.evaluate(z_new, scale, True)
            if ok and J_new is not None and float(r_new @ r_new) < cost:
                break
            J_new = None
            if chi2_tol is not None and _predicted_drop(r, J, (z_new - z) / scale) < chi2_tol:
                break  # even the linear model promises less than chi2_tol: converged, no λ hunt
            lam *= 10.0
        if J_new is None:
            break
        lam = max(lam / 10.0, 1e-9)
        new_cost = float(r_new @ r_new)
        drop = cost - new_cost
        step = (z_new - z) / scale
        z, r, J, cost = z_new, r_new, J_new, new_cost
        if np.any(np.abs(z[:p] - z0[:p]) / scale[:p] > RUNAWAY):
            raise Diverged(z)
        if progress:
            progress(it, cost)
        if chi2_tol is not None:
            if drop < chi2_tol:
                break
            continue
        # converged: the step is far below the statistical resolution, or the cost is flat
        with np.errstate(divide="ignore", invalid="ignore"):
            res_sd = np.sqrt(np.clip(np.diag(np.linalg.pinv(A)), 0, None))
        if drop / (cost + drop) < 1e-9 or np.all(np.abs(step) <= 1e-3 * np.maximum(res_sd, 1e-300)):
            break
    return z, r, J, it


def _predicted_drop(r: np.ndarray, J: np.ndarray, step: np.ndarray) -> float:
    """The drop of the weighted cost χ² the linear model r + J step promises for ``step`` (scaled
    variables): ‖r‖² − ‖r + J step‖² (–)."""
    lin = r + J @ step
    return float(r @ r - lin @ lin)


__all__ = ["RUNAWAY", "Diverged", "Problem", "projected_lm"]
