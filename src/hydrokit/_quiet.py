"""Third-party libraries kept off our terminal.

pymavlink prints a line per bad header (49 141 of them for a file of random bytes), scipy and
numpy warn about overflows, capytaine and meshio log and print. What hydrokit means to say it
says in its own words; everything such a library writes while :func:`quiet` is active —
``print`` and ``sys.stdout``/``sys.stderr`` writes, output of C code on file descriptors 1 and 2,
Python warnings and log records — is captured instead and kept in a bounded log
(:func:`captured`): the CLI shows it with ``hydrokit --verbose`` and appends it to the file
named by ``HYDROKIT_LOG``.

Captures nest (only the outermost one redirects the file descriptors) and are process-wide
while active: output other threads write to file descriptors 1 and 2 in that time is captured
too, so :func:`quiet` wraps the library call only, never a progress bar.
"""

from __future__ import annotations

import contextlib
import io
import logging
import os
import sys
import tempfile
import threading
import warnings
from collections import deque
from collections.abc import Iterator

#: characters of one capture kept (its start and its end), and lines of all captures kept
MAX_CAPTURE_CHARS = 20_000
MAX_LOG_LINES = 2_000
#: env var naming a file the captured text is appended to
LOG_ENV = "HYDROKIT_LOG"

_lock = threading.RLock()
_depth = 0
_log: deque[str] = deque(maxlen=MAX_LOG_LINES)
_dropped = 0
_show = False


class _Bounded(io.TextIOBase):
    """A text sink that keeps the first and last MAX_CAPTURE_CHARS // 2 characters."""

    def __init__(self) -> None:
        self.head = ""
        self.tail = ""
        self.total = 0

    def write(self, s: str) -> int:
        n = len(s)
        self.total += n
        half = MAX_CAPTURE_CHARS // 2
        if len(self.head) < half:
            take = s[: half - len(self.head)]
            self.head += take
            s = s[len(take) :]
        if s:
            self.tail = (self.tail + s)[-half:]
        return n

    def text(self) -> str:
        left = self.total - len(self.head) - len(self.tail)
        return self.head + (f"\n[… {left} characters left out …]\n" if left > 0 else "") + self.tail


class _Records(logging.Handler):
    def __init__(self, sink: _Bounded) -> None:
        super().__init__(logging.DEBUG)
        self.sink = sink

    def emit(self, record: logging.LogRecord) -> None:
        self.sink.write(f"{record.levelname} {record.name}: {record.getMessage()}\n")


@contextlib.contextmanager
def quiet(what: str, fds: bool = True, streams: bool = True) -> Iterator[None]:
    """Capture everything the library ``what`` writes while the block runs (see the module).

    Parameters
    ----------
    what : str — the library, named in the log (``"pymavlink"``, ``"scipy least_squares"`` …)
    fds : bool — also redirect file descriptors 1 and 2 (C code, subprocesses); False where a
        progress bar of ours may draw on the terminal during the block
    streams : bool — also redirect ``sys.stdout`` and ``sys.stderr``; False (warnings and log
        records only) for a long call that advances one of our progress bars
    """
    global _depth
    sink = _Bounded()
    handler = _Records(sink)
    root = logging.getLogger()
    with _lock:
        outer = _depth == 0
        _depth += 1
    saved: list[int] = []
    caught: list[warnings.WarningMessage] = []
    spool = None
    try:
        if outer and fds and streams:
            spool = tempfile.TemporaryFile(mode="w+b")
            for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
                with contextlib.suppress(Exception):
                    stream.flush()  # type: ignore[union-attr]
            for fd in (1, 2):
                with contextlib.suppress(OSError):
                    saved.append(os.dup(fd))
                    os.dup2(spool.fileno(), fd)
        root.addHandler(handler)
        with (
            warnings.catch_warnings(record=True) as record,
            contextlib.redirect_stdout(sink) if streams else contextlib.nullcontext(),
            contextlib.redirect_stderr(sink) if streams else contextlib.nullcontext(),
        ):
            warnings.simplefilter("always")
            try:
                yield
            finally:
                caught.extend(record)
    finally:
        root.removeHandler(handler)
        for w in caught:
            sink.write(f"{w.category.__name__}: {w.message} ({os.path.basename(w.filename)}:{w.lineno})\n")
        if saved:
            for stream in (sys.__stdout__, sys.__stderr__):
                with contextlib.suppress(Exception):
                    stream.flush()  # type: ignore[union-attr]
            for fd, old in zip((1, 2), saved):
                os.dup2(old, fd)
                os.close(old)
        if spool is not None:
            spool.seek(0)
            raw = spool.read(MAX_CAPTURE_CHARS + 1)
            spool.seek(0, os.SEEK_END)
            size = spool.tell()
            spool.close()
            sink.write(raw[:MAX_CAPTURE_CHARS].decode("utf-8", "replace"))
            if size > MAX_CAPTURE_CHARS:
                sink.write(f"\n[… {size - MAX_CAPTURE_CHARS} more bytes on the file descriptors left out …]\n")
        with _lock:
            _depth -= 1
        _keep(what, sink.text())


def _keep(what: str, text: str) -> None:
    """Add a capture to the bounded log (and to the ``HYDROKIT_LOG`` file when set)."""
    global _dropped
    lines = [f"[{what}] {line}" for line in text.splitlines() if line.strip()]
    if not lines:
        return
    with _lock:
        _dropped += max(0, len(_log) + len(lines) - MAX_LOG_LINES)
        _log.extend(lines)
    if _show:  # hydrokit --verbose: on stderr as they come, before our own last line
        sys.stderr.write("\n".join(lines) + "\n")
    path = os.environ.get(LOG_ENV)
    if path:
        with contextlib.suppress(OSError), open(path, "a", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")


def captured() -> list[str]:
    """The captured lines so far (at most :data:`MAX_LOG_LINES`; a first line says how many were
    left out)."""
    with _lock:
        head = [f"[… {_dropped} earlier captured line(s) left out …]"] if _dropped else []
        return head + list(_log)


def show(on: bool) -> None:
    """Echo captured lines on stderr as they are captured (``hydrokit --verbose``) or not."""
    global _show
    _show = bool(on)


def clear() -> None:
    """Forget the captured lines (the CLI starts each command with an empty log)."""
    global _dropped
    with _lock:
        _log.clear()
        _dropped = 0
