"""ROS bags (rosbag2 sqlite3 or mcap, ROS 1 ``.bag``) as a recording, through ``rosbags``.

``--topic`` picks the topic (optional when the bag has one), ``--signal`` the value: for
``sensor_msgs/msg/Imu`` the words ``roll``, ``pitch``, ``yaw`` are the Euler angles (ZYX, rad)
of the orientation quaternion; otherwise a dotted path to a number (``data``, ``position.0``,
``angular_velocity.x``). Time: the message's ``header.stamp`` when it has one and it is set,
else the time the message was recorded (``--time record`` forces that; ``--time PATH`` names
another stamp or number field). ROS values are SI (REP 103) unless ``--signal-unit`` says else.
"""

from __future__ import annotations

import math
import os
from numbers import Real
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.errors import InputError, MissingExtraError
from hydrokit.io.recording import TIME_UNITS, Recording

IMU = "sensor_msgs/msg/Imu"
EULER = ("roll", "pitch", "yaw")


def euler_zyx(w: np.ndarray, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, ...]:
    """Roll, pitch, yaw (rad) of unit quaternions (ZYX convention, as ROS ``tf`` uses)."""
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def _fields(obj: Any) -> str:
    names = [n for n in getattr(obj, "__dataclass_fields__", {}) if not n.startswith("_")]
    return ", ".join(names) if names else type(obj).__name__


def field_value(msg: Any, path: str, src: str) -> Any:
    """The value at a dotted path (``a.b.0``) of a deserialised message."""
    obj = msg
    for part in path.split("."):
        try:
            obj = obj[int(part)] if part.isdigit() else getattr(obj, part)
        except (AttributeError, IndexError, TypeError, KeyError):
            raise InputError(
                f"--signal/--time {path!r}: no field {part!r} here (fields: {_fields(obj)})", src
            ) from None
    return obj


def _number(v: Any, path: str, src: str) -> float:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (Real, np.number)):
        raise InputError(f"--signal/--time {path!r} is a {type(v).__name__}, not a number (fields: {_fields(v)})", src)
    return float(v)


def _stamp(msg: Any) -> float | None:
    st = getattr(getattr(msg, "header", None), "stamp", None)
    if st is None:
        return None
    return st.sec + st.nanosec * 1e-9


def read_bag(
    path: str | os.PathLike[str],
    *,
    topic: str | None = None,
    signal: str | None = None,
    unit: tuple[float, str] | None = None,
    time_unit: str | None = None,
    time: str | None = None,
) -> Recording:
    """One topic's signal against time, in s and SI (rad or m)."""
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise MissingExtraError("rosbags", "ros") from None

    p = Path(path)
    src = str(p)
    try:
        with quiet("rosbags"):
            reader = AnyReader([p], default_typestore=get_typestore(Stores.LATEST))
            reader.open()
    except Exception as exc:  # rosbags raises its own error types for unreadable bags
        raise InputError(f"cannot read the bag: {' '.join(str(exc).split())}", src) from None
    try:
        topics = sorted({c.topic for c in reader.connections})
        if topic is None and len(topics) == 1:
            topic = topics[0]
        if topic not in topics:
            what = "give --topic" if topic is None else f"--topic {topic!r} is not in the bag"
            raise InputError(f"{what} (topics: {', '.join(topics) or 'none'})", src)
        conns = [c for c in reader.connections if c.topic == topic]
        msgtype = conns[0].msgtype
        if signal is None:
            if msgtype == IMU:
                raise InputError(f"{topic} is {IMU}: give --signal roll, pitch, yaw or a field path", src)
            signal = "data"
        euler = msgtype == IMU and signal in EULER
        ts: list[float | None] = []
        rec_t: list[float] = []
        vals: list[Any] = []
        with quiet("rosbags"):  # its deserialisers may warn: into the log
            for conn, stamp_ns, raw in reader.messages(connections=conns):
                msg: Any = reader.deserialize(raw, conn.msgtype)
                rec_t.append(stamp_ns * 1e-9)
                if time not in (None, "record", "header"):
                    ts.append(_number(field_value(msg, time, src), time, src) * TIME_UNITS[time_unit or "s"])
                elif time != "record":
                    ts.append(_stamp(msg))
                if euler:
                    q = msg.orientation
                    vals.append((q.w, q.x, q.y, q.z))
                else:
                    vals.append(_number(field_value(msg, signal, src), signal, src))
    finally:
        reader.close()
    if not vals:
        raise InputError(f"topic {topic!r} has no messages", src)
    notes = [f"topic {topic} ({msgtype})"]
    if ts and all(s is not None for s in ts) and any(s != 0 for s in ts):
        t = np.asarray(ts, float)
        notes.append("time from the message stamps" if time not in (None, "header") else "time from header.stamp")
    else:
        t = np.asarray(rec_t)
        notes.append(
            "time: the record time (the messages have no header stamp)" if time is None else "time: record time"
        )
    if euler:
        q = np.asarray(vals, float)
        norm = np.linalg.norm(q, axis=1)
        if np.any(~np.isfinite(norm)) or np.any(np.abs(norm - 1) > 0.05):
            raise InputError(f"{topic}: orientation is not a unit quaternion (|q| = {norm.min():.3g}…)", src)
        y = euler_zyx(*(q / norm[:, None]).T)[EULER.index(signal)]
        notes.append(f"{signal} = Euler angle (ZYX) of the orientation quaternion, rad")
    else:
        y = np.asarray(vals, float)
    factor, uname = unit if unit else (1.0, "SI (ROS REP 103)")
    y = y * factor
    if not np.all(np.isfinite(y)):
        raise InputError(f"{topic} {signal}: NaN or inf in the signal", src)
    if math.isclose(factor, 1.0) and unit is None:
        notes.append("signal taken as SI (rad or m), ROS convention")
    return Recording(t, y, src, f"{topic} {signal} ({uname})", tuple(notes))
