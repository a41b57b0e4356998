"""The structured wedge mesh of a body of revolution at zero incidence, as a ``blockMeshDict``.

An axisymmetric body whose axis is x is meshed as OpenFOAM's standard wedge: one cell thick,
``wedge_deg`` wide, straddling the x–y plane symmetrically (the front side at
``z = +y tan(wedge_deg/2)``, the back side at ``z = -y tan(wedge_deg/2)``). Points on the axis are
shared by the two sides, so the cells next to the axis are collapsed hexahedra whose zero-area
axis faces blockMesh removes (as in the ``movingCone`` tutorial). No snappyHexMesh is involved.

Topology, in the meridian half-plane (x, r): a C-type (half O-type) grid wraps the body. Its
first index runs along the body from the nose to the tail, its second runs outward. At a blunt
end (half-angle ≥ 45°: Myring or hemispherical noses, a spheroid's tail) the grid wraps the
end: the outward grid line there is the axis itself (upstream of the nose, downstream of the
tail), so the cells at the stagnation point are orthogonal to the wall, and the outer boundary
is a quarter ellipse reaching ``upstream·L`` ahead of the nose or ``downstream·L`` behind the
tail. Between the two the outer boundary is a straight line at ``r = radial·L``. A pointed end
(half-angle < 45°) would leave an obtuse block corner at its tip; there the C grid ends on the
wall normal at the tip and a block of its own runs along the axis to a flat inlet or outlet
plane (the outer line then goes straight on to meet it).

The grid is cut into blocks along the body wherever the wall normal has turned by more than
``_MAX_TURN`` or a block has ``_MAX_BLOCK_CELLS`` cells; at every cut the block edge leaves the
wall along the wall normal (a quadratic Bézier curve written as a ``polyLine``, bending towards
its outer end within about a body length of the wall, so the edges fan out without crossing
however large the domain), so interior grid lines, which blockMesh interpolates between block edges, stay close to wall-normal near the
body. Each outward edge is graded on its own so its first cell is ``first_cell`` high; the body
edges are ``polyLine`` s through the profile points, so the wall is the profile itself.

Domains with very flat or very tall ends are refused rather than meshed badly: ``radial`` at most
2.5 × ``upstream`` and 2.5 × ``downstream``, and at a blunt end ``upstream`` or ``downstream`` at
most 4 × ``radial`` (checked with checkMesh for a sphere, 2:1 and 6:1 spheroids and a Myring hull
from 1.5 to 20 body lengths).

Patches: ``body`` (wall), ``farfield`` (patch: inlet, outlet and outer boundary together),
``front`` and ``back`` (wedge).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.errors import InputError

__all__ = ["PATCHES", "blockmesh_dict", "cell_count", "first_cell_height", "refinement_ratio"]

#: patch name -> OpenFOAM patch type, as written by :func:`blockmesh_dict`
PATCHES = {"body": "wall", "farfield": "patch", "front": "wedge", "back": "wedge"}

#: largest turn of the wall normal inside one block, rad (keeps interpolated grid lines near-normal)
_MAX_TURN = math.radians(12.0)
#: most cells along the body in one block at level 1
_MAX_BLOCK_CELLS = 24
#: streamwise cell at the nose and tail = mid-body cell / _END_REFINE
_END_REFINE = 5.0
#: growth ratio of the streamwise cells from the nose and tail towards mid-body
_END_GROWTH = 1.1
#: points on each curved outward block edge (polyLine)
_EDGE_POINTS = 24
#: share of the outer-boundary spacing that follows the cell count (the rest follows the
#: body zones: nose → upstream quarter ellipse, mid-body → top line, tail → downstream ellipse)
_OUTER_UNIFORM = 0.25
#: control-point distance of an outward Bézier edge, as a share of its chord and at most of L
_BEZIER_REACH = 0.3
#: most radial / upstream and radial / downstream: beyond it the outward grid lines meet the outer
#: boundary ahead of the nose or behind the tail at grazing angles (skewness > 4, non-orthogonality
#: > 70°)
_MAX_RADIAL_PER_END = 2.5
#: most upstream / radial (downstream / radial) at a blunt nose (tail): beyond it the quarter
#: ellipse there is too flat for the C wrap's end block
_MAX_END_PER_RADIAL = 4.0
#: an end whose half-angle is below this is pointed (gets its own block on the axis), rad
_POINTED = math.radians(45.0)
#: at a pointed end the C grid ends on the top line this far (× outer radius) beyond the tip
_WAKE_START = 0.2
#: expansion of the flat inlet and outlet sides, axis → outer boundary (last / first cell)
_WAKE_OUTLET_GRADING = 8.0


def refinement_ratio(level: int) -> float:
    """Linear refinement ratio of grid ``level`` against level 1: √2 per level.

    Parameters
    ----------
    level : int
        Grid level, 1 (base) or higher, dimensionless.

    Returns
    -------
    float
        ``2 ** ((level - 1) / 2)``, dimensionless.
    """
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or level < 1:
        raise InputError(f"level = {level!r}: expected an integer ≥ 1 (1 = base grid, 2 and 3 refine by √2 each)")
    return float(2.0 ** ((int(level) - 1) / 2.0))


def first_cell_height(length: float, reynolds: float, y_plus: float) -> float:
    """Wall-normal height of the first cell for a target y⁺, from flat-plate skin friction.

    Parameters
    ----------
    length : float
        Body length L, the length of the Reynolds number, m.
    reynolds : float
        Reynolds number ``Re_L = U L / ν``, dimensionless.
    y_plus : float
        Target y⁺ of the first cell (its full height, not its centre), dimensionless.

    Returns
    -------
    float
        First-cell height Δy, m.

    Raises
    ------
    InputError
        (a ValueError) when a value is not finite and positive.

    Notes
    -----
    Turbulent flat-plate skin friction ``C_f = 0.026 Re_L^(-1/7)`` (Schlichting, *Boundary-Layer
    Theory*, power-law profile; the form White, *Fluid Mechanics*, eq. 7.45 gives), friction
    velocity ``u_τ = U √(C_f / 2)`` and ``Δy = y⁺ ν / u_τ``. With ``ν / U = L / Re_L``:

    .. math:: Δy = \\frac{y^+ L}{Re_L \\sqrt{C_f / 2}}

    It is an estimate for laying out the mesh; the y⁺ a solution reaches varies along the body
    (largest near the nose).
    """
    for name, value in (("length", length), ("reynolds", reynolds), ("y_plus", y_plus)):
        _positive(name, value)
    c_f = 0.026 * float(reynolds) ** (-1.0 / 7.0)
    return float(y_plus) * float(length) / (float(reynolds) * math.sqrt(c_f / 2.0))


def blockmesh_dict(
    x: np.ndarray,
    r: np.ndarray,
    *,
    first_cell: float,
    level: int = 1,
    upstream: float = 1.5,
    downstream: float = 3.0,
    radial: float = 1.5,
    wedge_deg: float = 5.0,
    cells_along: int = 125,
    growth: float = 1.15,
    hold_first_cell: bool = False,
) -> dict[str, Any]:
    """The ``blockMeshDict`` of the wedge mesh around a closed body of revolution.

    Parameters
    ----------
    x : numpy.ndarray
        Axial stations of the profile, from the nose, strictly increasing, m.
    r : numpy.ndarray
        Radius at each station, ≥ 0, zero at the first and last station only (a closed body), m.
    first_cell : float
        Wall-normal height of the first cell at the body on level 1, m (see
        :func:`first_cell_height`).
    level : int, optional
        Grid level, dimensionless: 1 is the base grid; each further level refines every direction
        by √2 (cell counts along and across the body × √2, ``first_cell`` ÷ √2 unless
        ``hold_first_cell``), so levels 1, 2, 3 form a refinement triplet with ratio √2 for
        Richardson extrapolation / GCI.
    upstream : float, optional
        Distance from the nose to the inlet, in body lengths L, dimensionless.
    downstream : float, optional
        Distance from the tail to the outlet, in body lengths L, dimensionless.
    radial : float, optional
        Radius of the outer boundary, in body lengths L, dimensionless.
    wedge_deg : float, optional
        Wedge angle, degrees (the mesh straddles the x–y plane, ±wedge_deg/2).
    cells_along : int, optional
        Streamwise resolution on level 1: a mid-body cell is ``L / cells_along`` long, cells at the
        nose and tail are five times shorter, dimensionless.
    growth : float, optional
        Largest wall-normal growth ratio of consecutive cells on level 1, reached on the longest
        outward edge (the downstream axis behind a blunt tail); it sets the number of cells across,
        dimensionless.
    hold_first_cell : bool, optional
        Keep the wall-normal height of the first cell at ``first_cell`` on every level (the cells
        along and across are still refined). A wall-function grid study needs it: refining the
        first cell with the rest walks its y⁺ from the log layer into the buffer layer, where the
        wall function's answer changes with y⁺ rather than with the grid (on the Myring at Re_L
        1e6 and y⁺ 50 the drag rose 1 % over three levels, "diverging", as the cell-centre y⁺ fell
        from 25 to 12).

    Returns
    -------
    dict
        Keys ``convertToMeters``, ``vertices``, ``blocks``, ``edges``, ``boundary``,
        ``mergePatchPairs`` with plain Python lists, floats and ints, as ``foamlib`` writes them
        (blocks and edges are flat lists, e.g. ``["hex", [...], [...], "edgeGrading", [...], ...]``;
        boundary is a list of ``(name, {"type": ..., "faces": [...]})``). Lengths in m.

    Raises
    ------
    InputError
        (a ValueError) naming the bad value: a profile with fewer than 5 points, non-finite
        values, x not strictly increasing, r < 0, not closed at both ends or touching the axis
        between them; a non-positive or non-finite size; a level that is not an integer ≥ 1; a
        wedge angle outside (0°, 45°]; an outer radius that does not clear the body; a domain whose
        proportions the C wrap cannot mesh cleanly: ``radial`` more than 2.5 × ``upstream`` or
        2.5 × ``downstream``, or ``upstream`` (``downstream``) more than 4 × ``radial`` at a blunt
        nose (tail).

    Notes
    -----
    The number of cells is ``sum(cells along each block) × cells across`` (one cell thick); the
    cells along the body at level 1 follow from ``cells_along`` and the geometric growth from the
    ends, the cells across from ``first_cell``, ``growth`` and the longest outward edge. A finer level multiplies both by √2 (rounded), so its cell count is about
    2× (level 2) and 4× (level 3) that of level 1.
    """
    x, r = _validate_profile(x, r)
    _positive("first_cell", first_cell)
    ratio = refinement_ratio(level)
    for name, value in (("upstream", upstream), ("downstream", downstream), ("radial", radial)):
        _positive(name, value)
    _positive("wedge_deg", wedge_deg)
    if wedge_deg > 45.0:
        raise InputError(f"wedge_deg = {wedge_deg!r}°: expected a thin wedge, 0° < wedge_deg ≤ 45° (usually 5°)")
    if isinstance(cells_along, bool) or not isinstance(cells_along, (int, np.integer)) or cells_along < 10:
        raise InputError(f"cells_along = {cells_along!r}: expected an integer ≥ 10")
    _positive("growth", growth)
    if not 1.0 < growth <= 1.5:
        raise InputError(f"growth = {growth!r}: expected a wall-normal growth ratio 1 < growth ≤ 1.5")

    x0, length = float(x[0]), float(x[-1] - x[0])
    r_out = radial * length
    if r_out <= 2.0 * float(r.max()):
        raise InputError(
            f"radial = {radial!r}: the outer radius {r_out:g} m must be more than twice the body radius {r.max():g} m"
        )
    if first_cell >= 0.05 * r.max():
        raise InputError(
            f"first_cell = {first_cell!r} m: expected much less than the body radius {r.max():g} m (< 5 %)"
        )

    body = _Polyline(np.column_stack([x, r]))
    # a pointed end (half-angle below 45°) gets a block of its own on the axis instead of the C
    # wrap, whose corner at the tip would otherwise be 180° minus the half-angle; the domain then
    # ends in a flat inlet or outlet plane instead of a quarter ellipse, so that block has four
    # real corners
    nose, tail = body.p[1] - body.p[0], body.p[-2] - body.p[-1]
    pointed_nose = math.atan2(nose[1], nose[0]) < _POINTED
    pointed = math.atan2(tail[1], -tail[0]) < _POINTED
    _check_domain(upstream, downstream, radial, blunt_nose=not pointed_nose, blunt_tail=not pointed)
    outer = _Stadium(
        x0, length, upstream * length, downstream * length, r_out, flat_inlet=pointed_nose, flat_outlet=pointed
    )
    f_start = outer.fraction_on_top(x0 - _WAKE_START * r_out) if pointed_nose else 0.0
    f_end = outer.fraction_on_top(x0 + length + _WAKE_START * r_out) if pointed else 1.0

    # --- level-1 layout: body stations (arc length), the zones and the block cuts -------------
    s_nodes, zone_end = _along_body(body.length, length / cells_along)
    cuts = _block_cuts(body, s_nodes, zone_end)
    n_along1 = [int(n) for n in np.diff(cuts)]
    f_outer = _outer_fractions(s_nodes, zone_end, outer, f_start, f_end)

    # outward edges of the cuts, in the meridian plane: the axis at a C-wrapped end, Béziers
    # leaving the wall along its normal everywhere else
    p_body = [body.point(s_nodes[i]) for i in cuts]
    p_outer = [outer.point(f_outer[i] * outer.length) for i in cuts]
    j_edges: list[np.ndarray] = []
    for k, (pb, po) in enumerate(zip(p_body, p_outer)):
        if (k == 0 and not pointed_nose) or (k == len(cuts) - 1 and not pointed):
            j_edges.append(np.array([pb, po]))
        else:
            j_edges.append(_bezier(pb, body.normal(s_nodes[cuts[k]]), po, length))
    j_lengths = [_Polyline(e).length for e in j_edges]

    # --- cells across: from the longest outward edge at level 1, then refined ---------------
    longest = max(j_lengths + [r_out])  # r_out: the flat inlet or outlet side
    n_across = max(2, round(_cells_for_growth(longest, first_cell, growth) * ratio))
    h1 = first_cell if hold_first_cell else first_cell / ratio

    def across(edge_length: float) -> float:
        return _expansion_for_first_cell(edge_length, h1, n_across)

    mesh = _WedgeMesh(wedge_deg)
    v_body = [mesh.vertex(p) for p in p_body]
    v_outer = [mesh.vertex(p) for p in p_outer]
    for k in range(len(cuts) - 1):
        a, b = cuts[k], cuts[k + 1]
        d_body = np.diff(s_nodes[a : b + 1])
        d_outer = np.diff(f_outer[a : b + 1])
        mesh.block(
            (v_body[k], v_body[k + 1], v_outer[k + 1], v_outer[k]),
            (max(1, round(n_along1[k] * ratio)), n_across),
            bottom=(body.between(s_nodes[a], s_nodes[b]), float(d_body[-1] / d_body[0])),
            top=(outer.between(f_outer[a] * outer.length, f_outer[b] * outer.length), float(d_outer[-1] / d_outer[0])),
            left=(j_edges[k], across(j_lengths[k])),
            right=(j_edges[k + 1], across(j_lengths[k + 1])),
            patches={
                "bottom": "body",
                "top": "farfield",
                "left": "farfield" if k == 0 and not pointed_nose else None,
                "right": "farfield" if k == len(cuts) - 2 and not pointed else None,
            },
        )
    if pointed_nose:
        # entrance block: inlet → nose along the axis, its inlet side and top on the outer boundary
        n_end, i_end = p_body[0], outer.point(0.0)
        f_c = outer.fraction_on_top(x0 - upstream * length)
        v_c, v_i = mesh.vertex(outer.point(f_c * outer.length)), mesh.vertex(i_end)
        axis_len = float(n_end[0] - i_end[0])
        last_axial = float(s_nodes[1] - s_nodes[0])  # lead into the nose's streamwise spacing
        n_in = max(2, round(_cells_for_growth(axis_len, last_axial, _END_GROWTH) * ratio))
        g_axis = 1.0 / _expansion_for_first_cell(axis_len, last_axial / ratio, n_in)
        mesh.block(
            (v_i, v_body[0], v_outer[0], v_c),
            (n_in, n_across),
            bottom=(np.array([i_end, n_end]), g_axis),
            top=(outer.between(f_c * outer.length, f_start * outer.length), g_axis),
            left=(outer.between(0.0, f_c * outer.length), _WAKE_OUTLET_GRADING),
            right=(j_edges[0], across(j_lengths[0])),
            patches={"bottom": "farfield", "top": "farfield", "left": "farfield", "right": None},
        )
    if pointed:
        # wake block: tail → outlet along the axis, its top and outlet side on the outer boundary
        t_end, e_end = p_body[-1], outer.point(outer.length)
        f_x = outer.fraction_on_top(x0 + length + downstream * length)
        x_pt = outer.point(f_x * outer.length)
        v_x, v_e = mesh.vertex(x_pt), mesh.vertex(e_end)
        axis_len = float(e_end[0] - t_end[0])
        first_axial = float(s_nodes[-1] - s_nodes[-2])  # continue the tail's streamwise spacing
        n_wake = max(2, round(_cells_for_growth(axis_len, first_axial, _END_GROWTH) * ratio))
        outlet = outer.between(f_x * outer.length, outer.length)[::-1]
        g_axis = _expansion_for_first_cell(axis_len, first_axial / ratio, n_wake)
        mesh.block(
            (v_body[-1], v_e, v_x, v_outer[-1]),
            (n_wake, n_across),
            bottom=(np.array([t_end, e_end]), g_axis),
            top=(outer.between(f_end * outer.length, f_x * outer.length), g_axis),
            left=(j_edges[-1], across(j_lengths[-1])),
            right=(outlet, _WAKE_OUTLET_GRADING),
            patches={"bottom": "farfield", "top": "farfield", "left": None, "right": "farfield"},
        )
    return mesh.as_dict()


class _WedgeMesh:
    """Blocks drawn in the meridian plane, written as a one-cell wedge (shared vertices on the axis)."""

    # hex faces with outward normals (OpenFOAM's hex model), by block side
    _FACES = {
        "left": (0, 4, 7, 3),
        "right": (1, 2, 6, 5),
        "bottom": (0, 1, 5, 4),
        "top": (3, 7, 6, 2),
        "back": (0, 3, 2, 1),
        "front": (4, 5, 6, 7),
    }

    def __init__(self, wedge_deg: float):
        half = math.radians(wedge_deg) / 2.0
        self.cos, self.sin = math.cos(half), math.sin(half)
        self.vertices: list[list[float]] = []
        self.blocks: list[Any] = []
        self.edges: list[Any] = []
        self.faces: dict[str, list[list[int]]] = {name: [] for name in PATCHES}
        self._edge_done: set[tuple[int, int]] = set()

    def _xyz(self, p: np.ndarray, sign: float) -> list[float]:
        return [float(p[0]), float(p[1] * self.cos), float(sign * p[1] * self.sin)]

    def vertex(self, p: np.ndarray) -> tuple[int, int]:
        """Indices (back, front) of a meridian-plane point; one shared index on the axis."""
        if p[1] <= 0.0:
            self.vertices.append([float(p[0]), 0.0, 0.0])
            return len(self.vertices) - 1, len(self.vertices) - 1
        self.vertices += [self._xyz(p, -1.0), self._xyz(p, 1.0)]
        return len(self.vertices) - 2, len(self.vertices) - 1

    def _edge(self, a: tuple[int, int], b: tuple[int, int], pts: np.ndarray) -> None:
        inner = pts[1:-1]
        if len(inner) == 0 or np.all(pts[:, 1] <= 0.0) or (a[0], b[0]) in self._edge_done:
            return  # straight, on the axis, or written by the neighbouring block
        self._edge_done.add((a[0], b[0]))
        for side, sign in ((0, -1.0), (1, 1.0)):
            self.edges += ["polyLine", a[side], b[side], [self._xyz(p, sign) for p in inner]]

    def block(
        self,
        corners: tuple[tuple[int, int], ...],
        cells: tuple[int, int],
        *,
        bottom: tuple[np.ndarray, float],
        top: tuple[np.ndarray, float],
        left: tuple[np.ndarray, float],
        right: tuple[np.ndarray, float],
        patches: dict[str, str | None],
    ) -> None:
        """One block: corners (i0j0, i1j0, i1j1, i0j1), each edge as (points, expansion ratio)."""
        c00, c10, c11, c01 = corners
        self._edge(c00, c10, bottom[0])
        self._edge(c01, c11, top[0])
        self._edge(c00, c01, left[0])
        self._edge(c10, c11, right[0])
        hex_ = [c00[0], c10[0], c11[0], c01[0], c00[1], c10[1], c11[1], c01[1]]
        gb, gt, gl, gr = (_round(e[1]) for e in (bottom, top, left, right))
        # edgeGrading order: x1 edges (0 1)(3 2)(7 6)(4 5), x2 edges (0 3)(1 2)(5 6)(4 7), x3 edges
        grading = [gb, gt, gt, gb, gl, gr, gr, gl, 1, 1, 1, 1]
        self.blocks += ["hex", hex_, [int(cells[0]), int(cells[1]), 1], "edgeGrading", grading]
        sides = dict(patches, back="back", front="front")
        for side, patch in sides.items():
            if patch is not None:
                # a side on the axis collapses to nothing; listing it keeps blockMesh from
                # adding an empty 'defaultFaces' patch
                self.faces[patch].append([hex_[i] for i in self._FACES[side]])

    def as_dict(self) -> dict[str, Any]:
        return {
            "convertToMeters": 1,
            "vertices": self.vertices,
            "blocks": self.blocks,
            "edges": self.edges,
            "boundary": [(name, {"type": kind, "faces": self.faces[name]}) for name, kind in PATCHES.items()],
            "mergePatchPairs": [],
        }


def cell_count(mesh_dict: dict[str, Any]) -> int:
    """Number of cells a ``blockMeshDict`` from :func:`blockmesh_dict` asks for.

    Parameters
    ----------
    mesh_dict : dict
        The dictionary :func:`blockmesh_dict` returned.

    Returns
    -------
    int
        Sum over the blocks of the product of their cell counts, cells.
    """
    items = mesh_dict["blocks"]
    return sum(math.prod(items[i + 2]) for i, item in enumerate(items) if item == "hex")


# --- profile and numbers ------------------------------------------------------------------


def _positive(name: str, value: object) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{name} = {value!r}: expected a positive number")
    if not (math.isfinite(float(value)) and float(value) > 0.0):
        raise InputError(f"{name} = {value!r}: expected a finite number > 0")


def _check_domain(upstream: float, downstream: float, radial: float, *, blunt_nose: bool, blunt_tail: bool) -> None:
    """Refuse the domain proportions the C wrap cannot mesh cleanly (checkMesh fails or warns)."""
    for name, value in (("upstream", upstream), ("downstream", downstream)):
        if radial > _MAX_RADIAL_PER_END * value:
            raise InputError(
                f"radial = {radial!r} with {name} = {value!r}: the outer radius may be at most "
                f"{_MAX_RADIAL_PER_END:g} × {name} (body lengths), or the cells near the outer boundary are too skewed"
            )
    for name, value, blunt in (("upstream", upstream, blunt_nose), ("downstream", downstream, blunt_tail)):
        if blunt and value > _MAX_END_PER_RADIAL * radial:
            end = "nose" if name == "upstream" else "tail"
            raise InputError(
                f"{name} = {value!r} with radial = {radial!r}: at a blunt {end} {name} may be at most "
                f"{_MAX_END_PER_RADIAL:g} × radial (body lengths), or the cells at the {end} are too skewed"
            )


def _validate_profile(x: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    try:
        x = np.asarray(x, dtype=float)
        r = np.asarray(r, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"profile: x and r must be arrays of numbers ({exc})") from None
    if x.ndim != 1 or r.ndim != 1 or x.shape != r.shape:
        raise InputError(f"profile: x and r must be 1-D arrays of equal length, got shapes {x.shape} and {r.shape}")
    if len(x) < 5:
        raise InputError(f"profile: {len(x)} points, expected at least 5 (x, r) points from nose to tail")
    for name, arr in (("x", x), ("r", r)):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise InputError(f"profile: {name}[{bad[0]}] = {arr[bad[0]]!r}, expected a finite number (m)")
    step = np.diff(x)
    if np.any(step <= 0.0):
        i = int(np.flatnonzero(step <= 0.0)[0]) + 1
        raise InputError(
            f"profile: x[{i}] = {x[i]:g} m after x[{i - 1}] = {x[i - 1]:g} m, expected x strictly increasing"
        )
    if np.any(r < 0.0):
        i = int(np.flatnonzero(r < 0.0)[0])
        raise InputError(f"profile: r[{i}] = {r[i]:g} m, expected r ≥ 0")
    # round-off zeros (a profile from sin(π)) count as closed
    tol = 1e-9 * float(r.max())
    if r[0] > tol or r[-1] > tol:
        end, i = ("nose", 0) if r[0] > tol else ("tail", len(r) - 1)
        raise InputError(f"profile: r[{i}] = {r[i]:g} m at the {end}, expected 0 (a closed body: r = 0 at both ends)")
    if np.any(r[1:-1] <= 0.0):
        i = int(np.flatnonzero(r[1:-1] <= 0.0)[0]) + 1
        raise InputError(f"profile: r[{i}] = {r[i]:g} m between nose and tail, expected r > 0 (one closed body)")
    r = r.copy()
    r[0] = r[-1] = 0.0
    return x, r


def _round(value: float) -> float:
    # 12 significant digits: exact enough for blockMesh, short in the file
    return float(f"{value:.12g}")


def _cells_for_growth(length: float, first: float, growth: float) -> int:
    """Fewest cells that span ``length`` from a first cell ``first`` with growth ≤ ``growth``."""
    # geometric series: first (q^n − 1)/(q − 1) = length
    return max(2, math.ceil(math.log(1.0 + length / first * (growth - 1.0)) / math.log(growth)))


def _expansion_for_first_cell(length: float, first: float, n: int) -> float:
    """blockMesh expansion ratio (last cell / first cell) of ``n`` cells over ``length`` starting at ``first``."""
    target = length / first
    if target <= n:  # a uniform grid is already finer than asked: shrink the first cell
        lo, hi = 1e-6, 1.0
    else:
        lo, hi = 1.0, 2.0
        while (hi**n - 1.0) / (hi - 1.0) < target:
            hi *= 2.0
    for _ in range(200):  # bisection on the geometric-series sum, monotone in q
        q = 0.5 * (lo + hi)
        total = n if abs(q - 1.0) < 1e-15 else (q**n - 1.0) / (q - 1.0)
        lo, hi = (q, hi) if total < target else (lo, q)
    q = 0.5 * (lo + hi)
    return q ** (n - 1)


# --- curves in the meridian plane ----------------------------------------------------------


class _Polyline:
    """A polyline in the (x, r) half-plane, parametrised by arc length."""

    def __init__(self, points: np.ndarray):
        self.p = np.asarray(points, dtype=float)
        self.s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(self.p, axis=0).T))])
        self.length = float(self.s[-1])

    def point(self, s: float) -> np.ndarray:
        return np.array([np.interp(s, self.s, self.p[:, 0]), np.interp(s, self.s, self.p[:, 1])])

    def between(self, s_a: float, s_b: float) -> np.ndarray:
        """The points at s_a and s_b with the polyline's own points strictly between them."""
        tol = 1e-9 * self.length
        inside = (self.s > s_a + tol) & (self.s < s_b - tol)
        return np.vstack([self.point(s_a), self.p[inside], self.point(s_b)])

    def normal(self, s: float) -> np.ndarray:
        """Unit normal pointing away from the axis side (tangent turned +90°)."""
        ds = 0.004 * self.length
        t = self.point(min(s + ds, self.length)) - self.point(max(s - ds, 0.0))
        n = np.array([-t[1], t[0]])
        return n / np.hypot(*n)

    def angle(self, s: np.ndarray) -> np.ndarray:
        """Direction of the normal at each s, rad."""
        return np.array([math.atan2(*self.normal(float(si))[::-1]) for si in s])


class _Stadium(_Polyline):
    """Outer boundary: a quarter ellipse ahead of the nose, a line at r_out along the body and a
    quarter ellipse behind the tail; with ``flat_inlet`` / ``flat_outlet`` a plane up from the
    axis at the inlet / down to it at the outlet instead, the line carried on to meet it."""

    N = 400  # segments per quarter ellipse

    def __init__(
        self, x0: float, length: float, up: float, down: float, r_out: float, *, flat_inlet: bool, flat_outlet: bool
    ):
        self.x0 = x0
        t = np.linspace(0.0, 0.5 * np.pi, self.N + 1)
        if flat_inlet:
            front = np.array([[x0 - up, 0.0], [x0 - up, r_out], [x0, r_out]])
        else:
            front = np.column_stack([x0 - up * np.cos(t), r_out * np.sin(t)])
        if flat_outlet:
            back = np.array([[x0 + length + down, r_out], [x0 + length + down, 0.0]])
        else:
            back = np.column_stack([x0 + length + down * np.sin(t), r_out * np.cos(t)])
        super().__init__(np.vstack([front, back]))
        self.s_top = float(self.s[len(front) - 1])  # arc length at (x0, r_out)
        self.top_length = length

    def fraction_on_top(self, x: float) -> float:
        """Arc-length fraction of the point (x, r_out) on the top line."""
        return (self.s_top + (x - self.x0)) / self.length


