"""Vehicle files (YAML), frozen fields of issue #3 (see docs/model.md).

```yaml
name: bluerov2-heavy
gravity: 9.82                 # m/s^2
fluid: {density: 1000.0}      # kg/m^3
mass: 13.5                    # kg
volume: 0.0134                # m^3
inertia: [0.26, 0.23, 0.37]   # kg m^2: diagonal, or a 3x3 tensor about the centre of gravity
center_of_gravity: [0, 0, 0]  # m, from the body origin
center_of_buoyancy: [0, 0, -0.01]
added_mass: [6.36, 7.12, 18.68, 0.189, 0.135, 0.222]   # diag of M_A (positive), or 6x6
linear_damping: [13.7, 0, 33.0, 0, 0.8, 0]              # diag of D_L (positive), or 6x6
quadratic_damping: [141, 217, 190, 1.19, 0.47, 1.5]     # force_i = -d_i |nu_i| nu_i
```

Optional: ``reference_length`` (m) and ``reference_speed`` (m/s) for non-dimensional terms;
``terms:`` a mapping of SNAME term names (:mod:`hydrokit.model.terms`) to a number or to
``{value: …, nondimensional: true|false}``; ``terms_nondimensional`` (default false) sets the
default; ``thrusters:`` (issue #4, read by :mod:`hydrokit.io.thrusters`); ``drag_elements:``
(issue #11) point drag elements, each evaluated at its own point's relative velocity
(:mod:`hydrokit.core.drag`):

```yaml
drag_elements:                # optional list; linear and quadratic each default to zeros
  - name: arm-port
    position: [0, -0.75, 0]   # m, body axes from the body origin
    linear: [0, 0, 0]         # N s/m per body axis (>= 0)
    quadratic: [83.28, 0, 0]  # N s^2/m^2 per body axis (>= 0): 1/2 rho C_D A
```

Unknown keys in an element, a value that is not a list, or wrong lengths are one-line errors
naming the field (``drag_elements[1].position``).

A negative damping entry (``linear_damping`` diagonal, ``quadratic_damping``) feeds energy in:
refused unless the file sets ``allow_negative_damping: true`` (then warned).

``control_surfaces:`` (rudders, planes, fins) and ``dofs:`` (planar models), issue #45, are read
by :mod:`hydrokit.io.surfaces`; terms may then use ``delta(NAME)`` factors, and with a
``thrusters:`` block ``T(NAME)`` (thrust, N) and ``n(NAME)`` (rotation rate, rev/s, a
propeller's) factors; ``X_0`` … ``N_0`` are constant terms (issue #48). ``hull:`` (cross-flow
drag strips and viscous lift of a body of revolution from its profile) is read by
:mod:`hydrokit.io.hull`: its strips join the drag elements, its terms the ``terms:``.

``wind:`` (issue #48 item 4) the wind-load model of the part above the water
(:mod:`hydrokit.model.wind`, docs/model.md): ``frontal_area``, ``lateral_area`` (m²),
``length`` (m), ``density`` (kg/m³, default 1.225) and either ``model: table`` with
``coefficients: {angle_deg, C_X, C_Y, C_N}`` or ``model: blendermann1994`` with ``vessel`` (or
``parameters``) and ``s_L`` (m).

``uncertainty:`` (written by ``hydrokit run``, docs/run.md) is read into
``Vehicle.uncertainty`` (:mod:`hydrokit.model.uncertainty`): standard errors per coefficient
(6 numbers ≥ 0 each, SI), ``parameters`` (``<coefficient>.<dof>`` or ``terms.<term>``) and their
``covariance``; the ``--samples`` option of the simulate and mission commands draws
vehicles from it.

``service:`` (issue #55 item 2; :class:`hydrokit.model.vehicle.Service`) how the vehicle moves at
its service speed, flown by ``hydrokit manoeuvre`` and ``hydrokit simulate`` when they are given no
propulsion (docs/model.md):

```yaml
service:
  command: {propeller: 11.567}      # per thruster, in its unit (rev/s, the table's unit, N)
  force: [0, 0, 0, -0.543, 0, 0]    # N, N m body axes, added (optional)
  speed: 1.526                      # m/s: the steady speed through the water it reaches
```

``speed`` (> 0) and a ``command`` or a ``force`` are required; a command's thruster must be in
the ``thrusters:`` block.

``identification:`` (issue #48; :mod:`hydrokit.model.identification`) what the fit that wrote the
file claims of it; ``hydrokit sysid fit`` and ``sysid compare`` write it, whatever the verdict:

```yaml
identification:
  verdict: does not fit            # or: fits
  reasons: ['pond3 (held out): held-out NRMSE of v 0.57 … > 0.5 …']   # the verdict's sentences
  holdout_nrmse: {pond3: {u: 0.12, v: 0.57, r: 1.2}}   # per held-out run, moving channels (–)
  runs: [pond1, pond2]             # fitted runs (file stems)
  holdout: [pond3]                 # held-out runs
  method: output-error
  tool: hydrokit sysid 0.1.0
  date: '2026-11-29T19:30:00Z'     # UTC
```

Only ``verdict`` is required. A vehicle whose block says ``does not fit`` loads and flies, with
the warning ``FILE: its identification says "does not fit" (first reason): the predictions below
are not trustworthy`` first in ``Vehicle.warnings`` (every result that flies it carries it);
``--strict`` of the simulate and manoeuvre commands refuses it. A file without the block (deleted
by hand) makes no claim.

``envelope:`` (issue #56 item 7; :mod:`hydrokit.model.envelope`, read by :mod:`hydrokit.io.envelope`)
what the identification's fitted runs covered — each held command's steady straight speed, the
ranges of command, speed, deflection, yaw rate and drift; ``hydrokit sysid`` writes it beside
``identification:``, and ``hydrokit manoeuvre`` and ``hydrokit simulate`` say when a prediction
leaves it.

Writing: :func:`vehicle_text` is the one writer of vehicle files (``hydrokit sysid``, ``sysid
compare`` and ``hydrokit run`` all write through it); :func:`identified_vehicle_document` builds
the document of an identified vehicle and :func:`write_terms` puts identified ``terms.<term>``
values into one.
"""

