"""Project files (YAML) for ``hydrokit run``: the main job's inputs (issue #10 contract).

```yaml
name: udrobot
vehicle: base.yaml            # full-scale base: mass, volume, inertia, CG, CB, thrusters (vehicle file)
scale_ratio: 0.3              # model/full length ratio, as `hydrokit scale --ratio`
campaigns:                    # one entry per identified DOF
  - {dof: surge, rig: rigs/spring_x.yaml, launches: launches/spring_x/*.csv, method: output-error}
  - {dof: heave, rig: rigs/pendulum_z.yaml, launches: launches/pendulum_z/*.csv}
geometry: geometry.yaml       # optional: estimate (and --bem) for comparison and for DOFs not tested
forces: {surge: cfd_x.csv}    # optional CFD/tow force curves per DOF (speed m/s, force N), full scale
cfd: {speeds: [0.5, 1, 1.5], dofs: [heave]}   # optional: compute the CFD column with OpenFOAM (docs/cfd.md)
sysid: {runs: [dive1.csv, dive2.csv], holdout: [dive3.csv], free: [added_mass.surge, linear_damping.surge]}
                              # optional: identified from the vehicle's own free-running logs (docs/sysid.md)
choose: tank                  # rule when sources disagree: tank | geometry | bem | cfd | sysid (or per DOF)
mission: mission.yaml         # optional: flown with PID and S-plane on the identified vehicle
uncertainty: {samples: 200, seed: 1}   # Monte Carlo over the coefficient covariance
```

Extra fields (all optional): a campaign's own ``scale_ratio`` (its model may differ from the
project's), ``tare`` (a glob or list of in-air launches of a pendulum rig: the ENG2009 §IV.A air
tare is fitted to them and subtracted; or ``{launches: <glob or list>, convention: eng2009}`` to
convert γ to K_Q as ENG2009 does, γ·m·r, instead of the default ``physics`` γ·m/r), ``truth`` (model-scale ``added_mass``, ``linear_damping``, ``quadratic_damping``
of virtual data, shown as identified vs true), ``forces`` entries as
``{file, area (m²), density (kg/m³)}``, ``published`` (per DOF, full-scale values printed by a
source with a ``source`` text, shown in the comparison), ``choose`` as a mapping
``{surge: cfd, default: tank}``, ``virtual: true`` and ``description``. ``sysid`` takes
``runs`` and ``holdout`` (a glob or a list of run files, docs/sysid.md), ``free`` (a list or
comma-separated text of ``<coefficient>.<dof>`` / ``terms.<term>`` names), ``method``
(output-error or equation-error), ``dt`` (integration step, s), ``truth`` (the
``truth.json`` of ``hydrokit sysid generate``: the hidden values of virtual dives, shown as
true), ``window`` (a window length in s > 0, ``auto`` — the default, as ``hydrokit sysid
--window`` — or ``none`` for whole runs) and ``window_continuity`` (weight of the windows'
joins, dimensionless, ≥ 0, default 0). A project needs at least one campaign or a ``sysid``
section; ``scale_ratio`` only when a campaign lacks its own.

Paths are relative to the project file. Every problem is one line naming the field.
"""

from __future__ import annotations

import glob
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from hydrokit.core.names import DOF_NAMES
from hydrokit.core.validate import window_length, window_within
from hydrokit.errors import InputError
from hydrokit.identify.tare import TARE_CONVENTIONS
from hydrokit.identify.types import METHODS
from hydrokit.io.yamlfile import pydantic_error_line, read_yaml

# the coefficient names are the one table of hydrokit.model.uncertainty; re-exported here for
# one release (pipeline/compare.py still imports them from here)
from hydrokit.model.uncertainty import COEFFICIENTS  # noqa: F401

#: sources a coefficient can be chosen from
SOURCES = ("tank", "geometry", "bem", "cfd", "sysid")
PROJECTS_DIR = Path(__file__).resolve().parents[1] / "data" / "projects"


class _Truth(BaseModel):
    model_config = ConfigDict(extra="forbid")
    added_mass: float = Field(ge=0, description="kg or kg·m², model scale")
    linear_damping: float = Field(ge=0, description="N·s/m or N·m·s/rad, model scale")
    quadratic_damping: float = Field(ge=0, description="N·s²/m² or N·m·s²/rad², model scale")


class _Tare(BaseModel):
    model_config = ConfigDict(extra="forbid")
    launches: str | list[str]
    convention: str = Field("physics", description="physics (K_Q = γ m / r) or eng2009 (K_Q = γ m r)")


