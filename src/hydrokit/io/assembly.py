"""Assembly files (YAML) for ``hydrokit transport`` (issue #11; see docs/transport.md).

An assembly file is a geometry file (:mod:`hydrokit.io.geometry`, the format of
``hydrokit estimate``) whose parts also say how they hang together::

    parts:
      - {name: payload, shape: sphere, diameter: 0.5, mass: 130, position: [0, 0, 0]}
      - name: arm
        shape: cylinder
        ...
        parent: payload              # the part it is joined to (one part has no parent: the root)
        joint: [0, -0.25, 0]         # joint point, m, common frame
        joint_stiffness: [1e6, 1e6, 1e6, 1e6, 1e6, 1e6]   # optional: N/m ×3, N·m/rad ×3
        joint_damping: [...]         # optional: N·s/m ×3, N·m·s/rad ×3
        # defaults: each DOF a critically damped 100 Hz spring

Vehicle parts bring the thrusters of their vehicle file, named ``PART.THRUSTER``. Parts form
a tree: names unique, exactly one root, every parent known, no cycle, every joint point near
its parent or its child. Each error is one line naming the field.
"""

from __future__ import annotations

import math
import os
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.drag import DragElement
from hydrokit.core.validate import vector
from hydrokit.errors import InputError
from hydrokit.io.geometry import parse_geometry, vehicle_ref
from hydrokit.io.yamlfile import read_yaml
from hydrokit.model.assembly import Assembly, check_tree, joint_mobility, subtree_of
from hydrokit.model.thrusters import ThrusterSet
from hydrokit.model.vehicle import Vehicle, make_vehicle

ASSEMBLY_KEYS = frozenset({"parent", "joint", "joint_stiffness", "joint_damping"})
ASSEMBLIES_DIR = Path(__file__).resolve().parents[1] / "data" / "assemblies"
#: default joint of the joined-bodies model: every DOF a critically damped spring of this
#: natural frequency (Hz) against the mass it moves (1 / diagonal of the joint mobility): stiff enough
#: that a deflection is acceleration / (2π·100 Hz)² (2.5 µm per m/s²), soft enough that RK4
#: needs about 20 sub-steps at dt = 0.01 s
DEFAULT_JOINT_HZ = 100.0


def bundled_assemblies() -> list[str]:
    """Names of the bundled assembly files."""
    return sorted(p.stem for p in ASSEMBLIES_DIR.glob("*.yaml"))


def resolve_assembly(name_or_path: str | os.PathLike[str]) -> Path:
    """A path from a file path or a bundled assembly name."""
    p = Path(name_or_path)
    if p.is_file():
        return p
    bundled = ASSEMBLIES_DIR / f"{Path(str(name_or_path)).stem}.yaml"
    if "/" not in str(name_or_path) and bundled.is_file():
        return bundled
    raise InputError(f"no such file or bundled assembly '{name_or_path}' (bundled: {', '.join(bundled_assemblies())})")


