"""Control surfaces: rudders, stern planes and fins (SPEC §9.1, issue #45).

A control surface is a deflection δ (rad) that the vehicle's derivative terms may use as a
factor (``Y_uu*delta(rudder)``, :mod:`hydrokit.model.terms`) and that a servo moves towards its
command (:func:`servo_step`). A surface given an ``area`` is also a **physical fin**: its force
comes from its own inflow, through :func:`fin_wrench`.

The fin law, per fin at position r with hinge unit vector a and zero-deflection chord c₀ (the
body x axis with its a-component removed):

    c = c₀ cos δ + (a × c₀) sin δ,   n = a × c                       chord and normal at δ
    v_f = v_r + ω × r                                                  the fin's velocity through the water
    α = atan2(v_f·n, v_f·c)                                            angle of attack (in-plane)
    q S = ½ ρ S ((v_f·c)² + (v_f·n)²)
    C_L = C_Lα α,  C_D = C_D0 + C_L² / (π e AR)                        attached, |α| ≤ α_s
    C_L → C_N sin α cos α,  C_D → C_N sin² α                           flat plate beyond stall
    F = −q S [C_L (−sin α c + cos α n) + C_D (cos α c + sin α n)],  M = r × F

Lift is normal to the inflow and drag along it; the two regimes are joined by a cosine blend
over ``stall_width`` above α_s, so the force is continuous through stall (no jump; lift falls
towards the flat plate's normal force). Flow from behind (|α| > 90°) folds α by π: the section
is treated as symmetric. The lifting-line slope for a fin of aspect ratio AR (Helmbold; Whicker
& Fehlner 1958) is C_Lα = 2π AR / (2 + √(AR² + 4)) (:func:`helmbold_lift_slope`).

Sign check (Prestero 2001): a rudder with a = +z behind the origin, δ > 0, moving ahead, gives
α = −δ, a force +Y and a moment −N (Y_uuδr > 0, N_uuδr < 0); a stern plane with a = +y gives −Z
and −M (Z_uuδs < 0, M_uuδs < 0).

A rudder in a propeller race (``slipstream``) takes its inflow from the propeller's loading, T
the propeller's thrust (N): the named thruster's (``T`` of the input vector
[δ…, T…, n…], :mod:`hydrokit.model.terms`) when the run gives it, else the commanded surge force
τ_X times ``thrust_share``. Two inflow laws, with u_P = (1 − w_P) u the propeller's advance speed
(w_P the thruster's ``wake_fraction``, u the fin's axial speed through the water):

``race`` (actuator disc)
    the fully developed race of momentum theory, u_R = √(u_P² + 8 T / (ρ π D²)) (Carlton,
    *Marine Propellers and Propulsion*, §4); the lateral inflow is the fin's own.
``mmg`` (the MMG standard method's rudder inflow, Yasukawa & Yoshimura 2015, eq. 38–44)
    u_R = ε u_P √(η {1 + κ (√(1 + 8 K_T/(π J²)) − 1)}² + (1 − η)), v_R = U γ_R β_R with
    β_R = β − l_R' r', β = atan(−v/u), U = √(u² + v²), η = D/H_R and γ_R one value for β_R > 0
    and another for β_R < 0 (flow straightening). With K_T/J² = T/(ρ D² u_P²) the square root is
    the race's, √(u_P² + 8T/(ρπD²)) / u_P, so the law is written as u_R = ε √(η a² + (1 − η) u_P²)
    with a = (1 − κ) u_P + κ √(u_P² + 8T/(ρπD²)) — the same value for u_P > 0 and finite at rest;
    U β_R = U β − l_R r with l_R in m (l_R' L). The fin's lateral inflow is −v_R (body y: the law
    is for a rudder, hinge along body z). ε = κ = η = γ_R = 1, w_P = 0 and l_R at the rudder give
    back the race's axial speed and the fin's own geometric inflow for small drift.

A surface's ``neutral_deflection`` δ₀ (rad) is the deflection at which the fin is at zero angle
to its chord line's neutral: the law turns the chord by δ − δ₀.

:func:`fin_wrench` and :func:`servo_step` are the only implementations of these laws: the numpy
model (:mod:`hydrokit.model.dynamics`) calls them as Python, the compiled integrators
(:mod:`hydrokit.simulate.compiled`) compile the same functions with numba. They work on plain
floats and arrays, so that both can.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from hydrokit.errors import InputError
from hydrokit.model.terms import add_term_forces

#: numbers per packed fin row (see :func:`pack_fins`)
FIN_WIDTH = 32
#: the inflow laws of a fin in a propeller race (``slipstream.inflow``)
INFLOW_LAWS = ("race", "mmg")
#: most control surfaces a vehicle may have (sizes the compiled kernels' scratch buffers)
MAX_SURFACES = 16
#: flat-plate normal-force coefficient (Hoerner 1965, Fluid-Dynamic Drag, ch. 3: C_N ≈ 1.17–1.2)
FLAT_PLATE_NORMAL_FORCE = 1.2
#: default width of the blend from attached lift to the flat plate above the stall angle, rad
DEFAULT_STALL_WIDTH = math.radians(10.0)


def helmbold_lift_slope(aspect_ratio: float) -> float:
    """Lifting-line slope C_Lα (1/rad) of a fin of ``aspect_ratio`` (Helmbold, SPEC §9.1)."""
    return 2.0 * math.pi * aspect_ratio / (2.0 + math.sqrt(aspect_ratio * aspect_ratio + 4.0))


@dataclass(frozen=True)
class Fin:
    """The physical model of a surface (SI, body axes).

    axis : (3,) — hinge unit vector; chord : (3,) — zero-deflection chord unit vector (⟂ axis);
    area : float — m²; lift_slope : float — 1/rad; stall_angle : float — rad; stall_width : float —
    rad; drag_coefficient : float — C_D0; aspect_ratio : float — 0 when not given (no induced drag);
    oswald : float — e; normal_force_coefficient : float — flat-plate C_N;
    slipstream_diameter : float — m, 0 for none; thrust_share : float — share of τ_X that is the
    propeller's thrust when the run gives no thruster's thrust; neutral_deflection : float — δ₀,
    rad; race_thruster : int — index (file order) of the thruster whose race it is, −1 for none;
    inflow : str — ``race`` or ``mmg`` (module docstring); wake_fraction : float — w_P of that
    propeller, –; epsilon, kappa, eta : float — the MMG ε, κ and η = D/H_R, –;
    gamma_positive, gamma_negative : float — the MMG flow straightening γ_R for β_R > 0 and
    β_R < 0, –; l_R : float — the MMG l_R (l_R' L), m.
    """

    axis: tuple[float, float, float]
    chord: tuple[float, float, float]
    area: float
    lift_slope: float
    stall_angle: float
    stall_width: float = DEFAULT_STALL_WIDTH
    drag_coefficient: float = 0.0
    aspect_ratio: float = 0.0
    oswald: float = 0.9
    normal_force_coefficient: float = FLAT_PLATE_NORMAL_FORCE
    slipstream_diameter: float = 0.0
    thrust_share: float = 1.0
    neutral_deflection: float = 0.0
    race_thruster: int = -1
    inflow: str = "race"
    wake_fraction: float = 0.0
    epsilon: float = 1.0
    kappa: float = 1.0
    eta: float = 1.0
    gamma_positive: float = 1.0
    gamma_negative: float = 1.0
    l_R: float = 0.0


@dataclass(frozen=True)
class ControlSurface:
    """One control surface.

    name : str; position : (3,) — m, body axes; max_deflection : float — rad (mechanical limit);
    rate_limit : float — rad/s (inf: none); time_constant : float — s, first-order servo lag
    (0: none); fin : Fin or None — the physical model (None: a deflection variable only).
    """

    name: str
    position: tuple[float, float, float]
    max_deflection: float
    rate_limit: float = math.inf
    time_constant: float = 0.0
    fin: Fin | None = None


@dataclass(frozen=True)
class SurfaceSet:
    """A vehicle's control surfaces, in file order."""

    surfaces: tuple[ControlSurface, ...] = ()
    _index: dict[str, int] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if len(self.surfaces) > MAX_SURFACES:
            raise InputError(f"{len(self.surfaces)} control surfaces: expected at most {MAX_SURFACES}")
        self._index.update({s.name: k for k, s in enumerate(self.surfaces)})

    def __len__(self) -> int:
        return len(self.surfaces)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.surfaces)

    def index(self, name: str) -> int:
        """Position of surface ``name``; InputError naming the known ones if there is none."""
        if name not in self._index:
            known = ", ".join(self.names) or "none"
            raise InputError(f"no control surface named {name!r} (the vehicle has: {known})")
        return self._index[name]

    @property
    def max_deflection(self) -> np.ndarray:
        """Mechanical limits, rad."""
        return np.array([s.max_deflection for s in self.surfaces], dtype=float)

    @property
    def rate_limit(self) -> np.ndarray:
        """Servo rate limits, rad/s (inf: none)."""
        return np.array([s.rate_limit for s in self.surfaces], dtype=float)

    @property
    def time_constant(self) -> np.ndarray:
        """Servo time constants, s (0: none)."""
        return np.array([s.time_constant for s in self.surfaces], dtype=float)

    def check_deflection(self, delta: np.ndarray, where: str = "deflection") -> None:
        """InputError if any |δ| exceeds its surface's mechanical limit (rad in, degrees said)."""
        lim = self.max_deflection
        a = np.atleast_2d(np.asarray(delta, float))
        for k, s in enumerate(self.surfaces):
            worst = float(np.max(np.abs(a[:, k]))) if a.size else 0.0
            if worst > lim[k] * (1 + 1e-9):
                raise InputError(
                    f"{where}: {s.name} = {math.degrees(worst):.4g}°: expected at most "
                    f"{math.degrees(lim[k]):.4g}° (max_deflection_deg)"
                )

    def pack_fins(self, density: float, n_thrusters: int = 0) -> np.ndarray:
        """The physical fins as (n, FIN_WIDTH) rows for :func:`fin_wrench` (empty for none).

        Row: [r (3) m, axis (3), chord (3), ½ρS kg/m, C_Lα 1/rad, α_s rad, blend width rad, C_D0,
        1/(π e AR) (0 without AR), C_N, surface index, slipstream ρπD²/8 kg/m (0: none),
        thrust share, input index of the race's thrust (−1: none), inflow law (0 race, 1 mmg),
        ε, κ, η, γ_R(β_R > 0), γ_R(β_R < 0), l_R m, w_P, δ₀ rad, 0 …]; ``n_thrusters`` places the
        thrusts in the input vector (:func:`hydrokit.model.terms.input_layout`).
        """
        rows = []
        for k, s in enumerate(self.surfaces):
            fin = s.fin
            if fin is None:
                continue
            row = np.zeros(FIN_WIDTH)
            row[0:3] = s.position
            row[3:6] = fin.axis
            row[6:9] = fin.chord
            row[9] = 0.5 * density * fin.area
            row[10] = fin.lift_slope
            row[11] = fin.stall_angle
            row[12] = fin.stall_width
            row[13] = fin.drag_coefficient
            row[14] = 1.0 / (math.pi * fin.oswald * fin.aspect_ratio) if fin.aspect_ratio > 0 else 0.0
            row[15] = fin.normal_force_coefficient
            row[16] = k
            row[17] = density * math.pi * fin.slipstream_diameter**2 / 8.0
            row[18] = fin.thrust_share
            row[19] = len(self.surfaces) + fin.race_thruster if 0 <= fin.race_thruster < n_thrusters else -1.0
            row[20] = INFLOW_LAWS.index(fin.inflow)
            row[21:27] = (fin.epsilon, fin.kappa, fin.eta, fin.gamma_positive, fin.gamma_negative, fin.l_R)
            row[27] = fin.wake_fraction
            row[28] = fin.neutral_deflection
            rows.append(row)
        return np.array(rows, dtype=float).reshape(len(rows), FIN_WIDTH)