class _Campaign(BaseModel):
    model_config = ConfigDict(extra="forbid")
    dof: str
    rig: str
    launches: str | list[str]
    method: str = "output-error"
    scale_ratio: float | None = Field(None, gt=0)
    truth: _Truth | None = None
    tare: str | list[str] | _Tare | None = None


class _Force(BaseModel):
    model_config = ConfigDict(extra="forbid")
    file: str
    area: float | None = Field(None, gt=0, description="m²")
    density: float | None = Field(None, gt=0, description="kg/m³")


class _Cfd(BaseModel):
    model_config = ConfigDict(extra="forbid")
    body: str | None = Field(None, description="surface mesh, x,r profile or geometry file; default: geometry")
    speeds: list[float] = Field(min_length=3, description="m/s, full scale")
    dofs: list[str] = Field(default_factory=lambda: ["surge"], min_length=1)
    density: float | None = Field(None, gt=0, description="kg/m³; default the vehicle's")
    viscosity: float = Field(1.19e-6, gt=0, description="kinematic, m²/s")
    turbulence: str = "auto"
    grids: int = 1
    area: dict[str, float] = Field(default_factory=dict, description="m² per DOF")
    settings: dict[str, Any] = Field(default_factory=dict)


class _Uncertainty(BaseModel):
    model_config = ConfigDict(extra="forbid")
    samples: int = Field(200, ge=0, le=100_000)
    seed: int = 1


class _Sysid(BaseModel):
    model_config = ConfigDict(extra="forbid")
    runs: Any = Field(description="a glob or a list of run files")
    holdout: Any = Field(None, description="a glob or a list of run files, validation only")
    free: Any = Field(description="a list or comma-separated text of parameter names")
    method: str = "output-error"
    dt: float = Field(0.01, gt=0, le=0.1, description="integration step, s")
    truth: str | None = Field(None, description="truth.json of hydrokit sysid generate")
    window: Any = Field("auto", description="window length, s (> 0), 'auto' or 'none' (whole runs): sysid --window")
    window_continuity: float = Field(
        0.0, ge=0, allow_inf_nan=False, strict=True, description="weight of the windows' joins, dimensionless"
    )


