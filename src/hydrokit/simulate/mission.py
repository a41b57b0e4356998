"""Fly a mission with a vehicle object: the library's closed loop, no file needed.

:func:`fly_mission` runs the closed loop — compiled
(:func:`hydrokit.simulate.compiled_loop.run_closed_loop_compiled`, the default) or the Python
reference (:func:`hydrokit.simulate.closed_loop.run_closed_loop`) — for a
:class:`hydrokit.model.mission.Mission` and a :class:`hydrokit.model.vehicle.Vehicle` that
carries its thrusters, and returns a :class:`MissionResult`.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit._result import Result, html_table, jsonable
from hydrokit.core.names import STATE_COLUMNS
from hydrokit.errors import InputError
from hydrokit.model.mission import CONTROLLER_KINDS, Mission
from hydrokit.model.thrusters import ThrusterSet
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate.closed_loop import ClosedLoopResult, run_closed_loop

#: the closed-loop implementations :func:`fly_mission` can use
LOOPS = ("compiled", "python")
#: how each controller kind is labelled in tables, JSON and figures
CONTROLLER_LABEL = {"pid": "PID", "s-plane": "S-plane"}
#: units of the tracking and effort metrics (what metrics.json states)
METRIC_UNITS = {
    "cross_track_rms": "m",
    "cross_track_max": "m",
    "depth_error_rms": "m",
    "heading_error_rms": "rad",
    "waypoint_times": "s",
    "final_time": "s",
    "thrust_impulse": "N s",
    "thruster_energy": "J (ideal actuator-disk, lower bound)",
    "saturation_time": "s",
    "saturation_fraction": "-",
}
#: the unit of a thruster command, by curve kind
COMMAND_UNITS = {"propeller": "rev/s", "table": "table command", "ideal": "N"}


@dataclass(frozen=True)
class MissionResult(Result):
    """One flown mission with one controller.

    Attributes
    ----------
    mission : Mission — what was flown
    controller : str — "pid" or "s-plane"
    run : ClosedLoopResult — time (s), η (m, rad), ν (m/s, rad/s), set-points, thrusts (N) …
    thrusters : ThrusterSet
    metrics : dict — tracking and effort figures (SI; see :data:`METRIC_UNITS`)
    """

    mission: Mission
    controller: str
    run: ClosedLoopResult
    thrusters: ThrusterSet
    metrics: dict[str, Any]

    @property
    def label(self) -> str:
        """ "PID" or "S-plane"."""
        return CONTROLLER_LABEL[self.controller]

    @property
    def time(self) -> np.ndarray:
        """(n,) s."""
        return self.run.time

    @property
    def eta(self) -> np.ndarray:
        """(n, 6) position (m, NED) and Euler angles (rad)."""
        return self.run.eta

    @property
    def nu(self) -> np.ndarray:
        """(n, 6) body velocities, m/s and rad/s."""
        return self.run.nu

    def to_dict(self) -> dict[str, Any]:
        """Metrics of the run with their units (the per-controller entry of metrics.json)."""
        return jsonable(
            {
                "mission": self.mission.name,
                "controller": self.label,
                "metrics": self.metrics,
                "thrusters": self.thrusters.names,
                "command_units": [COMMAND_UNITS[t.model] for t in self.thrusters.thrusters],
                "units": METRIC_UNITS,
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Columns and rows of the trajectory: state, thruster commands and thrusts, saturation, leg."""
        cols, data = self.columns_and_data()
        return cols, data.tolist()

    def columns_and_data(self) -> tuple[list[str], np.ndarray]:
        """Trajectory columns (as in the mission CSV) and an (n, k) float array."""
        r = self.run
        cols = list(STATE_COLUMNS)
        blocks = [r.time[:, None], r.eta, r.nu]
        for prefix, arr in (
            ("cmd_demand_", r.command_demand),
            ("cmd_", r.command),
            ("thrust_demand_", r.thrust_demand),
            ("thrust_", r.thrust),
        ):
            cols += [prefix + n for n in r.thruster_names]
            blocks.append(arr)
        cols += ["saturated", "leg"]
        blocks += [r.limited[:, None].astype(float), r.leg[:, None].astype(float)]
        return cols, np.hstack(blocks)

    def summary_rows(self) -> list[tuple[str, Any]]:
        m = self.metrics
        return [
            ("mission", self.mission.name),
            ("controller", self.label),
            ("cross-track RMS (m)", m["cross_track_rms"]),
            ("cross-track max (m)", m["cross_track_max"]),
            ("depth error RMS (m)", m["depth_error_rms"]),
            ("heading error RMS (deg)", math.degrees(m["heading_error_rms"])),
            ("completed", m["completed"]),
            ("final time (s)", m["final_time"]),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Planned and flown horizontal path on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.mission import mission_axes

        return mission_axes(self.run, ax, label=self.label)

    def _repr_html_(self) -> str:
        return html_table(f"MissionResult: {self.mission.name}", self.summary_rows())


def fly_mission(
    mission: Mission,
    vehicle: Vehicle,
    controller: str | None = None,
    *,
    duration: float | None = None,
    current_ned: Any = None,
    progress: Callable[[float], None] | None = None,
    loop: str = "compiled",
) -> MissionResult:
    """Fly ``mission`` with ``vehicle`` (which must carry its thrusters) in closed loop.

    Parameters
    ----------
    mission : Mission — path, gains, initial state, step
    vehicle : Vehicle — 6-DOF model with ``thrusters`` (a ThrusterSet)
    controller : str, optional — "pid" or "s-plane" (default: the mission's)
    duration : float, optional — s, overrides the mission's
    current_ned : 3 floats, optional — m/s, overrides the mission's current
    progress : callable, optional — called with the simulated time, s
    loop : str — "compiled" (default: the numba loop of
        :mod:`hydrokit.simulate.compiled_loop`) or "python" (the reference,
        :func:`~hydrokit.simulate.closed_loop.run_closed_loop`); both give the same run to
        ~1e-12. A setup the compiled loop does not know (a custom controller or thrust
        curve) is flown by the Python loop, with a warning.

    Returns
    -------
    MissionResult

    Raises
    ------
    InputError
        A vehicle without thrusters, an unknown controller or one without gains, allocation
        weights that do not match the thrusters, a duration shorter than one step, an
        unknown ``loop``.
    """
    from hydrokit.simulate.compiled import make_dynamics

    if loop not in LOOPS:
        raise InputError(f"loop = {loop!r}: expected one of {', '.join(LOOPS)}")
    kind = controller or mission.controller
    if kind not in CONTROLLER_KINDS:
        raise InputError(f"controller = {kind!r}: expected one of {', '.join(CONTROLLER_KINDS)}")
    thrusters = vehicle.thrusters
    if thrusters is None or len(thrusters) == 0:
        raise InputError(f"vehicle '{vehicle.name}' has no thrusters: a mission needs a 'thrusters:' block")
    if mission.weights is not None and len(mission.weights) != len(thrusters):
        raise InputError(
            f"field 'allocation.weights': {len(mission.weights)} given; expected one per thruster ({len(thrusters)})",
            mission.source,
        )
    T = mission.duration if duration is None else float(duration)
    if not (math.isfinite(T) and T >= mission.dt):
        raise InputError(f"duration = {T}: expected a time ≥ the step dt = {mission.dt} s")
    current = mission.current if current_ned is None else np.asarray(current_ned, dtype=float)
    autopilot = mission.autopilot(kind)
    common: dict[str, Any] = {
        "duration": T,
        "dt": mission.dt,
        "current_ned": current,
        "weights": mission.weights,
        "output_every": mission.output_every,
        "progress": progress,
    }
    run = None
    if loop == "compiled":
        from hydrokit.simulate.compiled_loop import run_closed_loop_compiled, unsupported_reason

        why = unsupported_reason(thrusters, autopilot)
        if why is None:
            run = run_closed_loop_compiled(
                vehicle, thrusters, autopilot, mission.path, mission.eta0, mission.nu0, **common
            )
        else:
            warnings.warn(f"compiled closed loop: {why}; flying the Python loop instead", stacklevel=2)
    if run is None:
        from hydrokit.model.dynamics import steering
        from hydrokit.simulate.compiled_loop import input_columns

        run = run_closed_loop(
            make_dynamics(vehicle, current),
            thrusters,
            autopilot,
            mission.path,
            mission.eta0,
            mission.nu0,
            **common,
            steering=steering(vehicle),
            inputs=int(input_columns(vehicle, thrusters)[0]) >= 0,
        )
    return MissionResult(mission, kind, run, thrusters, run.metrics(thrusters))
