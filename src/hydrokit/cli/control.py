"""``hydrokit allocate``: thrust allocation (a thin layer over :func:`hydrokit.allocate`)."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._common import json_text, write_all
from hydrokit.cli._types import Numbers


@click.command()
@click.argument("vehicle")
@click.option(
    "--tau",
    type=Numbers(6, "N and N·m"),
    required=True,
    help="Demanded force/moment X,Y,Z,K,M,N in body axes (N, N·m), comma-separated.",
)
@click.option(
    "--method",
    type=click.Choice(["constrained", "pinv"]),
    default="constrained",
    show_default=True,
    help="constrained: least residual within the thrust limits (N), then least thrust; "
    "pinv: unconstrained (weighted) pseudo-inverse.",
)
@click.option(
    "--weights",
    type=Numbers(unit="dimensionless", positive=True),
    default=None,
    help="pinv only: per-thruster weights (dimensionless, larger = used less), comma-separated in file order.",
)
@click.option(
    "--json",
    "json_out",
    type=click.Path(dir_okay=False),
    default=None,
    help="Write the result as JSON to this file (forces in N, moments in N·m, speeds in rpm).",
)
def allocate(vehicle: str, tau: list[float], method: str, weights: list[float] | None, json_out: str | None) -> None:
    """Allocate a demanded force/moment TAU to the thrusters of VEHICLE (file or bundled name).

    Prints the configuration matrix, thrust per thruster (N), the achieved τ and the DOF the
    layout cannot actuate. Propeller thrusters also get the speed (rpm) that gives the
    thrust at zero advance speed.
    """
    from hydrokit.api import allocate as run
    from hydrokit.errors import InputError
    from hydrokit.io.thrusters import load_thrusters

    ts = load_thrusters(vehicle)
    if weights is not None:
        if len(weights) != len(ts):
            shown = ",".join(f"{x:g}" for x in weights)
            raise InputError(f"--weights {shown}: {len(weights)} weights; expected {len(ts)}, one per thruster")
        if method != "pinv":
            raise InputError("--weights applies only to --method pinv")
    res = run(ts, tau, method, weights)
    doc = {**res.to_dict(), "vehicle": vehicle}
    for msg in doc["warnings"]:
        click.echo(f"warning: {msg}", err=True)
    _print_allocation(doc)
    if json_out:
        write_all({json_out: json_text(doc)})


def _print_allocation(doc: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    from hydrokit.core.names import DOF_NAMES

    console = Console()
    mt = Table(title="Configuration matrix T (rows X Y Z K M N; m for moments)")
    mt.add_column("DOF")
    for name in doc["thrusters"]:
        mt.add_column(str(name), justify="right")
    for dof, row in zip(DOF_NAMES, doc["configuration_matrix"]):
        mt.add_row(dof, *[f"{x:.4g}" for x in row])
    console.print(mt)
    tt = Table(title=f"Allocation ({doc['method']})")
    for col in ("thruster", "thrust (N)", "min (N)", "max (N)", "command", "unit", "saturated"):
        tt.add_column(col, justify="left" if col in ("thruster", "unit") else "right")
    for i, name in enumerate(doc["thrusters"]):
        lo, hi = doc["thrust_limits"][i]
        tt.add_row(
            str(name),
            _g(doc["thrust"][i]),
            "none" if lo is None else f"{lo:.4g}",
            "none" if hi is None else f"{hi:.4g}",
            _g(doc["command"][i]),
            doc["command_unit"][i],
            "yes" if name in doc["saturated"] else "",
        )
    console.print(tt)
    at = Table(title="Demanded and achieved τ (N, N·m)")
    for col in ("DOF", "demanded", "achieved"):
        at.add_column(col, justify="right")
    scale = max([abs(x) for x in doc["tau"] + doc["achieved_tau"] if x is not None] + [1.0])
    for dof, a, b in zip(DOF_NAMES, doc["tau"], doc["achieved_tau"]):
        b = 0.0 if b is not None and abs(b) < 1e-12 * scale else b  # show round-off as 0
        at.add_row(dof, _g(a), _g(b))
    console.print(at)
    unc = ", ".join(doc["uncontrollable"]) or "none"
    console.print(f"residual |Tf − τ| = {_g(doc['residual'])}; not actuated: {unc}")


def _g(x: float | None) -> str:
    """A number of the JSON document (None where it was not finite) for the table."""
    return "not finite" if x is None else f"{x:.4g}"
