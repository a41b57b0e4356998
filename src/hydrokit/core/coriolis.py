"""Coriolis–centripetal matrices from a mass matrix (Fossen 2011 Theorem 3.2, eq. 3.46 and 6.43).

For a 6×6 mass matrix M = [[M11, M12], [M21, M22]] and ν = [ν1, ν2] (linear, angular),

    C(ν) = [[0, −S(M11ν1 + M12ν2)], [−S(M11ν1 + M12ν2), −S(M21ν1 + M22ν2)]],

skew-symmetric for every ν, so νᵀC(ν)ν = 0: it neither creates nor removes kinetic energy. The
same formula gives C_RB from M_RB and C_A from M_A (the symmetric part is used).
"""

from __future__ import annotations

import numpy as np

from hydrokit.core.rigid_body import skew


def coriolis_matrix(M: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """C(ν) of the 6×6 mass matrix M (kg, kg·m) at ν (m/s, rad/s)."""
    Ms = 0.5 * (np.asarray(M, float) + np.asarray(M, float).T)
    nu = np.asarray(nu, float)
    a = Ms[:3, :3] @ nu[:3] + Ms[:3, 3:] @ nu[3:]
    b = Ms[3:, :3] @ nu[:3] + Ms[3:, 3:] @ nu[3:]
    C = np.zeros((6, 6))
    C[:3, 3:] = -skew(a)
    C[3:, :3] = -skew(a)
    C[3:, 3:] = -skew(b)
    return C


def coriolis_force(M: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """C(ν) ν without forming C: [ω × a; v × a + ω × b]."""
    Ms = 0.5 * (np.asarray(M, float) + np.asarray(M, float).T)
    nu = np.asarray(nu, float)
    mv = Ms @ nu
    a, b = mv[:3], mv[3:]
    v, w = nu[:3], nu[3:]
    return np.concatenate([np.cross(w, a), np.cross(v, a) + np.cross(w, b)])
