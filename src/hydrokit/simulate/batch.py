"""Batch simulation: many vehicles or parameter sets at once (Monte Carlo over coefficient
uncertainty). Each vehicle is integrated by the compiled RK4 on its own core thread."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.names import STATE_COLUMNS
from hydrokit.errors import InputError
from hydrokit.model.dynamics import current_table, pack, stack_scal
from hydrokit.model.vehicle import Vehicle


@dataclass(frozen=True)
class BatchTrajectory(Result):
    """Many vehicles integrated side by side.

    Attributes
    ----------
    time : (n_out,) — s
    states : (n_vehicles, n_out, 12) — η (m, rad) then ν (m/s, rad/s); 13 columns with the
        quaternion attitude (x, y, z, q0..q3, ν)
    steps : (n_vehicles,) — steps taken (fewer when a vehicle's state became non-finite)
    attitude : str — "euler" or "quaternion"
    """

    time: np.ndarray
    states: np.ndarray
    steps: np.ndarray
    attitude: str = "euler"

    def __len__(self) -> int:
        return int(self.states.shape[0])

    def __getitem__(self, key: str) -> np.ndarray:
        """Mapping access by field name ("time", "states", "steps") for older callers."""
        if key not in ("time", "states", "steps"):
            raise KeyError(key)
        return getattr(self, key)

    @property
    def failed(self) -> np.ndarray:
        """Indices of vehicles whose state became non-finite before the end."""
        full = int(round(self.time[-1] / (self.time[1] - self.time[0]))) if self.time.size > 1 else 0
        return np.nonzero(self.steps < np.max(self.steps, initial=full))[0]

    def to_dict(self) -> dict[str, Any]:
        """Times, final states and steps of every vehicle (JSON-ready; SI)."""
        return jsonable(
            {
                "attitude": self.attitude,
                "time": self.time,
                "final_states": self.states[:, -1, :],
                "steps": self.steps,
                "vehicles": len(self),
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """One row per vehicle: its index and final state (Euler attitude only)."""
        cols = [
            "vehicle",
            *(
                STATE_COLUMNS[1:]
                if self.attitude == "euler"
                else ("x", "y", "z", "q0", "q1", "q2", "q3", "u", "v", "w", "p", "q", "r")
            ),
        ]
        return cols, [[k, *map(float, self.states[k, -1, :])] for k in range(len(self))]

    def summary_rows(self) -> list[tuple[str, Any]]:
        return [
            ("vehicles", len(self)),
            ("duration (s)", float(self.time[-1])),
            ("samples", self.time.size),
            ("failed", len(self.failed)),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Horizontal paths of every vehicle on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.vehicle import batch_axes

        return batch_axes(self.time, self.states, ax)


def simulate_batch(
    vehicles: Sequence[Vehicle],
    duration: float,
    dt: float,
    tau: Any = (0, 0, 0, 0, 0, 0),
    eta0: Any = None,
    nu0: Any = None,
    current_ned: Any = None,
    output_every: int | None = None,
    attitude: str = "euler",
    deflection: Any = None,
) -> BatchTrajectory:
    """Simulate every vehicle of ``vehicles`` (same derivative-term structure) in parallel.

    Parameters
    ----------
    vehicles : sequence of Vehicle — they may differ in every coefficient
    duration, dt : float — s
    tau : 6 floats (N, N·m) for all, or (n_vehicles, 6)
    eta0, nu0 : (6,) or (n_vehicles, 6) — initial pose (m, rad) and velocity (m/s, rad/s)
    output_every : int — keep every n-th step (default: only the final state)
    deflection : None or one constant deflection per control surface (rad, file order), for all

    Returns
    -------
    BatchTrajectory — ``time`` (n_out,), ``states`` (n_vehicles, n_out, 12 or 13), ``steps``
    (n_vehicles,): steps taken (fewer when a vehicle's state became non-finite).
    """
    from hydrokit.simulate.compiled import no_drive_batch, rk4_batch

    nv = len(vehicles)
    if nv == 0:
        raise InputError("no vehicles to simulate")
    if not (math.isfinite(duration) and duration > 0 and math.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"duration = {duration}, dt = {dt}: expected 0 < dt ≤ duration (s)")
    n_steps = int(math.floor(duration / dt + 1e-9))
    every = n_steps if output_every is None else int(output_every)
    quat = attitude == "quaternion"
    packs = [pack(v) for v in vehicles]
    n_terms = packs[0].t_dof.size
    for k, p in enumerate(packs):
        if p.t_dof.size != n_terms or not (
            np.array_equal(p.t_kind, packs[0].t_kind) and np.array_equal(p.t_dof, packs[0].t_dof)
        ):
            raise InputError(
                f"vehicle {k} has other derivative terms than vehicle 0; a batch shares one term structure"
            )
    stack = lambda name: np.ascontiguousarray(np.stack([getattr(p, name) for p in packs]))  # noqa: E731
    tau = np.asarray(tau, float)
    taus = np.broadcast_to(tau, (nv, 6)) if tau.ndim <= 1 else tau
    if taus.shape != (nv, 6):
        raise InputError(f"tau of shape {tau.shape}: expected 6 values or one row of 6 per vehicle")
    cols = [np.zeros((nv, 1)), taus]
    if deflection is not None:
        from hydrokit.simulate.driver import deflection_table

        dtab = deflection_table(vehicles[0], deflection)
        if dtab is None or dtab.shape[0] != 1:
            raise InputError("deflection: a batch takes one constant deflection per control surface (rad)")
        cols.append(np.broadcast_to(dtab[0, 1:], (nv, len(vehicles[0].surfaces))))
    tau_tab = np.ascontiguousarray(np.concatenate(cols, axis=1)[:, None, :])
    dim = 13 if quat else 12
    eta = np.broadcast_to(np.zeros(6) if eta0 is None else np.asarray(eta0, float), (nv, 6))
    nu = np.broadcast_to(np.zeros(6) if nu0 is None else np.asarray(nu0, float), (nv, 6))
    if quat:
        from hydrokit.core.kinematics import euler_to_quaternion

        x0 = np.array([np.concatenate([e[:3], euler_to_quaternion(*e[3:]), n]) for e, n in zip(eta, nu)])
    else:
        x0 = np.ascontiguousarray(np.concatenate([eta, nu], axis=1))
    n_out = n_steps // every + 1
    out = np.empty((nv, n_out, dim))
    done = np.empty(nv, dtype=np.int64)
    rk4_batch(
        x0,
        float(dt),
        n_steps,
        every,
        quat,
        tau_tab,
        current_table(current_ned),
        (
            stack("Minv"),
            stack("Mc"),
            stack("DL"),
            stack("DQ"),
            stack_scal([p.scal for p in packs]),  # drag elements: rows padded to the longest
            packs[0].t_dof,
            stack("t_coef"),
            packs[0].t_kind,
            packs[0].t_idx,
        ),
        no_drive_batch(nv),
        out,
        done,
    )
    return BatchTrajectory(np.arange(n_out) * dt * every, out, done, attitude)
