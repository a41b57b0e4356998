"""Thrust allocation: configuration matrix, pseudo-inverse and constrained solutions.

The demanded generalised force τ = [X Y Z K M N] (N, N·m, body axes) is mapped to thruster
forces f (N) with τ = T f, where column i of the 6×m configuration matrix T is
[e_i; r_i × e_i] (LI2021 eq. 22–23).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit._result import Result, jsonable
from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.model.bvls import _cols, _kkt, _on_bound_part, bvls, lstsq_small

Array = NDArray[np.float64]


#: A row of T whose largest entry is at most this (N per N, m) counts as all-zero: poses are
#: given to ~1e-3 m, so anything smaller is round-off, not a lever arm.
ZERO_ROW_TOL = 1e-9

#: Weight of the exact-achievement term in the second (least-norm) stage of the constrained
#: allocation, relative to the thrust-norm term after scaling T to unit norm. The achieved τ
#: then deviates from the stage-1 optimum by about |f| / W² ≈ 1e-10 of the thrust scale.
_STAGE2_WEIGHT = 1e5


def configuration_matrix(positions: ArrayLike, directions: ArrayLike) -> Array:
    """The 6×m configuration matrix (LI2021 eq. 22–23).

    Parameters
    ----------
    positions : (m, 3) array — thruster positions r_i in body axes, m
    directions : (m, 3) array — unit thrust directions e_i in body axes, –

    Returns
    -------
    T : (6, m) array — column i = [e_i; r_i × e_i]; rows X, Y, Z (N per N) and K, M, N
        (N·m per N, i.e. m)
    """
    r = np.atleast_2d(np.asarray(positions, dtype=float))
    e = np.atleast_2d(np.asarray(directions, dtype=float))
    if r.shape != e.shape or r.shape[1] != 3:
        raise InputError(f"positions {r.shape} and directions {e.shape}: expected two (m, 3) arrays")
    return np.vstack([e.T, np.cross(r, e).T])


def uncontrollable_dofs(T: ArrayLike, tol: float = ZERO_ROW_TOL) -> list[str]:
    """Names of the DOF whose row of T is all zero (LI2021 eq. 28): the layout cannot act on them."""
    T = np.asarray(T, dtype=float)
    return [DOF_NAMES[i] for i in range(6) if np.max(np.abs(T[i]), initial=0.0) <= tol]


def weighted_pinv(T: ArrayLike, weights: ArrayLike | None = None) -> Array:
    """Weighted pseudo-inverse T_W⁺ = W⁻¹ Tᵀ (T W⁻¹ Tᵀ)⁺ (Fossen 2011 eq. 12.245).

    Minimises fᵀ W f subject to T f = τ for achievable τ; W = I gives the Moore–Penrose
    inverse of LI2021 eq. 34. ``weights`` are the m positive diagonal entries of W (–):
    a larger weight makes a thruster less used.
    """
    T = np.asarray(T, dtype=float)
    m = T.shape[1]
    if weights is None:
        return np.linalg.pinv(T)
    w = np.asarray(weights, dtype=float).reshape(-1)
    if w.shape != (m,) or not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise InputError(f"allocation weights {w.tolist()}: expected {m} positive numbers")
    if w.min() < MIN_WEIGHT_RATIO * w.max():
        raise InputError(
            f"allocation weights: the smallest, {w.min():.4g}, is below {MIN_WEIGHT_RATIO:g} of the largest "
            f"({w.max():.4g}); expected weights within a factor {1 / MIN_WEIGHT_RATIO:g} of each other (–)"
        )
    Winv = np.diag(1.0 / w)
    return Winv @ T.T @ np.linalg.pinv(T @ Winv @ T.T)


@dataclass(frozen=True)
class Allocation(Result):
    """Outcome of one allocation.

    Attributes
    ----------
    thrust : (m,) array — thruster forces f, N (file order)
    achieved_tau : (6,) array — T f, N and N·m
    residual : float — |T f − τ|, in the mixed units of τ
    saturated : list of str — thrusters at a limit (within 1e-6 of the limit's magnitude)
    uncontrollable : list of str — DOF the layout cannot actuate
    warnings : list of str — recoverable oddities (e.g. τ asked in an uncontrollable DOF)
    method : str — "pinv", "weighted-pinv" or "constrained"
    tau : (6,) array or None — the demanded τ, N and N·m
    names : list of str — thruster names (file order)
    configuration_matrix : (6, m) array or None — T (–, m)
    f_min, f_max : (m,) arrays or None — thrust limits, N
    command : (m,) array or None — thruster commands giving ``thrust`` at zero advance speed
        (rev/s for propellers, table units, N for ideal thrusters)
    command_unit : list of str — the unit of each command
    vehicle : str — the vehicle name or file, for the record
    """

    thrust: Array
    achieved_tau: Array
    residual: float
    saturated: list[str]
    uncontrollable: list[str]
    warnings: list[str] = field(default_factory=list)
    method: str = "constrained"
    tau: Array | None = None
    names: list[str] = field(default_factory=list)
    configuration_matrix: Array | None = None
    f_min: Array | None = None
    f_max: Array | None = None
    command: Array | None = None
    command_unit: list[str] = field(default_factory=list)
    vehicle: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The ``hydrokit allocate --json`` document (forces N, moments N·m, propeller speeds rpm)."""
        shown = None
        if self.command is not None:
            # rev/s → rpm at the edge: the JSON contract states propeller speeds in rpm
            shown = [float(c) * 60.0 if u == "rev/s" else float(c) for c, u in zip(self.command, self.command_unit)]
        T = self.configuration_matrix
        n = len(self.thrust)  # a missing side is no limit, written as null (as ±∞ is)
        lo = [None] * n if self.f_min is None else [float(a) for a in self.f_min]
        hi = [None] * n if self.f_max is None else [float(b) for b in self.f_max]
        limits = [[a, b] for a, b in zip(lo, hi)]
        return jsonable(
            {
                "vehicle": self.vehicle,
                "method": self.method,
                "thrusters": list(self.names),
                "tau": None if self.tau is None else [float(x) for x in self.tau],
                "configuration_matrix": None if T is None else [[float(x) for x in row] for row in T],
                "thrust": [float(x) for x in self.thrust],
                "thrust_limits": None if self.f_min is None and self.f_max is None else limits,
                "command": shown,
                "command_unit": ["rpm" if u == "rev/s" else u for u in self.command_unit],
                "achieved_tau": [float(x) for x in self.achieved_tau],
                "residual": float(self.residual),
                "uncontrollable": list(self.uncontrollable),
                "saturated": list(self.saturated),
                "warnings": list(self.warnings),
                "units": {"thrust": "N", "tau": "N, N·m (X,Y,Z,K,M,N)", "configuration_matrix": "-, m"},
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """One row per thruster: name, thrust (N), limits (N), command and its unit."""
        n = len(self.thrust)
        names = self.names or [f"thruster {i + 1}" for i in range(n)]
        lo = self.f_min if self.f_min is not None else [None] * n
        hi = self.f_max if self.f_max is not None else [None] * n
        cmd = self.command if self.command is not None else [None] * n
        units = self.command_unit or [""] * n
        return (
            ["thruster", "thrust", "f_min", "f_max", "command", "command_unit", "saturated"],
            [
                [names[i], float(self.thrust[i]), lo[i], hi[i], cmd[i], units[i], names[i] in self.saturated]
                for i in range(n)
            ],
        )

    def summary_rows(self) -> list[tuple[str, Any]]:
        return [
            ("method", self.method),
            ("thrust (N)", [round(float(x), 3) for x in self.thrust]),
            ("residual", self.residual),
            ("saturated", ", ".join(self.saturated) or "none"),
            ("not actuated", ", ".join(self.uncontrollable) or "none"),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Thrust per thruster with its limits on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.allocation import allocation_axes

        n = len(self.thrust)
        names = self.names or [f"thruster {i + 1}" for i in range(n)]
        return allocation_axes(names, np.asarray(self.thrust), self.f_min, self.f_max, ax)


#: the earlier name of :class:`Allocation`
AllocationResult = Allocation


#: largest demand allocated, N and N·m: a million tonnes-force is beyond any thruster set, and
#: far below where |τ|² (the residual's norm) overflows a float (1e154)
MAX_DEMAND = 1e12
#: smallest pinv weight relative to the largest (W⁻¹ of a smaller one is out of float range)
MIN_WEIGHT_RATIO = 1e-12


def _check_tau(tau: ArrayLike) -> Array:
    t = np.asarray(tau, dtype=float).reshape(-1)
    if t.shape != (6,) or not np.all(np.isfinite(t)):
        raise InputError(f"tau = {np.asarray(tau).tolist()}: expected 6 finite numbers X,Y,Z,K,M,N")
    big = np.flatnonzero(np.abs(t) > MAX_DEMAND)
    if big.size:
        k = int(big[0])
        unit = "N" if k < 3 else "N·m"
        raise InputError(
            f"tau {'XYZKMN'[k]} = {t[k]:.4g} {unit}: expected |{'XYZKMN'[k]}| ≤ {MAX_DEMAND:g} {unit} "
            "(a demand no thruster set gives)"
        )
    return t


def _uncontrollable_warning(T: Array, tau: Array) -> tuple[list[str], list[str]]:
    unc = uncontrollable_dofs(T)
    asked = [d for d in unc if tau[DOF_NAMES.index(d)] != 0.0]
    warns = []
    if asked:
        vals = ", ".join(f"{d}={tau[DOF_NAMES.index(d)]:g}" for d in asked)
        warns.append(
            f"tau asks for {vals} but the thruster layout cannot actuate "
            f"{', '.join(asked)}; those components are ignored and the rest allocated"
        )
    return unc, warns


def allocate_pinv(
    T: ArrayLike,
    tau: ArrayLike,
    weights: ArrayLike | None = None,
    f_min: ArrayLike | None = None,
    f_max: ArrayLike | None = None,
    names: list[str] | None = None,
) -> AllocationResult:
    """Unconstrained allocation f = T_W⁺ τ (LI2021 eq. 34; weighted if ``weights`` given).

    Exact (T f = τ) whenever τ is achievable and the limits are ignored. Limits, if given,
    are only used to *report* saturation (forces beyond a limit are listed, not clipped).

    Parameters
    ----------
    T : (6, m) array — configuration matrix, – and m
    tau : 6 floats — demanded [X Y Z K M N], N and N·m
    weights : m floats or None — W diagonal, –
    f_min, f_max : m floats or None — thrust limits, N
    names : list of str or None — thruster names for the report
    """
    T = np.asarray(T, dtype=float)
    tau = _check_tau(tau)
    m = T.shape[1]
    names = names or [f"T{i + 1}" for i in range(m)]
    f = weighted_pinv(T, weights) @ tau
    achieved = T @ f
    unc, warns = _uncontrollable_warning(T, tau)
    sat: list[str] = []
    lo = hi = None
    if f_min is not None or f_max is not None:  # either limit alone is checked (the other is ±inf)
        lo = np.full(m, -np.inf) if f_min is None else np.asarray(f_min, float)
        hi = np.full(m, np.inf) if f_max is None else np.asarray(f_max, float)
        # beyond a limit by more than 1e-9 of it (a limit of either sign)
        over = [n for n, x, a, b in zip(names, f, lo, hi) if x > b + 1e-9 * abs(b) or x < a - 1e-9 * abs(a)]
        if over:
            warns.append(f"pseudo-inverse thrust exceeds the limits of {', '.join(over)}")
        sat = _at_limit(f, lo, hi, names)
    return AllocationResult(
        thrust=f,
        achieved_tau=achieved,
        residual=float(np.linalg.norm(achieved - tau)),
        saturated=sat,
        uncontrollable=unc,
        warnings=warns,
        method="pinv" if weights is None else "weighted-pinv",
        tau=tau,
        names=list(names),
        configuration_matrix=T,
        f_min=lo,
        f_max=hi,
    )


def _at_limit(f: Array, lo: Array, hi: Array, names: list[str]) -> list[str]:
    # tolerance from the finite limits only (a missing limit is ±inf and never reached)
    scale = np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)), np.abs(np.where(np.isfinite(hi), hi, 0.0)))
    tol = 1e-6 * np.maximum(scale, 1.0)
    return [n for n, x, a, b, t in zip(names, f, lo, hi, tol) if x >= b - t or x <= a + t]


def allocate_constrained(
    T: ArrayLike,
    tau: ArrayLike,
    f_min: ArrayLike,
    f_max: ArrayLike,
    names: list[str] | None = None,
    dof_weights: ArrayLike | None = None,
) -> AllocationResult:
    """Allocation within every thruster's limits; least residual, then least thrust.

    Stage 1 solves ``min |T f − τ|`` subject to ``f_min ≤ f ≤ f_max`` (bounded least squares,
    :func:`hydrokit.model.bvls.bvls`, scipy's BVLS step by step). The achieved force a* = T f* of that problem
    is unique (the objective is strictly convex in T f), so every optimal f satisfies
    T f = a*. Stage 2 picks the one with the smallest |f| among them:
    ``min W² |T̂ f − â*|² + |f|²`` within the bounds, with T̂, â* scaled so |T̂| = 1 and
    W = 1e5, which keeps T f within ~|f|·1e-10 of a*; then a polishing step fixes the
    thrusters found at a limit and gives the others the exact minimum-norm solution of
    T f = a* (the KKT point of that active set), kept if it stays within the limits. If stage
    2 ever raised the residual beyond 1e-8 of the thrust scale the stage-1 solution is kept.

    Parameters
    ----------
    T : (6, m) array — configuration matrix, – and m
    tau : 6 floats — demanded [X Y Z K M N], N and N·m
    f_min, f_max : m floats — thrust limits, N (f_min ≤ 0 ≤ f_max)
    names : list of str or None — thruster names for the report
    dof_weights : 6 floats or None — Q in ``min |Q (T f − τ)|`` (1/N and 1/(N·m)), to rank
        DOF when τ is out of reach; None = identity (the plain residual). ``residual`` in
        the result is always the unweighted |T f − τ|.
    """
    T = np.asarray(T, dtype=float)
    tau = _check_tau(tau)
    m = T.shape[1]
    names = names or [f"T{i + 1}" for i in range(m)]
    lo, hi = _thrust_limits(f_min, f_max, m)
    unc, warns = _uncontrollable_warning(T, tau)
    f, a, r = _ConstrainedSolver(T, lo, hi, dof_weights).solve(tau)
    return AllocationResult(
        thrust=f,
        achieved_tau=a,
        residual=r,
        saturated=_at_limit(f, lo, hi, names),
        uncontrollable=unc,
        warnings=warns,
        method="constrained",
        tau=tau,
        names=list(names),
        configuration_matrix=T,
        f_min=lo,
        f_max=hi,
    )


def _thrust_limits(f_min: ArrayLike, f_max: ArrayLike, m: int) -> tuple[Array, Array]:
    """The limits (N) as two (m,) arrays, refused in one line unless m pairs with min ≤ max."""
    lo = np.asarray(f_min, dtype=float).reshape(-1)
    hi = np.asarray(f_max, dtype=float).reshape(-1)
    if lo.shape != (m,) or hi.shape != (m,) or np.any(lo > hi):
        raise InputError(f"thrust limits: expected {m} pairs with min ≤ max, got {lo} and {hi}")
    return lo, hi


class _ConstrainedSolver:
    """The two stages of :func:`allocate_constrained` for one T and one set of limits, with
    everything that does not depend on τ computed once (the closed loop calls it with a new
    τ every step it saturates). The packed arrays are the compiled closed loop's too, in the same
    layout (Q T and the stage-2 matrix in Fortran order), so both call one specialization of
    :func:`constrained_kernel`."""

    def __init__(self, T: Array, lo: Array, hi: Array, dof_weights: ArrayLike | None) -> None:
        m = T.shape[1]
        self.T, self.lo, self.hi = np.asfortranarray(T, dtype=np.float64), lo, hi
        # Degenerate bounds (min == max) are allowed by the maths but not by BVLS.
        fixed = hi - lo <= 0
        lo_s, hi_s = lo.copy(), hi.copy()
        hi_s[fixed] = lo[fixed] + 1e-12
        self.bounds = (np.ascontiguousarray(lo_s, dtype=np.float64), np.ascontiguousarray(hi_s, dtype=np.float64))
        Q = np.ones(6) if dof_weights is None else np.asarray(dof_weights, dtype=float).reshape(6)
        self.Q = np.ascontiguousarray(Q, dtype=np.float64)
        self.QT = np.asfortranarray(Q[:, None] * T, dtype=np.float64)
        self.scale = scale = max(float(np.linalg.norm(T, 2)), 1e-300)
        self.A = np.asfortranarray(np.vstack([_STAGE2_WEIGHT * T / scale, np.eye(m)]), dtype=np.float64)
        self.thrust_scale = max(float(np.max(np.abs(np.concatenate([lo, hi])))), 1.0)
        self.q_max = float(np.max(Q))
        self.polish_tol = np.ascontiguousarray(1e-7 * np.maximum(np.maximum(np.abs(lo), np.abs(hi)), 1.0))
        self._lo = np.ascontiguousarray(lo, dtype=np.float64)
        self._hi = np.ascontiguousarray(hi, dtype=np.float64)

    def args(self, tau: Array) -> tuple[Any, ...]:
        """The arguments of :func:`constrained_law` for the demanded τ (N, N·m)."""
        lo_s, hi_s = self.bounds
        return (
            np.ascontiguousarray(tau, dtype=np.float64),
            self.T,
            self._lo,
            self._hi,
            lo_s,
            hi_s,
            self.Q,
            self.QT,
            self.A,
            self.scale,
            self.thrust_scale,
            self.q_max,
            self.polish_tol,
        )

    def solve(self, tau: Array) -> tuple[Array, Array, float]:
        """(f, T f, |T f − τ|) for the demanded τ: N, N and N·m, N."""
        f = constrained_kernel()(*self.args(tau))
        a = self.T @ f
        return f, a, float(np.linalg.norm(a - tau))


def _clip_vec(x, lo, hi):  # noqa: ANN001, ANN202
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = min(max(x[i], lo[i]), hi[i])
    return out


def _norm_diff(a, b):  # noqa: ANN001, ANN202
    s = 0.0
    for i in range(a.shape[0]):
        s += (a[i] - b[i]) * (a[i] - b[i])
    return math.sqrt(s)


def _polish(T, target, f, lo, hi, tol):  # noqa: ANN001, ANN202
    """Remove the stage-2 penalty's small bias: keep the thrusters found at a limit, give the
    others the exact minimum-norm solution of T f = target (the KKT point for that active set).
    The polished point is used only if it stays within the limits and misses the target by no
    more than f does.

    T : (6, m) array; target : 6 floats, N and N·m; f, lo, hi : m floats, N; tol : m floats —
    the limit tolerance, N."""
    m = f.shape[0]
    active = np.empty(m, dtype=np.bool_)
    n_free = 0
    for i in range(m):
        active[i] = f[i] <= lo[i] + tol[i] or f[i] >= hi[i] - tol[i]
        if not active[i]:
            n_free += 1
    if n_free == 0:
        return f
    g = np.zeros(m)
    free = np.empty(n_free, dtype=np.int64)
    k = 0
    for i in range(m):
        if active[i]:
            g[i] = lo[i] if f[i] <= lo[i] + tol[i] else hi[i]
        else:
            free[k] = i
            k += 1
    rhs = target - T @ g  # g is zero on the free thrusters here
    # pinv(T_free) @ rhs as the minimum-norm least-squares solution (singular values below
    # 1e-15 of the largest cut, as numpy.linalg.pinv)
    gf = lstsq_small(_cols(T, free, n_free), rhs, 1e-15)
    for jj in range(n_free):
        g[free[jj]] = gf[jj]
    for i in range(m):
        if not (g[i] >= lo[i] and g[i] <= hi[i]):
            return f
    if _norm_diff(T @ g, target) <= _norm_diff(T @ f, target):
        return g
    return f


def constrained_law(tau, T, lo, hi, lo_s, hi_s, Q, QT, A2, scale, thrust_scale, q_max, ptol):  # noqa: ANN001, ANN201
    """The thrusts of :func:`allocate_constrained`, written once: the Python allocator and the
    compiled closed loop call it compiled (:func:`constrained_kernel`).

    Parameters
    ----------
    tau : 6 floats — demanded [X Y Z K M N], N and N·m (unactuated DOFs already zeroed)
    T : (6, m) array — configuration matrix, – and m
    lo, hi : m floats — thrust limits, N
    lo_s, hi_s : m floats — the same with a degenerate pair (min = max) opened by 1e-12 N
    Q : 6 floats — DOF weights, 1/N and 1/(N·m)
    QT : (6, m) array — Q T
    A2 : (6 + m, m) array — the stage-2 system [W T / |T|₂; I]
    scale : float — |T|₂; thrust_scale : float — the largest |limit| (≥ 1), N; q_max : float — max Q
    ptol : m floats — the polishing step's limit tolerance, N

    Returns
    -------
    m floats — the thrusts, N
    """
    m = T.shape[1]
    f1 = _clip_vec(bvls(QT, Q * tau, lo_s, hi_s, 1e-12), lo, hi)
    a1 = T @ f1
    b2 = np.zeros(6 + m)
    for i in range(6):
        b2[i] = _STAGE2_WEIGHT * a1[i] / scale
    f2 = _clip_vec(bvls(A2, b2, lo_s, hi_s, 1e-12), lo, hi)
    f2 = _polish(T, a1, f2, lo, hi, ptol)
    a2 = T @ f2
    q1 = 0.0
    q2 = 0.0
    for i in range(6):
        q1 += (Q[i] * (a1[i] - tau[i])) ** 2
        q2 += (Q[i] * (a2[i] - tau[i])) ** 2
    if math.sqrt(q2) <= math.sqrt(q1) + 1e-8 * thrust_scale * q_max:
        return f2
    return f1  # defensive: stage 2 is designed not to lose residual (tested by forcing it)


@functools.cache
def constrained_kernel() -> Any:  # noqa: ANN401
    """:func:`constrained_law` compiled with the laws it calls (numba is imported here, at the
    first saturated allocation, not when this module is)."""
    from hydrokit._numba import compile_law

    lstsq = compile_law(lstsq_small, allocates=True)
    cols = compile_law(_cols, allocates=True)
    solver = compile_law(
        bvls,
        allocates=True,
        lstsq_small=lstsq,
        _cols=cols,
        _on_bound_part=compile_law(_on_bound_part, allocates=True),
        _kkt=compile_law(_kkt, allocates=True),
    )
    return compile_law(
        constrained_law,
        allocates=True,
        bvls=solver,
        _clip_vec=compile_law(_clip_vec, allocates=True),
        _polish=compile_law(
            _polish, allocates=True, lstsq_small=lstsq, _cols=cols, _norm_diff=compile_law(_norm_diff, allocates=True)
        ),
    )


def pinv_allocate(P, tau, f_min, f_max, f):  # noqa: ANN001, ANN201
    """The unconstrained step of :class:`Allocator` on plain floats: f ← P τ, and whether it
    breaks a thrust limit.

    Parameters
    ----------
    P : (m, 6) table — the (weighted) pseudo-inverse T_W⁺ (:func:`weighted_pinv`), N per N and
        1/m; any object indexed as ``P[i][j]``
    tau : 6 floats — demanded [X Y Z K M N], N and N·m
    f_min, f_max : m floats — thrust limits, N
    f : m floats, written — the thrusts P τ, N

    Returns
    -------
    bool — some f_i lies outside [f_min_i, f_max_i] (or is NaN): the constrained solution is needed

    Notes
    -----
    f = T_W⁺ τ, LI2021 eq. 34 (Fossen 2011 eq. 12.245 weighted). Each f_i is summed over
    τ_0 … τ_5 in order. Written once: :class:`Allocator` calls it as Python, the compiled
    closed loop compiles it (``compile_law``).
    """
    limited = False
    for i in range(len(f)):
        row = P[i]
        s = 0.0
        for j in range(6):
            s += row[j] * tau[j]
        f[i] = s
        if not (s <= f_max[i] and s >= f_min[i]):
            limited = True
    return limited


class Allocator:
    """Fast allocation for control loops: cached pseudo-inverse, constrained only if needed.

    The weighted pseudo-inverse is computed once; each call costs one matrix–vector product.
    Only when that solution would break a limit is :func:`allocate_constrained` called.

    Parameters
    ----------
    T : (6, m) array — configuration matrix, – and m
    f_min, f_max : m floats — thrust limits, N
    weights : m floats or None — W diagonal for the pseudo-inverse, –
    dof_weights : 6 floats, "capability" or None — Q for the constrained fallback (see
        :func:`allocate_constrained`). "capability" (default) uses 1 / (largest |τ_j| the
        layout can produce in DOF j), so a shortfall counts relative to what each DOF can
        do; without it a 40 N·m yaw shortfall weighs like 40 N of surge, and a saturated
        speed loop can starve heading control.
    """

    def __init__(
        self,
        T: ArrayLike,
        f_min: ArrayLike,
        f_max: ArrayLike,
        weights: ArrayLike | None = None,
        dof_weights: ArrayLike | str | None = "capability",
    ) -> None:
        self.T = np.asarray(T, dtype=float)
        self.f_min, self.f_max = _thrust_limits(f_min, f_max, self.T.shape[1])
        self.P = weighted_pinv(self.T, weights)
        # plain floats for pinv_allocate (the same numbers; Python indexes tuples fastest)
        self._P_rows = tuple(tuple(row) for row in self.P.tolist())
        self._limits = (tuple(self.f_min.tolist()), tuple(self.f_max.tolist()))
        self.unactuated = np.array([d in uncontrollable_dofs(self.T) for d in DOF_NAMES])
        if isinstance(dof_weights, str):
            if dof_weights != "capability":
                raise InputError(f"dof_weights = {dof_weights!r}: expected 6 numbers or 'capability'")
            reach = np.abs(self.T) @ np.maximum(np.abs(self.f_min), np.abs(self.f_max))
            self.Q: Array | None = np.where(reach > 0, 1.0 / np.where(reach > 0, reach, 1.0), 1.0)
        else:
            self.Q = None if dof_weights is None else np.asarray(dof_weights, dtype=float)
        self._solver: _ConstrainedSolver | None = None  # built at the first saturated call

    def __call__(self, tau: ArrayLike) -> tuple[Array, bool]:
        """Thrust (N) for the demanded τ (N, N·m) and whether the limits were active."""
        tau = np.asarray(tau, dtype=float)
        f_list = [0.0] * self.T.shape[1]
        if not pinv_allocate(self._P_rows, tau.reshape(-1).tolist(), *self._limits, f_list):
            return np.array(f_list), False
        tau_eff = _check_tau(np.where(self.unactuated, 0.0, tau))
        # what allocate_constrained(T, tau_eff, f_min, f_max, dof_weights=Q) computes, with
        # its τ-independent parts kept between calls
        solver = self._solver
        if solver is None:
            solver = self._solver = _ConstrainedSolver(self.T, self.f_min, self.f_max, self.Q)
        return solver.solve(tau_eff)[0], True