def section_coefficients(
    alpha: float,
    lift_slope: float,
    stall: float,
    width: float = DEFAULT_STALL_WIDTH,
    cd0: float = 0.0,
    k_ind: float = 0.0,
    cn: float = FLAT_PLATE_NORMAL_FORCE,
) -> tuple[float, float]:
    """(C_L, C_D) at angle of attack ``alpha`` (rad), continuous through stall.

    Read back from :func:`fin_wrench` (the one implementation of the law) for a unit fin in a
    unit inflow at ``alpha``: lift_slope 1/rad, stall and width rad, k_ind = 1/(π e AR).
    """
    row = np.zeros(FIN_WIDTH)
    row[3:9] = (0.0, 0.0, 1.0, 1.0, 0.0, 0.0)  # hinge +z, chord +x: the normal is +y
    row[9:16] = (1.0, lift_slope, stall, width, cd0, k_ind, cn)
    row[19] = -1.0
    nr = np.array([math.cos(alpha), math.sin(alpha), 0.0, 0.0, 0.0, 0.0])
    f = np.zeros(6)
    fin_wrench(row, 0, nr, 0.0, np.zeros(1), 1, f)
    ca, sa = math.cos(alpha), math.sin(alpha)
    fc, fn = f[0], f[1]
    return sa * fc - ca * fn, -ca * fc - sa * fn