from __future__ import annotations

import datetime
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.constants import GRAVITY, SEAWATER_DENSITY
from hydrokit.core.drag import DragElement
from hydrokit.core.names import DOF_NAMES
from hydrokit.core.validate import body_quantity, cut, cut_repr, mapping, matrix, number, vector
from hydrokit.errors import InputError
from hydrokit.io.fields import is_field, write_fields
from hydrokit.io.yamlfile import check_keys, read_yaml
from hydrokit.model.identification import VERDICTS, Identification
from hydrokit.model.terms import TermSet, parse_term
from hydrokit.model.uncertainty import COEFFICIENTS, TERM_PREFIX, check_parameter, location
from hydrokit.model.vehicle import Service, Vehicle, make_vehicle

VEHICLES_DIR = Path(__file__).resolve().parents[1] / "data" / "vehicles"
REQUIRED = (
    "mass",
    "volume",
    "inertia",
    "center_of_gravity",
    "center_of_buoyancy",
    "added_mass",
    "linear_damping",
    "quadratic_damping",
)
KNOWN = set(REQUIRED) | {
    "name",
    "gravity",
    "fluid",
    "reference_length",
    "reference_speed",
    "terms",
    "terms_nondimensional",
    "thrusters",
    "description",
    "source",
    "sources",
    "notes",
    "warnings",
    "geometry",
    "allocation",
    "volume_printed",
    "added_mass_coriolis",
    "uncertainty",
    "project",
    "drag_elements",
    "allow_negative_damping",
    "control_surfaces",
    "dofs",
    "hull",
    "wind",
    "identification",
    "service",
    "envelope",
}
#: the keys of the ``service`` block (issue #55 item 2: how the vehicle moves at its service speed)
SERVICE_KEYS = ("command", "force", "speed")
#: the keys of the ``identification`` block (issue #48: what the fit that wrote the file claims)
IDENTIFICATION_KEYS = ("verdict", "reasons", "holdout_nrmse", "runs", "holdout", "method", "tool", "date")
#: the keys of the ``wind`` block (frozen, issue #48 item 4)
WIND_KEYS = (
    "frontal_area",
    "lateral_area",
    "length",
    "density",
    "model",
    "vessel",
    "parameters",
    "s_L",
    "coefficients",
    "source",
)
#: the keys of the ``wind.coefficients`` table
WIND_TABLE_KEYS = ("angle_deg", "C_X", "C_Y", "C_N")
#: the keys of the ``fluid`` block (the viscosity is read by other tools: Reynolds numbers)
FLUID_KEYS = ("density", "kinematic_viscosity")
#: the keys of one ``drag_elements`` entry (frozen, issue #11)
DRAG_ELEMENT_KEYS = ("name", "position", "linear", "quadratic")
#: the keys of the ``uncertainty`` block
UNCERTAINTY_KEYS = ("description", *COEFFICIENTS, "parameters", "covariance")
TERM_KEYS = {"value", "nondimensional", "printed", "note", "suspect", "factors", "source"}


def bundled_vehicles() -> list[str]:
    """Names of the bundled vehicles."""
    return sorted(p.stem for p in VEHICLES_DIR.glob("*.yaml"))


def resolve_vehicle(name_or_path: str | os.PathLike[str]) -> Path:
    """A path from a file path or a bundled vehicle name."""
    p = Path(name_or_path)
    if p.is_file():
        return p
    bundled = VEHICLES_DIR / f"{name_or_path}.yaml"
    if "/" not in str(name_or_path) and bundled.is_file():
        return bundled
    raise InputError(
        f"no such file or bundled vehicle '{cut(str(name_or_path))}' (bundled: {', '.join(bundled_vehicles())})"
    )


def load_vehicle(name_or_path: str | os.PathLike[str]) -> Vehicle:
    """Read and validate a vehicle file or bundled vehicle (see module docstring)."""
    path = resolve_vehicle(name_or_path)
    return parse_vehicle(read_yaml(path), str(path))


def _number(value: Any, field: str, source: str, positive: bool = False) -> float:
    return number(value, field, source, positive=positive)


def _vector(value: Any, n: int, field: str, source: str) -> np.ndarray:
    return vector(value, n, field, source)


