"""Cooperative transport (issue #11, REHMAN): an :class:`~hydrokit.model.assembly.Assembly`
flown open loop under constant thruster commands and constant part forces, three ways.

``rigid``
    One body, the composite about the common origin (SPEC §2.3), RK4 of the vehicle model
    (compiled). The load at each joint is the Newton–Euler balance of the subtree beyond it,
    every recorded step: the parent must supply what the subtree's own forces do not,

        w_S = M_S ν̇ − f_S(η, ν) − τ_thrusters,S − τ_forces,S            (about the origin)

    with M_S, f_S = −C_S ν − D_S ν − drag_S − g_S the subtree's own mass matrix and forces
    (its parts' rigid-body and added mass, damping, drag elements, weight and buoyancy) and ν̇
    the assembly's acceleration. The force F = w_S[0:3] and the moment about the joint point j,
    M_j = w_S[3:6] − j × F, are what the manipulator must hold.
``multibody``
    Each part its own 6-DOF body (its own origin, axes parallel to the common axes at rest),
    joints as stiff spring–dampers: the relative displacement of the joint point and the
    relative rotation (rotation vector of R_pᵀ R_c), in the parent's axes, against
    ``joint_stiffness`` and ``joint_damping``. RK4 with as many sub-steps as the joint
    frequencies need. Loads are the spring–damper wrenches, turned into the root's axes;
    separations the joint-point mismatches.
``independent``
    REHMAN's separate bodies: each child subtree of the root with an equal share of the root
    part, flown as its own rigid body. The separation at a joint of the root is the distance
    between the root origin as carried by that group and by the others (mean): how far the
    vehicles pull apart.

Thrust: every thruster's command is held over a step and its thrust evaluated from the
advance speed of its own body at the start of the step (the propeller K_T(J), forward and
reverse, of :mod:`hydrokit.model.thrusters`, compiled in :mod:`hydrokit.simulate.compiled_loop`).
No current. State layout per body as the vehicle model's Euler state (12).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._numba import njit
from hydrokit._result import Result, html_table, jsonable
from hydrokit.errors import InputError
from hydrokit.model.assembly import Assembly, check_model
from hydrokit.model.dynamics import stack_scal
from hydrokit.simulate.compiled import (
    BUF_SIZE,
    deriv,
    deriv_rk4_step,
    rk4_combine_compiled,
    rk4_stage_compiled,
    rotation_zyx_into_compiled,
)
from hydrokit.simulate.compiled import advance_speed_compiled as _advance_speed
from hydrokit.simulate.compiled_loop import _pack_thrusters, _thrust

COLUMNS = ("time", "x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r")
LOAD_COLUMNS = ("time", "joint", "fx", "fy", "fz", "mx", "my", "mz")


# ============================================================================ kernels
@njit
def _thrusts(nu, owner, body, cmd, P, E, TH, out):  # noqa: ANN001, ANN202
    """Thrust (N) of every thruster of ``body`` (−1: all) at body velocity ``nu`` (6)."""
    wake, cmin, cmax, fmin, fmax, kind, tab_c, tab_f, tab_n, prop, kf, kr = TH
    u, v, w, p, q, r = nu[0], nu[1], nu[2], nu[3], nu[4], nu[5]
    for i in range(P.shape[0]):
        if body >= 0 and owner[i] != body:
            continue
        # e · (v + ω × r) = e · v + ω · (r × e): the arm r × e, then the one law
        ax = P[i, 1] * E[i, 2] - P[i, 2] * E[i, 1]
        ay = P[i, 2] * E[i, 0] - P[i, 0] * E[i, 2]
        az = P[i, 0] * E[i, 1] - P[i, 1] * E[i, 0]
        va = _advance_speed(wake[i], E[i, 0], E[i, 1], E[i, 2], ax, ay, az, u, v, w, p, q, r)
        c = min(max(cmd[i], cmin[i]), cmax[i])
        f = _thrust(i, c, va, kind, tab_c, tab_f, tab_n, prop, kf, kr)
        out[i] = min(max(f, fmin[i]), fmax[i])


@njit
def _config(P, E, T):  # noqa: ANN001, ANN202
    for i in range(P.shape[0]):
        T[0, i], T[1, i], T[2, i] = E[i, 0], E[i, 1], E[i, 2]
        T[3, i] = P[i, 1] * E[i, 2] - P[i, 2] * E[i, 1]
        T[4, i] = P[i, 2] * E[i, 0] - P[i, 0] * E[i, 2]
        T[5, i] = P[i, 0] * E[i, 1] - P[i, 1] * E[i, 0]


@njit
def _rigid(x0, dt, n_steps, every, cmd, sel, P, E, TH, tau_ext, V, SJ, out_x, out_f, out_l):  # noqa: ANN001, ANN201
    """One rigid body under held thrust; records state, thrust and subtree loads every
    ``every`` steps (and the last). ``sel`` masks the thrusters this body carries. Returns
    (steps taken, rows written)."""
    t_dof, t_coef, t_kind, t_idx = V[5], V[6], V[7], V[8]
    S_M, S_Mc, S_DL, S_DQ, S_scal, S_ext, S_mask, jp = SJ
    m = P.shape[0]
    nj = jp.shape[0]
    T = np.zeros((6, m))
    _config(P, E, T)
    owner = np.zeros(m, dtype=np.int64)
    x = x0.copy()
    f = np.zeros(m)
    nu = np.zeros(6)
    tau_tab = np.zeros((1, 7))
    zero_tab = np.zeros((1, 7))
    ctab = np.zeros((1, 4))
    eye = np.eye(6)
    buf = np.empty(BUF_SIZE)
    k1 = np.empty(12)
    k2 = np.empty(12)
    k3 = np.empty(12)
    k4 = np.empty(12)
    tmp = np.empty(12)
    fs = np.empty(12)
    w_ = np.empty(6)
    row = 0
    for step in range(n_steps + 1):
        t = step * dt
        for a in range(6):
            nu[a] = x[6 + a]
        _thrusts(nu, owner, -1, cmd, P, E, TH, f)
        for i in range(m):
            if not sel[i]:
                f[i] = 0.0
        for a in range(6):
            s = tau_ext[a]
            for i in range(m):
                s += T[a, i] * f[i]
            tau_tab[0, 1 + a] = s
        deriv(t, x, False, tau_tab, ctab, V, buf, k1)
        if step % every == 0 or step == n_steps:
            for a in range(12):
                out_x[row, a] = x[a]
            for i in range(m):
                out_f[row, i] = f[i]
            for jj in range(nj):
                deriv(
                    t,
                    x,
                    False,
                    zero_tab,
                    ctab,
                    (eye, S_Mc[jj], S_DL[jj], S_DQ[jj], S_scal[jj], t_dof, t_coef, t_kind, t_idx),
                    buf,
                    fs,
                )  # noqa: E501
                for a in range(6):
                    s = -fs[6 + a] - S_ext[jj, a]
                    for b in range(6):
                        s += S_M[jj, a, b] * k1[6 + b]
                    for i in range(m):
                        if S_mask[jj, i]:
                            s -= T[a, i] * f[i]
                    w_[a] = s
                jx, jy, jz = jp[jj, 0], jp[jj, 1], jp[jj, 2]
                out_l[row, jj, 0], out_l[row, jj, 1], out_l[row, jj, 2] = w_[0], w_[1], w_[2]
                out_l[row, jj, 3] = w_[3] - (jy * w_[2] - jz * w_[1])
                out_l[row, jj, 4] = w_[4] - (jz * w_[0] - jx * w_[2])
                out_l[row, jj, 5] = w_[5] - (jx * w_[1] - jy * w_[0])
            row += 1
        if step == n_steps:
            break
        # the RK4 step of deriv from the k1 evaluated above (compiled.deriv_rk4_step)
        if not deriv_rk4_step(
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
            True,
        ):
            return step, row
    return n_steps, row


@njit
def _mb_rhs(t, X, TAU, par, a_p, a_c, K, C, B, W, OUT, JW, SEP):  # noqa: ANN001, ANN201
    """ẋ of every body (OUT) with the joint wrenches on each child (JW: force, moment on the
    child at the joint point, parent axes) and the joint-point mismatches (SEP, m)."""
    B_Minv, B_Mc, B_DL, B_DQ, B_scal, t_dof, t_coef, t_kind, t_idx = B
    Rb, TT, tau_tab, ctab, buf, Rrel, d, dv, F, Mm, wr = W
    nb = X.shape[0]
    for i in range(nb):
        rotation_zyx_into_compiled(X[i, 3], X[i, 4], X[i, 5], Rb[i])
        for a in range(6):
            TT[i, a] = TAU[i, a]
    for c in range(nb):
        p = par[c]
        if p < 0:
            continue
        Rp, Rc = Rb[p], Rb[c]
        uc, vc, wc, pc, qc, rc = X[c, 6], X[c, 7], X[c, 8], X[c, 9], X[c, 10], X[c, 11]
        up, vp, wp, pp, qp, rp = X[p, 6], X[p, 7], X[p, 8], X[p, 9], X[p, 10], X[p, 11]
        ac0, ac1, ac2 = a_c[c, 0], a_c[c, 1], a_c[c, 2]
        ap0, ap1, ap2 = a_p[c, 0], a_p[c, 1], a_p[c, 2]
        # joint-point velocities in own axes: v + ω × a
        lc0, lc1, lc2 = uc + qc * ac2 - rc * ac1, vc + rc * ac0 - pc * ac2, wc + pc * ac1 - qc * ac0
        lp0, lp1, lp2 = up + qp * ap2 - rp * ap1, vp + rp * ap0 - pp * ap2, wp + pp * ap1 - qp * ap0
        for a in range(3):
            pos_c = X[c, a] + Rc[a, 0] * ac0 + Rc[a, 1] * ac1 + Rc[a, 2] * ac2
            pos_p = X[p, a] + Rp[a, 0] * ap0 + Rp[a, 1] * ap1 + Rp[a, 2] * ap2
            wr[a] = pos_c - pos_p
            wr[3 + a] = (Rc[a, 0] * lc0 + Rc[a, 1] * lc1 + Rc[a, 2] * lc2) - (
                Rp[a, 0] * lp0 + Rp[a, 1] * lp1 + Rp[a, 2] * lp2
            )
        SEP[c] = math.sqrt(wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2])
        for a in range(3):  # into the parent's axes
            d[a] = Rp[0, a] * wr[0] + Rp[1, a] * wr[1] + Rp[2, a] * wr[2]
            dv[a] = Rp[0, a] * wr[3] + Rp[1, a] * wr[4] + Rp[2, a] * wr[5]
        for a in range(3):
            for b in range(3):
                Rrel[a, b] = Rp[0, a] * Rc[0, b] + Rp[1, a] * Rc[1, b] + Rp[2, a] * Rc[2, b]
        # rotation vector of R_rel (log map), parent axes
        cth = 0.5 * (Rrel[0, 0] + Rrel[1, 1] + Rrel[2, 2] - 1.0)
        cth = min(1.0, max(-1.0, cth))
        th = math.acos(cth)
        k = 0.5 if th < 1e-6 else 0.5 * th / math.sin(th)
        ph0 = k * (Rrel[2, 1] - Rrel[1, 2])
        ph1 = k * (Rrel[0, 2] - Rrel[2, 0])
        ph2 = k * (Rrel[1, 0] - Rrel[0, 1])
        # relative angular velocity, parent axes: R_rel ω_c − ω_p
        om0 = Rrel[0, 0] * pc + Rrel[0, 1] * qc + Rrel[0, 2] * rc - pp
        om1 = Rrel[1, 0] * pc + Rrel[1, 1] * qc + Rrel[1, 2] * rc - qp
        om2 = Rrel[2, 0] * pc + Rrel[2, 1] * qc + Rrel[2, 2] * rc - rp
        for a in range(3):
            F[a] = -K[c, a] * d[a] - C[c, a] * dv[a]
        Mm[0] = -K[c, 3] * ph0 - C[c, 3] * om0
        Mm[1] = -K[c, 4] * ph1 - C[c, 4] * om1
        Mm[2] = -K[c, 5] * ph2 - C[c, 5] * om2
        for a in range(3):
            JW[c, a] = F[a]
            JW[c, 3 + a] = Mm[a]
        # on the child, child axes: R_relᵀ F at a_c, R_relᵀ M
        fc0 = Rrel[0, 0] * F[0] + Rrel[1, 0] * F[1] + Rrel[2, 0] * F[2]
        fc1 = Rrel[0, 1] * F[0] + Rrel[1, 1] * F[1] + Rrel[2, 1] * F[2]
        fc2 = Rrel[0, 2] * F[0] + Rrel[1, 2] * F[1] + Rrel[2, 2] * F[2]
        TT[c, 0] += fc0
        TT[c, 1] += fc1
        TT[c, 2] += fc2
        TT[c, 3] += Rrel[0, 0] * Mm[0] + Rrel[1, 0] * Mm[1] + Rrel[2, 0] * Mm[2] + ac1 * fc2 - ac2 * fc1
        TT[c, 4] += Rrel[0, 1] * Mm[0] + Rrel[1, 1] * Mm[1] + Rrel[2, 1] * Mm[2] + ac2 * fc0 - ac0 * fc2
        TT[c, 5] += Rrel[0, 2] * Mm[0] + Rrel[1, 2] * Mm[1] + Rrel[2, 2] * Mm[2] + ac0 * fc1 - ac1 * fc0
        # on the parent, parent axes: −F at a_p, −M
        TT[p, 0] -= F[0]
        TT[p, 1] -= F[1]
        TT[p, 2] -= F[2]
        TT[p, 3] -= Mm[0] + ap1 * F[2] - ap2 * F[1]
        TT[p, 4] -= Mm[1] + ap2 * F[0] - ap0 * F[2]
        TT[p, 5] -= Mm[2] + ap0 * F[1] - ap1 * F[0]
    for i in range(nb):
        for a in range(6):
            tau_tab[0, 1 + a] = TT[i, a]
        deriv(
            t,
            X[i],
            False,
            tau_tab,
            ctab,
            (B_Minv[i], B_Mc[i], B_DL[i], B_DQ[i], B_scal[i], t_dof, t_coef, t_kind, t_idx),
            buf,
            OUT[i],
        )  # noqa: E501


@njit
def _multibody(
    X0, dt, n_steps, every, n_sub, cmd, owner, P, E, TH, ext, par, a_p, a_c, K, C, B, out_x, out_f, out_l, out_s
):  # noqa: ANN001, ANN201, E501
    """Joined bodies under held thrust; records every body's state, the thrusts, the joint
    wrenches (parent axes) and mismatches every ``every`` steps (and the last)."""
    nb = X0.shape[0]
    m = P.shape[0]
    X = X0.copy()
    Rb = np.zeros((nb, 3, 3))
    W = (
        Rb,
        np.zeros((nb, 6)),
        np.zeros((1, 7)),
        np.zeros((1, 4)),
        np.empty(BUF_SIZE),
        np.zeros((3, 3)),
        np.zeros(3),
        np.zeros(3),
        np.zeros(3),
        np.zeros(3),
        np.zeros(6),
    )  # noqa: E501
    TAU = np.zeros((nb, 6))
    T = np.zeros((6, m))
    _config(P, E, T)
    f = np.zeros(m)
    k1 = np.empty((nb, 12))
    k2 = np.empty((nb, 12))
    k3 = np.empty((nb, 12))
    k4 = np.empty((nb, 12))
    tmp = np.empty((nb, 12))
    # flat views of the same memory (C order), for the RK4 arithmetic of core.integrate
    Xf, tmpf = X.reshape(nb * 12), tmp.reshape(nb * 12)
    k1f, k2f, k3f, k4f = k1.reshape(nb * 12), k2.reshape(nb * 12), k3.reshape(nb * 12), k4.reshape(nb * 12)
    JW = np.zeros((nb, 6))
    SEP = np.zeros(nb)
    h = dt / n_sub
    row = 0
    for step in range(n_steps + 1):
        t = step * dt
        for b in range(nb):
            _thrusts(X[b, 6:12], owner, b, cmd, P, E, TH, f)
        for b in range(nb):
            for a in range(6):
                TAU[b, a] = ext[b, a]
        for i in range(m):
            b = owner[i]
            for a in range(6):
                TAU[b, a] += T[a, i] * f[i]
        if step % every == 0 or step == n_steps:
            _mb_rhs(t, X, TAU, par, a_p, a_c, K, C, B, W, k1, JW, SEP)
            for b in range(nb):
                for a in range(12):
                    out_x[row, b, a] = X[b, a]
                for a in range(6):
                    out_l[row, b, a] = JW[b, a]
                out_s[row, b] = SEP[b]
            for i in range(m):
                out_f[row, i] = f[i]
            row += 1
        if step == n_steps:
            break
        for s_ in range(n_sub):
            ts = t + s_ * h
            # the bodies' states side by side: one RK4 of the joined system (core.integrate)
            _mb_rhs(ts, X, TAU, par, a_p, a_c, K, C, B, W, k1, JW, SEP)
            rk4_stage_compiled(Xf, k1f, 0.5 * h, tmpf)
            _mb_rhs(ts + 0.5 * h, tmp, TAU, par, a_p, a_c, K, C, B, W, k2, JW, SEP)
            rk4_stage_compiled(Xf, k2f, 0.5 * h, tmpf)
            _mb_rhs(ts + 0.5 * h, tmp, TAU, par, a_p, a_c, K, C, B, W, k3, JW, SEP)
            rk4_stage_compiled(Xf, k3f, h, tmpf)
            _mb_rhs(ts + h, tmp, TAU, par, a_p, a_c, K, C, B, W, k4, JW, SEP)
            if not rk4_combine_compiled(Xf, k1f, k2f, k3f, k4f, h):
                return step, row
    return n_steps, row


# ============================================================================ packing
def _vehicle_group(vehicle: Any) -> tuple[np.ndarray, ...]:
    from hydrokit.model.dynamics import pack

    p = pack(vehicle)
    return p.V


def _thruster_group(asm: Assembly) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[Any, ...]]:
    """P, E (common axes about the common origin), owner, TH."""
    ts = asm.thrusters
    if ts is None:
        z = np.zeros((0, 3))
        th: tuple[Any, ...] = (
            np.zeros(0),
            np.zeros(0),
            np.zeros(0),
            np.zeros(0),
            np.zeros(0),
            np.zeros(0, dtype=np.int64),
            np.zeros((0, 1)),
            np.zeros((0, 1)),
            np.ones(0, dtype=np.int64),
            np.zeros((0, 10)),
            np.zeros((0, 1)),
            np.zeros((0, 1)),
        )
        return z, z, np.zeros(0, dtype=np.int64), th
    kind, tab_c, tab_f, tab_n, prop, kf, kr = _pack_thrusters(ts)
    th = (ts._wake_factor, ts.command_min, ts.command_max, ts.f_min, ts.f_max, kind, tab_c, tab_f, tab_n, prop, kf, kr)
    return ts.positions.copy(), ts.directions.copy(), np.array(asm.thruster_part, dtype=np.int64), th


def _wrench(f_part: np.ndarray, R: np.ndarray, r: np.ndarray) -> np.ndarray:
    """A part's force/moment (part axes, at the part origin) as a wrench about the point that
    is ``r`` (m) from the part origin... i.e. in common axes about the common origin when r
    is the part position."""
    F = R @ f_part[:3]
    return np.concatenate([F, R @ f_part[3:] + np.cross(r, F)])


# ============================================================================ result
@dataclass
class TransportResult(Result):
    """A transport run (SI; angles in rad).

    Attributes
    ----------
    model : str — rigid, multibody or independent
    time : (N,) — s
    assembly : (N, 12) — η, ν of the assembly origin (common frame)
    parts : dict — part name → (N, 12) η, ν of that part's origin
    joint_names : tuple of str — the child part of each joint
    loads : (N, n_joints, 6) — force (N) and moment about the joint point (N·m) the parent
        exerts on the child subtree, assembly body axes
    separation : (N, n_joints) — m (rigid: 0; multibody: joint-point mismatch; independent:
        distance between the groups' copies of the root origin at the root's joints)
    thruster_names : tuple of str; thrust : (N, m) — N
    dt : float — s; substeps : int — per step (multibody); diverged_at : float or None — s
    """

    model: str
    time: np.ndarray
    assembly: np.ndarray
    parts: dict[str, np.ndarray]
    joint_names: tuple[str, ...]
    loads: np.ndarray
    separation: np.ndarray
    thruster_names: tuple[str, ...]
    thrust: np.ndarray
    dt: float
    substeps: int = 1
    diverged_at: float | None = None
    warnings: list[str] = field(default_factory=list)

    def summary(self) -> dict[str, Any]:
        """Largest load and separation per joint, the end state and the run's figures."""
        joints = {}
        for k, name in enumerate(self.joint_names):
            L = self.loads[:, k, :]
            joints[name] = {
                "max_force_N": float(np.max(np.linalg.norm(L[:, :3], axis=1))) if len(L) else 0.0,
                "max_moment_Nm": float(np.max(np.linalg.norm(L[:, 3:], axis=1))) if len(L) else 0.0,
                "max_abs_components": [float(v) for v in np.max(np.abs(L), axis=0)] if len(L) else [0.0] * 6,
                "max_separation_m": float(np.max(self.separation[:, k])) if len(L) else 0.0,
            }
        end = self.assembly[-1]
        return jsonable(
            {
                "model": self.model,
                "duration_s": float(self.time[-1]) if len(self.time) else 0.0,
                "dt_s": self.dt,
                "substeps": self.substeps,
                "diverged_at_s": self.diverged_at,
                "end": {"position_m": end[0:3], "attitude_deg": np.degrees(end[3:6]), "velocity": end[6:12]},
                "displacement_m": end[0:3] - self.assembly[0, 0:3],
                "joints": joints,
                "warnings": self.warnings,
            }
        )

    def to_dict(self) -> dict[str, Any]:
        return self.summary()

    def load_rows(self) -> tuple[list[str], list[list[Any]]]:
        """``loads.csv`` rows: time, joint, fx, fy, fz, mx, my, mz (one row per joint and time)."""
        rows = []
        for i, t in enumerate(self.time):
            for k, name in enumerate(self.joint_names):
                rows.append([float(t), name, *[float(v) for v in self.loads[i, k]]])
        return list(LOAD_COLUMNS), rows

    def summary_rows(self) -> list[tuple[str, Any]]:
        s = self.summary()
        rows: list[tuple[str, Any]] = [("model", self.model), ("duration (s)", s["duration_s"])]
        rows += [("displacement (m)", [round(v, 3) for v in s["displacement_m"]])]
        for name, j in s["joints"].items():
            rows.append(
                (f"{name}: max force (N) / moment (N·m)", (round(j["max_force_N"], 1), round(j["max_moment_Nm"], 1)))
            )
        return rows

    def _repr_html_(self) -> str:
        return html_table(f"Transport ({self.model})", self.summary_rows())

    def plot(self, ax: Any = None) -> Any:
        """3-D path of the assembly origin and every part; returns the axes."""
        from hydrokit.plot.transport import path_axes

        return path_axes(self, ax)


