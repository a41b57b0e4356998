"""Wind loads on the part of a vehicle above the water (issue #48 item 4).

The relative wind is the air's velocity past the vehicle, in body axes:

    u_w, v_w = Rᵀ v_w,NED (x, y),     v_w,NED = −V_w [cos β_w, sin β_w, 0]
    u_R = u − u_w,  v_R = v − v_w,  V_R² = u_R² + v_R²,  γ_R = atan2(v_R, u_R)

with V_w the true wind speed (m/s), β_w the true direction it blows *from* (rad, clockwise from
North, the meteorological convention of the run files' ``wind_direction``) and u, v the
vehicle's velocity over the ground (m/s; the current does not move the air). γ_R is the angle the
relative wind comes from, measured from the bow, positive from starboard (0 head wind, π/2 on the
starboard beam, ±π from astern) — the same sense as the heading and β_w. The loads
(Fossen 2011 §8.1; 2021 §10.1):

    X = ½ ρ_a V_R² A_F C_X(γ_R),  Y = ½ ρ_a V_R² A_L C_Y(γ_R),  N = ½ ρ_a V_R² A_L L_oa C_N(γ_R)

in body axes (X forward, Y to starboard, N turning the bow to starboard): A_F is the frontal
(transverse) projected area, A_L the lateral one, L_oa the length overall. Signs follow the axes:
a head wind gives C_X < 0, a wind from starboard C_Y < 0.

The coefficients C_X, C_Y, C_N come from either

``table``
    rows over γ_R (rad) interpolated linearly: from 0 to π for a hull symmetric port and
    starboard (the starboard side; the port side mirrors, C_Y and C_N change sign), or from −π to π;
``blendermann1994``
    Blendermann's parameter set for merchant ships (W. Blendermann 1994, *Parameter
    identification of wind loads on ships*, J. Wind Eng. Ind. Aerodyn. 51, 339–351; tabulated in
    Fossen's Handbook, 2nd ed. 2021, §10.1, and in the MSS toolbox's blendermann94.m, whose
    table this is). With a = |γ_R|,
    CD_l,AF = CD_l,AF(0) for a ≤ π/2 and CD_l,AF(π) beyond, CD_l = CD_l,AF A_F / A_L:

        den = 1 − ½ δ (1 − CD_l / CD_t) sin²(2a)
        C_X = −CD_l,AF cos a / den
        C_Y = −sign(γ_R) CD_t sin a / den
        C_N = C_Y (s_L / L_oa − 0.18 (a − π/2))

    s_L the longitudinal position of the lateral area's centroid forward of midship (m). The
    formula is written for one side (0 ≤ a ≤ π) and mirrored for the other, so that the yaw
    moment turns the bow away from a wind forward of the beam on either side.

:func:`wind_wrench` and :func:`wind_coefficients` are the only implementations: the numpy model
(:mod:`hydrokit.model.dynamics`) calls them as Python, the compiled integrators
(:mod:`hydrokit.simulate.compiled`) compile the same functions with numba. They read the packed
row of :meth:`WindModel.pack` (``WIND_HEAD`` numbers, then the table's 4 n numbers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.errors import InputError

#: air density at 15 °C and sea level (ISA), kg/m³
AIR_DENSITY = 1.225

#: packed head: [kind, ½ρA_F, ½ρA_L, ½ρA_L L, mirrored, CD_t, CD_lAF(0), CD_lAF(π), δ, s_L/L, A_F/A_L, n]
WIND_HEAD = 12
KIND_NONE, KIND_BLENDERMANN, KIND_TABLE = 0.0, 1.0, 2.0

#: Blendermann (1994) as the MSS toolbox's blendermann94.m tabulates it (after Fossen, §10.1):
#: CD_t, CD_l,AF(0), CD_l,AF(π), δ (κ, the roll factor, is not used: the wind model gives surge,
#: sway and yaw). The drilling vessel's published
#: ranges 0.70–1.00 and 0.75–1.10 are taken at their middle, as in the MSS toolbox.
BLENDERMANN_1994: dict[str, tuple[float, float, float, float]] = {
    "car_carrier": (0.95, 0.55, 0.60, 0.80),
    "cargo_vessel_loaded": (0.85, 0.65, 0.55, 0.40),
    "cargo_vessel_container_on_deck": (0.85, 0.55, 0.50, 0.40),
    "container_ship_loaded": (0.90, 0.55, 0.55, 0.40),
    "destroyer": (0.85, 0.60, 0.65, 0.65),
    "diving_support_vessel": (0.90, 0.60, 0.80, 0.55),
    "drilling_vessel": (1.00, 0.85, 0.925, 0.10),
    "ferry": (0.90, 0.45, 0.50, 0.80),
    "fishing_vessel": (0.95, 0.70, 0.70, 0.40),
    "lng_tanker": (0.70, 0.60, 0.65, 0.50),
    "offshore_supply_vessel": (0.90, 0.55, 0.80, 0.55),
    "passenger_liner": (0.90, 0.40, 0.40, 0.80),
    "research_vessel": (0.85, 0.55, 0.65, 0.60),
    "speed_boat": (0.90, 0.55, 0.60, 0.60),
    "tanker_loaded": (0.70, 0.90, 0.55, 0.40),
    "tanker_in_ballast": (0.70, 0.75, 0.55, 0.40),
    "tender": (0.85, 0.55, 0.55, 0.65),
}

MODELS = ("table", "blendermann1994")


def wind_coefficients(w, first, gamma):  # noqa: ANN001, ANN201
    """(C_X, C_Y, C_N) of the wind model packed at ``w[first:]`` at the relative wind angle
    ``gamma`` (rad, from the bow, positive from starboard; module docstring). Plain floats and
    loops: compiled by numba as it is."""
    kind = w[first]
    a = abs(gamma)
    s = 1.0 if gamma >= 0.0 else -1.0
    if kind == 1.0:
        cdt = w[first + 5]
        cdl_af = w[first + 6] if a <= 0.5 * math.pi else w[first + 7]
        dl = w[first + 8]
        cdl = cdl_af * w[first + 10]
        s2 = math.sin(2.0 * a)
        den = 1.0 - 0.5 * dl * (1.0 - cdl / cdt) * s2 * s2
        cx = -cdl_af * math.cos(a) / den
        cy = -s * cdt * math.sin(a) / den
        return cx, cy, cy * (w[first + 9] - 0.18 * (a - 0.5 * math.pi))
    if kind == 2.0:
        n = int(w[first + 11])
        mirrored = w[first + 4] > 0.0
        g = a if mirrored else gamma
        b = first + WIND_HEAD
        k = 0
        while k < n - 2 and w[b + k + 1] < g:
            k += 1
        g0, g1 = w[b + k], w[b + k + 1]
        th = (g - g0) / (g1 - g0)
        th = min(max(th, 0.0), 1.0)
        cx = w[b + n + k] + th * (w[b + n + k + 1] - w[b + n + k])
        cy = w[b + 2 * n + k] + th * (w[b + 2 * n + k + 1] - w[b + 2 * n + k])
        cn = w[b + 3 * n + k] + th * (w[b + 3 * n + k + 1] - w[b + 3 * n + k])
        if mirrored:
            cy *= s
            cn *= s
        return cx, cy, cn
    return 0.0, 0.0, 0.0


def wind_wrench(w, first, u_r, v_r, f):  # noqa: ANN001, ANN201
    """Add the wind's X, Y (N) and N (N·m) to ``f[0]``, ``f[1]``, ``f[5]`` for the relative wind
    (u_R, v_R) = vehicle's velocity over the ground minus the wind's, body axes (m/s), with the
    model packed at ``w[first:]`` (nothing when its kind is 0 or ``first`` is past the end)."""
    if first >= w.shape[0] or w[first] == 0.0:
        return
    v2 = u_r * u_r + v_r * v_r
    if v2 == 0.0:
        return
    cx, cy, cn = wind_coefficients(w, first, math.atan2(v_r, u_r))
    f[0] += w[first + 1] * v2 * cx
    f[1] += w[first + 2] * v2 * cy
    f[5] += w[first + 3] * v2 * cn


def wind_velocity_ned(speed: float, direction: float) -> tuple[float, float]:
    """The wind's velocity (north, east; m/s) from its speed (m/s) and the true direction it blows
    from (rad, clockwise from North)."""
    return -speed * math.cos(direction), -speed * math.sin(direction)


@dataclass(frozen=True)
class WindModel:
    """A vehicle's wind-load model (module docstring; SI).

    Attributes
    ----------
    frontal_area : float — A_F, frontal (transverse) projected area above the water, m²
    lateral_area : float — A_L, lateral projected area above the water, m²
    length : float — L_oa, length overall, m
    density : float — ρ_a, air density, kg/m³
    model : str — ``table`` or ``blendermann1994``
    angles : tuple of float — γ_R of the table rows, rad (table)
    C_X, C_Y, C_N : tuple of float — the table's coefficients (dimensionless)
    vessel : str or None — Blendermann's vessel type (blendermann1994)
    parameters : tuple of 4 floats — CD_t, CD_l,AF(0), CD_l,AF(π), δ (blendermann1994)
    s_L : float — lateral area centroid forward of midship, m (blendermann1994)
    """

    frontal_area: float
    lateral_area: float
    length: float
    density: float = AIR_DENSITY
    model: str = "table"
    angles: tuple[float, ...] = ()
    C_X: tuple[float, ...] = ()
    C_Y: tuple[float, ...] = ()
    C_N: tuple[float, ...] = ()
    vessel: str | None = None
    parameters: tuple[float, ...] = ()
    s_L: float = 0.0

    def pack(self) -> np.ndarray:
        """The packed row that :func:`wind_wrench` reads (module docstring)."""
        q = 0.5 * self.density
        head = np.zeros(WIND_HEAD)
        head[1:4] = q * self.frontal_area, q * self.lateral_area, q * self.lateral_area * self.length
        if self.model == "blendermann1994":
            head[0] = KIND_BLENDERMANN
            head[5:9] = self.parameters
            head[9] = self.s_L / self.length
            head[10] = self.frontal_area / self.lateral_area
            return head
        head[0] = KIND_TABLE
        head[4] = 1.0 if self.angles[0] == 0.0 else 0.0
        head[11] = len(self.angles)
        return np.concatenate([head, self.angles, self.C_X, self.C_Y, self.C_N])

    def coefficients(self, gamma: float) -> tuple[float, float, float]:
        """(C_X, C_Y, C_N) at the relative wind angle ``gamma`` (rad, from the bow, + from starboard)."""
        cx, cy, cn = wind_coefficients(self.pack(), 0, float(gamma))
        return float(cx), float(cy), float(cn)

    def wrench(self, u_r: float, v_r: float) -> np.ndarray:
        """[X, Y, Z, K, M, N] (N, N·m) of the relative wind (u_R, v_R) (m/s, body axes)."""
        out = np.zeros(6)
        wind_wrench(self.pack(), 0, float(u_r), float(v_r), out)
        return out


def make_wind(
    frontal_area: float,
    lateral_area: float,
    length: float,
    density: float = AIR_DENSITY,
    model: str = "table",
    angles: object = None,
    C_X: object = None,
    C_Y: object = None,
    C_N: object = None,
    vessel: str | None = None,
    parameters: object = None,
    s_L: float = 0.0,
    source: str = "",
) -> WindModel:
    """Validate and build a :class:`WindModel`; errors name the ``wind.`` field.

    Parameters
    ----------
    frontal_area, lateral_area : float — A_F, A_L, m² (> 0)
    length : float — L_oa, m (> 0)
    density : float — ρ_a, kg/m³ (> 0)
    model : str — ``table`` or ``blendermann1994``
    angles : list of float — table γ_R, rad, strictly increasing from 0 to π or from −π to π
    C_X, C_Y, C_N : list of float — one per angle (dimensionless)
    vessel : str — Blendermann's vessel type (a key of ``BLENDERMANN_1994``) or None with ``parameters``
    parameters : 4 floats — CD_t (> 0), CD_l,AF(0), CD_l,AF(π) (≥ 0), δ (0 ≤ δ ≤ 1)
    s_L : float — m
    """
    for name, value in (
        ("frontal_area", frontal_area),
        ("lateral_area", lateral_area),
        ("length", length),
        ("density", density),
    ):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise InputError(f"field 'wind.{name}' = {value!r}: expected a positive number", source)
    if model not in MODELS:
        raise InputError(f"field 'wind.model' = {model!r}: expected one of {', '.join(MODELS)}", source)
    if model == "blendermann1994":
        if vessel is not None:
            if vessel not in BLENDERMANN_1994:
                raise InputError(
                    f"field 'wind.vessel' = {vessel!r}: expected one of {', '.join(BLENDERMANN_1994)}", source
                )
            if parameters is None:
                parameters = list(BLENDERMANN_1994[vessel])
        try:
            par = np.asarray(parameters, dtype=float)
        except (TypeError, ValueError):
            par = np.zeros(0)
        if par.shape != (4,) or not np.all(np.isfinite(par)) or par[0] <= 0 or np.any(par[1:3] < 0):
            raise InputError(
                f"field 'wind.parameters' = {parameters!r}: expected a vessel type or 4 numbers "
                "[CD_t > 0, CD_l_AF_bow ≥ 0, CD_l_AF_stern ≥ 0, delta 0–1]",
                source,
            )
        if not 0.0 <= par[3] <= 1.0:
            raise InputError(f"field 'wind.parameters' delta = {par[3]}: expected 0 ≤ delta ≤ 1", source)
        if not (isinstance(s_L, (int, float)) and math.isfinite(s_L)):
            raise InputError(f"field 'wind.s_L' = {s_L!r}: expected a number (m)", source)
        return WindModel(
            float(frontal_area),
            float(lateral_area),
            float(length),
            float(density),
            model,
            vessel=vessel,
            parameters=tuple(float(x) for x in par),
            s_L=float(s_L),
        )
    cols = {}
    for name, raw in (("angle_deg", angles), ("C_X", C_X), ("C_Y", C_Y), ("C_N", C_N)):
        try:
            a = np.asarray(raw, dtype=float)
        except (TypeError, ValueError):
            a = np.zeros(0)
        if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)):
            raise InputError(f"field 'wind.coefficients.{name}' = {raw!r}: expected a list of ≥ 2 numbers", source)
        cols[name] = a
    n = cols["angle_deg"].size
    for name in ("C_X", "C_Y", "C_N"):
        if cols[name].size != n:
            raise InputError(
                f"field 'wind.coefficients.{name}': {cols[name].size} values; expected {n}, one per angle", source
            )
    g = cols["angle_deg"]
    if np.any(np.diff(g) <= 0):
        raise InputError("field 'wind.coefficients.angle_deg': expected strictly increasing angles", source)
    if not (math.isclose(g[-1], math.pi, abs_tol=1e-9) and (g[0] == 0.0 or math.isclose(g[0], -math.pi))):
        raise InputError(
            f"field 'wind.coefficients.angle_deg' spans {math.degrees(g[0]):.6g} to {math.degrees(g[-1]):.6g}°: "
            "expected 0 to 180 (a hull symmetric port and starboard) or −180 to 180",
            source,
        )
    g = g.copy()
    g[-1] = math.pi
    if g[0] != 0.0:
        g[0] = -math.pi
    return WindModel(
        float(frontal_area),
        float(lateral_area),
        float(length),
        float(density),
        "table",
        tuple(float(x) for x in g),
        tuple(float(x) for x in cols["C_X"]),
        tuple(float(x) for x in cols["C_Y"]),
        tuple(float(x) for x in cols["C_N"]),
    )


# ------------------------------------------------------------------ free fields (issue #48 item 4)
#: the numeric fields of a wind model that ``hydrokit sysid --free wind.FIELD`` may fit (frozen):
#: name → (unit, the models that have it). The table's coefficients are named by their row,
#: ``coefficients.C_X.<angle_deg>`` (:data:`WIND_TABLE_FIELDS`, dimensionless)
WIND_FIELDS: dict[str, tuple[str, tuple[str, ...]]] = {
    "frontal_area": ("m²", MODELS),
    "lateral_area": ("m²", MODELS),
    "CD_t": ("–", ("blendermann1994",)),
    "CD_l_AF_bow": ("–", ("blendermann1994",)),
    "CD_l_AF_stern": ("–", ("blendermann1994",)),
    "delta": ("–", ("blendermann1994",)),
    "s_L": ("m", ("blendermann1994",)),
}
#: the table's coefficient columns a free name may pick a row of (``coefficients.C_Y.90``)
WIND_TABLE_FIELDS = ("C_X", "C_Y", "C_N")
#: the fields that stay ≥ 0 when drawn from a covariance (an area, a drag coefficient, δ)
WIND_POSITIVE = ("frontal_area", "lateral_area", "CD_t", "CD_l_AF_bow", "CD_l_AF_stern", "delta")
_BLENDERMANN_INDEX = {"CD_t": 0, "CD_l_AF_bow": 1, "CD_l_AF_stern": 2, "delta": 3}


def parse_wind_field(field: str) -> tuple[str, float | None]:
    """``(field, angle_deg)`` of a wind field name: ``CD_t`` → ("CD_t", None),
    ``coefficients.C_Y.90`` → ("C_Y", 90.0) (the row's angle, degrees as the file gives it).

    Raises
    ------
    ValueError
        Not a field of :data:`WIND_FIELDS` nor ``coefficients.C_X|C_Y|C_N.<angle_deg>``.
    """
    if field in WIND_FIELDS:
        return field, None
    head, _, rest = field.partition(".")
    col, _, angle = rest.partition(".")
    if head == "coefficients" and col in WIND_TABLE_FIELDS:
        try:
            value = float(angle)
        except ValueError:
            value = math.nan
        if math.isfinite(value):
            return col, value
    raise ValueError(
        f"expected 'wind.<field>' with field one of {', '.join(WIND_FIELDS)} or "
        "'wind.coefficients.C_X|C_Y|C_N.<angle_deg>' (a row of the table)"
    )


def wind_field_names(model: WindModel) -> list[str]:
    """Every free field of ``model`` (without the ``wind.`` prefix), table rows by their angle in
    degrees."""
    out = [f for f, (_, models) in WIND_FIELDS.items() if model.model in models]
    if model.model == "table":
        out += [f"coefficients.{c}.{math.degrees(a):g}" for c in WIND_TABLE_FIELDS for a in model.angles]
    return out


def table_row(model: WindModel, angle_deg: float) -> int | None:
    """The row of ``model``'s table at ``angle_deg`` (degrees, within 1e-6°), or None."""
    for k, a in enumerate(model.angles):
        if abs(math.degrees(a) - angle_deg) <= 1e-6:
            return k
    return None


def wind_field(model: WindModel, field: str, row: int = -1) -> float:
    """The value of a free field of ``model`` (:data:`WIND_FIELDS` in its unit, or the table's
    ``C_X``/``C_Y``/``C_N`` at ``row``)."""
    if field in WIND_TABLE_FIELDS:
        return float(getattr(model, field)[row])
    if field in _BLENDERMANN_INDEX:
        return float(model.parameters[_BLENDERMANN_INDEX[field]])
    return float(getattr(model, field))


def with_wind_field(model: WindModel, field: str, value: float, row: int = -1) -> WindModel:
    """``model`` with one free field set (:func:`wind_field`'s names; the model's own ranges are
    not re-checked here: a fit keeps them by its bounds, a draw by clipping at 0)."""
    from dataclasses import replace

    v = float(value)
    if field in WIND_TABLE_FIELDS:
        col = list(getattr(model, field))
        col[row] = v
        changes: dict[str, Any] = {field: tuple(col)}
        return replace(model, **changes)
    if field in _BLENDERMANN_INDEX:
        par = list(model.parameters)
        par[_BLENDERMANN_INDEX[field]] = v
        return replace(model, parameters=tuple(par), vessel=None)
    size: dict[str, Any] = {field: v}
    return replace(model, **size)
