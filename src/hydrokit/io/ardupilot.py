"""ArduPilot logs as a recording, through ``pymavlink``: DataFlash ``.bin`` and MAVLink ``.tlog``.

``--signal MESSAGE.FIELD`` (``ATT.Pitch`` in a DataFlash log, ``ATTITUDE.pitch`` in a tlog).
Units: DataFlash logs carry their own (``FMTU``: ATT angles are degrees, converted to rad);
MAVLink attitude fields are rad. Time: the autopilot's clock, ``TimeUS`` (µs) in DataFlash and
``time_boot_ms``/``time_usec`` in MAVLink messages that have it; ``--time tlog`` takes the tlog's
receive stamps instead (the ground station's clock: bursts and repeated stamps over a
telemetry link), ``--time FIELD`` any other field (in ``--time-unit``). The attitude is the autopilot's filtered estimate
(EKF or DCM), not the raw gyro: ``ingest.json`` says so.
"""

from __future__ import annotations

import contextlib
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.errors import InputError, MissingExtraError
from hydrokit.io.channels import LogChannels, Stream, clean_stream
from hydrokit.io.recording import TIME_UNITS, Recording

#: DataFlash FMTU unit names → factor to SI
DF_UNITS = {"deg": math.pi / 180, "degheading": math.pi / 180, "rad": 1.0, "m": 1.0, "cm": 0.01, "mm": 1e-3}
#: MAVLink fields whose unit is known (the attitude messages are rad)
MAV_RAD = {"roll", "pitch", "yaw", "rollspeed", "pitchspeed", "yawspeed"}
TIME_FIELDS = {"TimeUS": 1e-6, "TimeMS": 1e-3, "time_boot_ms": 1e-3, "time_usec": 1e-6}
LAG_NOTE = (
    "the attitude is the autopilot's filtered estimate (EKF/DCM), not a raw sensor: it lags the true motion "
    "by the order of tens of ms and smooths the fastest content; compare the identified damping with a raw "
    "IMU record if one exists"
)


def _fields(msg: Any) -> list[str]:
    return [f for f in msg.get_fieldnames() if not f.startswith("_")]


def _open(p: Path, mavlink2: bool = False) -> Any:
    """The pymavlink reader of a DataFlash (``.bin``) or MAVLink (``.tlog``) file; ``mavlink2``
    decodes with the MAVLink 2 dialect (messages numbered above 255, e.g. VISION_POSITION_DELTA)."""
    try:
        from pymavlink import mavutil
    except ImportError:
        raise MissingExtraError("pymavlink", "ardupilot") from None
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    try:
        # the reader classes directly: mavlink_connection() would treat some paths as a
        # network address or an executable to run (a path with ':' or '/bin/')
        with quiet("pymavlink"):  # it prints a line per bad header: into the log, not on stderr
            if p.suffix.lower() == ".tlog":
                saved = os.environ.get("MAVLINK20")
                if mavlink2:  # pymavlink picks the dialect's protocol from this variable
                    os.environ["MAVLINK20"] = "1"
                try:
                    mavutil.set_dialect("ardupilotmega")
                finally:
                    if mavlink2 and saved is None:
                        del os.environ["MAVLINK20"]
                return mavutil.mavmmaplog(src)
            from pymavlink.DFReader import DFReader_binary

            return DFReader_binary(src, zero_time_base=False)
    except Exception as exc:  # pymavlink raises bare exceptions on unreadable files
        raise InputError(f"cannot read the log: {' '.join(str(exc).split())}", src) from None


