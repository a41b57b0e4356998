"""A signal stops the long commands cleanly: ``run`` with Dask workers and ``tune`` (issue #13 item 4).

"A SIGTERM during any command leaves no partial output." The mission case (the reference Python
loop) is in test_hostile_inputs.py; these are the two commands that fan work out: ``run`` to
Dask worker processes, ``tune`` to threads flying compiled fleets. Each must exit 143 with one
line on stderr (worker processes share it and must not add their shutdown logs), leave no
output but whole step-cache entries (``run`` keeps finished steps so that a rerun resumes), and
leave no worker process behind.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

HYDROKIT = [sys.executable, "-m", "hydrokit"]

pytestmark = pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs Linux /proc")


def _catches_sigterm(pid: int) -> bool:
    status = Path(f"/proc/{pid}/status").read_text().splitlines()
    caught = next((ln for ln in status if ln.startswith("SigCgt:")), "SigCgt: 0")
    return bool(int(caught.split()[1], 16) & (1 << (signal.SIGTERM - 1)))


def _children(pid: int) -> list[int]:
    """Live processes whose parent is ``pid`` (zombies excluded)."""
    out = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()  # after "(comm)": state, ppid, …
        if fields[0] != "Z" and int(fields[1]) == pid:
            out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        return (Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]) != "Z"
    except OSError:
        return False


def _wait(cond, what: str, proc: subprocess.Popen[str], timeout: float = 90.0) -> None:  # noqa: ANN001
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"finished before {what}: {proc.communicate()}"
        if cond():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def _terminate(proc: subprocess.Popen[str]) -> tuple[str, float]:
    """SIGTERM, then (stderr, seconds until the process had exited)."""
    t0 = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    return err, time.monotonic() - t0


def test_sigterm_stops_a_run_with_dask_workers_and_keeps_only_whole_cache_entries(tmp_path):
    pytest.importorskip("distributed")
    out = tmp_path / "o"
    proc = subprocess.Popen(
        [*HYDROKIT, "run", "udrobot", "--out", str(out), "--workers", "2", "--quiet"],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        _wait(lambda: _catches_sigterm(proc.pid), "the SIGTERM handler", proc)
        # the LocalCluster's worker processes (two, plus multiprocessing's resource tracker)
        _wait(lambda: len(_children(proc.pid)) >= 3, "the Dask workers", proc)
        workers = _children(proc.pid)
        time.sleep(2.0)  # launch fits are running on the workers now
        err, took = _terminate(proc)
    finally:
        proc.kill() if proc.poll() is None else None
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert err.splitlines() == ["interrupted (SIGTERM); no output written"], err[:2000]
    assert took < 30, f"took {took:.1f} s to stop"
    left = [p for p in out.rglob("*") if p.is_file()]
    assert all(p.parent == out / ".cache" and p.suffix == ".json" for p in left), left
    for p in left:  # finished steps only, each whole
        assert isinstance(json.loads(p.read_text()), dict), p
    deadline = time.monotonic() + 20
    while any(_alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [w for w in workers if _alive(w)], "worker processes outlived the run"


def test_sigterm_stops_tune_between_generations_with_nothing_written(tmp_path):
    out = tmp_path / "o"
    proc = subprocess.Popen(
        [
            *HYDROKIT,
            "tune",
            "lingyun_path",
            "--controller",
            "pid",
            "--out",
            str(out),
            "--workers",
            "2",
            "--maxiter",
            "400",
        ],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "COLUMNS": "100"},
    )
    try:
        _wait(lambda: _catches_sigterm(proc.pid), "the SIGTERM handler", proc)
        time.sleep(3.0)  # inside the search (400 generations: minutes of work)
        err, took = _terminate(proc)
    finally:
        proc.kill() if proc.poll() is None else None
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert err.splitlines()[-1:] == ["interrupted (SIGTERM); no output written"], err[:2000]
    assert len(err.splitlines()) == 1, err[:2000]
    assert took < 30, f"took {took:.1f} s to stop"
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == []
