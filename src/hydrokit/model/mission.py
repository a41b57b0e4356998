"""A mission as the library holds it: path, gains, initial state, current (SI, radians).

Parsed from a mission file by :func:`hydrokit.io.mission.load_mission`, or built in code with
:meth:`Mission.create` (no file needed). Flown by :func:`hydrokit.simulate.mission.fly_mission`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.model.control import PID, Autopilot, SPlane
from hydrokit.model.guidance import Path as WaypointPath

CONTROLLER_KINDS = ("pid", "s-plane")
LOOPS = ("speed", "depth", "heading", "roll", "pitch")


@dataclass(frozen=True)
class Mission:
    """A parsed mission (SI units, radians).

    Attributes
    ----------
    name : str
    source : str — the mission file
    vehicle : str — vehicle file path or bundled name
    duration : float — s
    dt : float — integration/control step, s
    output_every : int — keep every n-th step
    controller : str — default controller kind ("pid" or "s-plane")
    gains : dict — kind → loop → gains (as in the file, validated numbers)
    path : hydrokit.model.guidance.Path — waypoints, leg speeds, radius, lookahead
    eta0 : (6,) array — initial position (m) and attitude (rad)
    nu0 : (6,) array — initial body velocity, m/s and rad/s
    current : (3,) array — current velocity in NED, m/s
    weights : tuple of float or None — allocation weights, –
    """

    name: str
    source: str
    vehicle: str
    duration: float
    dt: float
    output_every: int
    controller: str
    gains: dict[str, dict[str, dict[str, float]]]
    path: WaypointPath
    eta0: np.ndarray
    nu0: np.ndarray
    current: np.ndarray
    weights: tuple[float, ...] | None = None

    def autopilot(self, kind: str | None = None) -> Autopilot:
        """Build the autopilot for ``kind`` ("pid" or "s-plane"; default: the file's)."""
        kind = kind or self.controller
        if kind not in self.gains:
            have = ", ".join(sorted(self.gains)) or "none"
            raise InputError(
                f"controllers.{kind}: no gains for the '{kind}' controller (file has: {have})",
                self.source,
            )
        loops: dict[str, Any] = {}
        for loop, g in self.gains[kind].items():
            if loop == "depth_pitch":
                loops[loop] = (g["gain"], g["max_pitch"])
                continue
            angle = loop in ("heading", "roll", "pitch")
            if kind == "pid":
                lim = g.get("limit", math.inf)
                loops[loop] = PID(
                    kp=g.get("kp", 0.0),
                    ki=g.get("ki", 0.0),
                    kd=g.get("kd", 0.0),
                    output_min=-lim,
                    output_max=lim,
                    angle=angle,
                )
            else:
                loops[loop] = SPlane(k1=g["k1"], k2=g.get("k2", 0.0), scale=g["scale"], angle=angle)
        return Autopilot(**loops)


def create_mission(
    waypoints: Any,
    gains: dict[str, dict[str, dict[str, float]]],
    *,
    vehicle: str = "",
    speed: float = 0.5,
    duration: float = 300.0,
    dt: float = 0.05,
    controller: str = "pid",
    acceptance_radius: float = 1.0,
    lookahead: float = 5.0,
    current: Any = (0.0, 0.0, 0.0),
    name: str = "mission",
    output_every: int = 1,
) -> Mission:
    """A :class:`Mission` from Python values (no file).

    Parameters
    ----------
    waypoints : (k, 3) array-like — NED waypoints x, y, z, m (k ≥ 2; the first is the start)
    gains : kind ("pid" / "s-plane") → loop ("speed", "depth", "heading", …) → gains, as in a
        mission file (PID: kp, ki, kd, limit in N or N·m per unit error; S-plane: k1, k2, scale)
    vehicle : str — vehicle name or path, recorded only (the vehicle object is passed to fly)
    speed : float — leg speed, m/s (default 0.5)
    duration, dt : float — flight time and integration/control step, s (defaults 300 and 0.05)
    controller : str — default gain set, "pid" or "s-plane"
    acceptance_radius, lookahead : float — m (defaults 1 and 5)
    current : 3 floats — NED current, m/s (default none)
    name : str
    output_every : int — keep every n-th step

    Raises
    ------
    InputError
        Bad waypoints (fewer than 2, repeated), an unknown controller, missing loops.
    """
    pts = np.asarray(waypoints, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < 2 or not np.all(np.isfinite(pts)):
        raise InputError(f"waypoints of shape {pts.shape}: expected at least 2 rows of x, y, z (m)")
    if np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) == 0):
        raise InputError("waypoints: two consecutive waypoints are equal; expected distinct points")
    if controller not in CONTROLLER_KINDS:
        raise InputError(f"controller = {controller!r}: expected one of {', '.join(CONTROLLER_KINDS)}")
    for kind, loops in gains.items():
        if kind not in CONTROLLER_KINDS:
            raise InputError(f"gains: unknown controller {kind!r} (expected pid or s-plane)")
        for req in ("speed", "depth", "heading"):
            if req not in loops:
                raise InputError(f"gains.{kind}: missing the '{req}' loop")
    if controller not in gains:
        raise InputError(f"gains: no gains for the chosen controller '{controller}'")
    path = WaypointPath(
        points=pts,
        speeds=np.full(len(pts) - 1, float(speed)),
        acceptance_radius=float(acceptance_radius),
        lookahead=float(lookahead),
    )
    psi0 = path.initial_state().heading  # facing along the first leg (0 if it is vertical)
    return Mission(
        name=name,
        source="<python>",
        vehicle=str(vehicle),
        duration=float(duration),
        dt=float(dt),
        output_every=int(output_every),
        controller=controller,
        gains={k: {lp: {g: float(v) for g, v in lg.items()} for lp, lg in loops.items()} for k, loops in gains.items()},
        path=path,
        eta0=np.array([*pts[0], 0.0, 0.0, psi0]),
        nu0=np.zeros(6),
        current=np.asarray(current, dtype=float),
        weights=None,
    )
