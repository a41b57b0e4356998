"""``hydrokit export VEHICLE``: the vehicle for Gazebo, uuv_simulator or python-control."""

from __future__ import annotations

from pathlib import Path

import click

from hydrokit.cli._types import Numbers

FORMATS = ("gazebo", "uuv-simulator", "python-control")


@click.command()
@click.argument("vehicle")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    required=True,
    help="gazebo: gz-sim SDF (Hydrodynamics + Thruster systems, FLU); uuv-simulator: the fossen "
    "plugin block (FLU); python-control: A, B, C, D linearised at --trim (.npz).",
)
@click.option("--out", "out", required=True, type=click.Path(dir_okay=False), help="Output file (path).")
@click.option(
    "--trim",
    type=Numbers(6, "m/s and rad/s"),
    default="0,0,0,0,0,0",
    show_default=True,
    help="python-control: trim body velocity u,v,w (m/s), p,q,r (rad/s) to linearise about.",
)
@click.option(
    "--added-mass",
    type=click.Choice(["plugin", "inertial"]),
    default="plugin",
    show_default=True,
    help="gazebo (no unit): plugin = the Hydrodynamics xDotU … parameters (an explicit force, unstable when "
    "M_A is not small against M_RB); inertial = the link's <fluid_added_mass> (gz-sim Garden or later, DART).",
)
def export(vehicle: str, fmt: str, out: str, trim: list[float], added_mass: str) -> None:
    """Write VEHICLE (a vehicle file or bundled name) for another tool.

    Gazebo and uuv_simulator use body FLU / world ENU: hydrokit's FRD/NED values are converted
    (y and z negated, 6x6 matrices T M T) and the file says so in a comment, with where the
    coefficients came from (when the vehicle file says). What the target cannot take is refused
    (M_RB + M_A not positive definite, M_A not positive semi-definite, an added mass too large
    for an explicit added-mass force: ρ(M_RB⁻¹ M_A) ≥ 1) and what it takes badly is warned.
    """
    from hydrokit.api import export_vehicle, load_vehicle
    from hydrokit.cli._common import write_all
    from hydrokit.io.export import export_checks

    v = load_vehicle(vehicle)
    notes = export_checks(v, fmt, added_mass)  # refuses what would crash the target, before writing
    data = export_vehicle(v, fmt, trim=trim, added_mass=added_mass)
    write_all({Path(out): data})
    for note in notes:
        click.echo(f"warning: {note}", err=True)
    if fmt == "python-control":
        import io

        import numpy as np

        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            ev = np.linalg.eigvals(z["A"])
        slow = ev.real[ev.real < -1e-9]
        click.echo(
            f"A: 12 states (eta, nu), B: 6 inputs (tau); slowest stable eigenvalue {slow.max():.4g} 1/s"
            if slow.size
            else "A: 12 states, B: 6 inputs; no stable eigenvalue"
        )  # a result: stdout (stderr holds warnings and the one 'wrote' line)
    click.echo(f"wrote {out}", err=True)