def _drag_elements(value: Any, source: str) -> list[DragElement]:
    """The ``drag_elements`` list (see module docstring); signs and unique names are checked by
    :func:`hydrokit.model.vehicle.make_vehicle`."""
    if not isinstance(value, list):
        raise InputError(
            f"field 'drag_elements' = {cut_repr(value)}: expected a list of {{name, position, linear, quadratic}}",
            source,
        )
    out = []
    for k, entry in enumerate(value):
        where = f"drag_elements[{k}]"
        mapping(entry, where, source)
        unknown = sorted(map(str, set(entry) - set(DRAG_ELEMENT_KEYS)))
        if unknown:
            raise InputError(
                f"field '{where}': unknown key(s) {cut(str(unknown))}; expected {', '.join(DRAG_ELEMENT_KEYS)}", source
            )
        for key in ("name", "position"):
            if key not in entry:
                raise InputError(f"field '{where}': missing '{key}'", source)
        name = entry["name"]
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"field '{where}.name' = {cut_repr(name)}: expected a non-empty text", source)
        triples = [
            _vector(entry.get(key, [0.0, 0.0, 0.0]), 3, f"{where}.{key}", source)
            for key in ("position", "linear", "quadratic")
        ]
        p, lin, quad = ((float(a[0]), float(a[1]), float(a[2])) for a in triples)
        out.append(DragElement(name, p, lin, quad))
    return out


def _wind(value: Any, source: str) -> Any:
    """The ``wind:`` block (docs/model.md; :func:`hydrokit.model.wind.make_wind` checks the values)."""
    from hydrokit.model.wind import AIR_DENSITY, MODELS, make_wind

    block = mapping(value, "wind", source)
    check_keys(block, WIND_KEYS, "wind", source)
    for key in ("frontal_area", "lateral_area", "length"):
        if key not in block:
            raise InputError(f"field 'wind' has no '{key}': expected A_F, A_L (m^2) and L_oa (m)", source)
    size = {k: number(block[k], f"wind.{k}", source, positive=True) for k in ("frontal_area", "lateral_area", "length")}
    density = number(block.get("density", AIR_DENSITY), "wind.density", source, positive=True)
    model = block.get("model", "table" if "coefficients" in block else None)
    if model not in MODELS:
        raise InputError(f"field 'wind.model' = {cut_repr(model)}: expected one of {', '.join(MODELS)}", source)
    if model == "blendermann1994":
        for key in ("coefficients",):
            if key in block:
                raise InputError(f"field 'wind.{key}' is for model table: not with blendermann1994", source)
        if ("vessel" in block) == ("parameters" in block):
            raise InputError(
                "field 'wind': expected one of 'vessel' (a type of Blendermann 1994) or 'parameters' "
                "[CD_t, CD_l_AF_bow, CD_l_AF_stern, delta]",
                source,
            )
        vessel = block.get("vessel")
        if vessel is not None and not isinstance(vessel, str):
            raise InputError(f"field 'wind.vessel' = {cut_repr(vessel)}: expected a vessel type's name", source)
        s_l = number(block.get("s_L", 0.0), "wind.s_L", source)
        return make_wind(
            model=model,
            vessel=vessel,
            parameters=block.get("parameters"),
            s_L=s_l,
            density=density,
            source=source,
            **size,
        )
    for key in ("vessel", "parameters", "s_L"):
        if key in block:
            raise InputError(f"field 'wind.{key}' is for model blendermann1994: not with a table", source)
    if "coefficients" not in block:
        raise InputError("field 'wind' has no 'coefficients': expected {angle_deg, C_X, C_Y, C_N} lists", source)
    table = mapping(block["coefficients"], "wind.coefficients", source)
    check_keys(table, WIND_TABLE_KEYS, "wind.coefficients", source)
    cols = {}
    for key in WIND_TABLE_KEYS:
        raw = table.get(key)
        if not isinstance(raw, list) or len(raw) < 2:
            raise InputError(
                f"field 'wind.coefficients.{key}' = {cut_repr(raw)}: expected a list of ≥ 2 numbers", source
            )
        cols[key] = [number(x, f"wind.coefficients.{key}[{i}]", source) for i, x in enumerate(raw)]
    return make_wind(
        size["frontal_area"],
        size["lateral_area"],
        size["length"],
        density,
        "table",
        angles=np.radians(cols["angle_deg"]),
        C_X=cols["C_X"],
        C_Y=cols["C_Y"],
        C_N=cols["C_N"],
        source=source,
    )


def _uncertainty(
    value: Any,
    source: str,
    terms: TermSet | None = None,
    surfaces: tuple[str, ...] = (),
    thrusters: tuple[str, ...] = (),
) -> Any:
    """The ``uncertainty`` block as an :class:`~hydrokit.model.uncertainty.Uncertainty` (or None);
    a ``terms.<term>`` parameter must name one of the vehicle's ``terms`` (or an acceleration
    term), with ``delta(NAME)`` among its control ``surfaces``."""
    from hydrokit.model.uncertainty import make_uncertainty

    if value is None:
        return None
    mapping(value, "uncertainty", source)
    unknown = sorted(map(str, set(value) - set(UNCERTAINTY_KEYS)))
    if unknown:
        raise InputError(
            f"field 'uncertainty': unknown key(s) {cut(str(unknown))}; expected {', '.join(UNCERTAINTY_KEYS)}", source
        )
    sigma = {}
    for coef in UNCERTAINTY_KEYS[1:4]:
        if coef in value:
            s = _vector(value[coef], 6, f"uncertainty.{coef}", source)
            if np.any(s < 0):
                raise InputError(
                    f"field 'uncertainty.{coef}' = {s.tolist()}: expected 6 standard errors ≥ 0 (SI)", source
                )
            sigma[coef] = s.tolist()
    names = value.get("parameters") or []
    if not isinstance(names, list):
        raise InputError(f"field 'uncertainty.parameters' = {cut_repr(names)}: expected a list of names", source)
    return make_uncertainty(names, value.get("covariance"), sigma, source, terms, surfaces, thrusters)


