"""Helpers shared by the CLI modules: option parsing, progress bars, writing outputs."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hydrokit.errors import InputError


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
    """Write every output as one set (all files or none) once everything has been computed."""
    from hydrokit._atomic import write_files

    data: dict[str | os.PathLike[str], bytes] = {
        p: d.encode("utf-8") if isinstance(d, str) else d for p, d in files.items()
    }
    try:
        write_files(data)
    except OSError as exc:
        where = shown(exc.filename) if exc.filename else "an output file"
        raise InputError(f"cannot write {where}: {exc.strerror or exc}; nothing was written") from None


def shown(text: Any, limit: int = 80) -> str:
    """``repr`` of a user's value cut to ``limit`` characters, so a message never echoes a whole file."""
    r = repr(str(text))
    return r if len(r) <= limit else f"{r[: limit - 20]}…{r[-15:]} ({len(str(text))} characters)"


def check_out_dir(path: str | Path, option: str = "--out") -> Path:
    """Refuse an output folder that cannot be written, before any computation starts.

    Checks that no part of the path is a file, that every name fits the file system, and
    that the folder (or its nearest existing parent) accepts new files (a probe folder is
    made and removed). Returns the path.
    """
    import tempfile

    out = Path(path)
    expected = "expected a folder that exists or can be created, and that accepts new files"
    name_max = _pathconf(Path(), "PC_NAME_MAX", 255)
    for part in out.parts:  # first: stat() itself fails on a name that is too long
        if len(os.fsencode(part)) > name_max:
            raise InputError(f"{option}: the name {shown(part)} is longer than {name_max} bytes; {expected}")
    if out.exists() and not out.is_dir():
        raise InputError(f"{option} {shown(out)} is a file; {expected}")
    base = out
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise InputError(f"{option} {shown(out)}: {shown(base)} is a file, not a folder; {expected}")
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".hydrokit-probe.", dir=base))
    except OSError as exc:
        raise InputError(
            f"{option} {shown(out)}: cannot create files in {shown(base)} ({exc.strerror}); {expected}"
        ) from None
    return out


def check_out_file(path: str | Path, option: str) -> Path:
    """Refuse an output file that cannot be written, before any computation starts.

    The path must not be a folder, its name must fit the file system, and its folder must
    pass :func:`check_out_dir`. Returns the path.
    """
    out = Path(path)
    if out.is_dir():
        raise InputError(f"{option} {shown(out)} is a folder; expected a file name")
    name_max = _pathconf(Path(), "PC_NAME_MAX", 255)
    if len(os.fsencode(out.name)) > name_max:
        raise InputError(
            f"{option}: the name {shown(out.name)} is longer than {name_max} bytes; expected a shorter name"
        )
    check_out_dir(out.parent, f"{option} {shown(out)}: its folder")
    return out


def check_outputs(files: Mapping[str, Any], folders: Mapping[str, Any] | None = None) -> None:
    """:func:`check_out_file` for each option → path of ``files`` and :func:`check_out_dir` for
    each of ``folders``, skipping the options not given (None)."""
    for option, path in files.items():
        _ = check_out_file(path, option) if path else None
    for option, path in (folders or {}).items():
        _ = check_out_dir(path, option) if path else None


def _pathconf(path: Path, name: str, default: int) -> int:
    try:
        return int(os.pathconf(path, name))
    except (AttributeError, ValueError, OSError):
        return default


def json_text(doc: Any) -> str:
    """Strict JSON text (NaN/inf must already be None: results' to_dict() guarantees it)."""
    import json

    return json.dumps(doc, indent=2, allow_nan=False, ensure_ascii=False) + "\n"
