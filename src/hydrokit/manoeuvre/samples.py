"""Predictions with intervals: ``hydrokit manoeuvre --samples N`` (issue #48 item 7).

N vehicles are drawn from the vehicle file's ``uncertainty:`` block (the sysid covariance;
:meth:`hydrokit.model.uncertainty.Uncertainty.sample_vehicles`, one seeded generator, the draw
``simulate --samples`` and ``mission --samples`` use), each flies the same manoeuvre, and every
numeric metric gets its median and 95 % interval (the 2.5 and 97.5 % points of the draws that
reached it). Each draw flies through the compiled manoeuvre loop
(:mod:`hydrokit.manoeuvre.compiled`: logic, holds, servo, thruster drive and RK4 compiled), the
draws as a fleet on threads — one per core, up to two (the loop's kernels release the GIL); the
draws are made before any flies, so the intervals do not depend on the order they finish in.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit.errors import InputError, SimulationError

#: the central interval reported, as a fraction
COVERAGE = 0.95
#: most sample tracks kept for the figures (the intervals use every draw)
SHOWN_TRACKS = 50
#: most threads that fly the draws at once (count; the machines we run on have 2 cores)
WORKERS = 2


def numeric_metrics(metrics: dict[str, Any], prefix: str = "") -> dict[str, float | None]:
    """Every numeric metric of ``metrics`` by name (a nested dict's as ``outer.inner``, a list's
    items as ``outer[k].inner``); None where a metric was not reached; flags and words left out."""
    out: dict[str, float | None] = {}
    for key, value in metrics.items():
        name = f"{prefix}{key}"
        if isinstance(value, bool) or isinstance(value, str):
            continue
        if isinstance(value, dict):
            out |= numeric_metrics(value, name + ".")
        elif isinstance(value, (list, tuple)):
            for k, item in enumerate(value):
                if isinstance(item, dict):
                    out |= numeric_metrics(item, f"{name}[{k}].")
        elif value is None or isinstance(value, (int, float, np.floating, np.integer)):
            out[name] = None if value is None or not np.isfinite(float(value)) else float(value)
    return out


def intervals(nominal: dict[str, Any], draws: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """``{metric: {median, low95, high95, samples}}`` for every numeric metric of ``nominal``
    (the flown vehicle's metrics), from the same metric of each draw in ``draws`` (``samples``:
    how many draws reached it; median and bounds None when none did).

    The bounds are the (1 ∓ :data:`COVERAGE`)/2 quantiles, linear between order statistics
    (numpy's default)."""
    flat = [numeric_metrics(d) for d in draws]
    tail = 50.0 * (1.0 - COVERAGE)
    out: dict[str, dict[str, Any]] = {}
    for name in numeric_metrics(nominal):
        values = np.array([f[name] for f in flat if f.get(name) is not None], float)
        if values.size:
            lo, mid, hi = np.percentile(values, [tail, 50.0, 100.0 - tail])
            out[name] = {"median": float(mid), "low95": float(lo), "high95": float(hi), "samples": int(values.size)}
        else:
            out[name] = {"median": None, "low95": None, "high95": None, "samples": 0}
    return out


@dataclass
class SampledManoeuvres:
    """The draws flown.

    Attributes
    ----------
    parameters : tuple of str — the uncertainty block's parameters
    values : (n, p) — the drawn coefficients, SI
    sigma : (p,) — their stated σ, SI
    metrics : list of dict — each draw's metrics (SI; ``*_deg`` in degrees)
    tracks : list of (k, 4) arrays — time (s, 0 at the execute), x, y, z (m) of the first
        :data:`SHOWN_TRACKS` draws (positions from the execute point)
    failed : list of str — why a draw flew nothing (a vehicle the dynamics refused, or whose
        state became non-finite)
    incomplete : int — draws with a ``problem`` (some of their metrics are None)
    clipped : int — drawn entries below zero, set to 0
    seed : int
    """

    parameters: tuple[str, ...]
    values: np.ndarray
    sigma: np.ndarray
    metrics: list[dict[str, Any]]
    tracks: list[np.ndarray] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)
    incomplete: int = 0
    clipped: int = 0
    seed: int = 1

    def sampling(self) -> dict[str, Any]:
        """manoeuvre.json's ``sampling``: the draw that the intervals come from (SI)."""
        return {
            "samples": int(self.values.shape[0]),
            "seed": self.seed,
            "parameters": list(self.parameters),
            "sigma": self.sigma.tolist(),
            "coverage": COVERAGE,
            "failed": len(self.failed),
            "incomplete": self.incomplete,
            "clipped_at_zero": self.clipped,
        }