# ============================================================================ driver
def _rotations(S: np.ndarray) -> np.ndarray:
    """(N, 3, 3) body → NED rotations of Euler states S (N, ≥ 6)."""
    from hydrokit.core.kinematics import rotation_zyx_many

    return rotation_zyx_many(S[:, 3:6])


def _point_states(S: np.ndarray, r: np.ndarray, R: np.ndarray | None = None) -> np.ndarray:
    """States of the point ``r`` (m, body axes) of a rigid body with states S (N, 12); ``R``
    the body's rotations (:func:`_rotations` of S) when already at hand."""
    out = S.copy()
    out[:, 0:3] = S[:, 0:3] + (_rotations(S) if R is None else R) @ np.asarray(r, float)
    out[:, 6:9] = S[:, 6:9] + np.cross(S[:, 9:12], r)
    return out


def _mean_states(states: list[np.ndarray]) -> np.ndarray:
    A = np.mean(states, axis=0)
    ang = np.array([s[:, 3:6] for s in states])
    A[:, 3:6] = np.arctan2(np.sin(ang).mean(axis=0), np.cos(ang).mean(axis=0))
    return A


def _steps(duration: float, dt: float, every: int) -> int:
    for v, nm in ((duration, "duration"), (dt, "dt")):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"{nm} = {v}: expected a positive number of seconds")
    if dt > duration:
        raise InputError(f"dt = {dt} s: expected at most the duration ({duration} s)")
    if not (isinstance(every, int) and every >= 1):
        raise InputError(f"output every = {every}: expected a positive whole number of steps")
    n = int(round(duration / dt))
    if n > 50_000_000:
        raise InputError(f"duration/dt = {n} steps: expected at most 5e7")
    return n


