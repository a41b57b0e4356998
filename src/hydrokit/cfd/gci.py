"""Grid convergence: Richardson extrapolation and Roache's grid convergence index.

ITTC 7.5-03-01-01 (2017), Roache (1998), Celik et al. (2008, J. Fluids Eng. 130:078001). Three
solutions S1 (fine), S2, S3 (coarse) on grids refined by ratios r21 = h2/h1 and r32 = h3/h2:

    ε21 = S2 − S1,  ε32 = S3 − S2,  R = ε21 / ε32

* 0 < R < 1 — monotonic convergence. Observed order p from
  p = |ln|ε32/ε21| + q(p)| / ln r21,  q(p) = ln((r21^p − s)/(r32^p − s)),  s = sign(ε32/ε21)
  (solved by fixed-point iteration; q = 0 for a constant ratio), extrapolated value
  S_ext = S1 − ε21 / (r21^p − 1) and GCI = F_s |ε21| / (r21^p − 1) (absolute, in the units of S).
  F_s = 1.25 in the asymptotic range (|p/p_th − 1| ≤ 0.1, p_th = 2 for second-order schemes),
  3 otherwise.
* R < 0 — oscillatory convergence: U = ½ (max − min) of the three solutions, no extrapolation.
* R ≥ 1 — divergence: U = F_s · max(|ε21|, |ε32|) with F_s = 3, no extrapolation.
* ε21 = ε32 = 0 — the three agree: U = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: theoretical order of the discretisation (second-order schemes)
P_THEORY = 2.0


@dataclass(frozen=True)
class GridStudy:
    """Richardson extrapolation of one quantity over three grids.

    kind : str — monotonic, oscillatory, diverging or converged (all three equal)
    order : float — observed order p (nan unless monotonic)
    extrapolated : float — S_ext (nan unless monotonic)
    gci : float — uncertainty of the fine-grid value, in the units of S (absolute)
    safety : float — F_s used
    """

    kind: str
    order: float
    extrapolated: float
    gci: float
    safety: float


def grid_study(s1: float, s2: float, s3: float, r21: float, r32: float | None = None) -> GridStudy:
    """Richardson extrapolation and GCI of fine, medium and coarse solutions (see module docstring).

    Parameters
    ----------
    s1, s2, s3 : float — solutions on the fine, medium and coarse grids
    r21, r32 : float — refinement ratios h2/h1 and h3/h2 (> 1; r32 defaults to r21)
    """
    r32 = r21 if r32 is None else r32
    if not (r21 > 1 and r32 > 1):
        raise ValueError(f"refinement ratios {r21}, {r32}: expected both > 1 (coarse/fine cell size)")
    e21, e32 = s2 - s1, s3 - s2
    if e21 == 0 and e32 == 0:
        return GridStudy("converged", math.nan, s1, 0.0, 1.25)
    if e32 == 0 or e21 / e32 >= 1:
        return GridStudy("diverging", math.nan, math.nan, 3.0 * max(abs(e21), abs(e32)), 3.0)
    R = e21 / e32
    if R < 0:
        return GridStudy("oscillatory", math.nan, math.nan, 0.5 * (max(s1, s2, s3) - min(s1, s2, s3)), 1.0)
    if e21 == 0:
        return GridStudy("converged", math.nan, s1, 0.0, 1.25)
    s = 1.0 if e32 / e21 > 0 else -1.0
    p = abs(math.log(abs(e32 / e21))) / math.log(r21)
    for _ in range(100):
        q = math.log((r21**p - s) / (r32**p - s))
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) < 1e-12:
            p = p_new
            break
        p = p_new
    fs = 1.25 if abs(p / P_THEORY - 1.0) <= 0.1 else 3.0
    denom = r21**p - 1.0
    return GridStudy("monotonic", p, s1 - e21 / denom, fs * abs(e21) / denom, fs)
