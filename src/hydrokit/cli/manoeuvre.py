"""``hydrokit manoeuvre``: the standard manoeuvres (turning circle, zigzag, spiral, pull-out, depth
change, vertical zigzag) of a vehicle with control surfaces (a thin layer over
:func:`hydrokit.manoeuvre.run.run_manoeuvre`)."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._identification import refuse_not_holding, strict_option
from hydrokit.cli._manoeuvre_options import manoeuvre_options
from hydrokit.cli._manoeuvre_print import print_result, print_warnings
from hydrokit.cli._replay import run_replay
from hydrokit.cli._samples import samples_options
from hydrokit.cli._service import service_line, service_record


@click.command()
@click.argument("vehicle", metavar="VEHICLE")
@manoeuvre_options
@samples_options("each metric's median and 95 % interval in manoeuvre.json (intervals), sample tracks on the plots")
@strict_option
def manoeuvre(
    vehicle: str,
    out_dir: str,
    turning_circle: float | None,
    zigzag: str | None,
    spiral: str | None,
    pull_out: float | None,
    depth_change: str | None,
    max_pitch: float | None,
    open_loop: bool | None,
    vertical_zigzag: str | None,
    replay: str | None,
    surface: str | None,
    force: list[float],
    command_text: str | None,
    initial_velocity: list[float] | None,
    dt: float,
    duration: float | None,
    loop: str,
    hold: bool | None,
    no_plots: bool,
    samples: int,
    seed: int,
    strict: bool = False,
) -> None:
    """Fly a standard manoeuvre with VEHICLE (a vehicle YAML file or bundled name): a straight
    approach until steady, then the execute; every metric is measured from the execute point
    (IMO MSC.137(76), ITTC 7.5-04-02-01).

    Writes DIR/manoeuvre.json (metrics under the manoeuvre's name; SI, *_deg in degrees),
    DIR/trajectory.csv (time,x,y,z,phi,theta,psi,u,v,w,p,q,r then one column per surface, rad;
    positions from the execute point, time 0 at the execute), track.png, time.png and report.html.
    Propulsion: --force (constant) and/or --command (the vehicle's thrusters; their thrust at the
    execute and at the end goes into manoeuvre.json's "propulsion"). Given neither, the vehicle
    file's service: condition is flown, the approach starting at its speed (one stderr line and
    manoeuvre.json's "propulsion_source": "service" and "service" say so); without one, refused.
    A manoeuvre that never reaches the heading it measures at is an error (exit 2); the track is
    still written.

    --samples N flies N vehicles drawn from the file's uncertainty: block after the nominal one,
    one after the other, and writes each metric's median and 95 % interval (manoeuvre.json's
    "intervals"); the sample tracks are drawn thin under the nominal one.

    --replay TRIAL.csv flies a recorded trial's inputs instead and writes manoeuvre.json with the
    "measured", "predicted" and "difference" metrics, trajectory.csv (measured_* and predicted_*
    states) and track.png, time.png with both tracks (docs/manoeuvre.md, "Replaying a trial").
    """
    if replay is not None:  # the manoeuvre and its inputs come from the trial
        return run_replay(**locals())
    from hydrokit.api import load_vehicle, manoeuvre_envelope, with_service
    from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all
    from hydrokit.errors import InputError
    from hydrokit.io.trajectory import table_csv
    from hydrokit.manoeuvre.run import commands_from_text, from_options, run_manoeuvre
    from hydrokit.manoeuvre.samples import add_intervals, check_samples

    out = check_out_dir(out_dir)
    kinds = dict(turning_circle=turning_circle, zigzag=zigzag, spiral=spiral, pull_out=pull_out)
    m = from_options(kinds | dict(depth_change=depth_change, vertical_zigzag=vertical_zigzag), max_pitch, open_loop)
    commands = None if command_text is None else commands_from_text(command_text)
    v = load_vehicle(vehicle)
    check_samples(v, samples)
    settings: dict[str, Any] = dict(surface=surface, tau=force, nu0=initial_velocity, dt=dt, duration=duration)
    settings, service = with_service(v, settings | dict(loop=loop, hold=hold, commands=commands))
    with progress_bar(time_based=True) as bar:
        task = bar.add_task(m.kind.replace("_", " "), total=duration)
        res = run_manoeuvre(v, m, **settings, progress=lambda t, total: bar.update(task, completed=t, total=total))
    files: dict[Any, Any] = {out / "trajectory.csv": table_csv(res.columns, res.array())}
    if res.problem:
        write_all(files)
        raise InputError(f"{res.problem}; the track was written to {out / 'trajectory.csv'}")
    # the approach against its own runs' speed, the rest against their ranges (issue #56 item 7)
    refuse_not_holding(manoeuvre_envelope(v, res, settings.get("commands"), settings.get("tau")), strict)
    if samples:
        with progress_bar() as bar:
            drawn = bar.add_task(f"{samples} drawn vehicles", total=samples)
            fly = lambda veh: run_manoeuvre(veh, m, **settings)  # noqa: E731
            add_intervals(res, v, samples, seed, fly, lambda k, n: bar.update(drawn, completed=k, total=n))
    files[out / "manoeuvre.json"] = json_text(res.to_dict() | service_record(v, service))
    if not no_plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.manoeuvre import figures
        from hydrokit.report.manoeuvre import render

        pngs = {k: to_png(f) for k, f in figures(res).items()}
        files |= {out / k: p for k, p in pngs.items()}
        files[out / "report.html"] = render(res, pngs)
    write_all(files)
    print_warnings(res.warnings)
    if service is not None:
        click.echo(service_line(v, service), err=True)
    print_result(res, samples, seed)
    click.echo(f"wrote {len(files)} files to {out}", err=True)
