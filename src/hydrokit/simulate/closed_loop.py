"""Closed-loop simulation: guidance → autopilot → allocation → thrusters → vehicle.

Every step of length dt (s), with the state measured at its start:

1. guidance gives the speed, depth and heading set-points for the current position;
2. the autopilot turns the errors into a demanded τ (N, N·m);
3. the allocator maps τ to thruster forces (cached pseudo-inverse; the constrained solver
   only when a limit would be broken);
4. each thruster's command is found by inverting its thrust curve at the present advance
   speed; the rotor follows with its first-order lag (exact update over the step, using the
   step-mean command for the force);
5. the actual thrust acts on the vehicle through T, held over the step, and the vehicle is
   integrated with one classical RK4 step
   (:func:`hydrokit.simulate.integrators.rk4_step`).

The vehicle enters as a pure function ``dynamics(t, x, tau) -> xdot`` with
x = [η; ν] (12 values); :func:`hydrokit.simulate.compiled.make_dynamics` builds it from a
:class:`hydrokit.model.vehicle.Vehicle` (the vehicle file's full 6-DOF model). Nothing is stored
on the vehicle, the controllers or the guidance: their states are local to one run, so two
runs give the same result.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit._atomic import raise_if_interrupted
from hydrokit.core.kinematics import rotation_zyx, wrap_angle
from hydrokit.errors import InputError, SimulationError
from hydrokit.model.allocation import Allocator
from hydrokit.model.control import Autopilot
from hydrokit.model.dynamics import Steering
from hydrokit.model.guidance import Path, path_distance
from hydrokit.model.surfaces import steer_surfaces, steer_work_size
from hydrokit.model.thrusters import ThrusterSet
from hydrokit.simulate.budget import check_memory
from hydrokit.simulate.integrators import rk4_step

Array = NDArray[np.float64]
Dynamics = Callable[..., Array]


@dataclass(frozen=True)
class ClosedLoopResult:
    """A closed-loop run (arrays hold every ``output_every``-th step, file order for thrusters).

    Attributes
    ----------
    time : (n,) — s
    eta : (n, 6) — x, y, z (m, NED), φ, θ, ψ (rad)
    nu : (n, 6) — u, v, w (m/s), p, q, r (rad/s), body axes
    reference : (n, 3) — speed (m/s), depth (m), heading (rad) set-points
    tau_demand : (n, 6) — autopilot output, N and N·m
    command_demand, command : (n, m) — thruster commands demanded by the allocation and
        reached by the rotors (rev/s, table unit or N; see ThrusterSet.thrust)
    thrust_demand, thrust : (n, m) — allocated and actual thrust, N
    limited : (n,) bool — the allocation hit a limit or a command saturated at this step
    leg : (n,) int — active guidance leg (1-based; > number of legs when finished)
    waypoint_times : list — time (s) each waypoint 1..N was reached, or None
    thruster_names : list of str
    dt : float — integration step, s
    deflection : (n, s) — control-surface deflections held over each step, rad (s = 0 without
        surfaces)
    """

    time: Array
    eta: Array
    nu: Array
    reference: Array
    tau_demand: Array
    command_demand: Array
    command: Array
    thrust_demand: Array
    thrust: Array
    limited: NDArray[np.bool_]
    leg: NDArray[np.int_]
    waypoint_times: list[float | None]
    thruster_names: list[str]
    dt: float
    path: Path = field(repr=False)
    deflection: Array = field(default_factory=lambda: np.zeros((0, 0)), repr=False)

    def metrics(self, thrusters: ThrusterSet | None = None) -> dict[str, Any]:
        """Tracking and effort figures; see :func:`mission_metrics`."""
        return mission_metrics(self, thrusters)


#: the recorded arrays of a run, in the order the compiled loop receives them
RECORD_FIELDS = (
    "time",
    "eta",
    "nu",
    "reference",
    "tau_demand",
    "command_demand",
    "command",
    "thrust_demand",
    "thrust",
    "limited",
    "leg",
    "deflection",
)


def new_record(n_steps: int, output_every: int, m: int, n_surfaces: int) -> dict[str, Array]:
    """The empty record of a run of ``n_steps`` steps keeping every ``output_every``-th, with m
    thrusters and ``n_surfaces`` control surfaces (the arrays of :class:`ClosedLoopResult`, both
    loops fill them); refused in one line when it would not fit in memory."""
    n_out = n_steps // output_every + 1
    check_memory(n_out * (8 * (23 + 4 * m + n_surfaces) + 1), f"the recorded trajectory ({n_out} rows)")
    return {
        "time": np.empty(n_out),
        "eta": np.empty((n_out, 6)),
        "nu": np.empty((n_out, 6)),
        "reference": np.empty((n_out, 3)),
        "tau_demand": np.empty((n_out, 6)),
        "command_demand": np.empty((n_out, m)),
        "command": np.empty((n_out, m)),
        "thrust_demand": np.empty((n_out, m)),
        "thrust": np.empty((n_out, m)),
        "limited": np.zeros(n_out, dtype=np.bool_),
        "leg": np.empty(n_out, dtype=np.int64),
        "deflection": np.zeros((n_out, n_surfaces)),
    }


def record_result(
    rec: dict[str, Array],
    j: int,
    arrivals: list[float | None],
    thrusters: ThrusterSet,
    dt: float,
    output_every: int,
    path: Path,
) -> ClosedLoopResult:
    """The result of a run from its record's first ``j`` rows (:func:`new_record`), the waypoint
    arrival times (s) and the step ``dt`` (s)."""
    return ClosedLoopResult(
        **{k_: v[:j] for k_, v in rec.items()},  # type: ignore[arg-type]
        waypoint_times=arrivals,
        thruster_names=thrusters.names,
        dt=dt * output_every,
        path=path,
    )


def run_closed_loop(
    dynamics: Dynamics,
    thrusters: ThrusterSet,
    autopilot: Autopilot,
    path: Path,
    eta0: ArrayLike,
    nu0: ArrayLike,
    duration: float,
    dt: float,
    current_ned: ArrayLike | None = None,
    weights: ArrayLike | None = None,
    output_every: int = 1,
    progress: Callable[[float], None] | None = None,
    stop_when_done: bool = False,
    steering: Steering | None = None,
    inputs: bool = False,
) -> ClosedLoopResult:
    """Run guidance, autopilot, allocation and thrusters in the loop with the vehicle.

    Parameters
    ----------
    dynamics : callable — ``f(t, x, tau) -> xdot`` for x = [η; ν] (12), τ in N and N·m;
        it must include the current (relative-velocity) effect itself
    thrusters : ThrusterSet — layout, limits, curves and rotor lags
    autopilot : Autopilot — speed/depth/heading (+ roll/pitch) loops
    path : Path — waypoints and speeds
    eta0 : 6 floats — initial position (m) and attitude (rad)
    nu0 : 6 floats — initial body velocity, m/s and rad/s
    duration : float — simulated time, s
    dt : float — integration and control step, s
    current_ned : 3 floats or None — current velocity in NED, m/s (for the thrusters'
        advance speed; the vehicle's own current effect is in ``dynamics``)
    weights : m floats or None — allocation weights, –
    output_every : int — keep every n-th step
    progress : callable or None — called with the simulated time (s) now and then
    stop_when_done : bool — end the run once the last waypoint is reached
    steering : Steering or None — the vehicle's control surfaces
        (:func:`hydrokit.model.dynamics.steering`): each step they are moved towards the
        autopilot's demanded moments (:func:`hydrokit.model.surfaces.steer_surfaces`) and the
        deflections, held over the step, reach ``dynamics`` as its fourth argument (rad); the
        thrusters are allocated the whole demand as before
    inputs : bool — ``thrusters`` are the vehicle's own: each step's thrust (N) and rotation
        rate (rev/s; a propeller's mean rotor state over the step) reach ``dynamics`` as its
        ``thrust`` and ``rate`` arguments (:func:`hydrokit.model.dynamics.vehicle_dynamics`), so
        ``T()``/``n()`` term factors and a race rudder see them, as on every other path (issue #56)

    Raises
    ------
    SimulationError
        The state became non-finite.
    """
    if not (math.isfinite(duration) and duration > 0 and math.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"duration = {duration}, dt = {dt}: expected 0 < dt ≤ duration (s)")
    if output_every < 1:
        raise InputError(f"output_every = {output_every}: expected a whole number ≥ 1")
    n_steps = int(math.floor(duration / dt + 1e-9))
    m = len(thrusters)
    T = thrusters.configuration_matrix()
    allocator = Allocator(T, thrusters.f_min, thrusters.f_max, weights)
    vc = np.zeros(3) if current_ned is None else np.asarray(current_ned, dtype=float)
    tc = thrusters.time_constants
    with np.errstate(divide="ignore"):
        decay = np.where(tc > 0, np.exp(-dt / np.where(tc > 0, tc, 1.0)), 0.0)
        # mean of c_t + (c0 - c_t) e^(-s/tc) over the step: weight of (c0 - c_t)
        mean_w = np.where(tc > 0, tc / dt * (1.0 - decay), 0.0)

    rec = new_record(n_steps, output_every, m, 0 if steering is None else steering.smax.size)
    delta = np.zeros(0 if steering is None else steering.smax.size)
    work = np.zeros(steer_work_size(delta.size))
    law: Any = None if steering is None else steering.args()
    x = np.concatenate([np.asarray(eta0, float), np.asarray(nu0, float)])
    c = np.zeros(m)
    gstate = path.initial_state(heading=float(x[5]))
    astate = autopilot.initial_state()
    n_legs = path.n_legs
    arrivals: list[float | None] = [None] * n_legs
    limited_any = False
    j = 0
    t = 0.0
    report_every = max(1, n_steps // 100)
    # per-run constants and bound methods, hoisted out of the loop
    cmd_min, cmd_max = thrusters.command_min, thrusters.command_max
    sat_hi, sat_lo = cmd_max * (1 - 1e-9), cmd_min * (1 - 1e-9)
    # without a current the relative velocity is ν itself (R^T 0 = 0)
    still_water = not bool(np.any(vc))
    guidance, control = path.update, autopilot.update
    advance_speed, command_for_thrust, thrust = (
        thrusters.advance_speed,
        thrusters.command_for_thrust,
        thrusters.thrust,
    )
    r_time, r_eta, r_nu, r_ref, r_tau = rec["time"], rec["eta"], rec["nu"], rec["reference"], rec["tau_demand"]
    r_cmd_d, r_cmd, r_f_d, r_f = rec["command_demand"], rec["command"], rec["thrust_demand"], rec["thrust"]
    r_lim, r_leg = rec["limited"], rec["leg"]
    for k in range(n_steps + 1):
        if k % 1000 == 0:
            # a termination signal whose raise numba's compiler swallowed stops the run here
            raise_if_interrupted()
        t = k * dt
        eta, nu = x[:6], x[6:]
        psi = float(eta[5])
        ref, gnew = guidance(gstate, eta[:3], vehicle_heading=psi)
        if gnew.leg != gstate.leg:
            for leg in range(gstate.leg, min(gnew.leg, n_legs + 1)):
                arrivals[leg - 1] = t
        gstate = gnew
        tau_d, astate = control(astate, ref, eta, nu, dt)
        f_cmd, limited = allocator(tau_d)
        # advance speed from the velocity relative to the water
        if still_water:
            nu_r = nu
        else:
            R = rotation_zyx(eta[3], eta[4], psi)
            nu_r = nu.copy()
            nu_r[:3] -= R.T @ vc
        va = advance_speed(nu_r)
        c_cmd = command_for_thrust(f_cmd, va).clip(cmd_min, cmd_max)
        c_mean = c_cmd + (c - c_cmd) * mean_w
        f_act = thrust(c_mean, va)
        sat = limited or bool((c_cmd >= sat_hi).any() or (c_cmd <= sat_lo).any())
        tau_act = T @ f_act
        if law is not None:
            steer_surfaces(tau_d, nu_r, float(tau_act[0]), *law, dt, delta, work)  # type: ignore[call-arg]
        if k % output_every == 0:
            rec["deflection"][j] = delta
            r_time[j] = t
            r_eta[j] = eta
            r_nu[j] = nu
            r_ref[j] = (ref.speed, ref.depth, ref.heading)
            r_tau[j] = tau_d
            r_cmd_d[j] = c_cmd
            r_cmd[j] = c
            r_f_d[j] = f_cmd
            r_f[j] = f_act
            r_lim[j] = sat or limited_any
            r_leg[j] = gstate.leg
            limited_any = False
            j += 1
        else:
            limited_any = limited_any or sat
        if k == n_steps or (stop_when_done and gstate.leg > n_legs):
            break
        if inputs:
            held_d = delta.copy() if law is not None else None
            rate = thrusters.rotation_rate(f_act, command=c_mean)
            x = rk4_step(
                lambda t_, x_, u_, d=held_d, f=f_act, n=rate: dynamics(t_, x_, u_, d, f, n), t, x, dt, u=tau_act
            )
        elif law is None:
            x = rk4_step(dynamics, t, x, dt, u=tau_act)
        else:
            held = delta.copy()
            x = rk4_step(lambda t_, x_, u_, d=held: dynamics(t_, x_, u_, d), t, x, dt, u=tau_act)
        c = c_cmd + (c - c_cmd) * decay
        if not np.isfinite(x).all():
            raise SimulationError(f"the state became non-finite at t = {t + dt:.6g} s")
        if progress is not None and k % report_every == 0:
            progress(t)
    if progress is not None:
        progress(t)
    return record_result(rec, j, arrivals, thrusters, dt, output_every, path)


def mission_metrics(res: ClosedLoopResult, thrusters: ThrusterSet | None = None) -> dict[str, Any]:
    """Tracking and effort metrics of a closed-loop run.

    Returns a dict (SI units) with: ``cross_track_rms`` and ``cross_track_max`` (m, the 3-D
    distance from the vehicle to the path polyline, sampled while the path is being
    followed), ``depth_error_rms`` (m), ``heading_error_rms`` (rad, on horizontal legs),
    ``waypoint_times`` (s, None if never reached), ``completed``, ``thrust_impulse``
    (∫Σ|f_i| dt, N·s), ``thruster_energy`` (J: ∫Σ |f_i|^{3/2} / √(2ρA_i) dt, the ideal
    actuator-disk power of Rankine–Froude momentum theory at zero advance speed — a lower
    bound — or None when a thruster has no diameter), ``saturation_time`` (s, time with a
    limit active) and ``saturation_fraction``.
    """
    h = res.dt
    following = res.leg <= res.path.n_legs
    if not np.any(following):
        following = np.ones_like(following)
    d = path_distance(res.eta[following, :3], res.path.points)
    z_err = res.eta[following, 2] - res.reference[following, 1]
    psi_err = np.array([wrap_angle(a - b) for a, b in zip(res.eta[following, 5], res.reference[following, 2])])
    absf = np.abs(res.thrust)
    energy = None
    if thrusters is not None and all(th.diameter is not None for th in thrusters.thrusters):
        area = np.array([math.pi * th.diameter**2 / 4 for th in thrusters.thrusters])  # type: ignore[operator]
        power = absf**1.5 / np.sqrt(2.0 * thrusters.density * area)
        energy = float(np.sum(power) * h)
    sat_time = float(np.count_nonzero(res.limited) * h)
    total = float(len(res.time) * h)
    return {
        "cross_track_rms": float(np.sqrt(np.mean(d**2))),
        "cross_track_max": float(np.max(d)),
        "depth_error_rms": float(np.sqrt(np.mean(z_err**2))),
        "heading_error_rms": float(np.sqrt(np.mean(psi_err**2))),
        "waypoint_times": list(res.waypoint_times),
        "completed": all(t is not None for t in res.waypoint_times),
        "final_time": float(res.time[-1]),
        "thrust_impulse": float(np.sum(absf) * h),
        "thruster_energy": energy,
        "saturation_time": sat_time,
        "saturation_fraction": sat_time / total if total > 0 else 0.0,
    }


def control_callback(
    thrusters: ThrusterSet,
    autopilot: Autopilot,
    path: Path,
    period: float,
    weights: ArrayLike | None = None,
) -> Callable[[float, Array, Array], Array]:
    """The autopilot as an input callback ``tau(t, eta, nu)`` for open-loop drivers.

    For a simulator that asks for τ (N, N·m) at arbitrary times (e.g. inside RK4 stages),
    the control law is sampled at t = k·``period`` and held in between (zero-order hold):
    guidance, autopilot and allocation run on the η, ν given at the first call at or after
    an instant, and the thrust (saturated, no rotor lag) is held until the next. A further
    call at exactly that instant (a step's last RK4 stage and the next step's first stage
    share the time) re-samples from the same controller state with the newer η, ν, so the
    state at the step start decides. The callable keeps the controller state *for one
    run*: build a new one for each simulation.

    Parameters
    ----------
    thrusters, autopilot, path : as :func:`run_closed_loop`
    period : float — control sampling period, s
    weights : m floats or None — allocation weights, –
    """
    if not (math.isfinite(period) and period > 0):
        raise InputError(f"control period = {period}: expected a positive time in s")
    T = thrusters.configuration_matrix()
    allocator = Allocator(T, thrusters.f_min, thrusters.f_max, weights)
    tol = 1e-9 * period
    # base: controller states before the current sample; state: after it
    memo: dict[str, Any] = {"k": -1, "tau": np.zeros(6), "base": None, "state": None}

    def sample(base: tuple[Any, Any], eta: Array, nu: Array) -> tuple[Any, Any]:
        g, a = base
        if g is None:
            g = path.initial_state(heading=float(eta[5]))
            a = autopilot.initial_state()
        ref, g = path.update(g, eta[:3], vehicle_heading=float(eta[5]))
        tau_d, a = autopilot.update(a, ref, eta, nu, period)
        f, _ = allocator(tau_d)
        memo["tau"] = T @ thrusters.thrust(thrusters.command_for_thrust(f))
        return g, a

    def tau(t: float, eta: ArrayLike, nu: ArrayLike) -> Array:
        k = int(math.floor((t + tol) / period))  # the latest sampling instant k·period ≤ t
        eta_a, nu_a = np.asarray(eta, dtype=float), np.asarray(nu, dtype=float)
        if k > memo["k"]:
            memo["base"] = memo["state"] if memo["state"] is not None else (None, None)
            memo["k"] = k
            memo["state"] = sample(memo["base"], eta_a, nu_a)
        elif abs(t - k * period) <= tol:
            # Called again exactly at the sampling instant (e.g. the first RK4 stage after
            # the last stage of the previous step): the newest state at that instant wins.
            memo["state"] = sample(memo["base"], eta_a, nu_a)
        return memo["tau"]

    return tau
