"""Helpers shared by the CLI modules: option parsing, progress bars, writing outputs."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hydrokit.errors import InputError


def floats(text: str, option: str, n: int | None = None, unit: str = "", positive: bool = False) -> list[float]:
    """Comma-separated finite numbers from an option value (exactly ``n`` when given)."""
    try:
        vals = [float(x) for x in text.replace(";", ",").split(",") if x.strip()]
    except ValueError:
        vals = []
    ok = bool(vals) and all(math.isfinite(v) and (v > 0 or not positive) for v in vals)
    if not ok or (n is not None and len(vals) != n):
        count = f"{n} " if n is not None else ""
        kind = "positive" if positive else "finite"
        raise InputError(
            f"{option} {text!r}: expected {count}comma-separated {kind} numbers" + (f" ({unit})" if unit else "")
        )
    return vals


def progress_bar(*, time_based: bool = False) -> Any:
    """A transient rich progress bar on stderr (count or simulated time)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    middle = (TextColumn("{task.percentage:>3.0f}%"), TimeRemainingColumn()) if time_based else (MofNCompleteColumn(),)
    console = Console(stderr=True)
    # not a terminal (a log, a pipe, CI): no bar at all, so an error stays the only stderr line
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        *middle,
        TimeElapsedColumn(),
        console=console,
        transient=True,
        disable=not console.is_terminal,
    )


def write_all(files: Mapping[str, Any] | Mapping[Path, Any] | Mapping[str | Path, Any]) -> None:
    """Write every output (each whole or not at all) once everything has been computed."""
    from hydrokit._atomic import write_bytes

    for path, data in files.items():
        write_bytes(path, data.encode("utf-8") if isinstance(data, str) else data)


def json_text(doc: Any) -> str:
    """Strict JSON text (NaN/inf must already be None: results' to_dict() guarantees it)."""
    import json

    return json.dumps(doc, indent=2, allow_nan=False, ensure_ascii=False) + "\n"
