"""Open-loop simulation of a vehicle: constant τ, τ(t) from a table, or a callable.

:func:`simulate` returns a :class:`Trajectory` with the twelve states (Euler angles even when
the quaternion form was integrated) sampled every ``output_every`` steps.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.kinematics import PITCH_WARNING, euler_to_quaternion, quaternion_to_euler
from hydrokit.core.names import STATE_COLUMNS
from hydrokit.errors import InputError, SimulationError
from hydrokit.model.dynamics import check_wind, current_table, pack, vehicle_dynamics
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate.budget import check_memory

COLUMNS = STATE_COLUMNS
INTEGRATORS = ("rk4", "rk4-numpy", "dop853", "rk45")


@dataclass
class Trajectory(Result):
    """An open-loop run.

    Attributes
    ----------
    time : (n,) — s
    eta : (n, 6) — x, y, z (m, NED) and φ, θ, ψ (rad)
    nu : (n, 6) — u, v, w (m/s) and p, q, r (rad/s), body axes
    warnings : list of str — oddities met during the run (near-singular pitch …)
    """

    time: np.ndarray
    eta: np.ndarray
    nu: np.ndarray
    warnings: list[str] = field(default_factory=list)

    def array(self) -> np.ndarray:
        """(n, 13) array in :data:`COLUMNS` order (what the trajectory CSV holds)."""
        return np.column_stack([self.time, self.eta, self.nu])

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Columns :data:`COLUMNS` and one row per sample (SI)."""
        return list(COLUMNS), self.array().tolist()

    def to_dict(self) -> dict[str, Any]:
        """Columns and values (SI) and the warnings, JSON-ready."""
        return jsonable(
            {"columns": list(COLUMNS), "time": self.time, "eta": self.eta, "nu": self.nu, "warnings": self.warnings}
        )

    def summary_rows(self) -> list[tuple[str, Any]]:
        return [
            ("duration (s)", float(self.time[-1])),
            ("samples", int(self.time.size)),
            ("final position (m)", [round(float(v), 4) for v in self.eta[-1, :3]]),
            ("final velocity (m/s, rad/s)", [round(float(v), 4) for v in self.nu[-1]]),
            ("warnings", len(self.warnings)),
        ]

    def plot(self, ax: Any = None) -> Any:
        """Horizontal path (east across, north up) on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.vehicle import path_axes

        return path_axes(self, ax)


def _tau_table(tau: Any) -> np.ndarray | None:
    if callable(tau):
        return None
    a = np.asarray(tau, dtype=float)
    if a.shape == (6,):
        return np.concatenate([[0.0], a])[None, :]
    if a.ndim == 2 and a.shape[1] == 7 and a.shape[0] >= 1:
        if np.any(np.diff(a[:, 0]) <= 0):
            raise InputError("force table: times must increase strictly (s)")
        return np.ascontiguousarray(a)
    raise InputError(f"force of shape {a.shape}: expected 6 values (N, N·m), rows [t, X, Y, Z, K, M, N] or a callable")


def simulate(
    vehicle: Vehicle,
    duration: float,
    dt: float,
    tau: Any = (0, 0, 0, 0, 0, 0),
    eta0: Any = (0, 0, 0, 0, 0, 0),
    nu0: Any = (0, 0, 0, 0, 0, 0),
    current_ned: Any = None,
    integrator: str = "rk4",
    attitude: str = "euler",
    output_every: int = 1,
    progress: Callable[[float], None] | None = None,
    deflection: Any = None,
) -> Trajectory:
    """Simulate ``vehicle`` for ``duration`` s.

    Parameters
    ----------
    vehicle : Vehicle
    duration : float — s
    dt : float — step, s (fixed-step integrators; output spacing of the adaptive ones × every)
    tau : 6 floats (N, N·m), rows [t, X, Y, Z, K, M, N] (interpolated, held at the ends), or a
        callable ``tau(t, eta, nu) -> 6 floats`` (controllers)
    eta0, nu0 : 6 floats each — initial pose (m, rad) and velocity (m/s, rad/s)
    current_ned : None, 3 floats (m/s) or rows [t, v_N, v_E, v_D], or with the wind's velocity
        [t, v_N, v_E, v_D, w_N, w_E] (m/s; :func:`hydrokit.model.dynamics.environment_table`)
    integrator : "rk4" (compiled), "rk4-numpy", "dop853" or "rk45"
    attitude : "euler" or "quaternion"
    output_every : int — keep every n-th step
    deflection : None (all 0), one deflection per control surface (rad, file order) or rows
        [t, δ_1 … δ_n] (s, rad; interpolated linearly, held at the ends). Checked against each
        surface's ``max_deflection``.

    Raises
    ------
    SimulationError
        At the first non-finite state, with its time.
    """
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
        raise InputError(f"duration = {duration}: expected a positive time (s)")
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"dt = {dt}: expected 0 < dt ≤ duration (s)")
    if integrator not in INTEGRATORS:
        raise InputError(f"integrator = {integrator!r}: expected one of {', '.join(INTEGRATORS)}")
    if attitude not in ("euler", "quaternion"):
        raise InputError(f"attitude = {attitude!r}: expected euler or quaternion")
    if not (isinstance(output_every, int) and output_every >= 1):
        raise InputError(f"output_every = {output_every}: expected a whole number ≥ 1")
    eta0 = np.asarray(eta0, float)
    nu0 = np.asarray(nu0, float)
    for name, a in (("initial pose", eta0), ("initial velocity", nu0)):
        if a.shape != (6,) or not np.all(np.isfinite(a)):
            raise InputError(f"{name} = {a.tolist()}: expected 6 finite numbers")
    if not math.isfinite(duration / dt):
        raise InputError(f"dt = {dt:.4g} s: duration / dt = {duration / dt} steps; expected a step of a realistic size")
    n_steps = math.floor(duration / dt + 1e-9)
    n_out = n_steps // output_every + 1
    # the recorded rows (time and 13 states, and the adaptive solvers' copy) are sized before any is made
    check_memory(2.0 * n_out * 14 * 8, f"the recorded trajectory ({n_out:.4g} rows)")
    quat = attitude == "quaternion"
    x0 = np.concatenate([eta0[:3], euler_to_quaternion(*eta0[3:]), nu0]) if quat else np.concatenate([eta0, nu0])
    warnings = list(vehicle.warnings)
    ttab = _tau_table(tau)
    dtab = deflection_table(vehicle, deflection)
    if ttab is not None and dtab is not None:
        ttab = merge_tables(ttab, dtab)
    ctab = current_table(current_ned)
    check_wind(vehicle, ctab)
    if integrator == "rk4" and ttab is not None:
        from hydrokit.simulate.compiled import no_drive, rk4_run

        p = pack(vehicle)
        out = np.empty((n_steps // output_every + 1, x0.size))
        done = rk4_run(
            x0,
            0.0,
            float(dt),
            n_steps,
            output_every,
            quat,
            ttab,
            ctab,
            p.V,
            no_drive(),
            out,
        )
        if done < n_steps:
            raise SimulationError(
                f"the state became non-finite at t = {(done + 1) * dt:.6g} s (step {done + 1}); "
                "check the coefficients' signs and the step size"
            )
        states = out
        times = np.arange(states.shape[0]) * dt * output_every
        if progress is not None:
            progress(duration)
    else:
        f = vehicle_dynamics(vehicle, current_ned, attitude)
        if ttab is None:
            from hydrokit.model.dynamics import interp_table

            def rhs(t: float, x: np.ndarray) -> np.ndarray:
                eta = _eta(x, quat)
                nu = x[-6:]
                d = None if dtab is None else interp_table(dtab, t)[0]
                return f(t, x, np.asarray(tau(t, eta, nu), float), d)
        else:
            from hydrokit.model.dynamics import interp_table

            def rhs(t: float, x: np.ndarray) -> np.ndarray:
                row = interp_table(ttab, t)[0]
                return f(t, x, row[:6], row[6:])

        if integrator in ("rk4", "rk4-numpy"):
            prog = None if progress is None else (lambda k: progress(k * dt))
            times, states = _rk4(rhs, x0, dt, n_steps, output_every, prog)
        else:
            from hydrokit.simulate.integrators import adaptive

            t_eval = np.arange(n_steps // output_every + 1) * dt * output_every
            times, states = adaptive(rhs, x0, t_eval[-1], t_eval, method=integrator.upper())
    eta = np.array([_eta(s, quat) for s in states]) if quat else states[:, :6]
    nu = states[:, -6:]
    if not quat and np.any(np.abs(eta[:, 4]) > PITCH_WARNING):
        warnings.append(
            f"pitch reached {math.degrees(float(np.max(np.abs(eta[:, 4])))):.1f}°: Euler angles are near their "
            "singularity at ±90°; use --attitude quaternion"
        )
    return Trajectory(times, eta, nu, warnings)


def deflection_table(vehicle: Vehicle, deflection: Any) -> np.ndarray | None:
    """``deflection`` (see :func:`simulate`) as rows [t, δ_1 … δ_n] (s, rad), or None for none;
    InputError for a wrong width, a time that does not increase or a deflection beyond a
    surface's limit."""
    if deflection is None:
        return None
    ns = len(vehicle.surfaces)
    a = np.asarray(deflection, dtype=float)
    if ns == 0:
        raise InputError(f"vehicle {vehicle.name!r} has no control surfaces: expected no deflection")
    if a.shape == (ns,):
        a = np.concatenate([[0.0], a])[None, :]
    elif not (a.ndim == 2 and a.shape[1] == ns + 1 and a.shape[0] >= 1):
        raise InputError(
            f"deflection of shape {a.shape}: expected {ns} values (rad, {', '.join(vehicle.surfaces.names)}) "
            f"or rows [t, {', '.join(vehicle.surfaces.names)}]"
        )
    if not np.all(np.isfinite(a)):
        raise InputError("deflection: expected finite numbers (s, rad)")
    if np.any(np.diff(a[:, 0]) <= 0):
        raise InputError("deflection table: times must increase strictly (s)")
    vehicle.surfaces.check_deflection(a[:, 1:])
    return np.ascontiguousarray(a)


def merge_tables(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Two piecewise-linear tables (rows [t, values…], held beyond their ends) as one on the
    union of their times: [t, a's values, b's values] — exact, both being linear between rows."""
    from hydrokit.model.dynamics import interp_table

    times = np.union1d(a[:, 0], b[:, 0])
    rows = [np.concatenate([[t], interp_table(a, t)[0], interp_table(b, t)[0]]) for t in times]
    return np.ascontiguousarray(np.array(rows))


def _rk4(rhs: Any, x0: np.ndarray, dt: float, n: int, every: int, progress: Any) -> tuple[np.ndarray, np.ndarray]:
    from hydrokit.simulate.integrators import rk4

    return rk4(rhs, x0, dt, n, every, progress)


def _eta(x: np.ndarray, quat: bool) -> np.ndarray:
    if quat:
        return np.concatenate([x[:3], quaternion_to_euler(x[3:7])])
    return x[:6]
