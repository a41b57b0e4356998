"""The manoeuvre loop compiled (issue #50 item 2): wiring only.

The helm logics, the hold autopilot, the approach's steadiness test
(:mod:`hydrokit.manoeuvre.laws`), the PID law and the Euler rates
(:mod:`hydrokit.model.control`), the servo (:func:`hydrokit.model.surfaces.servo_step`) and the
right-hand side (:func:`hydrokit.simulate.compiled.deriv`) are compiled from their one
implementation by ``compile_law``; this module only calls them step after step with RK4 at the
manoeuvre's step, as :class:`hydrokit.manoeuvre.run._PythonLoop` does in Python (the same
laws, the same order of operations: the two loops agree to rounding).

:class:`Engine` is what :func:`hydrokit.manoeuvre.run.fly_manoeuvre` takes as ``engine``: a
vehicle with a constant force (N, N·m) and an optional current, its approach and its manoeuvre.
With thruster commands it also flies :class:`~hydrokit.manoeuvre.run.ThrusterDrive`'s law:
the rotor lag, each propeller's K_T(J) thrust at its advance speed (the laws of
:mod:`hydrokit.model.thrusters`, compiled) and the configuration matrix, step by step, for
propeller and ideal thrusters in still water (:func:`drive_compiles`); a table curve, a current
with thrusters or a force that is a function of the state fly in the Python loop.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit._numba import njit
from hydrokit.core.kinematics import wrap_angle
from hydrokit.errors import InputError
from hydrokit.manoeuvre import laws as L
from hydrokit.model.control import _euler_rates, depth_to_pitch, pid_law
from hydrokit.model.thrusters import IdealCurve, PropellerCurve
from hydrokit.simulate.compiled import (
    BUF_SIZE,
    compile_law,
    deriv,
    deriv_rk4_step,
    njit_noalloc,
    servo_step_compiled,
)
from hydrokit.simulate.compiled import rk4_combine_compiled as _rk4_combine
from hydrokit.simulate.compiled import rk4_stage_compiled as _rk4_stage
from hydrokit.simulate.compiled import rotor_lag_compiled as _rotor_lag
from hydrokit.simulate.compiled import thruster_inputs_compiled as _thruster_inputs

#: the loop's two entry kernels run without the GIL, so drawn vehicles fly on threads at once
#: (``manoeuvre --samples``: :func:`hydrokit.manoeuvre.samples.fly_samples`)
_njit_nogil = njit(_nrt=False, nogil=True)


def _compile_all() -> dict[str, Any]:
    """Every law the loop calls, compiled in the order they call each other (each bound to the
    compiled versions of those before it)."""
    done: dict[str, Any] = {}
    for law in (
        wrap_angle,
        _euler_rates,
        pid_law,
        depth_to_pitch,
        L._execute,
        L._last_execute,
        L.scale_now,
        L._mean,
        L._record,
        L._reset,
        L.rate_pilot,
        L.turn_command,
        L.zigzag_command,
        L.spiral_command,
        L.pull_out_command,
        L.depth_change_command,
        L.depth_pilot_command,
        L.helm_command,
        L._set_pid,
        L.keeper_tune,
        L.keeper_due,
        L.keeper_settled,
        L._pid,
        L.keeper_command,
        L.pitch_hold,
        L.depth_pitch,
        L.manoeuvre_command,
        L.approach_steady,
    ):
        done[law.__name__] = compile_law(law, **done)
    return done


_LAWS = _compile_all()
_keeper_due = _LAWS["keeper_due"]
_keeper_tune = _LAWS["keeper_tune"]
_keeper_command = _LAWS["keeper_command"]
_keeper_settled = _LAWS["keeper_settled"]
_manoeuvre_command = _LAWS["manoeuvre_command"]
_approach_steady = _LAWS["approach_steady"]

# status of the loops: done, not yet (the record is full or the chunk ended), non-finite
_DONE, _RUNNING, _DIVERGED = 1, 0, -1


@njit_noalloc
def _rk4(t, x, dt, tau_tab, ctab, V, buf, W):  # noqa: ANN001, ANN202
    """x advanced in place by one RK4 step of ``dt`` (s) with the inputs of ``tau_tab`` held
    (:func:`hydrokit.simulate.compiled.deriv_rk4_step`, the one RK4 of the package); False
    when the new state is not finite."""
    k1, k2, k3, k4, tmp = W[0], W[1], W[2], W[3], W[4]
    return deriv_rk4_step(
        t,
        x,
        dt,
        False,
        tau_tab,
        ctab,
        V,
        buf,
        k1,
        k2,
        k3,
        k4,
        tmp,
        False,
    )


@njit_noalloc
def _probe(x, surface, limit, index, n_s, tau_tab, ctab, V, buf, out):  # noqa: ANN001, ANN202
    """∂(angular acceleration at ``index``)/∂δ of ``surface`` in the state ``x`` (1/s² per rad):
    the difference quotient of :func:`hydrokit.manoeuvre.run._probe`, at δ = 0 elsewhere (the
    ``n_s`` deflections; the thrusters' inputs as ``tau_tab`` holds them)."""
    for j in range(7, 7 + n_s):
        tau_tab[0, j] = 0.0
    eps = 0.1 * limit
    tau_tab[0, 7 + surface] = eps
    deriv(0.0, x, False, tau_tab, ctab, V, buf, out)
    a = out[index]
    tau_tab[0, 7 + surface] = 0.0
    deriv(0.0, x, False, tau_tab, ctab, V, buf, out)
    return (a - out[index]) / eps


@njit_noalloc
def _tune(K, t, x, lim, tau_tab, ctab, V, buf, out):  # noqa: ANN001, ANN202
    """The hold's probes and gain scheduling (:func:`~hydrokit.manoeuvre.laws.keeper_tune`)."""
    plane, rudder = int(K[L.K_PLANE]), int(K[L.K_RUDDER])
    n_s = lim.shape[0]
    g_q = _probe(x, plane, lim[plane], 10, n_s, tau_tab, ctab, V, buf, out) if plane >= 0 else 0.0
    g_r = _probe(x, rudder, lim[rudder], 11, n_s, tau_tab, ctab, V, buf, out) if rudder >= 0 else 0.0
    _keeper_tune(K, t, x, g_q, g_r)


@njit_noalloc
def _set_deflections(tau_tab, delta):  # noqa: ANN001, ANN202
    """The deflections (rad) into the first columns of the input vector; the thrusters' columns
    after them are the drive's (:func:`_drive_inputs`; 0 without a drive)."""
    for j in range(delta.shape[0]):
        tau_tab[0, 7 + j] = delta[j]


@njit_noalloc
def _drive_inputs(x, h, n_s, tau_tab, Dr):  # noqa: ANN001, ANN202
    """The thrusters' part of the input vector in the still-water state ``x`` into ``tau_tab``:
    τ (N, N·m) to the force columns, each thruster's thrust (N) and rotation rate (rev/s) to its
    input columns after the ``n_s`` deflections (:func:`hydrokit.model.thrusters.thruster_inputs`,
    compiled), at the rotor state ``h`` s into the step begun last (``h`` < 0: the state now)."""
    kind, prop, kf, kr, lim, tc, wake, dirs, arms, T, force, target, c, c0, cs, f, rate, tau = Dr
    m = kind.shape[0]
    for j in range(m):
        if h < 0.0:
            cs[j] = c[j]
        else:
            ct = target[j]
            ct = lim[j, 0] if ct < lim[j, 0] else (lim[j, 1] if ct > lim[j, 1] else ct)
            cs[j] = _rotor_lag(c0[j], ct, h, tc[j])
    _thruster_inputs(kind, prop, kf, kr, lim, wake, dirs, arms, T, force, cs, x[6:12], f, rate, tau)
    for i in range(6):
        tau_tab[0, 1 + i] = tau[i]
    if tau_tab.shape[1] >= 7 + n_s + 2 * m:  # the input vector holds the thrusters (≤ MAX_THRUSTERS)
        for j in range(m):
            tau_tab[0, 7 + n_s + j] = f[j]
            tau_tab[0, 7 + n_s + m + j] = rate[j]


@njit_noalloc
def _drive_begin(dt, Dr):  # noqa: ANN001, ANN202
    """ThrusterDrive.begin_step: c0 the rotor state at the step's start, c at its end (in place)."""
    kind, prop, kf, kr, lim, tc, wake, dirs, arms, T, force, target, c, c0, cs, f, rate, tau = Dr
    for j in range(kind.shape[0]):
        ct = target[j]
        ct = lim[j, 0] if ct < lim[j, 0] else (lim[j, 1] if ct > lim[j, 1] else ct)
        c0[j] = c[j]
        c[j] = _rotor_lag(c0[j], ct, dt, tc[j])


@njit_noalloc
def _drive_rk4(t, x, dt, n_s, tau_tab, ctab, V, buf, W, Dr):  # noqa: ANN001, ANN202
    """x advanced in place by one RK4 step of ``dt`` (s) with the thrusters' inputs evaluated at
    every stage, at its state and rotor state (as ``simulate --command``,
    :func:`hydrokit.simulate.commands.fly_commands`); the stages and the update are
    :mod:`hydrokit.core.integrate`'s. False when the new state is not finite."""
    k1, k2, k3, k4, tmp = W[0], W[1], W[2], W[3], W[4]
    _drive_begin(dt, Dr)
    _drive_inputs(x, 0.0, n_s, tau_tab, Dr)
    deriv(t, x, False, tau_tab, ctab, V, buf, k1)
    _rk4_stage(x, k1, 0.5 * dt, tmp)
    _drive_inputs(tmp, 0.5 * dt, n_s, tau_tab, Dr)
    deriv(t + 0.5 * dt, tmp, False, tau_tab, ctab, V, buf, k2)
    _rk4_stage(x, k2, 0.5 * dt, tmp)
    _drive_inputs(tmp, 0.5 * dt, n_s, tau_tab, Dr)
    deriv(t + 0.5 * dt, tmp, False, tau_tab, ctab, V, buf, k3)
    _rk4_stage(x, k3, dt, tmp)
    _drive_inputs(tmp, dt, n_s, tau_tab, Dr)
    deriv(t + dt, tmp, False, tau_tab, ctab, V, buf, k4)
    return _rk4_combine(x, k1, k2, k3, k4, dt)


@njit_noalloc
def _step(t, x, dt, n_s, tau_tab, ctab, V, buf, W, Dr):  # noqa: ANN001, ANN202
    """One step of the manoeuvre: the drive's (:func:`_drive_rk4`) or, with a constant force, RK4
    with the inputs held (:func:`_rk4`)."""
    if Dr[0].shape[0] > 0:
        return _drive_rk4(t, x, dt, n_s, tau_tab, ctab, V, buf, W, Dr)
    return _rk4(t, x, dt, tau_tab, ctab, V, buf, W)


@_njit_nogil
def _approach(x, n_app, window, dt, K, lim, rate, tc, delta, cmd, new, rows, used, tau_tab, ctab, V, buf, W, Dr):  # noqa: ANN001, ANN202
    """The straight approach (see :meth:`hydrokit.manoeuvre.run._PythonLoop.approach`)."""
    n_s = delta.shape[0]
    drive = Dr[0].shape[0] > 0
    for k in range(n_app):
        t = k * dt
        if K[L.K_ON] > 0:
            if _keeper_due(K, t):
                if drive:
                    _drive_inputs(x, -1.0, n_s, tau_tab, Dr)
                _tune(K, t, x, lim, tau_tab, ctab, V, buf, W[5])
            _keeper_command(K, x, dt, cmd, True)
        servo_step_compiled(delta, cmd, dt, lim, rate, tc, new)
        for j in range(n_s):
            delta[j] = new[j]
            used[k, j] = new[j]
        _set_deflections(tau_tab, delta)
        if not _step(t, x, dt, n_s, tau_tab, ctab, V, buf, W, Dr):
            return k, _DIVERGED
        for i in range(12):
            rows[k + 1, i] = x[i]
        if k >= window and k % window == 0 and _approach_steady(rows, k + 2, window, x):
            if K[L.K_ON] == 0 or _keeper_settled(K, x):
                return k, _DONE
    return n_app - 1, _RUNNING


@_njit_nogil
def _fly(
    x,
    k0,
    k_end,
    n_max,
    dt,
    t_start,
    surface,
    P,
    S,
    H,
    R,
    K,
    lim,
    rate,
    tc,
    delta,
    cmd,
    new,
    states,
    defl,
    tau_tab,
    ctab,
    V,
    buf,
    W,
    Dr,
):  # noqa: ANN001, ANN202
    """Steps k0 … k_end − 1 of the manoeuvre (see :meth:`hydrokit.manoeuvre.run._PythonLoop.fly`)."""
    n_s = delta.shape[0]
    drive = Dr[0].shape[0] > 0
    for k in range(k0, k_end):
        t = k * dt
        if _keeper_due(K, t_start + t):
            if drive:
                _drive_inputs(x, -1.0, n_s, tau_tab, Dr)
            _tune(K, t_start + t, x, lim, tau_tab, ctab, V, buf, W[5])
        _manoeuvre_command(P, S, H, R, K, t, x, dt, cmd, surface)
        servo_step_compiled(delta, cmd, dt, lim, rate, tc, new)
        for j in range(n_s):
            delta[j] = new[j]
            defl[k, j] = new[j]
        for i in range(12):
            states[k, i] = x[i]
        if S[L.S_DONE] > 0 or k == n_max:
            return k, _DONE
        _set_deflections(tau_tab, delta)
        if not _step(t, x, dt, n_s, tau_tab, ctab, V, buf, W, Dr):
            return k, _DIVERGED
    return k_end - 1, _RUNNING


def drive_compiles(drive: Any) -> bool:
    """Whether the compiled loop flies ``drive`` (a
    :class:`~hydrokit.manoeuvre.run.ThrusterDrive`): propeller and ideal curves, in still
    water (a table curve or a current: the Python loop)."""
    cur = np.asarray(drive.current, float)
    still = cur.shape[0] == 1 and not np.any(cur[0, 1:])
    return still and all(isinstance(cv, (PropellerCurve, IdealCurve)) for cv in drive.thrusters.curves)


def _pack_drive(drive: Any) -> tuple[np.ndarray, ...]:
    """The drive group of the kernels: (kind 0 ideal / 2 propeller, propeller constants
    [D, ρ, J_lo, J_hi, loss_f, loss_r], K_T forward and reverse padded with leading zeros to one
    length, limits [c_min, c_max, f_min, f_max], τ (s), 1 − w, e_i, r_i × e_i, T (6 × m), force,
    target, rotor state c now and c0 at the step's start (the drive's own arrays, advanced in
    place), scratch: the stage's rotor state, thrusts, rates and τ)."""
    ts = drive.thrusters
    m = len(ts)
    kind = np.zeros(m, dtype=np.int64)
    prop = np.zeros((m, 6))
    curves = ts.curves
    props = [cv for cv in curves if isinstance(cv, PropellerCurve)]
    n_poly = max([len(cv.law_args[4]) for cv in props] + [len(cv.law_args[5]) for cv in props] + [1])
    kf, kr = np.zeros((m, n_poly)), np.zeros((m, n_poly))
    for j, cv in enumerate(curves):
        if isinstance(cv, PropellerCurve):
            kind[j] = 2
            D, rho, jlo, jhi, k_f, k_r, lf, lr = cv.law_args
            prop[j] = (D, rho, jlo, jhi, lf, lr)
            # leading zeros keep Horner's value bit for bit
            kf[j, n_poly - len(k_f) :] = k_f
            kr[j, n_poly - len(k_r) :] = k_r
    lim = np.column_stack([ts.command_min, ts.command_max, ts.f_min, ts.f_max]).astype(float)
    drive.c = np.ascontiguousarray(drive.c, dtype=float)
    drive.c0 = np.ascontiguousarray(drive.c0, dtype=float)
    return (
        kind, prop, kf, kr, np.ascontiguousarray(lim), np.asarray(ts.time_constants, float),
        np.asarray(ts._wake_factor, float), np.ascontiguousarray(ts.directions, dtype=float),
        np.ascontiguousarray(ts._moment_arms, dtype=float), np.ascontiguousarray(drive.T, dtype=float),
        np.asarray(drive.force, float), np.asarray(drive.target, float), drive.c, drive.c0, np.zeros(m),
        np.zeros(m), np.zeros(m), np.zeros(6),
    )  # fmt: skip


def _no_drive() -> tuple[np.ndarray, ...]:
    e1, e2 = np.zeros(0), np.zeros((0, 1))
    return (
        np.zeros(0, dtype=np.int64), e2, e2, e2, e2, e1, e1, e2, e2, np.zeros((6, 0)), np.zeros(6), e1, e1, e1, e1,
        e1, e1, np.zeros(6),
    )  # fmt: skip


class Engine:
    """The compiled manoeuvre loop of ``vehicle`` pushed by the constant force ``tau`` (6 floats,
    N, N·m, body axes) in the current ``current_ned`` (None, 3 floats m/s NED, or rows [t, v_N,
    v_E, v_D]); pass it as ``engine`` to :func:`hydrokit.manoeuvre.run.fly_manoeuvre`
    with ``f = make_dynamics(vehicle, current_ned)``. With ``drive`` (a
    :class:`~hydrokit.manoeuvre.run.ThrusterDrive` that :func:`drive_compiles`) the force is
    the drive's, step by step, and its rotor state is advanced in place (``tau`` is then unused)."""

    def __init__(self, vehicle: Any, tau: Any, current_ned: Any = None, drive: Any = None) -> None:
        from hydrokit.model.dynamics import check_wind, current_table, pack
        from hydrokit.model.terms import MAX_THRUSTERS

        p = pack(vehicle)
        self.ctab = current_table(current_ned)
        check_wind(vehicle, self.ctab)
        ns, m = len(vehicle.surfaces), len(vehicle.thruster_names)
        # the layout of make_dynamics: [t, τ (6), the vehicle's input vector]
        self.tau_tab = np.zeros((1, 7 + (vehicle.n_inputs if m <= MAX_THRUSTERS else ns)))
        self.tau_tab[0, 1:7] = np.asarray(tau, float)
        self.V = p.V
        self.buf = np.empty(BUF_SIZE)
        self.W = np.empty((6, 12))
        if drive is not None and not drive_compiles(drive):
            raise InputError("the compiled manoeuvre loop flies propeller and ideal thrusters in still water")
        self.drive = drive
        self.Dr = _no_drive() if drive is None else _pack_drive(drive)

    def approach(
        self,
        x: np.ndarray,
        n_app: int,
        window: int,
        dt: float,
        keeper: Any,
        sv: Any,
        rows: np.ndarray,
        used: np.ndarray,
    ) -> tuple[int, int]:
        """As :meth:`hydrokit.manoeuvre.run._PythonLoop.approach`."""
        K = keeper.K if keeper is not None else np.zeros(L.K_SIZE)
        k, status = _approach(
            x, n_app, window, float(dt), K, sv.lim, sv.rate, sv.tc, sv.delta, sv.cmd, sv.new, rows, used,
            self.tau_tab, self.ctab, self.V, self.buf, self.W, self.Dr,
        )  # fmt: skip
        return int(k), int(status)

    def fly(
        self,
        x: np.ndarray,
        k0: int,
        k_end: int,
        n_max: int,
        dt: float,
        t_start: float,
        surface: int,
        logic: Any,
        keeper: Any,
        sv: Any,
        states: np.ndarray,
        defl: np.ndarray,
    ) -> tuple[int, int]:
        """As :meth:`hydrokit.manoeuvre.run._PythonLoop.fly`."""
        K = keeper.K if keeper is not None else np.zeros(L.K_SIZE)
        k, status = _fly(
            x, k0, k_end, n_max, float(dt), float(t_start), surface, logic.P, logic.S, logic.H, logic.R, K,
            sv.lim, sv.rate, sv.tc, sv.delta, sv.cmd, sv.new, states, defl, self.tau_tab, self.ctab, self.V,
            self.buf, self.W, self.Dr,
        )  # fmt: skip
        return int(k), int(status)
