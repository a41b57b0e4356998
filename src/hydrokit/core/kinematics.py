"""Kinematics: Euler angles (zyx) and unit quaternions (Fossen 2011 §2.2).

η = [x, y, z, φ, θ, ψ] in north-east-down (NED); ν = [u, v, w, p, q, r] in body axes.
Euler: η̇ = J(η) ν with J = diag(R(Θ), T(Θ)) (Fossen eq. 2.40; LI2021 eq. 2), singular at
θ = ±90°. Quaternions q = [η, ε1, ε2, ε3] (scalar first) have no singularity:
q̇ = ½ Ω(ω) q (Fossen eq. 2.82).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

#: |θ| beyond which Euler-angle integration is flagged (T(Θ) has 1/cos θ)
PITCH_WARNING = math.radians(85.0)


def rotation_zyx_entries(cf: Any, sf: Any, ct: Any, st: Any, cp: Any, sp: Any) -> tuple[Any, ...]:  # noqa: ANN401
    """The nine entries of R_b^n(Θ) (Fossen 2011 eq. 2.18) from the cosines and sines of φ, θ, ψ:
    the one law of the zyx rotation matrix.

    Parameters
    ----------
    cf, sf, ct, st, cp, sp : float or ndarray
        cos φ, sin φ, cos θ, sin θ, cos ψ, sin ψ (dimensionless); arrays give arrays, element
        by element (:func:`rotation_zyx_many`).

    Returns
    -------
    tuple of 9
        R00, R01, R02, R10, R11, R12, R20, R21, R22 (row by row), dimensionless.

    Notes
    -----
    R = R_z(ψ) R_y(θ) R_x(φ) multiplied out. It takes the trigonometric values, not the angles,
    so that a compiled right-hand side that needs cos φ, sin φ, cos θ, sin θ again for T(Θ)
    (:func:`hydrokit.simulate.compiled.deriv`) computes them once; it is compiled there by
    ``compile_law`` (and :func:`rotation_zyx_into` with it), not copied.
    """
    return (
        cp * ct,
        -sp * cf + cp * st * sf,
        sp * sf + cp * cf * st,
        sp * ct,
        cp * cf + sf * st * sp,
        -cp * sf + st * sp * cf,
        -st,
        ct * sf,
        ct * cf,
    )


def rotation_zyx_into(phi: float, theta: float, psi: float, R: Any) -> None:  # noqa: ANN401
    """R_b^n(Θ) of :func:`rotation_zyx_entries` written into the 3×3 array ``R`` (no allocation:
    the compiled kernels' form).

    Parameters
    ----------
    phi, theta, psi : float
        Roll φ, pitch θ and yaw ψ, rad.
    R : ndarray, shape (3, 3)
        Filled with R (v_NED = R v_body).
    """
    cf, sf = math.cos(phi), math.sin(phi)
    ct, st = math.cos(theta), math.sin(theta)
    cp, sp = math.cos(psi), math.sin(psi)
    R00, R01, R02, R10, R11, R12, R20, R21, R22 = rotation_zyx_entries(cf, sf, ct, st, cp, sp)
    R[0, 0], R[0, 1], R[0, 2] = R00, R01, R02
    R[1, 0], R[1, 1], R[1, 2] = R10, R11, R12
    R[2, 0], R[2, 1], R[2, 2] = R20, R21, R22


def rotation_zyx(phi: float, theta: float, psi: float) -> np.ndarray:
    """R_b^n(Θ): the body → NED rotation matrix of zyx Euler angles (Fossen 2011 eq. 2.18).

    Parameters
    ----------
    phi, theta, psi : float
        Roll φ, pitch θ and yaw ψ, rad.

    Returns
    -------
    ndarray, shape (3, 3)
        R with v_NED = R v_body; its third row is the NED "down" axis in body axes.

    Notes
    -----
    Called at every step of the closed loop and every stage of the numpy model, so it is
    scalar ``math`` and one array (a few µs), not a product of three elementary rotations.
    The entries are :func:`rotation_zyx_entries`'s, the law the compiled kernels use too.
    """
    cf, sf = math.cos(phi), math.sin(phi)
    ct, st = math.cos(theta), math.sin(theta)
    cp, sp = math.cos(psi), math.sin(psi)
    return np.array(rotation_zyx_entries(cf, sf, ct, st, cp, sp)).reshape(3, 3)


def rotation_zyx_many(angles: np.ndarray) -> np.ndarray:
    """:func:`rotation_zyx` for many attitudes at once: ``angles`` (N, 3) rows φ, θ, ψ (rad)
    → (N, 3, 3). :func:`rotation_zyx_entries` on arrays (post-processing of long runs)."""
    a = np.asarray(angles, dtype=float).reshape(-1, 3)
    trig = (np.cos(a[:, 0]), np.sin(a[:, 0]), np.cos(a[:, 1]), np.sin(a[:, 1]), np.cos(a[:, 2]), np.sin(a[:, 2]))
    R = np.empty((len(a), 3, 3))
    for k, entry in enumerate(rotation_zyx_entries(*trig)):
        R[:, k // 3, k % 3] = entry
    return R


def euler_rate_matrix(phi: float, theta: float) -> np.ndarray:
    """T(Θ): body rates → Euler-angle rates (Fossen eq. 2.29); singular at θ = ±90°."""
    cf, sf = math.cos(phi), math.sin(phi)
    ct, tt = math.cos(theta), math.tan(theta)
    return np.array([[1.0, sf * tt, cf * tt], [0.0, cf, -sf], [0.0, sf / ct, cf / ct]])


def J_euler(eta: np.ndarray) -> np.ndarray:
    """The 6×6 J(η) = diag(R, T) of η̇ = J(η) ν."""
    J = np.zeros((6, 6))
    J[:3, :3] = rotation_zyx(eta[3], eta[4], eta[5])
    J[3:, 3:] = euler_rate_matrix(eta[3], eta[4])
    return J


def euler_to_quaternion(phi: float, theta: float, psi: float) -> np.ndarray:
    """Unit quaternion [η, ε1, ε2, ε3] of the zyx Euler angles (rad)."""
    c1, s1 = math.cos(psi / 2), math.sin(psi / 2)
    c2, s2 = math.cos(theta / 2), math.sin(theta / 2)
    c3, s3 = math.cos(phi / 2), math.sin(phi / 2)
    return np.array(
        [
            c1 * c2 * c3 + s1 * s2 * s3,
            c1 * c2 * s3 - s1 * s2 * c3,
            c1 * s2 * c3 + s1 * c2 * s3,
            s1 * c2 * c3 - c1 * s2 * s3,
        ]
    )


def quaternion_rotation_entries(n: float, e1: float, e2: float, e3: float) -> tuple[float, ...]:
    """The nine entries of R(q) for a unit quaternion q = [η, ε1, ε2, ε3] (Fossen 2011 eq. 2.72):
    the one law of the quaternion rotation matrix, on plain floats.

    Parameters
    ----------
    n, e1, e2, e3 : float
        η, ε1, ε2, ε3 of a unit quaternion (dimensionless; normalise first, the formula assumes
        |q| = 1).

    Returns
    -------
    tuple of 9
        R00, R01, R02, R10, R11, R12, R20, R21, R22 (row by row), dimensionless.
    """
    return (
        1 - 2 * (e2 * e2 + e3 * e3),
        2 * (e1 * e2 - e3 * n),
        2 * (e1 * e3 + e2 * n),
        2 * (e1 * e2 + e3 * n),
        1 - 2 * (e1 * e1 + e3 * e3),
        2 * (e2 * e3 - e1 * n),
        2 * (e1 * e3 - e2 * n),
        2 * (e2 * e3 + e1 * n),
        1 - 2 * (e1 * e1 + e2 * e2),
    )


def quaternion_to_rotation(q: np.ndarray) -> np.ndarray:
    """R(q) for a unit quaternion [η, ε1, ε2, ε3] (Fossen eq. 2.72), of
    :func:`quaternion_rotation_entries`."""
    n, e1, e2, e3 = q
    return np.array(quaternion_rotation_entries(n, e1, e2, e3)).reshape(3, 3)


def quaternion_to_euler(q: np.ndarray) -> np.ndarray:
    """(φ, θ, ψ) in rad of a unit quaternion (Fossen eq. 2.77)."""
    R = quaternion_to_rotation(np.asarray(q, float) / np.linalg.norm(q))
    phi = math.atan2(R[2, 1], R[2, 2])
    theta = -math.asin(max(-1.0, min(1.0, R[2, 0])))
    psi = math.atan2(R[1, 0], R[0, 0])
    return np.array([phi, theta, psi])


def quaternion_rate(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """q̇ = ½ Ω(ω) q for body rates ω = [p, q, r] (rad/s)."""
    n, e1, e2, e3 = q
    p, qq, r = w
    return 0.5 * np.array(
        [
            -e1 * p - e2 * qq - e3 * r,
            n * p + e2 * r - e3 * qq,
            n * qq + e3 * p - e1 * r,
            n * r + e1 * qq - e2 * p,
        ]
    )


def wrap_angle(a: float) -> float:
    """Wrap an angle to [−π, π).

    Parameters
    ----------
    a : float
        Angle, rad (any value).

    Returns
    -------
    float
        a + 2πk in [−π, π), rad.
    """
    return (a + math.pi) % (2.0 * math.pi) - math.pi
