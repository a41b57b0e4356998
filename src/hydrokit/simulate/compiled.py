"""Compiled (numba) fixed-step RK4 of the vehicle model, single and batch.

The same equations as :func:`hydrokit.model.dynamics.vehicle_dynamics`, written with scalar
loops and preallocated buffers so that one RK4 step costs a few hundred flops and no
allocation. Inputs: a force table (rows [t, X, Y, Z, K, M, N, δ_1 … δ_n], linear
interpolation, held beyond its ends; one row = constant; the control surfaces' deflections,
rad, may follow the forces) and a current table (rows [t, v_N, v_E, v_D]).
Outputs are preallocated and the run stops at the first non-finite state (its step index is
returned), so cost grows linearly with the duration.

The laws written on plain floats are compiled here from their one implementation (the
pattern new laws follow, issues #45 and #50): the derivative terms
(:func:`hydrokit.model.terms.add_term_forces`), the point drag elements
(:func:`hydrokit.core.drag.add_drag_wrench`), the physical fins
(:func:`hydrokit.model.surfaces.fin_wrench`), the wind (:func:`hydrokit.model.wind.wind_wrench`), the
servo (:func:`hydrokit.model.surfaces.servo_step`), the rotation matrices R(Θ) and R(q)
(:func:`hydrokit.core.kinematics.rotation_zyx_entries`,
:func:`~hydrokit.core.kinematics.quaternion_rotation_entries`) and the RK4 step's arithmetic
(:mod:`hydrokit.core.integrate`, also that of :func:`hydrokit.simulate.integrators.rk4_step`).
The remaining blocks are still compiled *copies* of a numpy source, kept for speed only (a
debt, to move onto the same pattern when touched); the numpy one is the definition, and
tests/model/test_compiled_vs_numpy.py compares each copy with it at random states: T(Θ) and q̇
(:func:`~hydrokit.core.kinematics.euler_rate_matrix`,
:func:`~hydrokit.core.kinematics.quaternion_rate`), C(ν)ν
(:func:`hydrokit.core.coriolis.coriolis_force`) and the right-hand side
(:func:`hydrokit.model.dynamics.vehicle_dynamics`). Change a formula there first.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hydrokit._numba import compile_law, njit, njit_noalloc
from hydrokit.core.drag import add_drag_wrench
from hydrokit.core.integrate import rk4_combine_into, rk4_stage, rk4_stage_into, rk4_update
from hydrokit.core.kinematics import quaternion_rotation_entries, rotation_zyx_entries, rotation_zyx_into
from hydrokit.model.surfaces import FIN_WIDTH, MAX_SURFACES, fin_wrench, servo_step, steer_surfaces
from hydrokit.model.terms import MAX_THRUSTERS, add_term_forces
from hydrokit.model.thrusters import (
    advance_speed_law,
    propeller_speed,
    propeller_thrust,
    rotor_lag,
    table_interp,
    thruster_inputs,
)
from hydrokit.model.wind import wind_coefficients, wind_wrench

#: scratch length of :func:`deriv` (40 numbers, then the force table's values and slopes:
#: 6 forces and an input vector of up to MAX_SURFACES deflections, MAX_THRUSTERS thrusts and as
#: many rotation rates each)
BUF_SIZE = 40 + 2 * (6 + MAX_SURFACES + 2 * MAX_THRUSTERS)


# The laws written once in model/ and core/ (plain floats and loops), compiled here: not copies.
_terms = compile_law(add_term_forces)
_drag = compile_law(add_drag_wrench)
_fin = compile_law(fin_wrench)
servo_step_compiled = compile_law(servo_step)
_wind = compile_law(wind_wrench, wind_coefficients=compile_law(wind_coefficients))
steer_surfaces_compiled = compile_law(
    steer_surfaces, add_term_forces=_terms, fin_wrench=_fin, servo_step=servo_step_compiled
)
# the thruster laws (model/thrusters.py), for the compiled closed loop and manoeuvre loop
propeller_thrust_compiled = compile_law(propeller_thrust)
propeller_speed_compiled = compile_law(propeller_speed, propeller_thrust=propeller_thrust_compiled)
rotor_lag_compiled = compile_law(rotor_lag)
advance_speed_compiled = compile_law(advance_speed_law)
#: the thrusters' part of the input vector (thrusts, rates, τ) at a rotor state and ν_r
thruster_inputs_compiled = compile_law(
    thruster_inputs, advance_speed_law=advance_speed_compiled, propeller_thrust=propeller_thrust_compiled
)
#: a table thrust curve (and its inverse): np.interp for one number, on the first n points
table_interp_compiled = compile_law(table_interp)
# the rotation matrices (core/kinematics.py) and the RK4 step's arithmetic (core/integrate.py),
# for every compiled integrator and right-hand side: deriv, rk4_run, the transport kernels, the
# closed loop and the manoeuvre loop
rotation_zyx_entries_compiled = compile_law(rotation_zyx_entries)
rotation_zyx_into_compiled = compile_law(rotation_zyx_into, rotation_zyx_entries=rotation_zyx_entries_compiled)
quaternion_rotation_compiled = compile_law(quaternion_rotation_entries)
#: ``out[i] = x[i] + h k[i]`` (a stage's state; h = dt/2 or dt)
rk4_stage_compiled = compile_law(rk4_stage_into, rk4_stage=compile_law(rk4_stage))
#: ``x[i] += dt/6 (k1[i] + 2 k2[i] + 2 k3[i] + k4[i])`` in place; False when not all finite
rk4_combine_compiled = compile_law(rk4_combine_into, rk4_update=compile_law(rk4_update))


@njit(inline="always")
def _interp(tab, t, val, slope):  # noqa: ANN001, ANN202
    n = tab.shape[0]
    m = tab.shape[1] - 1
    if n == 1 or t <= tab[0, 0]:
        for j in range(m):
            val[j] = tab[0, j + 1]
            slope[j] = 0.0
        return
    if t >= tab[n - 1, 0]:
        for j in range(m):
            val[j] = tab[n - 1, j + 1]
            slope[j] = 0.0
        return
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if tab[mid, 0] <= t:
            lo = mid
        else:
            hi = mid
    h = tab[hi, 0] - tab[lo, 0]
    for j in range(m):
        s = (tab[hi, j + 1] - tab[lo, j + 1]) / h
        slope[j] = s
        val[j] = tab[lo, j + 1] + s * (t - tab[lo, 0])


@njit_noalloc
def deriv(t, x, quat, tau_tab, cur_tab, V, buf, out):  # noqa: ANN001, ANN201
    """ẋ into ``out``; ``buf`` is scratch of length ≥ BUF_SIZE; ``V`` the vehicle packed once
    (:attr:`hydrokit.model.dynamics.Packed.V`: Minv, Mc, DL, DQ, scal, t_dof, t_coef, t_kind,
    t_idx — every path passes this one tuple, issue #56).

    ``tau_tab`` rows are [t, X, Y, Z, K, M, N, δ_1 … δ_n, T_1 … T_m, n_1 … n_m] (s, N, N·m, rad,
    N, rev/s): the input vector of the vehicle (its control surfaces' deflections, then its
    thrusters' thrusts and rotation rates, :func:`hydrokit.model.terms.input_layout`) may follow
    the six forces (missing ones are 0).
    """
    Minv, Mc, DL, DQ, scal, t_dof, t_coef, t_kind, t_idx = V
    if quat:
        q0, q1, q2, q3 = x[3], x[4], x[5], x[6]
        nq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        R00, R01, R02, R10, R11, R12, R20, R21, R22 = quaternion_rotation_compiled(q0 / nq, q1 / nq, q2 / nq, q3 / nq)
        o = 7
    else:
        cf, sf = math.cos(x[3]), math.sin(x[3])
        ct, st = math.cos(x[4]), math.sin(x[4])
        cp, sp = math.cos(x[5]), math.sin(x[5])
        R00, R01, R02, R10, R11, R12, R20, R21, R22 = rotation_zyx_entries_compiled(cf, sf, ct, st, cp, sp)
        o = 6
    u, v, w, p, q, r = x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5]
    m_tab = tau_tab.shape[1] - 1
    tval = buf[40 : 40 + m_tab]
    tslope = buf[40 + m_tab : 40 + 2 * m_tab]
    _interp(tau_tab, t, tval, tslope)
    tau = tval[0:6]
    delta = tval[6:m_tab]
    n_delta = m_tab - 6
    # the current (and the wind's velocity, when the table has it: rows [t, vN, vE, vD, wN, wE])
    m_env = cur_tab.shape[1] - 1
    vc = buf[0:m_env]
    vcd = buf[6 : 6 + m_env]
    _interp(cur_tab, t, vc, vcd)
    # current in body axes: Rᵀ v_c and Rᵀ v̇_c
    cb0 = R00 * vc[0] + R10 * vc[1] + R20 * vc[2]
    cb1 = R01 * vc[0] + R11 * vc[1] + R21 * vc[2]
    cb2 = R02 * vc[0] + R12 * vc[1] + R22 * vc[2]
    cd0 = R00 * vcd[0] + R10 * vcd[1] + R20 * vcd[2]
    cd1 = R01 * vcd[0] + R11 * vcd[1] + R21 * vcd[2]
    cd2 = R02 * vcd[0] + R12 * vcd[1] + R22 * vcd[2]
    nr = buf[18:24]
    nr[0] = u - cb0
    nr[1] = v - cb1
    nr[2] = w - cb2
    nr[3] = p
    nr[4] = q
    nr[5] = r
    mv = buf[24:30]
    for i in range(6):
        s = 0.0
        for j in range(6):
            s += Mc[i, j] * nr[j]
        mv[i] = s
    a0_, a1_, a2_, b0, b1, b2 = mv[0], mv[1], mv[2], mv[3], mv[4], mv[5]
    f = buf[30:36]
    # −C(ν_r) ν_r = −[ω × a; v × a + ω × b]
    f[0] = -(q * a2_ - r * a1_)
    f[1] = -(r * a0_ - p * a2_)
    f[2] = -(p * a1_ - q * a0_)
    f[3] = -(nr[1] * a2_ - nr[2] * a1_ + q * b2 - r * b1)
    f[4] = -(nr[2] * a0_ - nr[0] * a2_ + r * b0 - p * b2)
    f[5] = -(nr[0] * a1_ - nr[1] * a0_ + p * b1 - q * b0)
    for i in range(6):
        s = DQ[i] * abs(nr[i]) * nr[i]
        for j in range(6):
            s += DL[i, j] * nr[j]
        f[i] += tau[i] - s
    # general derivative terms (model.terms.add_term_forces, compiled)
    _terms(t_dof, t_coef, t_kind, t_idx, nr, delta, n_delta, f)
    # restoring: −g(η); down = Rᵀ e_z = third row of R
    W, B = scal[0], scal[1]
    d0, d1, d2 = R20, R21, R22
    net = W - B
    f[0] += net * d0
    f[1] += net * d1
    f[2] += net * d2
    # moments r_g × (W d) + r_b × (−B d)
    g0, g1, g2 = scal[2], scal[3], scal[4]
    h0, h1, h2 = scal[5], scal[6], scal[7]
    f[3] += W * (g1 * d2 - g2 * d1) - B * (h1 * d2 - h2 * d1)
    f[4] += W * (g2 * d0 - g0 * d2) - B * (h2 * d0 - h0 * d2)
    f[5] += W * (g0 * d1 - g1 * d0) - B * (h0 * d1 - h1 * d0)
    # point drag elements (core.drag.add_drag_wrench, compiled): scal[8] = n, then rows of 9
    n_el = int(scal[8])
    _drag(scal, 9, n_el, nr, f)
    # physical fins (model.surfaces.fin_wrench, compiled): after the mask (6) and their count
    om = 9 + 9 * n_el
    n_fin = int(scal[om + 6])
    for e in range(n_fin):
        _fin(scal, om + 7 + FIN_WIDTH * e, nr, tau[0], delta, n_delta, f)
    # wind (model.wind.wind_wrench, compiled) after the fins, at ν minus the wind in body axes
    if m_env >= 5:
        uw = R00 * vc[3] + R10 * vc[4]
        vw = R01 * vc[3] + R11 * vc[4]
        _wind(scal, om + 7 + FIN_WIDTH * n_fin, u - uw, v - vw, f)
    # ν̇ = M⁻¹ f − [ω × Rᵀv_c − Rᵀv̇_c; 0], zero for a dropped DOF
    for i in range(6):
        s = 0.0
        for j in range(6):
            s += Minv[i, j] * f[j]
        out[o + i] = s
    out[o] += -(q * cb2 - r * cb1) + cd0
    out[o + 1] += -(r * cb0 - p * cb2) + cd1
    out[o + 2] += -(p * cb1 - q * cb0) + cd2
    for i in range(6):
        out[o + i] *= scal[om + i]
    # kinematics
    out[0] = R00 * u + R01 * v + R02 * w
    out[1] = R10 * u + R11 * v + R12 * w
    out[2] = R20 * u + R21 * v + R22 * w
    if quat:
        q0, q1, q2, q3 = x[3], x[4], x[5], x[6]
        corr = 0.5 * (1.0 - (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3))
        out[3] = 0.5 * (-q1 * p - q2 * q - q3 * r) + corr * q0
        out[4] = 0.5 * (q0 * p + q2 * r - q3 * q) + corr * q1
        out[5] = 0.5 * (q0 * q + q3 * p - q1 * r) + corr * q2
        out[6] = 0.5 * (q0 * r + q1 * q - q2 * p) + corr * q3
    else:
        tt = st / ct
        out[2] *= scal[om + 2]
        out[3] = (p + (sf * q + cf * r) * tt) * scal[om + 3]
        out[4] = (cf * q - sf * r) * scal[om + 4]
        out[5] = (sf * q + cf * r) / ct * scal[om + 5]


@njit_noalloc  # not inline="always": inlined into transport._rigid it ran 2× slower (measured)
def deriv_rk4_step(
    t,
    x,
    dt,
    quat,
    tau_tab,
    cur_tab,
    V,
    buf,
    k1,
    k2,
    k3,
    k4,
    tmp,
    k1_ready,
):  # noqa: ANN001, ANN201
    """x advanced in place by one RK4 step of ``dt`` (s) of :func:`deriv` with the inputs of
    ``tau_tab`` held: the stages and the update of :mod:`hydrokit.core.integrate` (compiled),
    the one order of operations of every RK4 of the package. k1 = ẋ(t, x) is evaluated into
    ``k1`` unless ``k1_ready`` (the caller has it already, e.g. to record loads); k1…k4 and tmp
    are scratch of the state's length. Returns False when the new state is not finite."""
    if not k1_ready:
        deriv(t, x, quat, tau_tab, cur_tab, V, buf, k1)
    rk4_stage_compiled(x, k1, 0.5 * dt, tmp)
    deriv(t + 0.5 * dt, tmp, quat, tau_tab, cur_tab, V, buf, k2)
    rk4_stage_compiled(x, k2, 0.5 * dt, tmp)
    deriv(t + 0.5 * dt, tmp, quat, tau_tab, cur_tab, V, buf, k3)
    rk4_stage_compiled(x, k3, dt, tmp)
    deriv(t + dt, tmp, quat, tau_tab, cur_tab, V, buf, k4)
    return rk4_combine_compiled(x, k1, k2, k3, k4, dt)


def no_drive() -> tuple[np.ndarray, ...]:
    """The drive argument of :func:`rk4_run` for a table whose thrusts are given (no propeller
    evaluated at the simulated state)."""
    e2 = np.zeros((0, 3))
    return (
        np.zeros(3, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0), e2, e2, np.zeros((6, 0)),
        np.zeros((0, 6)), np.zeros((0, 1)), np.zeros((0, 1)), np.zeros((0, 4)),
    )  # fmt: skip


@njit_noalloc
def _drive_row(t, x, quat, tau_tab, cur_tab, D, row, slope):  # noqa: ANN001, ANN202
    """The input row at ``t`` (``row[0, 1:]``, ``tau_tab`` interpolated) with each driven
    propeller's thrust evaluated at the state ``x`` (the advance speed of the simulated velocity
    through the water, issue #56) instead of the table's: the table holds each driven propeller's
    rotor state (value index ``cols[0] + j``), its thrust at the measured advance speed (``cols[1]
    + idx[j]``) and rate (``cols[2] + idx[j]``); τ trades that thrust for the new one through the
    configuration columns ``Tv`` (thrust deduction included; the table was built with the same
    thrusters). The laws: :func:`hydrokit.model.thrusters.advance_speed_law` and
    ``propeller_thrust``, compiled."""
    cols, idx, wake, dirs, arms, Tv, prop, kf, kr, lim = D
    val = row[0, 1:]
    _interp(tau_tab, t, val, slope)
    o = 7 if quat else 6
    u, v, w = x[o], x[o + 1], x[o + 2]
    m_env = cur_tab.shape[1] - 1
    if m_env >= 3:
        vc = slope[0:3]  # scratch: the current now (its slope is not needed here)
        cs = slope[3:6]
        _interp(cur_tab, t, vc, cs)
        if vc[0] != 0.0 or vc[1] != 0.0 or vc[2] != 0.0:
            if quat:
                q0, q1, q2, q3 = x[3], x[4], x[5], x[6]
                nq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
                R00, R01, R02, R10, R11, R12, R20, R21, R22 = quaternion_rotation_compiled(
                    q0 / nq, q1 / nq, q2 / nq, q3 / nq
                )
            else:
                R00, R01, R02, R10, R11, R12, R20, R21, R22 = rotation_zyx_entries_compiled(
                    math.cos(x[3]), math.sin(x[3]), math.cos(x[4]), math.sin(x[4]), math.cos(x[5]), math.sin(x[5])
                )
            u -= R00 * vc[0] + R10 * vc[1] + R20 * vc[2]
            v -= R01 * vc[0] + R11 * vc[1] + R21 * vc[2]
            w -= R02 * vc[0] + R12 * vc[1] + R22 * vc[2]
    p, q, r = x[o + 3], x[o + 4], x[o + 5]
    for j in range(idx.shape[0]):
        g = idx[j]
        c = val[cols[0] + j]
        c = lim[j, 0] if c < lim[j, 0] else (lim[j, 1] if c > lim[j, 1] else c)
        va = advance_speed_compiled(
            wake[j], dirs[j, 0], dirs[j, 1], dirs[j, 2], arms[j, 0], arms[j, 1], arms[j, 2], u, v, w, p, q, r
        )
        f = propeller_thrust_compiled(
            c, va, prop[j, 0], prop[j, 1], prop[j, 2], prop[j, 3], kf[j], kr[j], prop[j, 4], prop[j, 5]
        )
        f = lim[j, 2] if f < lim[j, 2] else (lim[j, 3] if f > lim[j, 3] else f)
        f_old = val[cols[1] + g]
        for i in range(6):
            val[i] += Tv[i, j] * (f - f_old)
        val[cols[1] + g] = f
        val[cols[2] + g] = c


@njit
def rk4_run(x0, t0, dt, n_steps, every, quat, tau_tab, cur_tab, V, D, out, held=0.0):  # noqa: ANN001, ANN201
    """Integrate n_steps RK4 steps from x0; store every ``every``-th state in ``out`` (rows).
    ``D``: the propellers whose thrust is evaluated at every stage's state (:func:`_drive_row`;
    :func:`no_drive` for none: the table's inputs as they are). ``held`` (s): each step's first
    stage reads the tables this much after the step's start — a table of held inputs, whose value
    at a jump node t_k is the one held up to it (the last stage of the step ending there reads it)
    and which reaches the new one ``held`` / 2 later (:func:`hydrokit.sysid.model.force_table`),
    gives the step starting at t_k its new value at every stage, as a zero-order hold does; 0 for
    piecewise-linear tables.

    Returns the number of steps taken (< n_steps if the state became non-finite).
    """
    n = x0.shape[0]
    x = x0.copy()
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    k4 = np.empty(n)
    tmp = np.empty(n)
    buf = np.empty(BUF_SIZE)
    for i in range(n):
        out[0, i] = x[i]
    j = 1
    # driven propellers: each stage's inputs at its own state, in ``row`` (else the table itself)
    driven = D[1].shape[0] > 0
    row = np.zeros((1, tau_tab.shape[1]))
    slope = np.empty(max(tau_tab.shape[1] - 1, 6))
    tab = row if driven else tau_tab
    for step in range(n_steps):
        t = t0 + step * dt
        # the stages written out rather than deriv_rk4_step: 1.30 M against 1.10 M steps/s (BlueROV2
        # Heavy, CPU time, best of 15 × 600 s, 2026-11-29): the call of the step kernel costs ~15 %
        if driven:
            _drive_row(t + held, x, quat, tau_tab, cur_tab, D, row, slope)
        deriv(t + held, x, quat, tab, cur_tab, V, buf, k1)
        rk4_stage_compiled(x, k1, 0.5 * dt, tmp)
        if driven:
            _drive_row(t + 0.5 * dt, tmp, quat, tau_tab, cur_tab, D, row, slope)
        deriv(t + 0.5 * dt, tmp, quat, tab, cur_tab, V, buf, k2)
        rk4_stage_compiled(x, k2, 0.5 * dt, tmp)
        if driven:
            _drive_row(t + 0.5 * dt, tmp, quat, tau_tab, cur_tab, D, row, slope)
        deriv(t + 0.5 * dt, tmp, quat, tab, cur_tab, V, buf, k3)
        rk4_stage_compiled(x, k3, dt, tmp)
        if driven:
            _drive_row(t + dt, tmp, quat, tau_tab, cur_tab, D, row, slope)
        deriv(t + dt, tmp, quat, tab, cur_tab, V, buf, k4)
        if not rk4_combine_compiled(x, k1, k2, k3, k4, dt):
            return step
        if (step + 1) % every == 0:
            for i in range(n):
                out[j, i] = x[i]
            j += 1
    return n_steps


def vehicle_member(V_all, k):  # noqa: ANN001, ANN201
    """Vehicle ``k``'s packed tuple from a batch's stacked one (the term structure is shared)."""
    Minv, Mc, DL, DQ, scal, t_dof, t_coef, t_kind, t_idx = V_all
    return (Minv[k], Mc[k], DL[k], DQ[k], scal[k], t_dof, t_coef[k], t_kind, t_idx)


vehicle_member_compiled = njit(vehicle_member)


def drive_member(D_all, k):  # noqa: ANN001, ANN201
    """Vehicle ``k``'s drive from a batch's (its wake factors and configuration columns)."""
    cols, idx, wake, dirs, arms, Tv, prop, kf, kr, lim = D_all
    return (cols, idx, wake[k], dirs, arms, Tv[k], prop, kf, kr, lim)


drive_member_compiled = njit(drive_member)


def no_drive_batch(nv: int) -> tuple[np.ndarray, ...]:
    """The batch drive argument of :func:`rk4_batch` for no driven propeller."""
    d = no_drive()
    return (d[0], d[1], np.zeros((nv, 0)), d[3], d[4], np.zeros((nv, 6, 0)), d[6], d[7], d[8], d[9])


@njit(parallel=True)
def rk4_batch(
    x0,
    dt,
    n_steps,
    every,
    quat,
    tau_tab,
    cur_tab,
    V_all,
    D_all,
    out,
    done,
    held=0.0,
):  # noqa: ANN001, ANN201
    """Many vehicles at once: leading axis of x0, tau_tab, out and of V_all's Minv, Mc, DL, DQ,
    scal and t_coef is the vehicle (:func:`vehicle_member`); ``done`` receives each vehicle's number of steps taken; ``D_all`` the
    driven propellers with each vehicle's wake factors and configuration columns
    (:func:`drive_member`; :func:`no_drive_batch` for none). A ``tau_tab`` of one table (1, k,
    columns) is shared by every vehicle (a run's perturbed vehicles, whose thrusters agree: a copy
    per vehicle costs more than the fit's linear algebra). ``held``: as :func:`rk4_run`'s."""
    nv = x0.shape[0]
    shared = tau_tab.shape[0] == 1
    for k in numba.prange(nv):
        done[k] = rk4_run(
            x0[k],
            0.0,
            dt,
            n_steps,
            every,
            quat,
            tau_tab[0] if shared else tau_tab[k],
            cur_tab,
            vehicle_member_compiled(V_all, k),
            drive_member_compiled(D_all, k),
            out[k],
            held,
        )


def make_dynamics(vehicle, current_ned=None, attitude: str = "euler"):  # noqa: ANN001, ANN201
    """f(t, x, τ, δ=None, thrust=None, rate=None) → ẋ calling the compiled right-hand side (same
    equations as :func:`hydrokit.model.dynamics.vehicle_dynamics`, about 50× faster per call). Used
    by the closed loop and the manoeuvres, where τ (N, N·m), the deflections δ (rad, one per
    control surface, or the whole input vector) and each thruster's thrust (N) and rotation rate
    (rev/s) change every step (:func:`hydrokit.model.dynamics.input_vector`)."""
    from hydrokit.errors import InputError
    from hydrokit.model.dynamics import check_wind, current_table, input_vector, pack

    if attitude == "quaternion" and vehicle.planar:
        raise InputError(f"vehicle {vehicle.name!r} is planar (dofs): expected attitude euler")
    p = pack(vehicle)
    ctab = current_table(current_ned)
    check_wind(vehicle, ctab)
    quat = attitude == "quaternion"
    n = 13 if quat else 12
    ns, m = len(vehicle.surfaces), len(vehicle.thruster_names)
    # the thrusts and rates fit the scratch of deriv up to MAX_THRUSTERS thrusters
    tau_tab = np.zeros((1, 7 + (vehicle.n_inputs if m <= MAX_THRUSTERS else ns)))
    buf = np.empty(BUF_SIZE)
    V = p.V

    def f(
        t: float,
        x: np.ndarray,
        tau: np.ndarray,
        delta: np.ndarray | None = None,
        thrust: np.ndarray | None = None,
        rate: np.ndarray | None = None,
    ) -> np.ndarray:
        tau_tab[0, 1:7] = tau
        if thrust is not None or rate is not None:
            if m > MAX_THRUSTERS:
                raise InputError(f"vehicle {vehicle.name!r} has {m} thrusters: expected at most {MAX_THRUSTERS}")
            delta = input_vector(vehicle, delta, thrust, rate)
        tau_tab[0, 7:] = 0.0
        if delta is not None:
            d = np.asarray(delta, float)
            tau_tab[0, 7 : 7 + d.shape[0]] = d
        out = np.empty(n)
        deriv(float(t), np.asarray(x, dtype=float), quat, tau_tab, ctab, V, buf, out)
        return out

    return f
