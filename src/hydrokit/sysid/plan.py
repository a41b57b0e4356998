"""Excitation design for system identification (issue #44, ``hydrokit sysid plan``): a thruster
command schedule that makes the free coefficients as well known as the thrusters allow.

**Signal.** Each excited DOF d gets a multi-sine τ_d(t) = w_d R_d Σ_k a_k sin(2π f_k t + φ_k)
(normalised to unit peak, cosine-tapered in and out so that the schedule starts and ends at
rest) on harmonics f_k = k / duration of the schedule, the harmonics dealt to the DOFs in turn so
that no two DOFs share a frequency (orthogonal multi-sines, Morelli 2003, "Multiple input
design for real-time parameter estimation in the frequency domain", IFAC SYSID); R_d is the
largest τ_d the thrusters give (|T_d|·limits). Per DOF the design chooses the weight w_d, the
band [f_lo, f_hi] of its harmonics, the slope α of the amplitudes a_k ∝ f_k^−α and a phase
offset; within a DOF the phases are Schroeder's (Schroeder 1970, IEEE Trans. Inf. Theory 16)
for a low peak factor. τ is allocated to the thrusters by the pseudo-inverse of the
configuration matrix (:func:`hydrokit.model.allocation.weighted_pinv`), scaled so that the
largest |thrust| / limit is ``amplitude``, and turned into each thruster's command
(:meth:`~hydrokit.model.thrusters.ThrusterSet.command_for_thrust`), held at the log rate.

**Criterion.** D-optimal: the determinant of the Fisher information of the free parameters
(the initial states, which the fit estimates too, marginalised), predicted at the base
vehicle's values by the output-error sensitivities of :func:`hydrokit.sysid.fit.identify`
itself (the same force table, rotor lag, batch integration and forward differences) with
each channel sampled at its sensor rate and weighted by its noise σ. Its inverse is the
Cramér–Rao covariance: no unbiased fit of data flown with the schedule does better.

**Search.** Random designs, then a coordinate pattern search from the best (a fixed budget of
evaluations, one batch simulation each). The result is compared with the virtual-dive
generator's random multi-sines (:func:`hydrokit.sysid.data.excitation_thrust`) on the
same DOFs at the same thrust fraction.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.data import ROW_RATE, SENSORS, VirtualRun, excitation_thrust
from hydrokit.sysid.fit import CORRELATION_LIMIT
from hydrokit.sysid.model import CHANNELS, Parameter, free_parameters, prepare_run, values_of
from hydrokit.sysid.problem import Problem
from hydrokit.sysid.stats import condition_number, correlation

#: band the design may use, Hz (above 2 Hz a pool vehicle barely moves; a DVL cannot see it)
F_MAX = 2.0
#: number of random designs tried before the pattern search (fraction of the budget)
RANDOM_SHARE = 1 / 3


@dataclass(frozen=True)
class SysidPlan(Result):
    """A planned excitation with the uncertainty it promises.

    Attributes
    ----------
    vehicle : str — name of the base vehicle
    parameters, units : tuple of str — free names and their SI units
    base : (p,) — the values the prediction is made at (the base file's), SI
    sigma : (p,) — Cramér–Rao σ with the schedule, SI; covariance : (p, p) — SI²
    correlation : (p, p); condition : float — of the Fisher information scaled to unit diagonal
    reference_sigma : (p,) — mean σ of the reference excitations, SI
    logdet, reference_logdet : float — log det of the Fisher information of the (scaled)
        parameters: the design's and the mean of the references'
    design : list of dict — per excited DOF: weight, band (Hz), slope, phase (rad), frequencies (Hz)
    time : (n,) — s; commands : thruster → (n,) commands held per row (curve unit);
    thrust : (n, m) — N; names, command_units : per thruster; f_min, f_max : (m,) — N
    sensors : channel → (rate Hz, σ SI); duration : s; amplitude : fraction of the thrust limit;
    dt : s; evaluations : int; messages, warnings : tuple of str; timing : dict — s
    """

    vehicle: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    base: np.ndarray
    sigma: np.ndarray
    covariance: np.ndarray
    correlation: np.ndarray
    condition: float
    reference_sigma: np.ndarray
    logdet: float
    reference_logdet: float
    design: list[dict[str, Any]]
    time: np.ndarray = field(repr=False)
    commands: dict[str, np.ndarray] = field(repr=False)
    thrust: np.ndarray = field(repr=False)
    names: tuple[str, ...] = ()
    command_units: tuple[str, ...] = ()
    f_min: np.ndarray = field(default_factory=lambda: np.zeros(0))
    f_max: np.ndarray = field(default_factory=lambda: np.zeros(0))
    sensors: dict[str, tuple[float, float]] = field(default_factory=dict)
    duration: float = 0.0
    amplitude: float = 0.0
    dt: float = 0.01
    evaluations: int = 0
    references: int = 0
    messages: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    timing: dict[str, float] = field(default_factory=dict)

    @property
    def ratio(self) -> np.ndarray:
        """σ with the schedule over σ with the reference excitation, per parameter (–)."""
        return self.sigma / self.reference_sigma

    @property
    def gain(self) -> float:
        """Geometric-mean σ ratio of the reference over the design, exp((logdet − ref)/2p) (–)."""
        return math.exp((self.logdet - self.reference_logdet) / (2 * len(self.parameters)))

    def to_dict(self) -> dict[str, Any]:
        """plan.json: expected σ (Cramér–Rao), correlation, condition number, the design, the
        schedule's peak thrusts and what the design is compared with (SI)."""
        limit = np.minimum(self.f_max, -self.f_min)
        params = [
            {
                "name": n,
                "unit": u,
                "value": v,
                "sigma": s,
                "relative_sigma": s / abs(v) if v else None,
                "reference_sigma": rs,
                "sigma_ratio": s / rs,
            }
            for n, u, v, s, rs in zip(self.parameters, self.units, self.base, self.sigma, self.reference_sigma)
        ]
        return jsonable(
            {
                "vehicle": self.vehicle,
                "criterion": "D-optimal (max det of the Fisher information of the free parameters)",
                "parameters": params,
                "covariance": self.covariance,
                "correlation": self.correlation,
                "condition_number": self.condition,
                "comparison": {
                    "reference": "the virtual-dive generator's random multi-sines (0.03–0.8 Hz, "
                    f"hydrokit sysid generate) on the same DOFs at the same thrust fraction, mean of {self.references}",
                    "logdet_fisher": self.logdet,
                    "reference_logdet_fisher": self.reference_logdet,
                    "geometric_mean_sigma_gain": self.gain,
                },
                "design": self.design,
                "schedule": {
                    "file": "schedule.csv",
                    "duration_s": self.duration,
                    "row_rate_hz": ROW_RATE,
                    "rows": int(self.time.size),
                    "amplitude": self.amplitude,
                    "thrusters": [
                        {"name": n, "command_unit": cu, "peak_thrust_n": float(pk), "peak_fraction_of_limit": float(fr)}
                        for n, cu, pk, fr in zip(
                            self.names,
                            self.command_units,
                            np.max(np.abs(self.thrust), axis=0),
                            np.max(np.abs(self.thrust), axis=0) / limit,
                        )
                    ],
                },
                "sensors": {c: {"rate_hz": r, "sigma": s} for c, (r, s) in self.sensors.items()},
                "integration_step_s": self.dt,
                "evaluations": self.evaluations,
                "messages": list(self.messages),
                "warnings": list(self.warnings),
                "timing_s": self.timing,
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        cols = ["parameter", "unit", "base", "sigma", "reference_sigma", "ratio"]
        rows = [
            [n, u, float(v), float(s), float(r), float(s / r)]
            for n, u, v, s, r in zip(self.parameters, self.units, self.base, self.sigma, self.reference_sigma)
        ]
        return cols, rows

    def summary_rows(self) -> list[tuple[str, Any]]:
        rows: list[tuple[str, Any]] = [
            (f"σ({n}) ({u})", f"{s:.3g} (×{s / r:.2f} of the reference)")
            for n, u, s, r in zip(self.parameters, self.units, self.sigma, self.reference_sigma)
        ]
        return rows + [("condition number", self.condition), ("duration (s)", self.duration)]

    def plot(self, ax: Any = None) -> Any:
        """The schedule's peak |thrust| per thruster with its limits (on ``ax``); returns the axes."""
        from hydrokit.plot.allocation import allocation_axes

        return allocation_axes(list(self.names), np.max(np.abs(self.thrust), axis=0), self.f_min, self.f_max, ax)


# ------------------------------------------------------------------------------ prediction
def _sample_channels(time: np.ndarray, sensors: Mapping[str, tuple[float, float]]) -> dict[str, Any]:
    out = {}
    for c, (rate, _) in sensors.items():
        every = max(1, int(round(ROW_RATE / rate)))
        rows = np.arange(0, time.size, every)
        out[c] = (time[rows], np.zeros(rows.size))
    return out


def fisher_information(
    vehicle: Vehicle,
    params: Sequence[Parameter],
    time: np.ndarray,
    commands: Mapping[str, np.ndarray],
    sensors: Mapping[str, tuple[float, float]],
    dt: float = 0.01,
) -> tuple[np.ndarray, np.ndarray]:
    """Fisher information of (parameters, estimated initial states) for one run flown with
    ``commands`` (thruster → command per row of ``time``, s) and sampled by ``sensors``
    (channel → (rate Hz, σ SI)), at the vehicle's values: JᵀJ of the weighted output-error
    Jacobian of :func:`hydrokit.sysid.fit.identify` (per unit of the scaled variables), and
    the scales (parameters: max(|value|, 1e-3) SI; initial states 0.01 SI).

    Raises
    ------
    InputError
        The vehicle diverges under these commands.
    """
    th = vehicle.thrusters
    run = VirtualRun("plan", time, _sample_channels(time, sensors), dict(commands), np.zeros((0, 12)))
    prep = prepare_run(run, th, dt)
    x0 = np.zeros(12)
    x0[2] = 1.5  # depth does not enter the model away from the surface
    est = np.array([i for i in range(12) if CHANNELS[i] in sensors], dtype=int)
    problem = Problem(vehicle, list(params), [prep], [x0], [est], {c: s for c, (_, s) in sensors.items()})
    theta = values_of(vehicle, params)
    scale = np.concatenate([np.maximum(np.abs(theta), 1e-3), np.full(est.size, 0.01)])
    _, J, ok = problem.evaluate(np.concatenate([theta, x0[est]]), scale, True)
    if not ok or J is None:
        raise InputError(
            f"vehicle {vehicle.name!r} diverges under the planned commands; expected a lower --amplitude (fraction "
            "of the thrust limits)"
        )
    return J.T @ J, scale


def _logdet(info: np.ndarray, p: int) -> float:
    """log det of the information of the first ``p`` variables, the others marginalised."""
    sign, ld = np.linalg.slogdet(np.linalg.pinv(info)[:p, :p])
    return float(-ld) if sign > 0 else -math.inf


# ------------------------------------------------------------------------------ the signal
@dataclass(frozen=True)
class _Designer:
    vehicle: Vehicle
    dofs: tuple[int, ...]
    time: np.ndarray
    amplitude: float
    f_lo: float
    f_hi: float

    @property
    def f0(self) -> float:
        return 1.0 / float(self.time[-1] - self.time[0])

    def decode(self, u: np.ndarray) -> list[dict[str, Any]]:
        """Per DOF: weight (–), band (Hz), slope (–), phase (rad), from the unit box ``u``."""
        out = []
        span = math.log(self.f_hi / self.f_lo)
        harmonics = np.arange(1, int(self.f_hi / self.f0) + 1) * self.f0
        for j, d in enumerate(self.dofs):
            w, a, b, slope, phase = u[5 * j : 5 * j + 5]
            lo, hi = sorted((self.f_lo * math.exp(span * a), self.f_lo * math.exp(span * b)))
            mine = harmonics[j :: len(self.dofs)]
            if mine.size == 0:
                mine = harmonics[-1:]
            sel = mine[(mine >= lo * (1 - 1e-9)) & (mine <= hi * (1 + 1e-9))]
            if sel.size == 0:
                sel = mine[[int(np.argmin(np.abs(np.log(mine / math.sqrt(lo * hi)))))]]
            out.append(
                {
                    "dof": DOF_NAMES[d],
                    "weight": float(0.1 + 0.9 * w),
                    "band_hz": [float(lo), float(hi)],
                    "slope": float(2.0 * slope),
                    "phase_rad": float(2 * math.pi * phase),
                    "frequencies_hz": [float(f) for f in sel],
                }
            )
        return out

    def thrust(self, design: Sequence[Mapping[str, Any]]) -> np.ndarray:
        """Thruster forces (n, m) of a design, N, within ``amplitude`` of the limits."""
        from hydrokit.model.allocation import weighted_pinv

        th = self.vehicle.thrusters
        assert th is not None
        T = th.configuration_matrix()
        limit = np.minimum(th.f_max, -th.f_min)
        reach = np.abs(T) @ limit
        t = self.time - self.time[0]
        ramp = min(2.0, 0.1 * float(t[-1]))
        taper = np.ones(t.size)
        for edge in (t, t[-1] - t):
            inside = edge < ramp
            taper[inside] *= 0.5 * (1 - np.cos(np.pi * edge[inside] / ramp))
        tau = np.zeros((t.size, 6))
        for d, spec in zip(self.dofs, design):
            f = np.asarray(spec["frequencies_hz"])
            a = (f / f[0]) ** (-spec["slope"])
            pw = a**2 / np.sum(a**2)
            k = np.arange(f.size)
            # Schroeder phases for the power shares pw: φ_k = φ_0 − 2π Σ_{l<k} (k − l) pw_l
            phi = spec["phase_rad"] - 2 * np.pi * np.array([np.sum((kk - k[:kk]) * pw[:kk]) for kk in k])
            s = (a[None, :] * np.sin(2 * np.pi * f[None, :] * t[:, None] + phi[None, :])).sum(axis=1)
            tau[:, d] = spec["weight"] * reach[d] * s / np.max(np.abs(s))
        f = (tau * taper[:, None]) @ weighted_pinv(T).T
        return f * (self.amplitude / np.max(np.abs(f) / limit))

    def start(self) -> np.ndarray:
        """The generator's choice as a design: band 0.03–0.8 Hz, slope 0.5, yaw at half weight."""
        span = math.log(self.f_hi / self.f_lo)
        u = []
        for d in self.dofs:
            a = math.log(max(0.03, self.f_lo) / self.f_lo) / span
            b = math.log(min(0.8, self.f_hi) / self.f_lo) / span
            u += [((0.5 if DOF_NAMES[d] == "yaw" else 1.0) - 0.1) / 0.9, a, b, 0.25, 0.0]
        return np.clip(np.array(u), 0, 1)


def _commands(vehicle: Vehicle, f: np.ndarray) -> dict[str, np.ndarray]:
    th = vehicle.thrusters
    assert th is not None
    cmd = np.array([th.command_for_thrust(row) for row in f])
    cmd[np.abs(cmd) < 1e-12 * max(1.0, float(np.max(np.abs(cmd))))] = 0.0  # round-off of the allocation
    return {n: cmd[:, i] for i, n in enumerate(th.names)}


def _excited_dofs(
    params: Sequence[Parameter], T: np.ndarray, dofs: Sequence[str] | None
) -> tuple[list[int], list[str]]:
    from hydrokit.model.allocation import uncontrollable_dofs

    dead = set(uncontrollable_dofs(T))
    warnings = []
    if dofs:
        bad = [d for d in dofs if d not in DOF_NAMES]
        if bad:
            raise InputError(f"dofs {', '.join(bad)}: expected some of {', '.join(DOF_NAMES)}")
        wanted = sorted({DOF_NAMES.index(d) for d in dofs})
    else:
        wanted = sorted({p.dof for p in params} | {p.index for p in params if p.kind == "accel"})
    out = [d for d in wanted if DOF_NAMES[d] not in dead]
    for d in wanted:
        if DOF_NAMES[d] in dead:
            warnings.append(f"the thrusters cannot act in {DOF_NAMES[d]}: it is not excited")
    if not out:
        raise InputError(
            f"no DOF to excite: {', '.join(DOF_NAMES[d] for d in wanted)} cannot be actuated by the thrusters; "
            "expected free parameters of actuated DOFs"
        )
    return out, warnings


def plan_excitation(
    vehicle: Vehicle,
    free: Sequence[str],
    duration: float = 60.0,
    amplitude: float = 0.6,
    dofs: Sequence[str] | None = None,
    sensors: Mapping[str, tuple[float, float]] | None = None,
    band: tuple[float, float] = (0.02, F_MAX),
    evaluations: int = 40,
    references: int = 3,
    dt: float = 0.01,
    seed: int = 0,
    progress: Callable[[int, float], None] | None = None,
) -> SysidPlan:
    """A D-optimal multi-sine schedule for identifying ``free`` (module docstring).

    Parameters
    ----------
    vehicle : Vehicle with thrusters — the base; the prediction is made at its values
    free : names as for :func:`hydrokit.sysid.fit.identify`
    duration : float — length of the schedule, s
    amplitude : float — largest fraction of a thruster's thrust limit used (0–1)
    dofs : DOF names to excite, or None: those the free parameters act in
    sensors : channel → (rate Hz, noise σ SI), or None: the virtual dives'
        (:data:`hydrokit.sysid.data.SENSORS`)
    band : (f_lo, f_hi) — the frequencies the design may use, Hz
    evaluations : int — designs simulated in the search (each one batch simulation)
    references : int — random multi-sines of the generator averaged as the comparison
    dt : float — integration step of the prediction, s
    seed : int — seed of the search and of the references
    progress : callable(evaluation, best log det) — after every evaluation

    Raises
    ------
    InputError
        No thrusters, a free name that does not exist, a bad duration, amplitude, band,
        sensor or budget, fewer samples than parameters, a vehicle that diverges.
    """
    t_start = _time.perf_counter()
    if vehicle.thrusters is None:
        raise InputError(f"vehicle {vehicle.name!r} has no thrusters: a schedule commands thrusters")
    if not (math.isfinite(duration) and 2.0 <= duration <= 3600.0):
        raise InputError(f"duration = {duration} s: expected 2 ≤ duration ≤ 3600 s")
    if not 0 < amplitude <= 1:
        raise InputError(f"amplitude = {amplitude}: expected 0 < amplitude ≤ 1 (fraction of the thrust limit)")
    if evaluations < 1 or references < 1:
        raise InputError(f"evaluations = {evaluations}, references = {references}: expected ≥ 1 each")
    if not (math.isfinite(dt) and 0 < dt <= 0.1):
        raise InputError(f"dt = {dt}: expected an integration step 0 < dt ≤ 0.1 s")
    sensors = dict(SENSORS if sensors is None else sensors)
    for c, (rate, sig) in sensors.items():
        if c not in CHANNELS or not (0 < rate <= ROW_RATE and sig > 0 and math.isfinite(sig)):
            raise InputError(
                f"sensor {c!r}: rate {rate} Hz, σ {sig}; expected a channel of {', '.join(CHANNELS)} with "
                f"0 < rate ≤ {ROW_RATE:g} Hz and σ > 0 (SI)"
            )
    if not sensors:
        raise InputError("no sensor channel; expected at least one of " + ", ".join(CHANNELS))
    f_lo, f_hi = max(band[0], 1.0 / duration), min(band[1], 0.25 * ROW_RATE)
    if not f_lo < f_hi:
        raise InputError(
            f"band {band[0]}–{band[1]} Hz: expected f_lo < f_hi with f_hi > 1/duration = {1 / duration:.3g} Hz"
        )
    veh, params = free_parameters(vehicle, list(free))
    p = len(params)
    time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / ROW_RATE), 6)
    n_samples = sum(v[0].size for v in _sample_channels(time, sensors).values())
    if n_samples <= p + 10:
        raise InputError(f"{n_samples} samples for {p} parameters: expected a longer duration or faster sensors")
    th = veh.thrusters
    assert th is not None
    excited, warnings = _excited_dofs(params, th.configuration_matrix(), dofs)
    designer = _Designer(veh, tuple(excited), time, amplitude, f_lo, f_hi)
    count = 0
    best_u = designer.start()
    best = -math.inf

    def score(u: np.ndarray) -> float:
        nonlocal count, best, best_u
        count += 1
        info, _ = fisher_information(
            veh, params, time, _commands(veh, designer.thrust(designer.decode(u))), sensors, dt
        )
        val = _logdet(info, p)
        if val > best:
            best, best_u = val, u.copy()
        if progress:
            progress(count, best)
        return val

    rng = np.random.default_rng(seed)
    score(best_u)
    for _ in range(int(round(RANDOM_SHARE * (evaluations - 1)))):
        score(rng.uniform(0, 1, best_u.size))
    step = 0.2
    while count < evaluations and step >= 0.01:
        improved = False
        for i in rng.permutation(best_u.size):
            for sign in (1.0, -1.0):
                if count >= evaluations:
                    break
                u = best_u.copy()
                u[i] = (u[i] + sign * step) % 1.0 if i % 5 == 4 else np.clip(u[i] + sign * step, 0, 1)
                if u[i] == best_u[i]:
                    continue
                before = best
                score(u)
                if best > before:
                    improved = True
                    break
        if not improved:
            step /= 2
    design = designer.decode(best_u)
    f = designer.thrust(design)
    commands = _commands(veh, f)
    info, scale = fisher_information(veh, params, time, commands, sensors, dt)
    S = np.diag(scale[:p])
    cov = S @ np.linalg.pinv(info)[:p, :p] @ S
    sigma = np.sqrt(np.clip(np.diag(cov), 0, None))
    names = tuple(DOF_NAMES[d] for d in excited)
    ref_sig, ref_ld = [], []
    for k in range(references):
        fr = excitation_thrust(veh, time, seed + 1000 + k, amplitude, names)
        ri, _ = fisher_information(veh, params, time, _commands(veh, fr), sensors, dt)
        ref_ld.append(_logdet(ri, p))
        ref_sig.append(scale[:p] * np.sqrt(np.clip(np.diag(np.linalg.pinv(ri))[:p], 0, None)))
    ref_sigma = np.mean(ref_sig, axis=0)
    corr = correlation(cov)
    base = values_of(veh, params)
    msgs = []
    for i in range(p):
        for j in range(i + 1, p):
            if abs(corr[i, j]) > CORRELATION_LIMIT:
                msgs.append(
                    f"{params[i].name} and {params[j].name} still move together with this schedule "
                    f"(ρ = {corr[i, j]:+.3f}): lengthen it, fly it twice, or free fewer parameters"
                )
    for prm, v, s in zip(params, base, sigma):
        if v != 0 and not s < abs(v):
            msgs.append(f"{prm.name}: expected σ = {s:.3g} > |{v:.4g}|: not identifiable with this schedule")
    th_units = tuple(_unit(t.model) for t in th.thrusters)
    return SysidPlan(
        vehicle=vehicle.name,
        parameters=tuple(q.name for q in params),
        units=tuple(q.unit for q in params),
        base=base,
        sigma=sigma,
        covariance=cov,
        correlation=corr,
        condition=condition_number(info[:p, :p]),
        reference_sigma=ref_sigma,
        logdet=_logdet(info, p),
        reference_logdet=float(np.mean(ref_ld)),
        design=design,
        time=time,
        commands=commands,
        thrust=f,
        names=tuple(th.names),
        command_units=th_units,
        f_min=np.asarray(th.f_min, float),
        f_max=np.asarray(th.f_max, float),
        sensors=sensors,
        duration=float(time[-1]),
        amplitude=amplitude,
        dt=dt,
        evaluations=count,
        references=references,
        messages=tuple(msgs),
        warnings=tuple(warnings),
        timing={"total": _time.perf_counter() - t_start},
    )


def _unit(model: str) -> str:
    from hydrokit.simulate.mission import COMMAND_UNITS

    return COMMAND_UNITS.get(model, model)


__all__ = ["F_MAX", "SysidPlan", "fisher_information", "plan_excitation"]
