"""Coefficients of a whole geometry: parts, optional BEM added mass, the combined body.

A :class:`Geometry` is what a geometry file holds (parsed by
:func:`hydrokit.io.geometry.load_geometry`); :func:`estimate_geometry` turns it into an
:class:`Estimate` — per-part coefficients with their sources and the composite body about the
common origin (full 6×6 transform and REHMAN's diagonal-only sum for comparison; quadratic
damping by one of the models of :func:`hydrokit.estimate.composite.combine`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit._result import Result, html_table, jsonable
from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.estimate.composite import QUADRATIC_DAMPING_MODELS, Composite, Part, combine
from hydrokit.estimate.mesh import check_mesh

#: what each quadratic-damping model means, for the sources list of the written vehicle fragment
MODEL_NOTES = {
    "elements": "parts' translational drag as point drag elements at the part origins (drag_elements); "
    "the diagonal holds the parts' own rotational drag",
    "rehman": "REHMAN's diagonal: Σ translational drag; rotational Σ own + d·r³ of each part at lever arm r",
    "shifted": "diagonal of Hᵀ D H (d·r², kg·m): dimensionally wrong, for comparison only",
}


# BEM panels around a sphere, spheroid or cylinder part whose file entry gives no resolution
# (docs/estimate.md); ``--resolution`` overrides every part's
DEFAULT_RESOLUTION = 48


@dataclass
class GeometryPart:
    """A parsed part: the composite Part, its coefficients' sources and the shape (for BEM)."""

    part: Any
    sources: dict[str, str]
    shape: str | None
    dims: dict[str, float]
    mesh: Any = None
    bem: bool = True
    resolution: int = DEFAULT_RESOLUTION


@dataclass
class Geometry:
    """A geometry file: name, gravity (m/s²), fluid density (kg/m³), parts, the file."""

    name: str
    gravity: float
    density: float
    parts: list[GeometryPart]
    source: str


def vehicle_part(name: str, vehicle: Any, position: np.ndarray, rotation: np.ndarray, label: str) -> GeometryPart:
    """A part that is a whole vehicle: its mass, inertia, CG, CB, M_A, D_L, D_Q and its own point
    drag elements (``vehicle.drag_elements``, when the vehicle has any) (SI).

    Parameters
    ----------
    name : str
    vehicle : Vehicle
    position : (3,) — part origin in the common frame, m
    rotation : (3, 3) — part axes in the common frame
    label : str — where the vehicle came from (name or file), for the sources list
    """
    elements = tuple(getattr(vehicle, "drag_elements", ()) or ())
    rows = [np.concatenate([e.position, e.linear, e.quadratic]).astype(float) for e in elements]
    part = Part(
        name,
        vehicle.mass,
        vehicle.volume,
        vehicle.inertia,
        vehicle.M_A,
        vehicle.D_L,
        np.diag(vehicle.D_Q),
        vehicle.r_g,
        vehicle.r_b,
        position,
        rotation,
        label,
        np.vstack(rows) if rows else np.zeros((0, 9)),
        tuple(str(e.name) for e in elements),
    )
    return GeometryPart(part, {"all": f"vehicle {label}"}, None, {})


def _tensor(inertia: Any) -> np.ndarray:
    """3 values (principal moments on the part axes) or a 3×3 tensor, kg·m²."""
    a = np.asarray(inertia, float)
    return np.diag(a) if a.shape == (3,) else a


