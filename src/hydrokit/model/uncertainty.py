"""Coefficient uncertainty of a vehicle: the ``uncertainty:`` block of a vehicle file.

``hydrokit run`` and ``hydrokit sysid`` write the standard errors of the coefficients they
identified and their covariance; :func:`make_uncertainty` checks such a block and
:meth:`Uncertainty.draw` samples vehicles from it (one seeded generator, so the same seed gives
the same vehicles on any machine). A parameter is named

- ``"<coefficient>.<dof>"`` with coefficient one of ``added_mass`` (kg, kg·m²),
  ``linear_damping`` (N·s/m, N·m·s/rad) or ``quadratic_damping`` (N·s²/m², N·m·s²/rad²) and
  dof one of surge … yaw: a diagonal entry (positive convention);
- ``"terms.<term>"`` with a derivative term of the grammar (:mod:`hydrokit.model.terms`): that
  term's SI coefficient, SNAME signs (``terms.N_r|r|`` in N·m·s²/rad², ``terms.Y_vdot`` in
  kg — for an acceleration term the value is −M_A[dof, acceleration], as ``hydrokit sysid``
  names it). A velocity term must be one of the vehicle's ``terms:``;
- ``"control_surfaces.<NAME>.<FIELD>"`` (issue #48): a numeric field of a physical surface's fin,
  FIELD one of :data:`SURFACE_FIELDS` (``lift_slope`` 1/rad, ``neutral_deflection_deg`` and
  ``stall_angle_deg`` in degrees as the file gives them, ``area`` m², the race's ``diameter`` m,
  ``l_R`` m, the rest –); the MMG fields need ``inflow: mmg``, the race fields a ``slipstream``;
- ``"thrusters.<NAME>.<FIELD>"``: FIELD ``wake_fraction`` or ``thrust_deduction`` (–) of a
  thruster of the vehicle's ``thrusters:`` block (a race that names the thruster follows its wake
  fraction);
- ``"wind.<FIELD>"``: a numeric field of the vehicle's wind-load model (:mod:`hydrokit.model.wind`,
  :data:`~hydrokit.model.wind.WIND_FIELDS`): ``frontal_area``, ``lateral_area`` (m²), and of the
  Blendermann set ``CD_t``, ``CD_l_AF_bow``, ``CD_l_AF_stern``, ``delta`` (–) and ``s_L`` (m); of
  a table, one coefficient ``wind.coefficients.C_Y.<angle_deg>`` (–, the row at that angle in
  degrees, as the file gives it). These names are frozen.

Drawn diagonal coefficients below zero are set to 0 (and counted); a term's coefficient keeps
its sign, which the grammar does not fix (X_u|u| < 0 is drag, a cross term may be either).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

# COEFFICIENTS, the diagonal coefficients an uncertainty block may name, is the one table of
# core.names; hydrokit.model.uncertainty.COEFFICIENTS stays importable
from hydrokit.core.names import COEFFICIENTS, DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.model.terms import ABS, VEL, Term, TermSet, parse_term
from hydrokit.model.wind import (
    WIND_FIELDS,
    WIND_POSITIVE,
    WIND_TABLE_FIELDS,
    parse_wind_field,
    table_row,
    wind_field,
    wind_field_names,
    with_wind_field,
)

#: the prefix of a derivative-term parameter (``terms.N_r|r|``)
TERM_PREFIX = "terms."
#: the prefixes of a surface's and a thruster's field (``control_surfaces.rudder.lift_slope``)
SURFACE_PREFIX, THRUSTER_PREFIX = "control_surfaces.", "thrusters."
#: the prefix of a wind-load model's field (``wind.CD_t``, ``wind.coefficients.C_Y.90``)
WIND_PREFIX = "wind."
#: a surface's free fields → (the :class:`~hydrokit.model.surfaces.Fin` attribute, file unit →
#: SI factor, what the fin needs: "" any fin, "race" a slipstream, "mmg" the MMG inflow)
SURFACE_FIELDS: dict[str, tuple[str, float, str]] = {
    "lift_slope": ("lift_slope", 1.0, ""),
    "neutral_deflection_deg": ("neutral_deflection", math.pi / 180.0, ""),
    "stall_angle_deg": ("stall_angle", math.pi / 180.0, ""),
    "area": ("area", 1.0, ""),
    "drag_coefficient": ("drag_coefficient", 1.0, ""),
    "diameter": ("slipstream_diameter", 1.0, "race"),
    "thrust_share": ("thrust_share", 1.0, "race"),
    "epsilon": ("epsilon", 1.0, "mmg"),
    "kappa": ("kappa", 1.0, "mmg"),
    "eta": ("eta", 1.0, "mmg"),
    "gamma_R_positive": ("gamma_positive", 1.0, "mmg"),
    "gamma_R_negative": ("gamma_negative", 1.0, "mmg"),
    "l_R": ("l_R", 1.0, "mmg"),
}
#: a thruster's free fields (–)
THRUSTER_FIELDS = ("wake_fraction", "thrust_deduction")
#: relative asymmetry, and negative eigenvalue relative to the largest, tolerated in a covariance
#: (the run writes a symmetric matrix; round-off of a hand-made one is no error)
COVARIANCE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ParameterRef:
    """Where a named parameter sits in a vehicle.

    kind : one of :data:`COEFFICIENTS` (diagonal entry ``dof``), ``"accel"`` (−M_A[dof, index]),
    ``"term"`` (the velocity term ``term``), ``"surface"`` or ``"thruster"`` (field ``field`` of
    the surface or thruster ``index``, file order), ``"wind"`` (field ``field`` of the wind model,
    without ``wind.``; ``index`` the table row, −1 until checked against a vehicle); dof : DOF
    index 0–5 of the force (a surface's field is reported under yaw, a thruster's under surge);
    index : the acceleration's velocity index (accel), the surface's or thruster's (surface,
    thruster), else ``dof``; term : the parsed term
    """

    kind: str
    dof: int
    index: int
    term: Term | None = None
    field: str = ""


def field_unit(name: str) -> str:
    """The unit of a ``control_surfaces.NAME.FIELD``, ``thrusters.NAME.FIELD`` or ``wind.FIELD``
    parameter (as the vehicle file gives it), "" for another name."""
    if name.startswith(WIND_PREFIX):
        try:
            field, _ = parse_wind_field(name[len(WIND_PREFIX) :])
        except ValueError:
            return ""
        return "–" if field in WIND_TABLE_FIELDS else WIND_FIELDS[field][0]
    field = name.rpartition(".")[2]
    if name.startswith(THRUSTER_PREFIX):
        return "–" if field in THRUSTER_FIELDS else ""
    if not name.startswith(SURFACE_PREFIX) or field not in SURFACE_FIELDS:
        return ""
    units = {"lift_slope": "1/rad", "area": "m²", "diameter": "m", "l_R": "m"}
    return "deg" if field.endswith("_deg") else units.get(field, "–")


def _field_parameter(text: str, what: str, source: str, surfaces: tuple[str, ...], thrusters: tuple[str, ...]) -> Any:
    """The :class:`ParameterRef` of ``control_surfaces.NAME.FIELD`` or ``thrusters.NAME.FIELD``
    (None for another name); NAME may hold dots, FIELD may not."""
    for prefix, names, fields, kind, dof in (
        (SURFACE_PREFIX, surfaces, tuple(SURFACE_FIELDS), "surface", 5),
        (THRUSTER_PREFIX, thrusters, THRUSTER_FIELDS, "thruster", 0),
    ):
        if not text.startswith(prefix):
            continue
        name, _, field = text[len(prefix) :].rpartition(".")
        if field not in fields:
            raise InputError(
                f"{what} {text[:80]!r}: expected '{prefix}<name>.<field>' with field one of {', '.join(fields)}", source
            )
        if name not in names:
            raise InputError(
                f"{what} {text[:80]!r}: {name!r} names no {kind} of the vehicle "
                f"({prefix.rstrip('.')}: {', '.join(names) or 'none'})",
                source,
            )
        return ParameterRef(kind, dof, names.index(name), None, field)
    return None


def check_parameter(
    name: Any,
    what: str,
    source: str,
    surfaces: tuple[str, ...] = (),
    thrusters: tuple[str, ...] = (),
    propellers: tuple[str, ...] | None = None,
) -> ParameterRef:
    """The :class:`ParameterRef` of ``"<coefficient>.<dof>"``, ``"terms.<term>"``,
    ``"control_surfaces.<NAME>.<FIELD>"`` or ``"thrusters.<NAME>.<FIELD>"``, or an error starting
    with ``what`` (``"field 'uncertainty.parameters[2]' ="``, ``"variation"``). ``surfaces`` are
    the control-surface names a ``delta(NAME)`` factor may use, ``thrusters`` the thruster names
    (file order) of ``T(NAME)`` and ``n(NAME)``, ``propellers`` those of them with a rotation rate
    that ``n(NAME)`` may use (None: all). A term of a vehicle document is checked with all three of
    the document's lists, as its loader checks it (:func:`hydrokit.io.vehicle.write_terms`)."""
    text = str(name)
    if isinstance(name, str):
        field_ref = _field_parameter(text, what, source, tuple(surfaces), tuple(thrusters))
        if field_ref is not None:
            return field_ref  # type: ignore[no-any-return]
        if text.startswith(WIND_PREFIX):
            try:
                field, _ = parse_wind_field(text[len(WIND_PREFIX) :])
            except ValueError as exc:
                raise InputError(f"{what} {text[:80]!r}: {exc}", source) from None
            # the force it enters first: X for the frontal area and C_X, N for C_N and s_L, else Y
            force = 0 if field in ("frontal_area", "C_X", "CD_l_AF_bow", "CD_l_AF_stern") else 1
            return ParameterRef("wind", 5 if field in ("C_N", "s_L") else force, -1, None, text[len(WIND_PREFIX) :])
    if isinstance(name, str) and text.startswith(TERM_PREFIX) and text[len(TERM_PREFIX) :].strip():
        try:
            term = parse_term(text[len(TERM_PREFIX) :], "", surfaces, thrusters, propellers)
        except InputError as exc:
            raise InputError(f"{what} {text[:80]!r}: {exc}", source) from None
        if term.acceleration is not None:
            return ParameterRef("accel", term.dof, term.acceleration, term)
        return ParameterRef("term", term.dof, term.dof, term)
    coef, _, dof = text.partition(".")
    if not isinstance(name, str) or coef not in COEFFICIENTS or dof not in DOF_NAMES:
        raise InputError(
            f"{what} {text[:80]!r}: expected '<coefficient>.<dof>' with coefficient one of "
            f"{', '.join(COEFFICIENTS)} and dof one of {', '.join(DOF_NAMES)}, 'terms.<term>' (e.g. terms.N_r|r|), "
            "'control_surfaces.<name>.<field>', 'thrusters.<name>.<field>' or 'wind.<field>'",
            source,
        )
    i = DOF_NAMES.index(dof)
    return ParameterRef(coef, i, i)


