"""Rigid-body matrices (Fossen 2011, ch. 3 and 6). numpy only, SI units.

Shared by the vehicle model (M_RB) and by composite bodies (moving 6×6 matrices between
origins).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]


def skew(a: ArrayLike) -> Array:
    """Skew-symmetric cross-product matrix S(a), so that S(a) b = a × b."""
    x, y, z = np.asarray(a, dtype=float).reshape(3)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def shift_matrix(r: ArrayLike) -> Array:
    """The 6×6 transform H(r) of Fossen 2011 eq. 7.12.

    For a point P at ``r`` (m) from the origin O, ν_P = H(r) ν_O, and a 6×6 matrix M_P
    expressed about P moves to O as ``H(r).T @ M_P @ H(r)``; ``H(-r)`` undoes ``H(r)``.
    """
    H = np.eye(6)
    H[0:3, 3:6] = skew(r).T
    return H


def move_matrix(M_P: ArrayLike, r: ArrayLike) -> Array:
    """Express a 6×6 mass-like or damping matrix given about point P (at ``r``, m, from O)
    about O: Hᵀ(r) M_P H(r) (Fossen 2011 eq. 7.13). Keeps symmetry and definiteness."""
    H = shift_matrix(r)
    return H.T @ np.asarray(M_P, dtype=float) @ H


def inertia_tensor(inertia: ArrayLike) -> Array:
    """A 3×3 inertia tensor (kg·m²) from 3 principal values or a 3×3 array."""
    a = np.asarray(inertia, dtype=float)
    if a.shape == (3,):
        return np.diag(a)
    if a.shape == (3, 3):
        return a.copy()
    raise ValueError(f"inertia must have 3 values or be 3x3, got shape {a.shape}")


def parallel_axis(I_cg: ArrayLike, mass: float, r: ArrayLike) -> Array:
    """Inertia about a point at −r from the centre of gravity (i.e. CG at ``r`` from it):
    I_O = I_CG − m S(r)² (Fossen 2011 eq. 3.37). kg·m²."""
    S = skew(r)
    return inertia_tensor(I_cg) - mass * S @ S


def rigid_body_mass_matrix(mass: float, I_cg: ArrayLike, r_g: ArrayLike) -> Array:
    """M_RB about the body origin for a body of ``mass`` (kg) with inertia ``I_cg`` (kg·m²,
    about the CG) and CG at ``r_g`` (m) from the origin (Fossen 2011 eq. 3.44)."""
    S = skew(r_g)
    M = np.zeros((6, 6))
    M[0:3, 0:3] = mass * np.eye(3)
    M[0:3, 3:6] = -mass * S
    M[3:6, 0:3] = mass * S
    M[3:6, 3:6] = parallel_axis(I_cg, mass, r_g)
    return M