def _bezier(p0: np.ndarray, n0: np.ndarray, p2: np.ndarray, length: float) -> np.ndarray:
    """Quadratic Bézier from p0, leaving along n0, to p2 (a block edge normal to the wall).

    Its control point lies ``_BEZIER_REACH`` of the edge's chord along n0, but no further than
    ``_BEZIER_REACH × length`` (the body length): on a domain large against the body, the
    neighbouring edges' normals fan out far faster than their outer ends are spread, and
    control points that far out made the edges cross each other (inverted cells).
    """
    reach = _BEZIER_REACH * min(float(np.hypot(*(p2 - p0))), length)
    p1 = p0 + reach * n0
    t = np.linspace(0.0, 1.0, _EDGE_POINTS)[:, None]
    return (1 - t) ** 2 * p0 + 2 * t * (1 - t) * p1 + t**2 * p2


# --- layout on level 1 ---------------------------------------------------------------------


def _along_body(total: float, mid: float) -> tuple[np.ndarray, tuple[int, int]]:
    """Grid stations along the body (arc length, m) and the node indices ending the nose and mid zones.

    Cells grow geometrically (×_END_GROWTH) from ``mid/_END_REFINE`` at each end to ``mid``, and
    are uniform in between.
    """
    end = mid / _END_REFINE
    n_end = math.ceil(math.log(_END_REFINE) / math.log(_END_GROWTH)) + 1
    q = _END_REFINE ** (1.0 / (n_end - 1))
    cells = end * q ** np.arange(n_end)
    l_end = float(cells.sum())
    if 2.0 * l_end >= 0.8 * total:  # a stubby body: shrink the ends to fit
        cells *= 0.4 * total / l_end
        l_end = float(cells.sum())
    n_mid = max(2, round((total - 2.0 * l_end) / mid))
    middle = np.full(n_mid, (total - 2.0 * l_end) / n_mid)
    widths = np.concatenate([cells, middle, cells[::-1]])
    s = np.concatenate([[0.0], np.cumsum(widths)])
    s[-1] = total
    return s, (n_end, n_end + n_mid)


