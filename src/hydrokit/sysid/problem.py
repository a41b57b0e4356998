"""The output-error problem shared by the whole-run fit (:mod:`hydrokit.sysid.fit`), the windowed
fit (:mod:`hydrokit.sysid.window`) and the experiment design (:mod:`hydrokit.sysid.plan`): the
weighted residuals of every run's open-loop simulation and their forward-difference Jacobian,
all perturbed vehicles of a run integrated at once on the compiled batch RK4.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.model import CHANNELS, Parameter, PreparedRun, simulate_run, stack_packs, take, with_values

#: initial states that move a prediction only by shifting their own channel: the north and east
#: positions (no force depends on where the vehicle is — current and wind are functions of time),
#: so their Jacobian columns are known without a simulation; state index → channel
TRANSLATION = {0: CHANNELS[0], 1: CHANNELS[1]}


def channel_rows(prep: PreparedRun, channel: str) -> slice:
    """The rows of ``channel`` in a prepared run's stacked residuals (an empty slice when the
    run does not measure it)."""
    k = 0
    for c, t in zip(prep.channels, prep.times):
        if c == channel:
            return slice(k, k + t.size)
        k += t.size
    return slice(k, k)


@dataclass
class Problem:
    """The output-error problem of a fit: the free parameters of ``vehicle``, the prepared runs
    and their initial states (``est``: which of them are estimated), each channel's noise σ
    (SI); :meth:`evaluate` gives the weighted residuals and their Jacobian. The windowed fit
    (:mod:`hydrokit.sysid.window`) subclasses it."""

    vehicle: Vehicle
    params: list[Parameter]
    preps: list[PreparedRun]
    x0: list[np.ndarray]  # per run, 12 states
    est: list[np.ndarray]  # per run, indices of the estimated initial states
    sigma: dict[str, float]
    sim_seconds: float = 0.0
    executor: Any = None  # hydrokit._parallel.Executor: the runs' simulations on Dask (None: here)

    @property
    def n_nuisance(self) -> int:
        return int(sum(e.size for e in self.est))

    def weights(self, prep: PreparedRun) -> np.ndarray:
        return np.concatenate([np.full(t.size, 1.0 / self.sigma[c]) for c, t in zip(prep.channels, prep.times)])

    def row_weights(self) -> np.ndarray:
        """The weight (1/σ of its channel, 1/SI) of every residual row, run after run."""
        return np.concatenate([self.weights(prep) for prep in self.preps])

    def unpack(self, z: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        p = len(self.params)
        theta = z[:p]
        x0s, k = [], p
        for x, e in zip(self.x0, self.est):
            xx = x.copy()
            xx[e] = z[k : k + e.size]
            x0s.append(xx)
            k += e.size
        return theta, x0s

    def packs(self, theta: np.ndarray, scale: np.ndarray, jac: bool) -> dict[str, Any]:
        """The compiled tables of the vehicle at ``theta`` (SI) and, if ``jac``, of one vehicle
        per parameter nudged by 1e-6 of its ``scale`` (the forward differences)."""
        vehicles = [with_values(self.vehicle, self.params, theta)]
        if jac:
            for k in range(len(self.params)):
                th = theta.copy()
                th[k] += 1e-6 * scale[k]
                vehicles.append(with_values(self.vehicle, self.params, th))
        return stack_packs(vehicles)

    def evaluate(self, z: np.ndarray, scale: np.ndarray, jac: bool) -> tuple[np.ndarray, np.ndarray | None, bool]:
        """Weighted residuals (and Jacobian w.r.t. z/scale) of every run."""
        from hydrokit.sysid.kernels import difference_columns

        p = len(self.params)
        theta, x0s = self.unpack(z)
        packs = self.packs(theta, scale, jac)
        res = []
        n_cols = p + self.n_nuisance
        col = p
        tasks = []
        for prep, x0, e in zip(self.preps, x0s, self.est):
            # the perturbed initial states that need a simulation (not the translations)
            moved = [(j, i) for j, i in enumerate(e) if i not in TRANSLATION] if jac else []
            index = list(range(p + 1)) + [0] * len(moved) if jac else [0]
            X0 = np.repeat(x0[None], len(index), axis=0)
            for k, (j, i) in enumerate(moved):
                X0[p + 1 + k, i] += 1e-6 * scale[col + j]
            tasks.append((prep, take(packs, index), X0))
            col += e.size
        # the runs (each with its perturbed vehicles and initial states) are independent tasks
        sims = [simulate_task(t) for t in tasks] if self.executor is None else self.executor.map(simulate_task, tasks)
        col = p
        # the Jacobian written in place, run after run (one array instead of blocks joined)
        J_all = np.zeros((sum(prep.n_samples for prep in self.preps), n_cols)) if jac else None
        row = 0
        for prep, e, (pred, done, seconds) in zip(self.preps, self.est, sims):
            w = self.weights(prep)
            self.sim_seconds += seconds
            if done[0] < math.ceil(prep.duration / prep.dt - 1e-9) or not np.all(np.isfinite(pred[0])):
                return np.empty(0), None, False
            r = (prep.measured - pred[0]) * w
            res.append(r)
            if J_all is not None:
                J = J_all[row : row + r.size]
                # the perturbed vehicles' columns: the p parameters, then the initial states
                # that were simulated (per unit of the scaled variable)
                cols = list(range(p)) + [col + j for j, i in enumerate(e) if i not in TRANSLATION]
                difference_columns(pred, w, np.array(cols, dtype=np.int64), J)
                for j, i in enumerate(e):
                    if i in TRANSLATION:  # the prediction of its channel shifts one for one
                        rows = channel_rows(prep, TRANSLATION[i])
                        J[rows, col + j] = -w[rows] * scale[col + j]
            row += r.size
            col += e.size
        return np.concatenate(res), J_all, True


def simulate_task(task: tuple[PreparedRun, Any, np.ndarray]) -> tuple[np.ndarray, np.ndarray, float]:
    """One run's batch of perturbed vehicles (a task for the Dask executor): predictions,
    steps done, seconds spent."""
    prep, packs, X0 = task
    t = _time.perf_counter()
    pred, done = simulate_run(prep, packs, X0)
    return pred, done, _time.perf_counter() - t