def load_assembly(name_or_path: str | os.PathLike[str], quadratic_damping: str = "elements") -> Assembly:
    """Read and validate an assembly file (see module docstring) and build its bodies.

    Parameters
    ----------
    name_or_path : a file or a bundled assembly name (``rehman_transport``)
    quadratic_damping : how composites carry the parts' quadratic drag — ``elements`` (each
        part's drag at its own point, the default), ``rehman`` (d·r³ diagonal) or ``shifted``
        (Hᵀ D H, dimensionally wrong; comparison only)
    """
    path = resolve_assembly(name_or_path)
    src = str(path)
    data = read_yaml(path)
    geo = parse_geometry(data, path, ASSEMBLY_KEYS)
    raw_parts = data["parts"]
    names = [gp.part.name for gp in geo.parts]
    parent_names: list[str | None] = []
    for k, raw in enumerate(raw_parts):
        par = raw.get("parent")
        if par is not None and not isinstance(par, str):
            raise InputError(f"field 'parts[{k}].parent' = {par!r}: expected a part name", src)
        parent_names.append(par)
    parents = check_tree(names, parent_names, src)
    n = len(names)
    positions = np.array([gp.part.position for gp in geo.parts], float)
    rotations = np.array([gp.part.rotation for gp in geo.parts], float)
    joints = positions.copy()
    stiff = np.full((n, 6), np.nan)
    damp = np.full((n, 6), np.nan)
    reach = [_reach(gp) for gp in geo.parts]
    for k, raw in enumerate(raw_parts):
        if parents[k] < 0:
            extra = sorted(ASSEMBLY_KEYS & set(raw))
            if extra:
                raise InputError(f"field 'parts[{k}].{extra[0]}': the root part ({names[k]}) has no joint", src)
            continue
        if "joint" not in raw:
            raise InputError(f"field 'parts[{k}].joint': missing; expected the joint point [x, y, z] (m)", src)
        j = vector(raw["joint"], 3, f"parts[{k}].joint", src)
        p = parents[k]
        d_par = float(np.linalg.norm(j - positions[p]))
        d_chi = float(np.linalg.norm(j - positions[k]))
        if d_par > 2 * reach[p] + 0.1 and d_chi > 2 * reach[k] + 0.1:
            raise InputError(
                f"field 'parts[{k}].joint' = {j.tolist()}: {d_chi:.3g} m from {names[k]} and {d_par:.3g} m from "
                f"its parent {names[p]}; expected a point on or near one of them (within {2 * reach[k] + 0.1:.3g} m "
                f"or {2 * reach[p] + 0.1:.3g} m)",
                src,
            )
        joints[k] = j
        for key, arr in (("joint_stiffness", stiff), ("joint_damping", damp)):
            if key in raw:
                v = vector(raw[key], 6, f"parts[{k}].{key}", src)
                if np.any(v <= 0) if key == "joint_stiffness" else np.any(v < 0):
                    raise InputError(
                        f"field 'parts[{k}].{key}' = {v.tolist()}: expected "
                        f"{'positive' if key == 'joint_stiffness' else 'non-negative'} values "
                        f"({'N/m, N·m/rad' if key == 'joint_stiffness' else 'N·s/m, N·m·s/rad'})",
                        src,
                    )
                arr[k] = v

    parts = [gp.part for gp in geo.parts]
    from hydrokit.estimate.composite import combine

    def vehicle_of(ps: list[Any], label: str) -> Vehicle:
        return _to_vehicle(combine(ps, quadratic_damping=quadratic_damping), label, geo.gravity, geo.density, src)

    composite = vehicle_of(parts, geo.name)
    subtrees = tuple(vehicle_of([parts[m] for m in subtree_of(parents, i)], names[i]) for i in range(n))
    bodies = tuple(vehicle_of([replace(parts[i], position=np.zeros(3))], names[i]) for i in range(n))
    root = parents.index(-1)
    kids = [i for i in range(n) if parents[i] == root]
    group_parts: list[tuple[int, ...]] = []
    groups: list[Vehicle] = []
    for c in kids:
        members = subtree_of(parents, c)
        share = _scaled(parts[root], 1.0 / len(kids))
        groups.append(vehicle_of([share] + [parts[m] for m in members], f"{names[c]} group"))
        group_parts.append((root, *members))
    w_j = 2.0 * math.pi * DEFAULT_JOINT_HZ
    for i in range(n):  # defaults against the mass each joint DOF moves (both bodies)
        if parents[i] >= 0:
            p = parents[i]
            G = joint_mobility(bodies[p], bodies[i], joints[i] - positions[p], joints[i] - positions[i])
            m_eff = 1.0 / np.diag(G)
            stiff[i] = np.where(np.isnan(stiff[i]), m_eff * w_j**2, stiff[i])
            damp[i] = np.where(np.isnan(damp[i]), 2.0 * np.sqrt(stiff[i] * m_eff), damp[i])
    stiff = np.nan_to_num(stiff)
    damp = np.nan_to_num(damp)
    thr, owner = _thrusters(raw_parts, geo, names, positions, rotations, path)
    return Assembly(
        geo.name,
        tuple(names),
        tuple(parents),
        positions,
        rotations,
        joints,
        stiff,
        damp,
        composite,
        subtrees,
        bodies,
        tuple(groups),
        tuple(group_parts),
        thr,
        owner,
        src,
    )


