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
from hydrokit.io.channels import LogChannels, Stream, clean_stream
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


def _open_bag(p: Path) -> Any:
    """An opened ``rosbags`` AnyReader of a bag (rosbag2 folder, .mcap, .db3, ROS 1 .bag)."""
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise MissingExtraError("rosbags", "ros") from None
    try:
        with quiet("rosbags"):
            reader = AnyReader([p], default_typestore=get_typestore(Stores.LATEST))
            reader.open()
    except Exception as exc:  # rosbags raises its own error types for unreadable bags
        raise InputError(f"cannot read the bag: {' '.join(str(exc).split())}", str(p)) from None
    return reader


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
    p = Path(path)
    src = str(p)
    reader = _open_bag(p)
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


# --------------------------------------------------------------------------- run files (#44)
PRESSURE = "sensor_msgs/msg/FluidPressure"
#: message type → path of the body velocity (DVL)
TWISTS = {
    "geometry_msgs/msg/TwistStamped": "twist.linear",
    "geometry_msgs/msg/TwistWithCovarianceStamped": "twist.twist.linear",
    "nav_msgs/msg/Odometry": "twist.twist.linear",
}
#: message type → path of the position whose z is the depth (ENU: z up)
POSES = {
    "geometry_msgs/msg/PoseStamped": "pose.position",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "pose.pose.position",
    "nav_msgs/msg/Odometry": "pose.pose.position",
}
SCALARS = ("std_msgs/msg/Float64", "std_msgs/msg/Float32")
ARRAYS = ("std_msgs/msg/Float64MultiArray", "std_msgs/msg/Float32MultiArray")
RCOUT = "mavros_msgs/msg/RCOut"


