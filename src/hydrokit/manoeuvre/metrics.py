"""Metrics of the standard manoeuvres, extracted from a sampled record (SPEC §9.2).

Pure functions of arrays (SI, radians): they take the time, the track and the executes of a
run — simulated by :mod:`hydrokit.manoeuvre.run` or logged at sea — and return the numbers
that IMO MSC.137(76) (Standards for ship manoeuvrability, annex §4.2) and ITTC 7.5-04-02-01
(Full scale manoeuvring trials, §2.2) define. Every distance and heading is measured from the
**execute point**: the position and heading at the instant the first order is given.

Definitions (our wording of the two documents):

- **advance** (IMO 4.2.3): distance travelled along the original course, from the execute point
  to where the heading has changed 90°;
- **transfer** (ITTC 2.2.1): distance travelled perpendicular to the original course, at the same
  instant (90°);
- **tactical diameter** (IMO 4.2.4): distance perpendicular to the original course at 180° of
  heading change;
- **steady turning diameter** (ITTC 2.2.1): the diameter of the circle the track settles on
  once speed and yaw rate are steady (here: a least-squares circle through the last 360° of the
  track, which starts no earlier than 180° of heading change);
- **drift angle** (ITTC 2.2.1): the angle between the vehicle's centreline and the tangent to its
  track (β = −atan2(v, u) in the turn's direction; positive when the bow points into the turn);
- **initial turning time** t_a (ITTC 2.2.2): time from the first execute to the heading being
  B off the original course (the second execute of an A/B zigzag);
- **overshoot angles** (IMO 4.2.7–4.2.8): how far the heading goes beyond ±B after the second
  (first overshoot) and third (second overshoot) execute, before the turn is checked;
- **time to check yaw** (ITTC 2.2.2): time from the second execute to the first heading peak;
- **period** (ITTC 2.2.2): the time of one full cycle of the heading; here the time between the
  second and the fourth execute (the heading crossing +B in the same sense twice).

The heading is the yaw angle ψ for the horizontal manoeuvres and the pitch angle θ for the
vertical ones; the sign of a turn is read from the record (the vehicle's own convention for a
positive deflection is not assumed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.manoeuvre.criteria import _limit, imo_criteria  # noqa: F401  (their old home, re-exported)

#: heading change held in a turning circle before the steady part is measured, rad
STEADY_WINDOW = 2.0 * math.pi
#: heading change at which the steady window may start at the earliest, rad (ITTC: past 180°)
STEADY_START = math.pi


@dataclass(frozen=True)
class Crossing:
    """Where a sampled signal first reaches a level: index ``i`` (the first sample at or past it)
    and the linear-interpolation weight ``w`` between samples i − 1 and i."""

    i: int
    w: float

    def at(self, a: np.ndarray) -> Any:
        """The value of ``a`` (first axis: samples) at the crossing, interpolated linearly."""
        if self.i == 0:
            return a[0]
        return a[self.i - 1] + self.w * (a[self.i] - a[self.i - 1])


def first_reach(s: np.ndarray, level: float, start: int = 0) -> Crossing | None:
    """The first upward reach of ``level`` by ``s`` at or after index ``start`` (None: never).

    A sample already at or past ``level`` at ``start`` is a crossing with weight 1.
    """
    s = np.asarray(s, float)
    idx = np.flatnonzero(s[start:] >= level)
    if idx.size == 0:
        return None
    i = start + int(idx[0])
    if i == start or i == 0:
        return Crossing(i, 1.0)
    lo, hi = s[i - 1], s[i]
    return Crossing(i, float((level - lo) / (hi - lo)) if hi != lo else 1.0)


def execute_frame(xy: np.ndarray, heading0: float) -> tuple[np.ndarray, np.ndarray]:
    """(along, across): the track (n, 2) north-east, m, relative to its first row in the axes of
    the original course ``heading0`` (rad): along it and 90° to starboard of it, m."""
    d = np.asarray(xy, float) - np.asarray(xy, float)[0]
    c, s = math.cos(heading0), math.sin(heading0)
    return d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c


def fit_circle(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Least-squares circle (algebraic, Kåsa 1976) through points: centre (x, y) and radius, m.

    Exact for points on a circle; needs at least three points not on one line.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    mx, my = float(np.mean(x)), float(np.mean(y))  # centred for conditioning
    u, v = x - mx, y - my
    A = np.column_stack([u, v, np.ones_like(u)])
    sol, *_ = np.linalg.lstsq(A, u * u + v * v, rcond=None)
    cu, cv = 0.5 * sol[0], 0.5 * sol[1]
    return cu + mx, cv + my, math.sqrt(max(sol[2] + cu * cu + cv * cv, 0.0))


@dataclass(frozen=True)
class TurningCircleMetrics:
    """Turning-circle results (module docstring for the definitions). None: not reached.

    advance, transfer, tactical_diameter, steady_turning_diameter : m
    steady_speed : m/s; steady_yaw_rate : rad/s (signed: + to starboard); drift_angle_deg : deg
    time_to_90_deg, time_to_180_deg, time_to_360_deg : s from the execute
    approach_speed : m/s at the execute; speed_ratio : steady / approach speed
    direction : "starboard" or "port"; heading_change_deg : the largest change reached, deg
    """

    advance: float | None
    transfer: float | None
    tactical_diameter: float | None
    steady_turning_diameter: float | None
    steady_speed: float | None
    steady_yaw_rate: float | None
    drift_angle_deg: float | None
    time_to_90_deg: float | None
    time_to_180_deg: float | None
    time_to_360_deg: float | None
    approach_speed: float
    speed_ratio: float | None
    direction: str
    heading_change_deg: float

    def missing(self) -> str | None:
        """What the record did not reach, as a phrase, or None when every metric is there."""
        if self.time_to_90_deg is None:
            return "90° (advance, transfer)"
        if self.time_to_180_deg is None:
            return "180° (tactical diameter)"
        if self.steady_turning_diameter is None:
            return f"{math.degrees(STEADY_START + STEADY_WINDOW):.0f}° (the steady turn)"
        return None


def turning_circle_metrics(time: np.ndarray, eta: np.ndarray, nu: np.ndarray) -> TurningCircleMetrics:
    """Turning-circle metrics of a record that starts at the execute.

    Parameters
    ----------
    time : (n,) — s, the first sample is the execute
    eta : (n, 6) — x, y, z (m, NED) and φ, θ, ψ (rad)
    nu : (n, 6) — u, v, w (m/s), p, q, r (rad/s), body axes
    """
    time, eta, nu = _checked(time, eta, nu)
    psi = np.unwrap(eta[:, 5])
    dpsi = psi - psi[0]
    k_end = int(np.argmax(np.abs(dpsi)))
    sign = 1.0 if dpsi[k_end] >= 0 else -1.0
    turn = sign * dpsi
    along, across = execute_frame(eta[:, :2], float(psi[0]))
    across = sign * across
    speed = np.hypot(nu[:, 0], nu[:, 1])
    c90, c180, c360 = (first_reach(turn, math.radians(a)) for a in (90.0, 180.0, 360.0))
    steady = _steady_turn(turn, eta, nu, speed)
    approach = float(speed[0])
    return TurningCircleMetrics(
        advance=_at(c90, along),
        transfer=_at(c90, across),
        tactical_diameter=_at(c180, across),
        steady_turning_diameter=None if steady is None else steady[0],
        steady_speed=None if steady is None else steady[1],
        steady_yaw_rate=None if steady is None else steady[2],
        drift_angle_deg=None if steady is None else math.degrees(-sign * steady[3]),
        time_to_90_deg=_at(c90, time),
        time_to_180_deg=_at(c180, time),
        time_to_360_deg=_at(c360, time),
        approach_speed=approach,
        speed_ratio=None if steady is None or approach <= 0 else steady[1] / approach,
        direction="starboard" if sign > 0 else "port",
        heading_change_deg=math.degrees(float(turn[k_end])),
    )


def _steady_turn(
    turn: np.ndarray, eta: np.ndarray, nu: np.ndarray, speed: np.ndarray
) -> tuple[float, float, float, float] | None:
    """(diameter m, speed m/s, yaw rate rad/s, sideslip atan2(v, u) rad) over the last 360°."""
    total = float(np.max(turn))
    if total < STEADY_START + STEADY_WINDOW - 1e-9:
        return None
    k_last = int(np.argmax(turn))
    start = first_reach(turn, total - STEADY_WINDOW)
    if start is None:  # pragma: no cover - the maximum itself reaches it
        return None
    sl = slice(start.i, k_last + 1)
    _, _, radius = fit_circle(eta[sl, 0], eta[sl, 1])
    beta = np.arctan2(nu[sl, 1], nu[sl, 0])
    return 2.0 * radius, float(np.mean(speed[sl])), float(np.mean(nu[sl, 5])), float(np.mean(beta))


@dataclass(frozen=True)
class ZigzagMetrics:
    """Zigzag (horizontal or vertical) results (module docstring). None: not reached.

    first_overshoot_deg, second_overshoot_deg, third_overshoot_deg : deg beyond ±B
    initial_turning_time, time_to_check_yaw, period : s
    execute_times : s of every execute (the first is 0)
    distance_at_second_execute : m travelled along the track to the second execute (IMO 5.3.2)
    check_angle_deg : B, deg; approach_speed : m/s
    """

    first_overshoot_deg: float | None
    second_overshoot_deg: float | None
    third_overshoot_deg: float | None
    initial_turning_time: float | None
    time_to_check_yaw: float | None
    period: float | None
    execute_times: tuple[float, ...]
    distance_at_second_execute: float | None
    check_angle_deg: float
    approach_speed: float

    def missing(self) -> str | None:
        """What the record did not reach, as a phrase, or None when every frozen metric is there."""
        b = f"{self.check_angle_deg:g}°"
        if self.initial_turning_time is None:
            return f"{b} off the original course (the second execute)"
        if self.first_overshoot_deg is None:
            return f"the first overshoot (the heading's peak past {b} after the second execute)"
        if self.second_overshoot_deg is None:
            return f"−{b} (the third execute) and the second overshoot (the heading's peak past −{b} after it)"
        if self.period is None:
            return f"{b} a second time (the fourth execute, the period)"
        return None


def zigzag_metrics(
    time: np.ndarray,
    angle: np.ndarray,
    executes: Any,
    check_angle: float,
    xy: np.ndarray | None = None,
    approach_speed: float = 0.0,
) -> ZigzagMetrics:
    """Zigzag metrics from a record starting at the first execute.

    Parameters
    ----------
    time : (n,) — s, the first sample is the first execute
    angle : (n,) — heading ψ (or pitch θ for a vertical zigzag), rad
    executes : times of the executes, s (the first is the first execute, at time[0])
    check_angle : B, rad (> 0): the heading change at which the deflection is reversed
    xy : (n, 2) or None — track, m (for the distance travelled to the second execute)
    approach_speed : float — m/s, recorded with the metrics
    """
    time = np.asarray(time, float)
    a = np.unwrap(np.asarray(angle, float))
    a = a - a[0]
    ex = [float(t) for t in executes]
    if not (check_angle > 0 and math.isfinite(check_angle)):
        raise InputError(f"check angle {check_angle!r} rad: expected a positive angle")
    # the first change of B in either direction fixes the sense of the first turn
    hit = np.flatnonzero(np.abs(a) >= check_angle)
    sign = 1.0 if hit.size == 0 or a[hit[0]] > 0 else -1.0
    s = sign * a
    t0 = float(time[0])
    ends = ex[1:] + [math.inf]

    def overshoot(k: int) -> float | None:
        # k-th overshoot: extreme after execute k+1 (index k in ex), before execute k+2 or the end
        if len(ex) <= k:
            return None
        lo, hi = ex[k], ends[k]
        m = (time >= lo) & (time <= hi)
        if not np.any(m):
            return None
        side = s[m] if k % 2 == 1 else -s[m]
        j = int(np.argmax(side))
        # a peak at the record's last sample (still turning) is no overshoot yet
        if hi == math.inf and np.flatnonzero(m)[j] == time.size - 1:
            return None
        # nor a peak short of B: a replayed model whose heading never got back past the check
        # angle before the trial's next execute did not overshoot (a negative angle would read
        # as one); the manoeuvre's own logic executes at B, so its peaks always pass it
        if side[j] < check_angle:
            return None
        return math.degrees(float(side[j]) - check_angle)

    def peak_time() -> float | None:
        if len(ex) < 2:
            return None
        m = (time >= ex[1]) & (time <= ends[1])
        j = int(np.argmax(s[m]))
        if ends[1] == math.inf and np.flatnonzero(m)[j] == time.size - 1:
            return None
        return float(time[m][j]) - ex[1]

    dist = None
    if xy is not None and len(ex) >= 2:
        xy = np.asarray(xy, float)
        path = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
        dist = float(np.interp(ex[1], time, path))
    return ZigzagMetrics(
        first_overshoot_deg=overshoot(1),
        second_overshoot_deg=overshoot(2),
        third_overshoot_deg=overshoot(3),
        initial_turning_time=ex[1] - t0 if len(ex) >= 2 else None,
        time_to_check_yaw=peak_time(),
        period=ex[3] - ex[1] if len(ex) >= 4 else None,
        execute_times=tuple(e - t0 for e in ex),
        distance_at_second_execute=dist,
        check_angle_deg=math.degrees(check_angle),
        approach_speed=float(approach_speed),
    )


def settled(values: np.ndarray, tolerance: float) -> bool:
    """True when the spread (max − min) of ``values`` is within ``tolerance`` (same unit)."""
    v = np.asarray(values, float)
    return bool(v.size > 0 and float(np.max(v) - np.min(v)) <= tolerance)


def _at(c: Crossing | None, a: np.ndarray) -> float | None:
    return None if c is None else float(c.at(a))


def _checked(time: Any, eta: Any, nu: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.asarray(time, float)
    e = np.asarray(eta, float)
    n = np.asarray(nu, float)
    if t.ndim != 1 or t.size < 2 or e.shape != (t.size, 6) or n.shape != (t.size, 6):
        raise InputError(
            f"record of shapes time {t.shape}, eta {e.shape}, nu {n.shape}: expected (n,), (n, 6), (n, 6) with n ≥ 2"
        )
    return t, e, n


def spiral_summary(points: list[dict[str, Any]], mode: str, length: float | None = None) -> dict[str, Any]:
    """Spiral table and verdict.

    ``points``: one per step, in the order flown, with ``deflection`` (rad, mean over the steady
    window), ``yaw_rate`` (rad/s), ``speed`` (m/s), ``settled`` and ``target`` (rad or rad/s).
    Direct (Dieudonné): the loop width is the largest |δ| at which the down and up branches turn
    opposite ways (0 for a course-stable vehicle). Reverse (Bech): the vehicle is course-unstable
    when δ(r) is not monotonic (an S-shaped curve).
    """
    rows = [
        {
            "deflection_deg": math.degrees(p["deflection"]),
            "yaw_rate": p["yaw_rate"],
            "yaw_rate_nondimensional": p["yaw_rate"] * length / p["speed"] if length and p["speed"] > 0 else None,
            "speed": p["speed"],
            "settled": bool(p["settled"]),
        }
        for p in points
    ]
    out: dict[str, Any] = {"mode": mode, "points": rows}
    if mode == "direct":
        half = (len(points) + 1) // 2
        down = {round(p["target"], 12): p["yaw_rate"] for p in points[:half]}
        up = {round(p["target"], 12): p["yaw_rate"] for p in points[half - 1 :]}
        tol = 1e-3 * max((abs(p["yaw_rate"]) for p in points), default=0.0)
        loop = [abs(d) for d in down if d in up and down[d] * up[d] < 0 and min(abs(down[d]), abs(up[d])) > tol]
        out["loop_width_deg"] = math.degrees(max(loop)) if loop else 0.0
        out["course_stable"] = not loop if len(points) > 2 else None
    else:
        top = max((abs(p["target"]) for p in points), default=0.0)
        for p, row in zip(points, rows):  # a rate beyond the surface's reach is held at its limit
            row["reached"] = bool(abs(p["yaw_rate"] - p["target"]) <= 0.02 * max(abs(p["target"]), 0.05 * top))
        pts = sorted((p["yaw_rate"], p["deflection"]) for p, r in zip(points, rows) if p["settled"] and r["reached"])
        slopes = [np.sign(b[1] - a[1]) for a, b in zip(pts, pts[1:]) if b[0] - a[0] > 1e-9 and b[1] != a[1]]
        overall = np.sign(pts[-1][1] - pts[0][1]) if len(pts) > 1 else 0.0
        out["course_stable"] = bool(all(s == overall for s in slopes)) if len(pts) > 2 else None
    return out


def pull_out_summary(sides: list[dict[str, Any]]) -> dict[str, Any]:
    """Pull-out (ITTC 2.2.6) per side and verdict.

    ``sides``: one per side, in the order flown, with ``deflection`` (rad), ``yaw_rate_before``
    (the steady turn's rate, rad/s), ``residual_yaw_rate`` (steady after the release, rad/s),
    ``time_to_half`` (s to half the rate, None: never), ``time_to_settle`` (s until the rate stays
    within 5 % of its change from its residual, None: never), ``turn_settled`` and
    ``decay_settled``. ``opposite`` when the two sides turned opposite ways.

    Course-stable (ITTC 7.5-04-02-01 §2.2.6) when the two sides turned opposite ways and came
    back to the same residual rate, within :data:`PULL_OUT_TOLERANCE` of the mean turn rate:
    a stable vehicle with a steady bias (a propeller's torque rolls it, a trim) settles on one
    residual from both sides, ``residual_bias``, their mean. Different residuals mean unstable:
    the released vehicle keeps turning the way it turned, and ``residual_difference`` (+δ side
    minus −δ side) is the height of the spiral's loop in yaw rate.
    """
    rows = [
        {
            "deflection_deg": math.degrees(s["deflection"]),
            "yaw_rate_before": s["yaw_rate_before"],
            "residual_yaw_rate": s["residual_yaw_rate"],
            "time_to_half": s["time_to_half"],
            "time_to_settle": s.get("time_to_settle"),
            "settled": bool(s["turn_settled"] and s["decay_settled"]),
        }
        for s in sides
    ]
    two = len(sides) == 2
    out: dict[str, Any] = {"sides": rows, "residual_yaw_rate": [s["residual_yaw_rate"] for s in sides]}
    if not two:
        return out | {"opposite": None, "course_stable": None, "residual_difference": None, "residual_bias": None}
    (a, b), opposite = sides, bool(sides[0]["yaw_rate_before"] * sides[1]["yaw_rate_before"] < 0)
    difference = float(a["residual_yaw_rate"] - b["residual_yaw_rate"])
    scale = 0.5 * (abs(a["yaw_rate_before"]) + abs(b["yaw_rate_before"]))
    stable = opposite and abs(difference) <= PULL_OUT_TOLERANCE * scale
    return out | {
        "opposite": opposite,
        "course_stable": stable,
        "residual_difference": difference,
        "residual_bias": 0.5 * float(a["residual_yaw_rate"] + b["residual_yaw_rate"]) if stable else None,
    }


#: the pull-out's two residual rates are "the same" within this fraction of the turns' mean rate
PULL_OUT_TOLERANCE = 0.05


def depth_change_metrics(time: np.ndarray, x: np.ndarray, executes: Any, depth: float) -> dict[str, Any]:
    """Depth change by ``depth`` (m, + deeper) from a record starting at the execute: the time to
    reach it and to level off (s), the depth overshoot past it (m) and the largest pitch (deg)."""
    ex = list(executes)
    sense = 1.0 if depth > 0 else -1.0
    dz = sense * (x[:, 2] - x[0, 2])
    theta = x[:, 4] - x[0, 4]
    overshoot = None
    if len(ex) >= 3:
        after = time >= ex[2]
        j = int(np.argmax(dz[after]))
        if np.flatnonzero(after)[j] < time.size - 1:  # a peak inside the record
            overshoot = float(dz[after][j]) - abs(depth)
    return {
        "target_depth_change": depth,
        "time_to_target": ex[1] if len(ex) >= 2 else None,
        "time_to_level": ex[2] if len(ex) >= 3 else None,
        "depth_overshoot": overshoot,
        "max_pitch_deg": math.degrees(float(theta[int(np.argmax(np.abs(theta)))])),
    }


def depth_change_closed_metrics(
    time: np.ndarray, x: np.ndarray, executes: Any, depth: float, max_pitch: float
) -> dict[str, Any]:
    """A closed-loop depth change by ``depth`` (m, + deeper) within the pitch limit
    ``max_pitch`` (rad), from a record starting at the execute (executes: 0, reached, settled):
    the time to reach the depth and to settle (s), the depth overshoot past it (m, 0 without
    one) and the largest pitch change and absolute pitch (deg)."""
    ex = list(executes)
    sense = 1.0 if depth > 0 else -1.0
    dz = sense * (x[:, 2] - x[0, 2])
    theta = x[:, 4] - x[0, 4]
    overshoot = None
    if len(ex) >= 2:
        overshoot = max(float(np.max(dz[time >= ex[1]])) - abs(depth), 0.0)
    return {
        "target_depth_change": depth,
        "time_to_target": ex[1] if len(ex) >= 2 else None,
        "time_to_settle": ex[2] if len(ex) >= 3 else None,
        "depth_overshoot": overshoot,
        "final_depth_change": float(sense * dz[-1]),
        "max_pitch_deg": math.degrees(float(theta[int(np.argmax(np.abs(theta)))])),
        "max_abs_pitch_deg": math.degrees(float(np.max(np.abs(x[:, 4])))),
        "pitch_limit_deg": math.degrees(max_pitch),
    }


#: units of the metrics in manoeuvre.json (the rest are in degrees where named *_deg)
UNITS = {
    "advance": "m",
    "transfer": "m",
    "tactical_diameter": "m",
    "steady_turning_diameter": "m",
    "steady_speed": "m/s",
    "steady_yaw_rate": "rad/s",
    "approach_speed": "m/s",
    "time_to_90_deg": "s",
    "time_to_180_deg": "s",
    "time_to_360_deg": "s",
    "initial_turning_time": "s",
    "time_to_check_yaw": "s",
    "period": "s",
    "execute_times": "s",
    "distance_at_second_execute": "m",
    "yaw_rate": "rad/s",
    "residual_yaw_rate": "rad/s",
    "residual_difference": "rad/s",
    "residual_bias": "rad/s",
    "time_to_half": "s",
    "depth_change": "m",
    "max_depth_change": "m",
    "depth_overshoot": "m",
    "time_to_target": "s",
    "time_to_level": "s",
    "reference_length": "m",
    "target_depth_change": "m",
    "yaw_rate_before": "rad/s",
    "time_to_settle": "s",
    "speed": "m/s",
    "speed_ratio": "–",
    "yaw_rate_nondimensional": "–",
    "max_depth_rise": "m",
    "pitch_limit_deg": "°",
    "max_abs_pitch_deg": "°",
    "max_depth_fall": "m",
    "final_depth_change": "m",
}


def unit_of(key: str) -> str:
    """The unit of a metric ``key`` as printed ("m", "s", "°", "rad/s", "–"; "" for a word or a
    yes/no): :data:`UNITS`, else degrees for a name ending in ``_deg``."""
    if key in UNITS:
        return UNITS[key]
    return "°" if key.endswith("_deg") else ""


def shown(key: str, value: Any) -> str:
    """``value`` of the metric ``key`` with its unit, for a person ("631.2 m", "not reached")."""
    if value is None:
        return "not reached"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        unit = unit_of(key)
        text = f"{value:.4g}"
        return text + ("°" if unit == "°" else f" {unit}" if unit and unit != "–" else "")
    if isinstance(value, (list, tuple)):
        return ", ".join(shown(key, v) for v in value)
    return str(value)


def describe(kind: str, metrics: dict[str, Any]) -> list[str]:
    """The metrics of a ``kind`` manoeuvre as lines ``name: value unit`` (the steps of a spiral and
    the sides of a pull-out one line each), what ``hydrokit manoeuvre`` prints."""
    lines: list[str] = []
    for key, value in metrics.items():
        if key in ("points", "sides"):
            continue
        lines.append(f"{key.replace('_', ' ')}: {shown(key, value)}")
    for p in metrics.get("sides", []):
        parts = [f"{k.replace('_', ' ')} {shown(k, v)}" for k, v in p.items() if k != "deflection_deg"]
        lines.append(f"side {p['deflection_deg']:+.4g}°: " + ", ".join(parts))
    for p in metrics.get("points", []):
        parts = [f"{k.replace('_', ' ')} {shown(k, v)}" for k, v in p.items() if k != "deflection_deg"]
        lines.append(f"step at {p['deflection_deg']:+.4g}°: " + ", ".join(parts))
    return lines
