"""The 3-D mesh: a background box (blockMesh) cut and refined around the body (snappyHexMesh).

The box spans ``upstream`` body lengths ahead of the body's bounding box, ``downstream``
behind it and ``lateral`` to each side, above and below; its six faces form the patch
``farfield``. The background cell is L / (base_cells · √2^(grid−1)) — grid levels 1, 2, 3 are
a refinement triplet with a constant ratio √2 — and snappyHexMesh refines to
``surface_level`` more halvings at the body, ``surface_level − 1`` in a box around the body
and ``surface_level − 2`` in the near wake, with ``layers`` prism layers on the body; a slender
body gets more levels, so its diameter is resolved like a sphere's (:func:`surface_level`), and
``end_level`` more at its fore and aft ends (:func:`end_triangles`), where the stagnation
pressure and the pressure recovery decide the pressure drag.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.cfd.case import Case

#: point of the far field kept by snappyHexMesh, nudged off cell faces (fractions of the box)
_INSIDE = np.array([0.137, 0.5213, 0.5371])


def surface_names(case: Case) -> list[str]:
    """STL and patch names of the body's surfaces: ``body``, or ``body_0`` … for several parts."""
    n = len(case.body.surfaces())
    return ["body"] if n == 1 else [f"body_{i}" for i in range(n)]


def smallest_extent(case: Case) -> float:
    """The body's smallest bounding-box extent, m (a slender hull's diameter)."""
    lo, hi = case.body.bounds()
    return float(min(hi - lo))


def surface_level(case: Case) -> int:
    """snappyHexMesh's level at the body: ``surface_level`` halvings of the background cell, plus
    one per halving of the body length needed to reach its smallest extent (round(log2(L/d))),
    so a slender hull gets as many cells across its diameter as a sphere across its own (a 7:1
    Myring hull: 3 more levels). The near box (¼ d around the body) is one level coarser, the
    wake box (1.5 L along the flow, ±0.4 d) two."""
    extra = max(0, round(math.log2(case.body.length / max(smallest_extent(case), 1e-300))))
    return case.settings.surface_level + extra


def capture_bands(h: float, level: int) -> list[list[float]]:
    """snappyHexMesh distance bands around the body that find it however thin it is: level k
    within one level-(k−1) cell, 2·h/2^k, of the surface (h: background cell size, m).

    snappyHexMesh sees a surface only where it cuts a line between neighbouring cell centres;
    a body thinner than the background cell (a 0.19 m Myring hull in 0.69 m cells) can lie
    between those lines once they are refined, and the mesher then drops it whole (all loads 0).
    A distance band is measured from each cell centre to the nearest surface point, which is
    at most half a cell diagonal (0.87 cell) away from any cell the body touches, so every
    cell the body touches is refined level by level down to ``level``.
    """
    return [[2.0 * h / 2.0**k, k] for k in range(level, 0, -1)]


#: growth ratio of the prism layers laid from a target y⁺
LAYER_GROWTH = 1.2
#: the prism layers laid from a target y⁺ are at most this many surface cells thick together
LAYER_STACK_CELLS = 2.0


def boundary_layer_thickness(length: float, reynolds: float) -> float:
    """Turbulent flat-plate boundary-layer thickness at x = L, δ = 0.37 L Re_L^(−1/5), m
    (Schlichting's one-seventh power law; White, *Fluid Mechanics*, eq. 7.41)."""
    return 0.37 * length * reynolds ** (-0.2)


def layer_plan(case: Case) -> tuple[int, float | None]:
    """(prism layers, first-layer height in m or None for sizes relative to the surface cells).

    Without a target y⁺ (``settings.y_plus`` 0): ``settings.layers`` relative layers. With one:
    the first layer from flat-plate friction (:func:`hydrokit.cfd.wedge.first_cell_height`) and
    as many layers, growing by :data:`LAYER_GROWTH`, as span the turbulent boundary layer at the
    tail (:func:`boundary_layer_thickness`) — at least ``settings.layers``, at most 20, and no
    more than fit, all together, in :data:`LAYER_STACK_CELLS` surface cells.

    A wall function's friction needs the boundary layer carried by the layers: on the 3-D Myring
    at Re_L 1e6, y⁺ 50, surface level 4 (5.4 mm cells; the mid-body layer ≈ 10 mm thick) one,
    two and four layers gave 0.706, 0.803 and 0.835 N of friction against the structured
    wedge's 0.837 N — beyond the stack the cubes are too coarse for the profile. A stack much
    thicker than the cells pushes into the castellated cells until snappyHexMesh gives up where
    the surface turns: nine layers (34 mm in 11 mm cells) stayed off the aft 13 % of the hull,
    whose y⁺ rose to 271; seven (21 mm, two cells) cover 87 % with y⁺ ≤ 197 and friction within
    1.2 % of the wedge's.
    """
    s = case.settings
    if s.y_plus <= 0:
        return s.layers, None
    from hydrokit.cfd.wedge import first_cell_height

    L, re = case.body.length, case.reynolds
    first = first_cell_height(L, re, s.y_plus)
    g = LAYER_GROWTH
    span = math.ceil(math.log(1.0 + (g - 1.0) * boundary_layer_thickness(L, re) / first) / math.log(g))
    stack = LAYER_STACK_CELLS * cell_size(case) / 2.0 ** surface_level(case)
    # n layers are first·(gⁿ − 1)/(g − 1) thick together
    fit = math.floor(math.log(1.0 + (g - 1.0) * stack / first) / math.log(g) + 1e-9)
    return max(1, min(20, fit, max(s.layers, span))), first


