"""One CFD case: the body, the flow it meets and the settings, and the OpenFOAM files they make.

A case is the body held still in body axes (x forward, y starboard, z down; origin = moment
reference point) with the fluid coming at it with the body's velocity reversed: a body moving at
(u, v, w) sees a far field of −(u, v, w). The drift angle is β = atan2(v, u) and the angle of
attack α = atan2(w, u) (the issue's definitions), so at speed U

    u = U / √(1 + tan²β + tan²α),   v = u tan β,   w = u tan α.

All far-field faces form one patch, ``farfield``, with OpenFOAM's freestream conditions (inflow
where the flow enters, zero gradient where it leaves), so any flow direction uses the same mesh.
Forces and moments on the patch ``body`` come from the ``forces`` function object about the
origin, in body axes: the SNAME force on the body (resistance is negative X).

Case files are written with foamlib (dictionaries as Python data, no string templates).
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.cfd.body import Body
from hydrokit.errors import InputError, MissingExtraError

#: bump when the case files or the stopping rule change in a way that changes results: cached
#: cases are redone. 2: a case stops only when the force's pressure and viscous parts have settled
#: too, not just their sum (2026-11-27)
CASE_FORMAT = 2
#: Re_L below which ``turbulence="auto"`` runs laminar (the issue's threshold)
LAMINAR_BELOW = 2000.0
TURBULENCE_MODELS = ("laminar", "kOmegaSST", "kEpsilon")
#: default free-stream turbulence at the inlet: intensity and eddy-to-molecular viscosity ratio.
#: Enough for k-ω SST to make the boundary layer turbulent from the nose (a tripped model, as
#: ITTC-1957's line assumes); at 0.5 % and 1 it left a laminar run of SST's own making whose
#: length moved with the smallest disturbance (a rotating arm at 100 L: +1.8 % drag)
INTENSITY = 0.01
VISCOSITY_RATIO = 10.0


@dataclass(frozen=True)
class Flow:
    """The motion of the body in one case (SI).

    speed : float — U, m/s (> 0)
    drift : float — β = atan2(v, u), rad (|β| < π/2)
    attack : float — α = atan2(w, u), rad (|α| < π/2)
    yaw_rate, pitch_rate : float — r and q, rad/s (rotating-arm cases)
    axis : str — ``x`` (the default: forward motion at β, α), or ``y`` / ``z`` for pure sway or
        heave at ``speed`` (CELY2019's per-axis speed sweeps; angles and rates must then be 0)
    """

    speed: float
    drift: float = 0.0
    attack: float = 0.0
    yaw_rate: float = 0.0
    pitch_rate: float = 0.0
    axis: str = "x"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.speed) and self.speed > 0):
            raise InputError(f"speed = {self.speed!r} m/s: expected a positive finite speed")
        for name, limit in (("drift", math.pi / 2), ("attack", math.pi / 2)):
            v = getattr(self, name)
            if not (math.isfinite(v) and abs(v) < limit):
                raise InputError(
                    f"{name} angle = {math.degrees(v):g}°: expected |angle| < 90° (the body must move forward)"
                )
        for name in ("yaw_rate", "pitch_rate"):
            if not math.isfinite(getattr(self, name)):
                raise InputError(f"{name} = {getattr(self, name)!r} rad/s: expected a finite rate")
        if self.yaw_rate and self.pitch_rate:
            raise InputError("a yaw rate and a pitch rate at once: expected one rotating-arm rate per case")
        if (self.yaw_rate or self.pitch_rate) and (self.drift or self.attack):
            raise InputError("a rotating-arm rate with a drift or attack angle: expected one of them per case")
        if self.axis not in ("x", "y", "z"):
            raise InputError(f"axis = {self.axis!r}: expected x, y or z")
        if self.axis != "x" and any((self.drift, self.attack, self.yaw_rate, self.pitch_rate)):
            raise InputError(f"a motion along {self.axis} takes no drift, attack or rates; expected them 0")

    def velocity(self) -> np.ndarray:
        """Body velocity (u, v, w), m/s."""
        if self.axis != "x":
            return self.speed * np.eye(3)["xyz".index(self.axis)]
        tb, ta = math.tan(self.drift), math.tan(self.attack)
        u = self.speed / math.sqrt(1.0 + tb * tb + ta * ta)
        return np.array([u, u * tb, u * ta])


@dataclass(frozen=True)
class Settings:
    """Fluid, model and numerics of a case (SI).

    density : float — ρ, kg/m³ (forces scale with it; the flow itself is incompressible)
    viscosity : float — kinematic ν, m²/s (sea water at 15 °C: 1.19e-6)
    turbulence : str — auto, laminar, kOmegaSST or kEpsilon (auto: laminar below Re_L = 2000)
    grid : int — grid level 1, 2 or 3 (each refines the base cell size by √2)
    base_cells : int — background cells per body length at grid level 1
    surface_level : int — snappyHexMesh refinement level at the body (cell size / 2^level)
    layers : int — prism layers on the body
    upstream, downstream, lateral : float — domain extents in body lengths
    max_iterations, min_iterations, window : int — solver iterations: at most, at least, and
        the window over which the force history is judged
    tolerance : float — relative change of the force over the window that counts as converged
    timeout : float — wall-clock limit of one solver run, s
    processes : int — MPI processes of one case's solver (decomposePar + mpirun; 1: serial)
    path : str — ``auto`` (a profile at zero incidence takes the axisymmetric wedge) or ``3d``
        (always snappyHexMesh: to compare the two paths on one body)
    inflow_intensity : float — free-stream turbulence intensity at the inlet, √(2k/3)/U,
        dimensionless (0.01 = 1 %); turbulent models only
    inflow_viscosity_ratio : float — free-stream eddy-to-molecular viscosity ratio ν_t/ν at the
        inlet, dimensionless; turbulent models only. The defaults (1 %, 10) make k-ω SST's boundary
        layer turbulent from the nose, like a tripped tow-tank model; 0.005 and 1 leave a laminar
        run of uncertain length (natural transition in a quiet tank)
    y_plus : float — target y⁺ of the first cell at the body, dimensionless. 0 (the default): each
        path its own way (the wedge at y⁺ ≈ 1, the viscous sublayer resolved; the 3-D path with
        ``layers`` prism layers sized relative to its surface cells, y⁺ wherever that falls).
        > 0: both paths lay their first cell for it from flat-plate friction (30–100: in the log
        layer, where the wall functions hold), and the 3-D path grows its prism layers from it
        (ratio 1.2) until they span the turbulent boundary layer at the tail (up to 20 layers,
        together no thicker than a surface cell)
    end_level : int — 3-D path: refinement levels added at the body's fore and aft tenth of its
        length (0 to 3), where the stagnation pressure and the pressure recovery set a streamlined
        hull's pressure drag; 1 costs about a third more cells on a slender hull
    turbulence_order : int — order of the convection of k and ω (ε), dimensionless. 1 (the
        default): first-order upwind throughout, the robust choice; its error is first order and
        on a fine grid it can move the friction against the rest of the solution (the Myring
        wedge's Re_L 3e6 triplet: friction 5.818 / 5.846 / 5.792 N, "diverging"). 2: upwind until
        the forces settle, then second-order ``linearUpwind`` (cell-limited gradient) continued from
        that state until they settle again (5.809 / 5.872 / 5.905 N, monotonic, observed order 1.9);
        a grid study (``--grids 3``) of a turbulent hull wants it. Started cold, a second-order ω
        leaves a laminar boundary layer that separates: hence the two stages
    """

    density: float = 1025.0
    viscosity: float = 1.19e-6
    turbulence: str = "auto"
    grid: int = 1
    base_cells: int = 2
    surface_level: int = 4
    layers: int = 3
    upstream: float = 3.0
    downstream: float = 6.0
    lateral: float = 3.0
    max_iterations: int = 1500
    min_iterations: int = 150
    window: int = 100
    tolerance: float = 2e-3
    timeout: float = 3600.0
    path: str = "auto"
    processes: int = 1
    y_plus: float = 0.0
    end_level: int = 0
    inflow_intensity: float = INTENSITY
    inflow_viscosity_ratio: float = VISCOSITY_RATIO
    turbulence_order: int = 1

    def __post_init__(self) -> None:
        for name in ("density", "viscosity", "upstream", "downstream", "lateral", "tolerance", "timeout"):
            v = getattr(self, name)
            if isinstance(v, bool) or not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise InputError(f"{name} = {v!r}: expected a positive finite number")
        y = self.y_plus
        if isinstance(y, bool) or not (isinstance(y, int | float) and math.isfinite(y) and 0 <= y <= 1000):
            raise InputError(f"y_plus = {y!r}: expected 0 (each path's default) or a target y⁺ from 0 to 1000")
        for name, hi in (("inflow_intensity", 0.5), ("inflow_viscosity_ratio", 1e4)):
            v = getattr(self, name)
            if isinstance(v, bool) or not (isinstance(v, int | float) and math.isfinite(v) and 0 < v <= hi):
                raise InputError(f"{name} = {v!r}: expected a number above 0 and at most {hi:g}")
        if self.turbulence not in ("auto", *TURBULENCE_MODELS):
            raise InputError(f"turbulence = {self.turbulence!r}: expected auto, laminar, kOmegaSST or kEpsilon")
        if self.path not in ("auto", "3d"):
            raise InputError(f"path = {self.path!r}: expected auto or 3d")
        if self.grid not in (1, 2, 3):
            raise InputError(f"grid level = {self.grid!r}: expected 1, 2 or 3")
        for name, lo, hi in (
            ("base_cells", 2, 200),
            ("surface_level", 0, 8),
            ("layers", 0, 20),
            ("end_level", 0, 3),
            ("max_iterations", 10, 1_000_000),
            ("min_iterations", 1, 1_000_000),
            ("window", 5, 1_000_000),
            ("processes", 1, 1024),
            ("turbulence_order", 1, 2),
        ):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
                raise InputError(f"{name} = {v!r}: expected a whole number from {lo} to {hi}")

    def model(self, reynolds: float) -> str:
        """The turbulence model used at a body-length Reynolds number."""
        if self.turbulence != "auto":
            return self.turbulence
        return "laminar" if reynolds < LAMINAR_BELOW else "kOmegaSST"


@dataclass(frozen=True)
class Case:
    """A body, a flow and settings: one OpenFOAM run."""

    body: Body
    flow: Flow
    settings: Settings
    label: str = ""

    @property
    def reynolds(self) -> float:
        """Re_L = U L / ν."""
        return self.flow.speed * self.body.length / self.settings.viscosity

    @property
    def model(self) -> str:
        return self.settings.model(self.reynolds)

    @property
    def path(self) -> str:
        """``wedge`` for a body of revolution at zero incidence without rotation, else ``3d``."""
        f = self.flow
        straight = f.axis == "x" and f.drift == 0 and f.attack == 0 and f.yaw_rate == 0 and f.pitch_rate == 0
        return "wedge" if self.body.kind == "profile" and straight and self.settings.path == "auto" else "3d"

    @property
    def rotation(self) -> np.ndarray:
        """Angular velocity (p, q, r) of the body, rad/s (zero but for rotating-arm cases)."""
        return np.array([0.0, self.flow.pitch_rate, self.flow.yaw_rate])

    @property
    def arm_centre(self) -> np.ndarray | None:
        """Centre of the rotating arm's circle in body axes, m: c = Ω × V / |Ω|² (the point of
        the body frame at rest), or None for straight motion. A yaw rate r at speed U puts it at
        (0, U/r, 0): to starboard for r > 0."""
        omega = self.rotation
        w2 = float(omega @ omega)
        if w2 == 0:
            return None
        return np.cross(omega, self.flow.velocity()) / w2

    def key(self) -> str:
        """Hash of every input that changes the result (the cache key), 16 hex digits."""
        data = {
            "format": CASE_FORMAT,
            "body": self.body.digest(),
            "flow": asdict(self.flow),
            # the timeout and the number of processes change when a result comes, not what it is;
            # the path is the one taken (``auto`` that goes 3-D is the same case as ``3d``)
            # a setting added later counts only where it can change the answer, so the cases
            # computed before it keep their keys: y_plus away from its default, the inflow
            # turbulence in a turbulent case (whose default changed with it: those are redone),
            # end_level away from 0 on the 3-D path, turbulence_order 2 in a turbulent case
            "settings": {
                **{
                    k: v
                    for k, v in asdict(self.settings).items()
                    if k not in ("timeout", "processes")
                    and not (k == "y_plus" and v == 0)
                    and not (k.startswith("inflow_") and self.model == "laminar")
                    and not (k == "end_level" and (v == 0 or self.path == "wedge"))
                    and not (k == "turbulence_order" and (v == 1 or self.model == "laminar"))
                },
                "path": self.path,
            },
        }
        if self.path == "3d" and self.settings.y_plus > 0:
            # the prism layers laid from a target y⁺ fit in two surface cells since 2026-11-27
            # (one surface cell in the morning of that day)
            data["layers"] = "stack within two surface cells"
        if self.arm_centre is not None:
            # grad(U), the absolute velocity's (turbulence model, forces), is limited in a
            # rotating-arm case since 2026-11-28
            data["arm_grad_U"] = "limited"
        if self.path == "wedge" and self.settings.y_plus > 0 and self.settings.grid > 1:
            # the first cell of an asked-for y⁺ is held on the finer levels since 2026-11-27 (late)
            data["first_cell"] = "held"
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]


# --- writing ---------------------------------------------------------------------------------


def foamlib() -> Any:
    """The foamlib module, or MissingExtraError naming the extra (pip install 'hydrokit[cfd]')."""
    try:
        import foamlib
    except ImportError as exc:
        raise MissingExtraError("foamlib", "cfd") from exc
    return foamlib


def foam_file(path: Path, entries: Mapping[str, Any], cls: str = "dictionary") -> None:
    """Write an OpenFOAM file of class ``cls`` with foamlib, serialised in one go (folders created).

    Never entry by entry: foamlib then re-parses the file for every key, and with Dask workers
    that fails now and then inside foamlib (``BufferError: Existing exports of data``; seen on a
    snappyHexMeshDict and on the 0/ field files).
    """
    FoamFile = foamlib().FoamFile  # noqa: N806 -- foamlib's class

    path.parent.mkdir(parents=True, exist_ok=True)
    header = {"version": 2.0, "format": "ascii", "class": cls, "object": path.name}
    path.write_bytes(FoamFile.dumps({"FoamFile": header, **entries}, ensure_header=False))


def _vec(v: np.ndarray | tuple[float, ...]) -> list[float]:
    return [float(x) for x in v]


def write_stl(path: Path, triangles: np.ndarray, solid: str = "body") -> None:
    """An ASCII STL of triangles (k, 3, 3), m, with outward normals from the vertex order."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    n = np.cross(b - a, c - a)
    norm = np.linalg.norm(n, axis=1)
    n = n / np.where(norm > 0, norm, 1.0)[:, None]
    lines = [f"solid {solid}"]
    for k in range(len(triangles)):
        lines.append(f"facet normal {n[k, 0]:.9g} {n[k, 1]:.9g} {n[k, 2]:.9g}")
        lines.append("outer loop")
        for v in triangles[k]:
            lines.append(f"vertex {v[0]:.12g} {v[1]:.12g} {v[2]:.12g}")
        lines.append("endloop")
        lines.append("endfacet")
    lines.append(f"endsolid {solid}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")


def inflow(case: Case) -> dict[str, float]:
    """Free-stream turbulence for the case's model: k (m²/s²), ω (1/s), ε (m²/s³)."""
    s = case.settings
    U, nu = case.flow.speed, s.viscosity
    k = 1.5 * (s.inflow_intensity * U) ** 2
    nut = s.inflow_viscosity_ratio * nu
    return {"k": k, "omega": k / nut, "epsilon": 0.09 * k * k / nut}


def write_case(case: Case, folder: Path, mesh_dicts: Mapping[str, Mapping[str, Any]]) -> None:
    """Write every file of the case except the mesh itself.

    ``mesh_dicts`` maps file names under ``system/`` (``blockMeshDict``, ``snappyHexMeshDict`` …)
    to their contents, made by the mesh path (:mod:`hydrokit.cfd.mesh3d` or :mod:`hydrokit.cfd.wedge`).
    """
    s, model = case.settings, case.model
    wedge = case.path == "wedge"
    centre = case.arm_centre
    U = "U" if centre is None else "Urel"
    for name, entries in mesh_dicts.items():
        foam_file(folder / "system" / name, entries)
    foam_file(folder / "system" / "controlDict", _control(case))
    foam_file(folder / "system" / "fvSchemes", _schemes(model, U))
    foam_file(folder / "system" / "fvSolution", _solution(model, U))
    if centre is not None:
        # the rotating arm: the frame turns with the body about the arm's centre (SRFSimpleFoam);
        # the far field is fluid at rest in the absolute frame
        omega = case.rotation
        rate = float(np.linalg.norm(omega))
        foam_file(
            folder / "constant" / "SRFProperties",
            {
                "SRFModel": "rpm",
                "origin": _vec(centre),
                "axis": _vec(omega / rate),
                "rpmCoeffs": {"rpm": rate * 60.0 / (2.0 * math.pi)},
            },
        )
    foam_file(folder / "constant" / "transportProperties", {"transportModel": "Newtonian", "nu": s.viscosity})
    if model == "laminar":
        turb: dict[str, Any] = {"simulationType": "laminar"}
    else:
        turb = {"simulationType": "RAS", "RAS": {"RASModel": model, "turbulence": True, "printCoeffs": False}}
    foam_file(folder / "constant" / "turbulenceProperties", turb)
    # a wedge is built in the profile's own coordinates (nose at the smallest x), where the body
    # moves towards −x: the fluid comes along +x there
    far = np.array([case.flow.speed, 0.0, 0.0]) if wedge else -case.flow.velocity()
    side = {"front": {"type": "wedge"}, "back": {"type": "wedge"}} if wedge else {}
    if centre is None:
        u_far: dict[str, Any] = {"type": "freestreamVelocity", "freestreamValue": _vec(far)}
        p_far: dict[str, Any] = {"type": "freestreamPressure", "freestreamValue": 0.0}
    else:
        u_far = {"type": "SRFFreestreamVelocity", "UInf": [0.0, 0.0, 0.0], "relative": False, "value": _vec(far)}
        p_far = {"type": "outletInlet", "outletValue": 0.0, "value": 0.0}
    fields: dict[str, tuple[str, Any, dict[str, Any], dict[str, Any]]] = {
        U: ("volVectorField", [0, 1, -1, 0, 0, 0, 0], u_far, {"type": "noSlip"}),
        "p": ("volScalarField", [0, 2, -2, 0, 0, 0, 0], p_far, {"type": "zeroGradient"}),
    }
    if model != "laminar":
        t = inflow(case)
        io = lambda v: {"type": "inletOutlet", "inletValue": v, "value": v}  # noqa: E731
        fields["k"] = (
            "volScalarField",
            [0, 2, -2, 0, 0, 0, 0],
            io(t["k"]),
            {"type": "kqRWallFunction", "value": t["k"]},
        )
        fields["nut"] = (
            "volScalarField",
            [0, 2, -1, 0, 0, 0, 0],
            {"type": "calculated", "value": 0.0},
            {"type": "nutUSpaldingWallFunction", "value": 0.0},
        )
        if model == "kOmegaSST":
            fields["omega"] = (
                "volScalarField",
                [0, 0, -1, 0, 0, 0, 0],
                io(t["omega"]),
                {"type": "omegaWallFunction", "value": t["omega"]},
            )
        else:
            fields["epsilon"] = (
                "volScalarField",
                [0, 2, -3, 0, 0, 0, 0],
                io(t["epsilon"]),
                {"type": "epsilonWallFunction", "value": t["epsilon"]},
            )
    for name, (cls, dims, farfield, body) in fields.items():
        if name in ("U", "Urel"):
            internal: Any = _vec(far)
        elif name in ("k", "omega", "epsilon"):
            internal = farfield["inletValue"]
        else:
            internal = 0.0
        _field_file(folder / "0" / name, cls, dims, internal, {"farfield": farfield, '"body.*"': body, **side})


def write_second_stage(case: Case, folder: Path, start: int) -> None:
    """Turn a case whose first stage (upwind k, ω) has settled at iteration ``start`` into its
    second: second-order convection of the turbulence, continued from the latest written time
    for at most ``max_iterations`` more (``turbulence_order`` 2)."""
    U = "U" if case.arm_centre is None else "Urel"
    foam_file(folder / "system" / "fvSchemes", _schemes(case.model, U, order=2))
    end = int(start) + case.settings.max_iterations
    control = {**_control(case), "startFrom": "latestTime", "endTime": end, "writeInterval": end}
    foam_file(folder / "system" / "controlDict", control)


def _field_file(path: Path, cls: str, dims: list[int], internal: Any, boundary: dict[str, Any]) -> None:
    DimensionSet = foamlib().DimensionSet  # noqa: N806 -- foamlib's class
    foam_file(path, {"dimensions": DimensionSet(*dims), "internalField": internal, "boundaryField": boundary}, cls)


def solver(case: Case) -> str:
    """simpleFoam, or SRFSimpleFoam for a rotating-arm case."""
    return "simpleFoam" if case.arm_centre is None else "SRFSimpleFoam"


def _control(case: Case) -> dict[str, Any]:
    s = case.settings
    rho = case.settings.density
    functions: dict[str, Any] = {
        "forces": {
            "type": "forces",
            "libs": ['"libforces.so"'],
            "writeControl": "timeStep",
            "writeInterval": 1,
            "patches": ['"body.*"'],
            "rho": "rhoInf",
            "rhoInf": rho,
            "U": "U" if case.arm_centre is None else "Urel",
            "CofR": [0.0, 0.0, 0.0],
            "log": False,
        },
    }
    # the velocity on the body's x–y plane (z = 0; a wedge's mid-plane) at the last write, for the report
    functions["slice"] = {
        "type": "surfaces",
        "libs": ['"libsampling.so"'],
        "writeControl": "writeTime",
        "surfaceFormat": "raw",
        "fields": ["U" if case.arm_centre is None else "Urel"],
        "interpolationScheme": "cellPoint",
        "surfaces": {
            "zNormal": {
                "type": "cuttingPlane",
                "planeType": "pointAndNormal",
                "pointAndNormalDict": {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]},
                "interpolate": False,
            }
        },
    }
    if case.model != "laminar":
        functions["yPlus"] = {
            "type": "yPlus",
            "libs": ['"libfieldFunctionObjects.so"'],
            "writeControl": "writeTime",
            "log": False,
        }
    return {
        "application": solver(case),
        "startFrom": "startTime",
        "startTime": 0,
        "stopAt": "endTime",
        "endTime": s.max_iterations,
        "deltaT": 1,
        "writeControl": "timeStep",
        "writeInterval": s.max_iterations,
        "purgeWrite": 1,
        "writeFormat": "binary",
        "writePrecision": 8,
        "writeCompression": False,
        "timeFormat": "general",
        "timePrecision": 8,
        "runTimeModifiable": True,
        # hydrokit stops a settled run by editing this file: see the change at once (OpenFOAM's
        # default ignores changes within 10 s of the last read, which a quick case never outlives)
        "OptimisationSwitches": {"fileModificationSkew": 0, "fileModificationChecking": "timeStamp"},
        "functions": functions,
    }


