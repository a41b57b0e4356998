"""Thruster commands over time as the force of an open-loop run (``simulate --command``, the
trial replay of ``manoeuvre --replay``).

:class:`CommandForce` is a callable ``τ(t, η, ν)`` (N, N·m) for
:func:`hydrokit.simulate.driver.simulate` and :func:`hydrokit.manoeuvre.replay.replay`: each
thruster either follows a schedule of commands, held from row to row (zero-order hold, as in a
run file), through its first-order rotor lag, or gives a measured thrust held the same way. The
rotor state at any time is exact: :meth:`~hydrokit.model.thrusters.ThrusterSet.rotor_step` from
the state reached at the row before (the one rotor law). The thrust is the thruster's own curve
(:meth:`~hydrokit.model.thrusters.ThrusterSet.thrust`) at that rotor state and at the advance
speed of the state's velocity relative to the water, so a propeller at constant revolutions
pushes harder as the vehicle slows — the same law as :class:`hydrokit.manoeuvre.run.ThrusterDrive`,
evaluated at every stage of the integrator instead of once per step. :func:`fly_commands` is the
open-loop run (``simulate --command``): RK4 on the compiled right-hand side, which also reads each
thruster's thrust and rotation rate (the ``T()`` and ``n()`` term factors, a rudder in a race).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from hydrokit.core.kinematics import rotation_zyx
from hydrokit.errors import InputError


class CommandForce:
    """τ(t, η, ν) = force(t) + T f(c(t), V_a(ν_r)) of the vehicle's thrusters (module docstring).

    Parameters
    ----------
    thrusters : ThrusterSet — the vehicle's thrusters (m of them)
    table : (k, 1 + m) rows [t, u_1 … u_m] — s, then per thruster its command (rev/s for a
        propeller, the table's unit for a table curve, N for an ideal thruster) or, where
        ``measured`` says so, its measured thrust (N); each row held until the next, the first
        also before it and the last after it
    measured : m bools or None — which columns are measured thrusts (None: none)
    force : 6 floats (N, N·m, body axes) added to the thrust, or rows [t, X, Y, Z, K, M, N] (s, N,
        N·m) interpolated linearly and held beyond their ends
    start : "rest" (rotors at 0 at the first row: a vehicle starting from rest) or "settled"
        (at the first row's command: a log that starts under way)
    current_ned : None, 3 floats (m/s, NED) or rows [t (s), v_N, v_E, v_D (m/s)]
    """

    def __init__(
        self,
        thrusters: Any,
        table: Any,
        measured: Any = None,
        force: Any = (0, 0, 0, 0, 0, 0),
        start: str = "rest",
        current_ned: Any = None,
    ) -> None:
        from hydrokit.model.dynamics import current_table

        m = len(thrusters)
        tab = np.asarray(table, float)
        if tab.ndim != 2 or tab.shape[1] != m + 1 or tab.shape[0] < 1:
            raise InputError(
                f"command table of shape {tab.shape}: expected rows [t, {', '.join(thrusters.names)}] "
                "(s, each thruster's unit)"
            )
        if not np.all(np.isfinite(tab)):
            raise InputError("command table: expected finite numbers (s, each thruster's unit)")
        if np.any(np.diff(tab[:, 0]) <= 0):
            raise InputError("command table: times must increase strictly (s)")
        if start not in ("rest", "settled"):
            raise InputError(f"start = {start!r}: expected rest or settled")
        self.thrusters = thrusters
        self.time = np.ascontiguousarray(tab[:, 0])
        self.values = np.ascontiguousarray(tab[:, 1:])
        self.measured = np.zeros(m, bool) if measured is None else np.asarray(measured, bool)
        if self.measured.shape != (m,):
            raise InputError(f"measured flags of shape {self.measured.shape}: expected one per thruster ({m})")
        f = np.asarray(force, float)
        f = np.concatenate([[0.0], f])[None, :] if f.shape == (6,) else f
        if f.ndim != 2 or f.shape[1] != 7 or f.shape[0] < 1 or not np.all(np.isfinite(f)):
            raise InputError(f"force of shape {np.shape(force)}: expected 6 finite numbers (N, N·m) or rows [t, X … N]")
        self.force_table = np.ascontiguousarray(f)
        self.T = thrusters.configuration_matrix()
        self.current = current_table(current_ned)[:, :4]  # the water's: the wind does not reach the propellers
        # the rotor state reached at every row (exact: the target is held over each interval)
        c = np.empty_like(self.values)
        lo, hi = thrusters.command_min, thrusters.command_max
        c[0] = np.clip(self.values[0], lo, hi) if start == "settled" else np.zeros(m)
        for k in range(1, self.time.size):
            c[k] = thrusters.rotor_step(c[k - 1], self.values[k - 1], float(self.time[k] - self.time[k - 1]))
        self.c_rows = c

    def rotor(self, t: float) -> np.ndarray:
        """The rotor state (command vector, each thruster's unit) at ``t`` (s)."""
        k = int(np.searchsorted(self.time, t, side="right")) - 1
        if k < 0:
            return self.c_rows[0].copy()
        return self.thrusters.rotor_step(self.c_rows[k], self.values[k], float(t - self.time[k]))

    def thrust(self, t: float, eta: Any, nu: Any) -> np.ndarray:
        """Each thruster's thrust, N, at ``t`` (s) in the pose ``eta`` (m, rad) and velocity ``nu``
        (m/s, rad/s): from its curve at the rotor state and the advance speed, or measured."""
        nu_r = np.asarray(nu, float)[:6]
        if np.any(self.current[:, 1:]):
            from hydrokit.model.dynamics import interp_table

            vc = interp_table(self.current, t)[0]
            nu_r = nu_r.copy()
            nu_r[:3] -= rotation_zyx(float(eta[3]), float(eta[4]), float(eta[5])).T @ vc
        ts = self.thrusters
        f = ts.thrust(self.rotor(t), ts.advance_speed(nu_r))
        if np.any(self.measured):
            k = min(max(int(np.searchsorted(self.time, t, side="right")) - 1, 0), self.time.size - 1)
            f = np.where(self.measured, np.clip(self.values[k], ts.f_min, ts.f_max), f)
        return np.asarray(f, float)

    def __call__(self, t: float, eta: Any, nu: Any) -> np.ndarray:
        """τ, N and N·m (body axes)."""
        return self.inputs(t, eta, nu)[0]

    def inputs(self, t: float, eta: Any, nu: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(τ in N and N·m, each thruster's thrust in N, each thruster's rotation rate in rev/s) at
        ``t`` (s) in the pose ``eta`` and velocity ``nu``: what the right-hand side reads (the
        thrust and rate feed the ``T()`` and ``n()`` term factors and a rudder's race). A
        propeller's rate is its rotor state; with a measured thrust, the curve's inversion at it."""
        from hydrokit.model.dynamics import interp_table

        ts = self.thrusters
        f = self.thrust(t, eta, nu)
        rate = ts.rotation_rate(f, command=self.rotor(t))
        if np.any(self.measured):
            va = ts.advance_speed(np.asarray(nu, float)[:6])
            rate = np.where(self.measured, ts.rotation_rate(f, va), rate)
        return interp_table(self.force_table, t)[0] + self.T @ f, f, rate


def driven_rhs(
    f: Callable[..., np.ndarray],
    inputs: Callable[[float, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]],
    n_thrusters: int,
) -> Callable[[float, np.ndarray, Any], np.ndarray]:
    """``rhs(t, x, δ) → ẋ``: the right-hand side ``f(t, x, τ, δ, thrust, rate)`` fed the whole
    input vector — τ (N, N·m), each thruster's thrust (N) and rotation rate (rev/s) from
    ``inputs(t, x)`` at that instant and state (a :class:`CommandForce`'s, a manoeuvre's thruster
    drive's), the deflections ``δ`` (rad) given. The one place the thrusters' inputs reach the
    model on the open-loop paths: ``simulate --command`` (:func:`fly_commands`), ``manoeuvre
    --replay`` and the manoeuvre loop in Python (issue #56). The input vector holds up to
    MAX_THRUSTERS thrusters; beyond that only τ is given."""
    from hydrokit.model.terms import MAX_THRUSTERS

    full = 0 < n_thrusters <= MAX_THRUSTERS

    def rhs(t: float, x: np.ndarray, d: Any) -> np.ndarray:
        tau, thrust, rate = inputs(t, x)
        return f(t, x, tau, d, thrust, rate) if full else f(t, x, tau, d)

    return rhs


def fly_commands(
    vehicle: Any,
    duration: float,
    dt: float,
    force: CommandForce,
    eta0: Any = (0, 0, 0, 0, 0, 0),
    nu0: Any = (0, 0, 0, 0, 0, 0),
    current_ned: Any = None,
    deflection: Any = None,
    output_every: int = 1,
    progress: Callable[[float], None] | None = None,
) -> Any:
    """Open-loop run of ``vehicle`` propelled by ``force`` (its thrusters under commands): RK4 on
    the compiled right-hand side in Euler angles, every stage given τ and each thruster's thrust
    and rotation rate (:meth:`CommandForce.inputs`). Returns a
    :class:`hydrokit.simulate.driver.Trajectory`.

    Parameters
    ----------
    vehicle : Vehicle — with the thrusters of ``force``
    duration, dt : float — s
    force : CommandForce
    eta0, nu0 : 6 floats each — initial pose (m, rad) and velocity (m/s, rad/s)
    current_ned : None, 3 floats (m/s) or rows [t, v_N, v_E, v_D]
    deflection : None, one deflection per surface (rad) or rows [t, δ_1 … δ_n] (s, rad;
        interpolated linearly, held at the ends), as :func:`hydrokit.simulate.driver.simulate`
    output_every : int — keep every n-th step
    progress : callable(simulated seconds) or None
    """
    from hydrokit.core.kinematics import PITCH_WARNING
    from hydrokit.model.dynamics import interp_table
    from hydrokit.simulate.compiled import make_dynamics
    from hydrokit.simulate.driver import Trajectory, deflection_table
    from hydrokit.simulate.integrators import rk4

    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
        raise InputError(f"duration = {duration}: expected a positive time (s)")
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"dt = {dt}: expected 0 < dt ≤ duration (s)")
    if not (isinstance(output_every, int) and output_every >= 1):
        raise InputError(f"output_every = {output_every}: expected a whole number ≥ 1")
    from hydrokit.simulate.budget import check_memory

    # every recorded row is allocated at once: sized first, as the driver does
    steps = duration / dt
    if not math.isfinite(steps):
        raise InputError(f"dt = {dt:.4g} s: duration / dt = {steps} steps; expected a step of a realistic size")
    n_out = math.floor(steps + 1e-9) // output_every + 1
    check_memory(8.0 * n_out * 13, f"the recorded trajectory ({n_out:.4g} rows)")
    x0 = np.concatenate([np.asarray(eta0, float), np.asarray(nu0, float)])
    if x0.shape != (12,) or not np.all(np.isfinite(x0)):
        raise InputError(f"initial pose and velocity {x0.tolist()}: expected 6 + 6 finite numbers")
    dtab = deflection_table(vehicle, deflection)
    g = driven_rhs(
        make_dynamics(vehicle, current_ned), lambda t, x: force.inputs(t, x[:6], x[6:]), len(vehicle.thruster_names)
    )

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        return g(t, x, None if dtab is None else interp_table(dtab, t)[0])

    n_steps = math.floor(duration / dt + 1e-9)
    prog = None if progress is None else (lambda k: progress(k * dt))
    times, states = rk4(rhs, x0, float(dt), n_steps, output_every, prog)
    if progress is not None:
        progress(duration)
    warnings = list(vehicle.warnings)
    if np.any(np.abs(states[:, 4]) > PITCH_WARNING):
        warnings.append(
            f"pitch reached {math.degrees(float(np.max(np.abs(states[:, 4])))):.1f}°: Euler angles are near their "
            "singularity at ±90°"
        )
    return Trajectory(times, states[:, :6], states[:, 6:], warnings)


def command_table(vehicle: Any, commands: Any) -> np.ndarray:
    """``commands`` as rows [t, u_1 … u_m] (s, each thruster's unit) in the vehicle's thruster
    order: a mapping {name: value} held from t = 0 (thrusters not named 0; checked by
    :func:`thruster_commands`), or rows already in that form, each
    command within its thruster's command limits (InputError naming the thruster and the row)."""
    from hydrokit.simulate.mission import COMMAND_UNITS

    if hasattr(commands, "items"):
        return np.concatenate([[0.0], thruster_commands(vehicle, commands)])[None, :]
    ts = vehicle.thrusters
    tab = np.asarray(commands, float)
    if tab.ndim != 2 or tab.shape[1] != len(ts) + 1 or tab.shape[0] < 1:
        raise InputError(
            f"command table of shape {tab.shape}: expected rows [t, {', '.join(ts.names)}] (s, each thruster's unit)"
        )
    for k, name in enumerate(ts.names):
        lo, hi = float(ts.command_min[k]), float(ts.command_max[k])
        bad = np.flatnonzero((tab[:, k + 1] < lo - 1e-12 * abs(lo)) | (tab[:, k + 1] > hi + 1e-12 * abs(hi)))
        if bad.size:
            unit = COMMAND_UNITS[ts.thrusters[k].model]
            raise InputError(
                f"row {int(bad[0]) + 2}, column '{name}' = {tab[bad[0], k + 1]:g} {unit}: expected within thruster "
                f"{name!r}'s command limits [{lo:.6g}, {hi:.6g}] {unit}"
            )
    if not math.isfinite(float(np.sum(tab))):
        raise InputError("command table: expected finite numbers (s, each thruster's unit)")
    return tab


def thruster_commands(vehicle: Any, commands: Any) -> np.ndarray:
    """The command vector (file order; thrusters not named 0) of ``commands`` {name: value}, the
    value in each thruster's unit (rev/s, the table's unit or N), checked against the vehicle's
    thrusters and their command limits (InputError: one line naming the thruster)."""
    from hydrokit.simulate.mission import COMMAND_UNITS

    ts = getattr(vehicle, "thrusters", None)
    if ts is None or len(ts) == 0:
        raise InputError(
            f"commands {short_repr(commands)}: vehicle {vehicle.name!r} has no thrusters; expected a vehicle file "
            "with a 'thrusters:' block (or a constant force only)"
        )
    if not hasattr(commands, "items"):
        raise InputError(f"commands {short_repr(commands)}: expected a mapping of thruster name to command")
    names = ts.names
    out = np.zeros(len(names))
    for name, value in commands.items():
        if name not in names:
            raise InputError(
                f"command {str(name)[:40]!r}: the vehicle has thrusters {', '.join(names)}; expected one of them"
            )
        k = names.index(name)
        unit = COMMAND_UNITS[ts.thrusters[k].model]
        try:
            c = float(value)
        except (TypeError, ValueError):
            c = math.nan
        lo, hi = float(ts.command_min[k]), float(ts.command_max[k])
        if not math.isfinite(c):
            raise InputError(f"command {name}={str(value)[:40]}: expected a finite number ({unit})")
        if not lo - 1e-12 * abs(lo) <= c <= hi + 1e-12 * abs(hi):
            raise InputError(
                f"command {name}={c:g} {unit}: expected within thruster {name!r}'s command limits [{lo:.6g}, {hi:.6g}] {unit}"
            )
        out[k] = c
    return out


def short_repr(x: Any) -> str:  # noqa: ANN401
    """``repr(x)`` cut to 60 characters (a bad value quoted in a one-line error)."""
    r = repr(x)
    return r if len(r) <= 60 else r[:57] + "…"