#: the body's fore and aft ends, refined ``end_level`` more: this fraction of its length each
END_FRACTION = 0.1


def end_triangles(case: Case) -> np.ndarray:
    """The body's triangles (k, 3, 3), m, whose centroids lie in its fore or aft
    :data:`END_FRACTION` of the length along x (all parts together; empty when no centroid does).

    Pressure drag of a streamlined body is the small difference between the stagnation push on
    the nose and the recovery on the tail; a faceted, snapped surface gets both slightly wrong.
    On the 3-D Myring at Re_L 1e6 (surface level 3), one more level on these ends cut the excess
    over the axisymmetric wedge from +8.5 % to +5.0 % for 34 % more cells, where a level more
    over the whole body costs 4×.
    """
    tri = np.concatenate(case.body.surfaces())
    lo, hi = case.body.bounds()
    x = tri[:, :, 0].mean(axis=1)
    band = END_FRACTION * (hi[0] - lo[0])
    return tri[(x <= lo[0] + band) | (x >= hi[0] - band)]


def cell_size(case: Case) -> float:
    """Background cell size, m."""
    s = case.settings
    return case.body.length / (s.base_cells * math.sqrt(2.0) ** (s.grid - 1))


def domain(case: Case) -> tuple[np.ndarray, np.ndarray]:
    """(min, max) corners of the computational box, m, rounded out to whole background cells."""
    s, L = case.settings, case.body.length
    lo, hi = case.body.bounds()
    lo = lo - L * np.array([s.upstream, s.lateral, s.lateral])
    hi = hi + L * np.array([s.downstream, s.lateral, s.lateral])
    # wake direction: a drifting body leaves its wake to the side, so the far side is widened
    h = cell_size(case)
    n = np.ceil((hi - lo) / h)
    centre = (hi + lo) / 2
    return centre - n * h / 2, centre + n * h / 2


