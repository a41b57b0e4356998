"""Run files: one free-running dive of a vehicle for ``hydrokit sysid`` (frozen contract, issue #44).

A CSV with a header. ``time`` in s, strictly increasing. Measured motion, any subset of

    x, y, z          m, NED position
    phi, theta, psi  rad, Euler angles (``psi`` may wrap at ±π: unwrapped on reading)
    u, v, w          m/s, body velocity
    p, q, r          rad/s, body angular rate

where **an empty cell means no sample at that time** (sensors at their own rates in one file).
Inputs are given on every row and held until the next row (zero-order hold): one column per
thruster of the vehicle, named as the thruster, holding its command in the unit of that
thruster's curve (table command, rev/s for a propeller, N for an ideal thruster), or a column
``thrust:NAME`` with the measured thrust of thruster NAME in N. A vehicle with control surfaces
(issue #45) has one more input column per surface, named as the surface, holding its deflection
in rad (right-handed about its hinge axis, as ``delta(NAME)`` in the terms), held like the
commands; it is the surface's actual angle (what a rudder-angle sensor logs), so the servo lag
and rate limit of the vehicle file do not act on it again. Columns matching none of these are
ignored with a warning naming them. ``#`` lines are comments.

Measured disturbances (issue #48 item 4), optional, in pairs: ``wind_speed`` (m/s) and
``wind_direction`` (rad, true, the direction the wind blows *from*, clockwise from North), read
only for a vehicle with a wind model (``wind:`` block; without one they are an error, not
ignored); ``current_speed`` (m/s) and ``current_direction`` (rad, the direction the current flows
*towards*, clockwise from North — the oceanographic convention). Empty cells are filled linearly
between the samples (held beyond them).

Bad input is one :class:`~hydrokit.errors.InputError` line naming the file, the column and the
value: time not increasing, a thruster with no column, a ``thrust:`` column naming no thruster,
a control surface with no column (a surface that did not move needs a column of zeros: flying
a log whose rudder moved as if it had not would bias every estimate silently), a deflection
beyond the surface's ``max_deflection_deg`` (naming the row), no motion channel, text where a
number belongs, an input cell left empty.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.names import POSE_SYMBOLS, VELOCITY_SYMBOLS
from hydrokit.core.validate import cut
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text

#: the motion channels a run file may hold, in state order (m, rad, m/s, rad/s)
MOTION_CHANNELS: tuple[str, ...] = (*POSE_SYMBOLS, *VELOCITY_SYMBOLS)
#: prefix of a measured-thrust column (N)
THRUST_PREFIX = "thrust:"
#: a deflection this far past a surface's limit (rad; 9 significant digits of a file) is still within it
DEFLECTION_TOLERANCE = 1e-9
#: measured disturbances (frozen, issue #48 item 4): m/s, rad (wind true, from; current towards)
ENVIRONMENT_COLUMNS = ("wind_speed", "wind_direction", "current_speed", "current_direction")
#: the largest run file read, characters (a 90 s log at 50 Hz is about 1 MB)
MAX_RUN_CHARS = 200_000_000


@dataclass(frozen=True)
class RunLog:
    """One run file in SI units.

    Attributes
    ----------
    name : str — the file's stem (used in reports)
    source : str — the file path
    time : (n,) — row times, s, strictly increasing
    channels : mapping channel → (t, y): sample times (s) and values (m, rad, m/s, rad/s) of
        every measured motion channel (``psi`` unwrapped)
    commands : mapping thruster → (n,) — command on each row (curve unit), held to the next row
    thrusts : mapping thruster → (n,) — measured thrust on each row, N (``thrust:NAME`` columns)
    deflections : mapping surface → (n,) — deflection on each row, rad, held to the next row; in
        the order of the surface names given to :func:`read_run` (the vehicle's file order)
    environment : mapping column → (n,) — the measured wind and current on each row
        (``ENVIRONMENT_COLUMNS``: m/s, rad), empty when the file has none
    warnings : tuple of str — ignored columns and other oddities
    """

    name: str
    source: str
    time: np.ndarray
    channels: Mapping[str, tuple[np.ndarray, np.ndarray]]
    commands: Mapping[str, np.ndarray] = field(default_factory=dict)
    thrusts: Mapping[str, np.ndarray] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    deflections: Mapping[str, np.ndarray] = field(default_factory=dict)
    environment: Mapping[str, np.ndarray] = field(default_factory=dict)

    def environment_table(self) -> np.ndarray | None:
        """The run's current and wind as the integrators take them (rows [t, v_N, v_E, v_D, w_N, w_E],
        m/s; :func:`hydrokit.model.dynamics.environment_table`), None when it logged neither."""
        if not self.environment:
            return None
        from hydrokit.model.dynamics import environment_table

        env, t = self.environment, self.time
        current = None
        if "current_speed" in env:
            c, d = env["current_speed"], env["current_direction"]
            current = np.column_stack([t, c * np.cos(d), c * np.sin(d), np.zeros_like(t)])
        wind = np.column_stack([t, env["wind_speed"], env["wind_direction"]]) if "wind_speed" in env else None
        return environment_table(current, wind)

    @property
    def duration(self) -> float:
        """Length of the run, s."""
        return float(self.time[-1] - self.time[0])

    def describe(self) -> str:
        """One line: name, duration and the channels with their sample counts."""
        chans = ", ".join(f"{c} ({t.size})" for c, (t, _) in self.channels.items())
        inputs = f"{len(self.commands)} command(s)" + (f", {len(self.thrusts)} thrust(s)" if self.thrusts else "")
        inputs += f", {len(self.deflections)} deflection(s)" if self.deflections else ""
        return f"{self.name}: {self.duration:.1f} s, {self.time.size} rows; {chans}; {inputs}"


def _cell(text: str, line: int, column: str, src: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"line {line}, column '{cut(column)}' = {cut(repr(text))}: expected a number", src) from None
    if not math.isfinite(v):
        raise InputError(f"line {line}, column '{cut(column)}' = {cut(text)}: expected a finite number", src)
    return v


def read_run(
    path: str | os.PathLike[str],
    thrusters: Sequence[str],
    surfaces: Sequence[str] = (),
    max_deflection: Sequence[float] | np.ndarray | None = None,
    wind_model: bool = True,
) -> RunLog:
    """Read a run file for a vehicle whose thrusters are named ``thrusters`` (file order).

    Parameters
    ----------
    path : str or path — the CSV (module docstring)
    thrusters : sequence of str — the vehicle's thruster names; each needs a command column
        or a ``thrust:NAME`` column
    surfaces : sequence of str — the vehicle's control-surface names (file order); each needs
        a column of deflections, rad
    max_deflection : sequence of float or None — each surface's limit, rad (``max_deflection_deg``
        of the vehicle file); a deflection beyond it is an error. None: not checked
    wind_model : bool — the vehicle has a wind model; False: wind columns are an error

    Returns
    -------
    RunLog — SI; ``psi`` unwrapped

    Raises
    ------
    InputError
        One line naming the file, column and value (see the module docstring).
    """
    p = Path(path)
    src = str(p)
    text = read_text(p, "a run CSV")
    if len(text) > MAX_RUN_CHARS:
        raise InputError(f"file of {len(text)} characters; expected a run file under {MAX_RUN_CHARS}", src)
    # the file's own line numbers (1-based, comments and blank lines counted) for the errors
    numbered = [(k + 1, ln) for k, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    if len(numbered) < 3:
        raise InputError(f"{max(len(numbered) - 1, 0)} data row(s); expected a header with 'time' and ≥ 2 rows", src)
    rows = list(csv.reader([ln for _, ln in numbered]))
    line_of = [k for k, _ in numbered]  # line_of[j]: the file line of rows[j] (rows[0] the header)
    header = [h.strip() for h in rows[0]]
    dup = next((h for h in header if header.count(h) > 1), None)
    if dup is not None:
        raise InputError(f"column '{cut(dup)}' appears twice in the header; expected each column once", src)
    if "time" not in header:
        raise InputError(f"no column 'time' (header: {cut(', '.join(header))}); expected time in s", src)
    names = set(thrusters)
    surf = list(surfaces)
    clash = next((n for n in surf if n in names or n in MOTION_CHANNELS or n == "time"), None)
    if clash is not None:
        raise InputError(
            f"control surface '{cut(clash)}' has the name of a thruster or channel; expected distinct column names",
            src,
        )
    limits = None if max_deflection is None else np.asarray(max_deflection, float)
    if limits is not None and limits.shape != (len(surf),):
        raise InputError(
            f"{limits.size} deflection limit(s) for {len(surf)} control surface(s); expected one each", src
        )
    motion = [c for c in header if c in MOTION_CHANNELS]
    cmd_cols = [c for c in header if c in names]
    def_cols = [c for c in surf if c in header]
    thr_cols = [c for c in header if c.startswith(THRUST_PREFIX)]
    for c in thr_cols:
        if c[len(THRUST_PREFIX) :] not in names:
            raise InputError(
                f"column '{cut(c)}' names no thruster of the vehicle (thrusters: {cut(', '.join(thrusters))}); "
                "expected thrust:NAME with NAME a thruster",
                src,
            )
    env_cols = [c for c in ENVIRONMENT_COLUMNS if c in header]
    for a, b in (ENVIRONMENT_COLUMNS[:2], ENVIRONMENT_COLUMNS[2:]):
        if (a in header) != (b in header):
            raise InputError(
                f"column '{a if a in header else b}' without '{b if a in header else a}'; expected both", src
            )
    if "wind_speed" in header and not wind_model:
        raise InputError(
            "columns wind_speed, wind_direction but the vehicle has no wind model; expected a 'wind:' block in the "
            "vehicle file (docs/model.md)",
            src,
        )
    used = {"time", *motion, *cmd_cols, *thr_cols, *def_cols, *env_cols}
    ignored = [c for c in header if c not in used]
    for name in thrusters:
        both = name in cmd_cols and THRUST_PREFIX + name in thr_cols
        if both:
            raise InputError(f"thruster '{name}' has both a command column and a thrust column; expected one", src)
        if name not in cmd_cols and THRUST_PREFIX + name not in thr_cols:
            hint = f" (ignored columns: {cut(', '.join(ignored))})" if ignored else ""
            raise InputError(
                f"no column for thruster '{name}'{hint}; expected a column '{name}' (its command) or "
                f"'{THRUST_PREFIX}{name}' (thrust, N)",
                src,
            )
    for name in surf:
        if name not in def_cols:
            hint = f" (ignored columns: {cut(', '.join(ignored))})" if ignored else ""
            raise InputError(
                f"no column for control surface '{cut(name)}'{hint}; expected a column '{cut(name)}' with its "
                "deflection in rad (a column of zeros if it did not move)",
                src,
            )
    if not motion:
        raise InputError(
            f"no motion channel (header: {cut(', '.join(header))}); expected at least one of {', '.join(MOTION_CHANNELS)}",
            src,
        )
    idx = {c: header.index(c) for c in header}
    n = len(rows) - 1
    time = np.empty(n)
    inputs = {c: np.empty(n) for c in (*cmd_cols, *thr_cols, *def_cols)}
    values = {c: np.full(n, np.nan) for c in (*motion, *env_cols)}
    width = len(header)
    for k, row in enumerate(rows[1:]):
        line = line_of[k + 1]
        if len(row) < width:
            row = row + [""] * (width - len(row))
        time[k] = _cell(row[idx["time"]].strip(), line, "time", src)
        for c, arr in inputs.items():
            cell = row[idx[c]].strip()
            if not cell:
                raise InputError(f"line {line}, column '{cut(c)}' is empty; expected the input on every row", src)
            arr[k] = _cell(cell, line, c, src)
        for c, arr in values.items():
            cell = row[idx[c]].strip()
            if cell:
                arr[k] = _cell(cell, line, c, src)
    if limits is not None:
        for c, lim in zip(surf, limits):
            over = np.nonzero(np.abs(inputs[c]) > lim + DEFLECTION_TOLERANCE)[0]
            if over.size:
                k = int(over[0])
                raise InputError(
                    f"line {line_of[k + 1]}, column '{cut(c)}' = {inputs[c][k]:.6g} rad ({math.degrees(inputs[c][k]):.4g}°) is "
                    f"beyond the surface's limit; expected |deflection| ≤ {lim:.6g} rad "
                    f"({math.degrees(lim):.4g}°, max_deflection_deg)",
                    src,
                )
    bad = np.nonzero(np.diff(time) <= 0)[0]
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"column 'time' = {time[i + 1]:.9g} at line {line_of[i + 2]} after {time[i]:.9g}; expected strictly increasing "
            "times (s)",
            src,
        )
    channels: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for c in MOTION_CHANNELS:
        if c not in values:
            continue
        ok = np.isfinite(values[c])
        t, y = time[ok], values[c][ok]
        if t.size == 0:
            continue
        if c == "psi":
            y = np.unwrap(y)
        channels[c] = (t, y)
    if not channels:
        raise InputError(f"motion column(s) {', '.join(motion)} hold no sample; expected measured motion", src)
    environment = {}
    for c in env_cols:
        ok = np.isfinite(values[c])
        if not ok.any():
            raise InputError(f"column '{c}' holds no sample; expected the measured value (m/s, rad)", src)
        if c.endswith("_speed") and np.any(values[c][ok] < 0):
            raise InputError(f"column '{c}' = {values[c][ok].min():.6g}: expected a speed ≥ 0 (m/s)", src)
        y = np.unwrap(values[c][ok]) if c.endswith("_direction") else values[c][ok]
        environment[c] = np.interp(time, time[ok], y)
    warnings = (f"ignored column(s) matching nothing: {cut(', '.join(ignored))}",) if ignored else ()
    return RunLog(
        p.stem,
        src,
        time,
        channels,
        {c: inputs[c] for c in cmd_cols},
        {c[len(THRUST_PREFIX) :]: inputs[c] for c in thr_cols},
        warnings,
        {c: inputs[c] for c in surf},
        environment,
    )


def read_runs(runs: Sequence[Any], vehicle: Any) -> list[Any]:
    """The runs of ``vehicle`` as :class:`RunLog` s: every path read with the vehicle's thruster
    names, control-surface names and deflection limits (one reader for the API, the CLI and
    the main job, so no caller forgets the surfaces); a run already read (anything with
    ``channels``) is passed through.

    Parameters
    ----------
    runs : sequence of path or RunLog — run CSVs (module docstring) or runs already read
    vehicle : Vehicle — with ``thrusters`` (None: no command column expected) and ``surfaces``

    Raises
    ------
    InputError
        As :func:`read_run`, naming the file.
    """
    names = vehicle.thrusters.names if vehicle.thrusters is not None else []
    surf = vehicle.surfaces
    wind = getattr(vehicle, "wind", None) is not None
    return [r if hasattr(r, "channels") else read_run(r, names, surf.names, surf.max_deflection, wind) for r in runs]


def _num(v: float) -> str:
    return "" if not math.isfinite(v) else f"{v:.9g}"


def run_csv(
    time: np.ndarray,
    channels: Mapping[str, np.ndarray],
    commands: Mapping[str, np.ndarray],
    thrusts: Mapping[str, np.ndarray] | None = None,
    comment: str = "",
    deflections: Mapping[str, np.ndarray] | None = None,
) -> str:
    """CSV text of a run file.

    Parameters
    ----------
    time : (n,) — s, strictly increasing
    channels : channel → (n,) values on the rows, NaN where there is no sample (SI)
    commands : thruster → (n,) commands (curve unit), held to the next row
    thrusts : thruster → (n,) measured thrusts, N (written as ``thrust:NAME``)
    comment : str — written as ``#`` lines at the top
    deflections : surface → (n,) deflections, rad, held to the next row (written as NAME)
    """
    unknown = [c for c in channels if c not in MOTION_CHANNELS]
    if unknown:
        raise InputError(f"channel(s) {', '.join(unknown)}: expected some of {', '.join(MOTION_CHANNELS)}")
    cols = [c for c in MOTION_CHANNELS if c in channels]
    data = [np.asarray(channels[c], float) for c in cols]
    heads = ["time", *cols, *commands, *(THRUST_PREFIX + k for k in (thrusts or {})), *(deflections or {})]
    data += [np.asarray(v, float) for v in commands.values()]
    data += [np.asarray(v, float) for v in (thrusts or {}).values()]
    data += [np.asarray(v, float) for v in (deflections or {}).values()]
    out = io.StringIO()
    for line in comment.splitlines():
        out.write(f"# {line}\n")
    out.write(",".join(heads) + "\n")
    for k, t in enumerate(np.asarray(time, float)):
        out.write(f"{t:.9g}," + ",".join(_num(float(a[k])) for a in data) + "\n")
    return out.getvalue()