def _texts(value: Any, field: str, source: str) -> tuple[str, ...]:
    """A list of texts (``identification.reasons``, ``.runs`` …)."""
    if not isinstance(value, list) or not all(isinstance(x, str) for x in value):
        raise InputError(f"field '{field}' = {cut_repr(value)}: expected a list of texts", source)
    return tuple(value)


def _identification(value: Any, source: str) -> Identification | None:
    """The ``identification:`` block (module docstring; :mod:`hydrokit.model.identification`), or
    None when the file has none (no claim)."""
    if value is None:
        return None
    block = mapping(value, "identification", source)
    check_keys(block, IDENTIFICATION_KEYS, "identification", source)
    verdict = block.get("verdict")
    if verdict not in VERDICTS:
        raise InputError(
            f"field 'identification.verdict' = {cut_repr(verdict)}: expected {' or '.join(map(repr, VERDICTS))}",
            source,
        )
    lists = {k: _texts(block.get(k, []), f"identification.{k}", source) for k in ("reasons", "runs", "holdout")}
    nrmse: dict[str, dict[str, float]] = {}
    for run, channels in mapping(block.get("holdout_nrmse") or {}, "identification.holdout_nrmse", source).items():
        where = f"identification.holdout_nrmse.{cut(str(run))}"
        values = {
            str(c): number(v, f"{where}.{cut(str(c))}", source) for c, v in mapping(channels, where, source).items()
        }
        for c, v in values.items():
            if v < 0:
                raise InputError(f"field '{where}.{cut(c)}' = {v:g}: expected an NRMSE ≥ 0 (–)", source)
        nrmse[str(run)] = values
    texts = {}
    for key in ("method", "tool", "date"):
        raw = block.get(key, "")
        if key == "date" and isinstance(raw, (datetime.date, datetime.datetime)):
            raw = raw.isoformat()  # an unquoted date in a hand-edited file
        if not isinstance(raw, str):
            raise InputError(f"field 'identification.{key}' = {cut_repr(raw)}: expected a text", source)
        texts[key] = raw
    return Identification(
        str(verdict),
        lists["reasons"],
        nrmse,
        lists["runs"],
        lists["holdout"],
        texts["method"],
        texts["tool"],
        texts["date"],
    )


def read_identification(name_or_path: str | os.PathLike[str]) -> Identification | None:
    """The ``identification:`` block of a vehicle file or bundled vehicle, read without building the
    vehicle (``--strict`` checks it before anything runs).

    Parameters
    ----------
    name_or_path : str or path — a vehicle YAML file or a bundled name

    Returns
    -------
    Identification or None — None when the file has no block (no claim)

    Raises
    ------
    InputError
        A missing file, or a block that is not as the module docstring says (naming the field).
    """
    path = resolve_vehicle(name_or_path)
    data = read_yaml(path)
    return _identification(data.get("identification") if isinstance(data, dict) else None, str(path))


def identification_block(result: Any) -> dict[str, Any] | None:
    """The ``identification:`` block of a fit's result (None when the result has no verdict).

    Parameters
    ----------
    result : an identification-from-logs result: ``verdict`` (``fits``, ``reasons``), ``runs``
        (dicts with ``name``, ``holdout`` and per channel ``nrmse`` and ``moving``), ``method``

    Returns
    -------
    dict — verdict, reasons, the held-out NRMSE of each moving channel (–, per run or window), runs
    and holdout (the run files' stems; a windowed fit's windows named by their run), method, tool
    (``hydrokit sysid VERSION``) and date (UTC, ISO 8601)
    """
    from importlib.metadata import PackageNotFoundError, version

    try:
        tool = f"hydrokit sysid {version('hydrokit')}"
    except PackageNotFoundError:  # a source tree run without installing
        tool = "hydrokit sysid"
    verdict = getattr(result, "verdict", None)
    if not isinstance(verdict, Mapping) or "fits" not in verdict:
        return None
    nrmse: dict[str, dict[str, float]] = {}
    for run in result.runs:
        if run.get("holdout"):
            chans = {
                str(c): round(float(e["nrmse"]), 4)
                for c, e in (run.get("channels") or {}).items()
                if e.get("moving", True) and math.isfinite(float(e.get("nrmse", math.nan)))
            }
            if chans:
                nrmse[str(run["name"])] = chans
    block: dict[str, Any] = {
        "verdict": VERDICTS[0] if verdict["fits"] else VERDICTS[1],
        "reasons": [str(r) for r in verdict.get("reasons", [])],
    }
    if nrmse:
        block["holdout_nrmse"] = nrmse
    for key, held in (("runs", False), ("holdout", True)):
        # the files: a windowed fit names its windows RUN@STARTs
        names = [str(r["name"]) for r in result.runs if bool(r["holdout"]) is held]
        block[key] = list(dict.fromkeys(n.split("@")[0] if getattr(result, "windows", None) else n for n in names))
    block["method"] = str(getattr(result, "method", ""))
    block["tool"] = tool
    block["date"] = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return block