def fly_transport(
    assembly: Assembly,
    duration: float,
    dt: float,
    model: str = "rigid",
    commands: dict[str, float] | None = None,
    forces: dict[str, Any] | None = None,
    output_every: int = 1,
    controller: Any = None,
    control_dt: float = 0.1,
) -> TransportResult:
    """Fly ``assembly`` open loop, or (rigid model) under ``controller``.

    Parameters
    ----------
    assembly : Assembly
    duration : float — s; dt : float — step, s
    model : "rigid", "multibody" or "independent" (module docstring)
    commands : dict — thruster name (``PART.THRUSTER``) → command in the thruster's unit
        (propeller speed, rev/s); unnamed thrusters are off
    forces : dict — part name → 6 numbers: constant force (N) and moment (N·m) in that part's
        axes at its origin
    output_every : int — record every n-th step (and the last)
    controller : callable (t, x) → commands (rev/s), optional — called every ``control_dt``
        (s) with the assembly origin's state x (12); rigid model only (e.g. :class:`CarryController`)

    Returns
    -------
    TransportResult
    """
    check_model(model)
    from hydrokit.model.dynamics import reads_thrust

    for part in assembly.bodies:
        what = reads_thrust(part)
        if what:
            raise InputError(
                f"transport: part vehicle {part.name!r} has {what}, which read its thrusters' thrust; the transport "
                "models feed no per-vehicle thrust to them yet (it would be 0) — expected a vehicle without them"
            )
    n_steps = _steps(duration, dt, output_every)
    n_rows = n_steps // output_every + 1 + (1 if n_steps % output_every else 0)
    asm = assembly
    P, E, owner, TH = _thruster_group(asm)
    m = P.shape[0]
    cmd = np.zeros(m)
    for name, c in (commands or {}).items():
        i = asm.thruster_index(name)
        if not math.isfinite(float(c)):
            raise InputError(f"command of thruster '{name}' = {c}: expected a finite number")
        cmd[i] = float(c)
    n = len(asm.part_names)
    ext = np.zeros((n, 6))  # part axes at the part origin
    for name, fv in (forces or {}).items():
        i = asm.part_index(name, "force on part")
        v = np.asarray(fv, float).reshape(-1)
        if v.shape != (6,) or not np.all(np.isfinite(v)):
            raise InputError(
                f"force on part '{name}' = {list(np.ravel(fv))}: expected 6 finite numbers fx,fy,fz,mx,my,mz (N, N·m)"
            )
        ext[i] = v
    ext_common = np.array([_wrench(ext[i], asm.rotations[i], asm.positions[i]) for i in range(n)])
    time = np.arange(n_rows, dtype=float) * dt * output_every
    time[-1] = n_steps * dt
    joints = asm.joint_parts
    jn = tuple(asm.part_names[i] for i in joints)
    warnings: list[str] = []
    if controller is not None and model != "rigid":
        raise InputError(f"a controller flies the rigid model only (model = {model!r})")
    if model == "multibody":
        return _run_multibody(asm, n_steps, dt, output_every, n_rows, cmd, P, E, owner, TH, ext, time, jn, warnings)
    groups: list[tuple[tuple[int, ...], Any]]
    if model == "rigid":
        groups = [(tuple(range(n)), asm.composite)]
    else:
        groups = list(zip(asm.group_parts, asm.groups))
    X_all: list[np.ndarray] = []
    loads = np.zeros((n_rows, len(joints), 6))
    thrust = np.zeros((n_rows, m))
    done_min = n_steps
    rows_min = n_rows
    for members, veh in groups:
        mem = set(members)
        sel = np.array([owner[i] in mem for i in range(m)], dtype=np.bool_)
        share = 1.0 / len(groups) if model == "independent" else 1.0
        tau_ext = sum((ext_common[i] * (share if i == asm.root else 1.0) for i in members), np.zeros(6))
        js = [k for k, c in enumerate(joints) if c in mem]
        SJ = _subtree_group(asm, [joints[k] for k in js], ext_common, owner, m)
        out_x = np.zeros((n_rows, 12))
        out_f = np.zeros((n_rows, m))
        out_l = np.zeros((n_rows, len(js), 6))
        V = _vehicle_group(veh)
        if controller is None:
            done, rows = _rigid(
                np.zeros(12), dt, n_steps, output_every, cmd, sel, P, E, TH, tau_ext, V, SJ, out_x, out_f, out_l
            )  # noqa: E501
        else:
            done, rows = _rigid_controlled(
                controller, control_dt, dt, n_steps, output_every, sel, P, E, TH, tau_ext, V, SJ, out_x, out_f, out_l
            )  # noqa: E501
        done_min, rows_min = min(done_min, done), min(rows_min, rows)
        X_all.append(out_x)
        thrust += out_f
        for a, k in enumerate(js):
            loads[:, k] = out_l[:, a]
    diverged = None if done_min == n_steps else float(done_min * dt)
    if diverged is not None:
        warnings.append(f"the state became non-finite at t = {diverged:.3g} s; the run stops there")
    sl = slice(0, rows_min)
    parts: dict[str, np.ndarray] = {}
    sep = np.zeros((n_rows, len(joints)))
    if model == "rigid":
        assembly_states = X_all[0]
        R = _rotations(X_all[0][sl])
        for i, name in enumerate(asm.part_names):
            parts[name] = _point_states(X_all[0][sl], asm.positions[i], R)
    else:
        root_copies = [_point_states(X[sl], asm.positions[asm.root]) for X in X_all]
        assembly_states = _mean_states([X[sl] for X in X_all])
        for g, (members, _) in enumerate(groups):
            for i in members:
                if i != asm.root:
                    parts[asm.part_names[i]] = _point_states(X_all[g][sl], asm.positions[i])
        parts[asm.part_names[asm.root]] = _mean_states(root_copies)
        for k, c in enumerate(joints):
            if asm.parents[c] == asm.root:
                g = next(gi for gi, (mem, _) in enumerate(groups) if c in mem)
                others = [root_copies[h][:, :3] for h in range(len(groups)) if h != g]
                if others:
                    sep[:rows_min, k] = np.linalg.norm(root_copies[g][:, :3] - np.mean(others, axis=0), axis=1)
    return TransportResult(
        model,
        time[sl],
        assembly_states[sl],
        {k: v for k, v in parts.items()},
        jn,
        loads[sl],
        sep[sl],
        tuple(asm.thrusters.names) if asm.thrusters is not None else (),
        thrust[sl],
        dt,
        1,
        diverged,
        warnings,
    )


