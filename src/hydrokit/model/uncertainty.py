"""Coefficient uncertainty of a vehicle: the ``uncertainty:`` block of a vehicle file.

``hydrokit run`` writes the standard errors of the chosen diagonal coefficients and their
covariance; :func:`make_uncertainty` checks such a block and :meth:`Uncertainty.draw` samples
vehicles from it (one seeded generator, so the same seed gives the same vehicles on any
machine). The parameters are named ``"<coefficient>.<dof>"`` with coefficient one of
``added_mass`` (kg, kg·m²), ``linear_damping`` (N·s/m, N·m·s/rad) or ``quadratic_damping``
(N·s²/m², N·m·s²/rad²) and dof one of surge … yaw.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError

#: the diagonal coefficients an uncertainty block may name
COEFFICIENTS = ("added_mass", "linear_damping", "quadratic_damping")
#: relative asymmetry, and negative eigenvalue relative to the largest, tolerated in a covariance
#: (the run writes a symmetric matrix; round-off of a hand-made one is no error)
COVARIANCE_TOLERANCE = 1e-9


def check_parameter(name: Any, what: str, source: str) -> tuple[str, int]:
    """(coefficient, DOF index) of ``"<coefficient>.<dof>"``, or an error starting with ``what``
    (``"field 'uncertainty.parameters[2]' ="``, ``"variation"``)."""
    coef, _, dof = str(name).partition(".")
    if not isinstance(name, str) or coef not in COEFFICIENTS or dof not in DOF_NAMES:
        raise InputError(
            f"{what} {str(name)[:80]!r}: expected '<coefficient>.<dof>' with coefficient one of "
            f"{', '.join(COEFFICIENTS)} and dof one of {', '.join(DOF_NAMES)}",
            source,
        )
    return coef, DOF_NAMES.index(dof)


def diagonal(vehicle: Any, name: str) -> float:
    """The vehicle's current value of the diagonal coefficient ``name`` (SI)."""
    coef, i = check_parameter(name, "parameter", "")
    if coef == "added_mass":
        return float(vehicle.M_A[i, i])
    if coef == "linear_damping":
        return float(vehicle.D_L[i, i])
    return float(vehicle.D_Q[i])


def with_coefficients(vehicle: Any, values: Any) -> Any:
    """``vehicle`` with diagonal coefficients replaced; ``values`` maps ``"<coefficient>.<dof>"``
    to the new value (SI). Off-diagonal entries and everything else are kept."""
    M_A, D_L, D_Q = vehicle.M_A.copy(), vehicle.D_L.copy(), np.array(vehicle.D_Q, float)
    for key, v in values.items():
        coef, i = check_parameter(key, "variation", "")
        if coef == "added_mass":
            M_A[i, i] = v
        elif coef == "linear_damping":
            D_L[i, i] = v
        else:
            D_Q[i] = v
    return replace(vehicle, M_A=M_A, D_L=D_L, D_Q=D_Q)


@dataclass(frozen=True, eq=False)
class Uncertainty:
    """Covariance of a vehicle's diagonal coefficients (SI, full scale).

    Attributes
    ----------
    parameters : tuple of str — ``"<coefficient>.<dof>"``, one per row of ``covariance``
    covariance : (p, p) — symmetric positive semi-definite, in the squared units of the parameters
    """

    parameters: tuple[str, ...]
    covariance: np.ndarray

    @property
    def std(self) -> np.ndarray:
        """Standard deviation σ of each parameter (SI)."""
        return np.sqrt(np.clip(np.diag(self.covariance), 0.0, None))

    def draw(self, mean: np.ndarray, n: int, seed: int) -> tuple[np.ndarray, int]:
        """``n`` parameter vectors from N(mean, covariance), negatives set to 0.

        One ``numpy.random.default_rng(seed)``; the eigen-decomposition method, so a singular
        covariance (a parameter with σ = 0, or two that move together) is fine.
        Returns the (n, p) samples and how many entries were clipped at zero.
        """
        rng = np.random.default_rng(seed)
        if not self.parameters:
            return np.zeros((n, 0)), 0
        x = rng.multivariate_normal(np.asarray(mean, float), self.covariance, size=n, method="eigh")
        clipped = int(np.sum(x < 0))
        return np.maximum(x, 0.0), clipped

    def sample_vehicles(self, vehicle: Any, n: int, seed: int) -> tuple[list[Any], np.ndarray, int]:
        """``n`` copies of ``vehicle`` whose parameters are drawn about its own values.

        Returns the vehicles, the (n, p) drawn values (SI) and the count clipped at zero.
        """
        mean = np.array([diagonal(vehicle, p) for p in self.parameters], float)
        values, clipped = self.draw(mean, n, seed)
        vehicles = [with_coefficients(vehicle, dict(zip(self.parameters, row))) for row in values]
        return vehicles, values, clipped


