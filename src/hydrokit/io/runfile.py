"""Run files from vehicle logs (issue #44): an ArduPilot log or a ROS bag → the run-file CSV that
``hydrokit sysid`` reads (:mod:`hydrokit.io.runlog` holds the contract and the reader).

The readers (:func:`hydrokit.io.ardupilot.read_log_channels`, :func:`hydrokit.io.rosbag.read_bag_channels`)
return a :class:`LogChannels`: every channel in SI on the log's own clock, the autopilot's
outputs and parameters. :func:`log_to_run` maps the outputs to the vehicle's thrusters, turns
pressure into depth and merges everything onto one time axis: a row at every sample time of any
channel, an empty cell where a channel has no sample at that time, the thruster commands held
(zero-order hold) on every row. Nothing is written here: the CLI writes the returned texts.

Servo outputs → commands (ArduSub, ``AP_Motors6DOF``): the autopilot writes
``PWM = 1500 + d·a·(MOT_PWM_MAX − 1500)`` for ``a ≥ 0`` (``1500 − MOT_PWM_MIN`` below), ``a`` the
demanded actuator level −1…1 of the motor along its frame direction and ``d`` its
``MOT_n_DIRECTION`` (±1). So ``a = d·(PWM − 1500)/range``, times −1 where the thruster entry
says ``reversed: true`` (its ``direction`` is the opposite of the frame's).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.names import POSE_SYMBOLS, VELOCITY_SYMBOLS
from hydrokit.errors import InputError

# Stream, LogChannels and clean_stream moved to hydrokit.io.channels (the readers import them
# from there); re-exported here for one release.
from hydrokit.io.channels import LogChannels, Stream, clean_stream
from hydrokit.model.thrusters import IdealCurve, PropellerCurve, TableCurve, Thruster, ThrusterSet

__all__ = ["LogChannels", "RunOutput", "Stream", "log_to_run", "pwm_to_level", "read_channels"]

#: run-file motion columns, in state order
MOTION = (*POSE_SYMBOLS, *VELOCITY_SYMBOLS)
#: ArduPilot SERVOn_FUNCTION of motor n: 33…40 for motors 1…8, 82…85 for motors 9…12
MOTOR_FUNCTIONS = {**{n: 32 + n for n in range(1, 9)}, **{n: 73 + n for n in range(9, 13)}}
#: the usual ArduSub PWM range, µs (MOT_PWM_MIN / MOT_PWM_MAX defaults; neutral 1500)
PWM_NEUTRAL, PWM_MIN, PWM_MAX = 1500.0, 1100.0, 1900.0
#: seconds of pressure at the start of a log averaged for the surface pressure
SURFACE_WINDOW = 1.0


@dataclass(frozen=True)
class RunOutput:
    """A run file's text and its summary (``to_dict`` is what ``RUN.json`` holds)."""

    csv: str
    summary: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        """The summary: source, span, columns with rates, commands' ranges, notes, warnings."""
        return self.summary

    def files(self, run_out: str | os.PathLike[str]) -> dict[Path, str]:
        """``{RUN.csv: text, RUN.json: summary}`` for ``write_all``."""
        p = Path(run_out)
        doc = json.dumps(self.summary, indent=2, allow_nan=False, ensure_ascii=False) + "\n"
        return {p: self.csv, p.with_suffix(".json"): doc}


def pwm_to_level(pwm: np.ndarray, pwm_min: float = PWM_MIN, pwm_max: float = PWM_MAX) -> np.ndarray:
    """ArduSub's actuator level −1…1 of a PWM output, µs (inverse of ``calc_thrust_to_pwm``).

    Parameters
    ----------
    pwm : array — output pulse widths, µs (1500 neutral)
    pwm_min, pwm_max : float — MOT_PWM_MIN / MOT_PWM_MAX, µs

    Returns
    -------
    array — ``(pwm − 1500)/(pwm_max − 1500)`` above neutral, ``/(1500 − pwm_min)`` below, clipped to ±1
    """
    d = np.asarray(pwm, float) - PWM_NEUTRAL
    return np.clip(np.where(d >= 0, d / (pwm_max - PWM_NEUTRAL), d / (PWM_NEUTRAL - pwm_min)), -1.0, 1.0)