def fin_wrench(p, b, nr, thrust_x, delta, n_delta, f):  # noqa: ANN001, ANN201
    """Add the force and moment (N, N·m) of the fin packed at ``p[b : b + FIN_WIDTH]`` to ``f``.

    ``nr`` the relative velocity ν_r (m/s, rad/s), ``thrust_x`` the commanded surge force τ_X (N,
    for a rudder in a propeller race when the run gives no thruster's thrust), ``delta`` the
    input vector (deflections rad, thrusts N, rotation rates rev/s; the first ``n_delta`` are
    real, a missing one is 0). Plain floats and loops: the numpy model calls it as Python and the
    compiled integrators compile it (module docstring for the law).
    """
    rx, ry, rz = p[b], p[b + 1], p[b + 2]
    ax, ay, az = p[b + 3], p[b + 4], p[b + 5]
    c0x, c0y, c0z = p[b + 6], p[b + 7], p[b + 8]
    k = int(p[b + 16])
    d = (delta[k] if k < n_delta else 0.0) - p[b + 28]
    cd_, sd_ = math.cos(d), math.sin(d)
    # c = c₀ cos δ + (a × c₀) sin δ  (Rodrigues with a·c₀ = 0)
    cx = c0x * cd_ + (ay * c0z - az * c0y) * sd_
    cy = c0y * cd_ + (az * c0x - ax * c0z) * sd_
    cz = c0z * cd_ + (ax * c0y - ay * c0x) * sd_
    nx = ay * cz - az * cy
    ny = az * cx - ax * cz
    nz = ax * cy - ay * cx
    p_, q_, r_ = nr[3], nr[4], nr[5]
    vx = nr[0] + (q_ * rz - r_ * ry)
    vy = nr[1] + (r_ * rx - p_ * rz)
    vz = nr[2] + (p_ * ry - q_ * rx)
    race = p[b + 17]
    if race > 0.0:
        ti = int(p[b + 19])
        thrust = delta[ti] if 0 <= ti < n_delta else p[b + 18] * thrust_x
        if thrust < 0.0:
            thrust = 0.0
        up = (1.0 - p[b + 27]) * (vx if vx > 0.0 else 0.0)
        if p[b + 20] == 0.0:  # the fully developed race (actuator disc)
            if thrust > 0.0:
                vx = math.sqrt(up * up + thrust / race)
        elif vx > 0.0 or thrust > 0.0:  # the MMG standard method's rudder inflow (module docstring)
            eps, kap, eta = p[b + 21], p[b + 22], p[b + 23]
            a_ = (1.0 - kap) * up + kap * math.sqrt(up * up + thrust / race)
            vx = eps * math.sqrt(eta * a_ * a_ + (1.0 - eta) * up * up)
            u_, v_ = nr[0], nr[1]
            ub = math.sqrt(u_ * u_ + v_ * v_) * math.atan2(-v_, u_) - p[b + 26] * r_  # U β_R
            vy = -(p[b + 24] if ub > 0.0 else p[b + 25]) * ub
    vc = vx * cx + vy * cy + vz * cz
    vn = vx * nx + vy * ny + vz * nz
    v2 = vc * vc + vn * vn
    if v2 <= 0.0:
        return
    speed = math.sqrt(v2)
    # section coefficients at α, folded by π for flow from behind (a symmetric section)
    a = math.atan2(vn, vc)
    if a > 0.5 * math.pi:
        a -= math.pi
    elif a < -0.5 * math.pi:
        a += math.pi
    slope, stall, width, cd0, k_ind, cn = p[b + 10], p[b + 11], p[b + 12], p[b + 13], p[b + 14], p[b + 15]
    if abs(a) <= stall:
        cl = slope * a
        cdrag = cd0 + k_ind * cl * cl
    else:
        t = (abs(a) - stall) / width if width > 0.0 else 1.0
        w = 0.5 * (1.0 + math.cos(math.pi * t)) if t < 1.0 else 0.0
        cl_s = slope * stall * (1.0 if a > 0.0 else -1.0)
        sa_ = math.sin(a)
        cl = w * cl_s + (1.0 - w) * cn * sa_ * math.cos(a)
        cdrag = w * (cd0 + k_ind * cl_s * cl_s) + (1.0 - w) * cn * sa_ * sa_
    qs = p[b + 9] * v2
    ca, sa = vc / speed, vn / speed
    fc = -qs * (-cl * sa + cdrag * ca)
    fn = -qs * (cl * ca + cdrag * sa)
    fx = fc * cx + fn * nx
    fy = fc * cy + fn * ny
    fz = fc * cz + fn * nz
    f[0] += fx
    f[1] += fy
    f[2] += fz
    f[3] += ry * fz - rz * fy
    f[4] += rz * fx - rx * fz
    f[5] += rx * fy - ry * fx


