"""Wind over time from a CSV: ``time,wind_speed,wind_direction`` (s, m/s, rad — the true direction
the wind blows from, clockwise from North; the run files' column names, issue #48 item 4)."""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text

#: the wind columns of a run file or a wind CSV (frozen): m/s and rad (true, from)
WIND_COLUMNS = ("wind_speed", "wind_direction")


def read_wind_table(path: str | os.PathLike[str]) -> np.ndarray:
    """Rows [t, speed, direction] (s, m/s, rad) from a wind CSV (``#`` comments allowed)."""
    src = str(path)
    text = read_text(Path(path), "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if len(lines) < 2:
        raise InputError("expected a header time,wind_speed,wind_direction and at least one row", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip() for h in rows[0]]
    cols = ("time", *WIND_COLUMNS)
    missing = [c for c in cols if c not in header]
    if missing:
        raise InputError(
            f"missing column(s) {', '.join(missing)} (header: {', '.join(header)}); "
            "expected time,wind_speed,wind_direction (s, m/s, rad from)",
            src,
        )
    idx = [header.index(c) for c in cols]
    out = np.empty((len(rows) - 1, 3))
    for k, row in enumerate(rows[1:]):
        for j, (i, c) in enumerate(zip(idx, cols)):
            try:
                v = float(row[i])
            except (ValueError, IndexError):
                raise InputError(f"row {k + 2}, column '{c}': expected a number", src) from None
            if not math.isfinite(v) or (c == "wind_speed" and v < 0):
                raise InputError(f"row {k + 2}, column '{c}' = {row[i]}: expected a finite number (speed ≥ 0)", src)
            out[k, j] = v
    if np.any(np.diff(out[:, 0]) <= 0):
        raise InputError("column 'time' must increase strictly (s)", src)
    return out
