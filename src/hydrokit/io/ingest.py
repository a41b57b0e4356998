"""Real recordings in (issue #12): a CSV/TSV table, a ROS bag, an ArduPilot log or a pendulum
video → launch files.

:func:`read_recording` reads one signal against time from any supported source (SI units,
the file's own time base); :func:`ingest_files` cuts it into launches (one, or one per
release with ``split``) and returns every output — launch CSVs in the format
:func:`hydrokit.io.launch.read_launch` reads, and ``ingest.json`` — without writing anything.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig
from hydrokit.io.recording import TIME_UNITS, Recording, check_times, signal_scale

__all__ = ["FORMATS", "Recording", "detect_format", "ingest_files", "read_recording"]

FORMATS = ("csv", "rosbag", "ardupilot", "video")
EXTENSIONS = {
    ".csv": "csv",
    ".tsv": "csv",
    ".txt": "csv",
    ".db3": "rosbag",
    ".mcap": "rosbag",
    ".bag": "rosbag",
    ".bin": "ardupilot",
    ".tlog": "ardupilot",
    ".mp4": "video",
    ".avi": "video",
    ".mov": "video",
    ".mkv": "video",
}


def detect_format(path: str | os.PathLike[str]) -> str:
    """``csv``, ``rosbag``, ``ardupilot`` or ``video`` from the extension (a folder is a rosbag2 bag)."""
    p = Path(path)
    if not p.exists():
        raise InputError("no such file or folder", str(p))
    if p.is_dir():
        return "rosbag"
    fmt = EXTENSIONS.get(p.suffix.lower())
    if fmt is None:
        known = ", ".join(sorted(EXTENSIONS))
        raise InputError(f"cannot tell the format from the extension {p.suffix!r} ({known}); give --format", str(p))
    return fmt


def read_recording(
    source: str | os.PathLike[str],
    rig: Rig,
    *,
    fmt: str | None = None,
    time: str | None = None,
    signal: str | None = None,
    time_unit: str | None = None,
    signal_unit: str | None = None,
    topic: str | None = None,
    marker: str = "dark",
    roi: str | tuple[float, ...] | None = None,
    pivot: str | tuple[float, ...] | None = None,
    fps: float | None = None,
) -> Recording:
    """Read the signal of ``source`` in SI (see docs/ingest.md for each format's defaults).
    ``marker``, ``roi``, ``pivot`` (pixels, ``"x,y,w,h"`` / ``"x,y"``) and ``fps`` are for video."""
    fmt = fmt or detect_format(source)
    if fmt not in FORMATS:
        raise InputError(f"--format {fmt!r}: expected one of {', '.join(FORMATS)}")
    if time_unit is not None and time_unit not in TIME_UNITS:
        raise InputError(f"--time-unit {time_unit!r}: expected s, ms, us or ns")
    unit = signal_scale(signal_unit, rig) if signal_unit else None
    if fmt == "csv":
        from hydrokit.io.table import read_table

        rec = read_table(source, rig, time=time, signal=signal, time_unit=time_unit or "s", unit=unit)
    elif fmt == "video":
        from hydrokit.io.video import read_video

        if rig.test == "spring":
            raise InputError("video tracks a rod angle: a spring rig records a position", str(source))
        rec = read_video(source, marker=marker, roi=roi, pivot=pivot, fps=fps)
    elif fmt == "rosbag":
        from hydrokit.io.rosbag import read_bag

        rec = read_bag(source, topic=topic, signal=signal, unit=unit, time_unit=time_unit, time=time)
    else:
        from hydrokit.io.ardupilot import read_log

        rec = read_log(source, signal=signal, unit=unit, time_unit=time_unit, time=time)
    check_times(rec.t, rec.source)
    if rig.test != "spring" and float(np.max(np.abs(rec.y))) > math.pi / 2:
        msg = f"the signal reaches {float(np.max(np.abs(rec.y))):.4g} rad (> 90°): is it really in the unit given?"
        rec = dataclasses.replace(rec, warnings=(*rec.warnings, msg))
    return rec


def ingest_files(
    rec: Recording, rig: Rig, out_dir: str | os.PathLike[str], *, split: bool = False, fmt: str = ""
) -> tuple[dict[Path, str], dict[str, Any]]:
    """Launch CSVs and ``ingest.json`` for ``rec``: ``({path: text}, ingest document)``.

    Raises
    ------
    InputError
        No release found (``split``), or a record without any motion.
    """
    from hydrokit.identify.split import Segment, find_release, split_launches
    from hydrokit.io.launch import launch_csv

    t, y = rec.t, rec.y
    rate = 1.0 / float(np.median(np.diff(t)))
    if rate > 5000.0:
        raise InputError(f"sample rate {rate:.4g} Hz: launch files keep 0.1 ms; decimate below 5 kHz", rec.source)
    if split:
        segments = split_launches(t, y, file=rec.source)
        if not segments:
            raise InputError("--split: no release found (no still hold followed by a free decay)", rec.source)
    else:
        if float(np.ptp(y)) == 0.0:
            raise InputError("no release found: the signal never moves", rec.source)
        segments = [Segment(0, find_release(t, y), t.size - 1)]
    column = "position" if rig.test == "spring" else "angle"
    out = Path(out_dir)
    files: dict[Path, str] = {}
    launches: list[dict[str, Any]] = []
    for k, s in enumerate(segments, start=1):
        name = f"launch_{k:03d}.csv"
        tt, yy = t[s.start : s.end + 1], y[s.start : s.end + 1]
        notes = [*rec.notes, "time kept in the source's time base (not re-based to 0)"]
        if s.release == 0 and not split:
            notes.append("no still hold found before the motion: the record starts at the release")
        warn = list(rec.warnings)
        dts = np.diff(tt)
        gaps = int(np.sum(dts > 3.0 * np.median(dts)))
        if gaps:
            warn.append(f"{gaps} gap(s) longer than 3 sample intervals (longest {dts.max():.3g} s): dropped samples?")
        if not split:
            from hydrokit.identify.preprocess import check_record, trim_launch
            from hydrokit.identify.types import Launch

            try:
                check_record(trim_launch(Launch(tt, yy, rec.source), release=float(t[s.release])))
            except InputError as exc:
                warn.append(f"not a usable free decay: {exc.detail}")
        head = [
            f"hydrokit ingest: {rec.source}, {rec.signal}",
            f"{column} in SI ({'m' if column == 'position' else 'rad'})",
        ]
        files[out / name] = launch_csv(tt, yy, column, head)
        launches.append(
            {
                "file": name,
                "source": rec.source,
                "signal": rec.signal,
                "start_time": float(tt[0]),
                "end_time": float(tt[-1]),
                "release_time": float(t[s.release]),
                "samples": int(tt.size),
                "rate": float(1.0 / np.median(np.diff(tt))),
                "notes": notes,
                "warnings": warn,
            }
        )
    doc = {
        "source": rec.source,
        "format": fmt,
        "rig": {"test": rig.test, "axis": rig.axis, "file": rig.source},
        "units": {
            "time": "s",
            "start_time": "s",
            "end_time": "s",
            "release_time": "s",
            "rate": "Hz",
            column: "m" if column == "position" else "rad",
        },
        "split": split,
        "recording": {"samples": int(t.size), "start_time": float(t[0]), "end_time": float(t[-1]), "rate": rate},
        "launches": launches,
        **({"tracking": rec.details} if rec.details is not None else {}),
        "warnings": sorted({w for d in launches for w in d["warnings"]}),
    }
    files[out / "ingest.json"] = json.dumps(doc, indent=2, allow_nan=False, ensure_ascii=False) + "\n"
    return files, doc
