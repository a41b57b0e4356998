"""The ``thrusters:`` block of a vehicle file.

Each entry (units in the file: m, N, s, rpm, degrees)::

    thrusters:
      - name: T1
        position: [-0.4, -0.2, 0.0]   # m, body axes from the body origin
        direction: [1, 0, 0]          # positive-thrust direction (normalised here)
        max_thrust: 60                # N, largest forward thrust
        min_thrust: -40               # N, largest reverse thrust (default -max_thrust)
        # optional:
        azimuth_deg: 10               # instead of direction: angle from +x towards +y, deg
        elevation_deg: 0              #   and angle below the x-y plane (towards +z), deg
        diameter: 0.22                # m  } propeller model f = loss K_T(J) rho D^4 |n| n
                                      #      (alone: only sizes the disk for power figures)
        kt_forward: [0.5, -0.66, -0.25, 0.24]   # K_T(J), highest power first
        kt_reverse: [0.025, -0.28, 0.17, 0.15]
        thrust_loss: {forward: 0.72, reverse: 0.53}   # or one number
        max_rpm: 1500                 # rpm (propeller model: required)
        advance_ratio_range: [-0.5, 1.0]
        wake_fraction: 0.1            # w: advance speed (1 - w) u at the propeller
        thrust_deduction: 0.2         # t: the thruster pushes the hull with (1 - t) T
        time_constant: 0.2            # s, first-order rotor lag
        thrust_table: {command: [...], thrust: [...]}  # table model, thrust in N
        channel: 1                    # autopilot servo output (SERVOn / RCOU Cn), 1-based
        motor: 1                      # or the ArduSub motor number (MOT_n); both: logs only
        reversed: false               # a positive autopilot command pushes against 'direction'

Conversions (rpm → rev/s, degrees → rad) happen here and nowhere else.
"""

from __future__ import annotations

import math
import os
from typing import Any

from hydrokit.core.constants import SEAWATER_DENSITY
from hydrokit.core.validate import mapping, number, vector
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_yaml
from hydrokit.model.thrusters import DEFAULT_ADVANCE_RATIO_RANGE, Thruster, ThrusterSet

ALLOWED = {
    "name",
    "position",
    "direction",
    "azimuth_deg",
    "elevation_deg",
    "max_thrust",
    "min_thrust",
    "diameter",
    "kt_forward",
    "kt_reverse",
    "thrust_loss",
    "max_rpm",
    "advance_ratio_range",
    "wake_fraction",
    "thrust_deduction",
    "time_constant",
    "thrust_table",
    "channel",
    "motor",
    "reversed",
}


def load_thrusters(name_or_path: str | os.PathLike[str]) -> ThrusterSet:
    """Read the ``thrusters:`` block of a vehicle file (path or bundled name)."""
    from hydrokit.io.vehicle import resolve_vehicle

    path = resolve_vehicle(name_or_path)
    return parse_thrusters(read_yaml(path), source=str(path))


def parse_thrusters(data: dict[str, Any], source: str) -> ThrusterSet:
    """Build a :class:`ThrusterSet` from a parsed vehicle document.

    Parameters
    ----------
    data : mapping — the whole vehicle document (``thrusters`` and ``fluid.density`` used)
    source : str — the file name, for messages

    Raises
    ------
    InputError
        No or an empty ``thrusters`` list, an unknown or bad field, zero-length direction,
        duplicate names. The message names the file, the entry and the field.
    """
    raw = data.get("thrusters")
    if raw is None:
        raise InputError("no 'thrusters' list: allocation needs the thruster layout", source)
    if not isinstance(raw, list) or not raw:
        raise InputError(f"'thrusters' = {raw!r}: expected a non-empty list of thrusters", source)
    density = _density(data, source)
    items = []
    notes: list[str] = []
    for i, entry in enumerate(raw):
        where = f"thrusters[{i}]"
        mapping(entry, where, source)
        unknown = sorted(set(map(str, entry)) - ALLOWED)
        if unknown:  # other tools' fields are tolerated, but a typo should not pass silently
            notes.append(
                f"{source}: {where}: unknown field(s) {', '.join(repr(u) for u in unknown)} "
                f"ignored (known: {', '.join(sorted(ALLOWED))})"
            )
        name = entry.get("name")
        if isinstance(name, (int, float)) and not isinstance(name, bool):
            name = str(name)
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{where}.name = {name!r}: expected a non-empty name", source)
        where = f"thrusters[{i}] ({name})"
        try:
            items.append(_one(entry, name, where, density))
        except InputError as exc:
            raise InputError(exc.detail, source) from None
    try:
        return ThrusterSet(
            tuple(items), density=density if density is not None else SEAWATER_DENSITY, notes=tuple(notes)
        )
    except InputError as exc:
        raise InputError(exc.detail, source) from None


