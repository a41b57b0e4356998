"""``--strict`` of the commands that fly a vehicle file (``simulate``, ``manoeuvre``): refuse a
vehicle whose ``identification:`` block says ``does not fit`` (issue #48).

Without ``--strict`` such a vehicle flies, and its warning (first in ``Vehicle.warnings``,
:mod:`hydrokit.io.vehicle`) is printed and written with the results.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

import click

F = TypeVar("F", bound=Callable[..., Any])

STRICT_HELP = (
    'Refuse a VEHICLE whose identification: block says "does not fit" (exit 2, nothing written); '
    "without it such a vehicle flies with a warning (flag)."
)


def refuse_unfit(vehicle: str) -> None:
    """Raise when the vehicle file's ``identification:`` block says ``does not fit``.

    Parameters
    ----------
    vehicle : str — a vehicle YAML file or a bundled name

    Raises
    ------
    InputError
        One line naming the file and the verdict's first reason.
    """
    from hydrokit.errors import InputError
    from hydrokit.io.vehicle import read_identification, resolve_vehicle
    from hydrokit.model.identification import UNFIT_MARK

    ident = read_identification(vehicle)
    if ident is None or ident.fits:
        return
    raise InputError(
        f"{UNFIT_MARK}{ident.why}: refused under --strict (without it the vehicle flies with a warning)",
        str(resolve_vehicle(vehicle)),
    )


def strict_option(command: F) -> F:
    """The ``--strict`` flag: checked before the command runs, so a refused vehicle writes nothing."""

    @functools.wraps(command)
    def run(*args: Any, strict: bool = False, **kwargs: Any) -> Any:
        if strict:
            refuse_unfit(kwargs["vehicle"])
        return command(*args, **kwargs)

    flagged: F = click.option("--strict", is_flag=True, default=False, help=STRICT_HELP)(run)  # type: ignore[assignment]
    return flagged