def _signature(dof: int, kinds: np.ndarray, idx: np.ndarray) -> tuple[Any, ...]:
    """A term's force DOF and its factors in a fixed order (a product does not depend on the
    order of its factors: N_r|r| and N_|r|r are one term)."""
    factors = sorted((int(k), tuple(int(i) for i in ix)) for k, ix in zip(kinds, idx) if k != 0)
    return (int(dof), tuple(factors))


def term_index(terms: TermSet, term: Term) -> int | None:
    """Position of ``term`` in ``terms`` (the same force DOF and factors, however spelt), or None."""
    one = TermSet.build([(term, 0.0)])
    want = _signature(one.dof[0], one.kinds[0], one.idx[0])
    for k in range(len(terms.names)):
        if _signature(terms.dof[k], terms.kinds[k], terms.idx[k]) == want:
            return k
    return None


def _ref(vehicle: Any, name: str, what: str = "parameter") -> tuple[ParameterRef, int]:
    """The reference of ``name`` in ``vehicle`` and, for a velocity term, its position; errors
    start with ``what``."""
    surfaces = tuple(vehicle.surfaces.names) if getattr(vehicle, "surfaces", None) is not None else ()
    ref = check_parameter(name, what, "", surfaces, tuple(getattr(vehicle, "thruster_names", ())))
    if ref.kind == "surface":
        fin = vehicle.surfaces.surfaces[ref.index].fin
        need = SURFACE_FIELDS[ref.field][2]
        said = {"": "a physical fin (area)", "race": "a slipstream", "mmg": "a slipstream with inflow: mmg"}[need]
        if fin is None or (need and fin.slipstream_diameter <= 0) or (need == "mmg" and fin.inflow != "mmg"):
            raise InputError(
                f"{what} {name[:80]!r}: control surface {vehicle.surfaces.names[ref.index]!r} has no {ref.field}; "
                f"expected a surface with {said}"
            )
    if ref.kind == "wind":
        return _wind_ref(vehicle, ref, name, what), -1
    if ref.kind == "thruster" and getattr(vehicle, "thrusters", None) is None:
        raise InputError(f"{what} {name[:80]!r}: the vehicle {vehicle.name!r} was loaded without its thrusters")
    k = -1
    if ref.kind == "term":
        assert ref.term is not None
        found = term_index(vehicle.terms, ref.term)
        if found is None:
            raise InputError(
                f"{what} {name[:80]!r}: the vehicle {vehicle.name!r} has no such term; expected one of its "
                "'terms:' or an acceleration term"
            )
        k = found
    return ref, k