def _reach(gp: Any) -> float:
    """A part's size for the joint check: half its largest dimension or its equivalent-sphere
    radius, m."""
    dims = [float(v) for v in gp.dims.values()] if gp.dims else []
    r_eq = (3.0 * max(gp.part.volume, 0.0) / (4.0 * math.pi)) ** (1.0 / 3.0)
    return max([0.5 * d for d in dims] + [r_eq, 0.05])


def _scaled(part: Any, s: float) -> Any:
    """A share s of a part (mass, volume, inertia, added mass and damping times s)."""
    kw: dict[str, Any] = {
        "name": f"{part.name} (share {s:.3g})",
        "mass": part.mass * s,
        "volume": part.volume * s,
        "inertia": part.inertia * s,
        "added_mass": part.added_mass * s,
        "linear_damping": part.linear_damping * s,
        "quadratic_damping": part.quadratic_damping * s,
    }
    el = getattr(part, "drag_elements", None)
    if el is not None and np.size(el):
        el = np.array(el, float)
        el[:, 3:9] *= s
        kw["drag_elements"] = el
    return replace(part, **kw)


def _to_vehicle(comp: Any, name: str, gravity: float, density: float, src: str) -> Vehicle:
    packed = np.asarray(getattr(comp, "drag_elements", np.zeros((0, 9))), float).reshape(-1, 9)
    el_names = list(getattr(comp, "drag_element_names", ())) or [f"e{k}" for k in range(len(packed))]
    elements = tuple(
        DragElement(str(nm), tuple(r[0:3]), tuple(r[3:6]), tuple(r[6:9]))  # type: ignore[arg-type]
        for nm, r in zip(el_names, packed)
    )
    return make_vehicle(
        name,
        comp.mass,
        comp.volume,
        gravity,
        density,
        comp.inertia_cg,
        comp.r_g,
        comp.r_b,
        comp.added_mass,
        comp.linear_damping,
        np.diag(comp.quadratic_damping),
        source=src,
        drag_elements=elements,
    )


def _thrusters(
    raw_parts: list[dict[str, Any]],
    geo: Any,
    names: list[str],
    positions: np.ndarray,
    rotations: np.ndarray,
    path: Path,
) -> tuple[ThrusterSet | None, tuple[int, ...]]:
    """Every vehicle part's thrusters in common axes about the common origin, PART.THRUSTER."""
    from hydrokit.io.thrusters import load_thrusters
    from hydrokit.io.vehicle import resolve_vehicle

    out = []
    owner: list[int] = []
    for k, raw in enumerate(raw_parts):
        if "vehicle" not in raw:
            continue
        vpath = resolve_vehicle(vehicle_ref(raw["vehicle"], path))
        if "thrusters" not in (read_yaml(vpath) or {}):
            continue
        ts = load_thrusters(vpath)
        R, p = rotations[k], positions[k]
        for th in ts.thrusters:
            pos = p + R @ np.asarray(th.position, float)
            e = R @ np.asarray(th.direction, float)
            out.append(
                replace(th, name=f"{names[k]}.{th.name}", position=tuple(pos.tolist()), direction=tuple(e.tolist()))
            )
            owner.append(k)
    if not out:
        return None, ()
    return ThrusterSet(tuple(out), density=geo.density), tuple(owner)
