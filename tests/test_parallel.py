"""The task executor: serial and Dask give the same results, in input order, and fail clearly."""

from __future__ import annotations

import pickle
import re
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from hydrokit._parallel import Executor
from hydrokit.errors import HydrokitError, InputError, MissingExtraError, SimulationError

#: the directory this module imports from as ``__name__`` (e.g. tests.test_parallel); worker
#: processes are spawned with this process's sys.path, so with it there they can import the
#: module-level task functions below whatever directory pytest was started in
IMPORT_ROOT = Path(__file__).resolve().parents[__name__.count(".")]


def sample(seed: int) -> np.ndarray:
    """A deterministic Monte Carlo-like task: the seed is drawn by the caller."""
    rng = np.random.default_rng(seed)
    return rng.normal(size=5) @ rng.normal(size=(5, 3))


def slow_square(item: tuple[int, float]) -> int:
    i, delay = item
    time.sleep(delay)
    return i * i


def fail_on_three(i: int) -> int:
    if i == 3:
        raise SimulationError("state became non-finite at t = 3 s")
    return i


def needs_dask() -> None:
    """Skip the calling test, with the reason, where the Dask extra is not installed."""
    pytest.importorskip("distributed", reason="Dask is not installed: pip install 'hydrokit[dask]'")


@pytest.fixture(scope="module")
def dask_ex() -> Iterator[Executor]:
    needs_dask()
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(IMPORT_ROOT))
        with Executor(workers=2) as ex:
            yield ex


def test_serial_map_keeps_order_and_counts_progress(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "dask", None)  # any dask import would now fail
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    calls: list[int] = []
    for workers in (None, 0, 1):
        calls.clear()
        with Executor(workers) as ex:
            assert ex.description == "serial"
            assert ex.map(lambda x: 10 * x, range(5), progress=calls.append) == [0, 10, 20, 30, 40]
        assert calls == [1] * 5
    assert Executor().map(str, []) == []


def test_local_cluster_listens_on_loopback_only(dask_ex: Executor) -> None:
    assert dask_ex.description == "Dask LocalCluster, 2 workers (127.0.0.1)"
    client = dask_ex._client
    assert client.cluster.scheduler_address.startswith("tcp://127.0.0.1:")
    info = client.scheduler_info()
    assert info["address"].startswith("tcp://127.0.0.1:")
    assert len(info["workers"]) == 2
    assert all(addr.startswith("tcp://127.0.0.1:") for addr in info["workers"])


def test_dask_matches_serial(dask_ex: Executor) -> None:
    seeds = list(range(100, 120))
    serial = Executor().map(sample, seeds)
    calls: list[int] = []
    distributed = dask_ex.map(sample, seeds, progress=calls.append)
    assert calls == [1] * len(seeds)
    assert len(distributed) == len(serial)
    for a, b in zip(serial, distributed):
        np.testing.assert_array_equal(a, b)
    assert dask_ex.map(sample, []) == []


def test_dask_keeps_input_order_when_tasks_finish_out_of_order(dask_ex: Executor) -> None:
    items = [(i, 0.3 if i < 2 else 0.0) for i in range(8)]  # the first two finish last
    assert dask_ex.map(slow_square, items) == [i * i for i in range(8)]


@pytest.mark.parametrize("engine", ["serial", "dask"])
def test_task_exception_propagates_with_type_and_message(engine: str, dask_ex: Executor) -> None:
    ex = Executor() if engine == "serial" else dask_ex
    with pytest.raises(SimulationError, match=r"^state became non-finite at t = 3 s$"):
        ex.map(fail_on_three, range(6))
    with pytest.raises(ZeroDivisionError):
        ex.map(lambda x: 1 / x, [1, 0, 2])
    assert ex.map(fail_on_three, [0, 1, 2]) == [0, 1, 2]  # still usable afterwards


@pytest.mark.parametrize(
    "error",
    [
        InputError("bad value", source="rig.yaml: mass"),
        SimulationError("state became non-finite at t = 3 s"),
        MissingExtraError("capytaine", "bem"),
    ],
    ids=lambda e: type(e).__name__,
)
def test_errors_survive_pickling(error: HydrokitError) -> None:
    """Dask sends a task's exception back pickled; type and one-line message must survive."""
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is type(error)
    assert str(back) == str(error)


