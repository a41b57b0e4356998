"""Write output files whole or not at all, and sets of files as a set.

Everything is first written to a temporary file in the destination directory and then moved
into place with :func:`os.replace`, which is atomic on POSIX and Windows for the same volume.
Several files (:func:`write_files`, :func:`staged_dir`) are all staged before any is moved, and
:func:`interrupt_on_signals` turns SIGTERM into an exception so that staging is cleaned up.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import sys
import tempfile
import threading
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success move it onto ``path``.

    On any exception the temporary file is removed and ``path`` is left untouched.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        raise_if_interrupted()
        # mkstemp creates 0600; give the file the permissions a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)
        os.replace(tmp_path, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()
        raise


def write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)


# --- sets of files -------------------------------------------------------------------------
#
# A command that writes several files (a CSV, a JSON and plots; a report folder) stages every
# file next to its destination first and only then moves them all into place. The moves take
# milliseconds; a termination signal that arrives meanwhile is held until the last one is done,
# so the destination shows either the old set or the new one, never a mix. A failure while
# staging removes every staged file and every folder the staging created.

#: signals turned into :class:`Interrupted` by :func:`interrupt_on_signals`
TERMINATING = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGINT", "SIGHUP") if hasattr(signal, name))

_committing = 0
_pending: list[int] = []
#: signals raised as Interrupted within the current interrupt_on_signals block. A raise can be
#: lost: when the signal lands while Python code runs inside a C callback (numba's compiler
#: calls back into Python while it caches), the callback's caller prints "Exception ignored" and
#: goes on. Long loops call :func:`raise_if_interrupted` to raise it again.
_received: list[int] = []


class Interrupted(BaseException):  # noqa: N818 -- like KeyboardInterrupt: not an error of the input
    """A termination signal arrived; raised in the main thread so staged outputs are removed.

    A ``BaseException`` (like :class:`KeyboardInterrupt`) so that no ``except Exception`` in the
    library swallows it. ``written`` is True when the signal arrived while a set of files was
    being moved into place: the set was completed first.
    """

    def __init__(self, signum: int, written: bool = False):
        self.signum = signum
        self.written = written
        super().__init__(signal.Signals(signum).name)


def _on_signal(signum: int, frame: object) -> None:
    if _committing:
        _pending.append(signum)  # finish the moves first: never half a set
        return
    _received.append(signum)
    raise Interrupted(signum)


def raise_if_interrupted() -> None:
    """Raise :class:`Interrupted` again if a termination signal arrived in this block but its
    first raise was swallowed (see ``_received``); a no-op otherwise. Call it between steps of
    long work (generations of a search, batches of runs)."""
    if _received:
        raise Interrupted(_received[0])


@contextlib.contextmanager
def interrupt_on_signals(signums: tuple[int, ...] = TERMINATING) -> Iterator[None]:
    """Within the block, SIGTERM/SIGINT/SIGHUP raise :class:`Interrupted` in the main thread.

    Context managers on the way out (staging folders, temporary files) then clean up. The
    previous handlers are restored on exit. Outside the main thread this does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.getsignal(s) for s in signums}
    old_hook = sys.unraisablehook

    def quiet(unraisable: Any) -> None:
        # a swallowed Interrupted is raised again by raise_if_interrupted: no traceback on stderr
        if not isinstance(unraisable.exc_value, Interrupted):
            old_hook(unraisable)

    _received.clear()
    sys.unraisablehook = quiet
    for s in signums:
        signal.signal(s, _on_signal)
    try:
        yield
    except Exception as exc:
        if _received:
            # the signal's raise was swallowed and the work then failed, most likely because of it
            # (numba interrupted mid-compilation leaves a function with "no compiled object yet"):
            # report the signal, not a consequence of it
            raise Interrupted(_received[0]) from exc
        raise
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)
        sys.unraisablehook = old_hook
        _received.clear()


