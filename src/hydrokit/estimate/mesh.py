"""Triangle/quad surface meshes: reading (STL ASCII/binary, OBJ) and checks for BEM.

Files are parsed by `meshio <https://github.com/nschloe/meshio>`_ (its STL and OBJ readers,
imported on first use so the command line starts fast). A mesh file is untrusted input, so
:func:`read_mesh` guards meshio on both sides: before parsing it refuses files larger than
:data:`MAX_MESH_BYTES` and binary STL headers whose triangle count does not match the file
size (meshio would otherwise allocate from the header, or fall back to reading the bytes as
text); afterwards it refuses empty meshes, non-finite or absurdly far vertices
(:data:`MAX_COORDINATE`) and faces that refer to vertices the file does not have. Any other
failure of the parser becomes one :class:`~hydrokit.errors.InputError` line naming the file.

Two meshio gaps are filled here: OBJ indices counted back from the last vertex (``f -4 -3 -2``)
are made absolute first (meshio would silently take them as 0-based indices), and an ASCII STL
that ends with blank lines is read without them (meshio's reader fails on a trailing blank
line).

Faces: triangles and quads are kept; OBJ polygons of five or more corners are split into a fan
of triangles from their first corner. A mesh with quads stores its triangles as quads that
repeat their last corner (the :class:`SurfaceMesh` convention).

A mesh for a deeply submerged body must be closed (every edge shared by exactly two faces)
and oriented with outward normals (positive enclosed volume by the divergence theorem).
"""

from __future__ import annotations

import hashlib
import io
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.core.validate import cut, cut_repr
from hydrokit.errors import InputError

MAX_MESH_BYTES = 200_000_000
"""Largest mesh file read, bytes (200 MB: 4 million binary STL triangles)."""

MAX_COORDINATE = 1e9
"""Largest vertex coordinate magnitude accepted, m (far beyond any hull; keeps volumes finite)."""

_STL_HEADER = 84  # bytes: 80-byte comment and the uint32 triangle count
_STL_RECORD = 50  # bytes per binary triangle: normal and 3 vertices (12 float32), uint16 attribute
# bytes that tell text from binary: text starts with 'solid' (after blank space) and holds no NUL
# in its first KiB
_STL_SNIFF = 1024
_STL_EXPECTED = "expected ASCII or binary STL"
_OBJ_EXPECTED = "expected Wavefront OBJ text with 'v x y z' and 'f i j k …' lines"


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

    def solid_inertia(self, mass: float) -> tuple[np.ndarray, np.ndarray]:
        """The enclosed body as a uniform solid of ``mass`` (kg): its centroid (3,), m, and its
        inertia tensor (3, 3) about the centroid, kg·m², in mesh axes.

        Exact for the polyhedron: each face triangle (a, b, c) closes a tetrahedron with the
        origin of signed volume V = a·(b × c)/6, first moment V(a + b + c)/4 and second moment
        ∫ x xᵀ dV = V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ), s = a + b + c.
        """
        v = self.vertices[self.triangles()]
        a, b, c = v[:, 0], v[:, 1], v[:, 2]
        vol = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
        s = a + b + c
        total = float(vol.sum())
        centroid = (vol[:, None] * s).sum(axis=0) / (4.0 * total)
        second = np.einsum("k,ki,kj->ij", vol, a, a) + np.einsum("k,ki,kj->ij", vol, b, b)
        second += np.einsum("k,ki,kj->ij", vol, c, c) + np.einsum("k,ki,kj->ij", vol, s, s)
        second = second / 20.0 - total * np.outer(centroid, centroid)  # about the centroid
        inertia = np.trace(second) * np.eye(3) - second
        return centroid, inertia * (mass / total)

    def digest(self) -> str:
        """SHA-256 of the geometry (the BEM cache key): vertices rounded to 1 nm (1e-9 m), so the
        round-off of a re-export does not miss the cache."""
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
    """Read an STL (ASCII or binary) or OBJ surface mesh with meshio; coordinates in metres.

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file, its format chosen by the extension: ``.stl`` (ASCII or binary) or
        ``.obj`` (any case).

    Returns
    -------
    SurfaceMesh
        Vertices (n, 3) in m; faces (m, 3) vertex indices, or (m, 4) when the file has quads
        (its triangles then repeat their last corner). OBJ polygons of five or more corners are
        split into fans of triangles.

    Raises
    ------
    InputError
        One line naming the file, what is wrong and what was expected: a missing file, an
        unknown extension, a file larger than :data:`MAX_MESH_BYTES`, a binary STL whose
        triangle count disagrees with its size, anything the parser cannot read, no vertices
        or faces, a non-finite vertex or one farther than :data:`MAX_COORDINATE`, a face that
        refers to a vertex the file does not have.
    """
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError("no such file", src)
    suffix = p.suffix.lower()
    if suffix not in (".stl", ".obj"):
        raise InputError(f"mesh format {cut_repr(suffix)}: expected .stl or .obj", src)
    kind, expected = ("STL", _STL_EXPECTED) if suffix == ".stl" else ("OBJ", _OBJ_EXPECTED)
    import meshio  # noqa: F401 -- here, not at the top: the command line must start fast

    size = 0
    try:
        size = p.stat().st_size
        if size > MAX_MESH_BYTES:
            raise InputError(
                f"the file has {size:,} bytes ({size / 1e6:.4g} MB), more than the {MAX_MESH_BYTES:,} bytes a mesh "
                "may have; expected a coarser hull mesh",
                src,
            )
        # nothing of meshio's or numpy's on stderr (e.g. an overflow warning): errors are one line
        with quiet("meshio"), np.errstate(all="ignore"):
            mesh = _read_stl(p) if kind == "STL" else _read_obj(p)
            return _surface(mesh, src, kind)
    except InputError:
        raise
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror or exc}); expected a readable mesh file", src) from exc
    except MemoryError as exc:
        raise InputError(f"not enough memory to read this {size / 1e6:.3g} MB {kind} file; {expected}", src) from exc
    except (Exception, SystemExit) as exc:  # an untrusted file: every parser failure is bad input
        raise InputError(f"not a readable {kind} ({_why(exc, kind)}); {expected}", src) from exc


