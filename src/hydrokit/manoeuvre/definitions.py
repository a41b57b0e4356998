"""What to fly: the standard manoeuvres as values (SPEC §9.2; IMO MSC.137(76), ITTC 7.5-04-02-01).

A :class:`Manoeuvre` says which manoeuvre and its settings (angles in rad, depth in m), checked
when it is made; :func:`turning_circle`, :func:`zigzag`, :func:`spiral`, :func:`pull_out`,
:func:`depth_change` and :func:`vertical_zigzag` build one, and :func:`from_options` parses the
command line's options (degrees at that edge). :mod:`hydrokit.manoeuvre.run` flies it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from hydrokit.errors import InputError
from hydrokit.manoeuvre import laws as L

KINDS = ("turning_circle", "zigzag", "spiral", "pull_out", "depth_change", "vertical_zigzag")
VERTICAL = ("depth_change", "vertical_zigzag")
#: spiral steps as fractions of the largest deflection (direct) or yaw rate (reverse)
SPIRAL_FRACTIONS = (1.0, 0.75, 0.5, 0.3, 0.15, 0.08, 0.04, 0.0)
#: non-dimensional yaw rates r L / U held by the reverse spiral (times SPIRAL_FRACTIONS)
REVERSE_SPIRAL_RATE = 0.5


@dataclass(frozen=True)
class Manoeuvre:
    """What to fly (build with the functions below; angles in rad, depth in m).

    kind : one of :data:`KINDS`; deflection : A or δ, rad (signed: its sign picks the first
    side; None for a spiral: the surface's limit); check_angle : B, rad (zigzags);
    depth : M, m (depth change, + deeper); mode : "direct" or "reverse" (spiral);
    max_pitch : rad or None — a depth change flown closed loop through the pitch-limited
    depth-to-pitch law (:func:`hydrokit.model.control.depth_to_pitch`, planes within ±A); None:
    the open-loop execute (planes held at A until the depth is reached)
    """

    kind: str
    deflection: float | None = None
    check_angle: float = 0.0
    depth: float = 0.0
    mode: str = "direct"
    max_pitch: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"manoeuvre {self.kind!r}: expected one of {', '.join(KINDS)}")
        d = self.deflection
        if d is not None and not (math.isfinite(d) and d != 0.0):
            raise InputError(f"{self.kind}: deflection {d!r} rad: expected a finite non-zero angle")
        if self.kind in ("zigzag", "vertical_zigzag") and not (0 < self.check_angle < math.pi / 2):
            raise InputError(
                f"{self.kind}: check angle {math.degrees(self.check_angle):.4g}°: expected between 0° and 90°"
            )
        if self.kind == "depth_change" and not (math.isfinite(self.depth) and self.depth != 0):
            raise InputError(f"depth change {self.depth!r} m: expected a finite non-zero depth change")
        p = self.max_pitch
        if p is not None and not (math.isfinite(p) and 0 < p < math.pi / 2):
            raise InputError(f"depth change: pitch limit {math.degrees(p):.4g}°: expected between 0° and 90°")
        if self.mode not in ("direct", "reverse"):
            raise InputError(f"spiral {self.mode!r}: expected direct or reverse")

    def parameters(self) -> dict[str, Any]:
        """The manoeuvre's settings for JSON (degrees, m)."""
        out: dict[str, Any] = {"kind": self.kind}
        if self.deflection is not None:
            out["deflection_deg"] = math.degrees(self.deflection)
        if self.kind in ("zigzag", "vertical_zigzag"):
            out["check_angle_deg"] = math.degrees(self.check_angle)
        if self.kind == "depth_change":
            out["depth_change"] = self.depth
            out["loop"] = "open" if self.max_pitch is None else "closed"
            if self.max_pitch is not None:
                out["max_pitch_deg"] = math.degrees(self.max_pitch)
        if self.kind == "spiral":
            out["mode"] = self.mode
        return out


def turning_circle(deflection: float) -> Manoeuvre:
    """Turning circle at ``deflection`` (rad)."""
    return Manoeuvre("turning_circle", deflection)


def zigzag(deflection: float, check_angle: float) -> Manoeuvre:
    """Zigzag A/B: ``deflection`` A and ``check_angle`` B, rad."""
    return Manoeuvre("zigzag", deflection, check_angle=check_angle)


def spiral(mode: str = "direct", deflection: float | None = None) -> Manoeuvre:
    """Spiral, ``mode`` "direct" or "reverse", up to ``deflection`` (rad; None: the limit)."""
    return Manoeuvre("spiral", deflection, mode=mode)


def pull_out(deflection: float) -> Manoeuvre:
    """Pull-out from steady turns at ±``deflection`` (rad)."""
    return Manoeuvre("pull_out", deflection)


def depth_change(depth: float, deflection: float, max_pitch: float | None = None) -> Manoeuvre:
    """Depth change by ``depth`` (m, + deeper): closed loop through the depth-to-pitch law with
    the pitch within ±``max_pitch`` (rad) and the planes within ±``deflection`` (rad); open loop
    (the planes held at ``deflection`` until the depth is reached) when ``max_pitch`` is None."""
    return Manoeuvre("depth_change", deflection, depth=depth, max_pitch=max_pitch)


def vertical_zigzag(deflection: float, check_angle: float) -> Manoeuvre:
    """Vertical zigzag A/B on the pitch angle: A, B in rad."""
    return Manoeuvre("vertical_zigzag", deflection, check_angle=check_angle)


def from_options(options: dict[str, Any], max_pitch: float | None = None, open_loop: bool | None = None) -> Manoeuvre:
    """The one manoeuvre of the command-line options given (the others None), degrees at this
    edge: ``turning_circle`` / ``pull_out`` a deflection (deg); ``zigzag`` / ``vertical_zigzag``
    "A/B" (deg/deg); ``spiral`` "direct" or "reverse"; ``depth_change`` "M" or "M/A" (m/deg; A 15°),
    closed loop with the pitch limit ``max_pitch`` (deg; None:
    :data:`hydrokit.manoeuvre.laws.HOLD_MAX_PITCH`) unless ``open_loop``; ``max_pitch`` and
    ``open_loop`` are refused with another manoeuvre.
    """
    given = {k: v for k, v in options.items() if v is not None}
    if len(given) != 1:
        names = ", ".join("--" + k.replace("_", "-") for k in options)
        raise InputError(f"{len(given)} manoeuvres given: expected exactly one of {names}")
    kind, v = next(iter(given.items()))
    rad = math.radians
    for name, value in (("--max-pitch", max_pitch), ("--open-loop", open_loop)):
        if value is not None and kind != "depth_change":
            raise InputError(f"{name} with --{kind.replace('_', '-')}: expected it with --depth-change only")
    if open_loop and max_pitch is not None:
        raise InputError("--max-pitch with --open-loop: an open-loop depth change holds its planes; expected one")
    if kind == "turning_circle":
        return turning_circle(rad(float(v)))
    if kind in ("zigzag", "vertical_zigzag"):
        a, b = _pair(v, "--" + kind.replace("_", "-"), "deg/deg")
        return (zigzag if kind == "zigzag" else vertical_zigzag)(rad(a), rad(b))
    if kind == "spiral":
        return spiral(str(v))
    if kind == "pull_out":
        return pull_out(rad(float(v)))
    if kind != "depth_change":
        raise InputError(f"manoeuvre option {kind!r}: expected one of {', '.join(KINDS)}")
    depth, a = _pair(v if "/" in str(v) else f"{v}/15", "--depth-change", "m/deg")
    pitch = None if open_loop else (L.HOLD_MAX_PITCH if max_pitch is None else rad(float(max_pitch)))
    return depth_change(depth, rad(a), pitch)


def _pair(text: Any, option: str, unit: str) -> tuple[float, float]:
    """``A/B`` as two finite floats, or an InputError naming the option."""
    parts = str(text).split("/")
    try:
        a, b = (float(p) for p in parts)
    except ValueError:
        a = b = math.nan
    if len(parts) != 2 or not (math.isfinite(a) and math.isfinite(b)):
        raise InputError(f"{option} {str(text)[:40]!r}: expected A/B, e.g. 20/20 ({unit})")
    return a, b
