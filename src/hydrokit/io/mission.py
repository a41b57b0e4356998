"""Mission files: vehicle, controllers and gains, waypoints, current, duration.

A mission file (YAML, units in the file: m, s, m/s, N, N·m, degrees where a key ends in
``_deg``)::

    name: lingyun-path
    vehicle: lingyun              # bundled vehicle name, or a path relative to this file
    duration: 400                 # s
    dt: 0.05                      # s, integration and control step
    output_every: 4               # keep every 4th step in the trajectory (default 1)
    controller: pid               # which gain set below to use: pid or s-plane
    controllers:
      pid:                        # P = -kp e - ki ∫e - kd ė ; limit = |output| cap (N, N·m)
        speed:   {kp: 400, ki: 20, kd: 0, limit: 150}
        depth:   {kp: 300, ki: 10, kd: 600, limit: 150}
        heading: {kp: 200, ki: 2,  kd: 300, limit: 60}
        roll:    {kp: 100, kd: 50, limit: 30}       # optional hold loops
        pitch:   {kp: 10, kd: 10, limit: 5}
        depth_pitch: {gain: 0.3, max_pitch_deg: 20}  # optional: depth through pitch (stern planes)
      s-plane:                    # P = -scale (2/(1+exp(-k1 e - k2 ė)) - 1)
        speed:   {k1: 8, k2: 0, scale: 150}
        depth:   {k1: 2, k2: 4, scale: 150}
        heading: {k1: 3, k2: 5, scale: 60}
    guidance:
      acceptance_radius: 1.0      # m
      lookahead: 4.0              # m
      speed: 0.5                  # m/s, default leg speed
      waypoints:                  # NED, m; first = start of the path
        - [0, 0, 2]
        - {x: 20, y: 0, z: 4, speed: 0.6}   # speed on the leg ending here, m/s
        - {x: 20, y: 20, z: 4, time: 120}   # or planned arrival times (all or none), s
    initial:                      # optional
      position: [0, 0, 2]         # m (default: first waypoint)
      attitude_deg: [0, 0, 0]     # roll, pitch, yaw in degrees (default: first leg course)
      velocity: [0, 0, 0, 0, 0, 0]  # m/s, rad/s (body axes)
    current: [0.1, 0, 0]          # m/s, NED, constant (default none)
    allocation: {weights: [1, 1, 1, 1]}   # optional pseudo-inverse weights

Every problem is reported as one :class:`InputError` line naming the file and field.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.validate import cut, cut_repr
from hydrokit.core.validate import mapping as _mapping
from hydrokit.core.validate import number as _num
from hydrokit.core.validate import vector as _vector
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import check_keys, read_yaml
from hydrokit.model.guidance import Path as WaypointPath
from hydrokit.model.mission import CONTROLLER_KINDS, LOOPS, Mission

MISSIONS_DIR = Path(__file__).resolve().parents[1] / "data" / "missions"
TOP_KEYS = {
    "name",
    "vehicle",
    "duration",
    "dt",
    "output_every",
    "controller",
    "controllers",
    "guidance",
    "initial",
    "current",
    "allocation",
    "description",
}
GAIN_KEYS = {"pid": {"kp", "ki", "kd", "limit"}, "s-plane": {"k1", "k2", "scale"}}


def resolve_mission(name_or_path: str | os.PathLike[str]) -> Path:
    """A mission file path from a path or a bundled mission name (e.g. ``lingyun_path``)."""
    p = Path(name_or_path)
    if p.is_file():
        return p
    bundled = MISSIONS_DIR / f"{name_or_path}.yaml"
    if "/" not in str(name_or_path) and bundled.is_file():
        return bundled
    names = sorted(q.stem for q in MISSIONS_DIR.glob("*.yaml"))
    raise InputError(
        f"no such file or bundled mission '{cut(str(name_or_path))}' (bundled: {', '.join(names) or 'none'})"
    )


def load_mission(name_or_path: str | os.PathLike[str]) -> Mission:
    """Read and validate a mission file (path or bundled name)."""
    path = resolve_mission(name_or_path)
    return parse_mission(read_yaml(path), source=str(path), base_dir=path.parent)


def parse_mission(data: dict[str, Any], source: str, base_dir: Path | None = None) -> Mission:
    """Validate a mission document; see the module docstring for the format."""
    check_keys(data, TOP_KEYS, "", source)
    for key in ("vehicle", "duration", "guidance", "controllers"):
        if key not in data:
            raise InputError(f"missing field '{key}'", source)
    vehicle = data["vehicle"]
    if not isinstance(vehicle, str) or not vehicle.strip():
        raise InputError(f"field 'vehicle' = {cut_repr(vehicle)}: expected a vehicle name or path", source)
    if base_dir is not None and ("/" in vehicle or vehicle.endswith((".yaml", ".yml"))):
        candidate = base_dir / vehicle
        vehicle = str(candidate) if candidate.is_file() else vehicle
    duration = _num(data["duration"], "duration", source, positive=True)
    dt = _num(data.get("dt", 0.05), "dt", source, positive=True)
    if dt > duration:
        raise InputError(f"field 'dt' = {dt:g}: expected a step no longer than duration ({duration:g} s)", source)
    every = data.get("output_every", 1)
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise InputError(f"field 'output_every' = {cut_repr(every)}: expected a whole number ≥ 1", source)
    steps = duration / dt  # a float: a huge duration is left to the step count's own overflow check
    if math.isfinite(steps) and every > math.floor(steps + 1e-9):
        raise InputError(
            f"field 'output_every' = {cut_repr(every)}: expected a whole number from 1 to "
            f"{math.floor(steps + 1e-9)} (the step count, duration / dt)",
            source,
        )
    kind = data.get("controller", "pid")
    if kind not in CONTROLLER_KINDS:
        raise InputError(
            f"field 'controller' = {cut_repr(kind)}: expected one of {', '.join(CONTROLLER_KINDS)}", source
        )
    gains = _parse_gains(data["controllers"], source)
    if kind not in gains:
        raise InputError(f"field 'controllers': no gains for the chosen controller '{kind}'", source)
    path = _parse_guidance(data["guidance"], source)

    init = _mapping(data.get("initial", {}) or {}, "initial", source)
    check_keys(init, ("position", "attitude_deg", "velocity"), "initial", source)
    pos = _vector(init["position"], 3, "initial.position", source) if "position" in init else path.points[0].copy()
    if "attitude_deg" in init:
        att = np.radians(_vector(init["attitude_deg"], 3, "initial.attitude_deg", source))
    else:
        att = np.array([0.0, 0.0, path.initial_state().heading])  # along the first leg (0 if vertical)
    nu0 = _vector(init["velocity"], 6, "initial.velocity", source) if "velocity" in init else np.zeros(6)
    current = _vector(data["current"], 3, "current", source) if data.get("current") is not None else np.zeros(3)
    weights = None
    if data.get("allocation") is not None:
        alloc = _mapping(data["allocation"], "allocation", source)
        check_keys(alloc, ("weights",), "allocation", source)
        w = alloc.get("weights")
        if w is not None:
            if not isinstance(w, list) or not w:
                raise InputError(
                    f"field 'allocation.weights' = {cut_repr(w)}: expected a list of positive numbers", source
                )
            weights = tuple(_num(x, f"allocation.weights[{i}]", source, positive=True) for i, x in enumerate(w))
    name = data.get("name", Path(source).stem)
    return Mission(
        name=str(name),
        source=source,
        vehicle=vehicle,
        duration=duration,
        dt=dt,
        output_every=int(every),
        controller=kind,
        gains=gains,
        path=path,
        eta0=np.concatenate([pos, att]),
        nu0=nu0,
        current=current,
        weights=weights,
    )


def _parse_gains(value: Any, source: str) -> dict[str, dict[str, dict[str, float]]]:
    ctrls = _mapping(value, "controllers", source)
    out: dict[str, dict[str, dict[str, float]]] = {}
    for kind, loops in ctrls.items():
        if kind not in CONTROLLER_KINDS:
            raise InputError(
                f"field 'controllers.{cut(str(kind))}': unknown controller (expected pid or s-plane)", source
            )
        loops = _mapping(loops, f"controllers.{kind}", source)
        parsed: dict[str, dict[str, float]] = {}
        for loop, g in loops.items():
            where = f"controllers.{kind}.{loop}"
            if loop == "depth_pitch":
                parsed[loop] = _depth_pitch(g, where, source)
                continue
            if loop not in LOOPS:
                raise InputError(f"field '{cut(where)}': unknown loop (expected {', '.join(LOOPS)})", source)
            g = _mapping(g, where, source)
            bad = sorted(set(g) - GAIN_KEYS[kind])
            if bad:
                raise InputError(
                    f"field '{where}.{cut(str(bad[0]))}': unknown gain (expected {', '.join(sorted(GAIN_KEYS[kind]))})",
                    source,
                )
            nums = {k: _num(v, f"{where}.{k}", source, nonneg=True) for k, v in g.items()}
            if kind == "pid" and "limit" in nums and nums["limit"] <= 0:
                raise InputError(
                    f"field '{where}.limit' = {nums['limit']:g}: expected a positive force or moment", source
                )
            if kind == "s-plane":
                for req in ("k1", "scale"):
                    if req not in nums:
                        raise InputError(f"field '{where}': missing '{req}'", source)
                if nums["scale"] <= 0:
                    raise InputError(
                        f"field '{where}.scale' = {nums['scale']:g}: expected a positive force or moment", source
                    )
            parsed[loop] = nums
        for req in ("speed", "depth", "heading"):
            if req not in parsed:
                raise InputError(f"field 'controllers.{kind}': missing the '{req}' loop", source)
        if "depth_pitch" in parsed and "pitch" not in parsed:
            raise InputError(
                f"field 'controllers.{kind}.depth_pitch': depth through pitch needs a 'pitch' loop; expected its gains",
                source,
            )
        out[kind] = parsed
    return out


def _depth_pitch(value: Any, where: str, source: str) -> dict[str, float]:
    """``depth_pitch: {gain: rad/m, max_pitch_deg: deg}`` → gain (rad/m), max_pitch (rad)."""
    g = _mapping(value, where, source)
    check_keys(g, ("gain", "max_pitch_deg"), where, source)
    for key in ("gain", "max_pitch_deg"):
        if key not in g:
            raise InputError(f"field '{where}': missing '{key}'", source)
    gain = _num(g["gain"], f"{where}.gain", source, positive=True)
    deg = _num(g["max_pitch_deg"], f"{where}.max_pitch_deg", source, positive=True)
    if deg >= 90:
        raise InputError(f"field '{where}.max_pitch_deg' = {deg:g}: expected an angle below 90 degrees", source)
    return {"gain": gain, "max_pitch": math.radians(deg)}


def _parse_guidance(value: Any, source: str) -> WaypointPath:
    g = _mapping(value, "guidance", source)
    check_keys(g, ("acceptance_radius", "lookahead", "speed", "waypoints"), "guidance", source)
    radius = _num(
        g.get("acceptance_radius", WaypointPath.acceptance_radius), "guidance.acceptance_radius", source, positive=True
    )
    lookahead = _num(g.get("lookahead", WaypointPath.lookahead), "guidance.lookahead", source, positive=True)
    default_speed = _num(g.get("speed", 0.5), "guidance.speed", source, nonneg=True)
    wps = g.get("waypoints")
    if not isinstance(wps, list) or len(wps) < 2:
        n = len(wps) if isinstance(wps, list) else 0
        raise InputError(
            f"field 'guidance.waypoints': {n} given; expected a list of at least 2 waypoints (x, y, z in m)", source
        )
    points: list[np.ndarray] = []
    speeds: list[float | None] = []
    times: list[float | None] = []
    for i, wp in enumerate(wps):
        where = f"guidance.waypoints[{i}]"
        if isinstance(wp, list):
            points.append(_vector(wp, 3, where, source))
            speeds.append(None)
            times.append(None)
            continue
        wp = _mapping(wp, where, source)
        check_keys(wp, ("x", "y", "z", "speed", "time"), where, source)
        for k in ("x", "y", "z"):
            if k not in wp:
                raise InputError(f"field '{where}': missing '{k}' (m)", source)
        points.append(np.array([_num(wp[k], f"{where}.{k}", source) for k in ("x", "y", "z")]))
        speeds.append(_num(wp["speed"], f"{where}.speed", source, nonneg=True) if "speed" in wp else None)
        times.append(_num(wp["time"], f"{where}.time", source, nonneg=True) if "time" in wp else None)
    P = np.array(points)
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    for i, L in enumerate(seg):
        if L == 0:
            raise InputError(
                f"field 'guidance.waypoints[{i + 1}]' repeats waypoint {i} (zero-length leg); expected distinct consecutive points",
                source,
            )
    given = [t is not None for t in times]
    if any(given) and not all(given):
        raise InputError(
            "field 'guidance.waypoints': 'time' given for some waypoints only; give it for all or none", source
        )
    if all(given):
        for i in range(1, len(times)):
            if times[i] <= times[i - 1]:  # type: ignore[operator]
                raise InputError(
                    f"field 'guidance.waypoints[{i}].time' = {times[i]:g}: waypoints out of order; "
                    f"expected a time after {times[i - 1]:g} s",
                    source,
                )
        leg_speeds = [seg[i] / (times[i + 1] - times[i]) for i in range(len(seg))]  # type: ignore[operator]
    else:
        leg_speeds = [default_speed if s is None else s for s in speeds[1:]]
    return WaypointPath(points=P, speeds=np.array(leg_speeds), acceptance_radius=radius, lookahead=lookahead)
