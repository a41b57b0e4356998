"""``--strict`` of the commands that fly a vehicle file (``simulate``, ``manoeuvre``): refuse a
vehicle whose ``identification:`` block says ``does not fit`` (issue #48), and a prediction whose
model does not hold at its own runs' speed (its ``envelope:`` block, issue #56 item 7).

Without ``--strict`` such a vehicle flies, and its warning (first in ``Vehicle.warnings``,
:mod:`hydrokit.io.vehicle`; the envelope's line, :mod:`hydrokit.model.envelope`) is printed and
written with the results.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import Any, TypeVar

import click

F = TypeVar("F", bound=Callable[..., Any])

STRICT_HELP = (
    'Refuse a VEHICLE whose identification: block says "does not fit", or a run whose model does not hold '
    "at its own runs' speed (its envelope: block) (exit 2, nothing written); without it such a vehicle flies "
    "with a warning (flag)."
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


def refuse_not_holding(lines: list[str], strict: bool) -> None:
    """Under ``--strict``, refuse a run whose model does not hold at its own runs' speed.

    Parameters
    ----------
    lines : the envelope's lines of the run (:func:`hydrokit.api.manoeuvre_envelope`)
    strict : bool — the flag

    Raises
    ------
    InputError
        The line, then "refused under --strict" (the command has written nothing yet).
    """
    from hydrokit.errors import InputError
    from hydrokit.model.envelope import does_not_hold

    held = [w for w in lines if does_not_hold(w)]
    if strict and held:
        raise InputError(f"{held[0]}: refused under --strict (without it the run is written with this line)")


def strict_option(command: F) -> F:
    """The ``--strict`` flag: the identification checked before the command runs, so a refused
    vehicle writes nothing; a command with a ``strict`` parameter gets the flag too (to refuse what
    only the run shows: :func:`refuse_not_holding`)."""
    takes = "strict" in inspect.signature(command).parameters

    @functools.wraps(command)
    def run(*args: Any, strict: bool = False, **kwargs: Any) -> Any:
        if strict:
            refuse_unfit(kwargs["vehicle"])
        if takes:
            kwargs["strict"] = strict
        return command(*args, **kwargs)

    flagged: F = click.option("--strict", is_flag=True, default=False, help=STRICT_HELP)(run)  # type: ignore[assignment]
    return flagged
