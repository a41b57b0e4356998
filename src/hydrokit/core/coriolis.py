"""Coriolis–centripetal matrices from a mass matrix (Fossen 2011 Theorem 3.2, eq. 3.46 and 6.43).

For a 6×6 mass matrix M = [[M11, M12], [M21, M22]] and ν = [ν1, ν2] (linear, angular),

    C(ν) = [[0, −S(M11ν1 + M12ν2)], [−S(M11ν1 + M12ν2), −S(M21ν1 + M22ν2)]],

skew-symmetric for every ν, so νᵀC(ν)ν = 0: it neither creates nor removes kinetic energy. The
same formula gives C_RB from M_RB and C_A from M_A (the symmetric part is used).
"""

from __future__ import annotations

import numpy as np

from hydrokit.core.rigid_body import skew


def _symmetric(M: np.ndarray, symmetric: bool) -> np.ndarray:
    # Theorem 3.2 needs M = Mᵀ; a measured or estimated M_A may be off by round-off
    M = np.asarray(M, float)
    return M if symmetric else 0.5 * (M + M.T)


def coriolis_matrix(M: np.ndarray, nu: np.ndarray, *, symmetric: bool = False) -> np.ndarray:
    """C(ν) of a 6×6 mass matrix (Fossen 2011 Theorem 3.2).

    Parameters
    ----------
    M : ndarray, shape (6, 6)
        Mass matrix M_RB, M_A or their sum: kg, kg·m and kg·m² blocks.
    nu : ndarray, shape (6,)
        ν = [u, v, w, p, q, r]: m/s and rad/s (use ν_r, relative to the water, for M_A).
    symmetric : bool, optional, keyword-only
        M is already exactly symmetric: skip symmetrising it (its symmetric part is used).

    Returns
    -------
    ndarray, shape (6, 6)
        C(ν), skew-symmetric; C(ν) ν in N and N·m.
    """
    Ms = _symmetric(M, symmetric)
    nu = np.asarray(nu, float)
    a = Ms[:3, :3] @ nu[:3] + Ms[:3, 3:] @ nu[3:]
    b = Ms[3:, :3] @ nu[:3] + Ms[3:, 3:] @ nu[3:]
    C = np.zeros((6, 6))
    C[:3, 3:] = -skew(a)
    C[3:, :3] = -skew(a)
    C[3:, 3:] = -skew(b)
    return C


def coriolis_force(M: np.ndarray, nu: np.ndarray, *, symmetric: bool = False) -> np.ndarray:
    """C(ν) ν without forming C: with [a; b] = M ν, C(ν) ν = [ω × a; v × a + ω × b].

    The one numpy implementation of the Coriolis–centripetal force: the vehicle model
    (:func:`hydrokit.model.dynamics.hydro_force`) calls it, and the compiled right-hand
    side (:func:`hydrokit.simulate.compiled.deriv`) is tested against it.

    Parameters
    ----------
    M : ndarray, shape (6, 6)
        Mass matrix: kg, kg·m and kg·m² blocks.
    nu : ndarray, shape (6,)
        ν = [v; ω]: m/s and rad/s.
    symmetric : bool, optional, keyword-only
        M is already exactly symmetric: skip symmetrising it (the model symmetrises once,
        not at every call).

    Returns
    -------
    ndarray, shape (6,)
        C(ν) ν: forces in N, moments in N·m (the model subtracts it from τ).
    """
    Ms = _symmetric(M, symmetric)
    nu = np.asarray(nu, float)
    mv = Ms @ nu
    a, b = mv[:3], mv[3:]
    v, w = nu[:3], nu[3:]
    return np.concatenate([np.cross(w, a), np.cross(v, a) + np.cross(w, b)])
