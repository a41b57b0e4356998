"""``hydrokit mission``: fly a closed-loop mission (a thin layer over :func:`hydrokit.fly`)."""

from __future__ import annotations

import math
from typing import Any

import click

from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all
from hydrokit.cli._samples import check_samples, mission_samples, samples_options
from hydrokit.cli._types import SECONDS


@click.command()
@click.argument("mission_file", metavar="MISSION")
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",  # checked by check_out_dir (one line naming --out), not by click
    help="Output directory (created if missing) for the CSV (SI: m, rad, s, N), plots and metrics JSON.",
)
@click.option(
    "--controller",
    type=click.Choice(["file", "pid", "s-plane", "both"]),
    default="file",
    show_default=True,
    help="Which gain set of the mission file to fly (dimensionless choice): the file's "
    "'controller', pid, s-plane, or both for a side-by-side comparison.",
)
@click.option("--duration", type=SECONDS, default=None, help="Override the mission duration, s.")
@click.option("--no-plots", is_flag=True, help="Skip the PNG figures (no unit).")
@click.option(
    "--loop",
    type=click.Choice(["compiled", "python"]),
    default="compiled",
    show_default=True,
    help="Closed-loop implementation (no unit): compiled (numba) or python (the reference).",
)
@samples_options("monte_carlo.json, envelope.csv (x, y, z: 5/50/95 %, min, max per controller; m, s), envelope.png")
def mission(
    mission_file: str,
    out_dir: str,
    controller: str,
    duration: float | None,
    no_plots: bool,
    loop: str,
    samples: int,
    seed: int,
) -> None:
    """Fly MISSION (a mission YAML file or bundled name) in closed loop and write results.

    Writes trajectory.csv (time,x,y,z,phi,theta,psi,u,v,w,p,q,r in m, rad, m/s, rad/s, then
    per thruster the demanded and reached command and the allocated and actual thrust in N;
    with --controller both, one trajectory_<controller>.csv per controller), metrics.json,
    path.png (3-D path and projections), tracking.png and thrusters.png.
    """
    from hydrokit.api import fly, load_mission, load_vehicle
    from hydrokit.errors import InputError
    from hydrokit.io.trajectory import table_csv
    from hydrokit.simulate.mission import COMMAND_UNITS, METRIC_UNITS

    out = check_out_dir(out_dir)  # before any work: a run must not be lost to a bad folder
    mis = load_mission(mission_file)
    if duration is not None and not (math.isfinite(duration) and duration >= mis.dt):
        raise InputError(f"--duration {duration}: expected a time ≥ the step dt = {mis.dt} s")
    kinds = {"file": [mis.controller], "both": ["pid", "s-plane"]}.get(controller, [controller])
    for kind in kinds:
        mis.autopilot(kind)  # validates the gains before any work
    vehicle = load_vehicle(mis.vehicle)  # all input validated before the run starts
    if vehicle.thrusters is None:
        raise InputError(f"vehicle '{mis.vehicle}' has no 'thrusters:' block; a mission needs thrusters", mis.source)
    check_samples(vehicle, samples)
    for note in vehicle.thrusters.notes:
        click.echo(f"warning: {note}", err=True)
    results = {}
    with progress_bar(time_based=True) as bar:
        for kind in kinds:
            task = bar.add_task(f"{kind} mission", total=duration if duration is not None else mis.duration)
            advance = lambda t, task=task: bar.update(task, completed=t)  # noqa: E731
            results[kind] = fly(mis, kind, vehicle=vehicle, duration=duration, progress=advance, loop=loop)
    thrusters = vehicle.thrusters
    metrics = {r.label: r.metrics for r in results.values()}
    # everything computed: build the outputs in memory, then write them
    files: dict[str, Any] = {}
    for kind, res in results.items():
        name = "trajectory.csv" if len(results) == 1 else f"trajectory_{kind}.csv"
        files[name] = table_csv(*res.columns_and_data())
    doc = {
        "mission": mis.name,
        "source": mis.source,
        "vehicle": mis.vehicle,
        "thrusters": thrusters.names,
        "command_units": [COMMAND_UNITS[t.model] for t in thrusters.thrusters],
        "controllers": metrics,
        "units": METRIC_UNITS,
    }
    files["metrics.json"] = json_text(doc)
    if not no_plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.mission import path_figure, thruster_figure, tracking_figure

        runs = {r.label: r.run for r in results.values()}
        files["path.png"] = to_png(path_figure(runs, f"{mis.name}: 3-D path and projections"))
        files["tracking.png"] = to_png(tracking_figure(runs, f"{mis.name}: tracking error"))
        for kind, res in results.items():
            name = "thrusters.png" if len(results) == 1 else f"thrusters_{kind}.png"
            files[name] = to_png(
                thruster_figure(res.run, thrusters.f_min, thrusters.f_max, f"{mis.name} ({res.label}): thruster usage")
            )
    extra, spread = mission_samples(mis, vehicle, results, samples, seed, duration, not no_plots)
    files |= extra
    write_all({out / name: data for name, data in files.items()})
    _print_metrics(metrics)
    click.echo(spread, nl=bool(spread))  # nothing without --samples
    click.echo(f"wrote {', '.join(sorted(files))} to {out}", err=True)


def _print_metrics(metrics: dict[str, dict[str, Any]]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="Mission metrics")
    table.add_column("metric")
    for label in metrics:
        table.add_column(label, justify="right")
    rows = [
        ("cross-track RMS (m)", "cross_track_rms", "{:.3f}"),
        ("cross-track max (m)", "cross_track_max", "{:.3f}"),
        ("depth error RMS (m)", "depth_error_rms", "{:.3f}"),
        ("heading error RMS (deg)", "heading_error_rms", "deg"),
        ("thrust impulse (N s)", "thrust_impulse", "{:.4g}"),
        ("thruster energy (J)", "thruster_energy", "{:.4g}"),
        ("saturation time (s)", "saturation_time", "{:.2f}"),
        ("completed", "completed", "{}"),
    ]
    for title, key, f in rows:
        cells = []
        for m in metrics.values():
            v = m[key]
            cells.append("–" if v is None else f"{math.degrees(v):.2f}" if f == "deg" else f.format(v))
        table.add_row(title, *cells)
    for i in range(len(next(iter(metrics.values()))["waypoint_times"])):
        cells = [
            "not reached" if m["waypoint_times"][i] is None else f"{m['waypoint_times'][i]:.1f}"
            for m in metrics.values()
        ]
        table.add_row(f"time to waypoint {i + 1} (s)", *cells)
    Console().print(table)
