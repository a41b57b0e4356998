"""Triangle/quad surface meshes: reading (STL ASCII/binary, OBJ) and checks for BEM.

A mesh for a deeply submerged body must be closed (every edge shared by exactly two faces)
and oriented with outward normals (positive enclosed volume by the divergence theorem).
"""

from __future__ import annotations

import hashlib
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hydrokit.errors import InputError


@dataclass(frozen=True)
class SurfaceMesh:
    """vertices (n, 3) m; faces (m, 3) or (m, 4) vertex indices (quads may repeat a vertex)."""

    vertices: np.ndarray
    faces: np.ndarray
    source: str = ""

    def triangles(self) -> np.ndarray:
        """Faces split into triangles (k, 3)."""
        f = self.faces
        if f.shape[1] == 3:
            return f
        tri = np.concatenate([f[:, [0, 1, 2]], f[:, [0, 2, 3]]])
        return tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])]

    def volume(self) -> float:
        """Enclosed volume, m³ (positive for outward normals)."""
        v = self.vertices[self.triangles()]
        return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)

    def digest(self) -> str:
        """SHA-256 of the geometry (cache key)."""
        h = hashlib.sha256()
        h.update(np.ascontiguousarray(np.round(self.vertices, 9)).tobytes())
        h.update(np.ascontiguousarray(self.faces.astype(np.int64)).tobytes())
        return h.hexdigest()


def check_mesh(mesh: SurfaceMesh) -> None:
    """Raise InputError if the mesh is open or its normals point inwards."""
    tri = mesh.triangles()
    if tri.size == 0:
        raise InputError("the mesh has no faces", mesh.source)
    if tri.max() >= len(mesh.vertices) or tri.min() < 0:
        raise InputError("a face refers to a vertex that does not exist", mesh.source)
    # merge coincident vertices so that a mesh written as a triangle soup can still be closed
    key = np.round(mesh.vertices / max(1e-12, float(np.ptp(mesh.vertices))) * 1e9).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    t = inv.reshape(-1)[tri]
    edges = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    und = np.sort(edges, axis=1)
    _, counts = np.unique(und, axis=0, return_counts=True)
    open_edges = int(np.sum(counts == 1))
    if open_edges:
        raise InputError(
            f"the mesh is not closed: {open_edges} edge(s) belong to one face only; expected a watertight hull",
            mesh.source,
        )
    if np.any(counts > 2):
        raise InputError(
            f"{int(np.sum(counts > 2))} edge(s) shared by more than two faces; expected a simple closed hull",
            mesh.source,
        )
    vol = SurfaceMesh(mesh.vertices, tri).volume()
    if vol < 0:
        raise InputError(
            f"the face normals point inwards (enclosed volume {vol:.4g} m³ < 0); "
            "expected outward normals — reverse the vertex order of every face",
            mesh.source,
        )
    if vol == 0:
        raise InputError("the mesh encloses no volume", mesh.source)


def read_mesh(path: str | os.PathLike[str]) -> SurfaceMesh:
    """Read an STL (ASCII or binary) or OBJ file (metres)."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    suffix = p.suffix.lower()
    data = p.read_bytes()
    if suffix == ".obj":
        return _read_obj(data.decode("utf-8", "replace"), src)
    if suffix == ".stl":
        if data[:5].lower() == b"solid" and b"facet" in data[:1000]:
            return _read_stl_ascii(data.decode("utf-8", "replace"), src)
        return _read_stl_binary(data, src)
    raise InputError(f"mesh format {suffix!r}: expected .stl or .obj", src)


def _soup(tris: np.ndarray, src: str) -> SurfaceMesh:
    verts, inv = np.unique(tris.reshape(-1, 3), axis=0, return_inverse=True)
    return SurfaceMesh(verts, inv.reshape(-1, 3), src)


def _read_stl_ascii(text: str, src: str) -> SurfaceMesh:
    pts = []
    for line in text.splitlines():
        w = line.split()
        if w and w[0] == "vertex":
            try:
                pts.append([float(x) for x in w[1:4]])
            except ValueError:
                raise InputError(f"bad vertex line {line.strip()!r}", src) from None
    if not pts or len(pts) % 3:
        raise InputError("no complete triangles in the STL file", src)
    return _soup(np.array(pts).reshape(-1, 3, 3), src)


def _read_stl_binary(data: bytes, src: str) -> SurfaceMesh:
    if len(data) < 84:
        raise InputError("file too short for a binary STL", src)
    (n,) = struct.unpack("<I", data[80:84])
    if len(data) < 84 + 50 * n:
        raise InputError(f"binary STL announces {n} triangles but is truncated", src)
    rec = np.frombuffer(data[84 : 84 + 50 * n], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    return _soup(rec["v"].astype(float), src)


def _read_obj(text: str, src: str) -> SurfaceMesh:
    verts, faces = [], []
    for line in text.splitlines():
        w = line.split()
        if not w:
            continue
        try:
            if w[0] == "v":
                verts.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = [int(x.split("/")[0]) for x in w[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):  # fan triangulation
                    faces.append([idx[0], idx[k], idx[k + 1]])
        except ValueError:
            raise InputError(f"bad OBJ line {line.strip()!r}", src) from None
    if not verts or not faces:
        raise InputError("no vertices or faces in the OBJ file", src)
    return SurfaceMesh(np.array(verts), np.array(faces), src)