def _wind_ref(vehicle: Any, ref: ParameterRef, name: str, what: str) -> ParameterRef:
    """``ref`` of a ``wind.FIELD`` checked against the vehicle's wind model, a table row's index
    set (errors start with ``what``)."""
    model = getattr(vehicle, "wind", None)
    if model is None:
        raise InputError(
            f"{what} {name[:80]!r}: the vehicle {vehicle.name!r} has no wind model; expected a 'wind:' block"
        )
    field, angle = parse_wind_field(ref.field)
    valid = wind_field_names(model)
    if (angle is None and field not in valid) or (angle is not None and model.model != "table"):
        raise InputError(
            f"{what} {name[:80]!r}: the wind model is {model.model!r}, which has no "
            f"{field if angle is None else 'table'}; expected one of "
            f"{', '.join(WIND_PREFIX + v for v in valid[:8])}{' …' if len(valid) > 8 else ''}"
        )
    if angle is None:
        return ref
    row = table_row(model, angle)
    if row is None:
        rows = ", ".join(f"{math.degrees(a):g}" for a in model.angles)
        raise InputError(
            f"{what} {name[:80]!r}: no row of the wind table at {angle:g}°; expected one of its angle_deg: {rows}"
        )
    return replace(ref, index=row)


def parameter_ref(vehicle: Any, name: str, what: str = "free parameter") -> ParameterRef:
    """The :class:`ParameterRef` of ``name`` checked against ``vehicle`` (its terms, surfaces and
    thrusters): the hook through which a free ``control_surfaces.NAME.FIELD`` or
    ``thrusters.NAME.FIELD`` (unit: :func:`field_unit`) joins a fit; errors start with ``what``."""
    return _ref(vehicle, name, what)[0]


