"""Force–speed regression (SPEC §1.4, CELY2019 §4.1, CHIN2012).

Chin model F = K_L U + K_Q |U| U and Morison model F = K_D |U| U (C_D = 2 K_D / (ρ A_ref)),
both linear least squares with standard errors σ̂ √diag((XᵀX)⁻¹) and R² = 1 − SS_res/SS_tot.
CELY2019 Table 5 (UDrobot CFD, 0.2–10 m/s) implies ½ρA_ref = K_D/C_D = 24.69 (x) and 45.20 (y, z)
N·s²/m², i.e. A_ref ≈ 0.0495 and 0.0906 m² at ρ = 998.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.validate import finite_samples
from hydrokit.errors import InputError


@dataclass(frozen=True)
class ForceFit(Result):
    """Both fits (SI): K_L N·s/m, K_Q and K_D N·s²/m², C_D –, standard errors alike.

    ``speed`` (m/s) and ``force`` (N) keep the fitted data for plots and tables; ``area`` (m²)
    and ``density`` (kg/m³) are the reference area and fluid density of C_D.
    """

    K_L: float
    K_Q: float
    K_L_se: float
    K_Q_se: float
    r2_chin: float
    K_D: float
    K_D_se: float
    C_D: float
    r2_morison: float
    n: int

    speed: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False, compare=False)
    force: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False, compare=False)
    area: float = math.nan
    density: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        """Both fits with area and density (what ``hydrokit fit-forces --json`` writes)."""
        keys = (
            "K_L",
            "K_Q",
            "K_L_se",
            "K_Q_se",
            "r2_chin",
            "K_D",
            "K_D_se",
            "C_D",
            "r2_morison",
            "n",
            "area",
            "density",
        )
        return jsonable({k: getattr(self, k) for k in keys})

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Rows of speed (m/s), measured force, Chin and Morison fits (N)."""
        U = np.asarray(self.speed, float)
        return (
            ["speed", "force", "chin", "morison"],
            np.column_stack([U, self.force, self.chin(U), self.morison(U)]).tolist(),
        )

    def plot(self, ax: Any = None) -> Any:
        """Data and both fitted curves on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.forces import force_fit_axes

        return force_fit_axes(np.asarray(self.speed, float), np.asarray(self.force, float), self, ax)

    def chin(self, U: np.ndarray) -> np.ndarray:
        return self.K_L * U + self.K_Q * np.abs(U) * U

    def morison(self, U: np.ndarray) -> np.ndarray:
        return self.K_D * np.abs(U) * U


def _r2(y: np.ndarray, fit: np.ndarray) -> float:
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    return 1.0 - float(np.sum((y - fit) ** 2)) / ss_tot if ss_tot > 0 else float("nan")


def _weights(sigma: np.ndarray | None, n: int) -> np.ndarray:
    """1/σ per point (ones without σ); σ must be finite and ≥ 0."""
    if sigma is None:
        return np.ones(n)
    sd = np.asarray(sigma, float)
    if sd.shape != (n,):
        raise InputError(f"sigma has shape {sd.shape}: expected one standard deviation per force ({n})")
    finite_samples(sd, "sigma", "N")
    if np.any(sd < 0):
        raise InputError(f"sigma holds {float(sd.min()):g} N: expected standard deviations >= 0")
    floor = float(sd[sd > 0].min()) if np.any(sd > 0) else 1.0
    return 1.0 / np.maximum(sd, floor)


def fit_forces(
    speed: np.ndarray, force: np.ndarray, area: float, density: float, sigma: np.ndarray | None = None
) -> ForceFit:
    """Fit the Chin and Morison models to speed (m/s) / force (N) pairs.

    Parameters
    ----------
    speed, force : arrays — U (m/s) and the resisting force F (N), same sign convention
    area : float — A_ref, m²
    density : float — ρ, kg/m³
    sigma : array, optional — standard deviation of each force, N (CFD iterative or unsteadiness
        σ). Given, both fits are weighted least squares (weights 1/σ²) and the standard errors
        are the larger of the formal ones (σ taken as absolute) and the scatter-scaled ones, so
        neither a poor model nor an overconfident σ is hidden. Zero σ counts as the smallest
        positive σ given (or 1 N when all are zero).
    """
    U = np.asarray(speed, float)
    F = np.asarray(force, float)
    if U.shape != F.shape or U.ndim != 1:
        raise InputError(f"speed and force must be 1-D of equal length, got {U.shape} and {F.shape}")
    if U.size < 3:
        raise InputError(f"only {U.size} point(s); expected at least 3 speed–force pairs to fit two coefficients")
    finite_samples(U, "speed", "m/s")
    finite_samples(F, "force", "N")
    if np.ptp(F) == 0:  # R² would be 0/0: nothing the models could explain
        raise InputError(
            f"force: all {F.size} forces are {F[0]:g} N: nothing to fit; expected resisting forces that change "
            "with speed (N)"
        )
    if np.unique(np.abs(U)).size < 2:
        raise InputError("all speeds are equal in magnitude; expected at least two different speeds")
    for k, v in (("area", area), ("density", density)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"{k} = {v}: expected a positive number")
    if not (area * density > 0 and math.isfinite(2.0 / (area * density))):  # C_D = 2 K_D / (ρ A)
        raise InputError(
            f"area = {area:.4g} m², density = {density:.4g} kg/m³: ρ A = {area * density:.4g} kg/m leaves C_D beyond "
            "the float range; expected a realistic reference area and density"
        )
    w = _weights(sigma, U.size)
    X = np.column_stack([U, np.abs(U) * U])
    Xw, Fw = X * w[:, None], F * w
    coef, *_ = np.linalg.lstsq(Xw, Fw, rcond=None)
    res = Fw - Xw @ coef
    s2 = float(res @ res) / max(1, U.size - 2)
    cov = (s2 if sigma is None else max(s2, 1.0)) * np.linalg.inv(Xw.T @ Xw)
    x1 = np.abs(U) * U
    xw = x1 * w
    kd = float(xw @ Fw / (xw @ xw))
    r1 = Fw - kd * xw
    s1 = float(r1 @ r1) / max(1, U.size - 1)
    kd_se = math.sqrt((s1 if sigma is None else max(s1, 1.0)) / float(xw @ xw))
    return ForceFit(
        float(coef[0]),
        float(coef[1]),
        math.sqrt(cov[0, 0]),
        math.sqrt(cov[1, 1]),
        _r2(F, X @ coef),
        kd,
        kd_se,
        2 * kd / (density * area),
        _r2(F, kd * x1),
        int(U.size),
        U,
        F,
        float(area),
        float(density),
    )
