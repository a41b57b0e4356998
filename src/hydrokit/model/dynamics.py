"""Vehicle dynamics as pure functions f(t, x, τ) → ẋ (SPEC M1, M2; Fossen 2011 eq. 10.1 with an
irrotational current).

State (Euler):      x = [x, y, z, φ, θ, ψ, u, v, w, p, q, r]                       (12)
State (quaternion): x = [x, y, z, η, ε1, ε2, ε3, u, v, w, p, q, r]                 (13)

ν_r = ν − [Rᵀ v_c; 0] with v_c the current in NED (constant, or a table over time);
M ν̇_r = τ − C(ν_r) ν_r − D_L ν_r − D_Q|ν_r|ν_r + τ_terms(ν_r) + τ_drag(ν_r) − g(η), with C from
M_RB + M_A (Fossen Theorem 3.2), τ_drag the wrench of the point drag elements
(:func:`hydrokit.core.drag.drag_wrench`), plus the wind's X, Y, N when the vehicle has a wind
model and the run a wind (:mod:`hydrokit.model.wind`, at ν minus the wind: the air moves over the
ground, not with the water), and ν̇ = ν̇_r + d/dt [Rᵀ v_c; 0]
= ν̇_r − [ω × Rᵀv_c − Rᵀ v̇_c; 0].

:func:`pack` flattens a vehicle into arrays for the compiled integrators in
:mod:`hydrokit.simulate.compiled`; :func:`vehicle_dynamics` is the plain numpy version (the
reference the compiled path is tested against, and the closed-loop model).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hydrokit.core.coriolis import coriolis_force
from hydrokit.core.drag import PACKED_WIDTH, drag_wrench
from hydrokit.core.kinematics import (
    euler_rate_matrix,
    quaternion_rate,
    quaternion_to_rotation,
    rotation_zyx,
)
from hydrokit.errors import InputError
from hydrokit.model.surfaces import FIN_WIDTH, fin_wrench
from hydrokit.model.terms import add_term_forces, input_layout
from hydrokit.model.vehicle import Vehicle
from hydrokit.model.wind import wind_wrench

Dynamics = Callable[..., np.ndarray]


@dataclass(frozen=True)
class Packed:
    """A vehicle as flat arrays (SI).

    scal = [W, B, r_g (3), r_b (3), n, then 9 numbers per drag element, the DOF mask (6), m,
    then FIN_WIDTH numbers per physical fin, then the wind model's packed row when the vehicle has
    one (:meth:`hydrokit.model.wind.WindModel.pack`; :func:`scal_wind` finds it)]: W and B in N, r_g and r_b in m, n the number of drag
    elements (stored as a float), and per element the packed row [x, y, z, Lx, Ly, Lz, Qx, Qy, Qz]
    (m, N·s/m, N·s²/m²; :mod:`hydrokit.core.drag`); the mask is 1 for a kept DOF and 0 for a
    dropped one (planar models); m the number of fins and their rows
    (:meth:`hydrokit.model.surfaces.SurfaceSet.pack_fins`). Stacks of several vehicles pad
    shorter rows with zeros (:func:`stack_scal`): n and m say how many elements are real.

    Minv is the inverse of M_RB + M_A over the kept DOF (zero rows and columns for the dropped
    ones): a planar model solves its own reduced equations, not rows of the 6-DOF inverse.
    """

    Minv: np.ndarray
    Mc: np.ndarray
    DL: np.ndarray
    DQ: np.ndarray
    scal: np.ndarray
    t_dof: np.ndarray
    t_coef: np.ndarray
    t_kind: np.ndarray
    t_idx: np.ndarray

    @property
    def V(self) -> tuple[np.ndarray, ...]:
        """The packed vehicle as the one tuple every compiled path passes to the right-hand side
        (:func:`hydrokit.simulate.compiled.deriv`): Minv, Mc, DL, DQ, scal, t_dof, t_coef,
        t_kind, t_idx."""
        return (self.Minv, self.Mc, self.DL, self.DQ, self.scal, self.t_dof, self.t_coef, self.t_kind, self.t_idx)


def pack(v: Vehicle) -> Packed:
    """Flatten ``v`` for the compiled integrators."""
    M = v.M
    Mc = v.M_coriolis
    kept = list(v.dofs)
    Minv = np.zeros((6, 6))
    Minv[np.ix_(kept, kept)] = np.linalg.inv(M[np.ix_(kept, kept)])
    mask = np.zeros(6)
    mask[kept] = 1.0
    fins = v.surfaces.pack_fins(v.density, len(v.thruster_names))
    return Packed(
        Minv=np.ascontiguousarray(Minv),
        Mc=np.ascontiguousarray(0.5 * (Mc + Mc.T)),
        DL=np.ascontiguousarray(v.D_L, dtype=float),
        DQ=np.ascontiguousarray(v.D_Q, dtype=float),
        scal=np.concatenate(
            [
                [v.weight, v.buoyancy],
                v.r_g,
                v.r_b,
                [len(v.drag_elements)],
                v.drag_packed.ravel(),
                mask,
                [fins.shape[0]],
                fins.ravel(),
                v.wind.pack() if v.wind is not None else np.zeros(0),
            ]
        ).astype(float),
        t_dof=v.terms.dof,
        t_coef=np.ascontiguousarray(v.terms.coef, dtype=float),
        t_kind=v.terms.kinds,
        t_idx=v.terms.idx,
    )


def reads_thrust(vehicle: Vehicle) -> str:
    """What of ``vehicle`` reads its thrusters' thrust or rotation rate: ``T()``/``n()`` term
    factors and rudders in a propeller race ('' for nothing)."""
    from hydrokit.model.terms import RATE, THRUST

    kinds = np.asarray(vehicle.terms.kinds)
    out = []
    if kinds.size and np.isin(kinds, (THRUST, RATE)).any():
        out.append("T()/n() terms")
    fins = vehicle.surfaces.pack_fins(vehicle.density, len(vehicle.thruster_names))
    if fins.size and np.any(fins[:, 17] > 0):
        out.append("a rudder in a propeller race")
    return " and ".join(out)


def scal_elements(scal: np.ndarray) -> np.ndarray:
    """The (n, 9) drag-element rows held in a packed ``scal`` (empty for none)."""
    n = int(scal[8])  # always packed, 0 without elements
    return scal[9 : 9 + PACKED_WIDTH * n].reshape(n, PACKED_WIDTH)


@dataclass(frozen=True)
class Steering:
    """What the closed loop needs to steer a vehicle's control surfaces
    (:func:`hydrokit.model.surfaces.steer_surfaces`): the packed terms and fins, the fins' place in
    ``scal``, and each surface's limit (rad), rate limit (rad/s) and servo lag (s)."""

    t_dof: np.ndarray
    t_coef: np.ndarray
    t_kind: np.ndarray
    t_idx: np.ndarray
    scal: np.ndarray
    fin_first: int
    n_fin: int
    smax: np.ndarray
    srate: np.ndarray
    stc: np.ndarray

    def args(self) -> tuple[object, ...]:
        """The law's arguments after (τ_d, ν_r, τ_X), up to the servo lag."""
        return (
            self.t_dof,
            self.t_coef,
            self.t_kind,
            self.t_idx,
            self.scal,
            self.fin_first,
            self.n_fin,
            self.smax,
            self.srate,
            self.stc,
        )


