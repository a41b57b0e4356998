"""Hull forces of a body of revolution from its profile (issue #45 item 3): cross-flow drag by
strips and viscous hull lift, for vehicles that have no coefficient table.

The profile is the ``x, r`` format of ``hydrokit cfd`` (:mod:`hydrokit.io.profile`): x (m) runs
aft from the nose, r (m) is the local radius, linear between points. The vehicle's body axes have
their origin on the axis ``origin`` metres aft of the nose, x pointing to the nose, so a profile
station x sits at body x_b = origin − x. Everything here is numpy on plain arrays, SI units.

Cross-flow drag (Prestero 2001, MIT MS thesis, §4: "crossflow drag"; after Hoerner 1965,
*Fluid-Dynamic Drag*, ch. 3). A strip dx at body x_b with diameter 2 r(x) sees the cross-flow
velocity of its own point, v_c = (v + x_b r, w − x_b q), and feels

    dF = −½ ρ C_dc 2 r(x) |v_c| v_c dx                                         (1)

C_dc is the drag coefficient of a circular cylinder in cross-flow: 1.1–1.2 in subcritical flow
(Hoerner 1965, ch. 3; DNV-RP-C205 (2010) §6.7, a smooth cylinder in steady flow below the drag
crisis); Prestero takes 1.1 from Hoerner, the default here (:data:`CYLINDER_CROSSFLOW_DRAG`).
Above the drag crisis (cross-flow Reynolds number 2r|v_c|/ν beyond ≈ 2–5·10⁵) C_dc falls to
0.3–0.7; a small AUV turning stays well below it. Two ways of putting (1) into a vehicle:

* **Strips** (:func:`crossflow_strips`, the default of the vehicle file's ``hull:`` block): the
  hull cut into n strips, each a point drag element (:mod:`hydrokit.core.drag`) at the strip's
  area centroid with quadratic coefficient Q_k = ½ ρ C_dc ∫_strip 2 r dx on the y and z axes. A
  drag element sees the velocity of its own point, v + x_b r and w − x_b q, so sway and yaw
  combine **along the hull** as (1) says — in a turn the cross-flow changes sign along the body,
  which separate Y_v|v| and Y_r|r| terms cannot express. The approximation: the elements are
  per-axis quadratic, Q |v_y| v_y and Q |v_z| v_z, instead of Q √(v_y² + v_z²) v_y; in pure
  horizontal or pure vertical cross-flow it is (1) exactly, at a combined incidence it
  underestimates the force (by 1/√2 at 45° between v and w). The moment arm of each strip is its
  centroid: the yaw moment of a uniform cylinder in pure yaw is off by the midpoint rule's
  2/n² (relative).
* **Derivative terms** (:func:`crossflow_derivatives`, ``crossflow_drag: terms``), Prestero's
  integrals: Y_v|v| = Z_w|w| = −½ρC_dc ∫2r dx, M_w|w| = −N_v|v| = ½ρC_dc ∫2r x_b dx,
  Y_r|r| = −Z_q|q| = −½ρC_dc ∫2r x_b|x_b| dx, M_q|q| = N_r|r| = −½ρC_dc ∫2r x_b²|x_b| dx. Each is
  (1) for one velocity alone; sums of them are wrong when v and r act together (a turn).

Viscous hull lift (Prestero 2001 §4 "body lift", after Hoerner & Borst 1985, *Fluid-Dynamic
Lift*): a force across the hull linear in the incidence, acting at the centre of pressure x_cp
(body x), written as derivative terms (SNAME signs, SI):

    Y_uv = Z_uw = −½ ρ d² c_ydβ,   N_uv = −½ ρ d² x_cp c_ydβ,   M_uw = +½ ρ d² x_cp c_ydβ      (2)

(the moment is x_cp × the force: N = x_cp Y, M = −x_cp Z). c_ydβ (1/rad) is the body-lift slope;
Hoerner's empirical value, the one Prestero uses for REMUS (c_ydβ = 1.2 at l/d = 6.98), is
0.003 (l/d) per degree (:func:`hoerner_body_lift_slope`). Prestero's REMUS x_cp = −0.321 m lies
0.70 l aft of the nose (nose 0.611 m ahead of his origin, l = 1.333 m): the default here
(:data:`LIFT_CENTER_FRACTION`). These terms are the viscous lift only; the potential-flow part of a
hull at incidence (the Munk moment, N = −(Y_v̇ − X_u̇) u v for a slender body) is the added-mass
Coriolis term C_A(ν)ν of the vehicle model, not repeated here.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit.errors import InputError

Array = NDArray[np.float64]

#: cross-flow drag coefficient of a circular cylinder, subcritical (Hoerner 1965 ch. 3: 1.1–1.2;
#: DNV-RP-C205 2010 §6.7); the value Prestero 2001 §4 takes for REMUS
CYLINDER_CROSSFLOW_DRAG = 1.1
#: Hoerner's body-lift slope per degree and per unit fineness ratio l/d (Prestero 2001 §4)
HOERNER_BODY_LIFT_PER_DEGREE = 0.003
#: centre of pressure of the viscous hull lift, as a fraction of the length aft of the nose
#: (Prestero 2001's REMUS: x_cp = −0.321 m, nose at +0.611 m, l = 1.333 m → 0.70)
LIFT_CENTER_FRACTION = 0.70
#: default number of cross-flow strips
DEFAULT_STRIPS = 20

# three-point Gauss–Legendre rule on [0, 1]: exact for polynomials up to degree 5, so every
# integral below (r linear per piece times x_b^k with k ≤ 3, split where x_b changes sign) is exact
_GAUSS_T = 0.5 + 0.5 * np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
_GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


def check_hull_profile(x: ArrayLike, r: ArrayLike, source: str = "profile") -> tuple[Array, Array]:
    """The profile as float arrays, refused in one line when it is not a body's outline.

    Parameters
    ----------
    x : array_like — stations aft of the nose, strictly increasing, m
    r : array_like — radius at each station, ≥ 0, m (the ends need not be closed: a truncated
        nose or tail is a strip like any other)
    source : str — the file or field named in the message

    Returns
    -------
    (x, r) : float arrays, m

    Raises
    ------
    InputError
        Fewer than 2 points, unequal lengths, a non-finite value, x not increasing, a negative
        radius, or no radius > 0 at all.
    """
    xa, ra = np.asarray(x, dtype=float), np.asarray(r, dtype=float)
    if xa.ndim != 1 or xa.shape != ra.shape or len(xa) < 2:
        raise InputError(f"profile of {xa.size} x and {ra.size} r values: expected ≥ 2 (x, r) points, m", source)
    for name, col in (("x", xa), ("r", ra)):
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise InputError(f"profile {name}[{bad[0]}] = {col[bad[0]]}: expected finite metres", source)
    back = np.flatnonzero(np.diff(xa) <= 0)
    if back.size:
        i = int(back[0])
        raise InputError(
            f"profile x goes from {xa[i]:g} to {xa[i + 1]:g} m at point {i + 1}: expected x increasing from the nose",
            source,
        )
    neg = np.flatnonzero(ra < 0)
    if neg.size:
        raise InputError(f"profile r[{neg[0]}] = {ra[neg[0]]:g} m: expected a radius ≥ 0", source)
    if not np.any(ra > 0):
        raise InputError("profile has r = 0 everywhere: expected a body (some radius > 0)", source)
    return xa, ra


def _nodes(x: Array, r: Array, breaks: Array) -> tuple[Array, Array, Array]:
    """Quadrature nodes (profile x, radius r, weight w) over the whole profile, the pieces cut at
    the profile's points and at ``breaks`` (profile x), so that ∫ f dx = Σ w f(x_node) is exact for
    f = r · polynomial of degree ≤ 4 on each piece."""
    edges = np.unique(np.concatenate([x, breaks[(breaks > x[0]) & (breaks < x[-1])]]))
    a, h = edges[:-1], np.diff(edges)
    xn = (a[:, None] + h[:, None] * _GAUSS_T[None, :]).ravel()
    wn = (h[:, None] * _GAUSS_W[None, :]).ravel()
    return xn, np.interp(xn, x, r), wn


def profile_centroid(x: ArrayLike, r: ArrayLike) -> float:
    """Volume centroid of the body of revolution, m aft of the nose: ∫x r² dx / ∫r² dx (the
    origin ``hydrokit cfd`` gives a profile body; exact for a profile linear between points)."""
    xa, ra = check_hull_profile(x, r)
    xn, rn, wn = _nodes(xa, ra, np.zeros(0))
    return float(np.sum(wn * xn * rn**2) / np.sum(wn * rn**2))


def crossflow_strips(
    x: ArrayLike,
    r: ArrayLike,
    origin: float,
    density: float,
    drag_coefficient: float = CYLINDER_CROSSFLOW_DRAG,
    strips: int = DEFAULT_STRIPS,
) -> tuple[Array, Array]:
    """Cross-flow drag (1) of the module docstring as ``strips`` point elements.

    Parameters
    ----------
    x, r : array_like — the profile: stations aft of the nose and radii, m
    origin : float — the body origin's distance aft of the nose along the axis, m
    density : float — fluid density ρ, kg/m³
    drag_coefficient : float — C_dc of a circular cylinder in cross-flow, dimensionless
    strips : int — number of strips of equal length, ≥ 1

    Returns
    -------
    positions : (n,) — each strip's area centroid ∫x_b r dx / ∫r dx in body x, m
    quadratic : (n,) — Q_k = ½ ρ C_dc ∫_strip 2 r dx, N·s²/m², for both the y and z axes

    Notes
    -----
    Σ Q_k = ½ρC_dc ∫2r dx exactly (the sway force of pure sway); the moments use the centroid of
    each strip as its lever (midpoint rule: relative error ≈ 2/n² on a cylinder's yaw moment).
    """
    xa, ra = check_hull_profile(x, r)
    n = int(strips)
    if n < 1 or n != strips:
        raise InputError(f"strips = {strips!r}: expected a whole number ≥ 1")
    edges = np.linspace(xa[0], xa[-1], n + 1)
    xn, rn, wn = _nodes(xa, ra, edges)
    k = np.clip(np.searchsorted(edges, xn, side="right") - 1, 0, n - 1)
    area = np.bincount(k, weights=wn * 2.0 * rn, minlength=n)
    first = np.bincount(k, weights=wn * 2.0 * rn * (origin - xn), minlength=n)
    mid = origin - 0.5 * (edges[:-1] + edges[1:])
    positions = np.where(area > 0, first / np.where(area > 0, area, 1.0), mid)
    quadratic = np.asarray(0.5 * density * drag_coefficient * area, dtype=float)
    return np.asarray(positions, dtype=float), quadratic


def crossflow_derivatives(
    x: ArrayLike,
    r: ArrayLike,
    origin: float,
    density: float,
    drag_coefficient: float = CYLINDER_CROSSFLOW_DRAG,
) -> dict[str, float]:
    """Prestero's (2001 §4) cross-flow drag derivatives of the hull (SNAME signs, SI).

    Parameters
    ----------
    x, r : array_like — the profile, m
    origin : float — the body origin's distance aft of the nose, m
    density : float — ρ, kg/m³
    drag_coefficient : float — C_dc, dimensionless

    Returns
    -------
    dict — term name → coefficient: ``Y_v|v|``, ``Z_w|w|`` (kg/m), ``M_w|w|``, ``N_v|v|`` (kg),
    ``Y_r|r|``, ``Z_q|q|`` (kg·m), ``M_q|q|``, ``N_r|r|`` (kg·m²); the integrals of the module
    docstring, exact for a profile linear between its points.
    """
    xa, ra = check_hull_profile(x, r)
    xn, rn, wn = _nodes(xa, ra, np.array([origin]))
    xb = origin - xn
    c = 0.5 * density * drag_coefficient
    i0 = c * float(np.sum(wn * 2.0 * rn))
    i1 = c * float(np.sum(wn * 2.0 * rn * xb))
    i2 = c * float(np.sum(wn * 2.0 * rn * xb * np.abs(xb)))
    i3 = c * float(np.sum(wn * 2.0 * rn * xb * xb * np.abs(xb)))
    return {
        "Y_v|v|": -i0,
        "Z_w|w|": -i0,
        "M_w|w|": i1,
        "N_v|v|": -i1,
        "Y_r|r|": -i2,
        "Z_q|q|": i2,
        "M_q|q|": -i3,
        "N_r|r|": -i3,
    }


def hoerner_body_lift_slope(length: float, diameter: float) -> float:
    """Hoerner's body-lift slope c_ydβ = 0.003 (l/d) per degree, returned per radian (1/rad).

    ``length`` and ``diameter`` in m. Prestero 2001 §4 uses it for REMUS: 1.2 at l/d = 6.98.
    """
    return HOERNER_BODY_LIFT_PER_DEGREE * (length / diameter) * 180.0 / math.pi


def hull_lift_derivatives(diameter: float, density: float, lift_slope: float, center: float) -> dict[str, float]:
    """Viscous hull-lift derivatives (2) of the module docstring (SNAME signs, SI).

    Parameters
    ----------
    diameter : float — hull diameter d, m
    density : float — ρ, kg/m³
    lift_slope : float — body-lift slope c_ydβ, 1/rad
    center : float — centre of pressure x_cp in body x, m (negative: aft of the origin)

    Returns
    -------
    dict — ``Y_uv``, ``Z_uw`` (kg/m), ``N_uv``, ``M_uw`` (kg).
    """
    lift = 0.5 * density * diameter * diameter * lift_slope
    return {"Y_uv": -lift, "Z_uw": -lift, "N_uv": -lift * center, "M_uw": lift * center}
