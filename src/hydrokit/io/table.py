"""Delimited tables (CSV, TSV, semicolon- or space-separated) as a recording for ``hydrokit ingest``.

Any delimiter (sniffed), any column names: the time and signal columns are chosen by name
(case-insensitive) or by 1-based number; by default the first and the second column. Lines
starting with ``#`` are comments. Units come from the options, never guessed — but a signal
header that names another angle unit than the one given (``pitch_deg`` read as rad) is warned
about.
"""

from __future__ import annotations

import csv
import io
import os
import re
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig
from hydrokit.io.recording import TIME_UNITS, Recording
from hydrokit.io.yamlfile import read_text

_DEG = re.compile(r"deg|°|degree", re.I)
_RAD = re.compile(r"rad", re.I)


def _rows(text: str, src: str) -> list[list[str]]:
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError("no rows; expected a table of time and signal columns", src)
    sample = "\n".join(lines[:50])
    try:
        dialect: type[csv.Dialect] | csv.Dialect = csv.Sniffer().sniff(sample, delimiters=",;\t| ")
    except csv.Error:
        dialect = csv.excel_tab if "\t" in lines[0] else csv.excel
    rows = list(csv.reader(io.StringIO("\n".join(lines)), dialect))
    if getattr(dialect, "delimiter", ",") == " ":
        rows = [[c for c in r if c.strip()] for r in rows]
    return rows


def _is_number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _column(want: str | None, default: int, header: list[str], src: str, option: str) -> int:
    names = ", ".join(header)
    if want is None:
        if default >= len(header):
            raise InputError(f"only {len(header)} column(s) ({names}); expected a time and a signal column", src)
        return default
    lower = [h.strip().lower() for h in header]
    if want.strip().lower() in lower:
        return lower.index(want.strip().lower())
    if want.isdigit() and 1 <= int(want) <= len(header):
        return int(want) - 1
    raise InputError(f"{option} {want!r}: no such column (columns: {names})", src)


def read_table(
    path: str | os.PathLike[str],
    rig: Rig,
    *,
    time: str | None = None,
    signal: str | None = None,
    time_unit: str = "s",
    unit: tuple[float, str] | None = None,
) -> Recording:
    """The ``time``/``signal`` columns of a delimited table, in s and SI."""

    p = Path(path)
    src = str(p)
    text = read_text(p, "a text table")
    rows = _rows(text, src)
    has_header = not all(_is_number(c) for c in rows[0])
    header = [c.strip() for c in rows[0]] if has_header else [str(k + 1) for k in range(len(rows[0]))]
    body = rows[1:] if has_header else rows
    it = _column(time, 0, header, src, "--time")
    iy = _column(signal, 1, header, src, "--signal")
    t = np.empty(len(body))
    y = np.empty(len(body))
    first = 2 if has_header else 1
    for k, row in enumerate(body):
        for arr, idx in ((t, it), (y, iy)):
            try:
                arr[k] = float(row[idx])
            except IndexError:
                raise InputError(f"row {k + first}: no column {header[idx]!r}", src) from None
            except ValueError:
                raise InputError(
                    f"row {k + first}, column {header[idx]!r} = {row[idx]!r}: expected a number", src
                ) from None
    default = "m" if rig.test == "spring" else "rad"
    factor, uname = unit if unit else (1.0, default)
    t = t * TIME_UNITS[time_unit]
    y = y * factor
    notes = [f"time column {header[it]!r} in {time_unit}", f"signal column {header[iy]!r} in {uname}"]
    warnings = []
    name = header[iy]
    if uname == "rad" and _DEG.search(name):
        warnings.append(f"column {name!r} looks like degrees but --signal-unit is rad (give --signal-unit deg)")
    elif uname == "deg" and _RAD.search(name) and not _DEG.search(name):
        warnings.append(f"column {name!r} looks like radians but --signal-unit is deg")
    if not np.all(np.isfinite(y)):
        raise InputError(f"column {name!r}: NaN or inf at row {int(np.nonzero(~np.isfinite(y))[0][0]) + first}", src)
    if time_unit == "s" and t.size > 1 and float(np.median(np.diff(t))) >= 1.0:
        dt = float(np.median(np.diff(t)))
        warnings.append(f"median time step {dt:g} s: is the time column really in s? (see --time-unit)")
    return Recording(t, y, src, f"column {name!r} ({uname})", tuple(notes), tuple(warnings))