def read_log(
    path: str | os.PathLike[str],
    *,
    signal: str | None = None,
    unit: tuple[float, str] | None = None,
    time_unit: str | None = None,
    time: str | None = None,
) -> Recording:
    """One MESSAGE.FIELD of a DataFlash or tlog file against time, in s and SI."""

    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    if not signal or signal.count(".") != 1:
        raise InputError(f"--signal {signal!r}: expected MESSAGE.FIELD (e.g. ATT.Pitch, ATTITUDE.pitch)", src)
    mtype, fld = signal.split(".")
    tlog = p.suffix.lower() == ".tlog"
    log = _open(p)
    ts: list[float] = []
    vals: list[float] = []
    first: Any = None
    system = None
    with contextlib.ExitStack() as stack:
        stack.callback(log.close)
        stack.enter_context(quiet("pymavlink"))  # the whole read: one capture, not one per message
        while True:
            msg = log.recv_match(type=mtype)
            if msg is None:
                break
            if tlog:
                if system is None:
                    system = msg.get_srcSystem()
                elif msg.get_srcSystem() != system:
                    continue
            first = first or msg
            if fld not in _fields(msg):
                raise InputError(
                    f"--signal {signal!r}: {mtype} has no field {fld!r} (fields: {', '.join(_fields(msg))})", src
                )
            v = getattr(msg, fld)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise InputError(f"--signal {signal!r} is a {type(v).__name__}, not a number", src)
            vals.append(float(v))
            if time is None:
                # the autopilot's clock: no link jitter (tlog receive stamps come in bursts)
                time = next((f for f in TIME_FIELDS if f in _fields(msg)), "tlog")
            if time == "tlog":
                ts.append(float(msg._timestamp))
            elif time not in _fields(msg):
                raise InputError(f"--time {time!r}: {mtype} has no such field (fields: {', '.join(_fields(msg))})", src)
            else:
                scale = TIME_UNITS[time_unit] if time_unit else TIME_FIELDS.get(time, 1.0)
                ts.append(float(getattr(msg, time)) * scale)
        kinds = ", ".join(sorted(log.messages)) if hasattr(log, "messages") else "?"
    if first is None:
        raise InputError(f"--signal {signal!r}: no {mtype} messages in the log (types: {kinds})", src)
    notes = []
    if unit is None:
        if tlog:
            factor, uname = (1.0, "rad") if fld in MAV_RAD else (1.0, "SI (assumed)")
        else:
            fu = getattr(first.fmt, "units", None)
            cols = list(first.fmt.columns)
            du = fu[cols.index(fld)] if fu and fld in cols else None
            if du is None:
                du = "deg" if fld in ("Roll", "Pitch", "Yaw", "DesRoll", "DesPitch", "DesYaw") else ""
            factor, uname = DF_UNITS.get(du, 1.0), (du or "SI (assumed)")
        if uname == "deg" or uname == "degheading":
            notes.append(f"{signal} logged in degrees: converted to rad")
    else:
        factor, uname = unit
    if time == "tlog":
        notes.append("time from the tlog receive stamps (the ground station's clock: link jitter, bursts)")
    else:
        notes.append(f"time from {mtype}.{time} (the autopilot's clock)")
    if tlog and system is not None:
        notes.append(f"messages of MAVLink system {system}")
    if mtype.upper() in ("ATT", "ATTITUDE", "AHR2", "AHRS2", "AHRS3", "XKF1", "NKF1"):
        notes.append(LAG_NOTE)
    t = np.asarray(ts, float)
    y = np.asarray(vals, float) * factor
    if fld.lower() in ("yaw", "desyaw") and unit is None:
        y = np.unwrap(y)  # a heading wraps at 360° / ±π
        notes.append("heading unwrapped")
    return Recording(t, y, src, f"{signal} ({uname})", tuple(notes))


# --------------------------------------------------------------------------- run files (#44)
#: MAVLink gyro messages (mrad/s, ArduPilot's scaling of RAW_IMU too) in order of preference
MAV_GYROS = ("RAW_IMU", "SCALED_IMU", "SCALED_IMU2", "SCALED_IMU3")
DF_TYPES = ["ATT", "IMU", "BARO", "RCOU", "VISO", "PARM"]
MAV_TYPES = [
    "ATTITUDE",
    *MAV_GYROS,
    "SCALED_PRESSURE",
    "SCALED_PRESSURE2",
    "SCALED_PRESSURE3",
    "SERVO_OUTPUT_RAW",
    "VISION_POSITION_DELTA",
    "PARAM_VALUE",
    "BAD_DATA",
]


def _wrap(a: np.ndarray) -> np.ndarray:
    """Angles to (−π, π], rad."""
    return np.angle(np.exp(1j * a))