def read_channels(
    source: str | os.PathLike[str],
    *,
    fmt: str | None = None,
    baro: int | None = None,
    topics: Mapping[str, str | None] | None = None,
    ros_frame: str = "enu",
) -> LogChannels:
    """Read every channel a run file needs from an ArduPilot log or a ROS bag.

    Parameters
    ----------
    source : path — ``.bin``/``.tlog`` (ArduPilot) or a ROS bag (folder, ``.mcap``, ``.db3``, ``.bag``)
    fmt : ``"ardupilot"``, ``"rosbag"`` or None (from the extension)
    baro : int or None — ArduPilot barometer instance of the depth sensor (0-based; default:
        ``BARO_PRIMARY`` when logged, else the second instance when present — ArduSub's external
        depth sensor — else the first)
    topics : ROS bag only: ``imu``, ``pressure``, ``depth``, ``dvl``, ``commands`` → topic names
    ros_frame : ROS bag only: ``"enu"`` (REP 103: ENU world, FLU body; converted to NED/FRD) or
        ``"ned"`` (values already NED/FRD)
    """
    from hydrokit.io.ingest import detect_format

    fmt = fmt or detect_format(source)
    if fmt == "ardupilot":
        from hydrokit.io.ardupilot import read_log_channels

        if topics and any(topics.values()):
            raise InputError("--imu-topic/--dvl-topic/…: topics are for a ROS bag, not an ArduPilot log", str(source))
        return read_log_channels(source, baro=baro)
    if fmt == "rosbag":
        from hydrokit.io.rosbag import read_bag_channels

        if baro is not None:
            raise InputError("--baro is for an ArduPilot log; a ROS bag names its --pressure-topic", str(source))
        return read_bag_channels(source, topics=dict(topics or {}), frame=ros_frame)
    raise InputError(f"--run-out reads an ArduPilot log or a ROS bag, not a {fmt} source", str(source))


def _output_of(th: Thruster, ch: LogChannels) -> tuple[int | str, int | None]:
    """(output number or the thruster's own stream name, ArduSub motor number or None) driving ``th``."""
    if th.name in ch.outputs:
        return th.name, None
    if th.channel is not None:
        out = th.channel
        motor = th.motor
        if motor is None:
            func = ch.params.get(f"SERVO{out}_FUNCTION")
            if func is None:  # not logged: ArduSub's default, output n drives motor n (n ≤ 8)
                motor = out if out <= 8 and ch.output_unit == "pwm" else None
            else:
                motor = next((n for n, f in MOTOR_FUNCTIONS.items() if f == func), None)
        return out, motor
    if th.motor is None:
        raise InputError(
            f"thruster '{th.name}' has no 'channel' (servo output, 1-based) or 'motor' (ArduSub motor number) "
            "in the vehicle file: cannot tell which log output drives it"
        )
    func = MOTOR_FUNCTIONS.get(th.motor)
    outs = [
        int(k[5:-9]) for k, v in ch.params.items() if k.startswith("SERVO") and k.endswith("_FUNCTION") and v == func
    ]
    return (min(outs) if outs else th.motor), th.motor


def _to_command(
    th: Thruster, curve: Any, level: np.ndarray, pwm_range: tuple[float, float] | None
) -> tuple[np.ndarray, str, str | None]:
    """Commands in the unit of the thruster's curve from actuator levels −1…1; (values, unit, note)."""
    if isinstance(curve, TableCurve):
        lo, hi = curve.command_limits()
        if lo >= -1.0 - 1e-9 and hi <= 1.0 + 1e-9:
            return np.clip(level, lo, hi), "normalised input −1…1", None
        if pwm_range is not None and lo >= 800.0 and hi <= 2200.0:
            up, down = pwm_range[1] - PWM_NEUTRAL, PWM_NEUTRAL - pwm_range[0]
            pwm = PWM_NEUTRAL + np.where(level >= 0, level * up, level * down)
            return np.clip(pwm, lo, hi), "PWM µs", "table in PWM µs: the signed level mapped back onto the PWM range"
        raise InputError(
            f"thruster '{th.name}': its thrust_table command runs {lo:g}…{hi:g}, neither a normalised input "
            "(−1…1) nor PWM (800…2200 µs): cannot convert servo outputs to it"
        )
    if isinstance(curve, PropellerCurve):
        return level * curve.max_speed, "rev/s", "propeller: speed taken proportional to the output (an assumption)"
    if isinstance(curve, IdealCurve):
        f = np.where(level >= 0, level * th.max_thrust, level * -float(th.min_thrust))  # type: ignore[arg-type]
        return f, "N", "ideal thruster: thrust taken proportional to the output (ArduSub linearises thrust)"
    raise InputError(f"thruster '{th.name}': unknown thrust curve {type(curve).__name__}")  # pragma: no cover


