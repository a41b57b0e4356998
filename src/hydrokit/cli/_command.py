"""``--command`` and ``--command-csv`` of ``hydrokit simulate`` (issue #48): the vehicle's thrusters
driven by commands in each thruster's own unit, as ``hydrokit manoeuvre --command`` (the same
parser, :func:`hydrokit.manoeuvre.run.commands_from_text`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from hydrokit.errors import InputError


def command_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the two command options to a command."""
    f = click.option(
        "--command-csv",
        type=click.Path(dir_okay=False),
        default=None,
        help="Thruster commands over time: CSV with time (s) and one column per thruster (its unit: rev/s for a "
        "propeller, the table's unit, N for an ideal thruster), each row held until the next.",
    )(f)
    return click.option(
        "--command",
        "command_text",
        default=None,
        metavar="NAME=VALUE[,NAME=VALUE]",
        help="Constant thruster commands from t = 0, each in its thruster's unit (rev/s for a propeller, the "
        "table's unit, N for an ideal thruster); others 0. Rotors spin up from rest with their lag; the "
        "thrust follows each propeller's advance speed. Added to --force.",
    )(f)


def command_force(
    vehicle: Any, text: str | None, csv_path: str | None, force: Any, current_ned: Any, samples: int = 0
) -> Any:
    """The force argument of :func:`hydrokit.simulate.driver.simulate`: ``force`` itself (6 floats
    or a force table) without commands, else a :class:`hydrokit.simulate.commands.CommandForce`
    adding the thrusters' force to it (refused with ``samples`` > 0: they fly a constant force)."""
    if text is not None and csv_path is not None:
        raise InputError("--command and --command-csv: expected one of them")
    if text is None and csv_path is None:
        return force
    if samples:
        raise InputError(
            f"--command{'-csv' if csv_path is not None else ''} with --samples: the samples fly a constant --force; "
            "expected no thruster commands"
        )
    from hydrokit.manoeuvre.run import commands_from_text
    from hydrokit.simulate.commands import CommandForce, command_table

    if text is not None:
        table = command_table(vehicle, commands_from_text(text))
    else:
        from hydrokit.io.commands import read_command_table

        src = str(csv_path)
        ts = getattr(vehicle, "thrusters", None)
        table = read_command_table(src, tuple(ts.names) if ts is not None else ())
        try:
            table = command_table(vehicle, table)
        except InputError as exc:
            raise InputError(str(exc), src) from None
    return CommandForce(vehicle.thrusters, table, force=force, start="rest", current_ned=current_ned)


def simulator(tau: Any, integrator: str, attitude: str) -> Callable[..., Any]:
    """The run function for ``tau``: :func:`hydrokit.simulate.driver.simulate`, or under thruster
    commands :func:`hydrokit.simulate.commands.fly_commands` with the same arguments (the compiled
    RK4 in Euler angles only: it gives the right-hand side each thruster's thrust and rate)."""
    from hydrokit.simulate.commands import CommandForce, fly_commands
    from hydrokit.simulate.driver import simulate

    if not isinstance(tau, CommandForce):
        return simulate
    for option, value, wanted in (("--integrator", integrator, "rk4"), ("--attitude", attitude, "euler")):
        if value != wanted:
            raise InputError(
                f"{option} {value} with thruster commands: they fly the compiled RK4 in Euler angles (each "
                f"thruster's thrust and rate reach the right-hand side); expected {option} {wanted}"
            )

    def run(
        vehicle: Any,
        duration: float,
        dt: float,
        force: Any,
        eta0: Any,
        nu0: Any,
        current_ned: Any,
        integrator: str,
        attitude: str,
        output_every: int,
        progress: Any = None,
        deflection: Any = None,
    ) -> Any:
        return fly_commands(vehicle, duration, dt, force, eta0, nu0, current_ned, deflection, output_every, progress)

    return run
