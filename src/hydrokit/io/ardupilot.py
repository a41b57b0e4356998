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


def read_log(
    path: str | os.PathLike[str],
    *,
    signal: str | None = None,
    unit: tuple[float, str] | None = None,
    time_unit: str | None = None,
    time: str | None = None,
) -> Recording:
    """One MESSAGE.FIELD of a DataFlash or tlog file against time, in s and SI."""
    try:
        from pymavlink import mavutil
    except ImportError:
        raise MissingExtraError("pymavlink", "ardupilot") from None

    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    if not signal or signal.count(".") != 1:
        raise InputError(f"--signal {signal!r}: expected MESSAGE.FIELD (e.g. ATT.Pitch, ATTITUDE.pitch)", src)
    mtype, fld = signal.split(".")
    tlog = p.suffix.lower() == ".tlog"
    try:
        # the reader classes directly: mavlink_connection() would treat some paths as a
        # network address or an executable to run (a path with ':' or '/bin/')
        with quiet("pymavlink"):  # it prints a line per bad header: into the log, not on stderr
            if tlog:
                mavutil.set_dialect("ardupilotmega")
                log = mavutil.mavmmaplog(src)
            else:
                from pymavlink.DFReader import DFReader_binary

                log = DFReader_binary(src, zero_time_base=False)
    except Exception as exc:  # pymavlink raises bare exceptions on unreadable files
        raise InputError(f"cannot read the log: {' '.join(str(exc).split())}", src) from None
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