def _provenance(data: dict[str, Any]) -> tuple[str, ...]:
    """Lines saying where the coefficients came from, as far as the file says (never an error:
    these fields are free text)."""
    out = []
    for key in ("source", "sources"):
        value = data.get(key)
        if isinstance(value, dict):
            out += [f"{key}.{k}: {cut(str(v))}" for k, v in value.items()]
        elif isinstance(value, list):
            out += [f"{key}: {cut(str(v))}" for v in value]
        elif value is not None:
            out.append(f"{key}: {cut(str(value))}")
    project = data.get("project")
    if isinstance(project, dict) and isinstance(project.get("sources"), dict):
        name = project.get("name")
        virtual = " (virtual data)" if project.get("virtual_data") else ""
        out.append(f"identified by hydrokit run of project {cut(str(name))}{virtual}; source per coefficient:")
        for dof, coefs in project["sources"].items():
            if isinstance(coefs, dict):
                out.append(f"{cut(str(dof))}: " + ", ".join(f"{c} {cut(str(s))}" for c, s in coefs.items()))
    return tuple(out)


def _feeding_terms(velocity_terms: list[Any]) -> list[str]:
    """Derivative terms that are damping of their own DOF (X_u, X_u|u|, N_rrr: odd in that one
    velocity) with a positive SNAME coefficient, i.e. pushing along the motion."""
    from hydrokit.model.terms import ABS, VEL

    out = []
    for term, coef in velocity_terms:
        own = bool(term.factors) and all(f.indices == (term.dof,) and f.kind in (VEL, ABS) for f in term.factors)
        if own and sum(f.kind == VEL for f in term.factors) % 2 == 1 and coef > 0:
            out.append(f"terms.{term.name} = {coef:.4g} is positive (a damping derivative is negative in SNAME)")
    return out


def _sign_warnings(
    M_A: np.ndarray,
    D_L: np.ndarray,
    D_Q: np.ndarray,
    allow: bool,
    source: str,
    feeding: list[str],
) -> list[str]:
    """Non-physical signs: negative damping is refused unless the file allows it; a negative
    added mass that still flies is said.

    A negative linear damping feeds energy in where it dominates, at low speed, a negative
    quadratic one at speed, and so does a positive own-DOF damping derivative of ``terms:``
    (X_u, X_u|u| …, ``feeding``): refused (one line naming the field and the values) unless the file
    sets ``allow_negative_damping: true``, then said (the quadratic warning comes from
    :func:`hydrokit.model.vehicle.make_vehicle`). A negative added mass (M_A after the ``terms:``)
    makes the body easier to accelerate than in vacuum; one so negative that M_RB + M_A is not
    positive definite is refused by :func:`hydrokit.model.vehicle.make_vehicle`.
    """
    out = []
    for field, diag, effect in (
        ("linear_damping", np.diag(D_L), "energy is fed in at low speed"),
        ("added_mass", np.diag(M_A), "the fluid makes the body easier to accelerate (expected −X_udot > 0 …)"),
    ):
        if np.any(diag < 0):
            out.append(f"{field} has negative diagonal entries {diag.tolist()}: {effect}")
    said = [w for w in out if w.startswith("linear_damping")]
    if np.any(D_Q < 0):
        said.append(f"quadratic_damping has negative entries {D_Q.tolist()}: energy is fed in at speed")
    for text in feeding:
        said.append(f"{text}: energy is fed in")
        out.append(said[-1])
    if said and not allow:
        field = said[0].split(" ", 1)[0]
        raise InputError(
            f"field '{field}': {said[0]}; expected {'a coefficient ≤ 0' if field.startswith('terms.') else 'entries ≥ 0'}"
            ", or 'allow_negative_damping: true' if intended",
            source,
        )
    return out