class ProjectFile(BaseModel):
    """The project file schema (see module docstring)."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(min_length=1)
    vehicle: str
    scale_ratio: float | None = Field(None, gt=0, le=1000)
    campaigns: list[_Campaign] = Field(default_factory=list)
    sysid: _Sysid | None = None
    geometry: str | None = None
    forces: dict[str, str | _Force] = Field(default_factory=dict)
    cfd: _Cfd | None = None
    choose: str | dict[str, str] = "tank"
    mission: str | None = None
    uncertainty: _Uncertainty = Field(default_factory=lambda: _Uncertainty(samples=200, seed=1))
    published: dict[str, dict[str, Any]] = Field(default_factory=dict)
    virtual: bool = False
    description: str = ""


@dataclass(frozen=True)
class CampaignSpec:
    """One campaign: the DOF it identifies, its rig file and launch files (sorted), the method,
    the model/full length ratio and, for virtual data, the true model-scale coefficients (SI)."""

    dof: str
    rig: Path
    launches: tuple[Path, ...]
    method: str
    scale_ratio: float
    pattern: str
    truth: dict[str, float] | None = None
    tare: tuple[Path, ...] = ()
    #: γ → K_Q of the air tare: "physics" (γ m / r) or "eng2009" (γ m r)
    tare_convention: str = "physics"


@dataclass(frozen=True)
class ForceSpec:
    """A full-scale CFD or tow-tank force curve for one DOF: file (speed m/s, force N), reference
    area (m², None = the campaign rig's, scaled) and density (kg/m³, None = the vehicle's)."""

    dof: str
    file: Path
    area: float | None
    density: float | None


@dataclass(frozen=True)
class SysidSpec:
    """The ``sysid:`` section: identification from the vehicle's own free-running runs
    (``hydrokit sysid``, docs/sysid.md). runs, holdout : run files (sorted per glob);
    free : parameter names (``<coefficient>.<dof>``, ``terms.<term>``,
    ``control_surfaces.<name>.<field>`` or ``thrusters.<name>.<field>``); method : output-error
    or equation-error; dt : integration step, s; truth : name → hidden value (SI) of virtual
    dives (``truth.json`` of ``hydrokit sysid generate``), or None; truth_file : its path;
    window : window length, s, ``"auto"`` (windows only when a run drifts) or None (whole runs),
    as ``hydrokit sysid --window``; window_continuity : weight of the windows' joins,
    dimensionless (``--window-continuity``)."""

    runs: tuple[Path, ...]
    holdout: tuple[Path, ...]
    free: tuple[str, ...]
    method: str
    dt: float
    pattern: str
    truth: dict[str, float] | None = None
    truth_file: Path | None = None
    window: float | str | None = "auto"
    window_continuity: float = 0.0


#: the label of ``sysid.window`` in its messages (``field 'sysid.window' = 'banana': expected …``)
_WINDOW = "field 'sysid.window' ="

#: DOFs a CFD speed sweep can give (a pure motion along a body axis) and their axes
CFD_AXES = {"surge": "x", "sway": "y", "heave": "z"}


@dataclass(frozen=True)
class CfdSpec:
    """The ``cfd:`` section: compute the CFD column with OpenFOAM (``hydrokit cfd``) instead of
    reading force curves. body (a file), speeds (m/s, full scale), dofs (surge, sway, heave),
    density (kg/m³ or None: the vehicle's), viscosity (m²/s), turbulence, grids, area (m² per DOF,
    default the projected area), settings (further ``hydrokit.cfd.case.Settings`` fields)."""

    body: Path
    speeds: tuple[float, ...]
    dofs: tuple[str, ...]
    density: float | None
    viscosity: float
    turbulence: str
    grids: int
    area: dict[str, float]
    settings: dict[str, Any]


@dataclass(frozen=True)
class Project:
    """A validated project: every path resolved and existing, every glob expanded."""

    name: str
    source: Path
    vehicle: Path
    scale_ratio: float | None
    campaigns: tuple[CampaignSpec, ...]
    geometry: Path | None
    forces: dict[str, ForceSpec]
    choose: dict[str, str]
    mission: Path | None
    samples: int
    seed: int
    published: dict[str, dict[str, Any]] = field(default_factory=dict)
    virtual: bool = False
    description: str = ""
    cfd: CfdSpec | None = None
    sysid: SysidSpec | None = None

    @property
    def root(self) -> Path:
        """The folder of the project file (paths in it are relative to this)."""
        return self.source.parent

    def input_files(self) -> list[Path]:
        """Every file the project reads (for hashing and for the report)."""
        files = [self.source, self.vehicle]
        for c in self.campaigns:
            files += [c.rig, *c.launches, *c.tare]
        files += [f.file for f in self.forces.values()]
        files += [p for p in (self.geometry, self.mission) if p is not None]
        if self.cfd is not None and self.cfd.body not in files:
            files.append(self.cfd.body)
        if self.sysid is not None:
            files += [*self.sysid.runs, *self.sysid.holdout]
            files += [self.sysid.truth_file] if self.sysid.truth_file is not None else []
        return list(dict.fromkeys(files))


def resolve_project(name_or_path: str | os.PathLike[str]) -> Path:
    """A project file from a path, a folder holding ``project.yaml``, or a bundled name."""
    p = Path(name_or_path)
    if p.is_dir() and (p / "project.yaml").is_file():
        return p / "project.yaml"
    if p.is_file():
        return p
    bundled = PROJECTS_DIR / str(name_or_path) / "project.yaml"
    if bundled.is_file():
        return bundled
    names = ", ".join(bundled_projects())
    raise InputError(f"project {str(name_or_path)!r} not found: expected a project file or a bundled name ({names})")


def bundled_projects() -> list[str]:
    """Names of the bundled projects."""
    return sorted(p.parent.name for p in PROJECTS_DIR.glob("*/project.yaml"))


def _file(root: Path, value: str, field_name: str, source: str) -> Path:
    p = Path(value)
    p = p if p.is_absolute() else root / p
    if not p.is_file():
        raise InputError(
            f"field '{field_name}' = {value!r}: file not found (expected a path relative to the project)", source
        )
    return p


def _launches(
    root: Path, value: str | list[str], field_name: str, source: str, what: str = "launch files"
) -> tuple[Path, ...]:
    patterns = [value] if isinstance(value, str) else list(value)
    if not patterns:
        raise InputError(f"field '{field_name}' is empty: expected a glob or a list of {what}", source)
    found: list[Path] = []
    for pat in patterns:
        full = pat if Path(pat).is_absolute() else str(root / pat)
        if glob.has_magic(pat):
            hits = sorted(Path(h) for h in glob.glob(full) if Path(h).is_file())
            if not hits:
                raise InputError(f"field '{field_name}' = {pat!r}: the glob matches no file", source)
            found += hits
        else:
            found.append(_file(root, pat, field_name, source))
    return tuple(dict.fromkeys(found))


def _choose(value: str | dict[str, str], source: str) -> dict[str, str]:
    rules = {"default": value} if isinstance(value, str) else dict(value)
    rules.setdefault("default", "tank")
    for key, rule in rules.items():
        if key != "default" and key not in DOF_NAMES:
            raise InputError(
                f"field 'choose.{key}': unknown DOF; expected one of {', '.join(DOF_NAMES)} or default", source
            )
        if rule not in SOURCES:
            where = "choose" if isinstance(value, str) else f"choose.{key}"
            raise InputError(f"field '{where}' = {rule!r}: expected one of {', '.join(SOURCES)}", source)
    return {d: rules.get(d, rules["default"]) for d in DOF_NAMES}


def parse_project(data: dict[str, Any], path: Path) -> Project:
    """Validate a project mapping read from ``path`` (errors name the file and field)."""
    source = str(path)
    try:
        f = ProjectFile.model_validate(data)
    except ValidationError as exc:
        raise pydantic_error_line(exc, source, ProjectFile) from None
    root = path.parent
    if not f.campaigns and f.sysid is None:
        raise InputError(
            "field 'campaigns' is empty and there is no 'sysid': expected at least one tank campaign or a "
            "'sysid:' section (runs of the vehicle itself)",
            source,
        )
    campaigns = []
    seen: dict[str, int] = {}
    for i, c in enumerate(f.campaigns):
        where = f"campaigns[{i}]"
        if c.dof not in DOF_NAMES:
            raise InputError(f"field '{where}.dof' = {c.dof!r}: expected one of {', '.join(DOF_NAMES)}", source)
        if c.dof in seen:
            raise InputError(
                f"field '{where}.dof' = {c.dof!r}: already identified by campaigns[{seen[c.dof]}]; expected one campaign per DOF",
                source,
            )
        seen[c.dof] = i
        if c.method not in METHODS:
            raise InputError(f"field '{where}.method' = {c.method!r}: expected one of {', '.join(METHODS)}", source)
        scale = c.scale_ratio if c.scale_ratio is not None else f.scale_ratio
        if scale is None:
            raise InputError(
                f"field 'scale_ratio' is missing: expected the model/full length ratio (> 0) of {where} "
                "(or the campaign's own scale_ratio)",
                source,
            )
        tare, convention = (c.tare.launches, c.tare.convention) if isinstance(c.tare, _Tare) else (c.tare, "physics")
        if convention not in TARE_CONVENTIONS:
            raise InputError(
                f"field '{where}.tare.convention' = {convention!r}: expected one of {', '.join(TARE_CONVENTIONS)}",
                source,
            )
        campaigns.append(
            CampaignSpec(
                dof=c.dof,
                rig=_file(root, c.rig, f"{where}.rig", source),
                launches=_launches(root, c.launches, f"{where}.launches", source),
                method=c.method,
                scale_ratio=scale,
                pattern=c.launches if isinstance(c.launches, str) else ", ".join(c.launches),
                truth=c.truth.model_dump() if c.truth is not None else None,
                tare=_launches(root, tare, f"{where}.tare", source) if tare is not None else (),
                tare_convention=convention,
            )
        )
    forces = {}
    for dof, spec in f.forces.items():
        if dof not in DOF_NAMES:
            raise InputError(f"field 'forces.{dof}': unknown DOF; expected one of {', '.join(DOF_NAMES)}", source)
        spec = spec if isinstance(spec, _Force) else _Force(file=spec, area=None, density=None)
        forces[dof] = ForceSpec(dof, _file(root, spec.file, f"forces.{dof}", source), spec.area, spec.density)
    cfd = _cfd(f, root, forces, source)
    for dof in f.published:
        if dof not in DOF_NAMES:
            raise InputError(f"field 'published.{dof}': unknown DOF; expected one of {', '.join(DOF_NAMES)}", source)
    return Project(
        name=f.name,
        source=path,
        vehicle=_file(root, f.vehicle, "vehicle", source),
        scale_ratio=f.scale_ratio,
        campaigns=tuple(campaigns),
        geometry=_file(root, f.geometry, "geometry", source) if f.geometry else None,
        forces=forces,
        choose=_choose(f.choose, source),
        mission=_file(root, f.mission, "mission", source) if f.mission else None,
        samples=f.uncertainty.samples,
        seed=f.uncertainty.seed,
        published=f.published,
        virtual=f.virtual,
        description=f.description,
        cfd=cfd,
        sysid=_sysid(f.sysid, root, source, _file(root, f.vehicle, "vehicle", source)),
    )


def _file_list(root: Path, value: Any, field_name: str, source: str) -> tuple[Path, ...]:
    """Run files from a glob or a list of paths and globs (each text)."""
    if isinstance(value, str):
        return _launches(root, value, field_name, source, "run files")
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise InputError(
            f"field '{field_name}' = {str(value)[:60]!r}: expected a glob or a list of run files (text)", source
        )
    return _launches(root, value, field_name, source, "run files")


def _vehicle_names(path: Path) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The control-surface and thruster names of the vehicle file ``path`` (file order), as far
    as it can be read here: a free ``control_surfaces.NAME.FIELD``, ``thrusters.NAME.FIELD``,
    ``delta(NAME)`` or ``T(NAME)`` is checked against them (the whole vehicle is checked when it
    is loaded; an unreadable file gives no names and its own error there)."""
    try:
        data = read_yaml(path)
    except (InputError, OSError):
        return (), ()

    def names(block: Any) -> tuple[str, ...]:
        items = block if isinstance(block, list) else []
        return tuple(str(e["name"]) for e in items if isinstance(e, dict) and isinstance(e.get("name"), str))

    if not isinstance(data, dict):
        return (), ()
    return names(data.get("control_surfaces")), names(data.get("thrusters"))