def servo_step(delta, command, dt, max_deflection, rate_limit, time_constant, out):  # noqa: ANN001, ANN201
    """One servo step of ``dt`` (s) for every surface, into ``out`` (rad).

    The command (rad) is first clipped to the mechanical limit; then a first-order lag of
    ``time_constant`` (s; exact discrete step 1 − e^(−dt/T), none at 0), then the rate limit
    (rad/s; inf: none). Without lag and rate limit the deflection equals the clipped command.
    """
    for k in range(delta.shape[0]):
        lim = max_deflection[k]
        c = command[k]
        if c > lim:
            c = lim
        elif c < -lim:
            c = -lim
        T = time_constant[k]
        target = delta[k] + (c - delta[k]) * (1.0 - math.exp(-dt / T)) if T > 0.0 else c
        step = target - delta[k]
        rmax = rate_limit[k] * dt
        if step > rmax:
            step = rmax
        elif step < -rmax:
            step = -rmax
        out[k] = delta[k] + step


#: deflection step of the effectiveness difference quotient, rad
EFFECTIVENESS_STEP = 1e-3


#: scratch :func:`steer_surfaces` needs: 12 + 3 per surface
def steer_work_size(n_surfaces: int) -> int:
    """Length of the ``work`` scratch of :func:`steer_surfaces` for ``n_surfaces``."""
    return 12 + 3 * n_surfaces