def _thruster_names(value: Any) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(names, propeller names) of the ``thrusters:`` list in file order, for the ``T(NAME)`` and
    ``n(NAME)`` term factors; the block itself is read and checked by :mod:`hydrokit.io.thrusters`."""
    if not isinstance(value, list):
        return (), ()
    names: list[str] = []
    props: list[str] = []
    for entry in value:
        name = entry.get("name") if isinstance(entry, dict) else None
        if isinstance(name, (int, float)) and not isinstance(name, bool):
            name = str(name)
        name = name if isinstance(name, str) else ""
        names.append(name)
        if isinstance(entry, dict) and "kt_forward" in entry:
            props.append(name)
    return tuple(names), tuple(props)


def parse_vehicle(data: dict[str, Any], source: str) -> Vehicle:
    """Validate a vehicle mapping (errors name the file and field)."""
    for key in REQUIRED:
        if key not in data:
            raise InputError(f"missing field '{key}' (see docs/model.md for the vehicle file)", source)
    check_keys(data, KNOWN, "", source)
    identification = _identification(data.get("identification"), source)
    unfit = identification.warning(source) if identification is not None else None
    warnings: list[str] = [unfit] if unfit else []  # first: the loudest thing to say of this vehicle
    flagged = data.get("warnings") or []
    if isinstance(flagged, list):
        warnings.extend(str(w) for w in flagged)
    gravity = _number(data.get("gravity", GRAVITY), "gravity", source, positive=True)
    fluid = data.get("fluid", {"density": SEAWATER_DENSITY})
    if not isinstance(fluid, dict) or "density" not in fluid:
        raise InputError(f"field 'fluid' = {cut_repr(fluid)}: expected a mapping with density (kg/m^3)", source)
    check_keys(fluid, FLUID_KEYS, "fluid", source)
    rho = _number(fluid["density"], "fluid.density", source, positive=True)
    mass = body_quantity(_number(data["mass"], "mass", source, positive=True), "mass", "mass", source)
    volume = body_quantity(_number(data["volume"], "volume", source, positive=True), "volume", "volume", source)
    inertia = matrix(data["inertia"], 3, "inertia", source)
    r_g = _vector(data["center_of_gravity"], 3, "center_of_gravity", source)
    r_b = _vector(data["center_of_buoyancy"], 3, "center_of_buoyancy", source)
    M_A = matrix(data["added_mass"], 6, "added_mass", source)
    D_L = matrix(data["linear_damping"], 6, "linear_damping", source)
    dq = data["quadratic_damping"]
    D_Q = _vector(dq, 6, "quadratic_damping", source)
    L = data.get("reference_length")
    L = None if L is None else _number(L, "reference_length", source, positive=True)
    U = data.get("reference_speed")
    U = None if U is None else _number(U, "reference_speed", source, positive=True)
    default_nd = data.get("terms_nondimensional", False)
    if not isinstance(default_nd, bool):
        raise InputError(f"field 'terms_nondimensional' = {cut_repr(default_nd)}: expected true or false", source)
    from hydrokit.io.envelope import read_envelope
    from hydrokit.io.surfaces import read_control_surfaces, read_dofs

    thrusters, propellers = _thruster_names(data.get("thrusters"))
    surfaces = read_control_surfaces(data.get("control_surfaces"), source, thrusters, data.get("thrusters"))
    dofs = read_dofs(data.get("dofs"), source)
    envelope = read_envelope(data.get("envelope"), source, thrusters, surfaces.names)
    terms_raw = data.get("terms") or {}
    if not isinstance(terms_raw, dict):
        raise InputError(f"field 'terms' = {cut_repr(terms_raw)}: expected a mapping of term names to values", source)
    velocity_terms = []
    hull_elements: list[DragElement] = []
    if data.get("hull") is not None:
        from hydrokit.io.hull import read_hull_block

        hull_elements, hull_terms = read_hull_block(data["hull"], source, rho)
        velocity_terms += [(parse_term(n, source, surfaces.names, thrusters, propellers), c) for n, c in hull_terms]
    for name, spec in terms_raw.items():
        where = f"terms.{cut(str(name))}"
        nd = default_nd
        if isinstance(spec, dict):
            extra = set(spec) - TERM_KEYS
            if extra:
                raise InputError(
                    f"field '{where}': unknown key(s) {cut(str(sorted(extra)))}; expected value, nondimensional", source
                )
            if "value" not in spec:
                raise InputError(f"field '{where}': missing 'value'", source)
            nd = spec.get("nondimensional", default_nd)
            if not isinstance(nd, bool):
                raise InputError(f"field '{where}.nondimensional' = {cut_repr(nd)}: expected true or false", source)
            value = _number(spec["value"], where + ".value", source)
        else:
            value = _number(spec, where, source)
        term = parse_term(str(name), source, surfaces.names, thrusters, propellers)
        if nd:
            if L is None:
                raise InputError(
                    f"field '{where}' is non-dimensional: the vehicle needs 'reference_length' (m)", source
                )
            coef = term.dimensional(value, rho, L, U, source)
        else:
            coef = value
        if term.acceleration is not None:
            # SNAME: X_udot < 0 is an added mass of −X_udot in M_A[dof, accel]
            M_A[term.dof, term.acceleration] += -coef
        else:
            velocity_terms.append((term, coef))
    name = str(data.get("name", Path(source).stem))
    cor = data.get("added_mass_coriolis", True)
    if not isinstance(cor, bool):
        raise InputError(f"field 'added_mass_coriolis' = {cut_repr(cor)}: expected true or false", source)
    elements = _drag_elements(data["drag_elements"], source) if "drag_elements" in data else None
    if hull_elements:
        elements = (elements or []) + hull_elements
    allow = data.get("allow_negative_damping", False)
    if not isinstance(allow, bool):
        raise InputError(f"field 'allow_negative_damping' = {cut_repr(allow)}: expected true or false", source)
    warnings.extend(_sign_warnings(M_A, D_L, D_Q, allow, source, _feeding_terms(velocity_terms)))
    uncertainty = _uncertainty(
        data.get("uncertainty"), source, TermSet.build(velocity_terms), surfaces.names, thrusters
    )
    return make_vehicle(
        name,
        mass,
        volume,
        gravity,
        rho,
        inertia,
        r_g,
        r_b,
        M_A,
        D_L,
        D_Q,
        TermSet.build(velocity_terms),
        L,
        source,
        warnings,
        cor,
        elements,
        uncertainty,
        _provenance(data),
        surfaces,
        dofs,
        thrusters,
        _wind(data["wind"], source) if data.get("wind") is not None else None,
        identification,
        _service(data.get("service"), source),
        envelope,
    )


def _service(value: Any, source: str) -> Service | None:
    """The ``service:`` block (module docstring) as a :class:`~hydrokit.model.vehicle.Service`, or
    None when the file has none; :func:`hydrokit.model.vehicle.make_vehicle` checks the speed's
    sign and the thruster names against the vehicle's."""
    if value is None:
        return None
    block = mapping(value, "service", source)
    check_keys(block, SERVICE_KEYS, "service", source)
    if "speed" not in block:
        raise InputError("field 'service' has no 'speed': expected the steady speed it reaches (m/s)", source)
    commands = mapping(block.get("command") or {}, "service.command", source)
    command = tuple((str(name), number(c, f"service.command.{cut(str(name))}", source)) for name, c in commands.items())
    force = block.get("force")
    if force is not None and not (isinstance(force, list) and len(force) == 6):
        raise InputError(
            f"field 'service.force' = {cut_repr(force)}: expected 6 numbers X, Y, Z (N), K, M, N (N·m), body axes",
            source,
        )
    return Service(
        number(block["speed"], "service.speed", source),
        command,
        None if force is None else tuple(_vector(force, 6, "service.force", source).tolist()),
    )