def parameter_value(vehicle: Any, name: str) -> float:
    """The vehicle's current value of the parameter ``name`` (SI; see the module docstring)."""
    ref, k = _ref(vehicle, name)
    if ref.kind == "added_mass":
        return float(vehicle.M_A[ref.dof, ref.dof])
    if ref.kind == "linear_damping":
        return float(vehicle.D_L[ref.dof, ref.dof])
    if ref.kind == "quadratic_damping":
        return float(vehicle.D_Q[ref.dof])
    if ref.kind == "accel":
        return float(-vehicle.M_A[ref.dof, ref.index])  # SNAME: X_udot = −M_A[0, 0]
    if ref.kind == "surface":
        attr, to_si, _ = SURFACE_FIELDS[ref.field]
        return float(getattr(vehicle.surfaces.surfaces[ref.index].fin, attr)) / to_si
    if ref.kind == "thruster":
        return float(getattr(vehicle.thrusters.thrusters[ref.index], ref.field))
    if ref.kind == "wind":
        return wind_field(vehicle.wind, parse_wind_field(ref.field)[0], ref.index)
    return float(vehicle.terms.coef[k])


def with_coefficients(vehicle: Any, values: Any) -> Any:
    """``vehicle`` with parameters replaced; ``values`` maps ``"<coefficient>.<dof>"`` or
    ``"terms.<term>"`` to the new value (SI, see the module docstring). Everything else is kept."""
    refs = [_ref(vehicle, key, "variation") for key in values]
    return _with(vehicle, refs, list(values.values()))