def _density(data: dict[str, Any], source: str) -> float | None:
    fluid = data.get("fluid")
    if not isinstance(fluid, dict) or "density" not in fluid:
        return None
    return number(fluid["density"], "fluid.density", source, positive=True)  # kg/m³


def _one(entry: dict[str, Any], name: str, where: str, density: float | None) -> Thruster:
    if "position" not in entry:
        raise InputError(f"{where}: missing 'position' (3 numbers, m)")
    if "max_thrust" not in entry:
        raise InputError(f"{where}: missing 'max_thrust' (N)")
    has_dir = "direction" in entry
    has_angles = "azimuth_deg" in entry or "elevation_deg" in entry
    if has_dir == has_angles:
        raise InputError(f"{where}: give either 'direction' (3 numbers) or 'azimuth_deg'/'elevation_deg'")
    if has_dir:
        direction = entry["direction"]
    else:
        az = math.radians(number(entry.get("azimuth_deg", 0.0), f"{where}.azimuth_deg"))
        el = math.radians(number(entry.get("elevation_deg", 0.0), f"{where}.elevation_deg"))
        direction = (math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
    kw: dict[str, Any] = {
        "name": name,
        "position": entry["position"],
        "direction": direction,
        "max_thrust": entry["max_thrust"],
        "min_thrust": entry.get("min_thrust"),
        "time_constant": entry.get("time_constant", 0.0),
        "wake_fraction": entry.get("wake_fraction", 0.0),
        "thrust_deduction": entry.get("thrust_deduction", 0.0),
        # log metadata (hydrokit ingest --run-out): which autopilot output drives it
        "channel": entry.get("channel"),
        "motor": entry.get("motor"),
        "reversed": entry.get("reversed", False),
    }
    if "diameter" in entry:
        kw["diameter"] = entry["diameter"]
    if "kt_forward" in entry:
        if density is None:
            raise InputError(f"{where}: the propeller model needs fluid.density in the file")
        for key in ("diameter", "kt_forward", "max_rpm"):
            if key not in entry:
                raise InputError(f"{where}: the propeller model needs '{key}'")
        kw["kt_forward"] = entry["kt_forward"]
        kw["kt_reverse"] = entry.get("kt_reverse")
        rpm = number(entry["max_rpm"], f"{where}.max_rpm", positive=True)
        kw["max_speed"] = rpm / 60.0  # rpm -> rev/s
        kw["advance_ratio_range"] = tuple(
            vector(entry.get("advance_ratio_range", DEFAULT_ADVANCE_RATIO_RANGE), 2, f"{where}.advance_ratio_range")
        )
        loss = entry.get("thrust_loss", 1.0)
        if isinstance(loss, dict):
            extra = set(loss) - {"forward", "reverse"}
            if extra:
                raise InputError(f"{where}.thrust_loss: unknown key '{sorted(extra)[0]}'")
            fwd = number(loss.get("forward", 1.0), f"{where}.thrust_loss.forward", positive=True)
            kw["thrust_loss_forward"] = fwd
            # reverse defaults to the forward factor
            kw["thrust_loss_reverse"] = number(loss.get("reverse", fwd), f"{where}.thrust_loss.reverse", positive=True)
        else:
            kw["thrust_loss_forward"] = kw["thrust_loss_reverse"] = number(loss, f"{where}.thrust_loss", positive=True)
    if "thrust_table" in entry:
        table = mapping(entry["thrust_table"], f"{where}.thrust_table")
        if set(table) != {"command", "thrust"}:
            raise InputError(f"{where}.thrust_table: expected a mapping with 'command' and 'thrust'")
        kw["table_command"] = table["command"]
        kw["table_thrust"] = table["thrust"]
    try:
        return Thruster(**kw)
    except InputError as exc:
        raise InputError(f"{where}: {exc.detail}") from None
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: {exc}") from None
