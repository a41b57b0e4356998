"""State reconstruction and the equation-error fit of system identification (issue #44).

**Smoother.** Each measured channel is smoothed by a Kalman filter and Rauch–Tung–Striebel
smoother of the kinematic model "white jerk" (state: value, rate, acceleration; Bar-Shalom et
al. 2001 §6.2) over the union of its own sample times and a uniform grid, so multi-rate
channels need no common grid and give their derivative (the accelerations ν̇ the
equation-error fit needs). The jerk intensity and the measurement noise are chosen by maximum
likelihood on a grid; that noise σ is each channel's first weight.

**Equation error.** (M_RB + M_A) ν̇ = τ − C(ν) ν − D(ν) ν + τ_terms − g(η) is affine in every
free coefficient (added mass enters M and the Coriolis matrix linearly; a derivative term,
``delta()`` terms included, enters linearly), so the equation residual
e(θ) = M(θ) ν̇ − F(x, τ, δ; θ) has exact regressor columns e(θ + δ e_k) − e(θ), computed with the
compiled right-hand side itself (no second copy of the model): F = M ν̇₀ with ν̇₀ the compiled
:func:`~hydrokit.simulate.compiled.deriv` at the run's thruster force τ and deflections δ (so
physical fins, whose force depends on both, and ``delta()`` terms are in it) and in the run's
logged current and wind (the vehicle's ``wind:`` model at the wind relative to the vehicle: a
wind force left out would be fitted as damping). Only the
vehicle's kept DOF (``dofs``) give equations. Weighted least squares per DOF equation (weights
from the residual RMS of a first pass) gives the start of the output-error fit and an
independent estimate.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from hydrokit._numba import njit
from hydrokit.errors import InputError
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate import compiled as _compiled
from hydrokit.simulate.compiled import deriv
from hydrokit.sysid.model import CHANNELS, Parameter, RunData, stack_packs, values_of, vehicle_arrays, with_values


@dataclass(frozen=True)
class Smoothed:
    """A run's reconstructed states on a uniform grid.

    time : (n,) — s; states : (n, 12) — η, ν (m, rad, m/s, rad/s; 0 where never measured);
    nu_dot : (n, 6) — body accelerations, m/s², rad/s²; known : (12,) bool — state measured
    (directly or through the Euler-angle kinematics); noise : channel → residual RMS (SI)
    """

    time: np.ndarray
    states: np.ndarray
    nu_dot: np.ndarray
    known: np.ndarray
    noise: dict[str, float]

    def at(self, t: float) -> np.ndarray:
        """The 12 states at time ``t`` (linear between grid points)."""
        return np.array([np.interp(t, self.time, self.states[:, k]) for k in range(12)])


@njit
def _mm3(A, B, out):  # noqa: ANN001, ANN202
    """out = A B for 3 × 3 arrays (no allocation: the filter's steps are many and tiny)."""
    for i in range(3):
        for j in range(3):
            out[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]


@njit
def _mm3t(A, B, out):  # noqa: ANN001, ANN202
    """out = A Bᵀ for 3 × 3 arrays."""
    for i in range(3):
        for j in range(3):
            out[i, j] = A[i, 0] * B[j, 0] + A[i, 1] * B[j, 1] + A[i, 2] * B[j, 2]


@njit
def _inv3(A, out):  # noqa: ANN001, ANN202
    """out = A⁻¹ of a 3 × 3 array by its cofactors (A a covariance: symmetric positive definite)."""
    c00 = A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1]
    c01 = A[1, 2] * A[2, 0] - A[1, 0] * A[2, 2]
    c02 = A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]
    det = A[0, 0] * c00 + A[0, 1] * c01 + A[0, 2] * c02
    if det == 0.0:  # singular to rounding (a flat channel): LAPACK's LU decides, as before
        out[:, :] = np.linalg.inv(A)
        return
    out[0, 0] = c00 / det
    out[1, 0] = c01 / det
    out[2, 0] = c02 / det
    out[0, 1] = (A[0, 2] * A[2, 1] - A[0, 1] * A[2, 2]) / det
    out[1, 1] = (A[0, 0] * A[2, 2] - A[0, 2] * A[2, 0]) / det
    out[2, 1] = (A[0, 1] * A[2, 0] - A[0, 0] * A[2, 1]) / det
    out[0, 2] = (A[0, 1] * A[1, 2] - A[0, 2] * A[1, 1]) / det
    out[1, 2] = (A[0, 2] * A[1, 0] - A[0, 0] * A[1, 2]) / det
    out[2, 2] = (A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]) / det