def _fmt(v: float) -> str:
    return "" if math.isnan(v) else f"{v:.9g}"


def log_to_run(
    ch: LogChannels,
    thrusters: ThrusterSet,
    *,
    density: float,
    gravity: float,
    surface_pressure: float | None = None,
    start: float | None = None,
    end: float | None = None,
) -> RunOutput:
    """The run-file CSV and its summary from a log's channels.

    Parameters
    ----------
    ch : LogChannels — from :func:`read_channels`
    thrusters : ThrusterSet — the vehicle's thrusters, each with ``channel`` and/or ``motor``
    density : float — water density ρ for depth from pressure, kg/m³
    gravity : float — g, m/s²
    surface_pressure : float or None — P_surface, Pa (None: the mean of the first second of the
        depth sensor's samples, taken as the vehicle at the surface)
    start, end : float or None — keep only ``start ≤ t ≤ end``, s on the log's clock

    Returns
    -------
    RunOutput — the CSV text (time in s on the log's clock) and the summary

    Raises
    ------
    InputError
        A thruster with no output mapping, an output absent from the log, no attitude, nothing
        left between ``start`` and ``end``.

    Notes
    -----
    Depth from pressure, hydrostatics: z = (P − P_surface)/(ρ g).
    """
    src = ch.source
    notes = list(ch.notes)
    warns = list(ch.warnings)
    if not any(c in ch.motion for c in ("phi", "theta", "psi")):
        raise InputError("no attitude in the log (ATT / ATTITUDE / Imu orientation): a run needs phi, theta, psi", src)
    motion: dict[str, Stream] = dict(ch.motion)
    p_surf_used: float | None = None
    if ch.pressure is not None and ch.pressure.t.size:
        pr = ch.pressure
        if surface_pressure is None:
            first = pr.y[pr.t <= pr.t[0] + SURFACE_WINDOW]
            p_surf_used = float(np.mean(first))
            notes.append(
                f"surface pressure {p_surf_used:.1f} Pa: the mean of the depth sensor's first "
                f"{SURFACE_WINDOW:g} s ({first.size} samples), taken as the vehicle at the surface"
            )
        else:
            p_surf_used = float(surface_pressure)
            notes.append(f"surface pressure {p_surf_used:.1f} Pa (given)")
        z = (pr.y - p_surf_used) / (density * gravity)
        motion["z"] = Stream(pr.t, z, f"{pr.source}: z = (P − P_surface)/(ρ g), ρ = {density:g} kg/m³, g = {gravity:g}")
    # thrusters → outputs
    pwm_min = ch.params.get("MOT_PWM_MIN", PWM_MIN)
    pwm_max = ch.params.get("MOT_PWM_MAX", PWM_MAX)
    if ch.output_unit == "pwm" and not (pwm_min < PWM_NEUTRAL < pwm_max):
        raise InputError(f"MOT_PWM_MIN {pwm_min:g} / MOT_PWM_MAX {pwm_max:g} µs do not bracket 1500 µs", src)
    maps = []
    for th in thrusters.thrusters:
        out, motor = _output_of(th, ch)
        if out not in ch.outputs:
            have = ", ".join(str(k) for k in sorted(ch.outputs)) or "none"
            what = f"output {out}" if isinstance(out, int) else "no command topic"
            raise InputError(
                f"thruster '{th.name}': {what} is not in the log ({ch.output_source or 'outputs'}: {have})", src
            )
        maps.append((th, out, motor))
    if any(isinstance(o, int) and f"SERVO{o}_FUNCTION" not in ch.params for _, o, m in maps if m is not None):
        notes.append("motor n taken as servo output n (ArduSub's default SERVOn_FUNCTION; none logged)")
    t_out = sorted({float(x) for _, o, _ in maps for x in ch.outputs[o].t})
    t_in = np.asarray(t_out)
    first_all = max(float(ch.outputs[o].t[0]) for _, o, _ in maps)  # from here every command is known
    lo = first_all if start is None else max(float(start), first_all)
    step = float(np.median(np.diff(t_in))) if t_in.size > 1 else 0.0
    hi_data = max(float(s.t[-1]) for s in motion.values()) if motion else t_in[-1]
    hi = min(t_in[-1] + step, hi_data)
    if end is not None:
        hi = min(hi, float(end))
    if start is not None and end is not None and end <= start:
        raise InputError(f"--end {end:g} s is not after --start {start:g} s", src)
    # rows at whole µs (the file's resolution), so two samples never print as one time
    motion = {k: clean_stream(np.round(s.t, 6), s.y, s.source) for k, s in motion.items()}
    outs = {o: clean_stream(np.round(ch.outputs[o].t, 6), ch.outputs[o].y, ch.outputs[o].source) for _, o, _ in maps}
    t_in = np.round(t_in, 6)
    kept = {k: s for k, s in motion.items() if np.any((s.t >= lo) & (s.t <= hi))}
    if not kept or hi <= lo:
        span = f"{t_in[0]:.3f}…{hi_data:.3f} s"
        raise InputError(f"no samples between {lo:.3f} and {hi:.3f} s (the log spans {span} on its clock)", src)
    rows = np.unique(
        np.concatenate([s.t[(s.t >= lo) & (s.t <= hi)] for s in kept.values()] + [t_in[(t_in >= lo) & (t_in <= hi)]])
    )
    cols: dict[str, np.ndarray] = {}
    chan_doc: dict[str, Any] = {}
    for name in MOTION:
        if name not in kept:
            continue
        s = kept[name]
        m = (s.t >= lo) & (s.t <= hi)
        col = np.full(rows.size, np.nan)
        col[np.searchsorted(rows, s.t[m])] = s.y[m]
        cols[name] = col
        chan_doc[name] = {
            "source": s.source,
            "samples": int(m.sum()),
            "rate": Stream(s.t[m], s.y[m], "").rate,
            "min": float(np.min(s.y[m])),
            "max": float(np.max(s.y[m])),
        }
    th_doc: dict[str, Any] = {}
    for (th, out, motor), curve in zip(maps, thrusters.curves):
        s = outs[out]
        idx = np.searchsorted(s.t, rows, side="right") - 1
        held = s.y[np.clip(idx, 0, None)]  # idx ≥ 0: the rows start once every output has a sample
        sign = -1.0 if th.reversed else 1.0
        direction = ch.params.get(f"MOT_{motor}_DIRECTION") if motor is not None else None
        if ch.output_unit == "pwm":
            dead = held == 0  # 0 µs: the output sends no pulse (disabled)
            if np.all(s.y == 0):
                warns.append(
                    f"thruster '{th.name}': output {out} is 0 µs throughout (no pulse: the autopilot does not drive "
                    "it — a frame with fewer motors?); its command is 0"
                )
            level = pwm_to_level(np.where(dead, PWM_NEUTRAL, held), pwm_min, pwm_max)
            if direction is not None and direction < 0:
                sign = -sign
            cmd, unit, note = _to_command(th, curve, sign * level, (pwm_min, pwm_max))
        else:
            cmd, unit, note = sign * held, "as logged (the thruster's command unit)", None
        cols[th.name] = cmd + 0.0  # no "-0" in the file
        th_doc[th.name] = {
            "output": out,
            "motor": motor,
            "reversed": th.reversed,
            "direction_param": direction,
            "unit": unit,
            "min": float(np.min(cmd)),
            "max": float(np.max(cmd)),
            "samples": int(((s.t >= lo) & (s.t <= hi)).sum()),
            "rate": s.rate,
            **({"note": note} if note else {}),
        }
    header = ["time", *cols]
    lines = [",".join(header)]
    mat = np.column_stack([rows, *cols.values()])
    for r in mat:
        lines.append(f"{r[0]:.6f}," + ",".join(_fmt(v) for v in r[1:]))
    summary = {
        "source": src,
        "units": {
            "time": "s (the log's clock)",
            "x y z": "m (NED)",
            "phi theta psi": "rad",
            "u v w": "m/s (body)",
            "p q r": "rad/s (body)",
            "rate": "Hz",
            "surface_pressure": "Pa",
        },
        "start_time": float(rows[0]),
        "end_time": float(rows[-1]),
        "duration": float(rows[-1] - rows[0]),
        "rows": int(rows.size),
        "channels": chan_doc,
        "thrusters": th_doc,
        "outputs": {"source": ch.output_source, "unit": ch.output_unit, "pwm_range": [pwm_min, pwm_max]},
        "surface_pressure": p_surf_used,
        "corrupt_packets": ch.corrupt if ch.corrupt >= 0 else None,
        "notes": notes,
        "warnings": warns,
    }
    return RunOutput("\n".join(lines) + "\n", summary)
