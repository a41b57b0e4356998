"""Automatic gain tuning: differential evolution over a controller's gains, each generation
flown as one fleet (:func:`hydrokit.simulate.fleet.fly_fleet`).

The cost of a gain set (lower is better), in metres-equivalent::

    J = cross_track · (cross-track RMS, m)
      + energy      · (thruster energy, kJ)
      + saturation  · (time with a thruster or allocation limit active, s)
      + incomplete  · (waypoints not reached)

each run stopping at its last waypoint (so energy and saturation are those spent to fly the
path). A run whose state becomes non-finite costs :data:`DIVERGED_COST`. The search variables
are the logarithms of the factors applied to the mission's own gains, within ``bounds``
(default ×0.2 … ×5): PID kp, ki, kd and S-plane k1, k2 of every loop, where the mission's gain
is non-zero (a zero gain stays zero; output limits and the S-plane scale are actuator limits,
not tuned). The mission's gains are a member of the first population, so the tuned cost is
never above the hand-picked one (when ×1 lies within the bounds).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit._result import Result, jsonable
from hydrokit.errors import InputError
from hydrokit.model.mission import CONTROLLER_KINDS, Mission
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate.mission import CONTROLLER_LABEL

#: default weights of the cost terms (see the module docstring for units)
DEFAULT_WEIGHTS = {"cross_track": 1.0, "energy": 0.001, "saturation": 0.001, "incomplete": 10.0}
#: units of the weights: metres of cost per unit of each term
WEIGHT_UNITS = {"cross_track": "m/m", "energy": "m/kJ", "saturation": "m/s", "incomplete": "m/waypoint"}
#: the cost of a diverged run (m-equivalent)
DIVERGED_COST = 1e6
#: gains tuned per controller kind
TUNED = {"pid": ("kp", "ki", "kd"), "s-plane": ("k1", "k2")}


@dataclass(frozen=True)
class TuneResult(Result):
    """A tuned gain set.

    Attributes
    ----------
    mission : Mission — the mission, with the tuned gains for ``controller``
    controller : str
    parameters : list of str — "loop.gain" searched
    before, after : dict — loop → gains (hand-picked, tuned)
    cost_before, cost_after : float — m-equivalent (module docstring)
    terms_before, terms_after : dict — the cost's terms (cross-track RMS m, energy kJ,
        saturation s, waypoints missed)
    evaluations : int — runs flown by the search
    generations : int
    elapsed : float — s
    convergence : list of float — best cost so far: the initial population, then each generation
    weights : dict ; bounds : (lo, hi) factors
    """

    mission: Mission
    controller: str
    parameters: list[str]
    before: dict[str, dict[str, float]]
    after: dict[str, dict[str, float]]
    cost_before: float
    cost_after: float
    terms_before: dict[str, float]
    terms_after: dict[str, float]
    evaluations: int
    generations: int
    elapsed: float
    convergence: list[float]
    weights: dict[str, float]
    bounds: tuple[float, float]

    def to_dict(self) -> dict[str, Any]:
        return jsonable(
            {
                "mission": self.mission.name,
                "controller": CONTROLLER_LABEL[self.controller],
                "cost_before": self.cost_before,
                "cost_after": self.cost_after,
                "terms_before": self.terms_before,
                "terms_after": self.terms_after,
                "gains_before": self.before,
                "gains_after": self.after,
                "parameters": self.parameters,
                "evaluations": self.evaluations,
                "generations": self.generations,
                "time_s": self.elapsed,
                "convergence": self.convergence,
                "weights": self.weights,
                "weight_units": WEIGHT_UNITS,
                "bounds_factor": list(self.bounds),
                "cost": "cross_track*RMS[m] + energy*E[kJ] + saturation*t_sat[s] + incomplete*missed "
                f"waypoints; diverged: {DIVERGED_COST:g}",
            }
        )

    def summary_rows(self) -> list[tuple[str, Any]]:
        return [
            ("mission", self.mission.name),
            ("controller", CONTROLLER_LABEL[self.controller]),
            ("cost before", self.cost_before),
            ("cost after", self.cost_after),
            ("cross-track RMS before (m)", self.terms_before["cross_track_rms"]),
            ("cross-track RMS after (m)", self.terms_after["cross_track_rms"]),
            ("evaluations", self.evaluations),
            ("time (s)", self.elapsed),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Best cost per generation on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot._mpl import axes_or_new

        ax = axes_or_new(ax)
        ax.plot(np.arange(len(self.convergence)), self.convergence, "o-", ms=3, label="best so far")
        ax.axhline(self.cost_before, color="k", ls="--", lw=1.0, label="hand-picked gains")
        ax.set_xlabel("generation")
        ax.set_ylabel("cost (m-equivalent)")
        ax.legend(fontsize=8)
        return ax


def parse_weights(text: str | None) -> dict[str, float]:
    """``"cross_track=1,energy=0.01"`` → the full weights mapping (defaults for the rest)."""
    out = dict(DEFAULT_WEIGHTS)
    for item in (text or "").split(","):
        if not item.strip():
            continue
        key, sep, val = item.partition("=")
        key = key.strip()
        try:
            v = float(val)
        except ValueError:
            v = math.nan
        if not sep or key not in out or not (math.isfinite(v) and v >= 0):
            raise InputError(
                f"weights item {item.strip()!r}: expected name=value (value ≥ 0) with name one of {', '.join(out)}"
            )
        out[key] = v
    return out


def search_space(mission: Mission, kind: str) -> list[tuple[str, str, float]]:
    """(loop, gain, hand-picked value) of every tuned gain (non-zero in the mission)."""
    if kind not in CONTROLLER_KINDS:
        raise InputError(f"controller = {kind!r}: expected one of {', '.join(CONTROLLER_KINDS)}")
    mission.autopilot(kind)  # validates that the mission has this controller's gains
    return [
        (lp, g, float(gains[g]))
        for lp, gains in mission.gains[kind].items()
        for g in TUNED[kind]
        if g in gains and float(gains[g]) != 0.0
    ]


def gains_for(mission: Mission, kind: str, space: list[tuple[str, str, float]], log_factors: Any) -> dict:
    """The mission's gains for ``kind`` with the searched ones scaled by exp(log_factors)."""
    g = {lp: dict(v) for lp, v in mission.gains[kind].items()}
    for (lp, name, base), lf in zip(space, np.asarray(log_factors, float)):
        g[lp][name] = base * math.exp(float(lf))
    return g