def mesh_part(
    name: str,
    mesh: Any,
    mass: float,
    position: np.ndarray,
    rotation: np.ndarray,
    *,
    density: float,
    gravity: float,
    buoyancy: float | None = None,
    inertia: np.ndarray | None = None,
    center_of_gravity: np.ndarray | None = None,
    dims: dict[str, float] | None = None,
    resolution: int = DEFAULT_RESOLUTION,
) -> GeometryPart:
    """A part given by a closed surface mesh (m, part axes); its added mass comes from the BEM
    solver, its centre of buoyancy is the enclosed volume's centroid.

    ``buoyancy`` (N) overrides the mesh volume. Without ``inertia`` (kg·m², 3 values or 3×3 about
    the CG) and ``center_of_gravity`` (m, part axes) the part is a uniform solid filling the mesh
    (:meth:`~hydrokit.estimate.mesh.SurfaceMesh.solid_inertia`); give both for a shell or a
    ballasted hull.
    """
    check_mesh(mesh)  # closed and outward: the solid below and the BEM both need it
    vol = mesh.volume() if buoyancy is None else buoyancy / (density * gravity)
    centroid, solid = mesh.solid_inertia(mass)
    part = Part(
        name,
        mass,
        vol,
        solid if inertia is None else _tensor(inertia),
        np.zeros((6, 6)),
        r_g=centroid if center_of_gravity is None else np.asarray(center_of_gravity, float),
        r_b=centroid,
        position=position,
        rotation=rotation,
    )
    sources = {"added_mass": "BEM (mesh)", "inertia": "given" if inertia is not None else "uniform solid (mesh)"}
    return GeometryPart(part, sources, None, dims or {}, mesh, True, resolution)


def shape_part(
    name: str,
    shape: str,
    mass: float,
    dims: dict[str, float],
    position: np.ndarray,
    rotation: np.ndarray,
    *,
    density: float,
    gravity: float,
    speed: float = 1.0,
    kinematic_viscosity: float = 1.05e-6,
    drag_coefficient: float | None = None,
    axial_model: str = "spheroid",
    buoyancy: float | None = None,
    inertia: np.ndarray | None = None,
    center_of_gravity: np.ndarray | None = None,
    bem: bool = True,
    resolution: int = DEFAULT_RESOLUTION,
    where: str = "",
    source: str = "",
) -> GeometryPart:
    """A simple body from the shape library (DNV-RP-H103, Lamb; see :mod:`hydrokit.estimate.shapes`).

    Parameters
    ----------
    name, shape : str — part name; sphere, spheroid, cylinder, block or flat_plate
    mass : float — kg
    dims : dict — diameter, length, width, height, thickness as the shape needs, m
    position : (3,) m; rotation : (3, 3) — the part's place in the common frame
    density : float — kg/m³; gravity : float — m/s²
    speed : float — operating speed for Reynolds-dependent drag (sphere), m/s
    kinematic_viscosity : float — m²/s
    drag_coefficient : float, optional — overrides the table C_D (axial C_D for spheroid and cylinder)
    axial_model : str — cylinder axial added mass: "spheroid" (Lamb) or "rehman" (REHMAN's 2/π)
    buoyancy : float, optional — N, overrides ρ g × shape volume
    inertia : (3,) or (3, 3), optional — kg·m² about the CG, part axes; overrides the uniform solid's
    center_of_gravity : (3,), optional — m, part axes; default the shape's centre (its CB)
    bem, resolution : eligibility for the BEM solver and its panel count
    where, source : the file field and file, for error messages

    Raises
    ------
    InputError
        An unknown shape or a missing dimension, naming ``where``.
    """
    from hydrokit.estimate.shapes import SHAPES, solid_inertia

    if shape not in SHAPES:
        raise InputError(f"field '{where}.shape' = {shape!r}: expected one of {', '.join(SHAPES)}", source)
    needs = {
        "sphere": ("diameter",),
        "spheroid": ("length", "diameter"),
        "cylinder": ("length", "diameter"),
        "block": ("length", "width", "height"),
        "flat_plate": ("length", "width"),
    }[shape]
    missing = [d for d in needs if d not in dims]
    if missing:
        raise InputError(f"field '{where}': shape {shape} needs '{missing[0]}' (m)", source)
    kw: dict[str, Any] = {"density": density, **{d: dims[d] for d in needs}}
    if shape == "sphere":
        kw.update(speed=speed, kinematic_viscosity=kinematic_viscosity)
    elif shape == "cylinder":
        kw["axial_model"] = axial_model
    elif shape == "flat_plate":
        kw["thickness"] = dims.get("thickness", 0.0)
    if drag_coefficient is not None:
        kw["drag_coefficient" if shape in ("sphere", "block", "flat_plate") else "drag_axial"] = drag_coefficient
    sc = SHAPES[shape](**kw)  # type: ignore[operator]
    vol = sc.volume if buoyancy is None else buoyancy / (density * gravity)
    part = Part(
        name,
        mass,
        vol,
        solid_inertia(shape, mass, dims) if inertia is None else _tensor(inertia),
        sc.added_mass,
        np.zeros((6, 6)),
        np.diag(sc.quadratic_damping(density)),
        r_g=np.zeros(3) if center_of_gravity is None else np.asarray(center_of_gravity, float),
        position=position,
        rotation=rotation,
        source=shape,
    )
    sources = dict(sc.sources) if inertia is None else {**sc.sources, "inertia": "given"}
    return GeometryPart(part, sources, shape, dims, None, bem, resolution)