def _why(exc: BaseException, kind: str) -> str:
    """What the parser said, on one line and cut to 160 characters (it may quote the file)."""
    name = type(exc).__name__
    text = " ".join(str(exc).split())
    if not text and kind == "STL" and name == "ReadError":  # meshio's ASCII reader says nothing
        text = "the facets are not each one 'facet normal' line and three 'vertex' lines"
    return cut(f"{name}: {text}" if text else name, 160)


def _read_stl(p: Path) -> Any:
    """meshio's STL reader, after the checks it lacks: a binary header must agree with the file
    size (meshio would allocate what it announces, or read the bytes as text), and text must not
    pass meshio's own binary test by accident (see :func:`_read_stl_ascii`)."""
    import meshio

    with p.open("rb") as f:
        head = f.read(_STL_SNIFF)
    size = p.stat().st_size
    if size >= _STL_HEADER and _STL_HEADER + _STL_RECORD * _stl_count(head) == size:
        return meshio.stl.read(str(p))  # binary: meshio reads exactly the announced triangles
    if not (head.lstrip()[:5].lower() == b"solid" and b"\0" not in head):
        if size < _STL_HEADER:
            raise _stl_error(f"{size} bytes: shorter than a binary header and not text that starts with 'solid'", p)
        count, have = _stl_count(head), (size - _STL_HEADER) // _STL_RECORD
        if _STL_HEADER + _STL_RECORD * count > size:
            raise _stl_error(
                f"the binary header announces {_triangles(count)} but is truncated: its {size} bytes hold {have}", p
            )
        extra = size - _STL_HEADER - _STL_RECORD * count
        raise _stl_error(f"the binary header announces {_triangles(count)} but {extra} bytes follow them", p)
    data = _bounded_bytes(p)
    if not _BLANK_LINE.search(data):
        return _read_stl_ascii(p, data)
    # meshio's ASCII reader fails on a blank line after the last vertex: read a copy without them
    data = _BLANK_LINES_INSIDE.sub(b"", data).rstrip() + b"\n"
    with tempfile.TemporaryDirectory(prefix="hydrokit-mesh-") as tmp:
        copy = Path(tmp) / "mesh.stl"
        copy.write_bytes(data)
        return _read_stl_ascii(copy, data, p)


_BLANK_LINE = re.compile(rb"\n[ \t\r\x0b\x0c]*\n|\n[ \t\r\x0b\x0c]+\Z")
_BLANK_LINES_INSIDE = re.compile(rb"\n[ \t\r\x0b\x0c]*(?=\n)")


def _bounded_bytes(p: Path) -> bytes:
    """The file's bytes, refused if it has grown past :data:`MAX_MESH_BYTES` since its size was checked."""
    with p.open("rb") as f:
        data = f.read(MAX_MESH_BYTES + 1)
    if len(data) > MAX_MESH_BYTES:
        raise InputError(f"the file has grown past {MAX_MESH_BYTES / 1e6:.4g} MB while being read", str(p))
    return data


def _stl_count(head: bytes) -> int:
    """The triangle count of a binary STL header (bytes 80–83, little-endian uint32)."""
    return int.from_bytes(head[80:_STL_HEADER], "little")


def _triangles(count: int) -> str:
    return f"{count} triangle" + ("" if count == 1 else "s")


def _stl_error(why: str, p: Path) -> InputError:
    return InputError(f"not a readable STL ({why}); {_STL_EXPECTED}", str(p))