def steering(v: Vehicle) -> Steering | None:
    """The :class:`Steering` of ``v``, None when it has no control surfaces."""
    if len(v.surfaces) == 0:
        return None
    p = pack(v)
    first, n = scal_fins(p.scal)
    s = v.surfaces
    return Steering(
        p.t_dof, p.t_coef, p.t_kind, p.t_idx, p.scal, first, n, s.max_deflection, s.rate_limit, s.time_constant
    )


def scal_mask_offset(scal: np.ndarray) -> int:
    """Index in a packed ``scal`` of the DOF mask (6 numbers), followed by the fin count and rows."""
    return 9 + PACKED_WIDTH * int(scal[8])


def scal_fins(scal: np.ndarray) -> tuple[int, int]:
    """(first index, count) of the fin rows in a packed ``scal``."""
    o = scal_mask_offset(scal) + 6
    return o + 1, int(scal[o])


def scal_wind(scal: np.ndarray) -> int:
    """Index in a packed ``scal`` of the wind model's row (past the end: no wind model)."""
    first, n = scal_fins(scal)
    return first + FIN_WIDTH * n


def stack_scal(rows: list[np.ndarray]) -> np.ndarray:
    """Stack the ``scal`` arrays of several vehicles, zero-padded to the longest (C order)."""
    width = max(r.shape[0] for r in rows)
    out = np.zeros((len(rows), width))
    for i, r in enumerate(rows):
        out[i, : r.shape[0]] = r
    return out


