"""``hydrokit ingest LOG --vehicle V.yaml --run-out RUN.csv``: the options and the step that write a
run file (issue #44) from an ArduPilot log or a ROS bag. The logic is in :mod:`hydrokit.io.runfile`."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from hydrokit.cli._types import Count, Number

#: launch-only options of ``hydrokit ingest`` (refused with --run-out)
LAUNCH_ONLY = (
    "rig_file",
    "out_dir",
    "time_field",
    "signal",
    "time_unit",
    "signal_unit",
    "topic",
    "roi",
    "pivot",
    "fps",
)
LAUNCH_FLAGS = ("split", "plots")

RUN_OPTIONS = [
    click.option(
        "--vehicle", "vehicle_file", default=None, help="Run file: vehicle file (thrusters with channel/motor)."
    ),
    click.option(
        "--run-out",
        default=None,
        type=click.Path(dir_okay=False),
        help="Write a run file RUN.csv (and RUN.json) for hydrokit sysid, instead of launches.",
    ),
    click.option(
        "--surface-pressure",
        type=Number("Pa", above=0),
        default=None,
        help="Run file: pressure at the surface, Pa (default: mean of the depth sensor's first 1 s).",
    ),
    click.option("--start", type=Number("s"), default=None, help="Run file: keep from this time, s (log clock)."),
    click.option("--end", type=Number("s"), default=None, help="Run file: keep up to this time, s (log clock)."),
    click.option(
        "--baro",
        type=Count(at_least=0),
        default=None,
        help="Run file: barometer instance of the depth sensor (0-based).",
    ),
    click.option("--imu-topic", default=None, help="Run file, ROS bag: sensor_msgs/Imu topic (attitude, rad/s)."),
    click.option("--pressure-topic", default=None, help="Run file, ROS bag: sensor_msgs/FluidPressure topic, Pa."),
    click.option("--depth-topic", default=None, help="Run file, ROS bag: depth as a pose/odometry/Float64 topic, m."),
    click.option("--dvl-topic", default=None, help="Run file, ROS bag: DVL twist topic (body velocity, m/s)."),
    click.option(
        "--command-topic",
        default=None,
        help="Run file, ROS bag: thruster commands (Float64MultiArray by channel; mavros RCOut in µs).",
    ),
    click.option(
        "--ros-frame",
        type=click.Choice(["enu", "ned"]),
        default="enu",
        help="Run file, ROS bag: frames of the bag (enu = REP 103 ENU/FLU, converted to NED/FRD).",
    ),
]


def run_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the run-file options to a click command."""
    for opt in reversed(RUN_OPTIONS):
        f = opt(f)
    return f


def write_run(source: str, fmt: str | None, run_out: str, vehicle_file: str | None, kw: dict[str, Any]) -> None:
    """Read ``source``, build the run file and write RUN.csv and RUN.json (all or nothing)."""
    from hydrokit.api import load_vehicle
    from hydrokit.cli._common import write_all
    from hydrokit.errors import InputError
    from hydrokit.io.runfile import log_to_run, read_channels

    given = [k for k in LAUNCH_ONLY if kw.get(k) is not None] + [k for k in LAUNCH_FLAGS if kw.get(k)]
    if given:
        raise InputError(
            f"--run-out writes a run file: --{given[0].replace('_file', '').replace('_dir', '').replace('_', '-')} is for launches"
        )
    if vehicle_file is None:
        raise InputError("--run-out needs --vehicle V.yaml (its thrusters, with channel/motor, and its water)")
    vehicle = load_vehicle(vehicle_file)
    if vehicle.thrusters is None:
        raise InputError("the vehicle has no 'thrusters' list: a run file holds their commands", vehicle_file)
    topics = {k: kw.get(f"{k}_topic") for k in ("imu", "pressure", "depth", "dvl", "command")}
    ch = read_channels(source, fmt=fmt, baro=kw.get("baro"), topics=topics, ros_frame=kw.get("ros_frame") or "enu")
    run = log_to_run(
        ch,
        vehicle.thrusters,
        density=vehicle.density,
        gravity=vehicle.gravity,
        surface_pressure=kw.get("surface_pressure"),
        start=kw.get("start"),
        end=kw.get("end"),
    )
    write_all(run.files(run_out))
    d = run.to_dict()
    chans = ", ".join(f"{c} {v['rate']:.3g} Hz" for c, v in d["channels"].items())
    click.echo(f"{source}: {d['duration']:.1f} s ({d['start_time']:.3f}…{d['end_time']:.3f} s), {chans}", err=True)
    for w in d["warnings"]:
        click.echo(f"warning: {w}", err=True)
    click.echo(f"wrote {run_out} ({d['rows']} rows, {len(d['thrusters'])} thrusters) and its .json summary", err=True)
