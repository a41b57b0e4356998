"""Trial replay (``hydrokit manoeuvre VEHICLE --replay TRIAL.csv``, issue #48): the model flown
through a recorded trial's own inputs and measured with the same code as the trial.

:func:`replay` takes a run (the arrays of :func:`hydrokit.io.runlog.read_run`: row times,
motion channels at their own rates, thruster commands or measured thrusts and control-surface
deflections, held from row to row) and

1. **detects the manoeuvre** from the steering surface's deflection (:func:`detect_manoeuvre`):
   its *sides* are the angles it is held at, long and large (:func:`_sides`: course keeping
   before the execute moves the rudder too, but briefly or by little); one side — a *turning
   circle*; two or more, alternating — a *zigzag* A/B, A the median held deflection and B the
   heading change at the reversals (rounded to the whole degree: the trial's nominal check
   angle). Each execute is the row where the surface starts to move towards its new side (the
   order given, as far as a log can tell it);
2. **puts the measured track** on the integration grid (each channel linear between its samples;
   a velocity not measured from the pose's rate, a position not measured by dead reckoning of u
   and v; what was neither is 0 and said in the warnings);
3. **flies the model** from the trial's first state (every channel's value at the first row from
   a quadratic least-squares fit through its first samples — half a second of them, three at
   least: a sparse or noisy channel does not set the start by one sample) with the recorded
   inputs: each step holds the deflections logged at its midpoint (the surfaces' measured
   angles: no servo acts on them again); thrusters follow their commands through their rotor lag,
   settled at the first command, with the thrust from each curve at the model's own advance
   speed (:class:`hydrokit.simulate.commands.CommandForce`), measured thrusts held as logged;
   RK4 on the compiled right-hand side;
4. **measures both tracks** with :func:`hydrokit.manoeuvre.result.measure` (the metric
   functions of :mod:`hydrokit.manoeuvre.metrics`) at the same executes, and differences
   them (predicted − measured, absolute and relative to |measured|).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.names import POSE_SYMBOLS, VELOCITY_SYMBOLS
from hydrokit.errors import InputError, SimulationError
from hydrokit.manoeuvre.run import Manoeuvre, ManoeuvreResult, measure, steering_surface

#: a steering surface whose deflection spans less than this never moved, rad (0.5°)
NEVER_MOVES = math.radians(0.5)
#: a surface is held while it stays within this angle of where it settled, rad (0.6°: a rudder
#: sensor's quantisation and noise)
HELD = math.radians(0.6)
#: a held stretch is a side of the manoeuvre when it lasts this fraction of the longest one …
LONG_FRACTION = 0.2
#: … at this fraction of the largest angle of those
SIDE_FRACTION = 0.5
#: the surface is moving towards its new side while each row changes by more than this fraction
#: of the largest deflection (the walk back from the side to the execute)
MOVING_FRACTION = 0.01
#: a zigzag's heading changes at the reversals may spread by this fraction of B before a warning
CHECK_SPREAD = 0.25
#: seconds of samples fitted for the initial state (at least INITIAL_MIN_SAMPLES samples)
INITIAL_WINDOW = 0.5
INITIAL_MIN_SAMPLES = 3
CHANNELS = (*POSE_SYMBOLS, *VELOCITY_SYMBOLS)


@dataclass(frozen=True)
class Detected:
    """The manoeuvre read from a trial's deflections.

    manoeuvre : Manoeuvre — kind, deflection A (rad, signed: the first side), check angle B (rad)
    executes : tuple of float — s, file time of every execute (the first is the manoeuvre's start)
    end : float — s, file time of the record's end (the last row the surface held its side)
    notes : tuple of str — what looked unlike the standard manoeuvre (for the warnings)
    """

    manoeuvre: Manoeuvre
    executes: tuple[float, ...]
    end: float
    notes: tuple[str, ...] = ()


def _sides(time: np.ndarray, delta: np.ndarray) -> list[tuple[int, int, int]]:
    """(side ±1, first row, last row) of the surface's held sides, in time order.

    A *plateau* is a run of rows within :data:`HELD` of its first row. The sides are the
    plateaus away from zero (≥ :data:`NEVER_MOVES`) held at least :data:`LONG_FRACTION` of the
    longest such plateau, at ≥ :data:`SIDE_FRACTION` of the largest of their angles — so the
    sweeps of course keeping before the execute (short, or small) are not sides — and the last
    plateau of the record if it reverses the last side (a trial's last side is cut short by the
    end of the log). Consecutive sides of one sign are one.
    """
    n = delta.size
    plateaus: list[tuple[int, int]] = []
    k = 0
    while k < n:
        j = k
        while j + 1 < n and abs(delta[j + 1] - delta[k]) <= HELD:
            j += 1
        plateaus.append((k, j))
        k = j + 1
    value = {p: float(np.median(delta[p[0] : p[1] + 1])) for p in plateaus}
    away = [p for p in plateaus if abs(value[p]) >= NEVER_MOVES and p[1] > p[0]]
    if not away:
        return []
    held = {p: float(time[p[1]] - time[p[0]]) for p in away}
    longest = max(held.values())
    long = [p for p in away if held[p] >= LONG_FRACTION * longest]
    big = max(abs(value[p]) for p in long)
    picked = [p for p in long if abs(value[p]) >= SIDE_FRACTION * big]
    last = next((p for p in reversed(away) if abs(value[p]) >= SIDE_FRACTION * big), None)
    if last is not None and last[0] > picked[-1][1] and value[last] * value[picked[-1]] < 0:
        picked.append(last)
    runs: list[tuple[int, int, int]] = []
    for a, b in picked:
        sign = 1 if value[(a, b)] > 0 else -1
        if runs and runs[-1][0] == sign:
            runs[-1] = (sign, runs[-1][1], b)
        else:
            runs.append((sign, a, b))
    return runs


def _execute_row(delta: np.ndarray, first: int, low: int, s: int, tol: float) -> int:
    """The row where the surface started to move towards side ``s``: back from ``first`` (the
    first row on the side) while the row before was still moving that way (by more than
    ``tol`` rad), no further back than ``low``."""
    j = first
    while j - 1 > low and s * (delta[j - 1] - delta[j - 2]) > tol:
        j -= 1
    return j


def detect_manoeuvre(
    time: np.ndarray, delta: np.ndarray, psi: Callable[[np.ndarray], np.ndarray], column: str = "rudder"
) -> Detected:
    """The turning circle or zigzag in a trial (module docstring).

    Parameters
    ----------
    time : (n,) — row times, s
    delta : (n,) — the steering surface's deflection on each row, rad (held to the next row)
    psi : callable — the measured heading (rad, unwrapped) at given times (s)
    column : str — the surface's column, for the messages

    Raises
    ------
    InputError
        A surface that never moves, or deflections that are neither manoeuvre.
    """
    t = np.asarray(time, float)
    d = np.asarray(delta, float)
    span = float(np.ptp(d)) if d.size else 0.0
    if span < NEVER_MOVES:
        raise InputError(
            f"column '{column}' moves by {math.degrees(span):.2g}° at most (from {math.degrees(float(d[0])):.4g}°): the "
            f"steering surface never moves; expected a turning circle (stepped to an angle and held) or a zigzag "
            f"(switched between ±A), a range of at least {math.degrees(NEVER_MOVES):g}°"
        )
    runs = _sides(t, d)
    if not runs:
        raise InputError(
            f"column '{column}' is never held at an angle of at least {math.degrees(NEVER_MOVES):g}° (it moves by "
            f"{math.degrees(span):.3g}°); expected a turning circle (stepped to an angle and held) or a zigzag "
            "(switched between ±A and held)"
        )
    big = max(float(np.max(np.abs(d[a : b + 1]))) for _, a, b in runs)
    tol = MOVING_FRACTION * big
    rows, low = [], 0
    for s, first, _ in runs:
        rows.append(_execute_row(d, first, low, s, tol))
        low = first
    executes = tuple(float(t[k]) for k in rows)
    held = np.concatenate([np.abs(d[a : b + 1]) for _, a, b in runs])
    a = runs[0][0] * float(np.median(held))
    end = float(t[runs[-1][2]])
    if len(runs) == 1:
        return Detected(Manoeuvre("turning_circle", a), executes, end)
    ex = np.asarray(executes)
    change = np.abs(psi(ex[1:]) - psi(ex[:1]))
    b = math.radians(round(math.degrees(float(np.median(change)))))
    if not 0 < b < math.pi / 2:
        raise InputError(
            f"column '{column}' switches side {len(runs) - 1} time(s) but the heading changed by "
            f"{math.degrees(float(np.median(change))):.3g}° at the reversals; expected a zigzag's check angle "
            "between 1° and 89°"
        )
    notes: tuple[str, ...] = ()
    if float(np.ptp(change)) > CHECK_SPREAD * b:
        notes = (
            f"zigzag: the heading changed by {math.degrees(float(np.min(change))):.3g}° to "
            f"{math.degrees(float(np.max(change))):.3g}° at the rudder reversals, not one check angle; B = "
            f"{math.degrees(b):g}° is their median",
        )
    return Detected(Manoeuvre("zigzag", a, check_angle=b), executes, end, notes)


# ------------------------------------------------------------------------------ the measured track
def _fit_at(ts: np.ndarray, ys: np.ndarray, t0: float) -> tuple[float, float]:
    """Value and rate at ``t0`` of a least-squares polynomial (degree ≤ 2) through the samples of
    the first :data:`INITIAL_WINDOW` s (at least :data:`INITIAL_MIN_SAMPLES` samples)."""
    n = max(int(np.searchsorted(ts, ts[0] + INITIAL_WINDOW, side="right")), INITIAL_MIN_SAMPLES)
    tt, yy = ts[:n] - t0, ys[:n]
    deg = min(2, tt.size - 1)
    if deg <= 0:
        return float(yy[0]), 0.0
    c = np.polynomial.polynomial.polyfit(tt, yy, deg)
    return float(c[0]), float(c[1])


def measured_track(
    grid: np.ndarray, channels: Mapping[str, tuple[np.ndarray, np.ndarray]]
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """The measured 12 states on ``grid`` (s), the initial state at grid[0] and notes.

    Each measured channel is linear between its samples (held beyond them); u, v and r not
    measured come from the rates of x, y and ψ (u = ẋ cos ψ + ẏ sin ψ, v = −ẋ sin ψ + ẏ cos ψ),
    x and y not measured from u and v (dead reckoning, from 0); the rest not measured are 0.
    """
    if "psi" not in channels:
        raise InputError("no heading: the trial has no 'psi' samples; expected the heading ψ (rad)")
    n = grid.size
    t0 = float(grid[0])
    x = np.zeros((n, 12))
    x0 = np.zeros(12)
    samples = {
        name: (np.asarray(channels[name][0], float), np.asarray(channels[name][1], float))
        for name in CHANNELS
        if name in channels and np.size(channels[name][0]) > 0
    }
    start = {name: _fit_at(ts, ys, t0) for name, (ts, ys) in samples.items()}  # (value, rate) at t0
    for j, name in enumerate(CHANNELS):
        if name in samples:
            x[:, j] = np.interp(grid, *samples[name])
            x0[j] = start[name][0]
    notes: list[str] = []
    cos, sin = np.cos(x[:, 5]), np.sin(x[:, 5])
    if "x" in samples and "y" in samples:
        xd, yd = np.gradient(x[:, 0], grid), np.gradient(x[:, 1], grid)
        rx, ry = start["x"][1], start["y"][1]
        derived = {
            "u": (xd * cos + yd * sin, rx * cos[0] + ry * sin[0]),
            "v": (-xd * sin + yd * cos, -rx * sin[0] + ry * cos[0]),
        }
        for name, j in (("u", 6), ("v", 7)):
            if name not in samples:
                x[:, j], x0[j] = derived[name]
                notes.append(f"{name} not measured: from the rate of x and y")
    elif "u" in samples and "v" in samples:
        xd, yd = x[:, 6] * cos - x[:, 7] * sin, x[:, 6] * sin + x[:, 7] * cos
        half = 0.5 * np.diff(grid)
        for j, rate in ((0, xd), (1, yd)):
            if POSE_SYMBOLS[j] not in samples:
                x[:, j] = np.concatenate([[0.0], np.cumsum(half * (rate[1:] + rate[:-1]))])
                x0[j] = 0.0
        notes.append("x, y not both measured: dead reckoning of u and v from 0")
    else:
        raise InputError(
            "no track: the trial has neither x and y nor u and v; expected the position (m) or the body velocity (m/s)"
        )
    if "r" not in samples:
        x[:, 11], x0[11] = np.gradient(x[:, 5], grid), start["psi"][1]
        notes.append("r not measured: from the rate of ψ")
    zero = [name for name in CHANNELS if name not in samples and name not in ("x", "y", "u", "v", "r")]
    if zero:
        notes.append(f"{', '.join(zero)} not measured: 0")
    return x, x0, notes


# ------------------------------------------------------------------------------ the result
@dataclass
class ReplayResult(Result):
    """A trial and its replay.

    Attributes
    ----------
    trial : str — the run's name; vehicle : str
    detected : Detected — the manoeuvre read from the deflections (file times)
    measured, predicted : ManoeuvreResult — the two tracks measured with the same code (time 0
        at the first execute, positions from the measured execute point, m)
    initial_state : (12,) — the state the model started from, SI
    dt : float — integration step, s
    warnings : list of str
    """

    trial: str
    vehicle: str
    detected: Detected
    measured: ManoeuvreResult
    predicted: ManoeuvreResult
    initial_state: np.ndarray
    dt: float
    warnings: list[str] = field(default_factory=list)

    @property
    def kind(self) -> str:
        return self.detected.manoeuvre.kind

    def difference(self) -> dict[str, dict[str, float | None]]:
        """Predicted − measured of every numeric metric (absolute, SI or deg as the metric) and
        relative to |measured| (None where either is missing or the measured value is 0)."""
        absolute: dict[str, float | None] = {}
        relative: dict[str, float | None] = {}
        for k, m in self.measured.metrics.items():
            p = self.predicted.metrics.get(k)
            if isinstance(m, bool) or not isinstance(m, (int, float, type(None))):
                continue
            if isinstance(p, bool) or not isinstance(p, (int, float, type(None))):
                continue
            if m is None or p is None:
                absolute[k] = relative[k] = None
                continue
            absolute[k] = float(p - m)
            relative[k] = float((p - m) / abs(m)) if m != 0 else None
        return {"absolute": absolute, "relative": relative}

    def to_dict(self) -> dict[str, Any]:
        """manoeuvre.json of a replay: the predicted run's document (as ``hydrokit manoeuvre``
        writes it) with ``measured``, ``predicted`` and ``difference`` blocks and the trial."""
        doc = self.predicted.to_dict()
        doc["measured"] = self.measured.metrics
        doc["predicted"] = self.predicted.metrics
        doc["difference"] = self.difference()
        doc["trial"] = {
            "name": self.trial,
            "executes": [e - self.detected.executes[0] for e in self.detected.executes],
            "execute_time": self.detected.executes[0],
            "end": self.detected.end - self.detected.executes[0],
            "initial_state": dict(zip(CHANNELS, self.initial_state.tolist())),
            "dt": self.dt,
        }
        doc["warnings"] = list(self.warnings)
        doc["complete"] = self.measured.problem is None and self.predicted.problem is None
        doc["problem"] = (
            "; ".join(
                f"{w}: {r.problem}"
                for w, r in (("measured", self.measured), ("predicted", self.predicted))
                if r.problem
            )
            or None
        )
        return jsonable(doc)

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """trajectory.csv: time (s, 0 at the execute), each surface (rad), the measured and the
        predicted 12 states (``measured_x`` … ``predicted_r``; SI)."""
        m, p = self.measured, self.predicted
        cols = ["time", *m.surface_names, *(f"measured_{c}" for c in CHANNELS), *(f"predicted_{c}" for c in CHANNELS)]
        data = np.column_stack([m.time, m.deflection, m.eta, m.nu, p.eta, p.nu])
        return cols, data.tolist()

    def array(self) -> np.ndarray:
        m, p = self.measured, self.predicted
        return np.column_stack([m.time, m.deflection, m.eta, m.nu, p.eta, p.nu])

    def summary_rows(self) -> list[tuple[str, Any]]:
        rows: list[tuple[str, Any]] = [("trial", self.trial), ("manoeuvre", self.kind)]
        diff = self.difference()["absolute"]
        for k, v in self.measured.metrics.items():
            if k in diff:
                rows.append((k, (v, self.predicted.metrics.get(k), diff[k])))
        return rows

    def plot(self, ax: Any = None) -> Any:
        """Both tracks overlaid on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.replay import tracks_axes

        return tracks_axes(self, ax)


