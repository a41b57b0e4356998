"""Force–speed CSV for ``hydrokit fit-forces``: columns ``speed`` (m/s) and ``force`` (N);
``#`` comment lines allowed."""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text


def read_forces(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """(speed m/s, force N) arrays from a CSV."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    text = read_text(p, "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError("empty file; expected a header speed,force and rows", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip().lower() for h in rows[0]]
    for col in ("speed", "force"):
        if col not in header:
            raise InputError(
                f"missing column '{col}' (header: {', '.join(header)}); expected speed (m/s) and force (N)", src
            )
    i, j = header.index("speed"), header.index("force")
    U, F = [], []
    for k, row in enumerate(rows[1:]):
        try:
            u, f = float(row[i]), float(row[j])
        except (ValueError, IndexError):
            raise InputError(f"row {k + 2}: expected numbers in speed and force", src) from None
        if not (math.isfinite(u) and math.isfinite(f)):
            raise InputError(f"row {k + 2}: NaN or infinite value", src)
        U.append(u)
        F.append(f)
    if len(U) < 3:
        raise InputError(f"only {len(U)} point(s); expected at least 3 speed–force pairs", src)
    return np.array(U), np.array(F)
