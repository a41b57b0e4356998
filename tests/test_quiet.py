"""Issue 32 class 1: third-party libraries do not talk on our terminal. ``hydrokit._quiet.quiet``
captures print, sys.stdout/stderr, file-descriptor output of C code, warnings and log records
into a bounded log; stderr carries only hydrokit's own lines."""

from __future__ import annotations

import logging
import os
import sys
import warnings
from pathlib import Path

import pytest

from hydrokit import _quiet
from hydrokit.data import DATA_DIR

RIG = DATA_DIR / "campaigns" / "udrobot" / "pendulum_x.yaml"


def talk(n: int = 3) -> None:
    """Everything a talkative library does: print, stream writes, C-level writes, a warning, a log record."""
    for k in range(n):
        print(f"bad header {k}")
    sys.stderr.write("python stderr line\n")
    os.write(1, b"C stdout line\n")
    os.write(2, b"C stderr line\n")
    warnings.warn("overflow encountered in dot", RuntimeWarning, stacklevel=1)
    logging.getLogger("capytaine").warning("a log record")


def test_everything_a_library_writes_is_captured_and_kept(capfd):
    _quiet.clear()
    with _quiet.quiet("lib"):
        talk()
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # nothing reached the file descriptors either
    kept = _quiet.captured()
    for line in ("bad header 2", "python stderr line", "C stdout line", "C stderr line", "a log record"):
        assert f"[lib] {line}" in kept or any(k.endswith(line) for k in kept), (line, kept)
    assert any("RuntimeWarning: overflow encountered in dot" in k for k in kept), kept
    print("after")  # the streams and descriptors are ours again
    os.write(2, b"fd after\n")
    out, err = capfd.readouterr()
    assert out == "after\n" and err == "fd after\n"


def test_captures_nest_survive_an_exception_and_stay_bounded(capfd):
    _quiet.clear()
    with pytest.raises(ValueError, match="from the library"), _quiet.quiet("outer"):
        with _quiet.quiet("inner"):
            print("x" * (10 * _quiet.MAX_CAPTURE_CHARS))
        os.write(2, b"y" * (10 * _quiet.MAX_CAPTURE_CHARS))
        raise ValueError("from the library")
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    text = "\n".join(_quiet.captured())
    assert len(text) < 3 * _quiet.MAX_CAPTURE_CHARS  # 200 000 characters in, bounded out
    assert "characters left out" in text and "more bytes on the file descriptors left out" in text
    for k in range(3 * _quiet.MAX_LOG_LINES):  # the log keeps the last lines and says how many went
        _quiet._keep("many", f"line {k}")
    kept = _quiet.captured()
    assert len(kept) == _quiet.MAX_LOG_LINES + 1 and kept[-1] == f"[many] line {3 * _quiet.MAX_LOG_LINES - 1}"
    assert kept[0].startswith("[… ") and "earlier captured line(s) left out" in kept[0]


def random_log(tmp_path: Path) -> Path:
    import random

    rng = random.Random(32)
    path = tmp_path / "random.bin"
    path.write_bytes(bytes(rng.randrange(256) for _ in range(200_000)))
    return path


def test_ingest_of_random_bytes_as_an_ardupilot_log_is_one_line(run_cli, tmp_path, monkeypatch):
    pytest.importorskip("pymavlink")
    log = tmp_path / "captured.log"
    monkeypatch.setenv(_quiet.LOG_ENV, str(log))
    args = ("ingest", random_log(tmp_path), "--rig", RIG, "--format", "ardupilot", "--signal", "ATT.Pitch")
    code, out, err = run_cli(*args, "--out", tmp_path / "o")
    # before: 49 141 lines of pymavlink's "bad header" / "Skipped … bad bytes" before the error
    assert code == 2 and out == ""
    assert err.splitlines() == [f"error: {tmp_path / 'random.bin'}: --signal 'ATT.Pitch': no ATT messages in the log "
                                "(types: MAV, __MAV__)"]  # fmt: skip
    assert "[pymavlink] Skipped" in log.read_text()  # what it said is in the log file
    code, _, err = run_cli("--verbose", *args, "--out", tmp_path / "o")
    lines = err.splitlines()
    assert code == 2 and lines[-1].startswith("error: ") and len(lines) > 10
    assert all(line.startswith("[pymavlink] ") for line in lines[:-1])
    assert len(err) < 3 * _quiet.MAX_CAPTURE_CHARS  # bounded, whatever the file holds
