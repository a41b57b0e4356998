"""Trajectory CSV (issue #3 columns) and force-table CSV.

TRAJ.csv columns, in this order: ``time,x,y,z,phi,theta,psi,u,v,w,p,q,r`` (s, m, rad, m/s,
rad/s; x, y, z north-east-down). A force CSV has columns ``time,X,Y,Z,K,M,N`` (s, N, N·m).
"""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from hydrokit.core.names import FORCE_COLUMNS, STATE_COLUMNS
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text

COLUMNS = STATE_COLUMNS


def trajectory_csv(table: np.ndarray) -> str:
    """CSV text of an (n, 13) table in :data:`COLUMNS` order."""
    out = io.StringIO()
    out.write(",".join(COLUMNS) + "\n")
    for row in table:
        out.write(",".join(f"{v:.9g}" for v in row) + "\n")
    return out.getvalue()


def read_force_table(path: str | os.PathLike[str]) -> np.ndarray:
    """Rows [t, X, Y, Z, K, M, N] from a force CSV (``#`` comments allowed)."""
    p = Path(path)
    src = str(p)
    text = read_text(p, "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if len(lines) < 2:
        raise InputError("expected a header time,X,Y,Z,K,M,N and at least one row", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip() for h in rows[0]]
    missing = [c for c in FORCE_COLUMNS if c not in header]
    if missing:
        raise InputError(
            f"missing column(s) {', '.join(missing)} (header: {', '.join(header)}); expected time,X,Y,Z,K,M,N", src
        )
    idx = [header.index(c) for c in FORCE_COLUMNS]
    out = np.empty((len(rows) - 1, 7))
    for k, row in enumerate(rows[1:]):
        for j, (i, c) in enumerate(zip(idx, FORCE_COLUMNS)):
            try:
                v = float(row[i])
            except (ValueError, IndexError):
                raise InputError(f"row {k + 2}, column '{c}': expected a number", src) from None
            if not math.isfinite(v):
                raise InputError(f"row {k + 2}, column '{c}' = {row[i]}: expected a finite number", src)
            out[k, j] = v
    if np.any(np.diff(out[:, 0]) <= 0):
        raise InputError("column 'time' must increase strictly (s)", src)
    return out


def read_deflection_table(path: str | os.PathLike[str], names: tuple[str, ...]) -> np.ndarray:
    """Rows [t, δ_1 … δ_n] (s, rad) from a CSV with ``time`` and one column per control surface
    (``names``, in file order of the vehicle; other columns are an error, so a misspelt surface is
    not read as 0)."""
    src = str(path)
    if not names:
        raise InputError("the vehicle has no control_surfaces; expected no deflection CSV", src)
    text = read_text(Path(path), "a CSV")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if len(lines) < 2:
        raise InputError(f"expected a header time,{','.join(names)} and at least one row", src)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip() for h in rows[0]]
    wanted = ("time", *names)
    unknown = [c for c in header if c not in wanted]
    missing = [c for c in wanted if c not in header]
    if unknown or missing:
        said = f"unknown column '{unknown[0]}'" if unknown else f"missing column '{missing[0]}'"
        raise InputError(f"{said}; expected time (s) and a column per control surface: {', '.join(names)} (rad)", src)
    idx = [header.index(c) for c in wanted]
    out = np.empty((len(rows) - 1, len(wanted)))
    for k, row in enumerate(rows[1:]):
        for j, (i, c) in enumerate(zip(idx, wanted)):
            try:
                v = float(row[i])
            except (ValueError, IndexError):
                v = math.nan
            if not math.isfinite(v):
                raise InputError(
                    f"row {k + 2}, column '{c}' = {row[i] if i < len(row) else ''!r}: expected a finite number", src
                )
            out[k, j] = v
    if np.any(np.diff(out[:, 0]) <= 0):
        raise InputError("column 'time' must increase strictly (s)", src)
    return out


def table_csv(columns: list[str], data: np.ndarray, int_columns: tuple[str, ...] = ("saturated", "leg")) -> str:
    """CSV text of a table: floats with 9 significant digits, ``int_columns`` as integers."""
    ints = {i for i, c in enumerate(columns) if c in int_columns}
    lines = [",".join(columns)]
    for row in data:
        lines.append(",".join(str(int(v)) if i in ints else f"{v:.9g}" for i, v in enumerate(row)))
    return "\n".join(lines) + "\n"
