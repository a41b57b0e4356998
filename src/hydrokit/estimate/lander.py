"""Box-like landers: LI2021 eq. 7 empirical inertial derivatives (SPEC §2.2).

Non-dimensional (divide by ½ρL³, ½ρL⁴ or ½ρL⁵):

    X'_udot = −(π/3)(B/L)(H/L) K11          Y'_vdot = −(π/3)(B/L)(H/L) K22
    Z'_wdot = −(π/3)(B/L)(H/L) K33          M'_qdot = −(π/60)(B/L)(H/L)(1 + B²/L²) K55
    N'_rdot = −(π/60)(B/L)(H/L)(1 + B²/L²) K66   (the formula as printed)

LI2021 prints N'_rdot = −5.6888e−3 for Lingyun (L = 1.25, B = 0.47, H = 0.93, K66 = 0.25); the
formula with B gives −4.18e−3, and the printed number is reproduced with H in place of B,
(1 + H²/L²). ``paper_nrdot=True`` reproduces the printed value; the default follows the formula.
"""

from __future__ import annotations

import math

from hydrokit.errors import InputError

LI2021_FACTORS = {"K11": 0.2, "K22": 1.3, "K33": 0.4, "K55": 0.8, "K66": 0.25}


def lander_derivatives(
    length: float, breadth: float, height: float, factors: dict[str, float] | None = None, paper_nrdot: bool = False
) -> dict[str, float]:
    """Non-dimensional X'_udot, Y'_vdot, Z'_wdot, M'_qdot, N'_rdot (negative numbers).

    Parameters
    ----------
    length, breadth, height : float — L, B, H of the box, m
    factors : dict — K11, K22, K33, K55, K66 (default LI2021's)
    paper_nrdot : bool — use (1 + H²/L²) in N'_rdot, reproducing LI2021's printed value
    """
    for k, v in (("length", length), ("breadth", breadth), ("height", height)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"{k} = {v}: expected a positive dimension (m)")
    K = dict(LI2021_FACTORS)
    K.update(factors or {})
    b, h = breadth / length, height / length
    base = math.pi / 3 * b * h
    rot = math.pi / 60 * b * h
    return {
        "X_udot": -base * K["K11"],
        "Y_vdot": -base * K["K22"],
        "Z_wdot": -base * K["K33"],
        "M_qdot": -rot * (1 + b * b) * K["K55"],
        "N_rdot": -rot * (1 + (h * h if paper_nrdot else b * b)) * K["K66"],
    }


def dimensional_added_mass(nd: dict[str, float], density: float, length: float) -> list[float]:
    """Diagonal added mass magnitudes [A11, A22, A33, 0, A55, A66] (kg, kg·m²) from the
    non-dimensional derivatives: force terms × ½ρL³, moment terms × ½ρL⁵ (roll not given)."""
    q3 = 0.5 * density * length**3
    q5 = 0.5 * density * length**5
    return [-nd["X_udot"] * q3, -nd["Y_vdot"] * q3, -nd["Z_wdot"] * q3, 0.0, -nd["M_qdot"] * q5, -nd["N_rdot"] * q5]