# ============================================================================ closed loop
@dataclass
class CarryController:
    """Carry an assembly along a straight line: a PID on the position error in body axes
    (x, y, z) and on heading, with the net weight fed forward, allocated to the thrusters
    within their forward and reverse limits (constrained allocation,
    :class:`~hydrokit.model.allocation.Allocator`), thrust turned into propeller speed at each
    thruster's advance speed. Roll and pitch are left to the hydrostatic restoring.

    Build with :meth:`for_assembly`. Call as ``controller(t, x)`` → commands (rev/s).

    Attributes
    ----------
    start, goal : (3,) — NED, m; speed : float — reference speed along the line, m/s
    heading : float — heading to hold, rad
    kp, ki, kd : (4,) — gains on x, y, z (N/m, N/(m·s), N·s/m) and yaw (N·m/rad, …)
    net_weight : float — W − B of the assembly, N
    """

    thrusters: Any
    allocator: Any
    start: np.ndarray
    goal: np.ndarray
    speed: float
    heading: float
    kp: np.ndarray
    ki: np.ndarray
    kd: np.ndarray
    net_weight: float
    control_dt: float
    integral: np.ndarray = field(default_factory=lambda: np.zeros(4))
    saturated_steps: int = 0
    steps: int = 0

    @classmethod
    def for_assembly(
        cls,
        asm: Assembly,
        goal: Any,
        speed: float = 0.3,
        bandwidth: float = 0.4,
        control_dt: float = 0.1,
    ) -> CarryController:
        """Gains from the composite's mass matrix: every loop a second-order system of natural
        frequency ``bandwidth`` (rad/s), damping 0.9, integral at bandwidth/5.

        goal : 3 floats — NED point (m) the assembly origin is carried to from (0, 0, 0);
        speed : m/s; control_dt : controller period, s
        """
        from hydrokit.model.allocation import Allocator

        if asm.thrusters is None:
            raise InputError("carry: the assembly has no thrusters (no vehicle part with a thrusters: block)")
        for v, nm in ((speed, "speed"), (bandwidth, "bandwidth"), (control_dt, "control_dt")):
            if not (math.isfinite(v) and v > 0):
                raise InputError(f"carry {nm} = {v}: expected a positive number")
        M = np.diag(asm.composite.M)[[0, 1, 2, 5]]
        w = bandwidth
        ts = asm.thrusters
        alloc = Allocator(ts.configuration_matrix(), ts.f_min, ts.f_max)
        return cls(
            ts,
            alloc,
            np.zeros(3),
            np.asarray(goal, float).reshape(3),
            float(speed),
            0.0,
            M * w * w,
            M * w * w * w / 5.0,
            2.0 * 0.9 * M * w,
            float(asm.composite.weight - asm.composite.buoyancy),
            float(control_dt),
        )

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Reference position (NED, m) and velocity (m/s) at time t."""
        d = self.goal - self.start
        L = float(np.linalg.norm(d))
        e = d / L if L > 0 else np.zeros(3)
        s = min(self.speed * t, L)
        return self.start + s * e, (self.speed * e if self.speed * t < L else np.zeros(3))

    def __call__(self, t: float, x: np.ndarray) -> np.ndarray:
        from hydrokit.core.kinematics import rotation_zyx, wrap_angle

        R = rotation_zyx(x[3], x[4], x[5])
        p_d, v_d = self.reference(t)
        e = np.empty(4)
        e[:3] = R.T @ (p_d - x[0:3])
        e[3] = wrap_angle(self.heading - x[5])
        de = np.empty(4)
        de[:3] = R.T @ v_d - x[6:9]
        de[3] = -x[11]
        lim = 2.0 * np.abs(self.net_weight) / np.maximum(self.ki, 1e-12) + 5.0  # anti-windup
        self.integral = np.clip(self.integral + e * self.control_dt, -lim, lim)
        u = self.kp * e + self.ki * self.integral + self.kd * de
        tau = np.zeros(6)
        tau[0:3] = u[:3] - self.net_weight * R[2, :]  # weight feed-forward: −(W − B) Rᵀ e_z
        tau[5] = u[3]
        f, sat = self.allocator(tau)
        self.steps += 1
        self.saturated_steps += int(sat)
        return self.thrusters.command_for_thrust(f, self.thrusters.advance_speed(x[6:12]))


def carry(
    assembly: Assembly,
    goal: Any,
    duration: float,
    dt: float = 0.01,
    speed: float = 0.3,
    bandwidth: float = 0.4,
    control_dt: float = 0.1,
    output_every: int = 10,
    forces: dict[str, Any] | None = None,
) -> tuple[TransportResult, dict[str, Any]]:
    """Carry the rigid assembly from the origin to ``goal`` (NED, m) with a
    :class:`CarryController`; returns the run and its figures (cross-track RMS and maximum,
    final position error, heading error, saturated fraction, largest joint loads).
    ``forces`` (part → 6 numbers, N and N·m, part axes) are disturbances the controller
    does not know."""
    ctl = CarryController.for_assembly(assembly, goal, speed, bandwidth, control_dt)
    res = fly_transport(
        assembly, duration, dt, "rigid", forces=forces, output_every=output_every, controller=ctl, control_dt=control_dt
    )
    d = ctl.goal - ctl.start
    e = d / np.linalg.norm(d)
    rel = res.assembly[:, 0:3] - ctl.start
    cross = rel - np.outer(rel @ e, e)
    s = res.summary()
    figures = {
        "goal_m": ctl.goal,
        "speed_m_s": ctl.speed,
        "cross_track_rms_m": float(np.sqrt(np.mean(np.sum(cross**2, axis=1)))),
        "cross_track_max_m": float(np.max(np.linalg.norm(cross, axis=1))),
        "final_error_m": float(np.linalg.norm(res.assembly[-1, 0:3] - ctl.goal)),
        "heading_error_max_deg": float(np.degrees(np.max(np.abs(res.assembly[:, 5])))),
        "saturated_fraction": ctl.saturated_steps / max(ctl.steps, 1),
        "joints": s["joints"],
    }
    return res, jsonable(figures)


def _rigid_controlled(controller, control_dt, dt, n_steps, every, sel, P, E, TH, tau_ext, V, SJ, out_x, out_f, out_l):  # noqa: ANN001, ANN202, E501
    """The rigid kernel in chunks of ``control_dt`` with the controller's commands held over each."""
    k = int(round(control_dt / dt))
    if k < 1 or abs(k * dt - control_dt) > 1e-9 * control_dt or k % every:
        raise InputError(
            f"control_dt = {control_dt} s: expected a whole multiple of dt ({dt} s) and of the output interval ({every} steps)"
        )
    x = np.zeros(12)
    row = 0
    step = 0
    while step < n_steps:
        n = min(k, n_steps - step)
        cmd = np.asarray(controller(step * dt, x), float)
        rows_c = n // every + 1 + (1 if n % every else 0)
        ox = np.zeros((rows_c, 12))
        of = np.zeros((rows_c, out_f.shape[1]))
        ol = np.zeros((rows_c, out_l.shape[1], 6))
        done, r = _rigid(x, dt, n, every, cmd, sel, P, E, TH, tau_ext, V, SJ, ox, of, ol)
        first = 0 if step == 0 else 1  # a chunk's first row is the previous chunk's last
        take = r - first if done == n else max(r - first - 1, 0)
        out_x[row : row + take] = ox[first : first + take]
        out_f[row : row + take] = of[first : first + take]
        out_l[row : row + take] = ol[first : first + take]
        row += take
        if done < n:
            return step + done, row
        x = ox[r - 1].copy()
        step += n
    return n_steps, row