def steer_surfaces(
    tau_d, nr, thrust_x, t_dof, t_coef, t_kind, t_idx, scal, fin_first, n_fin, smax, srate, stc, dt, delta, work
):  # noqa: ANN001, ANN201, E501
    """Move the control surfaces one servo step of ``dt`` (s) towards the deflections that give
    the autopilot's demanded moments (the closed loop's surface allocation, issue #45).

    Each surface's effectiveness b = ∂τ/∂δ (N·m/rad) at the present relative velocity ``nr``
    (m/s, rad/s) and propulsion ``thrust_x`` (N) is the central difference of the force laws
    themselves (:func:`hydrokit.model.terms.add_term_forces` for the ``delta()`` terms,
    :func:`fin_wrench` for the fins; step :data:`EFFECTIVENESS_STEP`), so it grows with u² and
    vanishes at rest. A surface steers the moment (roll K, pitch M or yaw N) it is most effective
    on; the surfaces that steer one moment share its demand ``tau_d`` equally:
    δ_cmd = τ_d,row / (n_row b_row), then the servo law (:func:`servo_step`: mechanical limit
    ``smax`` rad, rate limit ``srate`` rad/s, lag ``stc`` s) moves ``delta`` (rad, in/out).
    A surface with |b| below 1e-9 N·m/rad (no flow) is commanded to 0.

    ``work`` is scratch of at least :func:`steer_work_size` numbers. Plain floats and loops: the
    Python closed loop calls it as Python and the compiled loop compiles it.
    """
    ns = delta.shape[0]
    fp = work[0:6]
    fm = work[6:12]
    dv = work[12 : 12 + ns]
    gain = work[12 + ns : 12 + 2 * ns]
    cmd = work[12 + 2 * ns : 12 + 3 * ns]
    h = EFFECTIVENESS_STEP
    count3, count4, count5 = 0, 0, 0
    for k in range(ns):
        for i in range(ns):
            dv[i] = 0.0
        for i in range(6):
            fp[i] = 0.0
            fm[i] = 0.0
        dv[k] = h
        add_term_forces(t_dof, t_coef, t_kind, t_idx, nr, dv, ns, fp)
        for e in range(n_fin):
            fin_wrench(scal, fin_first + FIN_WIDTH * e, nr, thrust_x, dv, ns, fp)
        dv[k] = -h
        add_term_forces(t_dof, t_coef, t_kind, t_idx, nr, dv, ns, fm)
        for e in range(n_fin):
            fin_wrench(scal, fin_first + FIN_WIDTH * e, nr, thrust_x, dv, ns, fm)
        row, best = 5, 0.0
        for i in range(3, 6):
            b = (fp[i] - fm[i]) / (2.0 * h)
            if abs(b) > abs(best):
                row, best = i, b
        gain[k] = best
        cmd[k] = row  # the row, for now
        if abs(best) > 1e-9:
            if row == 3:
                count3 += 1
            elif row == 4:
                count4 += 1
            else:
                count5 += 1
    for k in range(ns):
        row = int(cmd[k])
        n_row = count3 if row == 3 else (count4 if row == 4 else count5)
        cmd[k] = tau_d[row] / (n_row * gain[k]) if abs(gain[k]) > 1e-9 else 0.0
    servo_step(delta, cmd, dt, smax, srate, stc, delta)
