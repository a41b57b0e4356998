"""Launch files (CSV), format frozen by issue #2.

Optional comment lines starting with ``#``, a header row, then numbers. Columns: ``time`` (s)
and ``position`` (m, spring) or ``angle`` (rad, pendulum and torsion); ``angle_deg`` (degrees)
is accepted instead of ``angle``. Extra columns are ignored. One launch per file.
"""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Launch, Rig
from hydrokit.io.yamlfile import read_text

#: an ``angle`` column whose largest magnitude exceeds this (rad) is almost surely in degrees
#: (a pendulum launched beyond 90°, or a torsion rig past a full turn, is not a free-decay test)
DEGREE_SUSPECT_PENDULUM = math.pi / 2
DEGREE_SUSPECT_TORSION = 2 * math.pi


def read_launch(path: str | os.PathLike[str], rig: Rig) -> Launch:
    """Read one launch for ``rig`` (signal in m for the spring, rad otherwise).

    Raises
    ------
    InputError
        Missing file or column, a cell that is not a number, NaN, non-monotonic or duplicate
        time, an ``angle`` column that looks like degrees, too few rows.
    """
    p = Path(path)
    src = str(p)
    text = read_text(p, "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError("no header row; expected a CSV with columns time and position/angle/angle_deg", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip().lower() for h in rows[0]]
    want = "position" if rig.translational_signal else ("angle" if "angle" in header else "angle_deg")
    if "time" not in header:
        raise InputError(f"missing column 'time' (header: {', '.join(header)})", src)
    if want not in header:
        expected = "'position' (m)" if rig.translational_signal else "'angle' (rad) or 'angle_deg'"
        raise InputError(f"missing column {expected} for a {rig.test} rig (header: {', '.join(header)})", src)
    it, iy = header.index("time"), header.index(want)
    t = np.empty(len(rows) - 1)
    y = np.empty(len(rows) - 1)
    for k, row in enumerate(rows[1:]):
        line_no = k + 2
        for arr, idx, name in ((t, it, "time"), (y, iy, want)):
            try:
                cell = row[idx].strip()
                arr[k] = float(cell)
            except IndexError:
                raise InputError(
                    f"row {line_no}: column '{name}' is missing; expected {len(header)} cells", src
                ) from None
            except ValueError:
                raise InputError(f"row {line_no}, column '{name}' = {cell!r}: expected a number", src) from None
            if not math.isfinite(arr[k]):
                raise InputError(
                    f"row {line_no}, column '{name}' = {cell}: expected a finite number (NaN/inf found)", src
                )
    if t.size < 20:
        raise InputError(f"only {t.size} data rows; expected a launch of at least 20 samples", src)
    dt = np.diff(t)
    if np.any(dt == 0):
        k = int(np.nonzero(dt == 0)[0][0])
        raise InputError(
            f"column 'time': duplicate time {t[k]:g} s at rows {k + 2} and {k + 3}; expected strictly increasing times",
            src,
        )
    if np.any(dt < 0):
        k = int(np.nonzero(dt < 0)[0][0])
        raise InputError(
            f"column 'time': time goes back from {t[k]:g} to {t[k + 1]:g} s at row {k + 3}; expected strictly increasing times",
            src,
        )
    notes: list[str] = []
    if want == "angle_deg":
        y = np.radians(y)
        notes.append("angle_deg converted to rad")
    elif want == "angle":
        limit = DEGREE_SUSPECT_PENDULUM if rig.test == "pendulum" else DEGREE_SUSPECT_TORSION
        peak = float(np.max(np.abs(y)))
        if peak > limit:
            raise InputError(
                f"column 'angle' reaches {peak:.4g}, which looks like degrees; expected radians "
                f"(|angle| ≤ {limit:.3g}) — name the column 'angle_deg' for degrees",
                src,
            )
    return Launch(t=t, y=y, file=src, notes=tuple(notes))


def launch_csv(t: np.ndarray, y: np.ndarray, column: str, comments: list[str] | tuple[str, ...] = ()) -> str:
    """A launch file's text (comments, header ``time,<column>``, rows)."""
    out = [f"# {c}" for c in comments]
    out.append(f"time,{column}")
    digits = 6 if column == "position" else 6
    out.extend(f"{a:.4f},{b:.{digits}g}" for a, b in zip(t, y))
    return "\n".join(out) + "\n"