def _file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _make_dirs(folder: Path, created: list[Path]) -> None:
    """``mkdir -p`` that records the folders it created (outermost first)."""
    missing = []
    for p in (folder, *folder.parents):
        if p.exists():
            break
        missing.append(p)
    for p in reversed(missing):
        with contextlib.suppress(FileExistsError):
            p.mkdir()
            created.append(p)


def _remove_dirs(created: list[Path]) -> None:
    for p in reversed(created):
        with contextlib.suppress(OSError):
            p.rmdir()  # only when empty: never a file someone else put there


def commit(moves: Mapping[Path, Path]) -> None:
    """Move each staged file (value) onto its destination (key) as one set.

    Every destination is checked first (none may be a folder); termination signals are held
    during the moves; if a move fails, the destinations already replaced get their old content
    back (kept as hard links) and new ones are removed, then the error is raised.
    """
    global _committing
    raise_if_interrupted()  # a termination signal whose raise was lost: nothing gets written
    for dest in moves:
        if dest.is_dir():
            raise IsADirectoryError(errno.EISDIR, "is a folder; expected a file (or nothing)", str(dest))
    created: list[Path] = []
    done: list[tuple[Path, Path | None]] = []  # (destination, backup of its old content)
    _committing += 1
    ok = False
    try:
        for dest, src in moves.items():
            _make_dirs(dest.parent, created)
            backup = None
            if dest.exists():
                backup = dest.with_name(f".{dest.name}.{os.getpid()}.old")
                try:
                    os.link(dest, backup)
                except OSError:
                    backup = None
            os.replace(src, dest)
            done.append((dest, backup))
        ok = True
    except BaseException:
        for dest, backup in reversed(done):
            with contextlib.suppress(OSError):
                if backup is None:
                    dest.unlink()
                else:
                    os.replace(backup, dest)
        _remove_dirs(created)
        raise
    finally:
        _committing -= 1
        for _, backup in done:
            if backup is not None:
                with contextlib.suppress(OSError):
                    backup.unlink()
        if not _committing and _pending:
            signum = _pending[0]
            _pending.clear()
            if ok:
                raise Interrupted(signum, written=True)


def write_files(files: Mapping[str | os.PathLike[str], bytes]) -> list[Path]:
    """Write several files as one set: all of them, or none (and no staged file left behind).

    Each file is staged as a hidden temporary next to its destination (creating missing
    folders), then :func:`commit` moves them all into place.
    """
    created: list[Path] = []
    moves: dict[Path, Path] = {}
    try:
        for path, data in files.items():
            dest = Path(path)
            _make_dirs(dest.parent, created)
            fd, tmp = tempfile.mkstemp(prefix=f".{dest.name}.", suffix=".part", dir=dest.parent)
            moves[dest] = Path(tmp)
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
            os.chmod(tmp, _file_mode())
        commit(moves)
    except BaseException:
        for staged in moves.values():
            with contextlib.suppress(FileNotFoundError):
                staged.unlink()
        _remove_dirs(created)
        raise
    return list(moves)


@contextlib.contextmanager
def staged_dir(out_dir: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield an empty hidden folder next to ``out_dir`` to write a set of outputs into.

    On success every file in it (subfolders included) is moved to the same place under
    ``out_dir`` with :func:`commit`; files already in ``out_dir`` that the set does not hold
    are kept. On an exception or a termination signal the staging folder is removed and
    ``out_dir`` is left exactly as it was (not even created).
    """
    target = Path(out_dir)
    created: list[Path] = []
    _make_dirs(target.parent, created)
    try:
        stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent))
    except BaseException:
        _remove_dirs(created)
        raise
    ok = False
    try:
        yield stage
        files = sorted(p.relative_to(stage) for p in stage.rglob("*") if not p.is_dir())
        for rel in files:
            os.chmod(stage / rel, _file_mode())
        commit({target / rel: stage / rel for rel in files})
        ok = True
    finally:
        shutil.rmtree(stage, ignore_errors=True)
        if not ok:
            _remove_dirs(created)
