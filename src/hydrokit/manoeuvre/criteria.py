"""The IMO criteria a manoeuvre's metrics are judged by (IMO MSC.137(76), Standards for ship
manoeuvrability, annex §5.3): turning ability, initial turning ability and yaw checking, with the
limits in ship lengths L and in L/V.

They apply to a surface craft's turning circle and 10°/10° or 20°/20° zigzag
(:meth:`hydrokit.manoeuvre.result.ManoeuvreResult.imo`); the metrics they read come from
:mod:`hydrokit.manoeuvre.metrics`.
"""

from __future__ import annotations

from typing import Any


def _limit(lv: float, low: float, high: float, a: float, b: float) -> float:
    """IMO's piecewise limit: ``low`` below L/V 10 s, ``high`` from 30 s, a + b·L/V between."""
    return low if lv < 10.0 else high if lv >= 30.0 else a + b * lv


def imo_criteria(
    kind: str, parameters: dict[str, Any], metrics: dict[str, Any], length: float | None, speed: float
) -> list[dict[str, Any]]:
    """IMO MSC.137(76) §5.3 criteria that a run of ``kind`` can check, as rows
    {criterion, value, limit, unit, passed, note}.

    Turning ability (5.3.1): advance ≤ 4.5 L and tactical diameter ≤ 5 L (the standard asks for
    35° or the largest rudder angle). Initial turning ability (5.3.2, 10°/10° zigzag): the distance
    travelled by the time the heading has changed 10° ≤ 2.5 L. Yaw checking (5.3.3): 10°/10°
    first overshoot ≤ 10° below L/V = 10 s, ≤ 20° from 30 s, 5 + ½ L/V between; second overshoot
    ≤ 25°, 40°, 17.5 + 0.75 L/V; 20°/20° first overshoot ≤ 25° (L in m, V in m/s).
    """
    if not length or speed <= 0:
        return []
    L = float(length)
    lv = L / speed
    rows: list[dict[str, Any]] = []

    def row(name: str, value: Any, limit: float, unit: str, note: str = "") -> None:
        ok = None if value is None else bool(value <= limit)
        rows.append({"criterion": name, "value": value, "limit": limit, "unit": unit, "passed": ok, "note": note})

    if kind == "turning_circle":
        a = abs(parameters.get("deflection_deg", 0.0))
        note = "" if a >= 35.0 - 1e-6 else f"flown at {a:g}°; the standard asks for 35° or the largest angle"
        row("advance ≤ 4.5 L", metrics.get("advance"), 4.5 * L, "m", note)
        row("tactical diameter ≤ 5 L", metrics.get("tactical_diameter"), 5.0 * L, "m", note)
    elif kind == "zigzag":
        a = abs(parameters.get("deflection_deg", 0.0))
        b = parameters.get("check_angle_deg", 0.0)
        if abs(a - 10.0) < 1e-6 and abs(b - 10.0) < 1e-6:
            row("initial turning: distance at 10° ≤ 2.5 L", metrics.get("distance_at_second_execute"), 2.5 * L, "m")
            row(
                "10°/10° first overshoot",
                metrics.get("first_overshoot_deg"),
                _limit(lv, 10, 20, 5, 0.5),
                "deg",
                f"L/V = {lv:.3g} s",
            )
            row(
                "10°/10° second overshoot",
                metrics.get("second_overshoot_deg"),
                _limit(lv, 25, 40, 17.5, 0.75),
                "deg",
                f"L/V = {lv:.3g} s",
            )
        elif abs(a - 20.0) < 1e-6 and abs(b - 20.0) < 1e-6:
            row("20°/20° first overshoot", metrics.get("first_overshoot_deg"), 25.0, "deg")
    return rows