def current_table(current_ned: object) -> np.ndarray:
    """A current given as None, 3 numbers (m/s, NED) or rows [t, v_N, v_E, v_D] → (n, 4) table;
    an environment table of :func:`environment_table` (rows [t, v_N, v_E, v_D, w_N, w_E], the
    current and the wind's velocity, m/s) is checked and kept whole."""
    if current_ned is None:
        return np.zeros((1, 4))
    a = np.asarray(current_ned, dtype=float)
    if a.shape == (3,):
        return np.concatenate([[0.0], a])[None, :]
    if a.ndim == 2 and a.shape[1] in (4, 6) and a.shape[0] >= 1:
        if np.any(np.diff(a[:, 0]) <= 0):
            raise InputError("current table: times must increase strictly (s)")
        if not np.all(np.isfinite(a)):
            raise InputError("current or wind table: expected finite numbers (s, m/s)")
        return a
    raise InputError(f"current of shape {a.shape}: expected 3 values (m/s, NED) or rows [t, vN, vE, vD]")


def wind_table(wind: object) -> np.ndarray:
    """A wind given as (speed m/s, direction rad) — true, the direction it blows from, clockwise
    from North — or rows [t s, speed, direction] → rows [t, w_N, w_E] of its velocity (m/s)."""
    a = np.asarray(wind, dtype=float)
    if a.shape == (2,):
        a = np.concatenate([[0.0], a])[None, :]
    if a.ndim != 2 or a.shape[1] != 3 or a.shape[0] < 1 or not np.all(np.isfinite(a)):
        raise InputError(
            f"wind of shape {a.shape}: expected speed (m/s) and direction (rad, from) or rows [t, speed, direction]"
        )
    if np.any(a[:, 1] < 0):
        raise InputError(f"wind speed {a[:, 1].min():.6g} m/s: expected ≥ 0")
    if np.any(np.diff(a[:, 0]) <= 0):
        raise InputError("wind table: times must increase strictly (s)")
    return np.column_stack([a[:, 0], -a[:, 1] * np.cos(a[:, 2]), -a[:, 1] * np.sin(a[:, 2])])


def environment_table(current_ned: object = None, wind: object = None) -> np.ndarray:
    """The current (:func:`current_table`) and the wind (:func:`wind_table`) on one time grid: rows
    [t, v_N, v_E, v_D, w_N, w_E] (s, m/s), each interpolated linearly and held beyond its ends —
    what the integrators take in place of a current. No wind: the current's own table."""
    cur = current_table(current_ned)
    if wind is None:
        return cur
    w = wind_table(wind)
    t = np.union1d(cur[:, 0], w[:, 0])
    cols = [np.interp(t, cur[:, 0], cur[:, j]) for j in (1, 2, 3)]
    cols += [np.interp(t, w[:, 0], w[:, j]) for j in (1, 2)]
    return np.column_stack([t, *cols])


def check_wind(vehicle: Vehicle, table: np.ndarray) -> None:
    """Refuse a wind that blows on a vehicle without a wind model (it would be ignored)."""
    if vehicle.wind is None and table.shape[1] >= 6 and np.any(table[:, 4:6] != 0):
        raise InputError(
            f"a wind is given but vehicle {vehicle.name!r} has no wind model: expected a 'wind:' block in its "
            "file (docs/model.md)"
        )