#: how every vehicle file is dumped: keys in the document's order, rows of numbers on one line,
#: lines up to 120 characters, non-ASCII names kept
_DUMP_OPTIONS: dict[str, Any] = {"sort_keys": False, "allow_unicode": True, "width": 120, "default_flow_style": None}


def vehicle_text(doc: Mapping[str, Any], header: str = "") -> str:
    """The text of a vehicle file: ``header`` as comment lines, then ``doc`` as YAML.

    Parameters
    ----------
    doc : mapping — the vehicle document (plain lists, numbers and strings; see the module docstring)
    header : str — comment lines; a line not starting with ``#`` gets ``# `` put before it, so no
        header text (a project's name) can be read as YAML

    Returns
    -------
    str — the file's text, which :func:`load_vehicle` reads back into the same vehicle
    """
    import yaml

    lines = [ln if ln.startswith("#") else f"# {ln}" for ln in header.splitlines()]
    head = "".join(f"{ln}\n" for ln in lines)
    return head + yaml.safe_dump(dict(doc), **_DUMP_OPTIONS)


def identified_vehicle_document(result: Any, base_data: Mapping[str, Any]) -> dict[str, Any]:
    """The base vehicle file's fields with the identified values and an ``uncertainty:`` block.

    Parameters
    ----------
    result : an identification-from-logs result (``SysidResult``): ``parameters``
        (names), ``values`` (SI), ``covariance`` (SI², in ``parameters`` order), ``method`` and
        ``runs`` (dicts with ``name`` and ``holdout``)
    base_data : mapping — the base vehicle file's fields, as read

    Returns
    -------
    dict — diagonal coefficients written into ``added_mass`` / ``linear_damping`` /
    ``quadratic_damping`` (6 numbers or a 6×6 matrix, as the base has them); ``terms.<term>``
    into ``terms`` as dimensional values (:func:`write_terms`); surface, thruster and wind fields
    (``control_surfaces.NAME.FIELD`` …) where the file keeps them (:func:`hydrokit.io.fields.write_fields`,
    in the file's units). The ``uncertainty`` block holds
    the σ of the diagonal coefficients and the full covariance (SI²) over every free parameter,
    ``terms.*`` included, which ``simulate --samples`` and ``mission --samples`` read. The
    ``identification`` block holds the fit's verdict, reasons, held-out NRMSE, runs, tool and date
    (:func:`identification_block`; replacing the base's own, if any), and the ``envelope`` block
    what the fitted runs covered (the result's ``envelope``, :mod:`hydrokit.model.envelope`).
    """
    doc = {k: v for k, v in base_data.items() if k != "uncertainty"}
    names = list(result.parameters)
    write_identified(doc, [(n, float(v)) for n, v in zip(names, result.values)])
    cov = np.asarray(result.covariance, float)
    se = {c: [0.0] * 6 for c in COEFFICIENTS}
    for k, name in enumerate(names):
        coef, _, dof = name.partition(".")
        if coef in COEFFICIENTS:
            se[coef][DOF_NAMES.index(dof)] = math.sqrt(max(float(cov[k, k]), 0.0))
    doc["uncertainty"] = {
        "description": f"hydrokit sysid ({result.method}): standard errors (SI) and covariance (SI²) of the "
        "identified parameters, inflated for coloured residuals",
        **se,
        "parameters": names,
        "covariance": (0.5 * (cov + cov.T)).tolist(),
    }
    runs = ", ".join(r["name"] for r in result.runs if not r["holdout"])
    sources = [str(s) for s in (doc.get("sources") or [])] if isinstance(doc.get("sources"), list) else []
    doc["sources"] = sources + [f"hydrokit sysid ({result.method}) from runs {runs}; free: {', '.join(names)}"]
    doc["name"] = f"{base_data.get('name', 'vehicle')}-sysid"
    doc.pop("identification", None)  # the base's claim is not this fit's
    doc.pop("envelope", None)  # nor are its runs
    block = identification_block(result)
    if block is not None:
        doc["identification"] = block
    envelope = getattr(result, "envelope", None)
    if envelope is not None:
        doc["envelope"] = envelope.to_dict()
    return doc


