"""Compiled (numba) closed loop: guidance, autopilot, allocation, thrusters and vehicle in one
compiled step.

The compiled twin of :func:`hydrokit.simulate.closed_loop.run_closed_loop`, kept for speed;
tests/simulate/test_compiled_loop.py flies every bundled mission both ways (agreement to 1e-9
of each column's scale). The laws are written once, on plain floats, in model/ and core/, and
compiled here by ``compile_law``; this module is their wiring (packing, the step order, the
record, the fleet):

- guidance: :func:`hydrokit.model.guidance.los_guidance` (LOS heading, depth lookahead, speed
  profile, waypoint switching) on the Path's per-leg table;
- autopilot: :func:`hydrokit.model.control.error_and_rate`, ``_euler_rates``,
  :func:`~hydrokit.model.control.depth_to_pitch`, :func:`~hydrokit.model.control.pid_law` and
  :func:`~hydrokit.model.control.splane_law`;
- allocation: :func:`hydrokit.model.allocation.pinv_allocate` (the cached (weighted)
  pseudo-inverse and the limit test);
- thrusters: the propeller laws and the table curve's interpolation
  (:func:`hydrokit.model.thrusters.table_interp`) of :mod:`hydrokit.model.thrusters`, and the
  rotation R(Θ) of the current into body axes (:func:`hydrokit.core.kinematics.rotation_zyx_entries`);
- vehicle: the RK4 step :func:`hydrokit.simulate.compiled.deriv_rk4_step` with the thrust held;
- the record: :func:`hydrokit.simulate.closed_loop.new_record` and ``record_result``;
- the fleet's metrics: the path distance :func:`hydrokit.model.guidance.point_path_distance`;
- allocation beyond a limit: :func:`hydrokit.model.allocation.constrained_kernel`, the two-stage
  constrained allocation (bounded least squares, :mod:`hydrokit.model.bvls`, and the polishing
  step) that the Python :class:`~hydrokit.model.allocation.Allocator` calls too.

The advance speed is the law :func:`hydrokit.model.thrusters.advance_speed_law`, as in
``ThrusterSet.advance_speed``.

Agreement is to round-off, not bit for bit: the small matrix–vector products (T f) are plain
loops here, where numpy calls BLAS (calling BLAS from the loop made it three
times slower). States, τ and thrusts then agree to ~1e-13 of their scale.
Two places turn round-off into more, in both loops alike: a propeller command n = ±√(|f|/k)
for a thrust demand that is zero up to round-off (±1e-14 N gives ±5e-7 rev/s), and the
allocation's polishing step, kept only if it stays within the limits, when a thruster lands
exactly on its limit (seen with 16 random thrusters, not in the bundled missions).

Everything is packed into arrays of fixed dtypes, so there is one compiled specialization
(cached on disk: ``cache=True``). The run goes in chunks of about 1 % so that a progress
callback can be called between them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike

from hydrokit._numba import njit
from hydrokit.core.kinematics import wrap_angle
from hydrokit.errors import InputError, SimulationError
from hydrokit.model.allocation import Allocator, _ConstrainedSolver, constrained_kernel, pinv_allocate
from hydrokit.model.control import (
    PID,
    Autopilot,
    SPlane,
    _euler_rates,
    depth_to_pitch,
    error_and_rate,
    pid_law,
    splane_law,
)
from hydrokit.model.guidance import Path, los_guidance, point_path_distance
from hydrokit.model.thrusters import IdealCurve, PropellerCurve, TableCurve, ThrusterSet
from hydrokit.simulate.closed_loop import RECORD_FIELDS, ClosedLoopResult, new_record, record_result
from hydrokit.simulate.compiled import (
    BUF_SIZE,
    compile_law,
    deriv_rk4_step,
    njit_noalloc,
    steer_surfaces_compiled,
)
from hydrokit.simulate.compiled import advance_speed_compiled as _advance_speed
from hydrokit.simulate.compiled import propeller_speed_compiled as _propeller_speed
from hydrokit.simulate.compiled import propeller_thrust_compiled as _propeller_thrust
from hydrokit.simulate.compiled import rotation_zyx_entries_compiled as _rotation_zyx
from hydrokit.simulate.compiled import table_interp_compiled as _table_interp

_depth_to_pitch = compile_law(depth_to_pitch)
_pid_law = compile_law(pid_law)
_splane_law = compile_law(splane_law)
_wrap = compile_law(wrap_angle)
_error_and_rate = compile_law(error_and_rate, wrap_angle=_wrap)
_euler_rates_law = compile_law(_euler_rates)
_los_guidance = compile_law(los_guidance)
_path_distance = compile_law(point_path_distance)
_pinv_allocate = compile_law(pinv_allocate)
_constrained = constrained_kernel()
# status codes of _loop
_RUNNING, _DONE, _DIVERGED = 0, 1, 2


# ============================================================================ thrust curves
# kinds: 0 ideal, 1 table, 2 propeller
# prop rows: D, D4, rho, jlo, jhi, loss_f, loss_r, n_max, den_f, den_r; kf/kr rows: K_T(J)
# polynomials padded with leading zeros. The propeller laws are model/thrusters.py's, compiled.
@njit_noalloc
def _prop_thrust(i, n, va, prop, kf, kr):  # noqa: ANN001, ANN202
    return _propeller_thrust(
        n, va, prop[i, 0], prop[i, 2], prop[i, 3], prop[i, 4], kf[i], kr[i], prop[i, 5], prop[i, 6]
    )


@njit_noalloc
def _prop_command(i, f, va, prop, kf, kr):  # noqa: ANN001, ANN202
    return _propeller_speed(
        f, va, prop[i, 7], prop[i, 0], prop[i, 2], prop[i, 3], prop[i, 4], kf[i], kr[i], prop[i, 5], prop[i, 6]
    )


@njit_noalloc
def _thrust(i, c, va, kind, tab_c, tab_f, tab_n, prop, kf, kr):  # noqa: ANN001, ANN202
    """Unclipped thrust of thruster i at command c, N."""
    k = kind[i]
    if k == 0:
        return c
    if k == 1:
        return _table_interp(c, tab_c[i], tab_f[i], tab_n[i])
    return _prop_thrust(i, c, va, prop, kf, kr)


@njit_noalloc
def _command(i, f, va, kind, tab_c, tab_f, tab_n, prop, kf, kr):  # noqa: ANN001, ANN202
    """Command of thruster i giving thrust f (already clipped to its limits)."""
    k = kind[i]
    if k == 0:
        return f
    if k == 1:
        return _table_interp(f, tab_f[i], tab_c[i], tab_n[i])
    return _prop_command(i, f, va, prop, kf, kr)


@njit
def _allocate_limited(tau_d, A, f_cmd):  # noqa: ANN001, ANN202
    """f_cmd ← the constrained allocation of τ_d (its unactuated DOFs zeroed). The one part of
    a step that allocates memory, so kept out of _control, which is compiled without numba's
    reference counting (the atomic reference-count updates of its ~60 array arguments were a
    fifth of a fleet step)."""
    _P, f_min, f_max, unact, T, lo_s, hi_s, Q, QT, A2, apar, ptol = A
    tau_eff = tau_d.copy()
    for jd in range(6):
        if unact[jd]:
            tau_eff[jd] = 0.0
    f_c = _constrained(tau_eff, T, f_min, f_max, lo_s, hi_s, Q, QT, A2, apar[0], apar[1], apar[2], ptol)
    for i in range(f_cmd.shape[0]):
        f_cmd[i] = f_c[i]


# ============================================================================ the loop
@njit
def _work(m, ns, first):  # noqa: ANN001, ANN202
    """Scratch arrays of one flight (one set per fleet member); ``ns`` control surfaces, whose
    deflections (rad, the servo's state) live in tau_tab[0, 7:], then (``first`` ≥ 0: the
    vehicle's input vector holds its thrusters) each thruster's thrust and rotation rate."""
    return (
        np.zeros((1, 7 + ns + (2 * m if first >= 0 else 0))),  # tau_tab
        np.empty(BUF_SIZE),  # buf
        np.empty(12),  # k1v
        np.empty(12),  # k2v
        np.empty(12),  # k3v
        np.empty(12),  # k4v
        np.empty(12),  # tmp
        np.zeros(6),  # tau_d
        np.empty(m),  # f_cmd
        np.empty(m),  # va
        np.empty(3),  # pa
        np.empty(m),  # c_cmd
        np.empty(m),  # f_act
        np.empty(5),  # meas
        np.empty(5),  # setp
        np.empty(5),  # rate
        np.zeros(5),  # out
    )


# The per-step kernel, shared by the single run (_loop) and the fleet (_fleet_member):
# _control (guidance → autopilot → unconstrained allocation at step k, with the state x at t = k dt),
# _allocate_limited when that exceeds a limit, _thrusters, then _integrate (RK4 of the vehicle with the thrust held, and the rotor lag).
# Argument groups (tuples of arrays, packed by _pack):
#   G guidance: points, leg table (model.guidance.Path.leg_table), [R, lookahead]
#   A allocation: P, f_min, f_max, unactuated, T, lo_s, hi_s, Q, QT, A2, [scale, thrust_scale,
#     q_max], polish tol
#   H thrusters: kind, dirs, arms, wake, cmd_min, cmd_max, decay, mean_w, tab_c, tab_f, tab_n,
#     prop, kf, kr, [first thrust column of tau_tab or −1] (input_columns)
#   ctl (5, 6) rows [kind, p1..p5] and angle flags (5,); vc (3,) NED current, m/s
#   V vehicle: current table, Minv, Mc, DL, DQ, scal (with the drag elements and fins, see
#     model.dynamics.Packed), t_dof, t_coef, t_kind, t_idx, and the control surfaces' limits smax
#     (rad), rate limits srate (rad/s), servo lags stc (s) and sfin [first fin index in scal, fins]
# numba's on-disk cache of these kernels holds its own copy of compiled.deriv and of the laws;
# it is keyed on their sources too (hydrokit/_numba.py), so a change there recompiles them.
#   state (in/out): x (12), c (m), fstate [heading, integral×5, previous×5], istate
#     [leg, j, limited_any, has_prev×5], arrivals (N,)
#   W scratch (_work)
@njit_noalloc
def _control(k, dt, G, A, ctl, ctl_angle, x, fstate, istate, arrivals, W):  # noqa: ANN001, ANN202
    """Guidance, autopilot and the unconstrained allocation at step k; fills W's τ_d and f_cmd
    and returns (leg, limited, speed, depth and heading references). When limited, the caller
    runs _allocate_limited (which allocates memory, so cannot be called from here), then
    _thrusters."""
    _pts, legs, gpar = G
    P, f_min, f_max = A[0], A[1], A[2]
    _tt, _b, _k1, _k2, _k3, _k4, _tmp, tau_d, f_cmd, _va, _pa, _cc, _fa, meas, setp, rate, out = W
    n_legs = legs.shape[0] - 1

    t = k * dt
    pz = x[2]
    phi, theta, psi = x[3], x[4], x[5]
    u = x[6]
    # ---------------------------------------------------------------- guidance (model.guidance.los_guidance)
    leg0 = istate[0]
    kk, heading, ref_speed, ref_depth, ref_heading = _los_guidance(
        x[0], x[1], pz, psi, True, leg0, fstate[0], legs, n_legs, gpar[0], gpar[1]
    )
    if kk != leg0:
        for lg in range(leg0, min(kk, n_legs + 1)):
            arrivals[lg - 1] = t
    istate[0] = kk
    fstate[0] = heading
    # ---------------------------------------------------------------- autopilot (model.control's laws)
    zdot, phidot, thetadot, psidot = _euler_rates_law(phi, theta, u, x[7], x[8], x[9], x[10], x[11])
    meas[0], meas[1], meas[2], meas[3], meas[4] = u, pz, psi, phi, theta
    setp[0], setp[1], setp[2], setp[3], setp[4] = ref_speed, ref_depth, ref_heading, 0.0, 0.0
    if ctl[5, 0] > 0.0:  # depth through pitch
        setp[4] = _depth_to_pitch(pz, ref_depth, ctl[5, 0], ctl[5, 1])
    rate[0], rate[1], rate[2], rate[3], rate[4] = 0.0, zdot, psidot, phidot, thetadot
    for L_ in range(5):
        kd_ = ctl[L_, 0]
        if kd_ == 0.0:
            out[L_] = 0.0
            continue
        y = meas[L_]
        # the speed loop differentiates u itself (no measured rate)
        e, rr = _error_and_rate(y, setp[L_], ctl_angle[L_], rate[L_], L_ != 0, fstate[6 + L_], istate[3 + L_] != 0, dt)
        if kd_ == 1.0:  # PID
            kp, ki, kdv, omin, omax = ctl[L_, 1], ctl[L_, 2], ctl[L_, 3], ctl[L_, 4], ctl[L_, 5]
            out[L_], fstate[1 + L_] = _pid_law(kp, ki, kdv, omin, omax, fstate[1 + L_], e, rr, dt)
        else:  # S-plane
            out[L_] = _splane_law(ctl[L_, 1], ctl[L_, 2], ctl[L_, 3], e, rr)
        fstate[6 + L_] = y
        istate[3 + L_] = 1
    tau_d[0], tau_d[1], tau_d[2] = out[0], 0.0, out[1]
    tau_d[3], tau_d[4], tau_d[5] = out[3], out[4], out[2]
    # ---------------------------------------------------------------- allocation (model.allocation.pinv_allocate)
    limited = _pinv_allocate(P, tau_d, f_min, f_max, f_cmd)
    return kk, limited, ref_speed, ref_depth, ref_heading


@njit_noalloc
def _thrusters(vc, x, c, A, H, W, limited):  # noqa: ANN001, ANN202
    """Thruster commands and thrusts for W's f_cmd at state x: fills W's c_cmd and f_act and
    returns whether any thruster saturated (or the allocation was limited)."""
    kind, dirs, arms, wake, cmd_min, cmd_max, decay, mean_w, tab_c, tab_f, tab_n, prop, kf, kr, inp = H
    tau_tab, _b, _k1, _k2, _k3, _k4, _tmp, _tau, f_cmd, va, pa, c_cmd, f_act, _me, _se, _ra, _ou = W
    first = inp[0]
    f_min, f_max = A[1], A[2]
    m = f_cmd.shape[0]
    still = vc[0] == 0.0 and vc[1] == 0.0 and vc[2] == 0.0
    phi, theta, psi = x[3], x[4], x[5]
    u, v, w, p, q, r = x[6], x[7], x[8], x[9], x[10], x[11]
    if still:
        ur, vr, wr = u, v, w
    else:
        cf, sf = math.cos(phi), math.sin(phi)
        ct, st = math.cos(theta), math.sin(theta)
        cp, sp = math.cos(psi), math.sin(psi)
        R00, R01, R02, R10, R11, R12, R20, R21, R22 = _rotation_zyx(cf, sf, ct, st, cp, sp)
        # ν_r = ν − [Rᵀ v_c; 0] (R = rotation_zyx, as deriv)
        ur = u - (R00 * vc[0] + R10 * vc[1] + R20 * vc[2])
        vr = v - (R01 * vc[0] + R11 * vc[1] + R21 * vc[2])
        wr = w - (R02 * vc[0] + R12 * vc[1] + R22 * vc[2])
    # the relative linear velocity, for _steer (W's pa: scratch)
    pa[0], pa[1], pa[2] = ur, vr, wr
    for i in range(m):
        va[i] = _advance_speed(
            wake[i], dirs[i, 0], dirs[i, 1], dirs[i, 2], arms[i, 0], arms[i, 1], arms[i, 2], ur, vr, wr, p, q, r
        )
    sat = limited
    for i in range(m):
        fi = min(max(f_cmd[i], f_min[i]), f_max[i])
        ci = _command(i, fi, va[i], kind, tab_c, tab_f, tab_n, prop, kf, kr)
        ci = min(max(ci, cmd_min[i]), cmd_max[i])
        c_cmd[i] = ci
        cm = ci + (c[i] - ci) * mean_w[i]
        cm = min(max(cm, cmd_min[i]), cmd_max[i])
        fa = _thrust(i, cm, va[i], kind, tab_c, tab_f, tab_n, prop, kf, kr)
        f_act[i] = min(max(fa, f_min[i]), f_max[i])
        if first >= 0:  # the vehicle's input vector: the thrust held over the step and the rotor's rate
            tau_tab[0, first + i] = f_act[i]
            tau_tab[0, first + m + i] = cm if kind[i] == 2 else 0.0
        if ci >= cmd_max[i] * (1 - 1e-9) or ci <= cmd_min[i] * (1 - 1e-9):
            sat = True
    return sat


@njit_noalloc
def _steer(dt, x, T, V, W):  # noqa: ANN001, ANN202
    """One servo step of the control surfaces towards W's τ_d (model.surfaces.steer_surfaces,
    compiled) at the relative velocity _thrusters left in W's pa; the deflections, in W's
    tau_tab[0, 7:], are then held over the step by _integrate."""
    _ct, _Mi, _Mc, _DL, _DQ, scal, t_dof, t_coef, t_kind, t_idx, smax, srate, stc, sfin = V
    tau_tab, buf, _k1, _k2, _k3, _k4, _tmp, tau_d, _fc, _va, pa, _cc, f_act, _me, _se, _ra, _ou = W
    ns = smax.shape[0]
    if ns == 0:
        return
    nr = buf[0:6]
    nr[0], nr[1], nr[2] = pa[0], pa[1], pa[2]
    nr[3], nr[4], nr[5] = x[9], x[10], x[11]
    tx = 0.0
    for i in range(T.shape[1]):
        tx += T[0, i] * f_act[i]
    delta = tau_tab[0, 7 : 7 + ns]
    steer_surfaces_compiled(
        tau_d, nr, tx, t_dof, t_coef, t_kind, t_idx, scal, sfin[0], sfin[1], smax, srate, stc, dt, delta, buf[8:]
    )


@njit_noalloc
def _integrate(t, dt, x, c, T, decay, V, W):  # noqa: ANN001, ANN202
    """One RK4 step of the vehicle with W's thrust f_act and deflections held, then the rotor
    lag; False when the state became non-finite."""
    ctab, Minv, Mc, DL, DQ, scal, t_dof, t_coef, t_kind, t_idx, _smax, _srate, _stc, _sfin = V
    VP = (Minv, Mc, DL, DQ, scal, t_dof, t_coef, t_kind, t_idx)  # the packed vehicle of deriv
    tau_tab, buf, k1v, k2v, k3v, k4v, tmp, _td, _fc, _va, _pa, c_cmd, f_act, _me, _se, _ra, _ou = W
    m = T.shape[1]
    for jd in range(6):
        s_ = 0.0
        for i in range(m):
            s_ += T[jd, i] * f_act[i]
        tau_tab[0, 1 + jd] = s_
    # the one RK4 step of the vehicle (simulate.compiled.deriv_rk4_step, core.integrate's laws)
    finite = deriv_rk4_step(
        t,
        x,
        dt,
        False,
        tau_tab,
        ctab,
        VP,
        buf,
        k1v,
        k2v,
        k3v,
        k4v,
        tmp,
        False,
    )
    for i in range(m):
        c[i] = c_cmd[i] + (c[i] - c_cmd[i]) * decay[i]
    return finite


@njit
def _loop(
    k0, k1, n_steps, dt, every, stop_when_done, G, A, H, ctl, ctl_angle, vc, V, x, c, fstate, istate, arrivals, R
):  # noqa: ANN001, ANN201, E501
    """Steps k0 … k1−1 of one run, recording every ``every``-th step into R (time, η, ν,
    references, τ_d, command demand, command, thrust demand, thrust, limited, leg); returns
    (status, k): _RUNNING, _DONE at step k, or _DIVERGED at k."""
    r_time, r_eta, r_nu, r_ref, r_tau, r_cmd_d, r_cmd, r_f_d, r_f, r_lim, r_leg, r_def = R
    T = A[4]
    decay = H[6]
    m = T.shape[1]
    n_legs = G[1].shape[0] - 1
    ns = V[10].shape[0]
    W = _work(m, ns, H[14][0])
    tau_tab = W[0]
    # the deflections persist between chunks in fstate[11:] (the servo's state)
    for i in range(ns):
        tau_tab[0, 7 + i] = fstate[11 + i]
    status, k_last = _RUNNING, k1 - 1
    tau_d, f_cmd, c_cmd, f_act = W[7], W[8], W[11], W[12]
    for k in range(k0, k1):
        t = k * dt
        kk, limited, ref_speed, ref_depth, ref_heading = _control(
            k, dt, G, A, ctl, ctl_angle, x, fstate, istate, arrivals, W
        )
        if limited:
            _allocate_limited(tau_d, A, f_cmd)
        sat = _thrusters(vc, x, c, A, H, W, limited)
        _steer(dt, x, T, V, W)
        # ---------------------------------------------------------------- record
        if k % every == 0:
            j = istate[1]
            r_time[j] = t
            for i in range(6):
                r_eta[j, i] = x[i]
                r_nu[j, i] = x[6 + i]
                r_tau[j, i] = tau_d[i]
            r_ref[j, 0], r_ref[j, 1], r_ref[j, 2] = ref_speed, ref_depth, ref_heading
            for i in range(m):
                r_cmd_d[j, i] = c_cmd[i]
                r_cmd[j, i] = c[i]
                r_f_d[j, i] = f_cmd[i]
                r_f[j, i] = f_act[i]
            for i in range(ns):
                r_def[j, i] = tau_tab[0, 7 + i]
            r_lim[j] = sat or istate[2] != 0
            r_leg[j] = kk
            istate[2] = 0
            istate[1] = j + 1
        elif sat:
            istate[2] = 1
        if k == n_steps or (stop_when_done and kk > n_legs):
            status, k_last = _DONE, k
            break
        if not _integrate(t, dt, x, c, T, decay, V, W):
            status, k_last = _DIVERGED, k
            break
    for i in range(ns):
        fstate[11 + i] = tau_tab[0, 7 + i]
    return status, k_last


# ============================================================================ the fleet
# per-member metric accumulators (acc columns), over the recorded steps (every ``every``-th):
# 0 recorded, 1 following the path, 2 Σd², 3 max d, 4 Σ depth error², 5 Σ heading error²
# (while following), 6–9 the same over all recorded steps (used when none follows),
# 10 Σ|f|, 11 Σ actuator-disk power, 12 limited count, 13 last recorded time
N_ACC = 14


@njit
def _fleet_member(
    n_steps, dt, every, stop_when_done, path_every, G, A, H, ctl, ctl_angle, vc, V, x, edenom, acc, arrivals, p_eta
):  # noqa: ANN001, ANN201, E501
    """Fly one member from x (12) for steps 0 … n_steps with the shared kernel, accumulating
    its metrics in acc and every ``path_every``-th η in p_eta (path_every 0: none); returns
    (status, k) as _loop."""
    T = A[4]
    decay = H[6]
    m = T.shape[1]
    pts, legs = G[0], G[1]
    n_legs = legs.shape[0] - 1
    W = _work(m, V[10].shape[0], H[14][0])
    f_act = W[12]
    c = np.zeros(m)
    fstate = np.zeros(11)
    istate = np.zeros(8, dtype=np.int64)
    # Path.initial_state: the first leg; its course, or the vehicle's heading on a vertical leg
    istate[0] = 1
    fstate[0] = legs[1, 12] if legs[1, 13] != 0.0 else x[5]
    limited_any = False
    for k in range(n_steps + 1):
        t = k * dt
        kk, limited, _rs, ref_depth, ref_heading = _control(k, dt, G, A, ctl, ctl_angle, x, fstate, istate, arrivals, W)
        if limited:
            _allocate_limited(W[7], A, W[8])
        sat = _thrusters(vc, x, c, A, H, W, limited)
        _steer(dt, x, T, V, W)
        if path_every > 0 and k % path_every == 0:
            jp = k // path_every
            for i in range(6):
                p_eta[jp, i] = x[i]
        if k % every == 0:
            d = _path_distance(x[0], x[1], x[2], pts)
            ze = x[2] - ref_depth
            pe = _wrap(x[5] - ref_heading)
            if kk <= n_legs:
                acc[1] += 1.0
                acc[2] += d * d
                acc[3] = max(acc[3], d)
                acc[4] += ze * ze
                acc[5] += pe * pe
            acc[0] += 1.0
            acc[6] += d * d
            acc[7] = max(acc[7], d)
            acc[8] += ze * ze
            acc[9] += pe * pe
            for i in range(m):
                af = abs(f_act[i])
                acc[10] += af
                acc[11] += af**1.5 / edenom[i]
            if sat or limited_any:
                acc[12] += 1.0
            acc[13] = t
            limited_any = False
        elif sat:
            limited_any = True
        if k == n_steps or (stop_when_done and kk > n_legs):
            return _DONE, k
        if not _integrate(t, dt, x, c, T, decay, V, W):
            return _DIVERGED, k
    return _DONE, n_steps


@njit
def _fcopy(a):  # noqa: ANN001, ANN202
    """A Fortran-ordered copy of a 2-D Fortran-ordered array."""
    out = np.empty((a.shape[1], a.shape[0])).T
    out[:, :] = a
    return out


@njit
def _own_g(G):  # noqa: ANN001, ANN202
    return (
        G[0].copy(),
        G[1].copy(),
        G[2].copy(),
    )


@njit
def _own_a(A):  # noqa: ANN001, ANN202
    return (
        A[0].copy(),
        A[1].copy(),
        A[2].copy(),
        A[3].copy(),
        _fcopy(A[4]),
        A[5].copy(),
        A[6].copy(),
        A[7].copy(),
        _fcopy(A[8]),
        _fcopy(A[9]),
        A[10].copy(),
        A[11].copy(),
    )


@njit
def _own_h(H):  # noqa: ANN001, ANN202
    return (
        H[0].copy(),
        H[1].copy(),
        H[2].copy(),
        H[3].copy(),
        H[4].copy(),
        H[5].copy(),
        H[6].copy(),
        H[7].copy(),
        H[8].copy(),
        H[9].copy(),
        H[10].copy(),
        H[11].copy(),
        H[12].copy(),
        H[13].copy(),
        H[14].copy(),
    )


@njit(parallel=True)
def _fleet(
    n_steps,
    dt,
    every,
    stop_when_done,
    path_every,
    G,
    A,
    H,
    ctl_angle,
    ctl_all,
    vc_all,
    V_all,
    x_all,
    edenom,
    acc,
    arrivals,
    p_eta,
    status,
    k_end,
):  # noqa: ANN001, ANN201, E501
    """_fleet_member for every member i (numba.prange): gains ctl_all[i], current vc_all[i],
    vehicle V_all[·][i], start x_all[i]; status and the last step in status[i], k_end[i]."""
    ctab_a, Minv_a, Mc_a, DL_a, DQ_a, scal_a, t_dof, t_coef_a, t_kind, t_idx, smax_a, srate_a, stc_a, sfin_a = V_all
    for i in numba.prange(x_all.shape[0]):
        # Every member flies on its own copies of the arrays it reads (and writes its own
        # buffers, copied out at the end): arrays shared between threads would share their
        # reference counts, which every kernel call updates atomically.
        V = (
            ctab_a[i].copy(),
            Minv_a[i].copy(),
            Mc_a[i].copy(),
            DL_a[i].copy(),
            DQ_a[i].copy(),
            scal_a[i].copy(),
            t_dof.copy(),
            t_coef_a[i].copy(),
            t_kind.copy(),
            t_idx.copy(),
            smax_a[i].copy(),
            srate_a[i].copy(),
            stc_a[i].copy(),
            sfin_a[i].copy(),
        )
        acc_i = acc[i].copy()
        arr_i = arrivals[i].copy()
        p_i = p_eta[i].copy()
        st, k = _fleet_member(
            n_steps,
            dt,
            every,
            stop_when_done,
            path_every,
            _own_g(G),
            _own_a(A),
            _own_h(H),
            ctl_all[i].copy(),
            ctl_angle.copy(),
            vc_all[i].copy(),
            V,
            x_all[i].copy(),
            edenom.copy(),
            acc_i,
            arr_i,
            p_i,
        )
        acc[i] = acc_i
        arrivals[i] = arr_i
        p_eta[i] = p_i
        status[i] = st
        k_end[i] = k


# ============================================================================ packing
def unsupported_reason(thrusters: ThrusterSet, autopilot: Autopilot) -> str | None:
    """Why the compiled loop cannot fly this setup (None: it can)."""
    for name in ("speed", "depth", "heading", "roll", "pitch"):
        ctl = getattr(autopilot, name)
        if ctl is not None and type(ctl) not in (PID, SPlane):
            return f"the {name} loop is a {type(ctl).__name__} (the compiled loop knows PID and SPlane)"
    for th, cv in zip(thrusters.thrusters, thrusters.curves):
        if type(cv) not in (IdealCurve, TableCurve, PropellerCurve):
            return f"thruster '{th.name}' has a {type(cv).__name__} curve (compiled: ideal, table, propeller)"
    return None


def _pack_autopilot(autopilot: Autopilot) -> tuple[np.ndarray, np.ndarray]:
    """ctl rows: the five loops [kind, gains…], then [depth-to-pitch gain rad/m (0: off), max
    pitch rad]."""
    ctl = np.zeros((6, 6))
    if autopilot.depth_pitch is not None:
        ctl[5, 0], ctl[5, 1] = autopilot.depth_pitch
    ang = np.zeros(5, dtype=np.bool_)
    for i, name in enumerate(("speed", "depth", "heading", "roll", "pitch")):
        c = getattr(autopilot, name)
        if c is None:
            continue
        ang[i] = bool(c.angle)
        if isinstance(c, PID):
            ctl[i] = (1.0, c.kp, c.ki, c.kd, c.output_min, c.output_max)
        else:
            ctl[i] = (2.0, c.k1, c.k2, c.scale, 0.0, 0.0)
    return ctl, ang


def _pack_path(path: Path) -> tuple[np.ndarray, ...]:
    """G: the waypoints, the per-leg table of :func:`hydrokit.model.guidance.los_guidance` and
    [acceptance radius, lookahead] (m)."""
    gpar = np.array([path.acceptance_radius, path.lookahead])
    table = np.ascontiguousarray(path.leg_table, dtype=np.float64)  # type: ignore[attr-defined]
    return np.ascontiguousarray(path.points, dtype=np.float64), table, gpar


def _pack_thrusters(thrusters: ThrusterSet) -> tuple[np.ndarray, ...]:
    m = len(thrusters)
    kind = np.zeros(m, dtype=np.int64)
    n_tab = max([len(cv.commands) for cv in thrusters.curves if isinstance(cv, TableCurve)] or [1])
    n_poly = max(
        [max(len(cv.kt_forward), len(cv.kt_reverse or ())) for cv in thrusters.curves if isinstance(cv, PropellerCurve)]
        or [1]
    )
    tab_c = np.zeros((m, n_tab))
    tab_f = np.zeros((m, n_tab))
    tab_n = np.ones(m, dtype=np.int64)
    prop = np.zeros((m, 10))
    kf = np.zeros((m, n_poly))
    kr = np.zeros((m, n_poly))
    for i, cv in enumerate(thrusters.curves):
        if isinstance(cv, TableCurve):
            kind[i] = 1
            nt = len(cv.commands)
            tab_c[i, :nt], tab_f[i, :nt], tab_n[i] = cv.commands, cv.thrusts, nt
        elif isinstance(cv, PropellerCurve):
            kind[i] = 2
            D, D4, rho, jlo, jhi, kfw, krv, lf, lr, n_max, den_f, den_r = cv._fast  # type: ignore[attr-defined]
            prop[i] = (D, D4, rho, jlo, jhi, lf, lr, n_max, den_f, den_r)
            # leading zeros keep Horner's value bit for bit (see thrusters._pad_cubic)
            kf[i, n_poly - len(cv.kt_forward) :] = cv.kt_forward
            kr[i, n_poly - len(cv.kt_reverse) :] = cv.kt_reverse  # type: ignore[arg-type]
    return kind, tab_c, tab_f, tab_n, prop, kf, kr


def input_columns(vehicle: Any, thrusters: ThrusterSet) -> np.ndarray:
    """[the input table's first thrust column]: 7 + the vehicle's surfaces when its input vector
    holds ``thrusters`` (its own, at most MAX_THRUSTERS) and something reads them (``T()``/``n()``
    factors, a race rudder: :func:`hydrokit.model.dynamics.reads_thrust`): each thrust and
    rotation rate then reach them, as on every other path (issue #56); else [-1] (nothing reads
    them: the columns would only cost interpolation)."""
    from hydrokit.model.dynamics import reads_thrust
    from hydrokit.model.terms import MAX_THRUSTERS

    own = thrusters is getattr(vehicle, "thrusters", None) and len(thrusters) <= MAX_THRUSTERS
    return np.array([7 + len(vehicle.surfaces) if own and reads_thrust(vehicle) else -1], dtype=np.int64)


def _pack_vehicle(vehicle: Any, vc: np.ndarray) -> tuple[np.ndarray, ...]:
    """V: the vehicle group of the kernel (current table and the packed model)."""
    from hydrokit.model.dynamics import current_table, pack, scal_fins

    p = pack(vehicle)
    ctab = np.ascontiguousarray(current_table(vc), dtype=np.float64)
    s = vehicle.surfaces
    sfin = np.array(scal_fins(p.scal), dtype=np.int64)
    return (
        *(ctab, p.Minv, p.Mc, p.DL, p.DQ, p.scal, p.t_dof, p.t_coef, p.t_kind, p.t_idx),
        *(s.max_deflection, s.rate_limit, s.time_constant, sfin),
    )


def _check_current(current_ned: ArrayLike | None) -> np.ndarray:
    vc = np.zeros(3) if current_ned is None else np.asarray(current_ned, dtype=float).reshape(-1)
    if vc.shape != (3,):
        raise InputError(f"current of shape {vc.shape}: the compiled loop takes a constant (3,) NED current, m/s")
    return np.ascontiguousarray(vc, dtype=np.float64)


def _check_steps(duration: float, dt: float, output_every: int) -> int:
    if not (math.isfinite(duration) and duration > 0 and math.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"duration = {duration}, dt = {dt}: expected 0 < dt ≤ duration (s)")
    if output_every < 1:
        raise InputError(f"output_every = {output_every}: expected a whole number ≥ 1")
    return int(math.floor(duration / dt + 1e-9))


def _pack_common(
    thrusters: ThrusterSet, path: Path, dt: float, weights: ArrayLike | None
) -> tuple[tuple[Any, ...], tuple[Any, ...], tuple[Any, ...]]:
    """G, A, H: the guidance, allocation and thruster groups of the kernel (shared by a fleet)."""
    m = len(thrusters)
    T = thrusters.configuration_matrix()
    # T (and Q T) in the layout numpy has them (Fortran order): the same BLAS kernels, the
    # same rounding as the Python loop
    Tf = np.asfortranarray(T, dtype=np.float64)
    allocator = Allocator(T, thrusters.f_min, thrusters.f_max, weights)
    lo = np.ascontiguousarray(allocator.f_min.reshape(-1))
    hi = np.ascontiguousarray(allocator.f_max.reshape(-1))
    if np.any(lo > hi):
        raise InputError(f"thrust limits: expected {m} pairs with min ≤ max, got {lo} and {hi}")
    solver = _ConstrainedSolver(T, lo, hi, allocator.Q)
    lo_s, hi_s = solver.bounds
    apar = np.array([solver.scale, solver.thrust_scale, solver.q_max])
    tc = thrusters.time_constants
    with np.errstate(divide="ignore"):
        decay = np.where(tc > 0, np.exp(-dt / np.where(tc > 0, tc, 1.0)), 0.0)
        mean_w = np.where(tc > 0, tc / dt * (1.0 - decay), 0.0)
    kind, tab_c, tab_f, tab_n, prop, kf, kr = _pack_thrusters(thrusters)
    f64 = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
    G = _pack_path(path)
    A = (
        f64(allocator.P),
        lo,
        hi,
        np.ascontiguousarray(allocator.unactuated, dtype=np.bool_),
        Tf,
        f64(lo_s),
        f64(hi_s),
        f64(solver.Q),
        np.asfortranarray(solver.QT, dtype=np.float64),
        np.asfortranarray(solver.A, dtype=np.float64),  # as the Python allocator packs them: one specialization
        apar,
        f64(solver.polish_tol),
    )
    H = (
        kind,
        f64(thrusters.directions),
        f64(thrusters._moment_arms),
        f64(thrusters._wake_factor),
        f64(thrusters.command_min),
        f64(thrusters.command_max),
        f64(decay),
        f64(mean_w),
        tab_c,
        tab_f,
        tab_n,
        prop,
        kf,
        kr,
    )
    return G, A, H


def run_closed_loop_compiled(
    vehicle: Any,
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
) -> ClosedLoopResult:
    """:func:`hydrokit.simulate.closed_loop.run_closed_loop`, compiled.

    The arguments are those of the Python loop, except that the vehicle enters as a
    :class:`hydrokit.model.vehicle.Vehicle` (its full 6-DOF model with Euler angles, the
    same as ``make_dynamics(vehicle, current_ned)``) instead of a ``dynamics`` callable;
    ``current_ned`` (3 floats, m/s NED, constant) acts on both the vehicle and the
    thrusters' advance speed.

    Raises
    ------
    InputError
        Bad duration/step/decimation, or a controller or thrust curve the compiled loop does
        not know (see :func:`unsupported_reason`; use the Python loop for those).
    SimulationError
        The state became non-finite.
    """
    n_steps = _check_steps(duration, dt, output_every)
    why = unsupported_reason(thrusters, autopilot)
    if why is not None:
        raise InputError(f"compiled closed loop: {why}; use loop='python'")
    vc = _check_current(current_ned)
    m = len(thrusters)
    G, A, H = _pack_common(thrusters, path, dt, weights)
    H = (*H, input_columns(vehicle, thrusters))
    ctl, ctl_angle = _pack_autopilot(autopilot)
    V = _pack_vehicle(vehicle, vc)

    rec = new_record(n_steps, output_every, m, len(vehicle.surfaces))
    x = np.concatenate([np.asarray(eta0, float).reshape(6), np.asarray(nu0, float).reshape(6)])
    c = np.zeros(m)
    fstate = np.zeros(11 + len(vehicle.surfaces))  # [heading, integral×5, previous×5, δ…]
    gs = path.initial_state(heading=float(x[5]))
    fstate[0] = gs.heading
    istate = np.zeros(8, dtype=np.int64)
    istate[0] = gs.leg
    arrivals = np.full(path.n_legs, np.nan)
    R = tuple(rec[name] for name in RECORD_FIELDS)
    args = (G, A, H, ctl, ctl_angle, vc, V, x, c, fstate, istate, arrivals, R)
    chunk = max(1, (n_steps + 1) // 100) if progress is not None else n_steps + 1
    k0 = 0
    t = 0.0
    while k0 <= n_steps:
        k1 = min(k0 + chunk, n_steps + 1)
        status, k = _loop(k0, k1, n_steps, float(dt), int(output_every), bool(stop_when_done), *args)
        t = k * dt
        if status == _DIVERGED:
            raise SimulationError(f"the state became non-finite at t = {t + dt:.6g} s")
        if status == _DONE:
            break
        if progress is not None:
            progress(t)
        k0 = k1
    if progress is not None:
        progress(t)
    waypoint_times: list[float | None] = [None if math.isnan(a) else float(a) for a in arrivals]
    return record_result(rec, int(istate[1]), waypoint_times, thrusters, dt, output_every, path)