@njit
def _rts(times, values, measured, q, r, smooth, out):  # noqa: ANN001, ANN202
    """Kalman filter (and RTS smoother if ``smooth``) of the white-jerk kinematic model
    s = [y, ẏ, ÿ] over ``times`` (values used where ``measured``); returns the log-likelihood,
    writes the smoothed [y, ẏ, ÿ] rows into ``out``."""
    n = times.shape[0]
    keep = 1 if not smooth else n  # the filter's history is needed by the smoother only
    m_f = np.zeros((keep, 3))
    P_f = np.zeros((keep, 3, 3))
    m_p = np.zeros((keep, 3))
    P_p = np.zeros((keep, 3, 3))
    F_all = np.zeros((keep, 3, 3))
    first = 0
    while first < n and not measured[first]:
        first += 1
    m = np.zeros(3)
    m[0] = values[first] if first < n else 0.0
    P = np.zeros((3, 3))
    P[0, 0] = 10.0 * r
    P[1, 1] = 1e2
    P[2, 2] = 1e4
    F = np.eye(3)
    FP = np.empty((3, 3))
    K = np.empty(3)
    ll = 0.0
    for i in range(n):
        if i > 0:
            h = times[i] - times[i - 1]
            F[0, 1] = h
            F[0, 2] = 0.5 * h * h
            F[1, 2] = h
            m0 = m[0] + F[0, 1] * m[1] + F[0, 2] * m[2]
            m1 = m[1] + F[1, 2] * m[2]
            m[0], m[1] = m0, m1
            _mm3(F, P, FP)
            _mm3t(FP, F, P)
            P[0, 0] += q * h**5 / 20.0
            P[0, 1] += q * h**4 / 8.0
            P[1, 0] += q * h**4 / 8.0
            P[0, 2] += q * h**3 / 6.0
            P[2, 0] += q * h**3 / 6.0
            P[1, 1] += q * h**3 / 3.0
            P[1, 2] += q * h**2 / 2.0
            P[2, 1] += q * h**2 / 2.0
            P[2, 2] += q * h
            if smooth:
                F_all[i] = F
        if smooth:
            m_p[i] = m
            P_p[i] = P
        if measured[i]:
            S = P[0, 0] + r
            v = values[i] - m[0]
            for j in range(3):
                K[j] = P[j, 0] / S
            for j in range(3):
                m[j] += K[j] * v
            for j in range(3):
                for k in range(3):
                    FP[j, k] = P[j, k] - K[j] * P[0, k]
            P[:, :] = FP
            ll += -0.5 * (math.log(2 * math.pi * S) + v * v / S)
        if smooth:
            m_f[i] = m
            P_f[i] = P
    if smooth:
        # the smoothed means need the gains C only (the smoothed covariances are not used)
        ms = m_f[n - 1].copy()
        out[n - 1] = ms
        Pinv = np.empty((3, 3))
        C = np.empty((3, 3))
        d = np.empty(3)
        for i in range(n - 2, -1, -1):
            _inv3(P_p[i + 1], Pinv)
            _mm3t(P_f[i], F_all[i + 1], FP)
            _mm3(FP, Pinv, C)
            for j in range(3):
                d[j] = ms[j] - m_p[i + 1, j]
            for j in range(3):
                ms[j] = m_f[i, j] + C[j, 0] * d[0] + C[j, 1] * d[1] + C[j, 2] * d[2]
            out[i] = ms
    return ll


#: rows on which a channel's noise and jerk intensity are estimated
ML_SAMPLES = 1500