def mesh_dicts(case: Case) -> dict[str, dict[str, Any]]:
    """``system/`` dictionaries of the 3-D mesh: blockMeshDict, surfaceFeatureExtractDict, snappyHexMeshDict."""
    L = case.body.length
    lo, hi = domain(case)
    h = cell_size(case)
    n = [int(round(x)) for x in (hi - lo) / h]
    corners = [
        [lo[0], lo[1], lo[2]],
        [hi[0], lo[1], lo[2]],
        [hi[0], hi[1], lo[2]],
        [lo[0], hi[1], lo[2]],
        [lo[0], lo[1], hi[2]],
        [hi[0], lo[1], hi[2]],
        [hi[0], hi[1], hi[2]],
        [lo[0], hi[1], hi[2]],
    ]
    block = {
        "convertToMeters": 1,
        "vertices": [[float(c) for c in v] for v in corners],
        "blocks": ["hex", list(range(8)), n, "simpleGrading", [1, 1, 1]],
        "edges": [],
        "boundary": [
            (
                "farfield",
                {
                    "type": "patch",
                    "faces": [[0, 4, 7, 3], [1, 2, 6, 5], [0, 1, 5, 4], [3, 7, 6, 2], [0, 3, 2, 1], [4, 5, 6, 7]],
                },
            )
        ],
        "mergePatchPairs": [],
    }
    names = surface_names(case)
    features = {
        f"{n}.stl": {
            "extractionMethod": "extractFromSurface",
            "extractFromSurfaceCoeffs": {"includedAngle": 150},
            "subsetFeatures": {"nonManifoldEdges": False, "openEdges": True},
            "writeObj": False,
        }
        for n in names
    }
    blo, bhi = case.body.bounds()
    d = smallest_extent(case)
    near_lo, near_hi = blo - 0.25 * d, bhi + 0.25 * d
    # the near wake follows the flow: extend the box along the far-field velocity
    direction = -case.flow.velocity() / case.flow.speed
    wake_end = (blo + bhi) / 2 + direction * 1.5 * L
    wake_lo = np.minimum(near_lo, wake_end - 0.4 * d)
    wake_hi = np.maximum(near_hi, wake_end + 0.4 * d)
    lvl = surface_level(case)
    ends = case.settings.end_level > 0 and len(end_triangles(case)) > 0
    end_level = lvl + case.settings.end_level
    n_layers, first = layer_plan(case)
    layer_sizes: dict[str, Any] = {"layers": {'"body.*"': {"nSurfaceLayers": n_layers}}}
    if first is None:  # relative to the surface cells: the last layer half a cell
        layer_sizes |= {"relativeSizes": True, "expansionRatio": 1.2, "finalLayerThickness": 0.5, "minThickness": 0.1}
    else:  # in metres, from the first layer (snappyHexMesh's first-and-expansion specification)
        layer_sizes |= {
            "relativeSizes": False,
            "firstLayerThickness": first,
            "expansionRatio": LAYER_GROWTH,
            "minThickness": 0.1 * first,
        }
    inside = lo + _INSIDE * (hi - lo)
    inside[0] = lo[0] + 0.37 * (blo[0] - lo[0]) + 0.0137 * h
    snappy = {
        "castellatedMesh": True,
        "snap": True,
        "addLayers": n_layers > 0,
        "geometry": {
            **{f"{n}.stl": {"type": "triSurfaceMesh", "name": n} for n in names},
            "near": {"type": "searchableBox", "min": _f(near_lo), "max": _f(near_hi)},
            "wake": {"type": "searchableBox", "min": _f(wake_lo), "max": _f(wake_hi)},
            **({"ends.stl": {"type": "triSurfaceMesh", "name": "ends"}} if ends else {}),
        },
        "castellatedMeshControls": {
            "maxLocalCells": 5_000_000,
            "maxGlobalCells": 20_000_000,
            "minRefinementCells": 0,
            "maxLoadUnbalance": 0.1,
            "nCellsBetweenLevels": 3,
            "features": [{"file": f'"{n}.eMesh"', "level": lvl} for n in names],
            "refinementSurfaces": {n: {"level": [lvl, lvl], "patchInfo": {"type": "wall"}} for n in names},
            "resolveFeatureAngle": 30,
            "refinementRegions": {
                **{n: {"mode": "distance", "levels": capture_bands(h, lvl)} for n in names},
                "near": {"mode": "inside", "levels": [[1e15, max(0, lvl - 1)]]},
                "wake": {"mode": "inside", "levels": [[1e15, max(0, lvl - 2)]]},
                # the ends: every level past the body's, each within one cell of the coarser level
                **(
                    {"ends": {"mode": "distance", "levels": capture_bands(h, end_level)[: case.settings.end_level]}}
                    if ends
                    else {}
                ),
            },
            "locationInMesh": _f(inside),
            "allowFreeStandingZoneFaces": True,
        },
        "snapControls": {
            "nSmoothPatch": 3,
            "tolerance": 2.0,
            "nSolveIter": 50,
            "nRelaxIter": 5,
            "nFeatureSnapIter": 10,
            "implicitFeatureSnap": False,
            "explicitFeatureSnap": True,
            "multiRegionFeatureSnap": False,
        },
        "addLayersControls": {
            **layer_sizes,
            "nGrow": 0,
            "featureAngle": 130,
            "slipFeatureAngle": 30,
            "nRelaxIter": 3,
            "nSmoothSurfaceNormals": 1,
            "nSmoothNormals": 3,
            "nSmoothThickness": 10,
            "maxFaceThicknessRatio": 0.5,
            "maxThicknessToMedialRatio": 0.3,
            "minMedialAxisAngle": 90,
            "nBufferCellsNoExtrude": 0,
            "nLayerIter": 50,
        },
        "meshQualityControls": {
            "maxNonOrtho": 65,
            "maxBoundarySkewness": 20,
            "maxInternalSkewness": 4,
            "maxConcave": 80,
            "minVol": 1e-13,
            "minTetQuality": 1e-15,
            "minArea": -1,
            "minTwist": 0.02,
            "minDeterminant": 0.001,
            "minFaceWeight": 0.05,
            "minVolRatio": 0.01,
            "minTriangleTwist": -1,
            "nSmoothScale": 4,
            "errorReduction": 0.75,
        },
        "mergeTolerance": 1e-6,
    }
    return {"blockMeshDict": block, "surfaceFeatureExtractDict": features, "snappyHexMeshDict": snappy}


def _f(v: np.ndarray) -> list[float]:
    return [float(x) for x in v]


def estimate_cells(case: Case) -> int:
    """A rough cell count of the case's mesh, for the cost printed before a sweep: background
    cells, plus the refined boxes (each level × 8) and the body's surface layers."""
    if case.path == "wedge":
        return int(15_000 * 2 ** (case.settings.grid - 1))
    lo, hi = domain(case)
    h = cell_size(case)
    total = float(np.prod((hi - lo) / h))
    blo, bhi = case.body.bounds()
    near = float(np.prod(bhi - blo + 0.5 * smallest_extent(case)))
    lvl = surface_level(case)
    if lvl >= 1:
        total += near / h**3 * (8 ** max(0, lvl - 1) - 1)
    area = sum(
        float(np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum()) / 2
        for t in case.body.surfaces()
    )
    hs = h / 2**lvl
    total += area / hs**2 * (layer_plan(case)[0] + 3)
    if case.settings.end_level > 0:
        tri = end_triangles(case)
        end_area = float(np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum()) / 2
        total += end_area / hs**2 * (4**case.settings.end_level - 1) * 3
    return int(total)
