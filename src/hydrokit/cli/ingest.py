"""``hydrokit ingest``: a real recording (CSV/TSV, ROS bag, ArduPilot log, video) → launch files, or
a vehicle log (ArduPilot, ROS bag) → a run file for ``hydrokit sysid`` (``--run-out``, :mod:`._run_options`).

Heavy imports stay inside the command function so ``hydrokit --help`` starts fast.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._common import write_all
from hydrokit.cli._run_options import run_options, write_run
from hydrokit.cli._types import Number


@click.command()
@click.argument("source", metavar="SOURCE", type=click.Path())
@click.option("--rig", "rig_file", default=None, type=click.Path(dir_okay=False), help="Launches: rig file (RIG.yaml).")
@click.option("--out", "out_dir", default=None, type=click.Path(file_okay=False), help="Launches: output directory.")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "rosbag", "ardupilot", "video"]),
    default=None,
    help="Default: from the extension.",
)
@click.option(
    "--time", "time_field", default=None, help="Time column (name or number), or bag/log field (default: see docs)."
)
@click.option("--signal", default=None, help="Signal column, bag field path (roll/pitch/yaw for Imu) or MESSAGE.FIELD.")
@click.option("--time-unit", type=click.Choice(["s", "ms", "us", "ns"]), default=None, help="Unit of the time column.")
@click.option("--signal-unit", default=None, help="rad, deg, m, mm or counts:SCALE (SCALE = m or rad per count).")
@click.option("--topic", default=None, help="ROS topic (default: the bag's only topic).")
@click.option("--marker", type=click.Choice(["dark", "bright"]), default="dark", help="Video: the marker's shade.")
@click.option("--roi", default=None, help="Video: search only in x,y,w,h (pixels).")
@click.option("--pivot", default=None, help="Video: pivot x,y (pixels; default: circle fit of the arc).")
@click.option(
    "--fps",
    type=Number("frames/s", above=0),
    default=None,
    help="Video: frame rate (default: the container's frame times).",
)
@click.option("--split", is_flag=True, help="One launch per release (hold → free decay) in a long recording.")
@click.option(
    "--plots", is_flag=True, help="Also write DIR/ingest.png (the launches cut) and, for a video, DIR/tracking.png."
)
@run_options
def ingest(
    source: str,
    rig_file: str,
    out_dir: str,
    fmt: str | None,
    time_field: str | None,
    signal: str | None,
    time_unit: str | None,
    signal_unit: str | None,
    topic: str | None,
    marker: str,
    roi: str | None,
    pivot: str | None,
    fps: float | None,
    split: bool,
    plots: bool,
    vehicle_file: str | None,
    run_out: str | None,
    **run: Any,
) -> None:
    """Read SOURCE and write DIR/launch_001.csv, … (the launch format of hydrokit identify) and
    DIR/ingest.json. Time in s (the source's time base), signal in m or rad. Nothing is written
    unless everything could be read. With --run-out: a run file from an ArduPilot log or a ROS bag
    (docs/ingest.md)."""
    from hydrokit.api import load_rig
    from hydrokit.errors import InputError
    from hydrokit.io.ingest import detect_format, ingest_files, read_recording

    if run_out is not None:
        launch = {"rig_file": rig_file, "out_dir": out_dir, "time_field": time_field, "signal": signal}
        launch |= {"time_unit": time_unit, "signal_unit": signal_unit, "topic": topic, "roi": roi, "pivot": pivot}
        write_run(source, fmt, run_out, vehicle_file, {**run, **launch, "fps": fps, "split": split, "plots": plots})
        return
    if rig_file is None or out_dir is None:
        raise InputError("give --rig RIG.yaml and --out DIR (launches), or --vehicle V.yaml and --run-out RUN.csv")
    rig = load_rig(rig_file)
    fmt = fmt or detect_format(source)
    rec = read_recording(
        source,
        rig,
        fmt=fmt,
        time=time_field,
        signal=signal,
        time_unit=time_unit,
        signal_unit=signal_unit,
        topic=topic,
        marker=marker,
        roi=roi,
        pivot=pivot,
        fps=fps,
    )
    texts, doc = ingest_files(rec, rig, out_dir, split=split, fmt=fmt)
    files: dict[str | Path, Any] = {p: text for p, text in texts.items()}
    if plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.ingest import recording_overview

        unit = "m" if rig.test == "spring" else "rad"
        files[Path(out_dir) / "ingest.png"] = to_png(recording_overview(rec.t, rec.y, doc["launches"], unit))
        if rec.image is not None and "tracking" in doc:
            from hydrokit.plot.ingest import video_tracking

            files[Path(out_dir) / "tracking.png"] = to_png(video_tracking(rec.image, doc["tracking"]))
    write_all(files)
    for w in doc["warnings"]:
        click.echo(f"warning: {w}", err=True)
    n = len(doc["launches"])
    click.echo(f"wrote {n} launch file(s) and ingest.json to {out_dir}", err=True)