def make_uncertainty(parameters: Any, covariance: Any, sigma: dict[str, Any], source: str) -> Uncertainty | None:
    """Check an uncertainty block and build it (None when it states no σ at all).

    Parameters
    ----------
    parameters : list of str — names of the covariance's rows (may be empty)
    covariance : (p, p) nested lists — SI², symmetric positive semi-definite
    sigma : coefficient → 6 standard errors (SI) per DOF; a σ > 0 whose parameter the
        covariance does not hold is added as an independent parameter; one it holds must
        equal the square root of its diagonal entry (rel. 1e-6)
    source : str — the file named in errors

    Raises
    ------
    InputError
        One line naming the field (``uncertainty.covariance``, ``uncertainty.parameters[2]`` …).
    """
    names = list(parameters or [])
    for k, name in enumerate(names):
        check_parameter(name, f"field 'uncertainty.parameters[{k}]' =", source)
    if len(set(names)) != len(names):
        dup = next(p for p in names if names.count(p) > 1)
        raise InputError(f"field 'uncertainty.parameters' names {dup!r} twice; expected each parameter once", source)
    p = len(names)
    try:
        cov = np.asarray(covariance if covariance is not None else np.zeros((0, 0)), dtype=float)
    except (TypeError, ValueError):
        cov = np.full((1,), np.nan)
    if p == 0 and cov.size == 0:
        cov = np.zeros((0, 0))
    if cov.shape != (p, p) or not np.all(np.isfinite(cov)):
        raise InputError(
            f"field 'uncertainty.covariance': shape {cov.shape}; expected a {p}×{p} matrix of finite numbers "
            "(one row per entry of uncertainty.parameters, SI²)",
            source,
        )
    scale = float(np.max(np.abs(cov), initial=0.0))
    if p and float(np.max(np.abs(cov - cov.T))) > COVARIANCE_TOLERANCE * scale:
        raise InputError("field 'uncertainty.covariance': not symmetric; expected a covariance matrix", source)
    if p and float(np.linalg.eigvalsh(cov).min()) < -COVARIANCE_TOLERANCE * scale:
        raise InputError(
            f"field 'uncertainty.covariance': smallest eigenvalue {float(np.linalg.eigvalsh(cov).min()):.4g}; "
            "expected a positive semi-definite matrix (a covariance)",
            source,
        )
    extra: list[tuple[str, float]] = []
    for coef in COEFFICIENTS:
        for i, s in enumerate(sigma.get(coef) or ()):
            name = f"{coef}.{DOF_NAMES[i]}"
            if name in names:
                stated = math.sqrt(max(cov[names.index(name)][names.index(name)], 0.0))
                if not math.isclose(s, stated, rel_tol=1e-6, abs_tol=1e-300):
                    raise InputError(
                        f"field 'uncertainty.{coef}' = {s:.6g} for {DOF_NAMES[i]}: the covariance gives σ = "
                        f"{stated:.6g}; expected the square root of its diagonal entry",
                        source,
                    )
            elif s > 0:
                extra.append((name, s))
    if extra:
        names += [n for n, _ in extra]
        full = np.zeros((len(names), len(names)))
        full[:p, :p] = cov
        for k, (_, s) in enumerate(extra):
            full[p + k, p + k] = s * s
        cov = full
    if not names:
        return None
    return Uncertainty(tuple(names), 0.5 * (cov + cov.T))