def _free_names(
    value: Any, source: str, surfaces: tuple[str, ...] = (), thrusters: tuple[str, ...] = ()
) -> tuple[str, ...]:
    """The free names of ``sysid.free`` (a list or comma-separated text), each checked;
    ``surfaces`` and ``thrusters``: the vehicle's control-surface and thruster names (file order)
    that a field name (``control_surfaces.rudder.lift_slope``, ``thrusters.prop.wake_fraction``)
    or a ``delta(NAME)`` / ``T(NAME)`` / ``n(NAME)`` factor may use."""
    from hydrokit.model.uncertainty import check_parameter, location

    if isinstance(value, str):
        names = [n.strip() for n in value.split(",")]
    elif isinstance(value, list) and all(isinstance(v, str) for v in value):
        names = [n.strip() for n in value]
    else:
        raise InputError(
            f"field 'sysid.free' = {str(value)[:60]!r}: expected a list or comma-separated text of names "
            "like added_mass.surge, linear_damping.yaw, terms.N_r|r|",
            source,
        )
    if not any(names):
        raise InputError(
            "field 'sysid.free' is empty: expected names like added_mass.surge, linear_damping.yaw", source
        )
    seen: dict[Any, str] = {}
    for k, name in enumerate(names):
        where = location(check_parameter(name, f"field 'sysid.free[{k}]' =", source, surfaces, thrusters))
        if where in seen:
            also = "" if seen[where] == name else f" (as {seen[where]!r}: the same coefficient)"
            raise InputError(
                f"field 'sysid.free[{k}]' = {name!r}: named twice{also}; expected each parameter once", source
            )
        seen[where] = name
    return tuple(names)


