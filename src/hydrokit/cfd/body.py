"""Bodies for CFD: a closed surface mesh or a profile of a body of revolution.

Both are in body axes (x forward, y starboard, z down), metres, origin = moment reference point.
A profile (columns x, r; x from the nose along the axis, r ≥ 0, r = 0 at both ends) takes the
axisymmetric wedge path at zero incidence; at incidence or turning it is revolved into a
triangle surface and takes the 3-D path.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit.errors import InputError

#: segments around the axis when a profile is revolved into a surface
REVOLVE_SEGMENTS = 48
#: pixels per side of the raster that measures a projected (frontal) area
_RASTER = 256


@dataclass(frozen=True)
class Body:
    """The body as OpenFOAM meets it.

    kind : str — ``mesh`` (a closed triangle surface, ``triangles`` (k, 3, 3) m) or ``profile``
        (a body of revolution about the x axis, ``profile`` (n, 2) of x, r in m)
    name : str — for messages and reports
    length : float — reference length L, m (the body's extent along x)
    area : float — reference area for C_D, m² (frontal area unless given)
    """

    kind: str
    name: str
    length: float
    area: float
    triangles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)), repr=False)
    profile: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)), repr=False)
    part_sizes: tuple[int, ...] = ()

    def surfaces(self) -> list[np.ndarray]:
        """The closed surfaces of the body, one per part (triangles (k, 3, 3) each); a profile
        is revolved into one (the 3-D path of a body of revolution at incidence)."""
        if self.kind == "profile":
            tri = revolve(self.profile)
            tri[..., 0] = self.centre_of_buoyancy - tri[..., 0]
            return [tri[:, ::-1].copy()]  # the mirror in x turns the faces inside out: reverse them
        if not self.part_sizes:
            return [self.triangles]
        ends = np.cumsum(self.part_sizes)[:-1]
        return list(np.split(self.triangles, ends))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(min, max) corners of the body's bounding box, m."""
        if self.kind == "mesh":
            pts = self.triangles.reshape(-1, 3)
            return pts.min(axis=0), pts.max(axis=0)
        x, r = self.profile[:, 0], self.profile[:, 1]
        R, c = float(r.max()), self.centre_of_buoyancy
        return np.array([c - x.max(), -R, -R]), np.array([c - x.min(), R, R])

    @property
    def centre_of_buoyancy(self) -> float:
        """A profile's volume centroid, m along its x (from the nose): x_B = ∫x r² dx / ∫r² dx
        (trapezoids). A profile body's origin — its moment reference point — is there, on the
        axis, and body x points to the nose: x_body = x_B − x_profile."""
        x, r2 = self.profile[:, 0], self.profile[:, 1] ** 2
        dx = np.diff(x)
        vol = float(np.sum(dx * (r2[1:] + r2[:-1]) / 2))
        first = float(np.sum(dx * (x[1:] * r2[1:] + x[:-1] * r2[:-1]) / 2))
        return first / vol if vol > 0 else float(x.mean())

    def digest(self) -> str:
        """SHA-256 of the geometry rounded to 1 nm (a re-export's round-off keeps the cache)."""
        h = hashlib.sha256(self.kind.encode())
        data = self.triangles if self.kind == "mesh" else self.profile
        h.update(np.ascontiguousarray(np.round(np.asarray(data, float), 9)).tobytes())
        h.update(repr(self.part_sizes).encode())
        return h.hexdigest()


def check_profile(x: np.ndarray, r: np.ndarray, source: str = "profile") -> None:
    """Refuse a profile that is not a closed body of revolution (one line naming the point)."""
    x, r = np.asarray(x, float), np.asarray(r, float)
    if x.ndim != 1 or x.shape != r.shape or len(x) < 5:
        raise InputError(f"{len(x)} point(s) of x, r: expected at least 5 points along the body", source)
    for name, col in (("x", x), ("r", r)):
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise InputError(f"column '{name}' holds {col[bad[0]]} at row {bad[0] + 1}: expected finite metres", source)
    neg = np.flatnonzero(r < 0)
    if neg.size:
        raise InputError(f"column 'r' = {r[neg[0]]:g} m at row {neg[0] + 1}: expected a radius r >= 0", source)
    step = np.diff(x)
    back = np.flatnonzero(step <= 0)
    if back.size:
        i = back[0]
        raise InputError(
            f"column 'x' goes from {x[i]:g} to {x[i + 1]:g} m at row {i + 2}: expected x increasing from the nose",
            source,
        )
    if r[0] != 0 or r[-1] != 0:
        raise InputError(
            f"r = {r[0]:g} m at the nose and {r[-1]:g} m at the tail: expected a closed body (r = 0 at both ends)",
            source,
        )
    if not np.all(r[1:-1] > 0):
        i = int(np.flatnonzero(r[1:-1] <= 0)[0]) + 1
        raise InputError(
            f"r = 0 at row {i + 1} inside the body: expected one body (r > 0 between the nose and the tail)", source
        )


def profile_body(x: np.ndarray, r: np.ndarray, name: str = "profile", area: float | None = None) -> Body:
    """A body of revolution from its profile (x, r in m); reference area π r_max² unless given (m²)."""
    check_profile(x, r, name)
    x, r = np.asarray(x, float), np.asarray(r, float)
    area = math.pi * float(r.max()) ** 2 if area is None else area
    return Body("profile", name, float(x[-1] - x[0]), float(area), profile=np.column_stack([x, r]))


def mesh_body(triangles: np.ndarray, name: str = "body", area: float | None = None) -> Body:
    """A body from a closed, outward triangle surface (k, 3, 3), m; reference area = frontal area unless given."""
    tri = np.asarray(triangles, float)
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    area = projected_area(tri, 0) if area is None else area
    return Body("mesh", name, float(hi[0] - lo[0]), float(area), triangles=tri)


def revolve(profile: np.ndarray, segments: int = REVOLVE_SEGMENTS) -> np.ndarray:
    """Triangles (k, 3, 3) of the surface of revolution of (x, r) about the x axis, outward normals."""
    x, r = profile[:, 0], profile[:, 1]
    phi = np.linspace(0.0, 2 * math.pi, segments + 1)[:-1]
    ring = lambda i: np.column_stack([np.full(segments, x[i]), r[i] * np.cos(phi), r[i] * np.sin(phi)])  # noqa: E731
    tris = []
    n = len(x)
    for i in range(n - 1):
        a, b = ring(i), ring(i + 1)
        a1, b1 = np.roll(a, -1, axis=0), np.roll(b, -1, axis=0)
        if i > 0:  # the nose ring is one point: no degenerate triangle
            tris.append(np.stack([a, a1, b1], axis=1))
        if i < n - 2:
            tris.append(np.stack([a, b1, b], axis=1))
    out = np.concatenate(tris)
    return out


def projected_area(triangles: np.ndarray, axis: int) -> float:
    """Area of the body's shadow on the plane normal to ``axis`` (0 x, 1 y, 2 z), m².

    Measured on a 256 × 256 raster of the shadow's bounding box (each pixel centre inside any
    projected triangle counts): about 1 % for a sphere; exact for concave bodies too, unlike
    ½ Σ |n·e| A.
    """
    keep = [i for i in range(3) if i != axis]
    # the triangles facing +axis already cover the whole shadow of a closed surface
    normal = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])[:, axis]
    t = triangles[normal > 0][:, :, keep]
    lo, hi = t.reshape(-1, 2).min(axis=0), t.reshape(-1, 2).max(axis=0)
    span = np.maximum(hi - lo, 1e-300)
    px = span / _RASTER
    cx = lo[0] + (np.arange(_RASTER) + 0.5) * px[0]
    cy = lo[1] + (np.arange(_RASTER) + 0.5) * px[1]
    covered = np.zeros((_RASTER, _RASTER), bool)
    for a, b, c in t:
        i0, i1 = np.searchsorted(cx, [min(a[0], b[0], c[0]), max(a[0], b[0], c[0])])
        j0, j1 = np.searchsorted(cy, [min(a[1], b[1], c[1]), max(a[1], b[1], c[1])])
        if i1 <= i0 or j1 <= j0:
            continue
        X, Y = np.meshgrid(cx[i0:i1], cy[j0:j1], indexing="ij")
        d1 = (X - b[0]) * (a[1] - b[1]) - (a[0] - b[0]) * (Y - b[1])
        d2 = (X - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (Y - c[1])
        d3 = (X - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (Y - a[1])
        neg = (d1 < 0) | (d2 < 0) | (d3 < 0)
        pos = (d1 > 0) | (d2 > 0) | (d3 > 0)
        covered[i0:i1, j0:j1] |= ~(neg & pos)
    return float(covered.sum() * px[0] * px[1])


def box(length: float, width: float, height: float) -> np.ndarray:
    """Triangles (12, 3, 3) of a closed box centred at the origin (x length, y width, z height, m)."""
    hx, hy, hz = length / 2, width / 2, height / 2
    v = np.array([[sx * hx, sy * hy, sz * hz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [[v[a], v[b], v[c]], [v[a], v[c], v[d]]]
    return np.array(tris)


def geometry_body(geo: Any, area: float | None = None) -> Body:
    """The surface of a geometry file's parts (spheres, spheroids, cylinders, blocks, meshes),
    each placed and turned as the file says, as one body (overlapping parts are merged by the mesher)."""
    from hydrokit.estimate.bem import shape_mesh

    parts = []
    for gp in geo.parts:
        name = gp.part.name
        if gp.mesh is not None:
            tri = gp.mesh.vertices[gp.mesh.triangles()]
        elif gp.shape in ("sphere", "spheroid", "cylinder"):
            m = shape_mesh(str(gp.shape), 48, **gp.dims)
            tri = m.vertices[m.triangles()]
        elif gp.shape == "block":
            tri = box(gp.dims["length"], gp.dims["width"], gp.dims["height"])
        else:
            raise InputError(
                f"part {name!r} has no surface ({gp.shape or 'a vehicle reference'}); expected sphere, spheroid, "
                "cylinder, block or mesh parts for CFD",
                geo.source,
            )
        R, r0 = np.asarray(gp.part.rotation, float), np.asarray(gp.part.position, float)
        parts.append(tri @ R.T + r0)
    if not parts:
        raise InputError("the geometry has no parts; expected at least one part with a surface", geo.source)
    tri = np.concatenate(parts)
    body = mesh_body(tri, geo.name, area)
    return Body(body.kind, body.name, body.length, body.area, triangles=tri, part_sizes=tuple(len(p) for p in parts))