def _schemes(model: str, U: str = "U", order: int = 1) -> dict[str, Any]:
    """fvSchemes: second-order U; k, ω, ε first-order upwind (``order`` 1) or second-order
    ``linearUpwind`` on a cell-limited gradient (``order`` 2, the second stage of a case whose
    ``turbulence_order`` is 2)."""
    div: dict[str, Any] = {
        "default": "none",
        f"div(phi,{U})": ("bounded", "Gauss", "linearUpwindV", f"grad({U})"),
        f"div((nuEff*dev2(T(grad({U})))))": ("Gauss", "linear"),
    }
    limited = ("cellLimited", "Gauss", "linear", 1)
    # SRFSimpleFoam builds its turbulence model on the absolute velocity U = Urel + Ω × r, so
    # the model's production, its wall functions and the forces' viscous stress take grad(U)
    # while the momentum equation takes grad(Urel): both limited, as in simpleFoam. With grad(U)
    # left to the unlimited default the rotating arm's friction was 2.8 % under straight flow at
    # any radius (the Myring on surface level 4, 2026-11-28)
    grad: dict[str, Any] = {"default": ("Gauss", "linear"), "grad(U)": limited, f"grad({U})": limited}
    for q in ("k", "omega", "epsilon"):
        div[f"div(phi,{q})"] = ("bounded", "Gauss", "upwind")
        if order == 2:
            div[f"div(phi,{q})"] = ("bounded", "Gauss", "linearUpwind", "limitedGrad")
    if order == 2:
        grad["limitedGrad"] = limited
    return {
        "ddtSchemes": {"default": "steadyState"},
        "gradSchemes": grad,
        "divSchemes": div,
        "laplacianSchemes": {"default": ("Gauss", "linear", "limited", "corrected", 0.5)},
        "interpolationSchemes": {"default": "linear"},
        "snGradSchemes": {"default": ("limited", "corrected", 0.5)},
        "wallDist": {"method": "meshWave"},
    }


def _solution(model: str, U: str = "U") -> dict[str, Any]:
    smooth = {"solver": "smoothSolver", "smoother": "GaussSeidel", "tolerance": 1e-8, "relTol": 0.1, "nSweeps": 1}
    return {
        "solvers": {
            "p": {"solver": "GAMG", "smoother": "GaussSeidel", "tolerance": 1e-7, "relTol": 0.01},
            f'"({U}|k|omega|epsilon)"': smooth,
        },
        "SIMPLE": {"nNonOrthogonalCorrectors": 1, "consistent": True},
        "relaxationFactors": {"equations": {U: 0.9, '".*"': 0.7}, "fields": {"p": 0.9}},
    }