def _block_cuts(body: _Polyline, s: np.ndarray, zone_end: tuple[int, int]) -> list[int]:
    """Node indices where blocks start and end: zone ends, wall-normal turns, block size."""
    angle = np.unwrap(body.angle(s))
    cuts = [0]
    for i in range(1, len(s)):
        start = cuts[-1]
        must = i in zone_end or i == len(s) - 1
        full = i - start >= _MAX_BLOCK_CELLS
        turned = abs(angle[i] - angle[start]) > _MAX_TURN and i - start >= 2
        if must or full or turned:
            cuts.append(i)
    # no block of a single cell at a zone end: merge it into its neighbour
    merged = [cuts[0]]
    for c in cuts[1:]:
        if c - merged[-1] < 2 and len(merged) > 1 and c not in zone_end and c != len(s) - 1:
            continue
        merged.append(c)
    return merged


def _outer_fractions(
    s: np.ndarray, zone_end: tuple[int, int], outer: _Stadium, f_start: float, f_end: float
) -> np.ndarray:
    """Arc-length fraction on the outer boundary of each body station's outward grid line.

    A blend of uniform spacing by cell count (even cells on the far field) and a zone map (nose
    → upstream quarter ellipse, mid-body → the straight top, tail → the downstream ellipse up to
    ``f_end``; from ``f_start`` at the nose), so grid lines go out roughly normal to the body), smoothed so the spacing has no
    jumps.
    """
    n = len(s) - 1
    uniform = f_start + np.arange(n + 1) / n * (f_end - f_start)
    f_top0, f_top1 = outer.fraction_on_top(outer.x0), outer.fraction_on_top(outer.x0 + outer.top_length)
    zoned = np.interp(np.arange(n + 1), [0, zone_end[0], zone_end[1], n], [f_start, f_top0, f_top1, f_end])
    f = _OUTER_UNIFORM * uniform + (1.0 - _OUTER_UNIFORM) * zoned
    # smooth the spacing with a moving average over ~n/12 cells, keeping the ends fixed
    width = max(3, n // 12) | 1
    d = np.diff(f)
    pad = np.concatenate([np.full(width // 2, d[0]), d, np.full(width // 2, d[-1])])
    d = np.convolve(pad, np.ones(width) / width, mode="valid")
    f = np.concatenate([[0.0], np.cumsum(d)])
    return f_start + f / f[-1] * (f_end - f_start)
