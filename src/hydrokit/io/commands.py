"""Thruster-command CSV (the ``--command-csv`` file of the simulate command): ``time`` (s) and one column per
thruster of the vehicle, named as the thruster, holding its command in the unit of its curve
(rev/s for a propeller, the table's unit for a table curve, N for an ideal thruster); each row is
held until the next (zero-order hold, as the command columns of a run file). ``#`` lines are
comments."""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from hydrokit.core.validate import cut
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_text


def read_command_table(path: str | os.PathLike[str], names: Sequence[str]) -> np.ndarray:
    """Rows [t, u_1 … u_m] (s, each thruster's unit) in the order of ``names`` (the vehicle's
    thrusters). Every thruster needs a column and every column must name one (a misspelt
    thruster is not read as 0); times increase strictly; every cell is a finite number."""
    src = str(path)
    if not names:
        raise InputError("the vehicle has no thrusters; expected no command CSV", src)
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
        said = f"unknown column '{cut(unknown[0])}'" if unknown else f"missing column '{cut(missing[0])}'"
        raise InputError(
            f"{said}; expected time (s) and a column per thruster: {', '.join(names)} (its command unit)", src
        )
    idx = [header.index(c) for c in wanted]
    out = np.empty((len(rows) - 1, len(wanted)))
    for k, row in enumerate(rows[1:]):
        for j, (i, c) in enumerate(zip(idx, wanted)):
            cell = row[i].strip() if i < len(row) else ""
            try:
                v = float(cell)
            except ValueError:
                v = math.nan
            if not math.isfinite(v):
                raise InputError(f"row {k + 2}, column '{c}' = {cut(repr(cell))}: expected a finite number", src)
            out[k, j] = v
    bad = np.flatnonzero(np.diff(out[:, 0]) <= 0)
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"column 'time' = {out[i + 1, 0]:.9g} at row {i + 3} after {out[i, 0]:.9g}; expected strictly "
            "increasing times (s)",
            src,
        )
    return out