def read_bag_channels(
    path: str | os.PathLike[str], *, topics: dict[str, str | None], frame: str = "enu"
) -> LogChannels:
    """Everything a run file needs from a ROS bag, by topic.

    Parameters
    ----------
    path : path — the bag
    topics : ``imu`` (sensor_msgs/Imu: orientation → phi, theta, psi; angular_velocity → p, q, r),
        ``pressure`` (sensor_msgs/FluidPressure, Pa), ``depth`` (a pose or odometry: depth = −z in
        ENU, z in NED; Float64/Float32 ``data``: depth in m, positive down), ``dvl`` (TwistStamped,
        TwistWithCovarianceStamped or Odometry twist: body velocity, m/s), ``command`` (thruster
        commands: Float64MultiArray/Float32MultiArray, element k → output k+1, already in the
        thrusters' command unit; mavros_msgs/RCOut ``channels`` in µs; or a pattern with ``{name}``
        naming one Float64 topic per thruster). ``imu`` and ``pressure`` default to the bag's only
        topic of their type.
    frame : ``"enu"`` — ROS REP 103 (world ENU, body FLU), converted to NED/FRD:
        φ_NED = φ, θ_NED = −θ, ψ_NED = π/2 − ψ_ENU, (p, q, r) = (ω_x, −ω_y, −ω_z), (u, v, w) = (v_x, −v_y, −v_z);
        ``"ned"`` — the bag is NED/FRD already

    Returns
    -------
    hydrokit.io.channels.LogChannels — time from ``header.stamp`` where set, else the record time, s
    """

    if frame not in ("enu", "ned"):
        raise InputError(f"--ros-frame {frame!r}: expected enu or ned")
    p = Path(path)
    src = str(p)
    reader = _open_bag(p)
    enu = frame == "enu"
    notes: list[str] = [f"frames: {'ENU/FLU (REP 103) converted to NED/FRD' if enu else 'NED/FRD as recorded'}"]
    motion: dict[str, Stream] = {}
    outputs: dict[Any, Stream] = {}
    pressure: Stream | None = None
    unit = "command"
    out_src = ""
    try:
        types = {c.topic: c.msgtype for c in reader.connections}
        listing = ", ".join(f"{t} ({m.split('/')[-1]})" for t, m in sorted(types.items())) or "none"

        def pick(key: str, msgtype: str) -> str | None:
            topic = topics.get(key)
            if topic is None:
                found = [t for t, m in types.items() if m == msgtype]
                return found[0] if len(found) == 1 else None
            if topic not in types:
                raise InputError(f"--{key}-topic {topic!r} is not in the bag (topics: {listing})", src)
            return topic

        def read(topic: str, allowed: tuple[str, ...], key: str) -> tuple[np.ndarray, list[Any]]:
            mt = types[topic]
            if mt not in allowed:
                raise InputError(f"--{key}-topic {topic}: a {mt}, expected {' or '.join(allowed)}", src)
            conns = [c for c in reader.connections if c.topic == topic]
            ts: list[float] = []
            msgs: list[Any] = []
            with quiet("rosbags"):
                for conn, stamp_ns, rawdata in reader.messages(connections=conns):
                    try:
                        msg = reader.deserialize(rawdata, conn.msgtype)
                    except Exception as exc:  # a type the bag does not define
                        raise InputError(f"{topic}: cannot decode {mt}: {' '.join(str(exc).split())}", src) from None
                    st = _stamp(msg)
                    ts.append(st if st else stamp_ns * 1e-9)
                    msgs.append(msg)
            if not msgs:
                raise InputError(f"topic {topic!r} has no messages", src)
            return np.asarray(ts), msgs

        imu = pick("imu", IMU)
        if imu is None:
            raise InputError(f"no attitude: give --imu-topic (a sensor_msgs/Imu topic; topics: {listing})", src)
        t, ms = read(imu, (IMU,), "imu")
        q = np.asarray([(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z) for m in ms], float)
        norm = np.linalg.norm(q, axis=1)
        if np.any(~np.isfinite(norm)) or np.any(np.abs(norm - 1) > 0.05):
            raise InputError(f"{imu}: orientation is not a unit quaternion (|q| = {np.nanmin(norm):.3g}…)", src)
        phi, theta, psi = euler_zyx(*(q / norm[:, None]).T)
        w = np.asarray([(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z) for m in ms], float)
        if enu:
            theta, psi, w = -theta, np.pi / 2 - psi, w * np.array([1.0, -1.0, -1.0])
        psi = np.angle(np.exp(1j * psi))
        for name, y in (("phi", phi), ("theta", theta), ("psi", psi), ("p", w[:, 0]), ("q", w[:, 1]), ("r", w[:, 2])):
            motion[name] = clean_stream(t, y, f"{imu} {name}")
        notes.append(f"phi, theta, psi: Euler angles (ZYX) of {imu} orientation; p, q, r: its angular_velocity")
        # an explicit depth topic replaces the pressure (unless a pressure topic is named too)
        prs = pick("pressure", PRESSURE) if topics.get("pressure") or not topics.get("depth") else None
        if prs is not None:
            t, ms = read(prs, (PRESSURE,), "pressure")
            pressure = clean_stream(t, [m.fluid_pressure for m in ms], f"{prs} fluid_pressure")
            notes.append(f"depth sensor: {prs} fluid_pressure, Pa")
        if topics.get("depth"):
            dep = str(pick("depth", ""))
            t, ms = read(dep, (*POSES, *SCALARS), "depth")
            mt = types[dep]
            if mt in SCALARS:
                z = [float(m.data) for m in ms]
                notes.append(f"z: {dep} data, depth in m (positive down)")
            else:
                z = [float(field_value(m, POSES[mt], src).z) * (-1.0 if enu else 1.0) for m in ms]
                notes.append(f"z: {dep} position z ({'−z: ENU up' if enu else 'NED down'})")
            motion["z"] = clean_stream(t, z, f"{dep} z")
        if topics.get("dvl"):
            dvl = str(pick("dvl", ""))
            t, ms = read(dvl, tuple(TWISTS), "dvl")
            v = np.asarray([(lambda a: (a.x, a.y, a.z))(field_value(m, TWISTS[types[dvl]], src)) for m in ms], float)
            if enu:
                v = v * np.array([1.0, -1.0, -1.0])
            for i, name in enumerate(("u", "v", "w")):
                motion[name] = clean_stream(t, v[:, i], f"{dvl} {name}")
            notes.append(f"u, v, w: {dvl} body velocity (DVL)")
        cmd = topics.get("command")
        if not cmd:
            raise InputError(f"give --command-topic (the thruster commands; topics: {listing})", src)
        if "{name}" in cmd:
            per = {t: m for t, m in types.items() if m in SCALARS}
            out_src = cmd
            for t_name in sorted(per):
                # a per-thruster topic: the part of the name the pattern leaves is the thruster
                head, _, tail = cmd.partition("{name}")
                if t_name.startswith(head) and t_name.endswith(tail) and len(t_name) > len(head) + len(tail):
                    th = t_name[len(head) : len(t_name) - len(tail)]
                    t, ms = read(t_name, SCALARS, "command")
                    outputs[th] = clean_stream(t, [float(m.data) for m in ms], f"{t_name} data")
            if not outputs:
                raise InputError(f"--command-topic {cmd!r}: no Float64/Float32 topic matches (topics: {listing})", src)
        else:
            if cmd not in types:
                raise InputError(f"--command-topic {cmd!r} is not in the bag (topics: {listing})", src)
            t, ms = read(cmd, (*ARRAYS, RCOUT), "command")
            arr = [list(m.channels if types[cmd] == RCOUT else m.data) for m in ms]
            unit = "pwm" if types[cmd] == RCOUT else "command"
            width = min(len(a) for a in arr)
            for k in range(width):
                outputs[k + 1] = clean_stream(t, [float(a[k]) for a in arr], f"{cmd}[{k}]")
            out_src = cmd
    finally:
        reader.close()
    notes.append("time: header.stamp where set, else the record time (s, the bag's clock)")
    return LogChannels(src, motion, pressure, outputs, unit, {}, tuple(notes), (), -1, out_src)  # type: ignore[arg-type]