def interp_table(tab: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Value and slope of a piecewise-linear table (rows [t, values…]) at t; held beyond the ends."""
    n = tab.shape[0]
    if n == 1 or t <= tab[0, 0]:
        return tab[0, 1:].copy(), np.zeros(tab.shape[1] - 1)
    if t >= tab[-1, 0]:
        return tab[-1, 1:].copy(), np.zeros(tab.shape[1] - 1)
    k = int(np.searchsorted(tab[:, 0], t, side="right")) - 1
    h = tab[k + 1, 0] - tab[k, 0]
    slope = (tab[k + 1, 1:] - tab[k, 1:]) / h
    return tab[k, 1:] + slope * (t - tab[k, 0]), slope


def input_vector(vehicle: Vehicle, delta: object = None, thrust: object = None, rate: object = None) -> np.ndarray:
    """The input vector [δ_1 … δ_ns, T_1 … T_m, n_1 … n_m] of ``vehicle`` (rad, N, rev/s) that the
    terms' ``delta()``, ``T()`` and ``n()`` factors and the fins read
    (:func:`hydrokit.model.terms.input_layout`).

    ``delta`` : None (all 0) or one deflection per control surface (rad), or already a whole input
    vector (then ``thrust`` and ``rate`` must be None); ``thrust`` : None (all 0) or one thrust per
    thruster of the vehicle file (N); ``rate`` : None (all 0) or one rotation rate per thruster
    (rev/s; :meth:`hydrokit.model.thrusters.ThrusterSet.rotation_rate`).
    """
    ns, m = len(vehicle.surfaces), len(vehicle.thruster_names)
    first_t, first_n, size = input_layout(ns, m)
    out = np.zeros(size)
    d = np.zeros(ns) if delta is None else np.atleast_1d(np.asarray(delta, float))
    if d.shape[0] not in (ns, size) or (d.shape[0] == size != ns and (thrust is not None or rate is not None)):
        raise InputError(
            f"{d.shape[0]} deflections: expected {ns} (one per control surface, rad) or a whole input vector of {size}"
        )
    out[: d.shape[0]] = d
    for values, first, what in ((thrust, first_t, "thrusts (N)"), (rate, first_n, "rotation rates (rev/s)")):
        if values is None:
            continue
        a = np.atleast_1d(np.asarray(values, float))
        if a.shape != (m,):
            raise InputError(f"{a.shape[0]} {what}: expected {m}, one per thruster of the vehicle file")
        out[first : first + m] = a
    return out


def hydro_force(
    p: Packed, nr: np.ndarray, R: np.ndarray, delta: np.ndarray | None = None, thrust_x: float = 0.0
) -> np.ndarray:
    """τ-independent right-hand side −C ν_r − D ν_r + τ_terms + τ_drag + τ_fins − g (N, N·m) at
    ν_r with rotation R, deflections ``delta`` (rad) and the commanded surge force ``thrust_x``
    (N; a rudder's propeller race)."""
    d = np.zeros(0) if delta is None else np.asarray(delta, float)
    cor = coriolis_force(p.Mc, nr, symmetric=True)  # p.Mc was symmetrised once in pack()
    damp = p.DL @ nr + p.DQ * np.abs(nr) * nr
    W, B = p.scal[0], p.scal[1]
    rg, rb = p.scal[2:5], p.scal[5:8]
    down = R[2]  # Rᵀ e_z: NED "down" in body axes
    fg, fb = W * down, -B * down
    g = -np.concatenate([fg + fb, np.cross(rg, fg) + np.cross(rb, fb)])
    out = -cor - damp - g
    add_term_forces(p.t_dof, p.t_coef, p.t_kind, p.t_idx, nr, d, d.shape[0], out)
    elements = scal_elements(p.scal)
    if elements.shape[0]:
        out += drag_wrench(elements, nr)
    first, n_fins = scal_fins(p.scal)
    for e in range(n_fins):
        fin_wrench(p.scal, first + FIN_WIDTH * e, nr, thrust_x, d, d.shape[0], out)
    return out


def vehicle_dynamics(vehicle: Vehicle, current_ned: object = None, attitude: str = "euler") -> Dynamics:
    """f(t, x, τ, δ=None, thrust=None, rate=None) → ẋ for ``vehicle`` (numpy; see module docstring
    for the state layout).

    τ: 6 floats (N, N·m); δ: the control surfaces' deflections (rad, file order; None: all 0) or
    the whole input vector; thrust, rate: each thruster's thrust (N) and rotation rate (rev/s)
    at that instant, read by the ``T()`` and ``n()`` term factors and a race's fin
    (:func:`input_vector`; None: 0, and the race takes its thrust from τ_X).
    A planar vehicle's dropped DOF have zero rates (their velocities and angles stay where they
    start: at zero, for a planar model).

    Parameters
    ----------
    vehicle : Vehicle
    current_ned : None, 3 floats (m/s, NED), (n, 4) rows [t s, v_N, v_E, v_D m/s] or the (n, 6)
        rows of :func:`environment_table` (the wind's velocity w_N, w_E m/s after the current's)
    attitude : "euler" or "quaternion"
    """
    if attitude not in ("euler", "quaternion"):
        raise InputError(f"attitude = {attitude!r}: expected euler or quaternion")
    if attitude == "quaternion" and vehicle.planar:
        raise InputError(f"vehicle {vehicle.name!r} is planar (dofs): expected attitude euler")
    p = pack(vehicle)
    ctab = current_table(current_ned)
    check_wind(vehicle, ctab)
    quat = attitude == "quaternion"
    mask = p.scal[scal_mask_offset(p.scal) : scal_mask_offset(p.scal) + 6]
    wfirst = scal_wind(p.scal)

    def f(
        t: float,
        x: np.ndarray,
        tau: np.ndarray,
        delta: np.ndarray | None = None,
        thrust: np.ndarray | None = None,
        rate: np.ndarray | None = None,
    ) -> np.ndarray:
        if thrust is not None or rate is not None:
            delta = input_vector(vehicle, delta, thrust, rate)
        if quat:
            q = x[3:7]
            R = quaternion_to_rotation(q / math.sqrt(q @ q))
            nu = x[7:13]
        else:
            R = rotation_zyx(x[3], x[4], x[5])
            nu = x[6:12]
        env, env_dot = interp_table(ctab, t)
        vc, vc_dot = env[:3], env_dot[:3]
        vcb = R.T @ vc
        nr = nu.copy()
        nr[:3] -= vcb
        tau = np.asarray(tau, float)
        force = tau + hydro_force(p, nr, R, delta, float(tau[0]))
        if env.shape[0] >= 5:
            # the air moves over the ground: the relative wind is ν minus the wind in body axes
            wb = R.T @ np.array([env[3], env[4], 0.0])
            wind_wrench(p.scal, wfirst, float(nu[0] - wb[0]), float(nu[1] - wb[1]), force)
        nr_dot = p.Minv @ force
        nu_dot = nr_dot
        nu_dot[:3] += -np.cross(nu[3:], vcb) + R.T @ vc_dot
        nu_dot *= mask
        pos_dot = R @ nu[:3]
        if quat:
            qd = quaternion_rate(x[3:7], nu[3:])
            # gentle constraint stabilisation keeps |q| = 1 under integration error
            qd += 0.5 * (1.0 - float(x[3:7] @ x[3:7])) * x[3:7]
            return np.concatenate([pos_dot, qd, nu_dot])
        pos_dot[2] *= mask[2]
        return np.concatenate([pos_dot, mask[3:] * (euler_rate_matrix(x[3], x[4]) @ nu[3:]), nu_dot])

    return f


def kinetic_energy(vehicle: Vehicle, nu: np.ndarray) -> float:
    """½ νᵀ (M_RB + M_A) ν, J."""
    nu = np.asarray(nu, float)
    return 0.5 * float(nu @ vehicle.M @ nu)
