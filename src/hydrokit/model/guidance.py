"""Waypoint guidance in 3-D: line-of-sight heading, depth reference and speed profile.

The path is a polyline through waypoints p_0 … p_N (NED, m). The vehicle starts on leg 1
(p_0 → p_1). On leg k from a = p_{k−1} to b = p_k:

- heading: lookahead-based line of sight (Fossen 2011 §10.3.2, eq. 10.73),
  ψ_d = α_k + atan(−e / Δ), with α_k the leg's course in the horizontal plane, e the
  horizontal cross-track error (positive to starboard of the leg) and Δ the lookahead
  distance; a vertical leg keeps the last heading;
- depth: the leg's depth (linear between a_z and b_z) at the along-track position plus
  Δ·|b_z − a_z|/L, i.e. the lookahead scaled by the leg's vertical share (full on a
  vertical leg, which would otherwise never progress; small on a gentle slope, so the
  reference does not lead the ramp);
- speed: the leg's speed times the horizontal share of the leg (0 on a vertical leg), and,
  when the vehicle's heading is given, times max(0, cos(ψ_d − ψ)) (slow down in turns);
- switching: to leg k+1 when |p − b| ≤ R (acceptance radius) or the along-track position
  has passed b. After the last waypoint the reference holds it with zero speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit.errors import InputError
from hydrokit.model.control import Reference

Array = NDArray[np.float64]

#: Legs shorter than this horizontally count as vertical (heading is not defined there), m.
_HORIZONTAL_EPS = 1e-6


@dataclass(frozen=True)
class Path:
    """A waypoint path with a speed per leg.

    Parameters
    ----------
    points : (N+1, 3) array — waypoints x, y, z in NED, m (N ≥ 1 legs)
    speeds : (N,) array — surge speed on each leg (leg k ends at points[k]), m/s
    acceptance_radius : float — switch when this close to the leg's end, m
    lookahead : float — LOS lookahead distance Δ, m
    """

    points: Array
    speeds: Array
    acceptance_radius: float = 1.0
    lookahead: float = 5.0

    def __post_init__(self) -> None:
        p = np.asarray(self.points, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 2:
            raise InputError(
                f"waypoints: expected at least 2 points of 3 coordinates (x, y, z in m), got shape {p.shape}"
            )
        if not np.all(np.isfinite(p)):
            raise InputError("waypoints: coordinates must be finite numbers")
        seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
        if np.any(seg <= 0):
            k = int(np.argmax(seg <= 0)) + 1
            raise InputError(
                f"waypoints: waypoint {k} repeats waypoint {k - 1} (zero-length leg); "
                "expected distinct consecutive points"
            )
        s = np.asarray(self.speeds, dtype=float).reshape(-1)
        if s.shape != (p.shape[0] - 1,) or not np.all(np.isfinite(s)) or np.any(s < 0):
            raise InputError(f"waypoints: expected {p.shape[0] - 1} leg speeds ≥ 0 m/s, got {s.tolist()}")
        R, L = float(self.acceptance_radius), float(self.lookahead)
        if not (math.isfinite(R) and R > 0):
            raise InputError(f"acceptance_radius = {R}: expected a positive distance in m")
        if not (math.isfinite(L) and L > 0):
            raise InputError(f"lookahead = {L}: expected a positive distance in m")
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "speeds", s)
        object.__setattr__(self, "acceptance_radius", R)
        object.__setattr__(self, "lookahead", L)
        # Per-leg constants of the law (not fields: no effect on == or repr): one row per leg
        # (row 0 unused, legs are 1-based), see los_guidance.
        rows: list[tuple[float, ...]] = [(0.0,) * LEG_COLUMNS]
        for k in range(1, p.shape[0]):
            a, b = p[k - 1], p[k]
            d = b - a
            Ld = float(np.linalg.norm(d))
            horizontal = math.hypot(d[0], d[1]) >= _HORIZONTAL_EPS
            course = math.atan2(d[1], d[0]) if horizontal else 0.0
            rows.append(
                (
                    *a.tolist(),
                    *d.tolist(),
                    *b.tolist(),
                    float(d @ d),
                    Ld,
                    Ld * Ld,
                    course,
                    float(horizontal),
                    float(s[k - 1]),
                )
            )
        # a tuple of tuples for the Python call (fast indexing), the same numbers as an array
        # for the compiled loops
        object.__setattr__(self, "_leg_rows", tuple(rows))
        object.__setattr__(self, "leg_table", np.array(rows, dtype=float))

    @property
    def n_legs(self) -> int:
        """Number of legs."""
        return int(self.points.shape[0] - 1)

    def initial_state(self, heading: float = 0.0) -> GuidanceState:
        """Start on leg 1; ``heading`` (rad) is used until a horizontal leg defines one."""
        return GuidanceState(leg=1, heading=self._leg_course(1, heading))

    def _leg_course(self, k: int, fallback: float) -> float:
        d = self.points[k] - self.points[k - 1]
        if math.hypot(d[0], d[1]) < _HORIZONTAL_EPS:
            return fallback
        return math.atan2(d[1], d[0])

    def update(
        self, state: GuidanceState, position: ArrayLike, vehicle_heading: float | None = None
    ) -> tuple[Reference, GuidanceState]:
        """Reference for the vehicle at ``position`` (NED x, y, z in m; the whole pose η may be
        given, its first three entries are used), and the new guidance state.

        The returned state's ``leg`` advances past every waypoint reached at this position.
        With the vehicle's heading ψ (``vehicle_heading``, rad) given, the speed set-point is scaled by
        max(0, cos(ψ_d − ψ)): no forward push while the vehicle still points the wrong way,
        which keeps a saturated speed loop from starving the heading loop in turns.
        """
        px, py, pz = np.asarray(position, dtype=float)[:3].tolist()
        slow = vehicle_heading is not None
        k, heading, speed, depth, command = los_guidance(
            px,
            py,
            pz,
            float(vehicle_heading) if slow else 0.0,  # type: ignore[arg-type]
            slow,
            state.leg,
            state.heading,
            self._leg_rows,  # type: ignore[attr-defined]
            self.n_legs,
            self.acceptance_radius,
            self.lookahead,
        )
        return Reference(speed=speed, depth=depth, heading=command), GuidanceState(k, heading)


#: columns of a leg row of :attr:`Path.leg_table` (and of the table :func:`los_guidance` reads):
#: a (3, m), d = b − a (3, m), b (3, m), |d|² (m²), |d| (m), |d|·|d| (m²), the course atan2(d_y, d_x)
#: (rad, 0 on a vertical leg), horizontal (1.0 or 0.0), the leg's speed (m/s)
LEG_COLUMNS = 15


def los_guidance(px, py, pz, psi, slow_in_turns, leg, heading, legs, n_legs, acceptance_radius, lookahead):  # noqa: ANN001, ANN201
    """One step of the waypoint guidance of :meth:`Path.update` (the module's Notes) on plain floats.

    Parameters
    ----------
    px, py, pz : float — vehicle position, NED, m
    psi : float — vehicle heading ψ, rad (used only with ``slow_in_turns``)
    slow_in_turns : bool — scale the speed by max(0, cos(ψ_d − ψ))
    leg : int — active leg (1-based) before this step
    heading : float — course of the last horizontal leg, rad
    legs : (N+1, LEG_COLUMNS) table — per-leg constants, row k for leg k (:attr:`Path.leg_table`;
        any object indexed as ``legs[k][c]``)
    n_legs : int — number of legs N
    acceptance_radius : float — switching radius R, m
    lookahead : float — LOS lookahead Δ, m

    Returns
    -------
    (leg, heading, speed m/s, depth m, heading set-point rad) — the new leg (> N when finished)
    and course memory, and the references.

    Notes
    -----
    ψ_d = α_k + atan(−e/Δ), Fossen 2011 eq. 10.73. Written once: :meth:`Path.update` calls it as
    Python, the compiled closed loop compiles it (``compile_law``).
    """
    k = leg
    pa_d = 0.0
    while k <= n_legs:
        row = legs[k]
        pa_d = (px - row[0]) * row[3] + (py - row[1]) * row[4] + (pz - row[2]) * row[5]
        s = pa_d / row[9]  # along-track fraction
        b0, b1, b2 = px - row[6], py - row[7], pz - row[8]
        if math.sqrt(b0 * b0 + b1 * b1 + b2 * b2) <= acceptance_radius or s >= 1.0:
            k += 1
            if k <= n_legs and legs[k][13] != 0.0:
                heading = legs[k][12]
            continue
        break
    if k > n_legs:
        return k, heading, 0.0, legs[n_legs][8], heading
    row = legs[k]
    a0, a1, a2 = row[0], row[1], row[2]
    d0, d1, d2 = row[3], row[4], row[5]
    L, LL = row[10], row[11]
    s = pa_d / LL  # (p − a)·d of the leg the loop stopped on
    horiz = math.hypot(d0, d1)
    # Depth lookahead scaled by the leg's vertical share |dz|/L: a vertical leg needs the
    # full lookahead to make progress, a gently sloping one should not lead its ramp.
    s_ahead = min(max(s + lookahead * abs(d2) / LL, 0.0), 1.0)
    depth = a2 + s_ahead * d2
    command = heading  # a vertical leg keeps the course of the last horizontal one
    if horiz >= _HORIZONTAL_EPS:
        alpha = row[12]
        e = -(px - a0) * math.sin(alpha) + (py - a1) * math.cos(alpha)
        command = alpha + math.atan(-e / lookahead)
    speed = row[14] * horiz / L
    if slow_in_turns:
        speed *= max(0.0, math.cos(command - psi))
    return k, heading, speed, depth, command


@dataclass(frozen=True)
class GuidanceState:
    """Guidance memory: the active leg (1-based; > n_legs when finished) and the course of the
    last horizontal leg (rad), held on vertical legs and after the end."""

    leg: int = 1
    heading: float = 0.0


def point_path_distance(px: float, py: float, pz: float, pts: Any) -> float:  # noqa: ANN401
    """Shortest distance from the position (px, py, pz) (NED, m) to the polyline through the
    waypoints ``pts`` (N+1 rows of [x, y, z], m), m: the law itself, on plain floats (compiled by
    ``compile_law`` for the fleet's metrics; :func:`path_distance` calls it per position).

    Notes
    -----
    For each leg a → b, d = b − a: s = clip((p − a)·d / |d|², 0, 1) and the distance |p − (a + s d)|;
    the smallest over the legs.
    """
    best = math.inf
    for k in range(len(pts) - 1):
        a, b = pts[k], pts[k + 1]
        a0, a1, a2 = a[0], a[1], a[2]
        d0, d1, d2 = b[0] - a0, b[1] - a1, b[2] - a2
        L2 = d0 * d0 + d1 * d1 + d2 * d2
        s = ((px - a0) * d0 + (py - a1) * d1 + (pz - a2) * d2) / L2
        s = min(max(s, 0.0), 1.0)
        e0, e1, e2 = px - (a0 + s * d0), py - (a1 + s * d1), pz - (a2 + s * d2)
        dist = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        if dist < best:
            best = dist
    return best


def path_distance(positions: ArrayLike, points: ArrayLike) -> Array:
    """Shortest distance from each position to the polyline through ``points``, m
    (:func:`point_path_distance` at each position).

    Parameters
    ----------
    positions : (n, 3) array — NED positions, m
    points : (N+1, 3) array — the path's waypoints, m
    """
    P = np.atleast_2d(np.asarray(positions, dtype=float)).tolist()
    W = np.asarray(points, dtype=float).tolist()
    return np.array([point_path_distance(p[0], p[1], p[2], W) for p in P], dtype=float)
