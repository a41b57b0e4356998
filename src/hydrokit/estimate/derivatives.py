"""Hydrodynamic derivatives from force sweeps (LI2021 §2.2: virtual tow tank and rotating arm).

A sweep gives the body-axis loads (X Y Z K M N) at known velocities (u v w p q r). Each load is
regressed on products of velocities by weighted least squares (weights 1/σ² from the CFD σ of
each point), as LI2021 regressed its virtual tow-tank and rotating-arm forces into Table 4:

    drift (β):      Y = Y_uv u v + Y_v|v| v|v|        N = N_uv u v + N_v|v| v|v|
    attack (α):     Z = Z_uw u w + Z_w|w| w|w|        M = M_uw u w + M_w|w| w|w|
    yaw rate:       Y = Y_ur u r                      N = N_ur u r + N_r|r| r|r|
    pitch rate:     Z = Z_uq u q                      M = M_uq u q + M_q|q| q|q|
    straight ahead: X = X_u|u| u|u|

Each product term's SI value is also given non-dimensionally, divided by ½ρL^k with k as in
:mod:`hydrokit.model.terms` (2 for two linear velocities, 3 for a linear velocity times a rate
or a moment of two linear velocities, 4 …), and as the linear derivative at the reference speed
U (Y_v = Y_uv U; non-dimensional Y'_v = Y_v / (½ρL²U), LI2021's form).

A term is fitted only when the sweep has at least one more distinct point than terms; a
quadratic term needs points on both sides of zero or of two magnitudes, else only the linear
one is fitted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hydrokit.errors import InputError

_VEL = "uvwpqr"
_LOAD = "XYZKMN"


@dataclass(frozen=True)
class Derivative:
    """One fitted derivative.

    name : str — SNAME term name readable by the vehicle file's ``terms:`` grammar (``Y_uv``)
    value, se : float — SI value and standard error
    nondimensional, nondimensional_se : float — divided by ½ρL^k
    k : int — the power of L
    points : int — sweep points fitted
    """

    name: str
    value: float
    se: float
    nondimensional: float
    nondimensional_se: float
    k: int
    points: int


def _product(term: str, nu: np.ndarray) -> np.ndarray:
    """u v, v|v| … of a term's factor string (two factors, the second possibly |·|)."""
    out = np.ones(len(nu))
    i = 0
    while i < len(term):
        if term[i] == "|":
            out = out * np.abs(nu[:, _VEL.index(term[i + 1])])
            i += 3
        else:
            out = out * nu[:, _VEL.index(term[i])]
            i += 1
    return out


def _power(load: str, term: str) -> int:
    rates = sum(1 for c in term if c in "pqr")
    return 2 + rates + (load in "KMN")


def fit_derivatives(
    nu: np.ndarray,
    loads: np.ndarray,
    sigma: np.ndarray,
    model: dict[str, list[str]],
    *,
    density: float,
    length: float,
) -> list[Derivative]:
    """Fit loads to products of velocities.

    Parameters
    ----------
    nu : (n, 6) — body velocities u v w (m/s) and p q r (rad/s) of the sweep's points
    loads : (n, 6) — X Y Z (N) and K M N (N·m)
    sigma : (n, 6) — their standard deviations (0 allowed: the smallest positive σ is used)
    model : dict — load letter → factor strings, e.g. ``{"Y": ["uv", "v|v|"]}``
    density : float — ρ, kg/m³
    length : float — L, m

    Returns
    -------
    list of Derivative — in the model's order; terms the points cannot support are left out
    """
    nu, loads, sigma = (np.asarray(a, float) for a in (nu, loads, sigma))
    if nu.ndim != 2 or nu.shape[1] != 6 or loads.shape != nu.shape or sigma.shape != nu.shape:
        raise InputError(f"nu, loads and sigma must be (n, 6) arrays, got {nu.shape}, {loads.shape}, {sigma.shape}")
    if not (math.isfinite(density) and density > 0 and math.isfinite(length) and length > 0):
        raise InputError(f"density = {density}, length = {length}: expected positive numbers (kg/m³, m)")
    out: list[Derivative] = []
    for load, terms in model.items():
        j = _LOAD.index(load)
        y = loads[:, j]
        keep = np.isfinite(y) & np.isfinite(sigma[:, j])
        cols = [_product(t, nu[keep]) for t in terms]
        usable = [k for k, c in enumerate(cols) if np.ptp(c) > 0 or np.any(c != 0)]
        terms_used = [terms[k] for k in usable]
        X = np.column_stack([cols[k] for k in usable]) if usable else np.zeros((int(keep.sum()), 0))
        # drop terms until the points support them (distinct regressor rows > terms)
        while X.shape[1] and (
            np.unique(np.round(X, 12), axis=0).shape[0] <= X.shape[1] or np.linalg.matrix_rank(X) < X.shape[1]
        ):
            X, terms_used = X[:, :-1], terms_used[:-1]
        if not X.shape[1]:
            continue
        sd = sigma[keep, j]
        floor = float(sd[sd > 0].min()) if np.any(sd > 0) else 1.0
        w = 1.0 / np.maximum(sd, floor)
        Xw, yw = X * w[:, None], y[keep] * w
        coef, *_ = np.linalg.lstsq(Xw, yw, rcond=None)
        res = yw - Xw @ coef
        dof = X.shape[0] - X.shape[1]
        s2 = float(res @ res) / dof if dof > 0 else 0.0
        cov = max(s2, 1.0) * np.linalg.pinv(Xw.T @ Xw)
        for t, c, v in zip(terms_used, coef, np.diag(cov), strict=True):
            k = _power(load, t)
            scale = 0.5 * density * length**k
            se = math.sqrt(max(float(v), 0.0))
            out.append(Derivative(f"{load}_{t}", float(c), se, float(c) / scale, se / scale, k, int(keep.sum())))
    return out


def linear_at(
    d: Derivative, speed: float, density: float, length: float
) -> tuple[str, float, float, float, float] | None:
    """A ``*_u?`` product derivative as the linear derivative at speed U.

    Y_uv → (``Y_v``, Y_uv U, se U, Y_v/(½ρL²U), se'); None for a term without a ``u`` factor.
    Non-dimensional: divided by ½ρL^k U, k as the product's.
    """
    load, factors = d.name.split("_", 1)
    if not factors.startswith("u") or len(factors) != 2:
        return None
    scale = 0.5 * density * length**d.k * speed
    return (f"{load}_{factors[1]}", d.value * speed, d.se * speed, d.value * speed / scale, d.se * speed / scale)
