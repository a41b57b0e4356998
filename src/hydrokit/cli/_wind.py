"""``--wind`` and ``--wind-csv`` of ``hydrokit simulate`` (issue #48 item 4): a true wind, degrees on
the command line and radians in the CSV (the run files' columns), for a vehicle with a ``wind:``
block."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any

import click

from hydrokit.cli._types import Numbers
from hydrokit.errors import InputError


def wind_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add --wind and --wind-csv to a command; it receives them as one ``wind`` argument
    (``(speed_direction, csv)``) for :func:`wind_input`."""

    @functools.wraps(f)
    def inner(*args: Any, wind_const: list[float] | None, wind_csv: str | None, **kw: Any) -> Any:
        return f(*args, wind=(wind_const, wind_csv), **kw)

    g = click.option(
        "--wind-csv",
        type=click.Path(dir_okay=False),
        default=None,
        help="Wind over time instead: CSV with time,wind_speed,wind_direction (s, m/s, rad from), interpolated "
        "linearly.",
    )(inner)
    return click.option(
        "--wind",
        "wind_const",
        type=Numbers(2, "m/s, deg"),
        help="Constant true wind SPEED,DIRECTION: m/s and degrees clockwise from North, the direction it blows "
        "from (the vehicle file needs a wind: block).",
    )(g)


def wind_input(v: Any, current: Any, wind: tuple[list[float] | None, str | None]) -> Any:
    """The current, or the current and the wind on one table
    (:func:`hydrokit.model.dynamics.environment_table`); a wind for a vehicle without a wind model
    is refused in one line."""
    const, csv = wind
    if const is None and csv is None:
        return current
    if const is not None and csv is not None:
        raise InputError("--wind and --wind-csv: expected one of them")
    if v.wind is None:
        raise InputError(
            f"--wind{'-csv' if const is None else ''}: vehicle {v.name!r} has no wind model; expected a 'wind:' "
            "block in its file (docs/model.md)"
        )
    from hydrokit.model.dynamics import environment_table

    if const is not None:
        if const[0] < 0:
            raise InputError(f"--wind speed = {const[0]:g}: expected ≥ 0 (m/s)")
        return environment_table(current, (const[0], math.radians(const[1])))
    from hydrokit.io.wind import read_wind_table

    return environment_table(current, read_wind_table(str(csv)))