def check_samples(vehicle: Any, samples: int) -> None:
    """Refuse a ``--samples`` the vehicle cannot honour (0: none asked, nothing to check)."""
    if samples == 0:
        return
    if not isinstance(samples, int) or samples < 2:
        raise InputError(f"--samples {samples}: expected a whole number ≥ 2 (vehicles to draw)")
    if vehicle.uncertainty is None:
        raise InputError(
            f"--samples {samples}: vehicle '{vehicle.name}' has no 'uncertainty:' block with a σ > 0; expected a "
            "vehicle file written by 'hydrokit run' or 'hydrokit sysid' (or one with standard errors, SI)"
        )


def fly_samples(
    vehicle: Any,
    samples: int,
    seed: int,
    fly: Callable[[Any], Any],
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
) -> SampledManoeuvres:
    """Draw ``samples`` vehicles from ``vehicle.uncertainty`` and fly each with ``fly(vehicle)``
    (a result with ``metrics``, ``time``, ``eta`` and ``problem``), ``workers`` at a time on
    threads (None: one per core, up to :data:`WORKERS`; 1: one after the other). The results
    are kept in the draws' order.

    Parameters
    ----------
    vehicle : Vehicle — with an ``uncertainty`` block
    samples : int — how many vehicles, ≥ 2
    seed : int — of the one generator that draws them
    fly : callable(Vehicle) → ManoeuvreResult
    progress : callable(draws flown, samples) or None
    workers : int or None — threads (count)

    Raises
    ------
    InputError
        No uncertainty block, or ``samples`` below 2.
    """
    check_samples(vehicle, samples)
    unc = vehicle.uncertainty
    vehicles, values, clipped = unc.sample_vehicles(vehicle, samples, seed)
    out = SampledManoeuvres(tuple(unc.parameters), values, unc.std, [], clipped=clipped, seed=int(seed))

    def one(v: Any) -> Any:
        try:
            return fly(v)
        except (InputError, SimulationError) as exc:  # refused (a singular mass) or diverged
            return exc

    n_workers = min(WORKERS, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    if n_workers == 1:
        flown = []
        for k, v in enumerate(vehicles):
            flown.append(one(v))
            if progress is not None:
                progress(k + 1, samples)
    else:
        from concurrent.futures import ThreadPoolExecutor, as_completed

        with ThreadPoolExecutor(max_workers=n_workers) as pool:
            futures = [pool.submit(one, v) for v in vehicles]
            for done, _ in enumerate(as_completed(futures), 1):
                if progress is not None:
                    progress(done, samples)
            flown = [f.result() for f in futures]
    for k, res in enumerate(flown):
        if isinstance(res, Exception):
            out.failed.append(f"sample {k}: {res}")
            out.metrics.append({})
        else:
            out.metrics.append(res.metrics)
            out.incomplete += res.problem is not None
            if len(out.tracks) < SHOWN_TRACKS:
                out.tracks.append(np.column_stack([res.time, res.eta[:, :3]]))
    return out


def add_intervals(
    result: Any,
    vehicle: Any,
    samples: int,
    seed: int,
    fly: Callable[[Any], Any],
    progress: Callable[[int, int], None] | None = None,
) -> SampledManoeuvres | None:
    """Fly ``samples`` draws (:func:`fly_samples`) and set ``result.intervals`` (about its
    metrics), ``result.sampling`` and ``result.sample_tracks``; a failed or incomplete draw is
    said in ``result.warnings``. Nothing is flown for ``samples`` = 0 (returns None)."""
    if samples == 0:
        return None
    drawn = fly_samples(vehicle, samples, seed, fly, progress)
    result.intervals = intervals(result.metrics, drawn.metrics)
    result.sampling = drawn.sampling()
    result.sample_tracks = drawn.tracks
    if drawn.failed:
        result.warnings.append(f"{len(drawn.failed)} of {samples} drawn vehicle(s) could not fly: {drawn.failed[0]}")
    if drawn.incomplete:
        result.warnings.append(
            f"{drawn.incomplete} of {samples} drawn vehicle(s) did not complete the manoeuvre; each interval "
            "uses the draws that reached its metric (its 'samples')"
        )
    return drawn


def interval_lines(found: dict[str, dict[str, Any]]) -> list[str]:
    """The intervals of the manoeuvre's own metrics as lines ``name: median (95 %: low to high
    unit, N samples)`` (the spiral's steps and the pull-out's sides stay in manoeuvre.json)."""
    from hydrokit.manoeuvre.metrics import shown

    lines = []
    for name, iv in found.items():
        if "[" in name or "." in name:
            continue
        if not iv["samples"]:
            lines.append(f"{name.replace('_', ' ')}: not reached by any sample")
            continue
        low, high = shown(name, iv["low95"]).split(" ")[0], shown(name, iv["high95"])
        lines.append(
            f"{name.replace('_', ' ')}: median {shown(name, iv['median'])} (95 %: {low} to {high}, "
            f"{iv['samples']} samples)"
        )
    return lines
