"""The axisymmetric wedge mesh (hydrokit.cfd.wedge): blockMesh + checkMesh on two bodies, and the
pure-Python parts (first-cell height, refused profiles, the refinement triplet's cell counts).

The OpenFOAM tests build each level-1 mesh once (a module fixture, ~2 s per body) and compare it
with independent numbers: the cell count the dictionary asks for, the closed-form surface of a
prolate spheroid, and the first-cell height asked for.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from hydrokit.cfd.wedge import PATCHES, blockmesh_dict, cell_count, first_cell_height, refinement_ratio
from hydrokit.errors import InputError

foamlib = pytest.importorskip("foamlib")

needs_openfoam = pytest.mark.skipif(
    shutil.which("blockMesh") is None, reason="OpenFOAM is not installed (apt-get install openfoam)"
)
WEDGE_DEG = 5.0
RE_L = 1e6


# --- bodies ---------------------------------------------------------------------------------


def spheroid(length: float = 1.0, fineness: float = 6.0, n: int = 201) -> tuple[np.ndarray, np.ndarray]:
    """A prolate spheroid, length/diameter = fineness, sampled evenly in the parametric angle."""
    t = np.linspace(0.0, math.pi, n)
    return 0.5 * length * (1.0 - np.cos(t)), 0.5 * length / fineness * np.sin(t)


def myring(
    a: float = 0.2, b: float = 0.6, c: float = 0.5, d: float = 0.2, n: float = 2.0, theta_deg: float = 25.0
) -> tuple[np.ndarray, np.ndarray]:
    """Myring (1976) hull: nose a, parallel middle b, tail c, diameter d, nose index n, tail angle θ.

    Nose ``r = d/2 (1 − ((x − a)/a)²)^(1/n)``; tail (ξ = x − a − b)
    ``r = d/2 − (3d/(2c²) − tanθ/c) ξ² + (d/c³ − tanθ/c²) ξ³``, which closes at ξ = c with slope −tanθ.
    """
    tan_t = math.tan(math.radians(theta_deg))
    t = np.linspace(0.0, 0.5 * math.pi, 60)
    x_nose = a * (1.0 - np.cos(t))  # clustered at the blunt nose
    r_nose = 0.5 * d * np.clip(1.0 - ((x_nose - a) / a) ** 2, 0.0, None) ** (1.0 / n)
    x_mid = np.linspace(a, a + b, 20)[1:]
    xi = np.linspace(0.0, c, 60)[1:]
    r_tail = 0.5 * d - (3 * d / (2 * c**2) - tan_t / c) * xi**2 + (d / c**3 - tan_t / c**2) * xi**3
    x = np.concatenate([x_nose, x_mid, a + b + xi])
    r = np.concatenate([r_nose, np.full_like(x_mid, 0.5 * d), r_tail])
    r[-1] = 0.0
    return x, r


def sphere(diameter: float = 1.0, n: int = 61) -> tuple[np.ndarray, np.ndarray]:
    """A sphere, sampled evenly in the polar angle: both ends blunt (the C grid wraps both)."""
    t = np.linspace(0.0, math.pi, n)
    r = 0.5 * diameter * np.sin(t)
    r[[0, -1]] = 0.0
    return 0.5 * diameter * (1.0 - np.cos(t)), r


def spheroid_area(a: float, b: float) -> float:
    """Surface of a prolate spheroid, semi-axes a > b: 2πb² (1 + a/(b e) arcsin e), e² = 1 − b²/a²."""
    e = math.sqrt(1.0 - (b / a) ** 2)
    return 2.0 * math.pi * b**2 * (1.0 + a / (b * e) * math.asin(e))


# --- running OpenFOAM and reading its mesh ----------------------------------------------------


@dataclass
class Built:
    case: Path
    asked: int
    check: str  # checkMesh's output
    first_cell: float
    x: np.ndarray
    r: np.ndarray


def _write(path: Path, entries: dict) -> None:
    f = foamlib.FoamFile(path)
    for key, value in entries.items():
        f[key] = value


def build(
    case: Path, x: np.ndarray, r: np.ndarray, level: int = 1, hold_first_cell: bool = False, **domain: float
) -> Built:
    (case / "system").mkdir(parents=True)
    # writePrecision 15: at the default 6 digits the wedge sides stop being planar (checkMesh warns)
    _write(
        case / "system" / "controlDict",
        {"application": "blockMesh", "startFrom": "startTime", "startTime": 0, "stopAt": "endTime", "endTime": 1,
         "deltaT": 1, "writeControl": "timeStep", "writeInterval": 1, "writeFormat": "ascii", "writePrecision": 15},
    )  # fmt: skip
    schemes = ("ddtSchemes", "gradSchemes", "divSchemes", "laplacianSchemes", "interpolationSchemes", "snGradSchemes")
    _write(case / "system" / "fvSchemes", dict.fromkeys(schemes, {}))
    _write(case / "system" / "fvSolution", {"solvers": {}})
    h = first_cell_height(float(x[-1] - x[0]), RE_L, 1.0)
    mesh = blockmesh_dict(
        x, r, first_cell=h, level=level, wedge_deg=WEDGE_DEG, hold_first_cell=hold_first_cell, **domain
    )
    _write(case / "system" / "blockMeshDict", mesh)
    env = dict(os.environ, WM_PROJECT_DIR="/usr/share/openfoam")
    outputs = []
    for program in ("blockMesh", "checkMesh"):
        run = subprocess.run([program, "-case", str(case)], capture_output=True, text=True, env=env, timeout=120)
        assert run.returncode == 0, f"{program} failed:\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}"
        outputs.append(run.stdout)
    return Built(case, cell_count(mesh), outputs[1], h if hold_first_cell else h / refinement_ratio(level), x, r)


def read_mesh(case: Path) -> tuple[np.ndarray, list[list[int]], np.ndarray, np.ndarray, dict]:
    poly = case / "constant" / "polyMesh"
    points = np.asarray(foamlib.FoamFile(poly / "points")[None], dtype=float)
    faces = [list(f) for f in foamlib.FoamFile(poly / "faces")[None]]
    owner = np.asarray(foamlib.FoamFile(poly / "owner")[None], dtype=int)
    neighbour = np.asarray(foamlib.FoamFile(poly / "neighbour")[None], dtype=int)
    boundary = dict(foamlib.FoamFile(poly / "boundary")[None])
    return points, faces, owner, neighbour, boundary


def face_area_vector(points: np.ndarray, face: list[int]) -> np.ndarray:
    p = points[face]
    if len(face) == 3:
        return 0.5 * np.cross(p[1] - p[0], p[2] - p[0])
    return 0.5 * np.cross(p[2] - p[0], p[3] - p[1])  # a planar quadrilateral


def first_cell_at_mid_body(built: Built) -> float:
    """Wall-normal height, m, of the body cell nearest mid-length, measured on the built mesh."""
    points, faces, owner, neighbour, boundary = read_mesh(built.case)
    body = boundary["body"]
    start, n = body["startFace"], body["nFaces"]
    centres = np.array([points[faces[i]].mean(axis=0) for i in range(start, start + n)])
    mid = 0.5 * (built.x[0] + built.x[-1])
    f_body = start + int(np.argmin(abs(centres[:, 0] - mid)))
    cell = owner[f_body]
    # the cell's face opposite the wall shares no point with the wall face
    n_internal = len(neighbour)
    cell_faces = [f for f in np.flatnonzero(owner == cell)] + [f for f in np.flatnonzero(neighbour == cell)]
    wall = set(faces[f_body])
    opposite = [f for f in cell_faces if f < n_internal and not wall & set(faces[f])]
    assert len(opposite) == 1
    normal = face_area_vector(points, faces[f_body])
    normal /= np.linalg.norm(normal)
    return abs(float((points[faces[opposite[0]]].mean(axis=0) - points[faces[f_body]].mean(axis=0)) @ normal))


def checkmesh_value(text: str, label: str) -> float:
    line = next(ln for ln in text.splitlines() if label in ln)
    return float(line.split(label)[1].split()[0])


@pytest.fixture(scope="module")
def built_spheroid(tmp_path_factory: pytest.TempPathFactory) -> Built:
    if shutil.which("blockMesh") is None:
        pytest.skip("OpenFOAM is not installed (apt-get install openfoam)")
    x, r = spheroid()
    return build(tmp_path_factory.mktemp("spheroid"), x, r)


@pytest.fixture(scope="module")
def built_myring(tmp_path_factory: pytest.TempPathFactory) -> Built:
    if shutil.which("blockMesh") is None:
        pytest.skip("OpenFOAM is not installed (apt-get install openfoam)")
    x, r = myring()
    return build(tmp_path_factory.mktemp("myring"), x, r)


@pytest.fixture(params=["spheroid", "myring"])
def built(request: pytest.FixtureRequest) -> Built:
    return request.getfixturevalue(f"built_{request.param}")


# --- OpenFOAM tests ---------------------------------------------------------------------------


@pytest.mark.cfd
@needs_openfoam
def test_checkmesh_passes_with_the_asked_cells(built: Built):
    assert "Mesh OK." in built.check
    assert int(checkmesh_value(built.check, "cells:")) == built.asked
    # a refined level asks for about 2× the cells (√2 in both directions); 10–25 k on level 1
    assert 8_000 <= built.asked <= 25_000
    # no hidden default patch (the collapsed axis faces are listed and removed)
    assert "defaultFaces" not in built.check
    assert checkmesh_value(built.check, "non-orthogonality Max:") < 50.0
    assert checkmesh_value(built.check, "Max skewness =") < 4.0


@pytest.mark.cfd
@needs_openfoam
def test_patches_are_the_four_the_case_files_use(built: Built):
    *_, boundary = read_mesh(built.case)
    assert {name: entry["type"] for name, entry in boundary.items()} == PATCHES
    assert all(boundary[name]["nFaces"] > 0 for name in PATCHES)


@pytest.mark.cfd
@needs_openfoam
def test_spheroid_body_area_is_the_wedge_share_of_the_closed_form(built_spheroid: Built):
    points, faces, _, _, boundary = read_mesh(built_spheroid.case)
    body = boundary["body"]
    start, n = body["startFace"], body["nFaces"]
    area = sum(np.linalg.norm(face_area_vector(points, faces[i])) for i in range(start, start + n))
    x, r = built_spheroid.x, built_spheroid.r
    expected = math.radians(WEDGE_DEG) / (2.0 * math.pi) * spheroid_area(0.5 * (x[-1] - x[0]), r.max())
    # the faces are flat chords of the 201-point profile and of the 5° arc (sin α/α = 0.9997):
    # well inside 1 %
    assert area == pytest.approx(expected, rel=0.01)


@pytest.mark.cfd
@needs_openfoam
def test_first_cell_height_at_mid_body(built: Built):
    assert first_cell_at_mid_body(built) == pytest.approx(built.first_cell, rel=0.05)


@pytest.mark.cfd
@needs_openfoam
def test_level_two_mesh_builds_with_twice_the_cells(tmp_path: Path):
    x, r = spheroid()
    level2 = build(tmp_path / "level2", x, r, level=2)
    assert "Mesh OK." in level2.check
    assert int(checkmesh_value(level2.check, "cells:")) == level2.asked
    # refined with the rest: the first cell is the level-1 height ÷ √2
    assert first_cell_at_mid_body(level2) == pytest.approx(first_cell_height(1.0, RE_L, 1.0) / math.sqrt(2.0), rel=0.05)


@pytest.mark.cfd
@needs_openfoam
def test_a_held_first_cell_keeps_its_height_on_level_two(tmp_path: Path):
    # a wall-function grid study refines along and across the body but keeps the y⁺ of the wall cell
    x, r = spheroid()
    held = build(tmp_path / "held", x, r, level=2, hold_first_cell=True)
    assert "Mesh OK." in held.check
    assert first_cell_at_mid_body(held) == pytest.approx(first_cell_height(1.0, RE_L, 1.0), rel=0.05)


def capsule() -> tuple[np.ndarray, np.ndarray]:
    """A hemisphere-capped cylinder, L = 1 m, D = 0.2 m: blunt at both ends (C wrap at both)."""
    t = np.linspace(0.0, 0.5 * math.pi, 40)
    x_mid = np.linspace(0.1, 0.9, 30)[1:-1]
    x = np.concatenate([0.1 * (1.0 - np.cos(t)), x_mid, 0.9 + 0.1 * np.sin(t)])
    r = np.concatenate([0.1 * np.sin(t), np.full_like(x_mid, 0.1), 0.1 * np.cos(t)])
    r[-1] = 0.0
    return x, r


def cone_nosed() -> tuple[np.ndarray, np.ndarray]:
    """A 20° cone nose, a cylinder and a 30° cone tail: pointed at both ends (a block on the axis at each)."""
    x = np.array([0.0, 0.05, 0.1, 0.2, 0.25, 0.5, 0.75, 0.8, 0.9, 1.0])
    r = np.minimum.reduce(
        [x * math.tan(math.radians(20.0)), np.full_like(x, 0.08), (1.0 - x) * math.tan(math.radians(30.0))]
    )
    return x, r


@pytest.mark.cfd
@needs_openfoam
@pytest.mark.parametrize("body", [capsule, cone_nosed])
def test_blunt_and_pointed_ends_mesh_cleanly(body, tmp_path: Path):
    built = build(tmp_path / body.__name__, *body())
    assert "Mesh OK." in built.check
    assert int(checkmesh_value(built.check, "cells:")) == built.asked
    # without the end blocks a 20° cone nose left a 160° corner and 67° non-orthogonality
    assert checkmesh_value(built.check, "non-orthogonality Max:") < 45.0


@pytest.mark.cfd
@needs_openfoam
@pytest.mark.parametrize("body", [sphere, myring])
@pytest.mark.parametrize(("upstream", "downstream", "radial"), [(10.0, 20.0, 15.0), (2.0, 4.0, 4.0)])
def test_large_domains_mesh_cleanly(body, upstream: float, downstream: float, radial: float, tmp_path: Path):
    # the outward Bézier edges once reached 0.3 × their chord along the wall normal, so on a
    # domain large against the body they fanned out and crossed (a sphere at 10, 20, 15 body
    # lengths had inverted cells, non-orthogonality 144° and skewness 82)
    domain = {"upstream": upstream, "downstream": downstream, "radial": radial}
    built = build(tmp_path / body.__name__, *body(), **domain)
    assert "Mesh OK." in built.check
    assert int(checkmesh_value(built.check, "cells:")) == built.asked
    assert checkmesh_value(built.check, "non-orthogonality Max:") < 70.0
    assert checkmesh_value(built.check, "Max skewness =") < 4.0


# --- pure Python --------------------------------------------------------------------------------


def test_first_cell_height_by_hand():
    # C_f = 0.026 / (1e6)^(1/7) = 0.026 / 7.19686 = 3.61269e-3; √(C_f/2) = 4.25010e-2;
    # Δy = y⁺ L / (Re √(C_f/2)) = 1 / (1e6 · 4.25010e-2) = 2.35289e-5 m
    assert first_cell_height(1.0, 1e6, 1.0) == pytest.approx(2.35289e-5, rel=1e-5)
    # linear in y⁺ and in L at a fixed Re
    assert first_cell_height(2.0, 1e6, 30.0) == pytest.approx(60.0 * 2.35289e-5, rel=1e-5)


@pytest.mark.parametrize(
    ("length", "reynolds", "y_plus", "match"),
    [(0.0, 1e6, 1.0, "length = 0"), (1.0, -1e6, 1.0, "reynolds = -1000000"), (1.0, 1e6, math.nan, "y_plus = nan")],
)
def test_first_cell_height_refuses_non_positive(length, reynolds, y_plus, match):
    with pytest.raises(InputError, match=match):
        first_cell_height(length, reynolds, y_plus)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda x, r: (x, np.where(np.arange(len(r)) == 3, -0.01, r)), r"r\[3\] = -0.01 m, expected r ≥ 0"),
        (lambda x, r: (x, r + 0.05), r"r\[0\] = 0.05 m at the nose, expected 0"),
        (lambda x, r: (x, np.concatenate([r[:-1], [0.02]])), r"r\[200\] = 0.02 m at the tail, expected 0"),
        (
            lambda x, r: (np.where(np.arange(len(x)) == 2, x[1], x), r),
            r"x\[2\] = .* after x\[1\] = .*strictly increasing",
        ),
        (
            lambda x, r: (np.array([0.0, 0.3, 0.6, 1.0]), np.array([0.0, 0.1, 0.1, 0.0])),
            r"4 points, expected at least 5",
        ),
        (lambda x, r: (x, np.where(np.arange(len(r)) == 100, 0.0, r)), r"r\[100\] = 0 m between nose and tail"),
        (lambda x, r: (x[:, None], r), r"1-D arrays of equal length"),
    ],
)
def test_refused_profiles(change, match):
    x, r = change(*spheroid())
    with pytest.raises(ValueError, match=match):
        blockmesh_dict(x, r, first_cell=1e-4)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"first_cell": 0.0}, "first_cell = 0.0"),
        ({"first_cell": 0.05}, "first_cell = 0.05 m"),
        ({"first_cell": 1e-4, "level": 0}, "level = 0"),
        ({"first_cell": 1e-4, "level": 1.5}, "level = 1.5"),
        ({"first_cell": 1e-4, "wedge_deg": 90.0}, "wedge_deg = 90.0"),
        ({"first_cell": 1e-4, "radial": 0.1}, "radial = 0.1"),
        ({"first_cell": 1e-4, "upstream": -1.0}, "upstream = -1.0"),
        # domains too flat or too tall at an end for the C wrap (checkMesh: skewness > 4)
        ({"first_cell": 1e-4, "upstream": 1.5, "radial": 6.0}, r"radial = 6.0 with upstream = 1.5.*2.5 × upstream"),
        (
            {"first_cell": 1e-4, "upstream": 10.0, "downstream": 3.0, "radial": 15.0},
            r"radial = 15.0 with downstream = 3.0",
        ),
        ({"first_cell": 1e-4, "downstream": 12.0, "radial": 1.5}, r"downstream = 12.0 with radial = 1.5.*4 × radial"),
        ({"first_cell": 1e-4, "upstream": 10.0, "radial": 1.5}, r"upstream = 10.0 with radial = 1.5.*blunt nose"),
    ],
)
def test_refused_options(options, match):
    with pytest.raises(InputError, match=match):
        blockmesh_dict(*spheroid(), **options)


def test_a_pointed_tail_takes_a_long_wake_on_a_narrow_domain():
    # the 4 × radial limit is the quarter ellipse's: a Myring's pointed tail ends in a flat outlet
    mesh = blockmesh_dict(*myring(), first_cell=1e-4, upstream=1.5, downstream=20.0, radial=1.5)
    assert cell_count(mesh) > 0


@pytest.mark.parametrize("body", [spheroid, myring])
def test_levels_form_a_root_two_triplet(body):
    x, r = body()
    h = first_cell_height(float(x[-1] - x[0]), RE_L, 1.0)
    counts = [cell_count(blockmesh_dict(x, r, first_cell=h, level=level)) for level in (1, 2, 3)]
    # √2 per direction in 2-D (rounded per block): ×2 and ×4 within 2 %
    assert counts[1] / counts[0] == pytest.approx(2.0, rel=0.02)
    assert counts[2] / counts[0] == pytest.approx(4.0, rel=0.02)


def test_a_held_first_cell_keeps_the_cell_counts_of_the_level():
    x, r = spheroid()
    h = first_cell_height(1.0, RE_L, 1.0)
    for level in (1, 2, 3):
        plain = blockmesh_dict(x, r, first_cell=h, level=level)
        held = blockmesh_dict(x, r, first_cell=h, level=level, hold_first_cell=True)
        assert cell_count(held) == cell_count(plain)
        # level 1 is the same mesh; finer levels differ only in their wall-normal grading
        assert (held == plain) == (level == 1)


def test_dictionary_is_plain_and_wedge_sides_planar():
    mesh = blockmesh_dict(*myring(), first_cell=3e-5, wedge_deg=WEDGE_DEG)
    assert set(mesh) == {"convertToMeters", "vertices", "blocks", "edges", "boundary", "mergePatchPairs"}
    v = np.array(mesh["vertices"])
    tan_half = math.tan(math.radians(WEDGE_DEG / 2.0))
    # every vertex lies on the axis or on one of the two wedge planes z = ±y tan(α/2)
    assert np.allclose(abs(v[:, 2]), v[:, 1] * tan_half, rtol=1e-12, atol=1e-15)
    assert all(isinstance(item, (str, int, float, list)) for item in mesh["blocks"] + mesh["edges"])
    assert [name for name, _ in mesh["boundary"]] == list(PATCHES)
