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
        # Per-leg constants of update() (not fields: no effect on == or repr), computed by
        # the same expressions update() used to evaluate at every call: for leg k (1-based)
        # a, b, d = b − a (arrays), |d|² and |d| (floats), and a, d as plain floats.
        legs = []
        for k in range(1, p.shape[0]):
            a, b = p[k - 1], p[k]
            d = b - a
            Ld = float(np.linalg.norm(d))
            legs.append((a, b, d, float(d @ d), Ld, Ld * Ld, a.tolist(), d.tolist()))
        object.__setattr__(self, "_legs", (None, *legs))

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
        p = np.asarray(position, dtype=float)[:3]
        k, heading = state.leg, state.heading
        n_legs = self.n_legs
        legs = self._legs  # type: ignore[attr-defined]
        while k <= n_legs:
            a, b, d, L2 = legs[k][:4]
            pa_d = float((p - a) @ d)
            s = pa_d / L2  # along-track fraction
            pb = p - b
            if math.sqrt(pb.dot(pb)) <= self.acceptance_radius or s >= 1.0:  # |p − b|, as np.linalg.norm
                k += 1
                if k <= n_legs:
                    heading = self._leg_course(k, heading)
                continue
            break
        if k > n_legs:
            end = self.points[-1]
            ref = Reference(speed=0.0, depth=float(end[2]), heading=heading)
            return ref, GuidanceState(leg=k, heading=heading)
        L, LL, (a0, a1, a2), (d0, d1, d2) = legs[k][4:]
        s = pa_d / LL  # (p − a)·d of the leg the loop stopped on
        horiz = math.hypot(d0, d1)
        # Depth lookahead scaled by the leg's vertical share |dz|/L: a vertical leg needs the
        # full lookahead to make progress, a gently sloping one should not lead its ramp.
        s_ahead = min(max(s + self.lookahead * abs(d2) / LL, 0.0), 1.0)
        depth = a2 + s_ahead * d2
        command = heading  # a vertical leg keeps the course of the last horizontal one
        if horiz >= _HORIZONTAL_EPS:
            p0, p1 = p[:2].tolist()
            alpha = math.atan2(d1, d0)
            e = -(p0 - a0) * math.sin(alpha) + (p1 - a1) * math.cos(alpha)
            command = alpha + math.atan(-e / self.lookahead)
        speed = float(self.speeds[k - 1]) * horiz / L
        if vehicle_heading is not None:
            speed *= max(0.0, math.cos(command - vehicle_heading))
        return Reference(speed=speed, depth=depth, heading=command), GuidanceState(k, heading)


@dataclass(frozen=True)
class GuidanceState:
    """Guidance memory: the active leg (1-based; > n_legs when finished) and the course of the
    last horizontal leg (rad), held on vertical legs and after the end."""

    leg: int = 1
    heading: float = 0.0


def path_distance(positions: ArrayLike, points: ArrayLike) -> Array:
    """Shortest distance from each position to the polyline through ``points``, m.

    Parameters
    ----------
    positions : (n, 3) array — NED positions, m
    points : (N+1, 3) array — the path's waypoints, m
    """
    P = np.atleast_2d(np.asarray(positions, dtype=float))
    W = np.asarray(points, dtype=float)
    a = W[:-1][None, :, :]
    d = (W[1:] - W[:-1])[None, :, :]
    L2 = np.einsum("ijk,ijk->ij", d, d)
    s = np.einsum("ijk,ijk->ij", P[:, None, :] - a, d) / L2
    s = np.clip(s, 0.0, 1.0)
    closest = a + s[..., None] * d
    dist = np.linalg.norm(P[:, None, :] - closest, axis=2)
    return dist.min(axis=1)
