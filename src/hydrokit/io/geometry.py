"""Geometry files (YAML) for ``hydrokit estimate`` (see docs/estimate.md).

```yaml
name: rehman-assembly
gravity: 9.81                  # m/s^2
fluid: {density: 1025, kinematic_viscosity: 1.05e-6}   # kg/m^3, m^2/s
speed: 1.0                     # m/s, operating speed for Reynolds-dependent drag
parts:
  - name: payload
    shape: sphere              # sphere | spheroid | cylinder | block | flat_plate
    diameter: 0.5              # m (dimensions: diameter, length, width, height, thickness)
    mass: 130                  # kg (or weight: N)
    buoyancy: 658              # N, optional (default ρ g × shape volume)
    position: [0, 0, 0]        # m, part centre in the common frame
    rotation_deg: [0, 0, 0]    # roll, pitch, yaw of the part axes (shape axis = part x)
    drag_coefficient: 0.46     # optional override
    center_of_gravity: [0, 0, 0.02]   # m, part axes, optional (default: the shape's centre)
    inertia: [2.1, 2.1, 2.1]   # kg m^2 about the CG, diagonal or 3x3, optional (default: uniform solid)
  - name: minerva-1
    vehicle: minerva           # a vehicle file or bundled name: its mass, inertia, CG, CB, M_A, D
    position: [0, -1.85, 0]
  - name: hull
    mesh: hull.stl             # STL/OBJ (m): added mass by BEM (needs --bem)
    mass: 12.0                 # without inertia / center_of_gravity: a uniform solid filling the mesh
```

A ``vehicle:`` part takes only name, position and rotation_deg besides the vehicle; any other
part key there is refused rather than ignored.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.constants import GRAVITY, SEAWATER_DENSITY
from hydrokit.core.validate import body_quantity, cut_repr, matrix, number, vector
from hydrokit.errors import InputError
from hydrokit.estimate.bem import MAX_RESOLUTION
from hydrokit.estimate.geometry import DEFAULT_RESOLUTION, Geometry, GeometryPart, mesh_part, shape_part, vehicle_part
from hydrokit.io.yamlfile import check_keys, read_yaml

DIMENSIONS = ("diameter", "length", "width", "height", "thickness")
#: the top-level keys of a geometry (and assembly) file and of its ``fluid`` block
TOP_KEYS = frozenset({"name", "description", "gravity", "fluid", "speed", "parts"})
FLUID_KEYS = frozenset({"density", "kinematic_viscosity"})
PART_KEYS = {
    "name",
    "shape",
    "vehicle",
    "mesh",
    "mass",
    "weight",
    "buoyancy",
    "position",
    "rotation_deg",
    "drag_coefficient",
    "axial_model",
    "inertia",
    "center_of_gravity",
    "bem",
    "resolution",
    *DIMENSIONS,
}


#: the keys a ``vehicle:`` part reads (its mass, inertia, shape come from the vehicle file)
VEHICLE_PART_KEYS = frozenset({"name", "vehicle", "position", "rotation_deg"})


def _num(v: Any, where: str, src: str, positive: bool = True) -> float:
    return number(v, where, src, positive=positive)


def _vec(v: Any, where: str, src: str) -> np.ndarray:
    return vector(v, 3, where, src)


def _inertia(v: Any, where: str, src: str) -> np.ndarray:
    """A part's inertia tensor (kg·m² about its CG): 3 values or 3×3, symmetric, with principal
    moments a rigid body can have (positive, each at most the sum of the other two)."""
    inertia = matrix(v, 3, where, src)
    if not np.allclose(inertia, inertia.T, rtol=0, atol=1e-9 * np.abs(inertia).max()):
        raise InputError(f"field '{where}' = {cut_repr(inertia.tolist())}: expected a symmetric tensor", src)
    p = np.linalg.eigvalsh(inertia)
    if not (p[0] > 0 and p[2] <= (p[0] + p[1]) * (1 + 1e-9)):
        raise InputError(
            f"field '{where}': principal moments {cut_repr([float(f'{x:.6g}') for x in p])} kg·m²; expected "
            "positive moments, each at most the sum of the other two (a rigid body's)",
            src,
        )
    return inertia


def vehicle_ref(ref: Any, p: Path) -> str:
    """A part's ``vehicle:`` value: a path relative to the geometry file at ``p`` when such a
    file exists there, else as given (a bundled name or a path from the working folder)."""
    local = p.parent / str(ref)
    return str(local) if local.is_file() else str(ref)


def load_geometry(path: str | os.PathLike[str]) -> Geometry:
    """Read a geometry file (fields validated here; each part's coefficients come from
    :mod:`hydrokit.estimate.geometry`)."""
    p = Path(path)
    return parse_geometry(read_yaml(p), p)


def parse_geometry(data: dict[str, Any], p: Path, extra_part_keys: frozenset[str] = frozenset()) -> Geometry:
    """Validate the parsed mapping of a geometry file at ``p`` (relative mesh and vehicle paths
    resolve against its folder). ``extra_part_keys`` are part keys another format (the
    assembly file) reads itself; they are ignored here."""
    from hydrokit.estimate.composite import rotation_from_degrees

    src = str(p)
    check_keys(data, TOP_KEYS, "", src)
    g = _num(data.get("gravity", GRAVITY), "gravity", src)
    fluid = data.get("fluid", {"density": SEAWATER_DENSITY})
    if not isinstance(fluid, dict):
        raise InputError(f"field 'fluid' = {fluid!r}: expected a mapping with density", src)
    check_keys(fluid, FLUID_KEYS, "fluid", src)
    rho = _num(fluid.get("density", SEAWATER_DENSITY), "fluid.density", src)
    nu = _num(fluid.get("kinematic_viscosity", 1.05e-6), "fluid.kinematic_viscosity", src)
    speed = _num(data.get("speed", 1.0), "speed", src)
    parts_raw = data.get("parts")
    if not isinstance(parts_raw, list) or not parts_raw:
        raise InputError("field 'parts': expected a non-empty list of parts", src)
    parts: list[GeometryPart] = []
    for k, raw in enumerate(parts_raw):
        where = f"parts[{k}]"
        if not isinstance(raw, dict):
            raise InputError(f"field '{where}': expected a mapping", src)
        check_keys(raw, PART_KEYS | extra_part_keys, where, src)
        name = str(raw.get("name", f"part{k + 1}"))
        pos = _vec(raw.get("position", [0, 0, 0]), f"{where}.position", src)
        rot_deg = _vec(raw.get("rotation_deg", [0, 0, 0]), f"{where}.rotation_deg", src)
        R = rotation_from_degrees(*rot_deg)
        kinds = [x for x in ("shape", "vehicle", "mesh") if x in raw]
        if len(kinds) != 1:
            raise InputError(f"field '{where}': give exactly one of shape, vehicle, mesh (got {kinds or 'none'})", src)
        if "vehicle" in raw:
            from hydrokit.io.vehicle import load_vehicle

            ignored = sorted(set(raw) & (PART_KEYS - VEHICLE_PART_KEYS))
            if ignored:
                raise InputError(
                    f"field '{where}.{ignored[0]}': a vehicle part takes its body from the vehicle file; "
                    "expected only name, vehicle, position, rotation_deg",
                    src,
                )

            parts.append(vehicle_part(name, load_vehicle(vehicle_ref(raw["vehicle"], p)), pos, R, str(raw["vehicle"])))
            continue
        if "mass" in raw:
            mass = body_quantity(_num(raw["mass"], f"{where}.mass", src), "mass", f"{where}.mass", src)
        elif "weight" in raw:
            weight = _num(raw["weight"], f"{where}.weight", src)
            mass = body_quantity(weight / g, "mass", f"{where}.weight", src, shown=weight)
        else:
            raise InputError(f"field '{where}': missing 'mass' (kg) or 'weight' (N)", src)
        dims = {
            d: body_quantity(_num(raw[d], f"{where}.{d}", src), "size", f"{where}.{d}", src)
            for d in DIMENSIONS
            if d in raw
        }
        buoyancy = _num(raw["buoyancy"], f"{where}.buoyancy", src) if "buoyancy" in raw else None
        resolution = raw.get("resolution", DEFAULT_RESOLUTION)
        if isinstance(resolution, bool) or not isinstance(resolution, int) or not 6 <= resolution <= MAX_RESOLUTION:
            raise InputError(
                f"field '{where}.resolution' = {cut_repr(resolution)}: expected a whole number of panels "
                f"around from 6 to {MAX_RESOLUTION}",
                src,
            )
        if not isinstance(raw.get("bem", True), bool):
            raise InputError(f"field '{where}.bem' = {cut_repr(raw['bem'])}: expected true or false", src)
        inertia = _inertia(raw["inertia"], f"{where}.inertia", src) if "inertia" in raw else None
        cog = _vec(raw["center_of_gravity"], f"{where}.center_of_gravity", src) if "center_of_gravity" in raw else None
        if "mesh" in raw:
            from hydrokit.estimate.mesh import read_mesh

            for key in ("bem", "resolution"):  # BEM on the mesh's own panels, always
                if key in raw:
                    raise InputError(
                        f"field '{where}.{key}' = {cut_repr(raw[key])}: a mesh part always takes its added "
                        "mass from BEM on the mesh's own panels; remove the key",
                        src,
                    )

            mpath = Path(raw["mesh"])
            mesh = read_mesh(mpath if mpath.is_absolute() else p.parent / mpath)
            parts.append(
                mesh_part(
                    name,
                    mesh,
                    mass,
                    pos,
                    R,
                    density=rho,
                    gravity=g,
                    buoyancy=buoyancy,
                    inertia=inertia,
                    center_of_gravity=cog,
                    dims=dims,
                    resolution=resolution,
                )
            )
            continue
        shape = raw["shape"]
        drag = _num(raw["drag_coefficient"], f"{where}.drag_coefficient", src) if "drag_coefficient" in raw else None
        parts.append(
            shape_part(
                name,
                shape,
                mass,
                dims,
                pos,
                R,
                density=rho,
                gravity=g,
                speed=speed,
                kinematic_viscosity=nu,
                drag_coefficient=drag,
                axial_model=str(raw.get("axial_model", "spheroid")),
                buoyancy=buoyancy,
                inertia=inertia,
                center_of_gravity=cog,
                bem=raw.get("bem", True),
                resolution=resolution,
                where=where,
                source=src,
            )
        )
    return Geometry(str(data.get("name", p.stem)), g, rho, parts, src)
