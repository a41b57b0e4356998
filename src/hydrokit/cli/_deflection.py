"""``--deflection`` and ``--deflection-csv`` of ``hydrokit simulate`` (issue #45): control-surface
deflections, degrees on the command line and radians in the CSV (as simulate's other CSVs are SI)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import click

from hydrokit.errors import InputError


def deflection_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the two deflection options to a command."""
    f = click.option(
        "--deflection-csv",
        type=click.Path(dir_okay=False),
        default=None,
        help="Deflections over time: CSV with time (s) and one column per control surface (rad), interpolated "
        "linearly and held at the ends.",
    )(f)
    return click.option(
        "--deflection",
        default=None,
        metavar="NAME=DEG[,NAME=DEG]",
        help="Constant control-surface deflections, degrees (right-handed about each hinge axis); others 0.",
    )(f)


def parse_deflection(text: str, names: tuple[str, ...]) -> list[float]:
    """``rudder=10,sternplane=-5`` → deflections in rad, file order (unnamed surfaces 0)."""
    out = [0.0] * len(names)
    if not names:
        raise InputError(f"--deflection {text[:80]!r}: the vehicle has no control_surfaces; expected no --deflection")
    for part in text.split(","):
        name, sep, value = part.partition("=")
        name = name.strip()
        if not sep or name not in names:
            raise InputError(
                f"--deflection {part.strip()[:80]!r}: expected NAME=DEG with NAME one of {', '.join(names)}"
            )
        try:
            deg = float(value)
        except ValueError:
            deg = math.nan
        if not math.isfinite(deg):
            raise InputError(f"--deflection {part.strip()[:80]!r}: expected a finite angle in degrees")
        out[names.index(name)] = math.radians(deg)
    return out


def deflection_input(vehicle: Any, text: str | None, csv_path: str | None) -> Any:
    """The deflection argument of :func:`hydrokit.simulate.driver.simulate` (None, rad or a table),
    checked against the surfaces' limits (degrees in the message)."""
    if text is not None and csv_path is not None:
        raise InputError("--deflection and --deflection-csv: expected one of them")
    names = vehicle.surfaces.names
    if text is not None:
        value = parse_deflection(text, names)
        vehicle.surfaces.check_deflection(value, "--deflection")
        return value
    if csv_path is not None:
        from hydrokit.io.trajectory import read_deflection_table

        table = read_deflection_table(csv_path, names)
        vehicle.surfaces.check_deflection(table[:, 1:], f"{csv_path}")
        return table
    return None
