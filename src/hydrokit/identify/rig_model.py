"""Free-decay rig models (SPEC §1.1–1.3) and their compiled integrator.

All three rigs reduce to one generalised equation in the recorded coordinate q (m for the
spring, rad for the pendulum and the torsion rig):

    A q̈ + c_L q̇ + c_Q |q̇| q̇ + S ρ(q) = 0,        ρ(q) = q (spring, torsion) or sin q (pendulum)

with the rig constants

=========  ===================================  ==============  ==============  =====================
rig        A (inertia)                          c_L             c_Q             S (restoring)
=========  ===================================  ==============  ==============  =====================
spring     m + m_a                               K_L             K_Q             k
torsion    I + I_a                               K_L             K_Q             K
pendulum   (m + m_a) r² + I_body + m_rod r²/3    K_L r²          K_Q r³          |(W − B) r + (W_rod − B_rod) r/2|
=========  ===================================  ==============  ==============  =====================

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

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig


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
    """

    S: float
    base_inertia: float
    added_factor: float
    linear_factor: float
    quadratic_factor: float
    speed_factor: float
    sine: bool

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
        if not rig.stiffness or rig.stiffness <= 0:
            raise InputError(f"spring.stiffness = {rig.stiffness}: expected a positive number (N/m)", rig.source)
        return RigConstants(rig.stiffness, rig.mass, 1.0, 1.0, 1.0, 1.0, False)
    if rig.test == "torsion":
        if not rig.stiffness or rig.stiffness <= 0:
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
    raise InputError(f"test = {rig.test!r}: expected spring, pendulum or torsion", rig.source)


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a hard dependency
        return None
    return numba


def _rhs(q: float, v: float, w2: float, b: float, g: float, sine: bool) -> tuple[float, float]:
    rho = math.sin(q) if sine else q
    return v, -w2 * rho - b * v - g * abs(v) * v


def _simulate_py(t, q0, v0, w2, b, g, sine, substeps, want_jac):  # noqa: ANN001
    """Fixed-step RK4 of the normalised rig ODE with forward sensitivities.

    Integrates from t[0] through each sample interval with ``substeps`` RK4 steps and
    returns q at the samples, q̇ at the samples and ∂q/∂(ω², b, g, q0, v0) (n × 5).
    The state is z = (q, v, s_1q, s_1v, …, s_5q, s_5v) with s_k = ∂(q, v)/∂p_k obeying
    ṡ = (∂f/∂z) s + ∂f/∂p_k.
    """
    n = t.shape[0]
    out_q = np.empty(n)
    out_v = np.empty(n)
    jac = np.zeros((n, 5))
    z = np.zeros(12)
    z[0] = q0
    z[1] = v0
    z[2 + 2 * 3] = 1.0  # ∂q/∂q0
    z[2 + 2 * 4 + 1] = 1.0  # ∂v/∂v0
    k1 = np.empty(12)
    k2 = np.empty(12)
    k3 = np.empty(12)
    k4 = np.empty(12)
    tmp = np.empty(12)
    m = 12 if want_jac else 2

    out_q[0] = z[0]
    out_v[0] = z[1]
    for j in range(5):
        jac[0, j] = z[2 + 2 * j]
    for i in range(1, n):
        h = (t[i] - t[i - 1]) / substeps
        for _ in range(substeps):
            _deriv(z, k1, w2, b, g, sine, m)
            for c in range(m):
                tmp[c] = z[c] + 0.5 * h * k1[c]
            _deriv(tmp, k2, w2, b, g, sine, m)
            for c in range(m):
                tmp[c] = z[c] + 0.5 * h * k2[c]
            _deriv(tmp, k3, w2, b, g, sine, m)
            for c in range(m):
                tmp[c] = z[c] + h * k3[c]
            _deriv(tmp, k4, w2, b, g, sine, m)
            for c in range(m):
                z[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c])
        out_q[i] = z[0]
        out_v[i] = z[1]
        if want_jac:
            for j in range(5):
                jac[i, j] = z[2 + 2 * j]
    return out_q, out_v, jac


def _deriv_py(z, dz, w2, b, g, sine, m):  # noqa: ANN001
    q = z[0]
    v = z[1]
    if sine:
        rho = math.sin(q)
        drho = math.cos(q)
    else:
        rho = q
        drho = 1.0
    av = abs(v)
    dz[0] = v
    dz[1] = -w2 * rho - b * v - g * av * v
    if m > 2:
        a_q = -w2 * drho
        a_v = -b - 2.0 * g * av
        forcing = (-rho, -v, -av * v, 0.0, 0.0)
        for j in range(5):
            sq = z[2 + 2 * j]
            sv = z[3 + 2 * j]
            dz[2 + 2 * j] = sv
            dz[3 + 2 * j] = a_q * sq + a_v * sv + forcing[j]


_nb = _numba()
if _nb is not None:
    _deriv = _nb.njit(cache=True)(_deriv_py)
    _simulate = _nb.njit(cache=True)(_simulate_py)
else:  # pragma: no cover
    _deriv = _deriv_py
    _simulate = _simulate_py


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
    substeps : int — RK4 steps per sample interval
    jacobian : bool — also integrate the forward sensitivities

    Returns
    -------
    q, qdot : (n,) arrays
    J : (n, 5) array — ∂q/∂(ω², b, g, q0, v0) (zeros unless ``jacobian``)
    """
    t = np.ascontiguousarray(t, dtype=float)
    return _simulate(t, float(q0), float(v0), float(w2), float(b), float(g), bool(sine), int(substeps), bool(jacobian))


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
    substeps : int — RK4 steps per sample interval

    Returns
    -------
    (n,) array — position (m) or angle (rad)
    """
    c = rig_constants(rig)
    if c.inertia(added_mass) <= 0:
        raise InputError(f"added_mass = {added_mass}: total inertia must be positive")
    w2, b, g = c.to_normalised(added_mass, linear_damping, quadratic_damping)
    q, _, _ = simulate_normalised(np.asarray(t, float), w2, b, g, y0, v0, c.sine, substeps)
    return q
