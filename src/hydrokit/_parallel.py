"""Run a list of independent tasks serially or on Dask.

Per-launch fits and Monte Carlo samples are independent tasks: each is ``fn(item)`` with no
shared state. :class:`Executor` runs them in a plain loop in this process, on a private
:class:`dask.distributed.LocalCluster` bound to loopback, or on an existing Dask scheduler.
The caller draws all random numbers (or per-item seeds) *before* mapping and puts them in the
items, so the results do not depend on the engine, the number of workers or completion order.

Dask is an optional extra (``pip install 'hydrokit[dask]'``) and is imported only when asked
for. Tasks and items must pickle: use module-level functions of an importable package.
"""

from __future__ import annotations

import contextlib
import logging
import numbers
from collections.abc import Callable, Iterable
from typing import Any, TypeVar

from hydrokit.errors import InputError, MissingExtraError

T = TypeVar("T")
R = TypeVar("R")


class _DropComputeFailed(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return not str(record.msg).startswith("Compute Failed")


def _quiet_task_failures() -> None:
    """Run on each local worker: a failed task's exception reaches the caller, its worker log is a duplicate."""
    logging.getLogger("distributed.worker").addFilter(_DropComputeFailed())


def _quiet_resource_tracker() -> None:
    """Start multiprocessing's resource tracker with its leaked-semaphore warning off.

    A run stopped by a signal can end before the LocalCluster's worker nannies release their
    semaphores; the tracker, a process of its own writing to this process's stderr, unlinks
    them anyway and would print a two-line warning under the one-line "interrupted" message.
    The tracker takes its warning filters from ``-W`` options given when it starts.
    """
    import sys
    from multiprocessing import resource_tracker

    saved = list(sys.warnoptions)
    sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    try:
        resource_tracker.ensure_running()
    finally:
        sys.warnoptions[:] = saved


class Executor:
    """Run ``fn(item)`` for every item, serially or on Dask; use as a context manager.

    Parameters
    ----------
    workers : int, optional
        Number of local worker processes (one thread each). None, 0 or 1 runs serially in
        this process; 2 or more starts a Dask LocalCluster listening on 127.0.0.1 only.
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``tcp://127.0.0.1:8786``; its workers are used.
    timeout : float, optional
        Time to wait when connecting to ``scheduler`` [s].

    Raises
    ------
    InputError
        On a bad ``workers`` value, ``workers`` >= 2 together with ``scheduler``, or (on enter)
        an unreachable scheduler.
    MissingExtraError
        On enter, if Dask is needed but not installed.
    """

    def __init__(self, workers: int | None = None, scheduler: str | None = None, *, timeout: float = 5.0):
        if workers is not None and (
            isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 0
        ):
            raise InputError(
                f"--workers = {workers!r}: expected a whole number of worker processes >= 0 (0, 1: serial)"
            )
        if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
            raise InputError(f"--scheduler = {scheduler!r}: expected a scheduler address, e.g. tcp://127.0.0.1:8786")
        self.workers = int(workers or 0)
        self.scheduler = scheduler.strip() if scheduler is not None else None
        if self.scheduler is not None and self.workers >= 2:
            raise InputError(
                f"--workers = {self.workers} with --scheduler = {self.scheduler!r}: give one or the other "
                "(a running scheduler brings its own workers)"
            )
        self.timeout = timeout
        self._client: Any = None
        self._stack: contextlib.ExitStack | None = None

    @property
    def serial(self) -> bool:
        """True if tasks run in a plain loop in this process."""
        return self.scheduler is None and self.workers < 2

    @property
    def description(self) -> str:
        """Where tasks run, for logs and reports, e.g. ``Dask LocalCluster, 2 workers (127.0.0.1)``."""
        if self.serial:
            return "serial"
        if self.scheduler is None:
            return f"Dask LocalCluster, {self.workers} workers (127.0.0.1)"
        return f"Dask scheduler {self.scheduler}"

    def __enter__(self) -> Executor:
        if self.serial:
            return self
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError as exc:
            raise MissingExtraError("dask", "dask") from exc
        with contextlib.ExitStack() as stack:
            if self.scheduler is None:
                _quiet_resource_tracker()
                cluster = LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=True,
                    host="127.0.0.1",
                    dashboard_address=None,
                    # no dashboard; its bare HTTP server (health, metrics) on a free loopback port, not :8787
                    scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                    # worker logs stay out of the user's stderr (one line per error): a task's
                    # exception reaches the caller through its future, a dead worker as
                    # KilledWorker, and a run stopped by a signal tears workers down mid-task,
                    # which they would report as cancelled tasks and lost heartbeats
                    silence_logs=logging.CRITICAL,
                )
                stack.enter_context(cluster)
                self._client = stack.enter_context(Client(cluster))
                self._client.run(_quiet_task_failures)
            else:
                try:
                    client = Client(self.scheduler, timeout=self.timeout)
                except Exception as exc:
                    reason = str(exc) or type(exc).__name__
                    raise InputError(
                        f"--scheduler = {self.scheduler!r}: cannot reach a Dask scheduler ({reason}); "
                        "expected the address of a running scheduler, e.g. tcp://127.0.0.1:8786"
                    ) from exc
                self._client = stack.enter_context(client)
            self._stack = stack.pop_all()  # on success keep cluster and client open until __exit__
        return self

    def __exit__(self, *exc_info: object) -> None:
        stack, self._stack, self._client = self._stack, None, None
        if stack is not None:
            stack.close()

    def map(self, fn: Callable[[T], R], items: Iterable[T], progress: Callable[[int], object] | None = None) -> list[R]:
        """Return ``[fn(item) for item in items]``, in input order whatever the completion order.

        A task's exception propagates with its type and message; the remaining tasks are cancelled.

        Parameters
        ----------
        fn : callable
            The task; with Dask it must pickle (a module-level function of an importable package).
        items : iterable
            One argument per task, carrying any random numbers or seeds the task needs.
        progress : callable, optional
            Called with 1 after each task completes.
        """
        items = list(items)
        if self.serial:
            results = []
            for item in items:
                results.append(fn(item))
                if progress is not None:
                    progress(1)
            return results
        if self._client is None:
            raise RuntimeError("a Dask Executor runs tasks only inside `with Executor(...) as ex:`")
        from dask.distributed import as_completed

        futures = self._client.map(fn, items, pure=False)
        where = {future.key: i for i, future in enumerate(futures)}
        out: list[Any] = [None] * len(items)
        try:
            for future in as_completed(futures):
                out[where[future.key]] = future.result()
                if progress is not None:
                    progress(1)
        except BaseException:
            self._client.cancel(futures)
            raise
        return out
