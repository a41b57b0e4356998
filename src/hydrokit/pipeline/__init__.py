"""The main job (``hydrokit run``): tank launches → full-scale coefficients → vehicle → mission.

Steps, each cached under the hash of its inputs (``OUT/.cache``; ``force`` redoes all):

1. identify every campaign (per-launch fits serial or on Dask) and scale it to full size;
2. estimate from the geometry file (and BEM) and fit the CFD/tow force curves;
3. compare every source with the tank (relative differences) and choose per the project's rule;
4. write the vehicle document with the chosen diagonals and an ``uncertainty:`` block;
5. fly the mission with PID and S-plane on the identified vehicle (and on the true one when the
   data are virtual and the truth is known);
6. Monte Carlo: sample the coefficients from their covariance and fly every sample.

The run folder's own files (report, results.json, vehicle.yaml, mission/) are cached the same
way: :func:`up_to_date` says whether a folder already holds them for unchanged inputs, options
and hydrokit, and :func:`hydrokit.report.run.write_run_folder` writes nothing when they are.

:func:`run_project` returns a :class:`RunResult`; :func:`hydrokit.report.run.write_run` writes
it (report, results.json, vehicle.yaml, mission/).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hydrokit.errors import InputError
from hydrokit.io.project import Project, load_project
from hydrokit.pipeline.cache import StepCache, digest, file_digest
from hydrokit.pipeline.result import RunResult

#: progress reporter: ``progress(label, total)`` → ``advance(n)``
Progress = Callable[[str, int], Callable[[int], None]]
CONTROLLERS = ("pid", "s-plane")


class _Mapper:
    """Serial or Dask map, the Dask cluster started on first use (a cached run never starts one)."""

    def __init__(self, workers: int | None, scheduler: str | None):
        from hydrokit._parallel import Executor

        self.note = ""
        if workers is None and scheduler is None:
            workers = default_workers()
            if workers <= 1:
                self.note = "serial: Dask is not installed (pip install 'hydrokit[dask]') or one core"
        self._make = lambda: Executor(workers, scheduler)
        self._ex: Any = None
        self.serial = scheduler is None and (workers is None or workers <= 1)
        if scheduler is not None:
            self._ex = self._make().__enter__()  # an unreachable scheduler fails before any step

    def __call__(self, fn: Callable[..., Any], items: list[Any], progress: Callable[[int], None] | None) -> list[Any]:
        if self._ex is None:
            self._ex = self._make().__enter__()
        return self._ex.map(fn, items, progress)

    @property
    def description(self) -> str:
        if self._ex is not None:
            return self.note or self._ex.description
        return self.note or ("serial" if self.serial else "Dask (not started: every step was cached)")

    def close(self) -> None:
        if self._ex is not None:
            self._ex.__exit__(None, None, None)
            self._ex = None


def default_workers() -> int:
    """Local Dask workers when none are asked for: one per core (at most 4) when Dask is
    installed, else 1 (serial)."""
    import importlib.util

    if importlib.util.find_spec("distributed") is None:
        return 1
    return max(1, min(4, os.cpu_count() or 1))


def _no_progress(label: str, total: int) -> Callable[[int], None]:
    return lambda n: None


def run_project(
    project: Project | str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    *,
    force: bool = False,
    bem: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    samples: int | None = None,
    progress: Progress | None = None,
) -> RunResult:
    """Run the main job of ``project`` with its step cache in ``out_dir/.cache``.

    Parameters
    ----------
    project : Project, or a project file, folder or bundled name (``udrobot``, ``rov2``)
    out_dir : folder of the run (only the cache is written here; see ``write_run``)
    force : bool — recompute every step
    bem : bool — boundary-element added mass from the geometry (``hydrokit[bem]``)
    workers : int, optional — Dask local workers (≥ 2) for launch fits and Monte Carlo;
        0 or 1 = serial in this process; None = one per core when ``hydrokit[dask]`` is
        installed (the cluster starts only if a step has to be computed)
    scheduler : str, optional — address of a running Dask scheduler (``tcp://host:8786``)
    samples : int, optional — Monte Carlo samples (count), overrides the project's
    progress : callable, optional — ``progress(label, total)`` returns ``advance(n)``

    Returns
    -------
    RunResult

    Raises
    ------
    InputError
        A bad project (naming the field), a mission for a vehicle without thrusters, an
        unreachable scheduler. Steps finished before the error stay cached.
    """
    from hydrokit.pipeline.steps import Runner

    proj = project if isinstance(project, Project) else load_project(project)
    if samples is not None and samples < 0:
        raise InputError(f"--samples = {samples}: expected a count ≥ 0")
    cache = StepCache(Path(out_dir) / ".cache", force=force)
    mapper = _Mapper(workers, scheduler)
    try:
        runner = Runner(
            proj, cache, mapper, progress or _no_progress, bem, proj.samples if samples is None else samples
        )
        return runner.run()
    finally:
        mapper.close()


def up_to_date(
    project: Project, out_dir: str | os.PathLike[str], *, bem: bool = False, samples: int | None = None
) -> bool:
    """True when ``out_dir`` holds the files of a run of ``project`` with these options and
    nothing has changed since: no input file, option or hydrokit source, and no output file
    edited (:func:`hydrokit.pipeline.cache.outputs_current`). Reads only the input files'
    bytes (hashes them), so ``project`` may come from :func:`hydrokit.io.project.parse_project`
    without :func:`~hydrokit.io.project.check_inputs`; a file that cannot be read gives False.

    Parameters
    ----------
    project : Project
    out_dir : the run folder (directory)
    bem : bool — the run's ``bem`` option
    samples : int, optional — Monte Carlo samples (count); None = the project's
    """
    from hydrokit.pipeline.cache import outputs_current, project_key

    try:
        return outputs_current(out_dir, project_key(project, bem, samples))
    except OSError:  # an input that vanished: the full run names it
        return False


__all__ = ["RunResult", "digest", "file_digest", "run_project", "up_to_date"]