def _subtree_group(
    asm: Assembly, children: list[int], ext_common: np.ndarray, owner: np.ndarray, m: int
) -> tuple[np.ndarray, ...]:  # noqa: E501
    """Stacked subtree bodies of the joints whose child is in ``children``."""
    if not children:
        return (
            np.zeros((0, 6, 6)),
            np.zeros((0, 6, 6)),
            np.zeros((0, 6, 6)),
            np.zeros((0, 6)),
            np.zeros((0, 9)),
            np.zeros((0, 6)),
            np.zeros((0, m), dtype=np.bool_),
            np.zeros((0, 3)),
        )
    from hydrokit.model.dynamics import pack

    packs = [pack(asm.subtrees[c]) for c in children]
    S_M = np.array([asm.subtrees[c].M for c in children])
    S_ext = np.array([ext_common[list(asm.subtree(c))].sum(axis=0) for c in children])
    S_mask = np.array([[owner[i] in asm.subtree(c) for i in range(m)] for c in children], dtype=np.bool_).reshape(
        len(children), m
    )
    return (
        S_M,
        np.array([p.Mc for p in packs]),
        np.array([p.DL for p in packs]),
        np.array([p.DQ for p in packs]),
        stack_scal([p.scal for p in packs]),
        S_ext,
        S_mask,
        asm.joints[children],
    )


