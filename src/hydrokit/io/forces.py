"""Two-column CSV files: force–speed curves for ``hydrokit fit-forces`` (columns ``speed``
(m/s) and ``force`` (N)) and, through :func:`read_columns`, profiles of bodies of revolution.
``#`` comment lines allowed; other columns are ignored."""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text

#: most rows read from a two-column file
MAX_ROWS = 1_000_000


def read_columns(path: str | os.PathLike[str], names: tuple[str, str], expected: str) -> tuple[np.ndarray, np.ndarray]:
    """The two named columns of a CSV with a header, as float arrays.

    ``expected`` says what the file should hold (with units), for the messages.
    """
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    text = read_text(p, "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    a, b = names
    if not lines:
        raise InputError(f"empty file; expected a header {a},{b} and rows", src)
    if len(lines) - 1 > MAX_ROWS:
        raise InputError(f"{len(lines) - 1} rows: expected at most {MAX_ROWS}", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip().lower() for h in rows[0]]
    for col in names:
        if col not in header:
            raise InputError(f"missing column '{col}' (header: {', '.join(header)[:120]}); expected {expected}", src)
    i, j = header.index(a), header.index(b)
    out = np.empty((len(rows) - 1, 2))
    for k, row in enumerate(rows[1:]):
        try:
            out[k] = float(row[i]), float(row[j])
        except (ValueError, IndexError):
            raise InputError(f"row {k + 2}: expected numbers in {a} and {b}", src) from None
        if not (math.isfinite(out[k, 0]) and math.isfinite(out[k, 1])):
            raise InputError(f"row {k + 2}: NaN or infinite value", src)
    return out[:, 0], out[:, 1]


def read_forces(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """(speed m/s, force N) arrays from a CSV."""
    U, F = read_columns(path, ("speed", "force"), "speed (m/s) and force (N)")
    if len(U) < 3:
        raise InputError(f"only {len(U)} point(s); expected at least 3 speed–force pairs", str(path))
    return U, F
