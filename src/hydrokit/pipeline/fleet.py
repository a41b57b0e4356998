"""Steps 5–6 of ``hydrokit run``: fly the mission on the identified vehicle, then Monte Carlo.

The Monte Carlo draws every sample's coefficients up front from one seeded generator (so the
result does not depend on how samples are spread over workers), flies each sample with each
controller (each task's chunk of samples as one compiled fleet, :func:`fly_many`), and keeps per-sample metrics and the path on a common time grid. The envelope is
the per-time 5–95 % band and min–max of x, y, z over the samples; metric summaries are the
median and 5–95 % range.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES

#: the tracking metrics summarised over the samples (SI; see simulate.mission.METRIC_UNITS)
MC_METRICS = (
    "cross_track_rms",
    "cross_track_max",
    "depth_error_rms",
    "heading_error_rms",
    "final_time",
    "thruster_energy",
    "saturation_fraction",
)
#: path grid step of the envelope, s
GRID_STEP = 0.5
#: samples flown per worker task (fewer, larger tasks keep the scheduling overhead small)
CHUNK = 10
#: sample paths kept for the figure (the envelope uses all of them)
SHOWN_PATHS = 40


def task_count(samples: int, controllers: Sequence[str]) -> int:
    """How many worker tasks :func:`monte_carlo` maps (for a progress bar)."""
    return len(controllers) * math.ceil(samples / CHUNK)


def with_coefficients(vehicle: Any, values: dict[str, float]) -> Any:
    """``vehicle`` with parameters replaced; keys ``"<coefficient>.<dof>"`` or ``"terms.<term>"``,
    SI (:func:`hydrokit.model.uncertainty.with_coefficients`)."""
    from hydrokit.model.uncertainty import with_coefficients as _with

    return _with(vehicle, values)


def fly_one(mission: Any, vehicle: Any, controller: str, grid: np.ndarray) -> dict[str, Any]:
    """Fly and keep the metrics and the path (x, y, z in m) on ``grid`` (s)."""
    from hydrokit.simulate.mission import fly_mission

    res = fly_mission(mission, vehicle, controller)
    t = res.time
    path = np.column_stack([np.interp(grid, t, res.eta[:, k], right=np.nan) for k in range(3)])
    m = res.metrics
    return {"metrics": {k: m.get(k) for k in MC_METRICS} | {"completed": bool(m.get("completed"))}, "path": path}


def sample_task(task: tuple[str, dict[str, Any], str, list[str], np.ndarray, np.ndarray]) -> list[dict[str, Any]]:
    """Fly a chunk of samples (a picklable task): (mission file, vehicle document, controller,
    parameter names, (k, p) sample values, time grid s)."""
    from hydrokit.api import load_mission, vehicle_from_dict

    mission_file, vehicle_doc, controller, names, values, grid = task
    mission = load_mission(mission_file)
    base = vehicle_from_dict(vehicle_doc, "vehicle.yaml")
    # one compiled single-run loop per sample (the kernel the nominal flights already compiled): at
    # a few hundred missions of ~10³ steps each it takes about a second, while the fleet kernel
    # (fly_many, identical results) costs a first-run compile of ~25 s per process on a fresh machine
    return [fly_one(mission, with_coefficients(base, dict(zip(names, row))), controller, grid) for row in values]


def fly_many(mission: Any, vehicles: Sequence[Any], controller: str, grid: np.ndarray) -> list[dict[str, Any]]:
    """:func:`fly_one` for each vehicle, flown as one compiled fleet
    (:func:`hydrokit.simulate.fleet.fly_fleet`; the same runs to ~1e-12)."""
    from hydrokit.errors import SimulationError
    from hydrokit.simulate.fleet import fly_fleet

    if not vehicles:
        return []
    # keep the steps fly_one's run records (every output_every-th), thinned to the grid when it allows
    every = mission.output_every
    ratio = GRID_STEP / (mission.dt * every)
    every *= round(ratio) if round(ratio) >= 1 and abs(ratio - round(ratio)) < 1e-9 else 1
    fleet = fly_fleet(mission, list(vehicles), controller, paths_every=every)
    bad = np.flatnonzero(np.isfinite(fleet.diverged_at))
    if bad.size:
        raise SimulationError(f"the state became non-finite at t = {fleet.diverged_at[bad[0]]:.6g} s")
    assert fleet.paths is not None and fleet.path_time is not None
    out = []
    for i in range(fleet.n):
        p = fleet.paths[i]
        path = np.column_stack([np.interp(grid, fleet.path_time, p[:, k], right=np.nan) for k in range(3)])
        m = fleet.member(i)
        out.append({"metrics": {k: m.get(k) for k in MC_METRICS} | {"completed": bool(m["completed"])}, "path": path})
    return out


def draw_samples(mean: np.ndarray, cov: np.ndarray, n: int, seed: int) -> tuple[np.ndarray, int]:
    """``n`` coefficient vectors from N(mean, cov) (one seeded generator), negatives set to 0
    (:meth:`hydrokit.model.uncertainty.Uncertainty.draw`).

    Returns the (n, p) samples and how many entries were clipped at zero.
    """
    from hydrokit.model.uncertainty import Uncertainty

    return Uncertainty(tuple(f"p{k}" for k in range(mean.size)), np.asarray(cov, float)).draw(mean, n, seed)


def grid_for(mission: Any) -> np.ndarray:
    """The envelope's time grid for ``mission``: 0 … duration every GRID_STEP s."""
    return np.arange(0.0, mission.duration + 1e-9, GRID_STEP)