def _read_stl_ascii(path: Path, data: bytes, named: Path | None = None) -> Any:
    """meshio's reader on ASCII STL ``data`` stored at ``path`` (``named`` for messages)."""
    import meshio

    size = len(data)
    if 80 <= size < _STL_HEADER:  # meshio reads a count from any file of 80 bytes or more
        raise _stl_error(f"{size} bytes of text: too short for a facet", named or path)
    # meshio takes the file for binary when 84 + 50·count equals its size in 32-bit arithmetic
    # (wrapping): text whose bytes 80–83 happen to do so would be read as billions of triangles
    if size >= _STL_HEADER and (_STL_HEADER + _STL_RECORD * _stl_count(data)) % 2**32 == size:
        raise _stl_error(
            f"text that starts with 'solid', but its bytes 80–83 read as a binary count of "
            f"{_stl_count(data)} triangles that matches the size modulo 2³²",
            named or path,
        )
    return meshio.stl.read(str(path))


_RELATIVE_FACE = re.compile(r"(?m)^[ \t]*f[ \t][^\n]*?-")
# texture coordinates, normals, parameter-space vertices: a hull needs none, and meshio refuses
# an OBJ whose vt or vn count differs from its vertex count (as Blender exports write them)
_VERTEX_DATA = re.compile(r"(?m)^[ \t]*v[tnp][ \t][^\n]*$")


def _read_obj(p: Path) -> Any:
    """meshio's OBJ reader on the file's text (UTF-8; undecodable bytes replaced)."""
    import meshio

    text = _VERTEX_DATA.sub("", _bounded_bytes(p).decode("utf-8", "replace"))
    if _RELATIVE_FACE.search(text):
        text = _absolute_obj_indices(text)
    return meshio.obj.read(io.StringIO(text, newline=None))


def _absolute_obj_indices(text: str) -> str:
    """OBJ face indices counted back (``-1``: the last vertex so far) made absolute (1-based)."""
    lines = []
    seen = 0  # vertices so far
    for line in text.splitlines():
        words = line.split()
        if words and words[0] == "v":
            seen += 1
        elif words and words[0] == "f":
            line = " ".join(["f", *(_absolute_index(w, seen) for w in words[1:])])
        lines.append(line)
    return "\n".join(lines)


def _absolute_index(word: str, seen: int) -> str:
    """``-k/…`` → ``(seen + 1 - k)/…``; other words unchanged."""
    index, slash, rest = word.partition("/")
    if index.startswith("-") and index[1:].isascii() and index[1:].isdigit():
        index = str(seen + 1 + int(index))
    return index + slash + rest


def _surface(mesh: Any, src: str, kind: str) -> SurfaceMesh:
    """A checked :class:`SurfaceMesh` from a meshio mesh (points in m, 0-based cells)."""
    pts = np.asarray(mesh.points, dtype=float)
    if pts.ndim != 2 or len(pts) == 0:
        raise InputError(f"no vertices in the {kind} file; expected a closed hull mesh", src)
    if pts.shape[1] < 3:
        raise InputError(f"vertices with {pts.shape[1]} coordinates; expected x y z in metres", src)
    pts = np.ascontiguousarray(pts[:, :3])  # an OBJ 'v x y z w' (or with colours) keeps x y z
    finite = np.isfinite(pts).all(axis=1)
    if not finite.all():
        first = pts[int(np.argmin(finite))]
        raise InputError(
            f"{int(np.sum(~finite))} vertex(es) not finite, e.g. ({_xyz(first)}); expected finite x y z in metres", src
        )
    far = float(np.abs(pts).max())
    if far > MAX_COORDINATE:
        raise InputError(
            f"a vertex coordinate is {far:.3g} m, beyond ±{MAX_COORDINATE:.0e} m; expected a hull in metres", src
        )
    n = len(pts)
    parts = [_corners(np.asarray(block.data), n, src) for block in mesh.cells]
    parts = [f for f in parts if len(f)]
    if not parts:
        raise InputError(f"no faces in the {kind} file; expected a closed hull mesh", src)
    if any(f.shape[1] == 4 for f in parts):  # quads kept: triangles repeat their last corner
        parts = [f if f.shape[1] == 4 else np.column_stack([f, f[:, 2]]) for f in parts]
    return SurfaceMesh(pts, np.concatenate(parts), src)


def _corners(data: np.ndarray, n: int, src: str) -> np.ndarray:
    """One block of faces as (k, 3) or (k, 4) indices into ``n`` vertices; polygons fanned."""
    width = data.shape[1] if data.ndim == 2 else 1  # a flat block: one index per cell (points)
    if width < 3:
        raise InputError(f"a face with {width} corner(s); expected 3 or more", src)
    try:
        faces = data.astype(np.int64)
    except (OverflowError, TypeError, ValueError):
        raise InputError(f"a face index is not a vertex number; expected indices 1 to {n}", src) from None
    if faces.size:
        lo, hi = int(faces.min()), int(faces.max())
        if lo < 0 or hi >= n:
            where = f"vertex {hi + 1} but the file has {n}" if lo >= 0 else "vertex 0 or counts back past the first"
            raise InputError(f"a face refers to {where}; expected indices 1 to {n} (or -1 back to the first)", src)
    if width > 4:  # a polygon: a fan of triangles from its first corner
        faces = np.concatenate([faces[:, [0, j, j + 1]] for j in range(1, width - 1)])
    return faces


def _xyz(row: np.ndarray) -> str:
    return ", ".join(f"{float(v):.6g}" for v in row)
