"""Free-decay rig models (SPEC §1.1–1.3, floating body: issue #16) and their compiled integrator.

All the rigs reduce to one generalised equation in the recorded coordinate q (m for the
spring, rad for the pendulum and the torsion rig):

    A q̈ + c_L q̇ + c_Q |q̇| q̇ + S ρ(q) = 0,        ρ(q) = q (spring, torsion) or sin q (pendulum)

(floating body: ρ(q) = C(q)/C1, the restoring over its linear part, so ρ'(0) = 1)

with the rig constants

=========  ===================================  ==============  ==============  =====================
rig        A (inertia)                          c_L             c_Q             S (restoring)
=========  ===================================  ==============  ==============  =====================
spring     m + m_a                               K_L             K_Q             k
torsion    I + I_a                               K_L             K_Q             K
pendulum   (m + m_a) r² + I_body + m_rod r²/3    K_L r²          K_Q r³          |(W − B) r + (W_rod − B_rod) r/2|
floating   m + m_a (heave), I + I_a (roll/pitch) K_L             K_Q             C1
=========  ===================================  ==============  ==============  =====================

Floating body (issue #16): C1 = ρ g A_wp (heave), ρ g ∇ GM (roll, pitch), the given C1 of a
polynomial C(φ) = C1 φ + C3 φ³ + C5 φ⁵, or ρ g ∇ GZ'(0) of a righting-arm curve (interpolated
by a monotone cubic, PCHIP, mirrored to negative angles). GM and A_wp give a linear restoring, so
the floating rig is then exactly the torsion (roll, pitch) or spring (heave) model.

For the point-mass pendulum (no body inertia, massless rod) dividing by r gives SPEC P1:
(m + m_a) r θ̈ = (B − W) sin θ − K_L r θ̇ − K_Q r² |θ̇| θ̇. A buoyant body (B > W) swings about
the upright equilibrium; with θ measured from that equilibrium the equation is the same with
S = |…|, so it needs no special case.

The fit works with the normalised parameters p = (ω², b, g) of
q̈ = −ω² ρ(q) − b q̇ − g |q̇| q̇, i.e. ω² = S/A, b = c_L/A, g = c_Q/A.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from hydrokit.core.integrate import rk4_combine_into, rk4_stage, rk4_stage_into, rk4_update
from hydrokit.errors import InputError
from hydrokit.identify.types import Rig

#: restoring shape codes of the compiled integrator
LINEAR, SINE, POLYNOMIAL, TABLE = 0, 1, 2, 3


@dataclass(frozen=True)
class Restoring:
    """The shape ρ(q) of a restoring S ρ(q), with ρ(0) = 0 and ρ'(0) = 1 (sine: the pendulum).

    kind : int — LINEAR (ρ = q), SINE (sin q), POLYNOMIAL (q + a3 q³ + a5 q⁵, params (a3, a5))
        or TABLE (odd piecewise cubic Hermite; params (n, x_0..x_{n−1}, ρ_0.., ρ'_0..) with
        x ≥ 0 increasing from 0, linear beyond the last knot)
    params : tuple of float
    """

    kind: int = LINEAR
    params: tuple[float, ...] = ()

    @classmethod
    def polynomial(cls, c1: float, c3: float, c5: float) -> Restoring:
        """ρ(q) = q + (C3/C1) q³ + (C5/C1) q⁵; linear when C3 = C5 = 0."""
        if c3 == 0 and c5 == 0:
            return cls(LINEAR)
        return cls(POLYNOMIAL, (c3 / c1, c5 / c1))

    @classmethod
    def table(cls, x: Any, y: Any) -> tuple[Restoring, float]:
        """An odd monotone-cubic (PCHIP) curve through (x, y), x ≥ 0 from 0 (rad), y(0) = 0.

        Returns the shape normalised to unit slope at 0 and that slope (y per rad).
        """
        from scipy.interpolate import PchipInterpolator

        x = np.asarray(x, float)
        y = np.asarray(y, float)
        xs = np.concatenate([-x[:0:-1], x])
        ys = np.concatenate([-y[:0:-1], y])
        d = PchipInterpolator(xs, ys).derivative()(x)
        slope = float(d[0])
        params = (float(x.size), *x.tolist(), *(y / slope).tolist(), *(d / slope).tolist())
        return cls(TABLE, params), slope

    def array(self) -> np.ndarray:
        """The parameters as the float array the integrator takes."""
        return np.asarray(self.params if self.params else (0.0,), float)

    def __call__(self, q: Any) -> np.ndarray:
        """ρ(q) (vectorised)."""
        return _restoring_values(np.asarray(q, float), self)[0]

    def slope(self, q: Any) -> np.ndarray:
        """ρ'(q) (vectorised)."""
        return _restoring_values(np.asarray(q, float), self)[1]

    def frequency_ratio(self, amplitude: float) -> float:
        """ω(a)/ω0 of the undamped oscillation of amplitude a by harmonic balance (first Fourier
        term): ω(a)²/ω0² = (1/(π a)) ∫ ρ(a cos θ) cos θ dθ over one cycle."""
        if self.kind == LINEAR or amplitude == 0:
            return 1.0
        th = np.linspace(0.0, 2.0 * math.pi, 257)[:-1]
        r = float(np.mean(self(amplitude * np.cos(th)) * np.cos(th))) * 2.0 / amplitude
        return math.sqrt(max(r, 0.0))


def _restoring_values(q: np.ndarray, shape: Restoring) -> tuple[np.ndarray, np.ndarray]:
    flat = np.atleast_1d(q).ravel()
    par = shape.array()
    rho = np.empty(flat.size)
    drho = np.empty(flat.size)
    for i, x in enumerate(flat):
        rho[i], drho[i] = _restore(float(x), shape.kind, par)
    return rho.reshape(np.shape(q)), drho.reshape(np.shape(q))


@dataclass(frozen=True)
class RigConstants:
    """Rig constants of the generalised equation (see module docstring).

    S : float — restoring stiffness, N/m (spring), N·m/rad (torsion, pendulum)
    base_inertia : float — A without the added mass: m (kg), I (kg·m²) or
        m r² + I_body + m_rod r²/3 (kg·m²)
    added_factor : float — dA/dm_a: 1 (spring, torsion) or r² (pendulum), so A = base + factor·m_a
    linear_factor : float — c_L = linear_factor·K_L: 1 or r²
    quadratic_factor : float — c_Q = quadratic_factor·K_Q: 1 or r³
    speed_factor : float — translational speed of the body per unit q̇: 1 (spring), r
        (pendulum), L_ref/2 (torsion: speed of the body's tip, for Re and KC)
    sine : bool — ρ(q) = sin q (pendulum) instead of q
    restoring : Restoring or None — a nonlinear restoring shape (floating rig); None: q or sin q
    """

    S: float
    base_inertia: float
    added_factor: float
    linear_factor: float
    quadratic_factor: float
    speed_factor: float
    sine: bool
    restoring: Restoring | None = None

    @property
    def shape(self) -> Restoring:
        """ρ(q) of this rig."""
        if self.restoring is not None:
            return self.restoring
        return Restoring(SINE if self.sine else LINEAR)

    def inertia(self, added_mass: float) -> float:
        """A = base + factor·m_a."""
        return self.base_inertia + self.added_factor * added_mass

    def added_mass(self, A: float) -> float:
        """m_a (kg or kg·m²) from the total inertia A."""
        return (A - self.base_inertia) / self.added_factor

    def to_normalised(self, added_mass: float, K_L: float, K_Q: float) -> tuple[float, float, float]:
        """(ω², b, g) from (m_a, K_L, K_Q) in reported units."""
        A = self.inertia(added_mass)
        return self.S / A, self.linear_factor * K_L / A, self.quadratic_factor * K_Q / A

    def from_normalised(self, w2: float, b: float, g: float) -> tuple[float, float, float]:
        """(m_a, K_L, K_Q) in reported units from (ω², b, g)."""
        A = self.S / w2
        return self.added_mass(A), b * A / self.linear_factor, g * A / self.quadratic_factor

    def jacobian_from_normalised(self, w2: float, b: float, g: float) -> np.ndarray:
        """∂(m_a, K_L, K_Q)/∂(ω², b, g), for propagating a covariance."""
        A = self.S / w2
        dA = -self.S / w2**2
        return np.array(
            [
                [dA / self.added_factor, 0.0, 0.0],
                [b * dA / self.linear_factor, A / self.linear_factor, 0.0],
                [g * dA / self.quadratic_factor, 0.0, A / self.quadratic_factor],
            ]
        )


def rig_constants(rig: Rig) -> RigConstants:
    """The generalised-equation constants of ``rig`` (see the module table).

    Raises
    ------
    InputError
        A pendulum whose buoyancy equals its weight (no restoring force), or a missing
        stiffness or length.
    """
    if rig.test == "spring":
        if not (rig.stiffness is not None and rig.stiffness > 0):  # also NaN
            raise InputError(f"spring.stiffness = {rig.stiffness}: expected a positive number (N/m)", rig.source)
        return RigConstants(rig.stiffness, rig.mass, 1.0, 1.0, 1.0, 1.0, False)
    if rig.test == "torsion":
        if not (rig.stiffness is not None and rig.stiffness > 0):  # also NaN
            raise InputError(f"torsion.stiffness = {rig.stiffness}: expected a positive number (N·m/rad)", rig.source)
        return RigConstants(rig.stiffness, rig.inertia, 1.0, 1.0, 1.0, 0.5 * rig.reference_length, False)
    if rig.test == "pendulum":
        r = rig.pendulum_length
        if not r or r <= 0:
            raise InputError(f"pendulum.length = {r}: expected a positive number (m)", rig.source)
        g = rig.gravity
        net = (rig.weight - rig.buoyancy) * r + (rig.rod_mass * g - rig.density * g * rig.rod_volume) * r / 2
        if abs(net) <= 1e-9 * max(rig.weight, rig.buoyancy, 1e-30) * r:
            raise InputError(
                f"body.volume = {rig.volume}: buoyancy {rig.buoyancy:.6g} N equals the weight "
                f"{rig.weight:.6g} N, so the pendulum has no restoring force; expected B ≠ W",
                rig.source,
            )
        base = rig.mass * r * r + rig.inertia + rig.rod_mass * r * r / 3.0
        return RigConstants(abs(net), base, r * r, r * r, r**3, r, True)
    if rig.test == "floating":
        return _floating_constants(rig)
    raise InputError(f"test = {rig.test!r}: expected spring, pendulum, torsion or floating", rig.source)


def _floating_constants(rig: Rig) -> RigConstants:
    """Constants of the floating-body rig (issue #16): base inertia m (heave) or I, and C1."""
    heave = rig.axis == "heave"
    base = rig.mass if heave else rig.inertia
    if base <= 0:
        raise InputError(
            f"body.inertia = {rig.inertia}: expected the dry inertia about the axis (kg·m², > 0)", rig.source
        )
    speed = 1.0 if heave else 0.5 * rig.reference_length
    kind, value = rig.floating if rig.floating is not None else ("stiffness", 0.0)
    value = cast(Any, value)
    rho_g = rig.density * rig.gravity
    shape = Restoring()
    if kind == "gm":
        S = rho_g * rig.volume * float(value)
    elif kind == "waterplane_area":
        S = rho_g * float(value)
    elif kind == "restoring":
        c1, c3, c5 = value
        S = float(c1)
        shape = Restoring.polynomial(c1, c3, c5)
    elif kind == "gz":
        ang = np.radians([row[0] for row in value])
        arm = np.asarray([row[1] for row in value], dtype=float)
        shape, gm0 = Restoring.table(ang, arm)
        S = rho_g * rig.volume * gm0
    else:
        S = float(rig.stiffness or 0.0)
    if not (S > 0 and math.isfinite(S)):
        raise InputError(f"floating restoring C1 = {S}: expected a positive number", rig.source)
    return RigConstants(S, base, 1.0, 1.0, 1.0, speed, False, shape)


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a hard dependency
        return None
    return numba


def _restore_py(q, kind, par):  # noqa: ANN001, ANN202
    """(ρ(q), ρ'(q)) for a shape code and its parameters (see :class:`Restoring`)."""
    if kind == 0:
        return q, 1.0
    if kind == 1:
        return math.sin(q), math.cos(q)
    if kind == 2:
        q2 = q * q
        return q * (1.0 + q2 * (par[0] + par[1] * q2)), 1.0 + q2 * (3.0 * par[0] + 5.0 * par[1] * q2)
    n = int(par[0])
    s = 1.0 if q >= 0.0 else -1.0
    x = abs(q)
    xe = par[n]
    if x >= xe:  # linear beyond the last knot
        return s * (par[2 * n] + par[3 * n] * (x - xe)), par[3 * n]
    i = 0
    while i < n - 2 and x >= par[2 + i]:
        i += 1
    x0 = par[1 + i]
    h = par[2 + i] - x0
    y0 = par[1 + n + i]
    y1 = par[2 + n + i]
    d0 = par[1 + 2 * n + i] * h
    d1 = par[2 + 2 * n + i] * h
    u = (x - x0) / h
    u2 = u * u
    u3 = u2 * u
    val = (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * d0 + (3 * u2 - 2 * u3) * y1 + (u3 - u2) * d1
    der = ((6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * d0 + (6 * u - 6 * u2) * y1 + (3 * u2 - 2 * u) * d1) / h
    return s * val, der


#: sensitivity columns of each parameter vector: the normalised rig frees (ω², b, g), the extended
#: one (ω², b, g, d, a3, a5); both then add (q0, v0)
NORMALISED_PARAMETERS, EXTENDED_PARAMETERS = 3, 6


def _deriv_py(z, dz, w2, b, g, d, a3, a5, nfree, kind, par, m):  # noqa: ANN001
    """Right-hand side of the rig ODE and, when m > 2, of its forward sensitivities.

    q̈ = −ω² (ρ(q) + a3 q³ + a5 q⁵) − b q̇ − g |q̇| q̇ − d q̇³ with p = (ω², b, g, d, a3, a5)
    (the normalised rig, nfree = 3, skips the d, a3 and a5 terms). z = (q, v, s_1q, s_1v, …) with
    s_k = ∂(q, v)/∂θ_k for θ = (p_0 … p_{nfree−1}, q0, v0), obeying ṡ = (∂f/∂z) s + ∂f/∂θ_k.
    The parameters come as scalars: read from an array, each store into ``dz`` would reload them.
    """
    q = z[0]
    v = z[1]
    rho, drho = _restore(q, kind, par)
    q2 = q * q
    q3 = q2 * q
    q5 = q3 * q2
    av = abs(v)
    extended = nfree == EXTENDED_PARAMETERS  # else d, a3, a5 are neither read nor freed
    r_all = rho + a3 * q3 + a5 * q5 if extended else rho
    dz[0] = v
    dz[1] = -w2 * r_all - b * v - g * av * v
    if extended:
        dz[1] -= d * v * v * v
    if m > 2:
        a_q = -w2 * (drho + 3.0 * a3 * q2 + 5.0 * a5 * q2 * q2) if extended else -w2 * drho
        a_v = -b - 2.0 * g * av
        if extended:
            a_v -= 3.0 * d * v * v
        for j in range(nfree + 2):
            if j >= nfree:  # q0, v0 enter through the seeds only
                forcing = 0.0
            elif j == 0:
                forcing = -r_all
            elif j == 1:
                forcing = -v
            elif j == 2:
                forcing = -av * v
            elif j == 3:
                forcing = -v * v * v
            elif j == 4:
                forcing = -w2 * q3
            else:
                forcing = -w2 * q5
            sq = z[2 + 2 * j]
            sv = z[3 + 2 * j]
            dz[2 + 2 * j] = sv
            dz[3 + 2 * j] = a_q * sq + a_v * sv + forcing


def _integrate_py(t, q0, v0, p, nfree, kind, par, substeps, want_jac):  # noqa: ANN001
    """Fixed-step RK4 of the rig ODE augmented with its forward sensitivities (:func:`_deriv_py`).

    Integrates from t[0] through each sample interval with ``substeps`` RK4 steps and returns
    q and q̇ at the samples and J = ∂q/∂(p_0 … p_{nfree−1}, q0, v0) (n × (nfree + 2); without
    ``want_jac`` only row 0, the seeds, is filled). The augmented state has 2 + 2 (nfree + 2)
    entries; without ``want_jac`` only (q, v) is integrated.
    """
    n = t.shape[0]
    ns = nfree + 2
    nz = 2 + 2 * ns
    out_q = np.empty(n)
    out_v = np.empty(n)
    jac = np.zeros((n, ns))
    z = np.zeros(nz)
    z[0] = q0
    z[1] = v0
    z[2 + 2 * nfree] = 1.0  # ∂q/∂q0
    z[2 + 2 * (nfree + 1) + 1] = 1.0  # ∂v/∂v0
    m = nz if want_jac else 2
    zm = z[:m]
    k1 = np.empty(m)
    k2 = np.empty(m)
    k3 = np.empty(m)
    k4 = np.empty(m)
    tmp = np.empty(m)
    w2, b, g, d, a3, a5 = p[0], p[1], p[2], p[3], p[4], p[5]
    out_q[0] = z[0]
    out_v[0] = z[1]
    for j in range(ns):
        jac[0, j] = z[2 + 2 * j]
    for i in range(1, n):
        h = (t[i] - t[i - 1]) / substeps
        for _ in range(substeps):
            # core.integrate's RK4 arithmetic on the first m entries (zm is z's view)
            _deriv(z, k1, w2, b, g, d, a3, a5, nfree, kind, par, m)
            _stage(zm, k1, 0.5 * h, tmp)
            _deriv(tmp, k2, w2, b, g, d, a3, a5, nfree, kind, par, m)
            _stage(zm, k2, 0.5 * h, tmp)
            _deriv(tmp, k3, w2, b, g, d, a3, a5, nfree, kind, par, m)
            _stage(zm, k3, h, tmp)
            _deriv(tmp, k4, w2, b, g, d, a3, a5, nfree, kind, par, m)
            _combine(zm, k1, k2, k3, k4, h)
        out_q[i] = z[0]
        out_v[i] = z[1]
        if want_jac:
            for j in range(ns):
                jac[i, j] = z[2 + 2 * j]
    return out_q, out_v, jac


_nb = _numba()
if _nb is not None:
    from hydrokit._numba import compile_law, njit

    # the RK4 step's arithmetic, written once in core/integrate.py (as simulate.compiled compiles it)
    _stage = compile_law(rk4_stage_into, rk4_stage=compile_law(rk4_stage))
    _combine = compile_law(rk4_combine_into, rk4_update=compile_law(rk4_update))
    _restore = njit(_restore_py)
    _deriv = njit(inline="always")(_deriv_py)
    _integrate = njit(_integrate_py)
else:  # pragma: no cover
    _stage, _combine = rk4_stage_into, rk4_combine_into
    _restore = _restore_py
    _deriv = _deriv_py
    _integrate = _integrate_py


def simulate_normalised(
    t: np.ndarray,
    w2: float,
    b: float,
    g: float,
    q0: float,
    v0: float = 0.0,
    sine: bool = False,
    substeps: int = 4,
    jacobian: bool = False,
    restoring: Restoring | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integrate q̈ = −ω² ρ(q) − b q̇ − g |q̇| q̇ on the sample times ``t`` (compiled RK4).

    Parameters
    ----------
    t : (n,) array — sample times, s, increasing
    w2 : float — ω², 1/s²
    b : float — linear damping per inertia, 1/s
    g : float — quadratic damping per inertia, 1/(unit of q)
    q0, v0 : float — initial q (m or rad) and q̇ (m/s or rad/s) at t[0]
    sine : bool — pendulum restoring sin q instead of q
    substeps : int — RK4 steps per sample interval (default 4)
    jacobian : bool — also integrate the forward sensitivities
    restoring : Restoring, optional — the shape ρ(q) (overrides ``sine``; floating rig)

    Returns
    -------
    q, qdot : (n,) arrays
    J : (n, 5) array — ∂q/∂(ω², b, g, q0, v0) (unless ``jacobian``, zeros after row 0, which
        holds the seed ∂q0/∂q0 = 1)
    """
    t = np.ascontiguousarray(t, dtype=float)
    shape = restoring if restoring is not None else Restoring(SINE if sine else LINEAR)
    p = np.array([w2, b, g, 0.0, 0.0, 0.0], dtype=float)
    return _integrate(
        t, float(q0), float(v0), p, NORMALISED_PARAMETERS, shape.kind, shape.array(), int(substeps), bool(jacobian)
    )


def simulate_extended(
    t: np.ndarray,
    p: Any,
    q0: float,
    v0: float = 0.0,
    restoring: Restoring | None = None,
    substeps: int = 4,
    jacobian: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integrate q̈ = −ω² (ρ(q) + a3 q³ + a5 q⁵) − b q̇ − g |q̇| q̇ − d q̇³ (cubic damping and
    restoring corrections, ``--damping-model cubic`` / ``--restoring-terms``).

    Parameters
    ----------
    t : (n,) array — sample times, s
    p : 6 floats — (ω² 1/s², b 1/s, g 1/unit, d s/unit², a3 1/unit², a5 1/unit⁴), unit = m or rad
    q0, v0 : float — initial state at t[0] (m or rad, m/s or rad/s; default: released from rest)
    restoring : Restoring, optional — ρ(q) (default linear)
    substeps : int — RK4 steps per sample interval (default 4)
    jacobian : bool — also integrate the forward sensitivities

    Returns
    -------
    q, qdot : (n,) arrays
    J : (n, 8) array — ∂q/∂(ω², b, g, d, a3, a5, q0, v0) (zeros unless ``jacobian``)
    """
    t = np.ascontiguousarray(t, dtype=float)
    shape = restoring if restoring is not None else Restoring()
    pp = np.ascontiguousarray(np.asarray(p, float).reshape(6))
    return _integrate(
        t, float(q0), float(v0), pp, EXTENDED_PARAMETERS, shape.kind, shape.array(), int(substeps), bool(jacobian)
    )


def simulate_rig(
    rig: Rig,
    t: np.ndarray,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    y0: float,
    v0: float = 0.0,
    substeps: int = 4,
) -> np.ndarray:
    """The rig's free decay sampled at ``t`` (SPEC S1, P1 / physical pendulum, T1).

    Parameters
    ----------
    rig : Rig
    t : (n,) array — sample times, s
    added_mass : float — m_a, kg (kg·m² for torsion)
    linear_damping : float — K_L, N·s/m (N·m·s/rad for torsion)
    quadratic_damping : float — K_Q, N·s²/m² (N·m·s²/rad² for torsion)
    y0 : float — initial displacement at t[0], m (spring) or rad
    v0 : float — initial rate, m/s or rad/s
    substeps : int — RK4 steps per sample interval (default 4)

    Returns
    -------
    (n,) array — position (m) or angle (rad)
    """
    c = rig_constants(rig)
    if c.inertia(added_mass) <= 0:
        raise InputError(f"added_mass = {added_mass}: total inertia must be positive")
    w2, b, g = c.to_normalised(added_mass, linear_damping, quadratic_damping)
    q, _, _ = simulate_normalised(np.asarray(t, float), w2, b, g, y0, v0, c.sine, substeps, restoring=c.restoring)
    return q
