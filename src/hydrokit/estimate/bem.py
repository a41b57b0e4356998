"""Boundary-element added mass of a deeply submerged body (SPEC §2.4; extra ``hydrokit[bem]``).

Capytaine solves the radiation problem with no free surface (``free_surface=np.inf``) at
infinite frequency (``omega=np.inf``) with the direct method (``BEMSolver(method="direct")``,
far more accurate for added mass than the default indirect one). Results are cached as JSON
keyed by the SHA-256 of the mesh, the density and the reference point (no pickle).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.core.constants import SEAWATER_DENSITY
from hydrokit.errors import InputError, MissingExtraError
from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

DOFS = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")


def cache_dir() -> Path:
    """$HYDROKIT_CACHE or ~/.cache/hydrokit/bem."""
    base = os.environ.get("HYDROKIT_CACHE")
    return Path(base) if base else Path.home() / ".cache" / "hydrokit" / "bem"


def _capytaine():  # noqa: ANN202
    try:
        import capytaine
    except ImportError:
        raise MissingExtraError("capytaine", "bem") from None
    return capytaine


#: the finest built-in mesh, panels around: a sphere then has ≈ MAX_RESOLUTION²/2 = 20 000 panels,
#: the most the direct solver's dense matrices hold in a few GB (see :func:`panel_memory_check`)
MAX_RESOLUTION = 200


def panel_memory_check(panels: int, source: str = "") -> None:
    """Refuse, before solving, a mesh whose direct BEM solve would not fit in memory: the
    solver holds two dense complex panels × panels matrices (16 bytes an entry), here allowed at
    most half of the machine's physical memory (not checked where the OS does not report it)."""
    need = 32.0 * panels * panels
    try:
        have = float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - no sysconf (Windows): not checked
        return
    if need > 0.5 * have:
        most = int(math.sqrt(0.5 * have / 32.0))
        raise InputError(
            f"mesh has {panels} panels: the direct BEM solve needs ≈ {need / 1e9:.1f} GB, more than half of "
            f"this machine's {have / 1e9:.1f} GB; expected at most {most} panels (a coarser --resolution or "
            "a decimated mesh)",
            source,
        )


def shape_mesh(shape: str, resolution: int = 24, **dims: float) -> SurfaceMesh:
    """A closed, outward mesh of a named shape centred at the origin (axis x).

    shape : sphere (diameter), spheroid (length, diameter), cylinder (length, diameter), block
    (length, width, height); resolution : panels around the circumference (≈ count).
    """
    n = int(resolution)
    if not 6 <= n <= MAX_RESOLUTION:
        raise InputError(f"resolution = {resolution}: expected from 6 to {MAX_RESOLUTION} panels around")
    if shape in ("sphere", "spheroid"):
        a = dims["length"] / 2 if shape == "spheroid" else dims["diameter"] / 2
        b = dims["diameter"] / 2
        nt, nphi = n // 2, n
        # cosine spacing of the polar angle packs panels near the tips of a slender spheroid
        th = np.linspace(0.0, np.pi, nt + 1)
        ph = np.linspace(0.0, 2 * np.pi, nphi + 1)[:-1]
        verts = [[a, 0.0, 0.0]]
        for t in th[1:-1]:
            for p in ph:
                verts.append([a * math.cos(t), b * math.sin(t) * math.cos(p), b * math.sin(t) * math.sin(p)])
        verts.append([-a, 0.0, 0.0])
        V = np.array(verts)
        faces = []
        ring = lambda i, j: 1 + i * nphi + (j % nphi)  # noqa: E731
        for j in range(nphi):
            faces.append([0, ring(0, j), ring(0, j + 1)])
        for i in range(nt - 2):
            for j in range(nphi):
                faces.append([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)])
        last = len(V) - 1
        for j in range(nphi):
            faces.append([ring(nt - 2, j + 1), ring(nt - 2, j), last, last])
        F = np.array([f if len(f) == 4 else f + [f[-1]] for f in faces])
        # outward by construction: the faces run counter-clockwise seen from outside the unit
        # sphere, and scaling the axes by a, b > 0 keeps the orientation
        return SurfaceMesh(V, F, shape)
    if shape == "cylinder":
        L, r = dims["length"], dims["diameter"] / 2
        nx = max(2, int(round(n * L / (2 * math.pi * r))))
        ph = np.linspace(0.0, 2 * np.pi, n + 1)[:-1]
        xs = np.linspace(-L / 2, L / 2, nx + 1)
        V = np.array(
            [[x, r * math.cos(p), r * math.sin(p)] for x in xs for p in ph] + [[-L / 2, 0.0, 0.0], [L / 2, 0.0, 0.0]]
        )
        idx = lambda i, j: i * n + (j % n)  # noqa: E731
        quads = [[idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)] for i in range(nx) for j in range(n)]
        c0, c1 = len(V) - 2, len(V) - 1
        quads += [[c0, idx(0, j + 1), idx(0, j), idx(0, j)] for j in range(n)]
        quads += [[c1, idx(nx, j), idx(nx, j + 1), idx(nx, j + 1)] for j in range(n)]
        # built facing outwards (positive enclosed volume) for every size and resolution:
        # tests/estimate/test_mutants_estimate.py checks the volume against the prism's
        return SurfaceMesh(V, np.array(quads), shape)
    raise InputError(
        f"shape {shape!r} has no built-in BEM mesh; expected sphere, spheroid or cylinder (or give an STL/OBJ)"
    )


