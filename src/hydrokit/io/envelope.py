"""The ``envelope:`` block of a vehicle file (issue #56 item 7): what the identification's runs
covered, read into a :class:`hydrokit.model.envelope.Envelope` (its docstring shows the block).

Every field is optional; a block written by ``hydrokit sysid`` has them all. Bad input is one line
naming the field, the value and what was expected; an unknown key is refused (a misspelt key must
not read as "the runs did not cover it").
"""

from __future__ import annotations

import math
from typing import Any

from hydrokit.core.validate import cut, cut_repr, mapping, number
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import check_keys
from hydrokit.model.envelope import Envelope, SpeedLevel

#: the keys of the ``envelope`` block
ENVELOPE_KEYS = (
    "runs",
    "length",
    "command_range",
    "speed_per_command",
    "speed_manoeuvring",
    "speed",
    "deflection_deg",
    "yaw_rate",
    "drift_deg",
)
#: the keys of one ``speed_per_command`` entry
LEVEL_KEYS = ("command", "speed", "scatter", "turning", "runs", "samples")


def _pair(value: Any, field: str, source: str, unit: str, nonneg: bool = False) -> tuple[float, float]:
    """[least, largest]: two numbers, the first not above the second."""
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(f"field '{field}' = {cut_repr(value)}: expected [least, largest] ({unit})", source)
    lo, hi = (number(x, f"{field}[{k}]", source, nonneg=nonneg) for k, x in enumerate(value))
    if lo > hi:
        raise InputError(f"field '{field}' = {cut_repr(value)}: expected the least first, then the largest", source)
    return lo, hi


def _named(name: Any, known: tuple[str, ...], field: str, what: str, source: str) -> str:
    """A thruster's or surface's name the vehicle has."""
    if str(name) not in known:
        has = ", ".join(known) or "none"
        raise InputError(
            f"field '{field}.{cut(str(name))}': the vehicle has {what} {has}; expected one of them", source
        )
    return str(name)


def _count(value: Any, field: str, source: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise InputError(f"field '{field}' = {cut_repr(value)}: expected a whole number ≥ 1 (count)", source)
    return int(value)


def _level(entry: Any, k: int, thrusters: tuple[str, ...], source: str, key: str = "speed_per_command") -> SpeedLevel:
    where = f"envelope.{key}[{k}]"
    block = mapping(entry, where, source)
    check_keys(block, LEVEL_KEYS, where, source)
    for key in ("command", "speed", "scatter"):
        if key not in block:
            raise InputError(f"field '{where}' has no '{key}': expected command, speed (m/s) and scatter (m/s)", source)
    commands = mapping(block["command"], f"{where}.command", source)
    command = tuple(
        (
            _named(n, thrusters, f"{where}.command", "thrusters", source),
            number(c, f"{where}.command.{cut(str(n))}", source),
        )
        for n, c in commands.items()
    )
    return SpeedLevel(
        command,
        number(block["speed"], f"{where}.speed", source, nonneg=True),
        number(block["scatter"], f"{where}.scatter", source, nonneg=True),
        _count(block.get("runs", 1), f"{where}.runs", source),
        _count(block.get("samples", 1), f"{where}.samples", source),
        None if block.get("turning") is None else number(block["turning"], f"{where}.turning", source, nonneg=True),
    )


def _levels(block: Any, key: str, thrusters: tuple[str, ...], source: str) -> tuple[SpeedLevel, ...]:
    levels = block.get(key) or []
    if not isinstance(levels, list):
        raise InputError(
            f"field 'envelope.{key}' = {cut_repr(levels)}: expected a list of {{command, speed, scatter, runs, samples}}",
            source,
        )
    return tuple(_level(e, k, thrusters, source, key) for k, e in enumerate(levels))


def read_envelope(
    value: Any, source: str, thrusters: tuple[str, ...] = (), surfaces: tuple[str, ...] = ()
) -> Envelope | None:
    """The ``envelope:`` block (module docstring), or None when the file has none.

    Parameters
    ----------
    value : the block as read (None: no block)
    source : str — the file (prefixed to errors)
    thrusters, surfaces : the vehicle's thruster and control-surface names (a command or a
        deflection must name one of them)

    Raises
    ------
    InputError
        One line naming the field: an unknown key, a value that is not a number (or is negative
        where it cannot be), a range whose least is above its largest, a name the vehicle lacks.
    """
    if value is None:
        return None
    block = mapping(value, "envelope", source)
    check_keys(block, ENVELOPE_KEYS, "envelope", source)
    runs = block.get("runs", [])
    if not isinstance(runs, list) or not all(isinstance(r, str) for r in runs):
        raise InputError(f"field 'envelope.runs' = {cut_repr(runs)}: expected a list of run names", source)
    ranges = mapping(block.get("command_range") or {}, "envelope.command_range", source)
    command_range = tuple(
        (
            _named(n, thrusters, "envelope.command_range", "thrusters", source),
            *_pair(r, f"envelope.command_range.{cut(str(n))}", source, "the thruster's unit"),
        )
        for n, r in ranges.items()
    )
    deflection = tuple(
        (
            _named(n, surfaces, "envelope.deflection_deg", "control surfaces", source),
            math.radians(number(d, f"envelope.deflection_deg.{cut(str(n))}", source, nonneg=True)),
        )
        for n, d in mapping(block.get("deflection_deg") or {}, "envelope.deflection_deg", source).items()
    )
    length = block.get("length")
    speed = block.get("speed")
    yaw, drift = block.get("yaw_rate"), block.get("drift_deg")
    if drift is not None and number(drift, "envelope.drift_deg", source, nonneg=True) > 180:
        raise InputError(
            f"field 'envelope.drift_deg' = {cut_repr(drift)}: expected an angle from 0 to 180 (deg)", source
        )
    return Envelope(
        speed_per_command=_levels(block, "speed_per_command", thrusters, source),
        speed_manoeuvring=_levels(block, "speed_manoeuvring", thrusters, source),
        command_range=command_range,
        speed=None if speed is None else _pair(speed, "envelope.speed", source, "m/s", nonneg=True),
        deflection=deflection,
        yaw_rate=None if yaw is None else number(yaw, "envelope.yaw_rate", source, nonneg=True),
        drift=None if drift is None else math.radians(float(drift)),
        length=None if length is None else number(length, "envelope.length", source, positive=True),
        runs=tuple(runs),
    )