def _with(vehicle: Any, refs: list[tuple[ParameterRef, int]], values: Any) -> Any:
    M_A, D_L, D_Q = vehicle.M_A.copy(), vehicle.D_L.copy(), np.array(vehicle.D_Q, float)
    coef = None
    fields = [(ref, float(v)) for (ref, _), v in zip(refs, values) if ref.kind in ("surface", "thruster")]
    wind: Any = vehicle.wind if any(ref.kind == "wind" for ref, _ in refs) else None
    for (ref, k), v in zip(refs, values):
        if ref.kind in ("surface", "thruster"):
            continue
        if ref.kind == "wind":
            wind = with_wind_field(wind, parse_wind_field(ref.field)[0], float(v), ref.index)
            continue
        if ref.kind == "added_mass":
            M_A[ref.dof, ref.dof] = v
        elif ref.kind == "linear_damping":
            D_L[ref.dof, ref.dof] = v
        elif ref.kind == "quadratic_damping":
            D_Q[ref.dof] = v
        elif ref.kind == "accel":
            M_A[ref.dof, ref.index] = -v
        else:
            coef = vehicle.terms.coef.copy() if coef is None else coef
            coef[k] = v
    out = replace(vehicle, M_A=M_A, D_L=D_L, D_Q=D_Q)
    out = out if wind is None else replace(out, wind=wind)
    out = out if coef is None else replace(out, terms=replace(vehicle.terms, coef=coef))
    return _with_fields(out, fields) if fields else out


def _with_fields(vehicle: Any, fields: list[tuple[ParameterRef, float]]) -> Any:
    """``vehicle`` with surface and thruster fields set (the values in the file's units; the
    model's own checks apply: a wake fraction of 1 is an error naming the thruster)."""
    from hydrokit.model.surfaces import SurfaceSet
    from hydrokit.model.thrusters import ThrusterSet

    surfaces = list(vehicle.surfaces.surfaces)
    ts = vehicle.thrusters
    thrusters = list(ts.thrusters) if ts is not None else []
    for ref, v in fields:
        if ref.kind == "thruster":
            thrusters[ref.index] = replace(thrusters[ref.index], **{ref.field: v})
            if ref.field == "wake_fraction":  # a race naming this thruster sees its wake
                for i, s in enumerate(surfaces):
                    if s.fin is not None and s.fin.race_thruster == ref.index:
                        surfaces[i] = replace(s, fin=replace(s.fin, wake_fraction=v))
            continue
        attr, to_si, _ = SURFACE_FIELDS[ref.field]
        s = surfaces[ref.index]
        surfaces[ref.index] = replace(s, fin=replace(s.fin, **{attr: v * to_si}))
    out = replace(vehicle, surfaces=SurfaceSet(tuple(surfaces)))
    if ts is not None:
        out = replace(out, thrusters=ThrusterSet(tuple(thrusters), density=ts.density, notes=ts.notes))
    return out


