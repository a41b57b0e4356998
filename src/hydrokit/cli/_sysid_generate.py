"""``hydrokit sysid generate``: virtual pool dives of a vehicle with hidden coefficients (issue #44)."""

from __future__ import annotations

import click

from hydrokit.cli._types import NON_NEGATIVE, SEED, Count, Number


@click.command("generate")
@click.option(
    "--vehicle", default="bluerov2-sysid", show_default=True, help="Vehicle YAML or bundled name (with thrusters)."
)
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Folder for diveN.csv and truth.json."
)
@click.option("--runs", "n_runs", type=Count(1), default=4, show_default=True, help="Number of dives (count).")
@click.option(
    "--duration", type=Number("s", at_least=1), default=90.0, show_default=True, help="Length of each dive, s."
)
@click.option(
    "--seed", type=SEED, default=1, show_default=True, help="Seed of the hidden coefficients, commands and noise."
)
@click.option(
    "--spread",
    type=Number(at_least=0, at_most=0.9),
    default=0.3,
    show_default=True,
    help="Hidden coefficients = base × uniform(1 − spread, 1 + spread) (fraction).",
)
@click.option(
    "--amplitude",
    type=Number(above=0, at_most=1),
    default=0.6,
    show_default=True,
    help="Largest fraction of a thrust limit used (0–1).",
)
@click.option(
    "--noise", type=NON_NEGATIVE, default=1.0, show_default=True, help="Multiplier of the sensor noise σ (0 = none)."
)
def generate(
    vehicle: str, out_dir: str, n_runs: int, duration: float, seed: int, spread: float, amplitude: float, noise: float
) -> None:
    """Write virtual pool dives of VEHICLE with hidden added mass and damping (surge, sway, heave,
    yaw): attitude and gyro at 50 Hz, depth at 10 Hz, DVL at 5 Hz, commands at 50 Hz."""
    from hydrokit.api import load_vehicle, sysid_dive_files
    from hydrokit.cli._common import check_out_dir, write_all

    check_out_dir(out_dir)
    write_all(sysid_dive_files(load_vehicle(vehicle), out_dir, n_runs, duration, seed, spread, amplitude, noise))
    click.echo(f"wrote {n_runs} dive(s) of {duration:g} s and truth.json to {out_dir}", err=True)