class _Channel:
    """Smoothed channel: value and derivative at the grid, noise σ (ML)."""

    def __init__(self, ts: np.ndarray, ys: np.ndarray, grid: np.ndarray):
        times = np.union1d(ts, grid)
        measured = np.isin(times, ts)
        values = np.zeros(times.size)
        values[measured] = ys
        d3 = np.diff(ys, 3) if ys.size > 3 else np.diff(ys)
        r0 = max(float(np.var(d3)) / 20.0, 1e-16)
        span = max(float(np.var(ys)), r0)
        # the noise and jerk intensity by maximum likelihood on a middle stretch (at most
        # ML_SAMPLES rows): a coarse grid in q, then a finer one about the best
        a = int(max(0, (times.size - ML_SAMPLES) // 2))
        part = slice(a, a + ML_SAMPLES)
        tp, vp, mp = times[part], values[part], measured[part]
        scratch = np.zeros((tp.size, 3))
        best = (-np.inf, r0, span)
        for rf in (0.25, 1.0, 4.0):
            for lq in (-6.0, -3.0, 0.0, 3.0, 6.0):
                ll = _rts(tp, vp, mp, span * 10.0**lq, rf * r0, False, scratch)
                if ll > best[0]:
                    best = (ll, rf * r0, span * 10.0**lq)
        for rf in (0.5, 0.7, 1.0, 1.4, 2.0):
            for lf in (-1.0, -0.5, 0.0, 0.5, 1.0):
                ll = _rts(tp, vp, mp, best[2] * 10.0**lf, rf * best[1], False, scratch)
                if ll > best[0]:
                    best = (ll, rf * best[1], best[2] * 10.0**lf)
        out = np.zeros((times.size, 3))
        _rts(times, values, measured, best[2], best[1], True, out)
        at = np.searchsorted(times, grid)
        self.value = out[at, 0]
        self.rate = out[at, 1]
        self.sigma = math.sqrt(best[1])


def smooth_run(run: RunData, dt: float = 0.02) -> Smoothed:
    """Smooth every channel of ``run`` onto a grid of step ``dt`` (s); see module docstring.

    Angular rates missing from the file are rebuilt from the smoothed Euler angles
    (ν₂ = T(Θ)⁻¹ Θ̇, Fossen eq. 2.29); a linear velocity missing stays unknown (0).
    """
    from hydrokit.core.kinematics import euler_rate_matrix

    t0, t1 = float(run.time[0]), float(run.time[-1])
    grid = np.arange(t0, t1 + 0.5 * dt, dt)
    grid = grid[grid <= t1 + 1e-9]
    states = np.zeros((grid.size, 12))
    deriv = np.zeros((grid.size, 12))
    known = np.zeros(12, bool)
    noise: dict[str, float] = {}
    for k, c in enumerate(CHANNELS):
        if c not in run.channels:
            continue
        ts, ys = run.channels[c]
        if ts.size < 2:
            continue
        ch = _Channel(np.asarray(ts, float), np.asarray(ys, float), grid)
        noise[c] = ch.sigma
        states[:, k] = ch.value
        deriv[:, k] = ch.rate
        known[k] = True
    if known[3:6].all() and not known[9:12].all():
        for i in range(grid.size):
            rates = np.linalg.solve(euler_rate_matrix(states[i, 3], states[i, 4]), deriv[i, 3:6])
            for j in range(3):
                if not known[9 + j]:
                    states[i, 9 + j] = rates[j]
        missing = ~known[9:12]
        for jj in np.nonzero(missing)[0]:
            deriv[:, 9 + jj] = np.gradient(states[:, 9 + jj], grid)
        known[9:12] = True
    return Smoothed(grid, states, deriv[:, 6:12], known, noise)


#: scratch length of the compiled right-hand side
_BUF = _compiled.BUF_SIZE


@njit
def _accelerations(T, X, U, env, V_all, out):  # noqa: ANN001, ANN202
    """ν̇ for every vehicle k of the stacked packs ``V_all`` and state row i at time T[i] and
    input row U[i] = [X..N, δ_1 … δ_n] in the current and wind of ``env`` at T[i] (the compiled
    right-hand side)."""
    tau = np.zeros((1, 1 + U.shape[1]))
    buf = np.empty(_BUF)
    xd = np.empty(12)
    for k in range(V_all[0].shape[0]):
        V = _compiled.vehicle_member_compiled(V_all, k)
        for i in range(X.shape[0]):
            for j in range(U.shape[1]):
                tau[0, 1 + j] = U[i, j]
            deriv(
                T[i],
                X[i],
                False,
                tau,
                env,
                V,
                buf,
                xd,
            )
            for j in range(6):
                out[k, i, j] = xd[6 + j]


def model_force(
    vehicles: Sequence[Vehicle],
    states: np.ndarray,
    inputs: np.ndarray | None = None,
    times: np.ndarray | None = None,
    env: np.ndarray | None = None,
) -> np.ndarray:
    """F(x, τ, δ) = M ν̇, the whole right-hand side force (N, N·m) of each vehicle at each state
    row: (nv, n, 6).

    Parameters
    ----------
    vehicles : Vehicles sharing one term structure
    states : (n, 12) — η, ν (m, rad, m/s, rad/s)
    inputs : (n, 6 + n_inputs) or None — per row the thruster force X..N (N, N·m) and the
        vehicle's input vector (deflections, rad, in the vehicle's surface order, then thrusts,
        N, and rotation rates, rev/s); None: no force, no input
    times : (n,) or None — time of each row, s, on the clock of ``env`` (None: 0)
    env : (k, 4 or 6) or None — the logged current and wind, rows [t, v_N, v_E, v_D, w_N, w_E]
        (s, m/s; :func:`hydrokit.model.dynamics.environment_table`): the forces are those at
        the velocity relative to the water and the air; None: still water and air
    """
    p = stack_packs(vehicles)
    n = states.shape[0]
    out = np.empty((len(vehicles), n, 6))
    U = np.zeros((n, 6)) if inputs is None else np.asarray(inputs, float)
    _accelerations(
        np.zeros(n) if times is None else np.ascontiguousarray(times, float),
        np.ascontiguousarray(states, float),
        np.ascontiguousarray(U),
        np.zeros((1, 4)) if env is None else np.ascontiguousarray(env, float),
        vehicle_arrays(p),
        out,
    )
    return np.einsum("kij,knj->kni", np.stack([v.M for v in vehicles]), out)


@dataclass(frozen=True)
class EquationError:
    """Equation-error estimate.

    values : (p,) — SI; covariance : (p, p) — SI², inflated for coloured residuals;
    dofs : tuple of int — the equations used; rms : (6,) — equation residual RMS, N or N·m
    """

    values: np.ndarray
    covariance: np.ndarray
    dofs: tuple[int, ...]
    rms: np.ndarray

    @property
    def std(self) -> np.ndarray:
        return np.sqrt(np.clip(np.diag(self.covariance), 0, None))


def equation_error(
    vehicle: Vehicle,
    params: Sequence[Parameter],
    smoothed: Sequence[Smoothed],
    taus: Sequence[np.ndarray],
    trim: float = 1.0,
    window: float = 2.0,
    envs: Sequence[np.ndarray | None] | None = None,
) -> EquationError:
    """Weighted least squares on the equations of motion (module docstring), integrated over
    windows.

    Parameters
    ----------
    vehicle : Vehicle — the base (values of every parameter not free)
    params : the free parameters
    smoothed : per run, its :class:`Smoothed` states
    taus : per run, (n, 6 + n_inputs) thruster force on the smoothed grid, N and N·m, then the
        vehicle's input vector: the control surfaces' deflections, rad, and each thruster's
        thrust, N, and rotation rate, rev/s (:func:`tau_on_grid` of the force table)
    trim : float — s cut from each end of a run (at most a tenth of it; smoother ends are the
        least certain)
    window : float — s; the equations are integrated over consecutive windows of this length,
        M (ν(b) − ν(a)) = ∫_a^b F dt, divided by b − a (a mean force, N or N·m): held inputs
        jump (a rudder's deflection, a measured thrust) while the smoother, which assumes a
        continuous acceleration, smears ν̇ over a few samples — the integral needs ν only, and
        takes the jump exactly. 0: the equations at every grid point, with the smoothed ν̇
    envs : per run, its logged current and wind (rows [t, v_N, v_E, v_D, w_N, w_E], s on the
        clock of its smoothed time, m/s; :meth:`hydrokit.io.runlog.RunLog.environment_table`)
        or None (still water and air); None: none for any run. The current's and the wind's
        forces (the vehicle's ``wind:`` model) enter F as in the simulation, so a wind-blown
        run does not bias the damping the regression returns
    """
    from hydrokit.sysid.stats import sandwich

    p = len(params)
    theta0 = values_of(vehicle, params)
    step = np.maximum(np.abs(theta0), 1.0)
    # a surface's or thruster's field enters nonlinearly and within limits (a wake fraction
    # below 1): a small step linearises it where it is (a thruster's field moves the thrust,
    # which these equations take as given, so its column is 0 here: its start is its base value)
    fields = np.array([q.kind in ("surface", "thruster") for q in params], dtype=bool)
    step[fields] = 0.05 * np.maximum(np.abs(theta0[fields]), 0.1)
    vehicles = [with_values(vehicle, params, theta0)]
    for k in range(p):
        th = theta0.copy()
        th[k] += step[k]
        vehicles.append(with_values(vehicle, params, th))
    Ms = np.stack([v.M for v in vehicles])
    rows_e: list[np.ndarray] = []
    rows_phi: list[np.ndarray] = []
    for sm, tau, env in zip(smoothed, taus, [None] * len(smoothed) if envs is None else envs):
        cut = min(trim, 0.1 * float(sm.time[-1] - sm.time[0]))
        keep = (sm.time >= sm.time[0] + cut) & (sm.time <= sm.time[-1] - cut)
        if not np.any(keep):
            keep[:] = True
        # (p+1, n, 6), thrust, fins, current and wind included
        f = model_force(vehicles, sm.states[keep], tau[keep], sm.time[keep], env)
        t = sm.time[keep]
        w = int(round(window / float(sm.time[1] - sm.time[0]))) if window > 0 and sm.time.size > 1 else 0
        if w >= 1 and t.size > w:
            # ∫F dt by the trapezoidal rule between window bounds, and Δν over each window
            cum = np.concatenate(
                [
                    np.zeros((f.shape[0], 1, 6)),
                    np.cumsum(0.5 * (f[:, 1:] + f[:, :-1]) * np.diff(t)[None, :, None], axis=1),
                ],
                axis=1,
            )
            b = np.arange(0, t.size, w)
            if t.size - 1 - b[-1] >= w // 2:  # the rest of the run: a last, shorter window
                b = np.append(b, t.size - 1)
            span = np.diff(t[b])[:, None]
            dv = np.diff(sm.states[keep][b, 6:12], axis=0)
            e = (np.einsum("kij,nj->kni", Ms, dv) - np.diff(cum[:, b], axis=1)) / span[None]
        else:
            e = np.einsum("kij,nj->kni", Ms, sm.nu_dot[keep]) - f
        rows_e.append(e[0])
        rows_phi.append(np.moveaxis((e[1:] - e[0]) / step[:, None, None], 0, -1))  # (n, 6, p)
    E = np.concatenate(rows_e)  # (N, 6)
    Phi = np.concatenate(rows_phi)  # (N, 6, p)
    dofs = tuple(int(d) for d in vehicle.dofs if np.any(Phi[:, d, :] != 0))
    if not dofs:
        raise InputError("no free parameter enters the equations of motion")
    n_rows = E.shape[0] * len(dofs)
    if n_rows <= p:
        raise InputError(f"{n_rows} equation samples for {p} free parameters; expected more samples than parameters")
    weights = np.array([1.0 / max(np.sqrt(np.mean(E[:, d] ** 2)), 1e-12) for d in range(6)])
    for _ in range(2):
        A = np.concatenate([Phi[:, d, :] * weights[d] for d in dofs])
        b = -np.concatenate([E[:, d] * weights[d] for d in dofs])
        delta, *_ = np.linalg.lstsq(A, b, rcond=None)
        res = np.stack([E[:, d] + Phi[:, d, :] @ delta for d in range(6)], axis=1)
        rms = np.sqrt(np.mean(res**2, axis=0))
        weights = 1.0 / np.maximum(rms, 1e-12)
    A = np.concatenate([Phi[:, d, :] * weights[d] for d in dofs])
    r = np.concatenate([res[:, d] * weights[d] for d in dofs])
    lengths = [len(sm_e) for sm_e in rows_e]
    # residual series: one per DOF and run, in the stacking order of A
    blocks = []
    offset = 0
    for _d in dofs:
        start = 0
        for n in lengths:
            blocks.append((offset + start, offset + start + n))
            start += n
        offset += E.shape[0]
    cov = sandwich(A, r, blocks)
    return EquationError(theta0 + delta, cov, dofs, rms)


def tau_on_grid(table: np.ndarray, time: np.ndarray) -> np.ndarray:
    """The force table (rows [t, X..N, δ…, T…, n…]) interpolated at ``time`` (s): (n, columns − 1)
    — forces in N, N·m, deflections in rad, thrusts in N, rotation rates in rev/s."""
    return np.stack([np.interp(time, table[:, 0], table[:, 1 + j]) for j in range(table.shape[1] - 1)], axis=1)


def initial_noise(smoothed: Sequence[Smoothed]) -> Mapping[str, float]:
    """Per channel, the RMS smoother residual over all runs (SI): the first weights."""
    out: dict[str, list[float]] = {}
    for sm in smoothed:
        for c, v in sm.noise.items():
            if np.isfinite(v):
                out.setdefault(c, []).append(v)
    return {c: float(np.sqrt(np.mean(np.square(v)))) for c, v in out.items()}
