"""``hydrokit sysid``: a vehicle's added mass and damping from its own dives (issue #44): ``sysid
RUN...`` fits (= ``sysid fit``); ``sysid generate`` writes virtual dives; ``sysid plan`` designs one."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._sysid_compare import compare
from hydrokit.cli._sysid_generate import generate
from hydrokit.cli._sysid_plan import _names, plan
from hydrokit.cli._types import NON_NEGATIVE, SECONDS, SEED, Count

SUBCOMMANDS = ("fit", "generate", "plan", "compare")


class _SysidGroup(click.Group):
    """A group whose default subcommand is ``fit``: ``hydrokit sysid RUN...`` keeps working."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if args and args[0] not in SUBCOMMANDS and args[0] not in ("-h", "--help"):
            args = ["fit", *args]
        return super().parse_args(ctx, args)


@click.group(cls=_SysidGroup, context_settings={"help_option_names": ["-h", "--help"]})
def sysid() -> None:
    """System identification from free-running logs: hydrokit sysid RUN... --vehicle BASE.yaml
    --free LIST --out DIR (same as 'sysid fit'); 'sysid generate' (virtual dives); 'sysid plan'."""


sysid.add_command(plan)
sysid.add_command(generate)
sysid.add_command(compare)


@sysid.command("fit")
@click.argument("runs", nargs=-1, required=True, metavar="RUN...")
@click.option("--vehicle", required=True, help="Base vehicle YAML (or bundled name) with its thrusters.")
@click.option(
    "--free",
    multiple=True,
    required=True,
    help="Free parameters (repeat or comma-separate): added_mass.surge, linear_damping.yaw, "
    "quadratic_damping.heave (SI: kg, N·s/m, N·s²/m²; rotations kg·m², N·m·s/rad, N·m·s²/rad²), terms.<term>.",
)
@click.option(
    "--out",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for vehicle.yaml, sysid.json, predictions.csv, report.html.",
)
@click.option("--holdout", multiple=True, help="Run file(s) used only for validation (repeat or comma-separate).")
@click.option(
    "--method",
    type=click.Choice(["output-error", "equation-error"]),
    default="output-error",
    show_default=True,
    help="Output error (simulation vs measurement) or equation error (least squares on the smoothed states).",
)
@click.option("--dt", type=SECONDS, default=0.01, show_default=True, help="Integration step, s.")
@click.option(
    "--workers", type=Count(1), default=None, help="Threads for the batch simulations (count; default: all cores)."
)
@click.option(
    "--scheduler", default=None, help="Dask scheduler address (e.g. tcp://127.0.0.1:8786): runs on its workers."
)
@click.option(
    "--samples", type=Count(0), default=40, show_default=True, help="Monte Carlo draws for the prediction band (count)."
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the Monte Carlo draws (integer).")
@click.option(
    "--window",
    default="auto",
    show_default=True,
    help="Fit windows of about this length, s, each started from its smoothed state (for runs that drift open "
    "loop, e.g. a course-unstable hull); 'auto': 30 s windows only when a run drifts at the start values; "
    "'none': whole runs.",
)
@click.option(
    "--window-continuity",
    "window_continuity",
    type=NON_NEGATIVE,
    default=0.0,
    show_default=True,
    help="With windows: weight (dimensionless) of each measured state's jump between a window's end and the next "
    "window's start, in σ of its channel's noise (1: a jump of one σ costs one measurement σ; 0: windows not tied).",
)
def fit(
    runs: tuple[str, ...], vehicle: str, free: tuple[str, ...], out_dir: str, holdout: tuple[str, ...], **opts: Any
) -> None:
    """Identify the --free coefficients of --vehicle from the run files RUN... (CSV: time s; x y z m,
    phi theta psi rad, u v w m/s, p q r rad/s, empty = no sample; one command column per thruster)."""
    from hydrokit.api import identify_runs, load_vehicle
    from hydrokit.cli._common import check_out_dir, progress_bar, write_all
    from hydrokit.io.vehicle import resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml
    from hydrokit.report.sysid import describe_runs, output_files, verdict_lines

    check_out_dir(out_dir)
    base = load_vehicle(vehicle)
    base_data = read_yaml(resolve_vehicle(vehicle))  # what vehicle.yaml is written from

    bar = progress_bar()
    task = bar.add_task("output-error fit", total=None)

    def said(train: list[Any], held: list[Any]) -> None:  # the runs as read, then the fit's bar
        for line in describe_runs(train, held):
            click.echo(line, err=True)
        for r in (*train, *held):
            for w in r.warnings:
                click.echo(f"warning: {r.source}: {w}", err=True)
        bar.start()

    step = lambda it, cost: bar.update(task, advance=1, description=f"iteration {it}: cost {cost:.6g}")  # noqa: E731
    try:
        # every --free name written into base_data before a run is read: one it could not write
        # fails now, not after the fit
        result = identify_runs(
            base, runs, _names(free), _names(holdout), on_read=said, progress=step, document=base_data, **opts
        )
    finally:
        bar.stop()
    files = output_files(result, base_data, out_dir)
    write_all(files)
    for line in verdict_lines(result):
        click.echo(line)
    for n, u, v, s in zip(result.parameters, result.units, result.values, result.sigma):
        click.echo(f"{n} = {v:.5g} ± {s:.2g} {u}")
    for m in (*result.messages, *result.warnings):
        click.echo(f"note: {m}", err=True)
    click.echo(f"wrote {', '.join(Path(f).name for f in files)} to {out_dir}", err=True)
