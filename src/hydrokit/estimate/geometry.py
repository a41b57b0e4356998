"""Coefficients of a whole geometry: parts, optional BEM added mass, the combined body.

A :class:`Geometry` is what a geometry file holds (parsed by
:func:`hydrokit.io.geometry.load_geometry`); :func:`estimate_geometry` turns it into an
:class:`Estimate` — per-part coefficients with their sources and the composite body about the
common origin (full 6×6 transform and REHMAN's diagonal-only sum for comparison).
"""

from __future__ import annotations

import html
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit._result import Result, html_table, jsonable
from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.estimate.composite import Composite, combine


@dataclass
class GeometryPart:
    """A parsed part: the composite Part, its coefficients' sources and the shape (for BEM)."""

    part: Any
    sources: dict[str, str]
    shape: str | None
    dims: dict[str, float]
    mesh: Any = None
    bem: bool = True
    resolution: int = 48


@dataclass
class Geometry:
    """A geometry file: name, gravity (m/s²), fluid density (kg/m³), parts, the file."""

    name: str
    gravity: float
    density: float
    parts: list[GeometryPart]
    source: str


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
    bem: bool = False

    def vehicle_fields(self) -> dict[str, Any]:
        """The combined body as vehicle-file fields (issue #3 format; full 6×6 matrices)."""
        return vehicle_fragment(self.geometry, self.composite)

    def to_dict(self) -> dict[str, Any]:
        """What ``hydrokit estimate`` writes: the vehicle-file fragment (JSON/YAML-ready)."""
        return jsonable(self.vehicle_fields())

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """One row per DOF: added mass full transform vs diagonal-only, linear and quadratic damping."""
        c = self.composite
        return (
            ["dof", "added_mass", "added_mass_diagonal_only", "linear_damping", "quadratic_damping"],
            [
                [
                    DOF_NAMES[i],
                    float(c.added_mass[i, i]),
                    float(c.added_mass_diagonal_only[i, i]),
                    float(c.linear_damping[i, i]),
                    float(c.quadratic_damping[i, i]),
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
            ("added mass diagonal", [round(float(x), 4) for x in np.diag(c.added_mass)]),
            ("BEM", self.bem),
        ]

    def _repr_html_(self) -> str:
        return html_table(f"Estimate: {html.escape(self.geometry.name)}", self.summary_rows())

    def plot(self, ax: Any = None) -> Any:
        """Added-mass diagonal per DOF, full transform vs REHMAN's diagonal-only sum; returns the axes."""
        from hydrokit.plot.estimate import added_mass_axes

        return added_mass_axes(
            np.diag(self.composite.added_mass), np.diag(self.composite.added_mass_diagonal_only), ax, self.geometry.name
        )


def estimate_geometry(geometry: Geometry, bem: bool = False, resolution: int | None = None) -> Estimate:
    """Estimate the coefficients of ``geometry``; with ``bem`` the added mass of sphere,
    spheroid, cylinder and mesh parts comes from Capytaine (``hydrokit[bem]``).

    Parameters
    ----------
    geometry : Geometry
    bem : bool — use the boundary-element solver where a part allows it
    resolution : int, optional — BEM panels around the circumference (count; default per part)

    Returns
    -------
    Estimate

    Raises
    ------
    InputError
        A mesh part without ``bem`` (its added mass can only come from the solver).
    MissingExtraError
        ``bem`` without capytaine installed.
    """
    parts = list(geometry.parts)
    if bem:
        from hydrokit.estimate.bem import added_mass_bem, shape_mesh

        new = []
        for gp in parts:
            if gp.mesh is None and (gp.shape not in ("sphere", "spheroid", "cylinder") or not gp.bem):
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
    return Estimate(geo, combine([gp.part for gp in parts]), bool(bem))


def vehicle_fragment(geo: Geometry, comp: Any) -> dict[str, Any]:
    """The combined body as vehicle-file fields (issue #3 format; full 6×6 matrices)."""
    r = lambda a: np.round(np.asarray(a, float), 9).tolist()  # noqa: E731
    return {
        "name": geo.name,
        "gravity": geo.gravity,
        "fluid": {"density": geo.density},
        "mass": round(float(comp.mass), 9),
        "volume": round(float(comp.volume), 9),
        "inertia": r(comp.inertia_cg),
        "center_of_gravity": r(comp.r_g),
        "center_of_buoyancy": r(comp.r_b),
        "added_mass": r(comp.added_mass),
        "linear_damping": r(comp.linear_damping),
        "quadratic_damping": r(np.diag(comp.quadratic_damping)),
        "sources": [f"{gp.part.name}: {k}: {v}" for gp in geo.parts for k, v in gp.sources.items()],
    }