# ------------------------------------------------------------------------------ the replay
def _held(time: np.ndarray, values: np.ndarray, t: float) -> np.ndarray:
    k = min(max(int(np.searchsorted(time, t, side="right")) - 1, 0), time.size - 1)
    return np.asarray(values[k])


def replay(
    vehicle: Any,
    run: Any,
    *,
    surface: str | None = None,
    tau: Any = (0, 0, 0, 0, 0, 0),
    dt: float = 0.02,
    current_ned: Any = None,
    loop: str = "compiled",
    progress: Callable[[float], None] | None = None,
) -> ReplayResult:
    """Replay a trial with ``vehicle`` (module docstring).

    Parameters
    ----------
    vehicle : Vehicle — with ``control_surfaces`` (and the thrusters the run commands)
    run : the run's arrays, as :func:`hydrokit.io.runlog.read_run` gives them: ``name``,
        ``time`` (s), ``channels`` {channel: (t s, values SI)}, ``commands`` {thruster: command on
        each row, its unit}, ``thrusts`` {thruster: N on each row}, ``deflections`` {surface: rad
        on each row}
    surface : str or None — the steering surface (None: the one named rudder)
    tau : 6 floats — constant force added to the thrusters', N, N·m (body axes)
    dt : float — integration step, s
    current_ned : None or 3 floats — ocean current, m/s (NED); None: the run's logged wind and current
        (``wind_speed`` … columns, :meth:`hydrokit.io.runlog.RunLog.environment_table`), if any
    loop : "compiled" (the numba right-hand side) or "python" (the numpy one)
    progress : callable(seconds flown) or None

    Returns
    -------
    ReplayResult

    Raises
    ------
    InputError
        A steering surface that never moves, deflections that are neither a turning circle nor a
        zigzag, a trial without heading or track, a bad ``dt``.
    """
    names = tuple(vehicle.surfaces.names)
    idx = steering_surface(names, "turning_circle", surface)
    t_rows = np.asarray(run.time, float)
    defl = np.column_stack([np.asarray(run.deflections[n], float) for n in names])
    if not (math.isfinite(dt) and 0 < dt <= t_rows[-1] - t_rows[0]):
        raise InputError(f"dt = {dt} s: expected 0 < dt ≤ the trial's length {t_rows[-1] - t_rows[0]:.6g} s")
    if "psi" not in run.channels:
        raise InputError("no heading: the trial has no 'psi' samples; expected the heading ψ (rad)")
    ts_psi, ys_psi = (np.asarray(a, float) for a in run.channels["psi"])
    det = detect_manoeuvre(t_rows, defl[:, idx], lambda t: np.interp(t, ts_psi, ys_psi), names[idx])
    t_ex = det.executes[0]
    # the grid passes through the execute, from the first row (or just after it) to the end
    k_ex = int(math.floor((t_ex - float(t_rows[0])) / dt + 1e-9))
    n = k_ex + int(math.floor((det.end - t_ex) / dt + 1e-9))
    time = dt * (np.arange(n + 1) - k_ex)  # s from the execute
    grid = t_ex + time
    t0 = float(grid[0])
    meas, x0, notes = measured_track(grid, run.channels)
    if current_ned is None and hasattr(run, "environment_table"):
        current_ned = run.environment_table()  # the logged wind and current, when the run has them
    force = _force(vehicle, run, tau, current_ned)
    if loop == "compiled":
        from hydrokit.simulate.compiled import make_dynamics

        f = make_dynamics(vehicle, current_ned)
    elif loop == "python":
        from hydrokit.model.dynamics import vehicle_dynamics

        f = vehicle_dynamics(vehicle, current_ned)
    else:
        raise InputError(f"loop = {loop!r}: expected compiled or python")
    from hydrokit.simulate.commands import CommandForce, driven_rhs
    from hydrokit.simulate.integrators import rk4_step

    if isinstance(force, CommandForce):  # T(), n() factors and a rudder's race read the thrust: simulate's inputs
        cf = force
        g = driven_rhs(f, lambda t, y: cf.inputs(t, y[:6], y[6:]), len(vehicle.thruster_names))
    else:  # a vehicle without thrusters: the constant force

        def g(t: float, y: np.ndarray, d: np.ndarray) -> np.ndarray:
            return f(t, y, force(t, y[:6], y[6:]), d)

    pred = np.empty((n + 1, 12))
    d_grid = np.empty((n + 1, len(names)))
    y = x0.copy()
    report = max(1, n // 100)
    for k in range(n + 1):
        pred[k] = y
        d = _held(t_rows, defl, float(grid[k]) + 0.5 * dt)  # held over the step: the logged angle
        d_grid[k] = d
        if k == n:
            break
        y = rk4_step(g, float(grid[k]), y, dt, u=d)
        if not np.all(np.isfinite(y)):
            raise SimulationError(
                f"the predicted state became non-finite at t = {grid[k + 1] - t0:.6g} s into the trial; check the "
                "coefficients and dt"
            )
        if progress is not None and k % report == 0:
            progress(float(grid[k] - t0))
    origin = np.interp(t_ex, grid, meas[:, 0]), np.interp(t_ex, grid, meas[:, 1])
    for a in (meas, pred):
        a[:, 0] -= origin[0]
        a[:, 1] -= origin[1]
    logic = SimpleNamespace(executes=[e - t_ex for e in det.executes], notes=[])
    kw = {
        "vehicle": vehicle.name,
        "surface_names": names,
        "surface": names[idx],
        "reference_length": vehicle.reference_length,
        "planar": bool(vehicle.planar),
    }
    m_res = measure(det.manoeuvre, time, meas, d_grid, logic, **kw)  # type: ignore[arg-type]
    p_res = measure(det.manoeuvre, time, pred, d_grid, logic, **kw)  # type: ignore[arg-type]
    warnings = [*vehicle.warnings, *getattr(run, "warnings", ()), *det.notes, *notes]
    for what, r in (("measured", m_res), ("predicted", p_res)):
        if r.problem:
            warnings.append(f"{what}: {r.problem}")
    if progress is not None:
        progress(float(grid[-1] - t0))
    return ReplayResult(
        trial=str(run.name),
        vehicle=vehicle.name,
        detected=det,
        measured=m_res,
        predicted=p_res,
        initial_state=x0,
        dt=float(dt),
        warnings=warnings,
    )


def _force(vehicle: Any, run: Any, tau: Any, current_ned: Any) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray]:
    """τ(t, η, ν): the thrusters at the run's commands (rotors settled at the first) or measured
    thrusts, plus the constant ``tau`` (N, N·m)."""
    force = np.asarray(tau, float)
    if force.shape != (6,) or not np.all(np.isfinite(force)):
        raise InputError(f"force {force.tolist()}: expected 6 finite numbers (N, N·m)")
    ts = getattr(vehicle, "thrusters", None)
    if ts is None or len(ts) == 0:
        return lambda t, eta, nu: force
    from hydrokit.simulate.commands import CommandForce

    cols, measured = [], []
    for name in ts.names:
        if name in run.commands:
            cols.append(np.asarray(run.commands[name], float))
            measured.append(False)
        elif name in run.thrusts:
            cols.append(np.asarray(run.thrusts[name], float))
            measured.append(True)
        else:
            raise InputError(f"no input for thruster '{name}'; expected a column '{name}' or 'thrust:{name}'")
    table = np.column_stack([np.asarray(run.time, float), *cols])
    return CommandForce(ts, table, measured, force, start="settled", current_ned=current_ned)
