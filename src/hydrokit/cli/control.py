"""``hydrokit allocate`` and ``hydrokit mission``: thrust allocation and closed-loop missions.

Heavy imports (numpy, scipy, matplotlib) stay inside the command functions so that
``hydrokit --help`` starts fast.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import click

from hydrokit.errors import InputError

DOF = ("surge", "sway", "heave", "roll", "pitch", "yaw")


def _parse_tau(text: str) -> list[float]:
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 6 or not all(math.isfinite(v) for v in values):
        raise InputError(
            f"--tau {text!r}: expected 6 comma-separated finite numbers X,Y,Z,K,M,N (N and N·m)"
        )
    return values


def _parse_weights(text: str | None, m: int) -> list[float] | None:
    if text is None:
        return None
    try:
        values = [float(p) for p in text.split(",")]
    except ValueError:
        values = []
    if len(values) != m or not all(math.isfinite(v) and v > 0 for v in values):
        raise InputError(f"--weights {text!r}: expected {m} comma-separated positive numbers")
    return values


@click.command()
@click.argument("vehicle")
@click.option("--tau", required=True, help="Demanded force/moment X,Y,Z,K,M,N in body axes (N, N·m), comma-separated.")
@click.option(
    "--method",
    type=click.Choice(["constrained", "pinv"]),
    default="constrained",
    show_default=True,
    help="constrained: least residual within the thrust limits (N), then least thrust; "
    "pinv: unconstrained (weighted) pseudo-inverse.",
)
@click.option("--weights", default=None, help="pinv only: per-thruster weights (dimensionless, larger = used less), comma-separated in file order.")
@click.option("--json", "json_out", type=click.Path(dir_okay=False), default=None, help="Write the result as JSON to this file (forces in N, moments in N·m, speeds in rpm).")
def allocate(vehicle: str, tau: str, method: str, weights: str | None, json_out: str | None) -> None:
    """Allocate a demanded force/moment TAU to the thrusters of VEHICLE (file or bundled name).

    Prints the configuration matrix, thrust per thruster (N), the achieved τ and the DOF the
    layout cannot actuate. Propeller thrusters also get the speed (rpm) that gives the
    thrust at zero advance speed.
    """
    import numpy as np

    from hydrokit._atomic import write_text
    from hydrokit.io.thrusters import load_thrusters
    from hydrokit.model.allocation import allocate_constrained, allocate_pinv

    tau_v = _parse_tau(tau)
    ts = load_thrusters(vehicle)
    w = _parse_weights(weights, len(ts))
    if w is not None and method != "pinv":
        raise InputError("--weights applies only to --method pinv")
    T = ts.configuration_matrix()
    if method == "pinv":
        res = allocate_pinv(T, tau_v, weights=w, f_min=ts.f_min, f_max=ts.f_max, names=ts.names)
    else:
        res = allocate_constrained(T, tau_v, ts.f_min, ts.f_max, names=ts.names)
    command = ts.command_for_thrust(res.thrust)
    units = []
    shown = []
    for th, c in zip(ts.thrusters, command):
        if th.model == "propeller":
            units.append("rpm")
            shown.append(float(c) * 60.0)  # rev/s -> rpm at the edge
        elif th.model == "table":
            units.append("table command")
            shown.append(float(c))
        else:
            units.append("N")
            shown.append(float(c))
    doc: dict[str, Any] = {
        "vehicle": vehicle,
        "method": res.method,
        "thrusters": ts.names,
        "tau": tau_v,
        "configuration_matrix": [[float(x) for x in row] for row in T],
        "thrust": [float(x) for x in res.thrust],
        "thrust_limits": [[float(a), float(b)] for a, b in zip(ts.f_min, ts.f_max)],
        "command": shown,
        "command_unit": units,
        "achieved_tau": [float(x) for x in res.achieved_tau],
        "residual": float(res.residual),
        "uncontrollable": res.uncontrollable,
        "saturated": res.saturated,
        "warnings": res.warnings,
        "units": {"thrust": "N", "tau": "N, N·m (X,Y,Z,K,M,N)", "configuration_matrix": "-, m"},
    }
    for msg in res.warnings:
        click.echo(f"warning: {msg}", err=True)
    _print_allocation(doc)
    if json_out:
        write_text(json_out, json.dumps(doc, indent=2) + "\n")
    del np


def _print_allocation(doc: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    mt = Table(title="Configuration matrix T (rows X Y Z K M N; m for moments)")
    mt.add_column("DOF")
    for name in doc["thrusters"]:
        mt.add_column(str(name), justify="right")
    for dof, row in zip(DOF, doc["configuration_matrix"]):
        mt.add_row(dof, *[f"{x:.4g}" for x in row])
    console.print(mt)
    tt = Table(title=f"Allocation ({doc['method']})")
    for col in ("thruster", "thrust [N]", "min [N]", "max [N]", "command", "unit", "saturated"):
        tt.add_column(col, justify="left" if col in ("thruster", "unit") else "right")
    for i, name in enumerate(doc["thrusters"]):
        lo, hi = doc["thrust_limits"][i]
        tt.add_row(
            str(name), f"{doc['thrust'][i]:.4g}", f"{lo:.4g}", f"{hi:.4g}",
            f"{doc['command'][i]:.4g}", doc["command_unit"][i],
            "yes" if name in doc["saturated"] else "",
        )
    console.print(tt)
    at = Table(title="Demanded and achieved τ (N, N·m)")
    for col in ("DOF", "demanded", "achieved"):
        at.add_column(col, justify="right")
    for dof, a, b in zip(DOF, doc["tau"], doc["achieved_tau"]):
        at.add_row(dof, f"{a:.4g}", f"{b:.4g}")
    console.print(at)
    unc = ", ".join(doc["uncontrollable"]) or "none"
    console.print(f"residual |Tf − τ| = {doc['residual']:.4g}; not actuated: {unc}")