def _substeps(asm: Assembly, dt: float) -> int:
    """Sub-steps per step so that RK4 resolves the stiffest joint: h·λ ≤ 1.5 with
    λ = ρ(G C) + √ρ(G K), G the joint mobility (:func:`~hydrokit.model.assembly.joint_mobility`)."""
    from hydrokit.model.assembly import joint_mobility

    lam = 0.0
    for c in asm.joint_parts:
        p = asm.parents[c]
        j = asm.joints[c]
        G = joint_mobility(asm.bodies[p], asm.bodies[c], j - asm.positions[p], j - asm.positions[c])
        rho_c = float(np.max(np.abs(np.linalg.eigvals(G @ np.diag(asm.joint_damping[c])))))
        rho_k = float(np.max(np.abs(np.linalg.eigvals(G @ np.diag(asm.joint_stiffness[c])))))
        lam = max(lam, rho_c + math.sqrt(rho_k))
    return max(1, int(math.ceil(dt * lam / 1.5)))


def _run_multibody(asm, n_steps, dt, every, n_rows, cmd, P, E, owner, TH, ext, time, jn, warnings):  # noqa: ANN001, ANN202
    n = len(asm.part_names)
    # bodies: origin at the part origin, axes parallel to the common axes; thrusters and the
    # part forces in those axes
    Pb = P - asm.positions[owner] if len(P) else P
    ext_b = np.array([np.concatenate([asm.rotations[i] @ ext[i, :3], asm.rotations[i] @ ext[i, 3:]]) for i in range(n)])
    packs = [_vehicle_group(b) for b in asm.bodies]
    B = (
        np.array([p[0] for p in packs]),
        np.array([p[1] for p in packs]),
        np.array([p[2] for p in packs]),
        np.array([p[3] for p in packs]),
        stack_scal([p[4] for p in packs]),
        packs[0][5],
        packs[0][6],
        packs[0][7],
        packs[0][8],
    )
    par = np.array(asm.parents, dtype=np.int64)
    a_p = np.array([asm.joints[i] - asm.positions[par[i]] if par[i] >= 0 else np.zeros(3) for i in range(n)])
    a_c = asm.joints - asm.positions
    X0 = np.zeros((n, 12))
    X0[:, 0:3] = asm.positions
    n_sub = _substeps(asm, dt)
    out_x = np.zeros((n_rows, n, 12))
    out_f = np.zeros((n_rows, len(P)))
    out_l = np.zeros((n_rows, n, 6))
    out_s = np.zeros((n_rows, n))
    done, rows = _multibody(X0, dt, n_steps, every, n_sub, cmd, owner, Pb, E, TH, ext_b, par, a_p, a_c,
                            asm.joint_stiffness, asm.joint_damping, B, out_x, out_f, out_l, out_s)  # fmt: skip
    diverged = None if done == n_steps else float(done * dt)
    if diverged is not None:
        warnings.append(f"the state became non-finite at t = {diverged:.3g} s; the run stops there")
    sl = slice(0, rows)
    r = asm.root
    root_states = out_x[sl, r]
    assembly_states = _point_states(root_states, -asm.positions[r])
    loads = np.zeros((rows, len(jn), 6))
    Rr = _rotations(out_x[sl, r])
    for k, c in enumerate(asm.joint_parts):
        A = np.transpose(Rr, (0, 2, 1)) @ _rotations(out_x[sl, asm.parents[c]])
        loads[:, k, :3] = np.einsum("nij,nj->ni", A, out_l[sl, c, :3])
        loads[:, k, 3:] = np.einsum("nij,nj->ni", A, out_l[sl, c, 3:])
    parts = {name: out_x[sl, i] for i, name in enumerate(asm.part_names)}
    sep = out_s[sl][:, list(asm.joint_parts)] if asm.joint_parts else np.zeros((rows, 0))
    return TransportResult(
        "multibody",
        time[sl],
        assembly_states,
        parts,
        jn,
        loads,
        sep,
        tuple(asm.thrusters.names) if asm.thrusters is not None else (),
        out_f[sl],
        dt,
        n_sub,
        diverged,
        warnings,
    )
