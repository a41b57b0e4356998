"""System identification from free-running logs (issue #44): a vehicle's added mass and
damping from its own dives.

1. **States** — every measured channel is smoothed (:mod:`hydrokit.sysid.smooth`: a
   smoothing spline = RTS smoother of the kinematics, multi-rate) for the accelerations, the
   initial states and the first noise levels.
2. **Equation error** — weighted least squares on the equations of motion (affine in the
   coefficients): the start of step 3 and an independent estimate.
3. **Output error** — Levenberg–Marquardt on the open-loop simulation of every training run
   from the recorded thruster commands (rotor lag and thrust curves of the vehicle file), each
   channel weighted by its noise σ (re-estimated from the residuals until stable), with the
   initial state of every run estimated alongside. Jacobians by forward differences, all
   perturbed vehicles of a run integrated at once on the compiled batch RK4.
4. **Covariance** — the Fisher information A = JᵀJ, made robust to coloured residuals by the
   sandwich of :mod:`hydrokit.sysid.stats`; σ, correlations, the condition number,
   pairs that move together, parameters with σ > |value|, values past a physical bound.
5. **Validation** — held-out runs predicted open loop from their smoothed initial state;
   NRMSE = RMS(measured − predicted) / standard deviation of the measured channel.

The integrator check re-linearises at the estimate with half the step: the Gauss–Newton step
it implies, in units of σ, is ``step_check`` (issue: must stay below 0.1).
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.errors import InputError
from hydrokit.model.envelope import Envelope
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.envelope import run_envelope
from hydrokit.sysid.lm import Diverged as _Diverged
from hydrokit.sysid.lm import projected_lm
from hydrokit.sysid.model import (
    CHANNELS,
    Parameter,
    PreparedRun,
    RunData,
    curve_thrusts,
    free_parameters,
    prepare_run,
    simulate_run,
    stack_packs,
    values_of,
    with_values,
)
from hydrokit.sysid.problem import Problem
from hydrokit.sysid.stats import (
    channel_checks,
    condition_number,
    correlation,
    sandwich,
    verdict,
    whiteness,
)

METHODS = ("output-error", "equation-error")
#: |ρ| above which two parameters are said to move together
CORRELATION_LIMIT = 0.95
#: feedback is said detected when a DOF's command correlates with the sensor noise of that
#: DOF's channels beyond this many times the 1/√n band (open-loop generated dives: below 3)
FEEDBACK_Z = 5.0
#: the position and rate channels of each DOF (what a hold would act on)
_HOLD_CHANNELS = (("x", "u"), ("y", "v"), ("z", "w"), ("phi", "p"), ("theta", "q"), ("psi", "r"))


@dataclass(frozen=True)
class SysidResult(Result):
    """An identified vehicle with its uncertainty and the evidence for it.

    Attributes
    ----------
    vehicle : Vehicle — the base vehicle with the identified values
    parameters : tuple of str — free names; units : tuple of str — their SI units
    values, sigma, start, base : (p,) — estimate, standard error (coloured-residual sandwich),
        start of the output-error fit (equation error), base-file value; SI
    fisher_sigma : (p,) — σ from the Fisher information alone (white residuals), SI
    covariance : (p, p) — SI²; correlation : (p, p); condition : float — of the Fisher
        information scaled to unit diagonal
    equation_error : dict — ``values`` and ``sigma`` of the equation-error fit (SI)
    runs : list of dict — per run: name, holdout, duration (s), per channel residual RMS (SI),
        whiteness (lag-1 ρ, fraction of lags outside the 95 % band), NRMSE, sensor noise σ (SI)
        and the residual's ratio to it, its systematic part (:func:`~hydrokit.sysid.stats.channel_checks`)
    noise : dict — channel → σ used as weight (SI)
    predictions : list of dict — per run and channel: time (s), measured, simulated, low, high
        (2.5/97.5 % of the Monte Carlo over the covariance)
    messages : tuple of str — identifiability in plain words; warnings : tuple of str
    verdict : dict — ``fits`` (bool) and ``reasons`` (sentences): does the model describe the
        runs (:func:`hydrokit.sysid.stats.verdict`: held-out NRMSE, residuals against
        the sensor noise and their whiteness)
    method : str; iterations : int; step_check : float — max |Δθ|/σ on halving the step
    timing : dict — seconds: total, simulation (the fit's and the integrator check's), and each
        stage in order: smoothing, force tables, equation error, feedback check, setup, windows
        first (when the windows' fit starts the whole runs'), output error (with its simulations),
        covariance, step check, bands (the Monte Carlo predictions), held-out preparation, report
    windows : dict — of a windowed fit: ``count``, ``length_s`` (s), ``continuity`` (–) and
        ``largest_jump_sigma``, the largest jump of a measured state at a join in σ of its
        channel's noise; {} for whole runs
    envelope : Envelope or None — what the fitted runs covered: speed per held command, the
        commands', speeds', deflections', yaw rates' and drift's ranges
        (:func:`hydrokit.sysid.envelope.run_envelope`); written into the identified vehicle
    estimator : dict — which estimator fitted the runs and why: ``method`` (words), ``window_s``
        (s, None for whole runs), ``jacobian_step_s`` (s: the step of the parameters' Jacobian
        columns when coarser than the fit's, else None) and ``why``
    """

    vehicle: Vehicle
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    sigma: np.ndarray
    start: np.ndarray
    base: np.ndarray
    fisher_sigma: np.ndarray
    covariance: np.ndarray
    correlation: np.ndarray
    condition: float
    equation_error: dict[str, Any]
    runs: list[dict[str, Any]]
    noise: dict[str, float]
    predictions: list[dict[str, Any]] = field(repr=False)
    messages: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    verdict: dict[str, Any] = field(default_factory=lambda: {"fits": True, "reasons": []})
    method: str = "output-error"
    iterations: int = 0
    step_check: float = float("nan")
    timing: dict[str, float] = field(default_factory=dict)
    windows: dict[str, Any] = field(default_factory=dict)
    envelope: Envelope | None = None
    estimator: dict[str, Any] = field(default_factory=dict)

    def interval(self, level: float = 0.95) -> np.ndarray:
        """(p, 2) two-sided normal interval of each parameter (SI)."""
        from scipy.stats import norm

        z = float(norm.ppf(0.5 + level / 2))
        return np.column_stack([self.values - z * self.sigma, self.values + z * self.sigma])

    def uncertain_vehicle(self) -> Vehicle:
        """The identified vehicle carrying the fit's covariance as its uncertainty block — what the
        written vehicle.yaml holds and ``manoeuvre --samples`` draws from
        (:func:`hydrokit.model.uncertainty.make_uncertainty`)."""
        from dataclasses import replace

        from hydrokit.model.uncertainty import make_uncertainty

        v = self.vehicle
        unc = make_uncertainty(
            list(self.parameters),
            self.covariance,
            {},
            "fit",
            surfaces=tuple(v.surfaces.names),
            thrusters=v.thruster_names,
        )
        return replace(v, uncertainty=unc)

    def to_dict(self) -> dict[str, Any]:
        """sysid.json, led by the verdict (``fits``, ``reasons``): parameters (value, σ, start,
        base, unit), correlation, condition number, runs, noise, messages, warnings (SI)."""
        params = [
            {
                "name": n,
                "unit": u,
                "value": v,
                "sigma": s,
                "fisher_sigma": fs,
                "start": st,
                "base": b,
                "equation_error": {"value": ev, "sigma": es},
                "identifiable": bool(math.isfinite(s) and s < abs(v)),
            }
            for n, u, v, s, fs, st, b, ev, es in zip(
                self.parameters,
                self.units,
                self.values,
                self.sigma,
                self.fisher_sigma,
                self.start,
                self.base,
                self.equation_error["values"],
                self.equation_error["sigma"],
            )
        ]
        return jsonable(
            {
                "verdict": {
                    "fits": bool(self.verdict["fits"]),
                    "reasons": list(self.verdict["reasons"]),
                    "details": list(self.verdict.get("details", [])),
                },
                "method": self.method,
                "parameters": params,
                "covariance": self.covariance,
                "correlation": self.correlation,
                "condition_number": self.condition,
                "runs": self.runs,
                "noise": self.noise,
                "iterations": self.iterations,
                "step_check_sigma": self.step_check,
                "messages": list(self.messages),
                "warnings": list(self.warnings),
                "timing_s": self.timing,
                "windows": self.windows,
                "estimator": self.estimator,
                "envelope": None if self.envelope is None else self.envelope.to_dict(),
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        cols = ["parameter", "unit", "value", "sigma", "start", "base"]
        rows = [
            [n, u, float(v), float(s), float(st), float(b)]
            for n, u, v, s, st, b in zip(self.parameters, self.units, self.values, self.sigma, self.start, self.base)
        ]
        return cols, rows

    def summary_rows(self) -> list[tuple[str, Any]]:
        rows: list[tuple[str, Any]] = [
            (f"{n} ({u})", f"{v:.4g} ± {s:.2g}")
            for n, u, v, s in zip(self.parameters, self.units, self.values, self.sigma)
        ]
        rows = [("verdict", "fits" if self.verdict["fits"] else "does not fit"), *rows]
        rows += [("condition number", self.condition), ("runs", len(self.runs))]
        return rows + [("note", m) for m in self.messages]

    def plot(self, ax: Any = None) -> Any:
        """Measured vs simulated channels of the first run (or on ``ax``); returns the axes."""
        from hydrokit.plot.sysid import prediction_axes

        return prediction_axes(self.predictions[0], ax)


# ------------------------------------------------------------------------------ the fit
def _series(problem: Problem) -> list[tuple[int, int]]:
    out, k = [], 0
    for prep in problem.preps:
        for t in prep.times:
            out.append((k, k + t.size))
            k += t.size
    return out


#: the whole-run fit: projected Levenberg–Marquardt in the scaled variables z/scale, stopped
#: when the step is far below the statistical resolution (the windows' stops on χ²)
_lm = projected_lm


def _runaway_message(problem: Problem, z: np.ndarray, z0: np.ndarray, scale: np.ndarray) -> str:
    p = len(problem.params)
    far = np.abs(z[:p] - z0[:p]) / scale[:p]
    k = int(np.argmax(far))
    return (
        f"the output-error fit diverged: {problem.params[k].name} ran away to {z[k]:.4g} (start {z0[k]:.4g} "
        f"{problem.params[k].unit}); expected runs that excite it, or fix it (leave it out of --free)"
    )


def _messages(
    names: Sequence[str],
    params: Sequence[Parameter],
    values: np.ndarray,
    sigma: np.ndarray,
    corr: np.ndarray,
    smoothed: Sequence[Any],
) -> list[str]:
    from hydrokit.core.names import DOF_NAMES, VELOCITY_SYMBOLS

    out = []
    p = len(names)
    for i in range(p):
        for j in range(i + 1, p):
            if abs(corr[i, j]) <= CORRELATION_LIMIT:
                continue
            a, b = params[i], params[j]
            head = f"{a.name} and {b.name} move together (ρ = {corr[i, j]:+.3f}): "
            if a.dof == b.dof and "added_mass" in (a.kind, b.kind):
                acc = np.concatenate([s.nu_dot[:, a.dof] for s in smoothed]) if smoothed else np.zeros(1)
                out.append(
                    head
                    + f"these runs hold little {DOF_NAMES[a.dof]} acceleration (RMS {np.sqrt(np.mean(acc**2)):.3g}); "
                    f"add sharp {DOF_NAMES[a.dof]} steps or a multi-sine above 0.3 Hz"
                )
            elif a.dof == b.dof:
                vel = np.concatenate([s.states[:, 6 + a.dof] for s in smoothed]) if smoothed else np.zeros(1)
                out.append(
                    head + f"these runs reach only |{VELOCITY_SYMBOLS[a.dof]}| ≤ {np.max(np.abs(vel)):.3g}; "
                    f"fly {DOF_NAMES[a.dof]} over a wider speed range"
                )
            elif a.kind == b.kind == "added_mass" and a.dof < 3 and b.dof < 3 and corr[i, j] > 0:
                # the Munk moment (e.g. N = (Y_vdot − X_udot) u v) in the well-measured rotation
                # fixes their difference; their sum rests on the translational accelerations
                out.append(
                    head + f"the rotation fixes their difference (Munk moment), not each; more {DOF_NAMES[a.dof]} "
                    f"and {DOF_NAMES[b.dof]} acceleration (sharper steps, a faster DVL) separates them"
                )
            else:
                out.append(
                    head + f"excite {DOF_NAMES[a.dof]} and {DOF_NAMES[b.dof]} separately "
                    "(other runs, or independent phases)"
                )
    for n, v, s in zip(names, values, sigma):
        if not (s < abs(v)):
            out.append(f"{n} = {v:.4g} with σ = {s:.3g} > |value|: not identifiable from these runs")
    for prm, v in zip(params, values):
        if prm.kind in ("added_mass", "linear_damping", "quadratic_damping") and v < 0:
            out.append(
                f"{prm.name} = {v:.4g} {prm.unit} is below its physical bound 0 (reported as fitted, not clipped)"
            )
    return out


def _feedback(runs: Sequence[RunData], smoothed: Sequence[Any], thrusters: Any) -> list[str]:
    """Warnings for runs whose commands follow the measured state (flown under feedback).

    The plant makes the state follow the commands, so a command–state correlation alone says
    nothing; but the plant cannot make a command follow the *sensor noise*. Each channel's
    noise is estimated as measured − smoothed, and correlated with the commanded generalised
    force of its DOF (τ = T f(command) on the rows, no rotor lag) at the row of the sample and
    the two after it (an autopilot acts on its latest sample); |ρ| √n > :data:`FEEDBACK_Z`
    says that an autopilot closed the loop on that channel (Ljung 1999, System
    Identification §13.4 and §16.6: feedback shows as input correlated with past output noise).
    """
    from hydrokit.core.names import DOF_NAMES

    T = thrusters.configuration_matrix()
    out = []
    for run, sm in zip(runs, smoothed):
        t = np.asarray(run.time, float)
        f = np.empty((t.size, len(thrusters)))
        for i, (n, cv) in enumerate(zip(thrusters.names, thrusters.curves)):
            if n in run.thrusts:
                f[:, i] = run.thrusts[n]
                continue
            c = np.clip(np.asarray(run.commands[n], float), thrusters.command_min[i], thrusters.command_max[i])
            f[:, i] = np.clip(curve_thrusts(cv, c, np.zeros(t.size)), thrusters.f_min[i], thrusters.f_max[i])
        tau = f @ T.T
        for d, chans in enumerate(_HOLD_CHANNELS):
            if not np.std(tau[:, d]) > 1e-9 * (1 + np.max(np.abs(tau[:, d]))):
                continue
            best = (0.0, 0.0, "", 0)
            for c in chans:
                if c not in run.channels or not sm.known[CHANNELS.index(c)]:
                    continue
                ts, ys = (np.asarray(a, float) for a in run.channels[c])
                noise = ys - np.interp(ts, sm.time, sm.states[:, CHANNELS.index(c)])
                if c == "psi":
                    noise = np.angle(np.exp(1j * noise))
                k = np.searchsorted(t, ts - 1e-9)
                for lag in range(3):
                    ok = k + lag < t.size
                    x, y = noise[ok], tau[k[ok] + lag, d]
                    if ok.sum() < 10 or np.std(x) == 0 or np.std(y) == 0:
                        continue
                    rho = float(np.corrcoef(x, y)[0, 1])
                    z = rho * math.sqrt(int(ok.sum()))
                    if abs(z) > abs(best[0]):
                        best = (z, rho, c, lag)
            z, rho, c, lag = best
            if abs(z) > FEEDBACK_Z:
                out.append(
                    f"{run.name}: the {DOF_NAMES[d]} command follows the measured {c} (its sensor noise reaches the "
                    f"command {lag} row(s) later: ρ = {rho:+.2f}, {abs(z):.0f}× the 1/√n band; it explains "
                    f"{100 * rho * rho:.0f} % of the command's variance): feedback detected — flown under a hold "
                    "(depth/heading hold, stabilise). Commands that follow the state carry little excitation of their "
                    f"own, so {DOF_NAMES[d]} coefficients lose precision and an equation-error fit is biased; add a "
                    "dither (a multi-sine on the setpoint or on the command) or fly open-loop segments (manual mode)"
                )
    return out


def _predict(
    problem: Problem,
    theta: np.ndarray,
    cov: np.ndarray,
    x0s: Sequence[np.ndarray],
    preps: Sequence[PreparedRun],
    samples: int,
    seed: int,
    coarse: Sequence[PreparedRun] | None = None,
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Nominal prediction and 2.5/97.5 % Monte Carlo band per run (samples at the sample times);
    with ``coarse`` (the same runs at a coarser step) the draws are simulated there and the band
    is their spread about the coarse nominal, put about the nominal at the fit's step."""
    from hydrokit.sysid.model import take

    rng = np.random.default_rng(seed)
    draws = rng.multivariate_normal(theta, cov, size=samples, method="eigh") if samples else np.zeros((0, theta.size))
    vehicles = [with_values(problem.vehicle, problem.params, th) for th in (theta, *draws)]
    packs = stack_packs(vehicles)
    out = []
    for k, (prep, x0) in enumerate(zip(preps, x0s)):
        X0 = np.repeat(x0[None], len(vehicles), axis=0)
        if coarse is not None and samples:
            nominal = simulate_run(prep, take(packs, [0]), X0[:1])[0][0]
            twin, _ = simulate_run(coarse[k], packs, X0)
            mc = nominal + (twin[1:] - twin[0])
        else:
            pred, _ = simulate_run(prep, packs, X0)
            nominal, mc = pred[0], pred[1:]
        lo, hi = np.percentile(mc, [2.5, 97.5], axis=0) if samples else (nominal, nominal)
        out.append((nominal, lo, hi))
    return out


def check_options(
    vehicle: Vehicle, free: Sequence[str], method: str = "output-error", dt: float = 0.01
) -> tuple[Vehicle, list[Parameter]]:
    """Check what :func:`identify` is asked before any run is read: the method, the step, the
    vehicle's thrusters and every free name (a bad one with the nearest valid names).

    Parameters
    ----------
    vehicle : Vehicle — the base; free : names; method : str; dt : float — integration step, s

    Returns
    -------
    The vehicle with absent free terms added at 0 and the parameters
    (:func:`hydrokit.sysid.model.free_parameters`).

    Raises
    ------
    InputError
        One line naming the option, the bad value and what was expected.
    """
    if method not in METHODS:
        raise InputError(f"method {method!r}: expected one of {', '.join(METHODS)}")
    if not (math.isfinite(dt) and 0 < dt <= 0.1):
        raise InputError(f"dt = {dt}: expected an integration step 0 < dt ≤ 0.1 s")
    if vehicle.thrusters is None:
        raise InputError(f"vehicle {vehicle.name!r} has no thrusters: the runs' commands cannot be turned into forces")
    return free_parameters(vehicle, list(free))


def identify(
    vehicle: Vehicle,
    runs: Sequence[RunData],
    free: Sequence[str],
    holdout: Sequence[RunData] = (),
    method: str = "output-error",
    dt: float = 0.01,
    max_iter: int = 30,
    check_step: bool = True,
    samples: int = 40,
    seed: int = 0,
    progress: Callable[[int, float], None] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    window: float | str | None = None,
    bounds: bool = True,
    window_continuity: float = 0.0,
) -> SysidResult:
    """Identify the ``free`` coefficients of ``vehicle`` from ``runs`` (module docstring).

    Parameters
    ----------
    vehicle : Vehicle with thrusters — the base (every coefficient not free keeps its value)
    runs : training runs (:class:`hydrokit.io.runlog.RunLog` or generated)
    free : names (``added_mass.surge``, ``linear_damping.yaw``, ``terms.N_r|r|`` …)
    holdout : runs used only for validation
    method : "output-error" (default) or "equation-error"
    dt : float — integration step, s
    max_iter : int — Levenberg–Marquardt iterations per noise re-weighting
    check_step : bool — re-linearise with dt/2 and report the implied change in σ units
    samples : int — Monte Carlo draws from the covariance for the prediction band
    seed : int — seed of those draws
    progress : callable(iteration, cost) — called after every accepted iteration
    workers : int or None — threads of the compiled batch simulations (None: all cores)
    scheduler : str or None — address of a running Dask scheduler: each iteration's runs (with
        all their perturbed vehicles) are simulated on its workers as independent tasks
    window : float, "auto" or None — cut the runs into windows of about this many seconds,
        each started from its smoothed state (:mod:`hydrokit.sysid.window`); "auto":
        only when a run drifts at the start values (said in the warnings); None: whole runs
    bounds : bool — keep every free damping physical (``linear_damping``/``quadratic_damping``
        ≥ 0, an own-DOF damping derivative such as N_r|r| ≤ 0:
        :func:`hydrokit.model.uncertainty.physical_sign`), so the fitted vehicle is one that
        hydrokit loads; a parameter held on its bound is said in the messages. False: unbounded
    window_continuity : float — with windows, the weight (dimensionless) of each measured
        state's jump between a window's simulated end and the next window's start, in σ of its
        channel's noise (:func:`hydrokit.sysid.window.cut_runs`); 0 (default): windows
        not tied. The largest jump is in the result's ``windows``

    Raises
    ------
    InputError
        No thrusters, a free name that does not exist, fewer samples than parameters, a fit
        that diverged (naming the parameter that ran away).
    """
    if workers:
        import numba

        numba.set_num_threads(min(int(workers), numba.config.NUMBA_NUM_THREADS))  # type: ignore[attr-defined]
    args = (vehicle, runs, free, holdout, method, dt, max_iter, check_step, samples, seed, progress)
    if scheduler is None:
        return _identify(*args, None, window, bounds, window_continuity)
    from hydrokit._parallel import Executor

    with Executor(scheduler=scheduler) as executor:
        return _identify(*args, executor, window, bounds, window_continuity)


def _identify(
    vehicle: Vehicle,
    runs: Sequence[RunData],
    free: Sequence[str],
    holdout: Sequence[RunData],
    method: str,
    dt: float,
    max_iter: int,
    check_step: bool,
    samples: int,
    seed: int,
    progress: Callable[[int, float], None] | None,
    executor: Any,
    window: float | str | None = None,
    bounds: bool = True,
    window_continuity: float = 0.0,
) -> SysidResult:
    """:func:`identify` with the runs' simulations on ``executor`` (None: in this process)."""
    from hydrokit.sysid.smooth import equation_error, initial_noise, smooth_run, tau_on_grid
    from hydrokit.sysid.window import check_continuity

    t_start = _time.perf_counter()
    stages: dict[str, float] = {}
    mark = [t_start]

    def lap(stage: str) -> None:  # the seconds since the last lap, added to ``stage``
        now = _time.perf_counter()
        stages[stage] = stages.get(stage, 0.0) + now - mark[0]
        mark[0] = now

    window_continuity = check_continuity(window_continuity)
    if not runs:
        raise InputError("no training run; expected at least one run file")
    veh, params = check_options(vehicle, free, method, dt)
    p = len(params)
    base = values_of(veh, params)
    th = veh.thrusters
    smoothed = [smooth_run(r) for r in runs]
    lap("smoothing")
    n_samples = sum(sum(t.size for t, _ in r.channels.values()) for r in runs)
    n_x0 = sum(int(np.sum(s.known)) for s in smoothed)
    if n_samples <= p + n_x0:
        raise InputError(
            f"{n_samples} samples for {p} parameters and {n_x0} initial states; expected more samples than parameters"
        )
    preps = [prepare_run(r, th, dt, surfaces=veh.surfaces.names) for r in runs]
    lap("force tables")
    taus = [tau_on_grid(_abs_table(pr), s.time) for pr, s in zip(preps, smoothed)]
    ee = equation_error(veh, params, smoothed, taus, envs=[_abs_env(pr) for pr in preps])
    lap("equation error")
    warnings: list[str] = []
    for run in runs:
        warnings += [f"{run.name}: {w}" for w in getattr(run, "warnings", ())]
    warnings += _feedback(runs, smoothed, th)
    lap("feedback check")
    # the initial state of every measured channel is estimated, the start position too (taken from
    # the smoother it is about 1 cm off at a run's end, which biased the fit: the stated σ came out
    # 1.4× too small on a race-rudder ship, bench/race_rudder_acceptance.py); an unmeasured velocity
    # starts at 0 (said in the warnings)
    est = [np.array([i for i in range(12) if s.known[i]], dtype=int) for s in smoothed]
    for run, s in zip(runs, smoothed):
        unmeasured = [CHANNELS[i] for i in range(6, 12) if not s.known[i] and (i - 6) in veh.dofs]
        if unmeasured:
            warnings.append(f"{run.name}: {', '.join(unmeasured)} not measured: taken as 0 at the start")
    problem = Problem(
        veh, params, preps, [s.at(s.time[0]) for s in smoothed], est, dict(initial_noise(smoothed)), executor=executor
    )
    for c in list(problem.sigma):
        problem.sigma[c] = max(problem.sigma[c], 1e-9)
    lower, upper = _bounds(veh, params) if bounds else (np.full(p, -np.inf), np.full(p, np.inf))
    start = ee.values.copy()
    bad = ~np.isfinite(start)
    start[bad] = base[bad]
    start = np.clip(start, lower, upper)
    cut = None
    if window is not None:  # windowed output error (issue #48): the windows replace the runs
        from hydrokit.sysid.window import cut_runs, parse_window

        cut = cut_runs(parse_window(window), veh, params, start, runs, smoothed, preps, window_continuity)
    first_iterations = 0
    if cut is not None:
        if cut.first is not None and method == "output-error":  # windows first, whole runs from their estimate
            lap("setup")
            start, first_iterations = _first_stage(cut.first, problem, start, base, max_iter, progress, (lower, upper))
            warnings.append(cut.first.note)
            lap("windows first")
        preps, smoothed, est = cut.preps, cut.smoothed, cut.est
        problem = cut.problem(problem)
        warnings.append(cut.note)
    z0 = np.concatenate([start, *[x[e] for x, e in zip(problem.x0, est)]])
    scale = np.concatenate([np.maximum(np.abs(start), np.maximum(np.abs(base), 1e-3)), np.full(z0.size - p, 0.01)])
    iterations = first_iterations
    J: np.ndarray | None = None
    lap("setup")
    if method == "output-error":
        # whole runs: the check that the start can be simulated is the fit's first evaluation
        # (with its Jacobian, handed to the fit); windows evaluate their own problem
        prior: tuple[np.ndarray, np.ndarray] | None = None
        try:
            r0, J0, ok0 = problem.evaluate(z0, scale, cut is None)
            ok0 or _raise_diverged(z0)
            if cut is None and J0 is not None:
                prior = (r0, J0)
        except _Diverged:
            start = base.copy()
            z0[:p] = start
        z = z0
        try:
            # whole runs: the residuals and Jacobian at the fit's end are re-weighted in place of
            # simulating the runs again (rows scale with their weights); windows re-project their
            # initial states with the new weights, so they are evaluated again
            for _ in range(3):  # re-weight: σ of each channel from its residuals
                if cut:
                    z, r, J, its = cut.lm(problem, z, scale, max_iter, progress, (lower, upper))
                else:
                    z, r, J, its = _lm(problem, z, scale, max_iter, progress, (lower, upper), prior)
                iterations += its
                sig = _channel_rms(problem, r)
                if all(abs(sig[c] / problem.sigma[c] - 1) < 0.02 for c in sig):
                    break
                old = problem.row_weights()
                problem.sigma.update(sig)
                if cut is None:
                    f = problem.row_weights() / old
                    r, J = r * f, J * f[:, None]
                    prior = (r, J)
            if cut is not None:
                r, J, _ok = problem.evaluate(z, scale, True)
        except _Diverged as exc:
            raise InputError(_runaway_message(problem, exc.z, z0, scale)) from None
    else:
        z = z0.copy()
        z[:p] = ee.values
    # the equation-error fit is projected onto the bounds at the end (the output-error fits
    # keep them throughout; the projection then changes nothing)
    moved = not np.array_equal(np.clip(z[:p], lower, upper), z[:p])
    z[:p] = np.clip(z[:p], lower, upper)
    if method != "output-error" or moved:
        r, J, _ok = problem.evaluate(z, scale, True)
        if not _ok:
            raise InputError(_runaway_message(problem, z, z0, scale))
    assert J is not None
    if not np.all(np.isfinite(J)):  # a simulation blew up when a parameter was nudged
        cols = np.nonzero(~np.all(np.isfinite(J), axis=0))[0]
        names = [params[k].name if k < p else "an initial state" for k in cols[:3]]
        raise InputError(
            f"the fitted vehicle is on the edge of instability: nudging {', '.join(names)} by 1e-6 makes the "
            "simulation diverge; expected a base vehicle that describes the runs (check its mass, inertia and "
            "centres) and free parameters the runs excite"
        )
    lap("output error")
    blocks = _series(problem)
    cov_s = sandwich(J, r, blocks, first=p)
    info = J.T @ J
    fisher = np.linalg.pinv(info)[:p, :p]
    S = np.diag(scale[:p])
    theta = z[:p]
    cov = S @ cov_s @ S if method == "output-error" else ee.covariance
    sigma = np.sqrt(np.clip(np.diag(cov), 0, None))
    fisher_sigma = scale[:p] * np.sqrt(np.clip(np.diag(fisher), 0, None))
    if method == "equation-error":
        theta = np.clip(ee.values, lower, upper)
    corr = correlation(cov)
    lap("covariance")
    step_check = float("nan")
    if check_step and method == "output-error":
        half = Problem(
            veh,
            params,
            cut.prepare(runs, th, dt / 2, veh.surfaces.names)
            if cut
            else [prepare_run(rr, th, dt / 2, surfaces=veh.surfaces.names) for rr in runs],
            problem.x0,
            est,
            problem.sigma,
        )
        if cut is not None:  # the windows' initial states projected out at dt/2 too
            half = cut.projected(half)
            r2, J2, ok2 = half.evaluate(z, scale, True)
            rhs = None if J2 is None else J2.T @ r2
        else:
            # whole runs: the residuals at dt/2 only, with the fit's Jacobian at dt (the two differ by
            # the integrator's error, far below what moves a Gauss–Newton step): one simulation per
            # run instead of one per parameter and initial state, at twice the steps
            r2, _, ok2 = half.evaluate(z, scale, False)
            J2 = J
            rhs = J.T @ (r2 - r) if ok2 and r2.shape == r.shape else None
        if ok2 and J2 is not None and rhs is not None:
            # the Gauss–Newton step by the normal equations (min-norm, as lstsq; the Jacobian has
            # few columns and very many rows, and its QR would cost more than the fit's steps)
            dz = -(np.linalg.pinv(J2.T @ J2) @ rhs)[:p] * scale[:p]
            step_check = float(np.max(np.abs(dz) / np.maximum(sigma, 1e-300)))
        problem.sim_seconds += half.sim_seconds
    lap("step check")
    _, x0s = problem.unpack(z)
    fitted = _predict(problem, theta, cov, x0s, preps, samples, seed, cut.coarse if cut is not None else None)
    lap("bands")
    hold_preps = [prepare_run(r, th, dt, surfaces=veh.surfaces.names) for r in holdout]
    hold_smoothed = [smooth_run(r) for r in holdout]
    hold_x0 = [sm.at(float(r.time[0])) for sm, r in zip(hold_smoothed, holdout)]
    if cut is not None:
        hold_preps, hold_x0, hold_smoothed = cut.holdout(holdout, th, dt, veh.surfaces.names)
    lap("held-out preparation")
    held = _predict(problem, theta, cov, hold_x0, hold_preps, samples, seed + 1)
    lap("bands")
    run_rows, predictions = [], []
    for prep, (nom, lo, hi), is_hold, sm in [(a, b, False, c) for a, b, c in zip(preps, fitted, smoothed)] + [
        (a, b, True, c) for a, b, c in zip(hold_preps, held, hold_smoothed)
    ]:
        row: dict[str, Any] = {"name": prep.name, "holdout": is_hold, "duration_s": prep.duration, "channels": {}}
        k = 0
        chans = {}
        for c, t, y in zip(prep.channels, prep.times, prep.values):
            e = y - nom[k : k + t.size]
            entry = {"samples": int(t.size), "residual_rms": float(np.sqrt(np.mean(e**2))), "whiteness": whiteness(e)}
            # the sensor noise of this run's channel from the smoother (independent of the model)
            entry.update(channel_checks(y, e, sm.noise.get(c, float("nan"))))
            row["channels"][c] = entry
            chans[c] = {
                "time": t + prep.t0,
                "measured": y,
                "simulated": nom[k : k + t.size],
                "low": lo[k : k + t.size],
                "high": hi[k : k + t.size],
            }
            k += t.size
        run_rows.append(row)
        predictions.append({"name": prep.name, "holdout": is_hold, "channels": chans})
    msgs = _messages([q.name for q in params], params, theta, sigma, corr, smoothed)
    bound_msgs = _bound_messages(params, theta, lower, upper)
    if bound_msgs:  # a value held at 0 has σ > |value| by construction: said by the bound's message instead
        at = {q.name for q, v, lo, hi in zip(params, theta, lower, upper) if v in (lo, hi)}
        msgs = [m for m in msgs if not (m.split(" = ", 1)[0] in at and m.endswith("not identifiable from these runs"))]
    msgs += bound_msgs
    lap("report")
    if math.isfinite(step_check) and step_check > 0.1:
        warnings.append(
            f"halving the integration step moves an estimate by {step_check:.2f} σ (> 0.1): use a smaller dt — "
            "unless the model does not fit or a parameter is not identifiable (above), where the optimum itself "
            "is not determined and the step only shows it"
        )
    return SysidResult(
        vehicle=with_values(veh, params, theta),
        parameters=tuple(q.name for q in params),
        units=tuple(q.unit for q in params),
        values=theta,
        sigma=sigma,
        start=start,
        base=base,
        fisher_sigma=fisher_sigma,
        covariance=cov,
        correlation=corr,
        condition=condition_number(info[:p, :p]),
        equation_error={"values": ee.values, "sigma": ee.std},
        runs=run_rows,
        noise=dict(problem.sigma),
        predictions=predictions,
        messages=tuple(msgs),
        warnings=tuple(warnings),
        verdict=verdict(run_rows),
        method=method,
        iterations=iterations,
        step_check=step_check,
        timing={"total": _time.perf_counter() - t_start, "simulation": problem.sim_seconds, **stages},
        windows=_window_summary(cut, problem),
        envelope=run_envelope(runs, veh),
        estimator=_estimator(method, window, cut),
    )


#: the smallest value a wind field that must be positive is fitted to (m² or –)
WIND_FLOOR = 1e-9
#: the range a surface's, thruster's or wind model's free field must keep for the model to accept it (the
#: vehicle file's own checks: 0 ≤ w, t < 1; a size or slope is not negative), in its unit
FIELD_RANGE: dict[str, tuple[float, float]] = {
    "wake_fraction": (0.0, 0.99),
    "thrust_deduction": (0.0, 0.99),
    "lift_slope": (0.0, math.inf),
    "area": (0.0, math.inf),
    "diameter": (0.0, math.inf),
    "drag_coefficient": (0.0, math.inf),
    # the wind model's (model/wind.py make_wind): areas and CD_t > 0 (held a hair above 0, which
    # the file refuses), the longitudinal drag numbers ≥ 0, δ within 0–1; s_L and a table's
    # coefficients take either sign
    "frontal_area": (WIND_FLOOR, math.inf),
    "lateral_area": (WIND_FLOOR, math.inf),
    "CD_t": (WIND_FLOOR, math.inf),
    "CD_l_AF_bow": (0.0, math.inf),
    "CD_l_AF_stern": (0.0, math.inf),
    "delta": (0.0, 1.0),
}


#: parameter kinds that are a file field (their range in :data:`FIELD_RANGE`)
FIELD_KINDS = ("surface", "thruster", "wind")


def _bounds(vehicle: Vehicle, params: Sequence[Parameter]) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the parameters (SI): 0 on the side where a damping would feed
    energy in (:func:`hydrokit.model.uncertainty.physical_sign`), a surface's or thruster's
    field within :data:`FIELD_RANGE`, ±inf elsewhere."""
    from hydrokit.model.uncertainty import parameter_ref, physical_sign

    signs = np.array([physical_sign(parameter_ref(vehicle, q.name)) for q in params], dtype=float)
    lower, upper = np.where(signs > 0, 0.0, -np.inf), np.where(signs < 0, 0.0, np.inf)
    for k, q in enumerate(params):
        if q.kind in FIELD_KINDS:
            lower[k], upper[k] = FIELD_RANGE.get(q.name.rpartition(".")[2], (-math.inf, math.inf))
    return lower, upper


def _bound_messages(params: Sequence[Parameter], theta: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> list[str]:
    """One message per parameter held on its physical bound."""
    out = []
    for q, v, lo, hi in zip(params, theta, lower, upper):
        if q.kind in FIELD_KINDS and v in (lo, hi):
            out.append(
                f"{q.name} is held at the end of its range [{lo:g}, {hi:g}] {q.unit}: these runs push it past — "
                "the model misses something (see the verdict) or the runs do not determine it"
            )
            continue
        if v == lo or v == hi:
            side = (
                "≥ 0: a negative damping feeds energy in" if v == lo else "≤ 0 (SNAME): a positive one feeds energy in"
            )
            out.append(
                f"{q.name} is held at its physical bound 0 {q.unit} ({side}): these runs push it past — the model "
                "misses something (see the verdict) or the runs do not determine it; bounds=False fits it unbounded"
            )
    return out


def _raise_diverged(z: np.ndarray) -> bool:
    raise _Diverged(z)


def _abs_table(prep: PreparedRun) -> np.ndarray:
    tab = prep.table.copy()
    tab[:, 0] += prep.t0
    return tab


def _first_stage(
    stage: Any,
    runs_problem: Problem,
    start: np.ndarray,
    base: np.ndarray,
    max_iter: int,
    progress: Callable[[int, float], None] | None,
    bounds: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, int]:
    """The fit of the windows ``stage`` (:class:`hydrokit.sysid.window.Windows`) from ``start``
    (SI), re-weighted as the main fit is, whose estimate starts the fit of the whole runs: their
    parameters (SI) and its iterations; ``start`` unchanged when the windows cannot be fitted.
    The channels' noise σ it re-estimates carry on (the problems share them)."""
    problem = stage.problem(runs_problem)
    scale = np.maximum(np.abs(start), np.maximum(np.abs(base), 1e-3))
    z, iterations = start.copy(), 0
    try:
        for _ in range(3):
            z, r, _, its = stage.lm(problem, z, scale, max_iter, progress, bounds)
            iterations += its
            sig = _channel_rms(problem, r)
            if all(abs(sig[c] / problem.sigma[c] - 1) < 0.02 for c in sig):
                break
            problem.sigma.update(sig)
    except _Diverged:
        return start, iterations
    runs_problem.sim_seconds = problem.sim_seconds  # it started from the runs' count
    return z, iterations


def _estimator(method: str, window: Any, cut: Any) -> dict[str, Any]:
    """Which estimator fitted the runs and why (:class:`SysidResult` ``estimator``)."""
    if method == "equation-error":
        return {"method": "equation error", "window_s": None, "jacobian_step_s": None, "why": "as asked (method)"}
    if cut is None:
        why = (
            "as asked (window none)"
            if window is None
            else "window auto: no run drifts open loop at the start values, or none is long enough to cut"
        )
        return {"method": "output error, whole runs", "window_s": None, "jacobian_step_s": None, "why": why}
    whole = len(cut.preps) == len(set(cut.owner))
    what = "output error, whole runs (each run's initial state projected out)" if whole else "output error in windows"
    return {
        "method": what,
        "window_s": None if whole else cut.length,
        "jacobian_step_s": cut.jacobian_dt,
        "why": cut.why,
    }


def _window_summary(cut: Any, problem: Any) -> dict[str, Any]:
    """The windows of a windowed fit: count, length (s), continuity weight (–) and the largest
    jump of a measured state at a join, in σ of its channel's noise; {} for whole runs."""
    if cut is None:
        return {}
    jumps = getattr(problem, "jumps", np.zeros(0))
    return {
        "count": len(cut.preps),
        "length_s": cut.length,
        "continuity": cut.continuity,
        "largest_jump_sigma": float(np.max(jumps)) if jumps.size else 0.0,
    }


def _abs_env(prep: PreparedRun) -> np.ndarray | None:
    """The run's current and wind table with the run's own time (s), None for none."""
    if prep.env is None:
        return None
    env = prep.env.copy()
    env[:, 0] += prep.t0
    return env


def _channel_rms(problem: Problem, r: np.ndarray) -> dict[str, float]:
    """Unweighted residual RMS per channel over all runs (SI)."""
    acc: dict[str, list[np.ndarray]] = {}
    k = 0
    for prep in problem.preps:
        for c, t in zip(prep.channels, prep.times):
            acc.setdefault(c, []).append(r[k : k + t.size] * problem.sigma[c])
            k += t.size
    return {c: max(float(np.sqrt(np.mean(np.concatenate(v) ** 2))), 1e-9) for c, v in acc.items()}


__all__ = ["CHANNELS", "METHODS", "SysidResult", "check_options", "identify"]