def summarize_runs(runs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Median and 5–95 % of each metric; the path envelope (5/50/95 % and min/max per time)."""
    out: dict[str, Any] = {
        "n": len(runs),
        "completed_fraction": float(np.mean([r["metrics"]["completed"] for r in runs])),
    }
    stats = {}
    for k in MC_METRICS:
        v = np.array([r["metrics"][k] for r in runs if r["metrics"][k] is not None], float)
        v = v[np.isfinite(v)]
        stats[k] = (
            {"median": float(np.median(v)), "p5": float(np.percentile(v, 5)), "p95": float(np.percentile(v, 95))}
            if v.size
            else {"median": None, "p5": None, "p95": None}
        )
    out["metrics"] = stats
    from hydrokit.simulate.samples import envelope

    out["envelope"] = envelope(np.stack([r["path"] for r in runs]))  # (n, t, 3): band → (t, 3)
    return out


def containment(path: np.ndarray, envelope: dict[str, Any], band: tuple[str, str] = ("min", "max")) -> float:
    """Fraction of grid times at which ``path`` (t, 3) lies inside the envelope in x, y and z."""
    lo, hi = np.asarray(envelope[band[0]], float), np.asarray(envelope[band[1]], float)
    ok = np.isfinite(path).all(axis=1) & np.isfinite(lo).all(axis=1)
    inside = np.all((path >= lo - 1e-9) & (path <= hi + 1e-9), axis=1)
    return float(np.mean(inside[ok])) if ok.any() else math.nan


def monte_carlo(
    mission_file: str,
    vehicle_doc: dict[str, Any],
    controllers: Sequence[str],
    samples: int,
    seed: int,
    mapper: Callable[..., list[Any]],
    advance: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """Sample the covariance of the vehicle document's ``uncertainty`` block (as the vehicle file
    reader parses it: every coefficient with a σ) and fly every sample with every controller.
    Returns per controller the summary, plus the samples' parameter names."""
    from hydrokit.api import load_mission, vehicle_from_dict
    from hydrokit.model.uncertainty import parameter_value

    vehicle = vehicle_from_dict(vehicle_doc, "vehicle.yaml")
    unc = vehicle.uncertainty
    names = list(unc.parameters) if unc is not None else []
    mean = np.array([parameter_value(vehicle, p) for p in names], float)
    values, clipped = unc.draw(mean, samples, seed) if unc is not None else (np.zeros((samples, 0)), 0)
    grid = grid_for(load_mission(mission_file))
    tasks = []
    for c in controllers:
        for k in range(0, samples, CHUNK):
            tasks.append((mission_file, vehicle_doc, c, names, values[k : k + CHUNK], grid))

    done = mapper(sample_task, tasks, advance)
    out: dict[str, Any] = {
        "parameters": names,
        "samples": samples,
        "seed": seed,
        "clipped_at_zero": clipped,
        "grid": grid,
        "controllers": {},
    }
    i = 0
    for c in controllers:
        runs: list[dict[str, Any]] = []
        for _k in range(0, samples, CHUNK):
            runs += done[i]
            i += 1
        shown = np.stack([r["path"] for r in runs[:SHOWN_PATHS]])
        out["controllers"][c] = summarize_runs(runs) | {"sample_paths": shown}
    return out


def _nominal(doc: dict[str, Any], name: str) -> float:
    """The document's entry of a diagonal coefficient ``"<coefficient>.<dof>"`` (SI). The Monte
    Carlo reads the vehicle's values instead (:func:`hydrokit.model.uncertainty.parameter_value`:
    acceleration terms included, ``terms.*`` too)."""
    coef, dof = name.split(".")
    i = DOF_NAMES.index(dof)
    v = doc[coef]
    return float(v[i][i] if isinstance(v[i], list) else v[i])