def _check_clock(t: list[float], what: str, src: str) -> None:
    d = np.diff(np.asarray(t, float))
    if d.size and d.min() < -1.0:
        k = int(np.argmin(d))
        raise InputError(
            f"{what}: the autopilot's clock goes back from {t[k]:.3f} to {t[k + 1]:.3f} s (a reboot inside the log): "
            "split the log at the reboot",
            src,
        )


def read_log_channels(path: str | os.PathLike[str], *, baro: int | None = None) -> LogChannels:
    """Everything a run file needs from a DataFlash (``.bin``) or MAVLink (``.tlog``) log.

    Parameters
    ----------
    path : path — the log
    baro : int or None — barometer instance of the depth sensor, 0-based (DataFlash ``BARO.I``;
        MAVLink 0 → ``SCALED_PRESSURE``, 1 → ``SCALED_PRESSURE2``, 2 → ``SCALED_PRESSURE3``).
        None: ``BARO_PRIMARY`` when logged, else instance 1 when present (ArduSub's external depth
        sensor), else 0.

    Returns
    -------
    hydrokit.io.channels.LogChannels — attitude (rad), gyro (rad/s), DVL body velocity (m/s) when
    logged, depth-sensor pressure (Pa), servo outputs (µs) and parameters, on the autopilot's clock (s)

    Notes
    -----
    DataFlash: ``ATT`` Roll/Pitch/Yaw (deg → rad), ``IMU`` GyrX/Y/Z of the first instance (rad/s),
    ``BARO`` Press (Pa), ``RCOU`` C1…C16 (µs), the DVL as ArduSub logs it from its visual-odometry
    input (VISION_POSITION_DELTA, what the BlueOS DVL extensions send): ``VISO`` PosDX/Y/Z ÷ dt
    (body-frame position change over the interval, m/s); ``PARM``. MAVLink: ``ATTITUDE`` (rad), the gyro message with the most
    samples among RAW_IMU, SCALED_IMU…3 and ATTITUDE's rates (mrad/s → rad/s), SCALED_PRESSUREn
    ``press_abs`` (hPa → Pa), ``SERVO_OUTPUT_RAW`` (µs; ``time_usec`` unwrapped at 2³² µs),
    ``VISION_POSITION_DELTA`` (placed on the autopilot's clock by the tlog receive stamps), PARAM_VALUE.
    """

    p = Path(path)
    src = str(p)
    tlog = p.suffix.lower() == ".tlog"
    log = _open(p, mavlink2=True)
    raw: dict[tuple[int, str], list[Any]] = {}
    params: dict[str, float] = {}
    bad = 0
    with contextlib.ExitStack() as stack:
        stack.callback(log.close)
        stack.enter_context(quiet("pymavlink"))
        types = MAV_TYPES if tlog else DF_TYPES
        while True:
            try:
                msg = log.recv_match(type=types)
            except Exception as exc:  # a truncated or corrupt record pymavlink cannot step over
                raise InputError(f"cannot read the log: {' '.join(str(exc).split())}", src) from None
            if msg is None:
                break
            mt = msg.get_type()
            if mt == "BAD_DATA":
                bad += 1
                continue
            if mt == "PARM":
                params[str(msg.Name)] = float(msg.Value)
                continue
            if mt == "PARAM_VALUE":
                pid = msg.param_id
                params[pid.decode() if isinstance(pid, bytes) else str(pid)] = float(msg.param_value)
                continue
            system = msg.get_srcSystem() if tlog else 0
            raw.setdefault((system, mt), []).append(msg)
    kinds = sorted({k[1] for k in raw})
    if tlog:
        att_sys = [k[0] for k in raw if k[1] == "ATTITUDE"]
        if not att_sys:
            raise InputError(
                f"no ATTITUDE messages in the log: a run needs the attitude (types: {', '.join(kinds) or 'none'})", src
            )
        system = max(att_sys, key=lambda s: len(raw[(s, "ATTITUDE")]))
        msgs = {k[1]: v for k, v in raw.items() if k[0] == system}
    else:
        system = 0
        msgs = {k[1]: v for k, v in raw.items()}
        if "ATT" not in msgs:
            raise InputError(
                f"no ATT messages in the log: a run needs the attitude (types: {', '.join(kinds) or 'none'})", src
            )
    notes: list[str] = ["time: the autopilot's clock (s since boot), not re-based"]
    warns: list[str] = []
    motion: dict[str, Stream] = {}

    def put(names: tuple[str, ...], mt: str, tfield: str, tscale: float, fields: tuple[str, ...], scale: float) -> None:
        ms = msgs[mt]
        t = [float(getattr(m, tfield)) * tscale for m in ms]
        _check_clock(t, mt, src)
        for name, f in zip(names, fields):
            motion[name] = clean_stream(t, [float(getattr(m, f)) * scale for m in ms], f"{mt}.{f}")

    if tlog:
        notes.append(f"messages of MAVLink system {system}")
        put(("phi", "theta", "psi"), "ATTITUDE", "time_boot_ms", 1e-3, ("roll", "pitch", "yaw"), 1.0)
        gyros = [g for g in MAV_GYROS if g in msgs and any(m.xgyro or m.ygyro or m.zgyro for m in msgs[g])]
        best = max(gyros, key=lambda g: len(msgs[g]), default=None)
        if best is not None and len(msgs[best]) * 2 >= len(msgs["ATTITUDE"]):
            tf = "time_usec" if best == "RAW_IMU" else "time_boot_ms"
            put(("p", "q", "r"), best, tf, 1e-6 if tf == "time_usec" else 1e-3, ("xgyro", "ygyro", "zgyro"), 1e-3)
            notes.append(f"p, q, r from {best} (mrad/s → rad/s)")
        else:
            put(("p", "q", "r"), "ATTITUDE", "time_boot_ms", 1e-3, ("rollspeed", "pitchspeed", "yawspeed"), 1.0)
            why = f"more samples than {best}" if best else "no gyro message with data"
            notes.append(f"p, q, r from ATTITUDE rollspeed/pitchspeed/yawspeed (the bias-corrected gyro; {why})")
        pres = [n for n in ("SCALED_PRESSURE", "SCALED_PRESSURE2", "SCALED_PRESSURE3") if n in msgs]
        pick = baro if baro is not None else (1 if "SCALED_PRESSURE2" in pres else 0)
        pname = "SCALED_PRESSURE" + (str(pick + 1) if pick else "")
        pressure = None
        if baro is not None and pname not in pres:
            raise InputError(f"--baro {baro}: no {pname} in the log (have: {', '.join(pres) or 'none'})", src)
        if pname in pres:
            t = [m.time_boot_ms * 1e-3 for m in msgs[pname]]
            pressure = clean_stream(t, [m.press_abs * 100.0 for m in msgs[pname]], f"{pname}.press_abs")
            notes.append(f"depth sensor: {pname}.press_abs (hPa → Pa)")
        outputs: dict[int | str, Any] = {}
        if "SERVO_OUTPUT_RAW" in msgs:
            ms = msgs["SERVO_OUTPUT_RAW"]
            t_us = np.asarray([m.time_usec for m in ms], float)
            wraps = np.concatenate([[0], np.cumsum(np.diff(t_us) < -(2.0**31))])  # uint32 µs wraps at 71.6 min
            t_s = (t_us + wraps * 2.0**32) * 1e-6
            for k in range(1, 17):
                f = f"servo{k}_raw"
                for port in sorted({int(m.port) for m in ms}):
                    sel = [(tt, getattr(m, f, None)) for tt, m in zip(t_s, ms) if int(m.port) == port]
                    pairs = [(tt, v) for tt, v in sel if v is not None]
                    if pairs:
                        outputs[8 * port + k] = clean_stream(
                            [a for a, _ in pairs], [b for _, b in pairs], f"SERVO_OUTPUT_RAW.{f}"
                        )
        if "VISION_POSITION_DELTA" in msgs:
            att = msgs["ATTITUDE"]
            offset = float(np.median([m._timestamp - m.time_boot_ms * 1e-3 for m in att]))
            ms = [m for m in msgs["VISION_POSITION_DELTA"] if m.time_delta_usec > 0]
            t = [m._timestamp - offset for m in ms]
            for i, name in enumerate(("u", "v", "w")):
                motion[name] = clean_stream(
                    t,
                    [m.position_delta[i] / (m.time_delta_usec * 1e-6) for m in ms],
                    f"VISION_POSITION_DELTA.position_delta[{i}]/dt",
                )
            notes.append(
                "u, v, w: VISION_POSITION_DELTA (DVL) over its interval, placed on the autopilot's clock by the tlog receive stamps (link latency)"
            )
        out_src = "SERVO_OUTPUT_RAW"
    else:
        att = msgs["ATT"]
        t = [m.TimeUS * 1e-6 for m in att]
        _check_clock(t, "ATT", src)
        for name, f in (("phi", "Roll"), ("theta", "Pitch"), ("psi", "Yaw")):
            y = np.radians([float(getattr(m, f)) for m in att])
            motion[name] = clean_stream(t, _wrap(y) if name == "psi" else y, f"ATT.{f}")
        notes.append("phi, theta, psi: ATT Roll/Pitch/Yaw, logged in degrees (converted to rad; psi wrapped to ±π)")
        if "IMU" in msgs:
            imu = msgs["IMU"]
            first = int(getattr(imu[0], "I", 0) or 0)
            msgs["IMU"] = [m for m in imu if int(getattr(m, "I", 0) or 0) == first]
            put(("p", "q", "r"), "IMU", "TimeUS", 1e-6, ("GyrX", "GyrY", "GyrZ"), 1.0)
            notes.append(f"p, q, r: IMU GyrX/Y/Z of instance {first} (rad/s, the raw gyro)")
        pressure = None
        if "BARO" in msgs:
            inst = sorted({int(getattr(m, "I", 0) or 0) for m in msgs["BARO"]})
            prim = params.get("BARO_PRIMARY")
            pick = (
                baro
                if baro is not None
                else (int(prim) if prim is not None and int(prim) in inst else (1 if 1 in inst else inst[0]))
            )
            if pick not in inst:
                raise InputError(
                    f"--baro {pick}: no BARO instance {pick} in the log (have: {', '.join(map(str, inst))})", src
                )
            bm = [m for m in msgs["BARO"] if int(getattr(m, "I", 0) or 0) == pick]
            pressure = clean_stream([m.TimeUS * 1e-6 for m in bm], [m.Press for m in bm], f"BARO[{pick}].Press")
            why = (
                "given"
                if baro is not None
                else ("BARO_PRIMARY" if prim is not None and int(prim) in inst else "default")
            )
            notes.append(
                f"depth sensor: BARO instance {pick} ({why}; instances {', '.join(map(str, inst))}), Press in Pa"
            )
        if "VISO" in msgs:
            vm = [m for m in msgs["VISO"] if m.dt > 0]
            dts = np.asarray([m.dt for m in vm], float)
            scale = 1e-6 if dts.size and np.median(dts) > 10.0 else 1.0  # dt logged in µs by some versions
            t = [m.TimeUS * 1e-6 for m in vm]
            for name, f in (("u", "PosDX"), ("v", "PosDY"), ("w", "PosDZ")):
                motion[name] = clean_stream(t, [getattr(m, f) / (m.dt * scale) for m in vm], f"VISO.{f}/dt")
            notes.append("u, v, w: VISO PosDX/Y/Z ÷ dt (DVL position change in body axes over its interval, m/s)")
        outputs = {}
        if "RCOU" in msgs:
            rc = msgs["RCOU"]
            t = [m.TimeUS * 1e-6 for m in rc]
            _check_clock(t, "RCOU", src)
            for k in range(1, 33):
                if f"C{k}" in _fields(rc[0]):
                    outputs[k] = clean_stream(t, [float(getattr(m, f"C{k}")) for m in rc], f"RCOU.C{k}")
        out_src = "RCOU"
    if not outputs:
        raise InputError(f"no servo outputs ({out_src}) in the log: a run needs the thruster commands", src)
    if bad:
        warns.append(f"{bad} corrupt MAVLink packet(s) skipped")
    return LogChannels(
        src,
        motion,
        pressure,
        outputs,
        "pwm",
        params,
        tuple(notes),
        tuple(warns),
        bad if tlog else -1,
        out_src,
    )