def added_mass_bem(
    mesh: SurfaceMesh, density: float = SEAWATER_DENSITY, reference_point=(0.0, 0.0, 0.0), use_cache: bool = True
) -> np.ndarray:
    """6×6 added mass (kg, kg·m, kg·m²) about ``reference_point`` (m) of a deeply submerged body.

    Raises MissingExtraError without capytaine, InputError for an open or inward mesh.
    """
    check_mesh(mesh)
    panel_memory_check(len(mesh.faces), mesh.source)
    ref = tuple(float(x) for x in reference_point)
    key = f"{mesh.digest()}-{density:.6g}-{ref[0]:.6g},{ref[1]:.6g},{ref[2]:.6g}"
    cfile = cache_dir() / f"{key[:40]}.json"
    if use_cache and cfile.is_file():
        try:
            doc = json.loads(cfile.read_text())
            if doc.get("key") == key:
                return np.array(doc["added_mass"])
        except (ValueError, KeyError):
            pass
    with quiet("capytaine"):
        return _solve(mesh, density, ref, cfile if use_cache else None, key)


def _solve(mesh: Any, density: float, ref: Any, cfile: Any, key: str) -> np.ndarray:
    """Capytaine's six radiation problems at infinite frequency (see :func:`added_mass_bem`)."""
    cpt = _capytaine()
    faces = mesh.faces if mesh.faces.shape[1] == 4 else np.column_stack([mesh.faces, mesh.faces[:, 2]])
    cmesh = cpt.Mesh(vertices=mesh.vertices, faces=faces)
    body = cpt.FloatingBody(mesh=cmesh, dofs=cpt.rigid_body_dofs(rotation_center=ref))
    solver = cpt.BEMSolver(method="direct")
    MA = np.zeros((6, 6))
    for j, dof in enumerate(DOFS):
        res = solver.solve(
            cpt.RadiationProblem(body=body, radiating_dof=dof, omega=np.inf, free_surface=np.inf, rho=float(density))
        )
        for i, d in enumerate(DOFS):
            MA[i, j] = res.added_mass[d]
    MA = 0.5 * (MA + MA.T)
    if cfile is not None:
        from hydrokit._atomic import write_text

        write_text(cfile, json.dumps({"key": key, "added_mass": MA.tolist()}))
    return MA
