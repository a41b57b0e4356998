"""A vehicle's service condition on the command line (issue #55 item 2): what ``hydrokit
manoeuvre`` and ``hydrokit simulate`` fly when given no propulsion, the one stderr line that says
so and the JSON record of it (the rule itself: :func:`hydrokit.api.service_propulsion`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from hydrokit.errors import InputError

_FORCE = (("X", "N"), ("Y", "N"), ("Z", "N"), ("K", "N·m"), ("M", "N·m"), ("N", "N·m"))


def no_service_option(f: Callable[..., Any]) -> Callable[..., Any]:
    """``--no-service`` of ``hydrokit simulate``."""
    return click.option(
        "--no-service",
        is_flag=True,
        help="Without --force, --force-csv, --command or --command-csv the vehicle file's service: condition "
        "propels it (its thruster commands and force; said on stderr); this flag flies no propulsion at all "
        "instead (at rest, or coasting from --initial-velocity; no unit).",
    )(f)


def _units(vehicle: Any) -> dict[str, str]:
    from hydrokit.api import command_units

    return command_units(vehicle)


def service_line(vehicle: Any, service: Any) -> str:
    """``propulsion: NAME's service condition — propeller=11.567 rev/s, force K -0.543 N·m (about 1.53 m/s)``."""
    units = _units(vehicle)
    parts = [f"{n}={c:g} {units.get(n, '')}".rstrip() for n, c in service.command]
    force = [f"{s} {x:g} {u}" for (s, u), x in zip(_FORCE, service.tau) if x != 0.0]
    if force:
        parts.append("force " + ", ".join(force))
    return f"propulsion: {vehicle.name}'s service condition — {', '.join(parts)} (about {service.speed:.3g} m/s)"


def service_record(vehicle: Any, service: Any) -> dict[str, Any]:
    """The JSON record: ``propulsion_source`` and, when the service condition was flown, ``service``
    (commands and their units, force in N and N·m, the speed it reaches in m/s)."""
    if service is None:
        return {"propulsion_source": "options"}
    units = _units(vehicle)
    block = {
        "commands": service.commands,
        "command_units": {n: units.get(n) for n in service.commands},
        "force": list(service.tau),
        "speed": service.speed,
    }
    return {"propulsion_source": "service", "service": block}


def simulate_service(
    vehicle: Any,
    tau: Any,
    given: bool,
    samples: int,
    integrator: str,
    attitude: str,
    current_ned: Any,
) -> tuple[Any, Any]:
    """(force argument, service flown or None) of ``hydrokit simulate``: the service condition
    when no propulsion was ``given`` and the file states one, as a force or as a
    :class:`hydrokit.simulate.commands.CommandForce` (thrusters from rest, as ``--command``); a
    run that cannot fly its commands (``--samples``, an adaptive integrator, quaternions) is
    refused in one line naming the options that would."""
    from hydrokit.api import service_propulsion

    service = None if given else service_propulsion(vehicle, tau)
    if service is None or not service.command:
        return (tau if service is None else list(service.tau)), service
    what = f"no propulsion given: the service: condition of vehicle {vehicle.name!r} drives its thrusters"
    if samples:
        raise InputError(
            f"--samples {samples} with {what}, which the samples cannot fly (they fly a constant force); "
            "expected --force X,Y,Z,K,M,N (N, N·m) or --no-service"
        )
    for option, value, wanted in (("--integrator", integrator, "rk4"), ("--attitude", attitude, "euler")):
        if value != wanted:
            raise InputError(
                f"{option} {value} with {what}, flown by the compiled RK4 in Euler angles; expected {option} "
                f"{wanted}, a --force or --no-service"
            )
    from hydrokit.simulate.commands import CommandForce, command_table

    table = command_table(vehicle, service.commands)
    return CommandForce(
        vehicle.thrusters, table, force=list(service.tau), start="rest", current_ned=current_ned
    ), service