def test_cluster_closed_on_exception() -> None:
    needs_dask()
    with pytest.raises(RuntimeError, match="boom"):
        with Executor(workers=2) as ex:
            client = ex._client
            cluster = client.cluster
            raise RuntimeError("boom")
    assert client.status == "closed"
    assert cluster.status.name == "closed"
    assert ex._client is None
    with pytest.raises(RuntimeError, match="inside `with Executor"):
        ex.map(abs, [1])


def test_unreachable_scheduler_is_one_line_input_error() -> None:
    needs_dask()
    start = time.monotonic()
    with pytest.raises(
        InputError, match=r"^--scheduler = 'tcp://127.0.0.1:1': cannot reach a Dask scheduler \("
    ) as err:
        with Executor(scheduler="tcp://127.0.0.1:1", timeout=1):
            pass
    assert "\n" not in str(err.value)
    assert "e.g. tcp://127.0.0.1:8786" in str(err.value)
    assert time.monotonic() - start < 10
    assert Executor(scheduler="tcp://127.0.0.1:1").description == "Dask scheduler tcp://127.0.0.1:1"


def test_missing_dask_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    for kwargs in ({"workers": 2}, {"scheduler": "tcp://127.0.0.1:8786"}):
        with pytest.raises(MissingExtraError, match=r"pip install 'hydrokit\[dask\]'"):
            with Executor(**kwargs):  # type: ignore[arg-type]
                pass


@pytest.mark.parametrize("workers", [-1, 2.5, "3", True])
def test_bad_workers(workers: object) -> None:
    with pytest.raises(InputError, match="^--workers = " + re.escape(repr(workers)) + ": expected"):
        Executor(workers)  # type: ignore[arg-type]


@pytest.mark.parametrize("scheduler", ["", "  ", 8786])
def test_bad_scheduler(scheduler: object) -> None:
    with pytest.raises(InputError, match="^--scheduler = "):
        Executor(scheduler=scheduler)  # type: ignore[arg-type]


def test_workers_and_scheduler_are_exclusive() -> None:
    with pytest.raises(InputError, match="--workers = 4 with --scheduler"):
        Executor(4, "tcp://127.0.0.1:8786")
    assert Executor(1, "tcp://127.0.0.1:8786").description == "Dask scheduler tcp://127.0.0.1:8786"


def test_dask_tests_skip_with_a_reason_where_dask_is_missing() -> None:
    """Issue #32 class 9: without Dask each test that needs it skips and says why (the loopback
    test used to error in its fixture)."""
    import subprocess

    hide = "import sys; sys.modules.update(dict.fromkeys(['dask', 'distributed', 'dask.distributed']))"
    names = [
        "test_local_cluster_listens_on_loopback_only",
        "test_dask_matches_serial",
        "test_cluster_closed_on_exception",
        "test_unreachable_scheduler_is_one_line_input_error",
    ]
    tests = [f"{__file__}::{n}" for n in names]
    # in-process (-n 0): xdist workers would not inherit the hidden modules
    code = (
        f"{hide}; import pytest; sys.exit(pytest.main({tests!r} + ['-q', '-rs', '-p', 'no:cacheprovider', '-n', '0']))"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout[-2000:]
    assert f"{len(names)} skipped" in proc.stdout, proc.stdout[-2000:]
    reasons = [ln for ln in proc.stdout.splitlines() if ln.startswith("SKIPPED")]
    assert reasons and all(ln.endswith("Dask is not installed: pip install 'hydrokit[dask]'") for ln in reasons)


def test_the_resource_tracker_starts_with_its_leaked_semaphore_warning_off():
    # a run stopped by SIGTERM must print one line; the tracker (own process, our stderr)
    # would add "resource_tracker: There appear to be N leaked semaphore objects …"
    import subprocess
    import sys

    # the tracker's command line is read once it has exec'd: right after the fork it is empty
    # (a loaded machine showed that gap)
    code = (
        "import sys, time; from hydrokit._parallel import _quiet_resource_tracker as q; before = list(sys.warnoptions); "
        "q(); from multiprocessing import resource_tracker as r; assert sys.warnoptions == before; "
        "end = time.monotonic() + 20; line = ''\n"
        "while 'resource_tracker' not in line and time.monotonic() < end:\n"
        "    line = open(f'/proc/{r._resource_tracker._pid}/cmdline').read().replace(chr(0), ' '); time.sleep(0.01)\n"
        "print(line)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True).stdout
    assert "-Wignore:resource_tracker:UserWarning" in out and "resource_tracker" in out