@dataclass(frozen=True)
class Estimate(Result):
    """Coefficients estimated from a geometry.

    Attributes
    ----------
    geometry : Geometry — with each part's (possibly BEM-replaced) added mass
    composite : Composite — the combined body about the common origin (SI)
    bem : bool — whether the boundary-element solver gave the added mass of eligible parts
    """

    geometry: Geometry
    composite: Composite
    bem: bool

    def vehicle_fields(self) -> dict[str, Any]:
        """The combined body as vehicle-file fields (issue #3 format; full 6×6 matrices)."""
        return vehicle_fragment(self.geometry, self.composite)

    def to_dict(self) -> dict[str, Any]:
        """What ``hydrokit estimate`` writes: the vehicle-file fragment (JSON/YAML-ready)."""
        return jsonable(self.vehicle_fields())

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """One row per DOF: added mass full transform vs diagonal-only, linear damping, and the
        quadratic damping of the model (N·s²/m², N·m·s²/rad²).

        ``elements``: ``quadratic_damping_diagonal`` (what the vehicle file's diagonal holds: the
        parts' own rotational drag, and drag of parts centred at the origin) and
        ``quadratic_damping_single_axis`` (diagonal plus drag elements, for motion along or about
        that axis alone). ``rehman``: ``quadratic_damping`` (its diagonal is the single-axis
        value). ``shifted``: ``quadratic_damping_shifted`` next to ``quadratic_damping_single_axis``
        — the shifted rotational entries are d·r² (kg·m), not a drag coefficient.
        """
        c = self.composite
        DQ, one = np.diag(c.quadratic_damping), c.quadratic_damping_single_axis
        quad: dict[str, Any] = {
            "elements": {"quadratic_damping_diagonal": DQ, "quadratic_damping_single_axis": one},
            "rehman": {"quadratic_damping": DQ},
            "shifted": {"quadratic_damping_shifted": DQ, "quadratic_damping_single_axis": one},
        }[c.quadratic_damping_model]
        return (
            ["dof", "added_mass", "added_mass_diagonal_only", "linear_damping", *quad],
            [
                [
                    DOF_NAMES[i],
                    float(c.added_mass[i, i]),
                    float(c.added_mass_diagonal_only[i, i]),
                    float(c.linear_damping[i, i]),
                    *(float(v[i]) for v in quad.values()),
                ]
                for i in range(6)
            ],
        )

    def summary_rows(self) -> list[tuple[str, Any]]:
        c = self.composite
        return [
            ("geometry", self.geometry.name),
            ("parts", len(self.geometry.parts)),
            ("mass (kg)", c.mass),
            ("volume (m³)", c.volume),
            ("added mass diagonal", [float(x) for x in np.diag(c.added_mass)]),
            ("quadratic damping model", c.quadratic_damping_model),
            ("quadratic damping, single axis", [float(x) for x in c.quadratic_damping_single_axis]),
            ("drag elements", len(c.drag_element_names)),
            ("BEM", self.bem),
        ]

    def _repr_html_(self) -> str:
        return html_table(f"Estimate: {self.geometry.name}", self.summary_rows())

    def plot(self, ax: Any = None) -> Any:
        """Added-mass diagonal per DOF, full transform vs REHMAN's diagonal-only sum; returns the axes."""
        from hydrokit.plot.estimate import added_mass_axes

        return added_mass_axes(
            np.diag(self.composite.added_mass), np.diag(self.composite.added_mass_diagonal_only), ax, self.geometry.name
        )