def _sysid(s: _Sysid | None, root: Path, source: str, vehicle: Path) -> SysidSpec | None:
    if s is None:
        return None
    runs = _file_list(root, s.runs, "sysid.runs", source)
    holdout = _file_list(root, s.holdout, "sysid.holdout", source) if s.holdout not in (None, []) else ()
    both = sorted(set(runs) & set(holdout))
    if both:
        raise InputError(
            f"field 'sysid.holdout' = {both[0].name!r}: also a training run in 'sysid.runs'; expected validation "
            "runs the fit does not see",
            source,
        )
    truth = None
    truth_file = _file(root, s.truth, "sysid.truth", source) if s.truth is not None else None
    if truth_file is not None:
        truth = _sysid_truth(truth_file, source)
    pattern = s.runs if isinstance(s.runs, str) else ", ".join(map(str, s.runs))
    free = _free_names(s.free, source, *_vehicle_names(vehicle))
    window = window_length(s.window, _WINDOW, source)  # as hydrokit sysid --window reads it
    return SysidSpec(
        runs,
        holdout,
        free,
        s.method,
        float(s.dt),
        pattern,
        truth,
        truth_file,
        window=window,
        window_continuity=float(s.window_continuity),
    )


def _sysid_truth(path: Path, source: str) -> dict[str, float]:
    """``hidden`` of a ``truth.json`` written by ``hydrokit sysid generate`` (name → SI value)."""
    import json
    import math

    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        hidden = doc["hidden"]
        out = {str(k): float(v) for k, v in hidden.items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        raise InputError(
            f"field 'sysid.truth' = {path.name!r}: expected the truth.json of 'hydrokit sysid generate' "
            "(a JSON object with 'hidden': name → value)",
            source,
        ) from None
    if not all(math.isfinite(v) for v in out.values()):
        raise InputError(f"field 'sysid.truth' = {path.name!r}: a hidden value is not finite", source)
    return out


def _cfd(f: ProjectFile, root: Path, forces: dict[str, ForceSpec], source: str) -> CfdSpec | None:
    c = f.cfd
    if c is None:
        return None
    for i, dof in enumerate(c.dofs):
        if dof not in CFD_AXES:
            raise InputError(f"field 'cfd.dofs[{i}]' = {dof!r}: expected surge, sway or heave", source)
        if dof in forces:
            raise InputError(
                f"field 'cfd.dofs[{i}]' = {dof!r}: also given a force curve in 'forces'; expected one CFD source per DOF",
                source,
            )
    for dof in c.area:
        if dof not in c.dofs:
            raise InputError(
                f"field 'cfd.area.{dof}': not among cfd.dofs {c.dofs}; expected an area per computed DOF", source
            )
    for i, u in enumerate(c.speeds):
        if not (u > 0 and u < 1e3):
            raise InputError(f"field 'cfd.speeds[{i}]' = {u!r}: expected a speed in m/s, > 0", source)
    if c.body is None and f.geometry is None:
        raise InputError("field 'cfd.body' is missing and there is no 'geometry'; expected the body to compute", source)
    body = _file(root, c.body if c.body is not None else str(f.geometry), "cfd.body", source)
    return CfdSpec(
        body,
        tuple(c.speeds),
        tuple(c.dofs),
        c.density,
        c.viscosity,
        c.turbulence,
        c.grids,
        dict(c.area),
        dict(c.settings),
    )


def check_inputs(project: Project) -> None:
    """Read every rig and launch, the geometry, each force curve and the mission once, so a bad
    one is refused (one line naming it) before the run identifies anything, not minutes into it."""
    from hydrokit.io.forces import read_forces
    from hydrokit.io.geometry import load_geometry
    from hydrokit.io.launch import read_launch
    from hydrokit.io.mission import load_mission
    from hydrokit.io.rig import load_rig

    for c in project.campaigns:
        rig = load_rig(c.rig)
        for launch in (*c.launches, *c.tare):
            read_launch(launch, rig)
    _ = load_geometry(project.geometry) if project.geometry else None
    for spec in project.forces.values():
        read_forces(spec.file)
    _ = load_mission(project.mission) if project.mission else None
    if project.sysid is not None:
        check_sysid_runs(project)


def check_sysid_runs(project: Project) -> None:
    """Read the base vehicle and every run of ``sysid:`` once: a vehicle without thrusters, a
    bad run file (one line naming its file and column) or a ``sysid.window`` longer than a
    training run is refused before any step runs."""
    from hydrokit.io.runlog import read_run
    from hydrokit.io.thrusters import parse_thrusters

    assert project.sysid is not None
    data = read_yaml(project.vehicle)
    thrusters = parse_thrusters(data, str(project.vehicle)) if data.get("thrusters") else None
    if thrusters is None or len(thrusters) == 0:
        raise InputError(
            f"field 'sysid': the vehicle {project.vehicle.name} has no 'thrusters:' block; expected the thrusters "
            "whose commands the runs hold",
            str(project.source),
        )
    read = [read_run(run, thrusters.names) for run in (*project.sysid.runs, *project.sysid.holdout)]
    window_within(project.sysid.window, read[: len(project.sysid.runs)], _WINDOW, str(project.source))


def load_project(name_or_path: str | os.PathLike[str]) -> Project:
    """Read and validate a project file (a path, a folder with ``project.yaml`` or a bundled
    name) and the rig, geometry, force and mission files it names (:func:`check_inputs`)."""
    path = resolve_project(name_or_path)
    project = parse_project(read_yaml(path), path)
    check_inputs(project)
    return project
