"""``hydrokit simulate``: open-loop simulation of a vehicle file or bundled vehicle."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._command import command_force, command_options, simulator
from hydrokit.cli._deflection import deflection_input, deflection_options
from hydrokit.cli._identification import refuse_not_holding, strict_option
from hydrokit.cli._manoeuvre_print import print_warnings
from hydrokit.cli._samples import check_samples, sampled_files, samples_options
from hydrokit.cli._service import no_service_option, service_line, simulate_service
from hydrokit.cli._types import SECONDS, Count, Numbers
from hydrokit.cli._wind import wind_input, wind_options


@click.command()
@click.argument("vehicle", metavar="VEHICLE")
@click.option("--duration", type=SECONDS, default=60.0, show_default=True, help="Simulated time, s.")
@click.option("--dt", type=SECONDS, default=0.01, show_default=True, help="Integration step, s.")
@click.option(
    "--force",
    type=Numbers(6, "N, N·m"),
    default="0,0,0,0,0,0",
    show_default=True,
    help="Constant force X,Y,Z,K,M,N (body): N, N·m.",
)
@click.option(
    "--force-csv",
    type=click.Path(dir_okay=False),
    default=None,
    help="Force over time instead: CSV with time,X,Y,Z,K,M,N (s, N, N·m), interpolated linearly.",
)
@click.option(
    "--initial-velocity", type=Numbers(6, "m/s, rad/s"), help="Initial u,v,w,p,q,r: m/s and rad/s (default 0)."
)
@click.option(
    "--initial-pose", type=Numbers(6, "m, rad"), help="Initial x,y,z,phi,theta,psi: m (NED) and rad (default 0)."
)
@click.option("--current-ned", type=Numbers(3, "m/s"), help="Constant ocean current vx,vy,vz in north-east-down: m/s.")
@click.option(
    "--integrator",
    type=click.Choice(["rk4", "dop853", "rk45", "rk4-numpy"]),
    default="rk4",
    show_default=True,
    help="rk4: compiled fixed step (as the sources); dop853/rk45: scipy adaptive (no unit).",
)
@click.option(
    "--attitude",
    type=click.Choice(["euler", "quaternion"]),
    default="euler",
    show_default=True,
    help="Attitude representation (quaternions have no singularity at pitch ±90°).",
)
@click.option("--output-every", type=Count(1), default=1, show_default=True, help="Write every N-th step (count).")
@click.option(
    "--out",
    "out_file",
    required=True,
    type=click.Path(dir_okay=False),
    help="Trajectory CSV: time,x,y,z,phi,theta,psi,u,v,w,p,q,r (s, m, rad, m/s, rad/s).",
)
@click.option(
    "--plots", "plots_dir", type=click.Path(file_okay=False), help="Write states.png, path.png here (folder)."
)
@deflection_options
@wind_options
@command_options
@no_service_option
@samples_options("OUT_envelope.csv (5/50/95 %, min, max per state and time; SI), OUT_samples.csv, envelope.png")
@strict_option
def simulate(
    vehicle: str,
    duration: float,
    dt: float,
    force: list[float],
    force_csv: str | None,
    initial_velocity: list[float] | None,
    initial_pose: list[float] | None,
    current_ned: list[float] | None,
    wind: Any,
    integrator: str,
    attitude: str,
    output_every: int,
    out_file: str,
    plots_dir: str | None,
    samples: int,
    seed: int,
    deflection: str | None,
    deflection_csv: str | None,
    command_text: str | None,
    command_csv: str | None,
    no_service: bool,
    strict: bool = False,
) -> None:
    """Simulate VEHICLE (a vehicle YAML file or a bundled name: bluerov2-heavy, minerva,
    lingyun, udrobot) under a constant or tabulated force and/or its thrusters' commands
    (--command, --command-csv), from rest unless told otherwise. Given none of these, a vehicle
    file with a service: block flies its service condition (one stderr line says which; see
    --no-service); deflections and --initial-velocity do not propel."""
    from hydrokit.api import load_vehicle, simulate_envelope  # with its thrusters: --command drives them
    from hydrokit.cli._common import check_out_dir, check_out_file, progress_bar, write_all

    check_out_file(out_file, "--out")  # before the run: it must not be lost to a bad path
    if plots_dir:
        check_out_dir(plots_dir, "--plots")
    v = load_vehicle(vehicle)
    tau: Any = force
    if force_csv is not None:
        from hydrokit.io.trajectory import read_force_table

        tau = read_force_table(force_csv)
    nu0, eta0, cur = initial_velocity or [0.0] * 6, initial_pose or [0.0] * 6, wind_input(v, current_ned, wind)
    delta = deflection_input(v, deflection, deflection_csv)
    check_samples(v, samples, force_csv or deflection_csv, integrator, attitude)  # before the run, like every input
    tau = command_force(v, command_text, command_csv, tau, cur, samples)
    given = no_service or any(x is not None for x in (force_csv, command_text, command_csv))
    tau, service = simulate_service(v, tau, given, samples, integrator, attitude, cur)
    from hydrokit.io.trajectory import trajectory_csv

    run = simulator(tau, integrator, attitude)  # the driver, or the thrusters' own loop under --command
    with progress_bar(time_based=True) as bar:
        task = bar.add_task("simulating", total=duration)
        advance = lambda t: bar.update(task, completed=t)  # noqa: E731
        traj = run(v, duration, dt, tau, eta0, nu0, cur, integrator, attitude, output_every, advance, delta)
    refuse_not_holding(simulate_envelope(v, traj, tau, delta), strict)  # the identification's runs (#56)
    import numpy as np

    files = {out_file: trajectory_csv(np.column_stack([traj.time, traj.eta, traj.nu])).encode()}
    if plots_dir:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.vehicle import path_figure, states_figure

        files[str(Path(plots_dir) / "states.png")] = to_png(states_figure(traj, f"{v.name}: states"))
        files[str(Path(plots_dir) / "path.png")] = to_png(path_figure(traj, f"{v.name}: path"))
    setup = (duration, dt, tau, eta0, nu0, cur, output_every, delta)
    extra, spread = sampled_files(v, traj, samples, seed, setup, out_file, plots_dir)
    write_all(files | extra)
    print_warnings(traj.warnings)
    if service is not None:
        click.echo(service_line(v, service), err=True)
    u, p = (", ".join(f"{x:.4g}" for x in part) for part in (traj.nu[-1][:3], traj.nu[-1][3:]))
    click.echo(f"final velocity u,v,w (m/s) = {u}; p,q,r (rad/s) = {p}" + spread)
    click.echo(
        f"wrote {out_file} ({traj.time.size} rows)" + (f" and plots to {plots_dir}" if plots_dir else ""), err=True
    )