def estimate_geometry(
    geometry: Geometry, bem: bool = False, resolution: int | None = None, quadratic_damping: str = "elements"
) -> Estimate:
    """Estimate the coefficients of ``geometry``; with ``bem`` the added mass of sphere,
    spheroid, cylinder and mesh parts comes from Capytaine (``hydrokit[bem]``).

    Parameters
    ----------
    geometry : Geometry
    bem : bool — use the boundary-element solver where a part allows it
    resolution : int, optional — BEM panels around the circumference (count; default per part)
    quadratic_damping : str — "elements" (default), "rehman" or "shifted": how the parts'
        quadratic damping combines (:func:`hydrokit.estimate.composite.combine`)

    Returns
    -------
    Estimate

    Raises
    ------
    InputError
        A mesh part without ``bem`` (its added mass can only come from the solver), or an
        unknown ``quadratic_damping`` model.
    MissingExtraError
        ``bem`` without capytaine installed.
    """
    if quadratic_damping not in QUADRATIC_DAMPING_MODELS:  # before any BEM run
        raise InputError(
            f"quadratic damping model {quadratic_damping!r}: expected one of {', '.join(QUADRATIC_DAMPING_MODELS)}"
        )
    parts = list(geometry.parts)
    if bem:
        from hydrokit.estimate.bem import added_mass_bem, shape_mesh

        new = []
        for gp in parts:
            if not gp.bem or (gp.mesh is None and gp.shape not in ("sphere", "spheroid", "cylinder")):
                new.append(gp)
                continue
            res = resolution or gp.resolution
            mesh = gp.mesh if gp.mesh is not None else shape_mesh(str(gp.shape), res, **gp.dims)
            sources = {**gp.sources, "added_mass": f"BEM (Capytaine, direct, {len(mesh.faces)} panels)"}
            new.append(
                replace(gp, part=replace(gp.part, added_mass=added_mass_bem(mesh, geometry.density)), sources=sources)
            )
        parts = new
    elif any(gp.mesh is not None for gp in parts):
        raise InputError("a mesh part needs --bem (its added mass comes from the BEM solver)", geometry.source)
    geo = replace(geometry, parts=parts)
    return Estimate(geo, combine([gp.part for gp in parts], quadratic_damping), bool(bem))


def vehicle_fragment(geo: Geometry, comp: Any) -> dict[str, Any]:
    """The combined body as vehicle-file fields (issue #3 format; full 6×6 matrices).

    ``quadratic_damping`` is the composite's diagonal; with the ``elements`` model the parts'
    translational drag follows as ``drag_elements: [{name, position, linear, quadratic}]`` (m,
    N·s/m, N·s²/m², body axes from the body origin). The model is named in ``sources``, and the
    composite's warnings go to ``warnings`` (both fields the vehicle reader keeps).
    """
    # 12 significant digits: drops the sums' round-off (stable files across BLAS builds) without
    # flattening a millimetre-scale part's inertia (1e-10 kg·m²) as fixed decimals would
    r = lambda a: np.vectorize(lambda v: float(f"{v:.12g}"), otypes=[float])(np.asarray(a, float)).tolist()  # noqa: E731
    model = getattr(comp, "quadratic_damping_model", "shifted")
    out: dict[str, Any] = {
        "name": geo.name,
        "gravity": geo.gravity,
        "fluid": {"density": geo.density},
        "mass": r(comp.mass),
        "volume": r(comp.volume),
        "inertia": r(comp.inertia_cg),
        "center_of_gravity": r(comp.r_g),
        "center_of_buoyancy": r(comp.r_b),
        "added_mass": r(comp.added_mass),
        "linear_damping": r(comp.linear_damping),
        "quadratic_damping": r(np.diag(comp.quadratic_damping)),
    }
    names = getattr(comp, "drag_element_names", ())
    if len(names):
        out["drag_elements"] = [
            {"name": n, "position": r(row[0:3]), "linear": r(row[3:6]), "quadratic": r(row[6:9])}
            for n, row in zip(names, comp.drag_elements)
        ]
    out["sources"] = [f"{gp.part.name}: {k}: {v}" for gp in geo.parts for k, v in gp.sources.items()]
    out["sources"].append(f"quadratic damping model: {model} ({MODEL_NOTES.get(model, '')})")
    if getattr(comp, "warnings", ()):
        out["warnings"] = list(comp.warnings)
    return out