def write_identified(doc: dict[str, Any], values: Sequence[tuple[str, float]]) -> dict[str, Any]:
    """Write identified values into the vehicle document ``doc`` (changed in place and returned)
    where the file keeps them, as :func:`identified_vehicle_document` writes a fit.

    Parameters
    ----------
    doc : dict — a vehicle file's fields, as read
    values : (name, value) pairs — ``<coefficient>.<dof>`` into ``added_mass`` /
        ``linear_damping`` / ``quadratic_damping`` (6 numbers or a 6×6 matrix, as ``doc`` has
        them; SI), ``terms.<term>`` (:func:`write_terms`; SI), and surface, thruster and wind
        fields (:func:`hydrokit.io.fields.write_fields`; in the file's units), so the written
        vehicle flies the fitted values and its uncertainty block is centred on them

    Raises
    ------
    InputError
        A term or field the document cannot hold (one line naming it).
    """
    names = [n for n, _ in values]
    for coef in COEFFICIENTS:
        entries = doc.get(coef)
        matrix = isinstance(entries, list) and bool(entries) and all(isinstance(r, list) for r in entries)
        vals: Any = [list(map(float, r)) for r in entries] if matrix else [float(x) for x in entries]  # type: ignore[union-attr]
        for i, dof in enumerate(DOF_NAMES):
            name = f"{coef}.{dof}"
            if name in names:
                v = float(values[names.index(name)][1])
                if matrix:
                    vals[i][i] = v
                else:
                    vals[i] = v
        doc[coef] = vals
    write_terms(doc, [(n, float(v)) for n, v in values if n.startswith(TERM_PREFIX)])
    write_fields(doc, [(n, float(v)) for n, v in values if is_field(n)])
    return doc


def check_writable(
    base_data: Mapping[str, Any], start: Vehicle, names: Sequence[str], source: str = "--free"
) -> Vehicle:
    """The vehicle a fit of ``names`` writes, at their start values: each name's value in
    ``start`` written into a copy of ``base_data`` by :func:`write_identified`, with an
    ``uncertainty:`` block over them, and loaded back. ``hydrokit sysid`` calls it before any run
    is read, so a name the fit could not write into vehicle.yaml (or that would not load back)
    fails in the first second, not after the fit.

    Parameters
    ----------
    base_data : mapping — the base vehicle file's fields, as read (not changed)
    start : Vehicle — the fit's start: the base with its absent free terms added at 0
        (:func:`hydrokit.sysid.fit.check_options`)
    names : the free parameter names (:mod:`hydrokit.model.uncertainty`)
    source : str — what errors are prefixed with (the option that named the parameters)

    Raises
    ------
    InputError
        One line: the term, field or block that could not be written or read back.
    """
    import copy

    from hydrokit.model.uncertainty import parameter_value

    doc = copy.deepcopy({k: v for k, v in base_data.items() if k != "uncertainty"})
    doc["uncertainty"] = {"parameters": list(names), "covariance": [[0.0] * len(names) for _ in names]}
    try:
        write_identified(doc, [(n, parameter_value(start, n)) for n in names])
        return parse_vehicle(doc, "")
    except InputError as exc:
        raise InputError(f"the fit could not be written into a vehicle file: {exc}", source) from None


def doc_surfaces(doc: Mapping[str, Any]) -> tuple[str, ...]:
    """The control-surface names of a vehicle document (its ``control_surfaces:`` entries)."""
    entries = doc.get("control_surfaces") or []
    return tuple(str(e["name"]) for e in entries if isinstance(e, Mapping) and "name" in e)


def write_terms(doc: dict[str, Any], values: Sequence[tuple[str, float]]) -> dict[str, Any]:
    """Write identified ``terms.<term>`` values (SI, as :mod:`hydrokit.model.uncertainty` names
    them) into the vehicle document ``doc`` (changed in place and returned).

    ``delta(NAME)`` factors name the document's ``control_surfaces``, ``T(NAME)`` and ``n(NAME)``
    its ``thrusters`` (``n()`` a propeller), as its loader reads them. A velocity term replaces
    the file's entry of the same term (however spelt) with its SI
    value; an acceleration term (``terms.Y_vdot``, value −M_A[dof, acceleration]) is written as
    the file term that, with the document's ``added_mass`` entry, gives that M_A entry:
    term = added_mass[dof][acceleration] + value (the file subtracts a term from M_A).
    """
    terms = dict(doc.get("terms") or {})
    named = (doc_surfaces(doc), *_thruster_names(doc.get("thrusters")))  # surfaces, thrusters, propellers
    spelt = {}
    for key in terms:
        try:
            spelt[location(check_parameter(TERM_PREFIX + str(key), "term", "", *named))] = key
        except InputError:  # not a term this document's vehicle could load: never a free one
            continue
    for name, v in values:
        ref = check_parameter(name, "parameter", "", *named)
        key = spelt.get(location(ref), name[len(TERM_PREFIX) :])
        value = float(v)
        if ref.kind == "accel":
            am = doc.get("added_mass")
            a = 0.0
            if isinstance(am, list) and am and isinstance(am[0], list):
                a = float(am[ref.dof][ref.index])
            elif isinstance(am, list) and ref.dof == ref.index:
                a = float(am[ref.dof])
            value = a + value
        terms[key] = {"value": value, "nondimensional": False}
    if terms:
        doc["terms"] = terms
    return doc
