"""Fly a fleet: N copies of one mission in one compiled call (numba ``prange`` over the copies).

The copies may differ in vehicle (coefficients or whole vehicles with the same thrusters and
model terms), gains, current and start state. Each copy runs the same per-step kernel as the
single compiled run (:func:`hydrokit.simulate.compiled_loop._control` and ``_integrate``), so
copy i equals ``fly_mission`` of the same configuration to round-off; its metrics (those of
:class:`hydrokit.simulate.mission.MissionResult`) are accumulated as it flies, and the path
is kept only when asked, every ``paths_every``-th step (memory N × steps / paths_every × 6
floats, nothing that grows with the step count otherwise).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit._result import Result, html_table, jsonable
from hydrokit.errors import InputError
from hydrokit.model.dynamics import stack_scal
from hydrokit.model.mission import CONTROLLER_KINDS, Mission

# the coefficient names a variations mapping accepts ("<name>.<dof>", SI) are the one table of
# hydrokit.model.uncertainty; re-exported here for one release
from hydrokit.model.uncertainty import COEFFICIENTS  # noqa: F401
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate.budget import check_memory
from hydrokit.simulate.mission import CONTROLLER_LABEL, METRIC_UNITS

#: per-run metrics of a fleet (the scalar metrics of MissionResult)
FLEET_METRICS = (
    "cross_track_rms",
    "cross_track_max",
    "depth_error_rms",
    "heading_error_rms",
    "final_time",
    "thrust_impulse",
    "thruster_energy",
    "saturation_time",
    "saturation_fraction",
)


@dataclass(frozen=True)
class FleetResult(Result):
    """N flown copies of a mission.

    Attributes
    ----------
    mission : Mission
    controller : str — "pid" or "s-plane"
    metrics : dict — metric name → (N,) array (SI, see :data:`~hydrokit.simulate.mission.METRIC_UNITS`;
        thruster_energy NaN when a thruster has no diameter)
    waypoint_times : (N, legs) array — s, NaN where never reached
    completed : (N,) bool — every waypoint reached
    diverged_at : (N,) array — s, the time the state became non-finite (NaN: it did not)
    path_time : (k,) array or None — s, the times of the kept path samples
    paths : (N, k, 6) array or None — η (m, rad) every ``paths_every``-th step; NaN after a
        copy stopped
    elapsed : float — wall time of the compiled call, s
    steps : int — integration steps per copy (the run's length; a copy may stop earlier)
    """

    mission: Mission
    controller: str
    metrics: dict[str, np.ndarray]
    waypoint_times: np.ndarray
    completed: np.ndarray
    diverged_at: np.ndarray
    path_time: np.ndarray | None
    paths: np.ndarray | None
    elapsed: float
    steps: int

    @property
    def n(self) -> int:
        """Number of copies."""
        return int(self.completed.shape[0])

    def member(self, i: int) -> dict[str, Any]:
        """Copy i's metrics as in ``MissionResult.metrics`` (plus ``diverged_at``, s or None)."""
        out: dict[str, Any] = {k: float(v[i]) for k, v in self.metrics.items()}
        if math.isnan(out["thruster_energy"]):
            out["thruster_energy"] = None
        out["waypoint_times"] = [None if math.isnan(t) else float(t) for t in self.waypoint_times[i]]
        out["completed"] = bool(self.completed[i])
        out["diverged_at"] = None if math.isnan(self.diverged_at[i]) else float(self.diverged_at[i])
        return out

    def to_dict(self) -> dict[str, Any]:
        """Per-run metrics with units, and their median and 5–95 % over the copies."""
        summary = {}
        for k, v in self.metrics.items():
            f = v[np.isfinite(v)]
            summary[k] = (
                {"median": float(np.median(f)), "p5": float(np.percentile(f, 5)), "p95": float(np.percentile(f, 95))}
                if f.size
                else None
            )
        return jsonable(
            {
                "mission": self.mission.name,
                "controller": CONTROLLER_LABEL[self.controller],
                "n": self.n,
                "steps": self.steps,
                "elapsed_s": self.elapsed,
                "vehicle_steps_per_s": self.n * self.steps / self.elapsed if self.elapsed > 0 else None,
                "summary": summary,
                "runs": [self.member(i) for i in range(self.n)],
                "units": METRIC_UNITS | {"diverged_at": "s"},
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """One row per copy: run index, the metrics, completed, diverged_at (s)."""
        cols = ["run", *self.metrics, "completed", "diverged_at"]
        rows = [
            [i, *(float(v[i]) for v in self.metrics.values()), bool(self.completed[i]), float(self.diverged_at[i])]
            for i in range(self.n)
        ]
        return cols, rows

    def summary_rows(self) -> list[tuple[str, Any]]:
        ct = self.metrics["cross_track_rms"]
        return [
            ("mission", self.mission.name),
            ("controller", CONTROLLER_LABEL[self.controller]),
            ("copies", self.n),
            ("completed", int(np.sum(self.completed))),
            ("diverged", int(np.sum(np.isfinite(self.diverged_at)))),
            ("cross-track RMS median (m)", float(np.nanmedian(ct)) if self.n else math.nan),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Kept paths (plan view) over the planned path, or — without paths — the histogram
        of cross-track RMS; returns the axes."""
        from hydrokit.plot.mission import fleet_axes

        return fleet_axes(self.mission.path.points, self.paths, self.metrics["cross_track_rms"], ax)

    def _repr_html_(self) -> str:
        return html_table(f"FleetResult: {self.mission.name}", self.summary_rows())


def vary(vehicle: Vehicle, values: Mapping[str, float]) -> Vehicle:
    """``vehicle`` with diagonal coefficients replaced; keys ``"<coefficient>.<dof>"`` with
    coefficient one of added_mass (kg, kg m²), linear_damping, quadratic_damping (SI)
    (:func:`hydrokit.model.uncertainty.with_coefficients`)."""
    from hydrokit.model.uncertainty import with_coefficients

    return with_coefficients(vehicle, values)  # type: ignore[no-any-return]


def _count(name: str, value: Any, n: int | None, width: int | None = None) -> int | None:
    """The copy count ``value`` implies (None: one value for all), checked against ``n``."""
    if value is None:
        return n
    if width is not None:
        a = np.asarray(value, dtype=float)
        if a.shape == (width,):
            return n
        if a.ndim != 2 or a.shape[1] != width:
            raise InputError(f"{name} of shape {a.shape}: expected ({width},) or (N, {width})")
        k = a.shape[0]
    else:
        k = len(value)
    if n is not None and k != n:
        raise InputError(f"{name}: {k} copies, but {n} elsewhere; expected the same N")
    return k


def _rows(value: Any, default: np.ndarray, n: int) -> np.ndarray:
    a = default if value is None else np.asarray(value, dtype=float)
    # a writable C copy: read-only or strided arrays would compile another specialization
    return np.array(np.broadcast_to(a, (n, a.shape[-1])), dtype=np.float64, order="C")


def fly_fleet(
    mission: Mission,
    vehicles: Vehicle | Sequence[Vehicle],
    controller: str | None = None,
    *,
    variations: Mapping[str, Any] | None = None,
    gains: Sequence[Mapping[str, Mapping[str, float]]] | None = None,
    currents: Any = None,
    eta0: Any = None,
    nu0: Any = None,
    n: int | None = None,
    duration: float | None = None,
    paths_every: int | None = None,
    stop_when_done: bool = False,
) -> FleetResult:
    """Fly N copies of ``mission`` in one compiled, parallel call.

    Parameters
    ----------
    mission : Mission
    vehicles : Vehicle (every copy) or N Vehicles — same thrusters and model terms; the
        thrusters of the first are used
    controller : str, optional — "pid" or "s-plane" (default: the mission's)
    variations : mapping, optional — ``"<coefficient>.<dof>"`` → N values (SI) applied to a
        single ``vehicles`` (e.g. ``{"linear_damping.surge": [...]}``; see :func:`vary`)
    gains : N mappings, optional — loop → gains of ``controller`` per copy (as the mission
        file's ``controllers.<kind>``); default: the mission's
    currents : (3,) or (N, 3), optional — NED current, m/s (default: the mission's)
    eta0, nu0 : (6,) or (N, 6), optional — start pose (m, rad) and body velocity (m/s, rad/s)
    n : int, optional — number of copies when nothing above sets it
    duration : float, optional — s (default: the mission's)
    paths_every : int, optional — keep η every this many steps (default: no paths)
    stop_when_done : bool — stop a copy once it reached its last waypoint

    Returns
    -------
    FleetResult

    Raises
    ------
    InputError
        Mismatched copy counts, bad shapes, a controller or curve the compiled loop does not
        know, vehicles with different model terms, a bad ``paths_every``.
    """
    from hydrokit.simulate.compiled_loop import (
        _DIVERGED,
        N_ACC,
        _check_current,
        _check_steps,
        _fleet,
        _pack_autopilot,
        _pack_common,
        _pack_vehicle,
        input_columns,
        unsupported_reason,
    )

    kind = controller or mission.controller
    if kind not in CONTROLLER_KINDS:
        raise InputError(f"controller = {kind!r}: expected one of {', '.join(CONTROLLER_KINDS)}")
    vlist = [vehicles] if isinstance(vehicles, Vehicle) else list(vehicles)
    if not vlist:
        raise InputError("vehicles: none given; expected a Vehicle or N of them")
    N = None if len(vlist) == 1 else len(vlist)
    if variations:
        if len(vlist) != 1:
            raise InputError("variations apply to one vehicle; got several vehicles as well")
        lengths = {k: len(np.atleast_1d(np.asarray(v, dtype=float))) for k, v in variations.items()}
        if len(set(lengths.values())) != 1:
            raise InputError(f"variations: expected the same number of values for each, got {lengths}")
        N = _count("variations", range(next(iter(lengths.values()))), N)
    N = _count("gains", gains, N)
    N = _count("currents", currents, N, 3)
    N = _count("eta0", eta0, N, 6)
    N = _count("nu0", nu0, N, 6)
    if n is not None:
        N = _count("n", range(int(n)), N)
    N = 1 if N is None else N
    if N < 1:
        raise InputError("a fleet of 0 copies: expected N ≥ 1")
    thrusters = vlist[0].thrusters
    if thrusters is None or len(thrusters) == 0:
        raise InputError(f"vehicle '{vlist[0].name}' has no thrusters: a mission needs a 'thrusters:' block")
    if mission.weights is not None and len(mission.weights) != len(thrusters):
        raise InputError(
            f"field 'allocation.weights': {len(mission.weights)} given; expected one per thruster ({len(thrusters)})",
            mission.source,
        )
    if paths_every is not None and int(paths_every) < 1:
        raise InputError(f"paths_every = {paths_every}: expected a whole number of steps ≥ 1")
    T = mission.duration if duration is None else float(duration)
    dt = mission.dt
    if not (math.isfinite(T) and T >= dt):
        raise InputError(f"duration = {T}: expected a time ≥ the step dt = {dt} s")
    n_steps = _check_steps(T, dt, mission.output_every)

    # gains → (N, 5, 6)
    base_ap = mission.autopilot(kind)
    why = unsupported_reason(thrusters, base_ap)
    if why is not None:
        raise InputError(f"compiled closed loop: {why}")
    ctl0, ctl_angle = _pack_autopilot(base_ap)
    if gains is None:
        ctl_all = np.array(np.broadcast_to(ctl0, (N, *ctl0.shape)), order="C")
    else:
        ctl_all = np.empty((N, *ctl0.shape))
        for i, g in enumerate(gains):
            mis_i = replace(mission, gains={kind: {lp: dict(v) for lp, v in g.items()}})
            ctl_all[i], ang = _pack_autopilot(mis_i.autopilot(kind))
            if not np.array_equal(ang, ctl_angle):
                raise InputError(f"gains[{i}]: the loops differ from the mission's; expected the same loops")
    # currents, starts
    vc_all = _rows(currents, np.asarray(mission.current, dtype=float), N)
    for v in vc_all[:1] if currents is None else vc_all:
        _check_current(v)
    x_all = np.hstack([_rows(eta0, np.asarray(mission.eta0, float), N), _rows(nu0, np.asarray(mission.nu0, float), N)])
    # vehicles → stacked packed models (one pack per distinct vehicle and current)
    if variations:
        cols = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in variations.items()}
        members = [vary(vlist[0], {k: float(c[i]) for k, c in cols.items()}) for i in range(N)]
    else:
        members = vlist * N if len(vlist) == 1 else vlist
    packs: dict[tuple[int, bytes], tuple[np.ndarray, ...]] = {}
    V_rows = []
    for i, veh in enumerate(members):
        key = (id(veh), vc_all[i].tobytes())
        if key not in packs:
            packs[key] = _pack_vehicle(veh, vc_all[i])
        V_rows.append(packs[key])
    first = V_rows[0]
    for i, row in enumerate(V_rows):
        for j in (6, 8, 9):  # t_dof, t_kind, t_idx: shared by the kernel
            if not np.array_equal(row[j], first[j]):
                raise InputError(f"vehicle of copy {i}: its model terms differ from copy 0's; expected the same terms")
        if row[7].shape != first[7].shape:
            raise InputError(f"vehicle of copy {i}: its model terms differ from copy 0's; expected the same terms")

    def stacked(j: int) -> np.ndarray:
        if j in (6, 8, 9):
            return first[j]
        if j == 5:  # scal carries the drag elements: a vehicle with fewer gets zero padding
            return stack_scal([r[j] for r in V_rows])
        return np.ascontiguousarray(np.stack([r[j] for r in V_rows]), dtype=first[j].dtype)

    V_all = tuple(stacked(j) for j in range(14))
    G, A, H = _pack_common(thrusters, mission.path, dt, mission.weights)
    H = (*H, input_columns(vlist[0], thrusters))
    m = len(thrusters)
    if all(th.diameter is not None for th in thrusters.thrusters):
        area = np.array([math.pi * th.diameter**2 / 4 for th in thrusters.thrusters])  # type: ignore[operator]
        edenom = np.sqrt(2.0 * thrusters.density * area)
        has_energy = True
    else:
        edenom, has_energy = np.full(m, np.inf), False
    pe = int(paths_every) if paths_every is not None else 0
    n_keep = n_steps // pe + 1 if pe else 0
    check_memory(N * n_keep * 6 * 8, f"the paths of {N} copies ({n_keep} points each)")
    p_eta = np.full((N, n_keep, 6), np.nan)
    acc = np.zeros((N, N_ACC))
    arrivals = np.full((N, mission.path.n_legs), np.nan)
    status = np.zeros(N, dtype=np.int64)
    k_end = np.zeros(N, dtype=np.int64)
    t0 = time.perf_counter()
    _fleet(
        n_steps,
        float(dt),
        int(mission.output_every),
        bool(stop_when_done),
        pe,
        G,
        A,
        H,
        ctl_angle,
        ctl_all,
        vc_all,
        V_all,
        x_all,
        np.ascontiguousarray(edenom, dtype=np.float64),
        acc,
        arrivals,
        p_eta,
        status,
        k_end,
    )
    elapsed = time.perf_counter() - t0
    h = dt * mission.output_every
    follow = acc[:, 1] > 0
    cnt = np.where(follow, acc[:, 1], acc[:, 0])
    cnt = np.where(cnt > 0, cnt, 1.0)
    pick = lambda a, b: np.where(follow, acc[:, a], acc[:, b])  # noqa: E731
    sat_time = acc[:, 12] * h
    total = acc[:, 0] * h
    metrics = {
        "cross_track_rms": np.sqrt(pick(2, 6) / cnt),
        "cross_track_max": pick(3, 7),
        "depth_error_rms": np.sqrt(pick(4, 8) / cnt),
        "heading_error_rms": np.sqrt(pick(5, 9) / cnt),
        "final_time": acc[:, 13].copy(),
        "thrust_impulse": acc[:, 10] * h,
        "thruster_energy": acc[:, 11] * h if has_energy else np.full(N, np.nan),
        "saturation_time": sat_time,
        "saturation_fraction": np.divide(sat_time, total, out=np.zeros(N), where=total > 0),
    }
    diverged_at = np.where(status == _DIVERGED, (k_end + 1) * dt, np.nan)
    return FleetResult(
        mission=mission,
        controller=kind,
        metrics=metrics,
        waypoint_times=arrivals,
        completed=np.all(np.isfinite(arrivals), axis=1),
        diverged_at=diverged_at,
        path_time=(np.arange(n_keep) * pe) * dt if pe else None,  # k dt, as the single run's time
        paths=p_eta if pe else None,
        elapsed=elapsed,
        steps=n_steps,
    )