@dataclass(frozen=True, eq=False)
class Uncertainty:
    """Covariance of a vehicle's coefficients (SI, full scale).

    Attributes
    ----------
    parameters : tuple of str — ``"<coefficient>.<dof>"`` or ``"terms.<term>"`` (module
        docstring), one per row of ``covariance``
    covariance : (p, p) — symmetric positive semi-definite, in the squared units of the parameters
    """

    parameters: tuple[str, ...]
    covariance: np.ndarray

    @property
    def std(self) -> np.ndarray:
        """Standard deviation σ of each parameter (SI)."""
        return np.sqrt(np.clip(np.diag(self.covariance), 0.0, None))

    def draw(self, mean: np.ndarray, n: int, seed: int) -> tuple[np.ndarray, int]:
        """``n`` parameter vectors from N(mean, covariance), negative diagonal coefficients and
        surface or thruster fields set to 0 (a ``terms.*`` parameter keeps its sign: the grammar
        does not fix it; so do ``neutral_deflection_deg`` and ``l_R``).

        One ``numpy.random.default_rng(seed)``; the eigen-decomposition method, so a singular
        covariance (a parameter with σ = 0, or two that move together) is fine.
        Returns the (n, p) samples and how many entries were clipped at zero.
        """
        rng = np.random.default_rng(seed)
        if not self.parameters:
            return np.zeros((n, 0)), 0
        x = rng.multivariate_normal(np.asarray(mean, float), self.covariance, size=n, method="eigh")
        # a term keeps its sign, and so do a neutral deflection and l_R; the rest are ≥ 0
        signed = (".neutral_deflection_deg", ".l_R")

        def clipped(p: str) -> bool:
            if p.startswith(WIND_PREFIX):  # a table's C_X, C_Y, C_N and s_L take either sign
                return p[len(WIND_PREFIX) :] in WIND_POSITIVE
            return not (p.startswith(TERM_PREFIX) or p.endswith(signed))

        clip = np.array([clipped(str(p)) for p in self.parameters])
        below = (x < 0) & clip
        x[below] = 0.0
        return x, int(np.sum(below))

    def sample_vehicles(self, vehicle: Any, n: int, seed: int) -> tuple[list[Any], np.ndarray, int]:
        """``n`` copies of ``vehicle`` whose parameters are drawn about its own values.

        Returns the vehicles, the (n, p) drawn values (SI) and the count clipped at zero.
        """
        mean = np.array([parameter_value(vehicle, p) for p in self.parameters], float)
        values, clipped = self.draw(mean, n, seed)
        refs = [_ref(vehicle, p) for p in self.parameters]
        vehicles = [_with(vehicle, refs, row) for row in values]
        return vehicles, values, clipped


def physical_sign(ref: ParameterRef) -> int:
    """The sign a parameter must keep to be physical: +1 (≥ 0) for a ``linear_damping`` or
    ``quadratic_damping`` diagonal entry and for a diagonal ``added_mass``; −1 (≤ 0, SNAME) for
    a damping derivative of its own DOF (a term odd in that one velocity: X_u, X_u|u|, N_r|r|,
    N_rrr), also when the forward speed scales it (Y_uv, N_ur, Z_uw, M_uq, K_up, Y_|u|v: damping
    for a vehicle moving ahead, u > 0), and for an own-DOF acceleration term (X_udot … N_rdot = −M_A[i, i]); 0 (either sign)
    otherwise.

    A damping of the other sign feeds energy in (a vehicle file refuses it unless
    ``allow_negative_damping``); the added-mass matrix of a body in unbounded fluid is positive
    definite (the fluid's kinetic energy ½ νᵀ M_A ν > 0; Newman 1977, Marine Hydrodynamics,
    ch. 4), so its diagonal is positive — a negative one, which the file accepts with a warning,
    makes the body easier to accelerate than in vacuum and can leave M_RB + M_A singular."""
    if ref.kind in COEFFICIENTS:
        return 1
    if ref.kind == "accel":
        return -1 if ref.index == ref.dof else 0
    if ref.kind == "term" and ref.term is not None:
        t = ref.term
        own = [f for f in t.factors if f.indices == (t.dof,) and f.kind in (VEL, ABS)]
        # the forward speed u scales a damping derivative of another DOF (Y_uv = Y_v / u,
        # N_ur, Z_uw, M_uq, K_up, Y_|u|v): for a vehicle moving ahead (u > 0) it is the damping
        # itself, ≤ 0 like Y_v (a positive one is the anti-damping no ship or AUV has)
        speed = [f for f in t.factors if t.dof != 0 and f.indices == (0,) and f.kind in (VEL, ABS)]
        if own and len(own) + len(speed) == len(t.factors) and sum(f.kind == VEL for f in own) % 2 == 1:
            return -1
    return 0