def costs(fleet: Any, weights: dict[str, float]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Cost of each run of a fleet and its terms."""
    m = fleet.metrics
    energy = np.nan_to_num(m["thruster_energy"], nan=0.0) / 1000.0
    missed = np.sum(~np.isfinite(fleet.waypoint_times), axis=1).astype(float)
    terms = {
        "cross_track_rms": m["cross_track_rms"],
        "thruster_energy_kJ": energy,
        "saturation_time": m["saturation_time"],
        "waypoints_missed": missed,
    }
    j = (
        weights["cross_track"] * terms["cross_track_rms"]
        + weights["energy"] * energy
        + weights["saturation"] * terms["saturation_time"]
        + weights["incomplete"] * missed
    )
    j = np.where(np.isfinite(fleet.diverged_at) | ~np.isfinite(j), DIVERGED_COST, j)
    return j, terms


def tune_gains(
    mission: Mission,
    vehicle: Vehicle,
    controller: str,
    *,
    weights: dict[str, float] | None = None,
    bounds: tuple[float, float] = (0.2, 5.0),
    maxiter: int = 50,
    popsize: int = 6,
    seed: int = 0,
    workers: int | None = None,
    duration: float | None = None,
) -> TuneResult:
    """Tune ``controller``'s gains of ``mission`` for ``vehicle`` (see the module docstring).

    Parameters
    ----------
    mission, vehicle : what to fly
    controller : "pid" or "s-plane"
    weights : cost weights (default :data:`DEFAULT_WEIGHTS`)
    bounds : (lo, hi) — factor range around the mission's gains, 0 < lo ≤ hi
    maxiter, popsize : differential evolution generations and population per parameter
    seed : int — the search is reproducible for a seed
    workers : int, optional — threads flying each generation's fleet (default: all)
    duration : float, optional — s (default: the mission's)

    Raises
    ------
    InputError
        A bound with min > max or ≤ 0, no gains to tune, bad weights, an empty path.
    """
    lo, hi = float(bounds[0]), float(bounds[1])
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
        raise InputError(f"tuner bounds {lo:g} … {hi:g}: expected factors with 0 < min ≤ max")
    if maxiter < 1 or popsize < 1:
        raise InputError(f"maxiter = {maxiter}, popsize = {popsize}: expected whole numbers ≥ 1")
    if mission.path.n_legs < 1:
        raise InputError("the mission's waypoint list is empty; expected at least 2 waypoints")
    w = dict(DEFAULT_WEIGHTS) | dict(weights or {})
    space = search_space(mission, controller)
    if not space:
        raise InputError(f"controllers.{controller}: every gain is zero; nothing to tune", mission.source)
    if workers is not None and workers < 1:
        raise InputError(f"workers = {workers}: expected a whole number ≥ 1")
    import numba

    threads = numba.get_num_threads()
    if workers is not None:
        numba.set_num_threads(min(int(workers), int(numba.config.NUMBA_NUM_THREADS)))  # type: ignore[attr-defined]
    try:
        return _search(mission, vehicle, controller, w, space, lo, hi, maxiter, popsize, seed, duration)
    finally:
        numba.set_num_threads(threads)


def _search(
    mission: Mission,
    vehicle: Vehicle,
    controller: str,
    w: dict[str, float],
    space: list[tuple[str, str, float]],
    lo: float,
    hi: float,
    maxiter: int,
    popsize: int,
    seed: int,
    duration: float | None,
) -> TuneResult:
    from scipy.optimize import differential_evolution

    from hydrokit._atomic import raise_if_interrupted
    from hydrokit.simulate.fleet import fly_fleet

    def fly(log_factors: np.ndarray) -> Any:
        gains = [gains_for(mission, controller, space, col) for col in log_factors.T]
        return fly_fleet(mission, vehicle, controller, gains=gains, duration=duration, stop_when_done=True)

    best: list[float] = []
    count = [0]

    def objective(x: np.ndarray) -> np.ndarray:
        raise_if_interrupted()  # a SIGTERM swallowed inside numba's compiler callback stops here
        x2 = np.asarray(x, float).reshape(len(space), -1)
        j, _ = costs(fly(x2), w)
        count[0] += x2.shape[1]
        best.append(float(min(j.min(), best[-1] if best else math.inf)))
        return j

    t0 = time.perf_counter()
    x0 = np.zeros(len(space))
    j0, t_before = costs(fly(x0[:, None]), w)
    b = [(math.log(lo), math.log(hi))] * len(space)
    if lo == hi:
        x_best = np.full(len(space), math.log(lo))
        gens = 0
    else:
        with quiet("scipy differential_evolution", streams=False):  # our progress bar draws meanwhile
            res = differential_evolution(
                objective,
                b,
                maxiter=maxiter,
                popsize=popsize,
                seed=seed,
                polish=False,
                vectorized=True,
                updating="deferred",
                x0=np.clip(x0, math.log(lo), math.log(hi)),
                tol=1e-6,
            )
        x_best, gens = res.x, int(res.nit)
    j1, t_after = costs(fly(x_best[:, None]), w)
    elapsed = time.perf_counter() - t0
    after = gains_for(mission, controller, space, x_best)
    tuned = replace(mission, gains=mission.gains | {controller: after}, controller=controller)
    return TuneResult(
        mission=tuned,
        controller=controller,
        parameters=[f"{lp}.{g}" for lp, g, _ in space],
        before={lp: dict(v) for lp, v in mission.gains[controller].items()},
        after=after,
        cost_before=float(j0[0]),
        cost_after=float(j1[0]),
        terms_before={k: float(v[0]) for k, v in t_before.items()},
        terms_after={k: float(v[0]) for k, v in t_after.items()},
        evaluations=count[0],
        generations=gens,
        elapsed=elapsed,
        convergence=best,
        weights=w,
        bounds=(lo, hi),
    )
