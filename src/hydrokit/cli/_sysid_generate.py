"""``hydrokit sysid generate``: virtual pool dives of a vehicle with hidden coefficients (issue #44), or
the zigzag trials of a tanker model (``--zigzags``, issue #56)."""

from __future__ import annotations

import click

from hydrokit.cli._types import NON_NEGATIVE, SEED, Count, Number


@click.command("generate")
@click.option(
    "--vehicle", default=None, help="Vehicle YAML or bundled name (with thrusters)  [default: bluerov2-sysid]"
)
@click.option(
    "--zigzags",
    is_flag=True,
    help="Instead of dives: zigzag trials (10/10, 15/15, 20/20, 25/5, 30/5, 35/5, each to starboard then port; "
    "20 Hz, a smoothed heading) of a KVLCC2-like 7 m tanker, with its truth.yaml and a start.yaml 20-30 %% off.",
)
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Folder for the runs and truth.json."
)
@click.option("--runs", "n_runs", type=Count(1), default=None, help="Number of runs (count)  [default: 4; zigzags 12]")
@click.option(
    "--duration", type=Number("s", at_least=1), default=None, help="Length of each run, s  [default: 90; zigzags 150]"
)
@click.option(
    "--seed", type=SEED, default=1, show_default=True, help="Seed of the hidden coefficients, commands and noise."
)
@click.option(
    "--spread",
    type=Number(at_least=0, at_most=0.9),
    default=0.3,
    show_default=True,
    help="Hidden coefficients = base × uniform(1 − spread, 1 + spread) (fraction); zigzags: start.yaml's terms "
    "= truth × (1 ± uniform(spread − 0.1, spread)).",
)
@click.option(
    "--amplitude",
    type=Number(above=0, at_most=1),
    default=0.6,
    show_default=True,
    help="Largest fraction of a thrust limit used (0–1; dives).",
)
@click.option(
    "--noise", type=NON_NEGATIVE, default=1.0, show_default=True, help="Multiplier of the sensor noise σ (0 = none)."
)
def generate(
    vehicle: str | None,
    zigzags: bool,
    out_dir: str,
    n_runs: int | None,
    duration: float | None,
    seed: int,
    spread: float,
    amplitude: float,
    noise: float,
) -> None:
    """Write virtual pool dives of VEHICLE with hidden added mass and damping (surge, sway, heave,
    yaw): attitude and gyro at 50 Hz, depth at 10 Hz, DVL at 5 Hz, commands at 50 Hz. --zigzags:
    zigzag trials of a tanker model at 20 Hz (zigzagA-B{s,p}.csv, truth.yaml, start.yaml, truth.json,
    free.txt)."""
    from hydrokit.api import load_vehicle, sysid_dive_files
    from hydrokit.cli._common import check_out_dir, write_all

    if zigzags and vehicle is not None:
        raise click.UsageError("--zigzags flies its own tanker (hydrokit.sysid.ship.TANKER); expected no --vehicle")
    check_out_dir(out_dir)
    if zigzags:
        from hydrokit.cli._sysid_zigzags import zigzag_files

        n, length = min(n_runs or 12, 12), duration or 150.0
        write_all(zigzag_files(out_dir, n, length, seed, spread, noise))
        click.echo(
            f"wrote {n} zigzag run(s) of {length:g} s, truth.yaml, start.yaml, truth.json, free.txt to {out_dir}",
            err=True,
        )
        return
    n, length = n_runs or 4, duration or 90.0
    files = sysid_dive_files(
        load_vehicle(vehicle or "bluerov2-sysid"), out_dir, n, length, seed, spread, amplitude, noise
    )
    write_all(files)
    click.echo(f"wrote {n} dive(s) of {length:g} s and truth.json to {out_dir}", err=True)