def location(ref: ParameterRef) -> tuple[Any, ...]:
    """What a parameter changes: two names with one location (``added_mass.surge`` and
    ``terms.X_udot``, or one term spelt twice) would overwrite each other."""
    if ref.kind == "added_mass":
        return ("M_A", ref.dof, ref.dof)
    if ref.kind == "accel":
        return ("M_A", ref.dof, ref.index)
    if ref.kind == "term":
        assert ref.term is not None
        one = TermSet.build([(ref.term, 0.0)])
        return ("term", _signature(one.dof[0], one.kinds[0], one.idx[0]))
    if ref.kind in ("surface", "thruster"):
        return (ref.kind, ref.index, ref.field)
    if ref.kind == "wind":
        field, angle = parse_wind_field(ref.field)
        return (ref.kind, field, angle)
    return (ref.kind, ref.dof)


def make_uncertainty(
    parameters: Any,
    covariance: Any,
    sigma: dict[str, Any],
    source: str,
    terms: TermSet | None = None,
    surfaces: tuple[str, ...] = (),
    thrusters: tuple[str, ...] = (),
) -> Uncertainty | None:
    """Check an uncertainty block and build it (None when it states no σ at all).

    Parameters
    ----------
    parameters : list of str — names of the covariance's rows (may be empty):
        ``<coefficient>.<dof>`` or ``terms.<term>`` (module docstring)
    covariance : (p, p) nested lists — SI², symmetric positive semi-definite
    sigma : coefficient → 6 standard errors (SI) per DOF; a σ > 0 whose parameter the
        covariance does not hold is added as an independent parameter; one it holds must
        equal the square root of its diagonal entry (rel. 1e-6)
    source : str — the file named in errors
    terms : TermSet, optional — the vehicle's velocity terms: a ``terms.*`` velocity term must
        be one of them (None: not checked)
    surfaces : tuple of str — control-surface names a ``delta(NAME)`` factor may use
    thrusters : tuple of str — thruster names (file order) of ``T(NAME)``, ``n(NAME)`` and
        ``thrusters.NAME.FIELD``

    Raises
    ------
    InputError
        One line naming the field (``uncertainty.covariance``, ``uncertainty.parameters[2]`` …).
    """
    names = list(parameters or [])
    seen: dict[tuple[Any, ...], str] = {}
    for k, name in enumerate(names):
        what = f"field 'uncertainty.parameters[{k}]' ="
        ref = check_parameter(name, what, source, surfaces, thrusters)
        if ref.kind == "term" and terms is not None and ref.term is not None and term_index(terms, ref.term) is None:
            raise InputError(
                f"{what} {str(name)[:80]!r}: the vehicle has no such term; expected one of its 'terms:' "
                "(or an acceleration term)",
                source,
            )
        where = location(ref)
        if where in seen:
            also = "" if seen[where] == name else f" (as {seen[where]!r})"
            raise InputError(
                f"field 'uncertainty.parameters' names {name!r} twice{also}; expected each parameter once", source
            )
        seen[where] = name
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
