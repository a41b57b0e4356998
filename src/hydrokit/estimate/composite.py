"""Composite rigid bodies (SPEC §2.3, REHMAN §2.3–2.6).

Parts, each with its own mass properties and hydrodynamic matrices about its own origin and a
pose (position r and rotation R of the part frame in the common frame), combine into one body
about the common origin: masses sum; the inertia tensor by the parallel-axis theorem; centres
of gravity and buoyancy as weighted means; added mass and linear damping moved with the 6×6
transform M' = Hᵀ(r) (R₆ M R₆ᵀ) H(r), R₆ = diag(R, R) (Fossen 2011 eq. 7.14) — the full matrix,
not only its diagonal.

Quadratic damping cannot be moved that way (issue #11). A part's translational drag d at lever
arm ρ from the common origin, turning at ω, meets the water at speed ρω: force d ρ² ω², moment
d ρ³ ω². Hᵀ D H gives d ρ² in the rotational diagonal (kg·m — not even the unit of a rotational
quadratic damping, kg·m²). REHMAN Table 1 prints 35.1 = 83.28 · 0.75³ for a manipulator's yaw
damping (but 24.1 = 42.8 · 0.75² for its added inertia, where ρ² is right). :func:`combine`
offers three models (``quadratic_damping=``):

- ``"elements"`` (default): each part's translational drag becomes a point drag element
  (:mod:`hydrokit.core.drag`) at the part origin, evaluated at that point's own velocity;
- ``"rehman"``: REHMAN's diagonal, the d ρ³ terms of each element for rotation about one axis;
- ``"shifted"``: the diagonal of Hᵀ D H, dimensionally wrong, kept only for comparison.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from hydrokit.core.drag import PACKED_WIDTH, moved_elements
from hydrokit.core.rigid_body import move_matrix, parallel_axis
from hydrokit.errors import InputError

#: the ``quadratic_damping`` models of :func:`combine`
QUADRATIC_DAMPING_MODELS = ("elements", "rehman", "shifted")

SHIFTED_WARNING = (
    "quadratic damping model 'shifted': each part's translational drag d at lever arm r enters the "
    "rotational diagonal as d·r² (kg·m, Hᵀ D H) — dimensionally wrong; a rotating part's drag moment "
    "is d·r³·ω² (use 'elements' or 'rehman')"
)


def _no_elements() -> np.ndarray:
    return np.zeros((0, PACKED_WIDTH))


@dataclass(frozen=True)
class Part:
    """One rigid part.

    name : str; mass : kg; volume : m³; inertia : (3, 3) about the part's CG, part axes, kg·m²;
    r_g, r_b : (3,) CG and CB in part axes from the part origin, m; added_mass, linear_damping,
    quadratic_damping : (6, 6) about the part origin in part axes (quadratic: its diagonal is
    used, N·s²/m² and N·m·s²/rad²); position : (3,) part origin in the common frame, m;
    rotation : (3, 3) part axes → common axes; source : str;
    drag_elements : (n, 9) packed point drag elements of the part itself
    (:mod:`hydrokit.core.drag`: position m, linear N·s/m, quadratic N·s²/m², part axes about the
    part origin); drag_element_names : their names (default ``<part>/<k>``)
    """

    name: str
    mass: float
    volume: float
    inertia: np.ndarray
    added_mass: np.ndarray
    linear_damping: np.ndarray = field(default_factory=lambda: np.zeros((6, 6)))
    quadratic_damping: np.ndarray = field(default_factory=lambda: np.zeros((6, 6)))
    r_g: np.ndarray = field(default_factory=lambda: np.zeros(3))
    r_b: np.ndarray = field(default_factory=lambda: np.zeros(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    source: str = ""
    drag_elements: np.ndarray = field(default_factory=_no_elements)
    drag_element_names: tuple[str, ...] = ()


def rotation_from_degrees(roll: float = 0.0, pitch: float = 0.0, yaw: float = 0.0) -> np.ndarray:
    """Part axes → common axes for zyx angles given in degrees."""
    from hydrokit.core.kinematics import rotation_zyx

    return rotation_zyx(math.radians(roll), math.radians(pitch), math.radians(yaw))


def move(M: np.ndarray, rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """A 6×6 matrix about a part origin, in part axes → about the common origin, common axes."""
    R6 = np.zeros((6, 6))
    R6[:3, :3] = rotation
    R6[3:, 3:] = rotation
    return move_matrix(R6 @ M @ R6.T, np.asarray(position, float))


def single_axis_diagonal(packed: np.ndarray) -> np.ndarray:
    """The quadratic damping (6,) that packed elements show in motion along or about one axis.

    Translation: Σ Q per axis (N·s²/m²). Rotation at rate ω about one axis through the origin:
    an element at r = (rx, ry, rz) moves at ω × r, and its moment about that axis is
    −c |ω| ω with (N·m·s²/rad²)

        c_K = Qy|rz|³ + Qz|ry|³,  c_M = Qx|rz|³ + Qz|rx|³,  c_N = Qy|rx|³ + Qx|ry|³.

    (About z: v_P = ω(−ry, rx, 0), f = −Q ∘ |v_P| ∘ v_P, N = rx f_y − ry f_x
    = −(Qy|rx|³ + Qx|ry|³)|ω|ω.) This is REHMAN's d·r³ (REHMAN Table 1: 35.1 = 83.28 · 0.75³).
    """
    P = np.asarray(packed, float).reshape(-1, PACKED_WIDTH)
    a = np.abs(P[:, 0:3]) ** 3
    Q = P[:, 6:9]
    out = np.zeros(6)
    out[:3] = Q.sum(axis=0)
    out[3] = float(np.sum(Q[:, 1] * a[:, 2] + Q[:, 2] * a[:, 1]))
    out[4] = float(np.sum(Q[:, 0] * a[:, 2] + Q[:, 2] * a[:, 0]))
    out[5] = float(np.sum(Q[:, 1] * a[:, 0] + Q[:, 0] * a[:, 1]))
    return out


def _shifted_diagonal(packed: np.ndarray, column: slice) -> np.ndarray:
    """Σ Hᵀ(r) diag(c, 0) H(r) over packed elements, with c the given coefficient columns."""
    out = np.zeros((6, 6))
    for row in np.asarray(packed, float).reshape(-1, PACKED_WIDTH):
        D = np.zeros((6, 6))
        D[:3, :3] = np.diag(row[column])
        out += move_matrix(D, row[0:3])
    return out


@dataclass(frozen=True)
class Composite:
    """The combined body about the common origin (SI).

    ``quadratic_damping`` is diagonal (6×6) and means what ``quadratic_damping_model`` says
    (see :func:`combine`); ``drag_elements`` (n, 9) are point drag elements in common axes about
    the common origin (model ``"elements"`` only), named by ``drag_element_names``;
    ``quadratic_damping_single_axis`` (6,) is the drag coefficient the body shows in motion
    along or about one axis alone (the same for every model: diagonal plus elements);
    ``warnings`` are recoverable oddities.
    """

    mass: float
    volume: float
    inertia_cg: np.ndarray
    r_g: np.ndarray
    r_b: np.ndarray
    added_mass: np.ndarray
    linear_damping: np.ndarray
    quadratic_damping: np.ndarray
    added_mass_diagonal_only: np.ndarray
    parts: tuple[str, ...]
    drag_elements: np.ndarray = field(default_factory=_no_elements)
    drag_element_names: tuple[str, ...] = ()
    quadratic_damping_model: str = "elements"
    quadratic_damping_single_axis: np.ndarray = field(default_factory=lambda: np.zeros(6))
    warnings: tuple[str, ...] = ()

    def weight(self, gravity: float) -> float:
        return self.mass * gravity

    def buoyancy(self, density: float, gravity: float) -> float:
        return density * gravity * self.volume


def _part_elements(p: Part) -> tuple[np.ndarray, list[str]]:
    """The part's drag elements in common axes about the common origin: its translational
    quadratic damping as an element at the part origin (named after the part), then its own."""
    Qt = np.diag(np.asarray(p.quadratic_damping, float))[:3]
    rows, names = [], []
    if np.any(Qt != 0):
        rows.append(np.concatenate([np.zeros(6), Qt]))
        names.append(p.name)
    own = np.asarray(p.drag_elements, float).reshape(-1, PACKED_WIDTH)
    rows.extend(own)
    given = list(p.drag_element_names)
    names.extend(f"{p.name}/{given[k] if k < len(given) else k + 1}" for k in range(own.shape[0]))
    packed = np.vstack(rows) if rows else _no_elements()
    return moved_elements(packed, p.rotation, p.position), names


def _unique(names: list[str]) -> tuple[str, ...]:
    seen: dict[str, int] = {}
    out = []
    for n in names:
        seen[n] = seen.get(n, 0) + 1
        out.append(n if seen[n] == 1 else f"{n}#{seen[n]}")
    return tuple(out)


def combine(parts: Sequence[Part], quadratic_damping: str = "elements") -> Composite:
    """Combine ``parts`` (see module docstring).

    Parameters
    ----------
    parts : sequence of Part
    quadratic_damping : str — how the parts' quadratic damping combines:

        ``"elements"`` (default, physics) — each part's translational quadratic damping (the
        first three diagonal entries, N·s²/m²) becomes a drag element at the part origin, and
        the part's own elements are moved (:func:`hydrokit.core.drag.moved_elements`); the
        diagonal keeps only the parts' own rotational damping (N·m·s²/rad², turned into the
        common axes with |R|). An element at the common origin itself (a part centred there)
        is folded into the translational diagonal: there v_P = v and r × f = 0, the same law.
        ``"rehman"`` — REHMAN's diagonal approximation, no elements: translational Σ Q,
        rotational Σ own + the d·r³ terms of :func:`single_axis_diagonal`. Right for motion
        along or about one axis, wrong for combined motion (a yawing body that also moves).
        ``"shifted"`` — the diagonal of Σ Hᵀ D H: d·r² (kg·m) in the rotational entries.
        Dimensionally wrong, kept for comparison; recorded in ``warnings``.

    Returns
    -------
    Composite
        ``added_mass_diagonal_only`` is what REHMAN does: the sum of each part's diagonal
        entries (turned into the common axes), without the shift to the common origin.

    Raises
    ------
    InputError
        No parts, a non-positive total mass, or an unknown ``quadratic_damping`` model.
    """
    if quadratic_damping not in QUADRATIC_DAMPING_MODELS:
        raise InputError(
            f"quadratic damping model {quadratic_damping!r}: expected one of {', '.join(QUADRATIC_DAMPING_MODELS)}"
        )
    if not parts:
        raise InputError("no parts to combine")
    mass = sum(p.mass for p in parts)
    vol = sum(p.volume for p in parts)
    if mass <= 0:
        raise InputError(f"total mass = {mass}: expected a positive mass")
    cg = [p.position + p.rotation @ p.r_g for p in parts]
    cb = [p.position + p.rotation @ p.r_b for p in parts]
    r_g = sum(p.mass * c for p, c in zip(parts, cg)) / mass
    r_b = sum(p.volume * c for p, c in zip(parts, cb)) / vol if vol > 0 else np.zeros(3)
    I = np.zeros((3, 3))
    for p, c in zip(parts, cg):
        I += parallel_axis(p.rotation @ p.inertia @ p.rotation.T, p.mass, c - r_g)
    MA = sum(move(p.added_mass, p.rotation, p.position) for p in parts)
    # A linear law is linear in the point velocity v + ω × r, so Hᵀ D H moves it exactly.
    DL = np.asarray(sum(move(p.linear_damping, p.rotation, p.position) for p in parts), float)
    diag = np.zeros((6, 6))
    for p in parts:  # REHMAN: each part's diagonal, turned into the common axes, no shift
        R6 = np.zeros((6, 6))
        R6[:3, :3] = p.rotation
        R6[3:, 3:] = p.rotation
        diag += np.diag(np.diag(R6 @ np.diag(np.diag(p.added_mass)) @ R6.T))

    warnings: list[str] = []
    own_rot = np.zeros(3)  # the parts' own rotational quadratic damping, common axes
    rows, names = [], []
    for p in parts:
        DQ = np.asarray(p.quadratic_damping, float)
        absR = np.abs(p.rotation)
        own_rot += absR @ np.diag(DQ)[3:]
        packed, pnames = _part_elements(p)
        rows.append(packed)
        names.extend(pnames)
        if quadratic_damping != "shifted" and np.any(DQ - np.diag(np.diag(DQ)) != 0):
            warnings.append(f"part {p.name}: off-diagonal quadratic damping ignored (a drag law per axis)")
        has_drag = np.any(np.diag(DQ) != 0) or np.asarray(p.drag_elements).size > 0
        if has_drag and not np.allclose(absR, np.round(absR), atol=1e-9):
            warnings.append(
                f"part {p.name}: rotation is not a multiple of 90°; its per-axis drag is turned with |R| "
                "(an approximation)"
            )
    elements = np.vstack(rows) if rows else _no_elements()
    single_axis = single_axis_diagonal(elements)
    single_axis[3:] += own_rot

    DQ_out = np.zeros(6)
    kept = _no_elements()
    kept_names: tuple[str, ...] = ()
    if quadratic_damping == "elements":
        DQ_out[3:] = own_rot
        at_origin = np.all(elements[:, 0:3] == 0, axis=1) & np.all(elements[:, 3:6] == 0, axis=1)
        DQ_out[:3] = elements[at_origin, 6:9].sum(axis=0)
        kept = elements[~at_origin]
        kept_names = _unique([n for n, o in zip(names, at_origin) if not o])
    else:
        # the elements' linear parts are a linear law: moved exactly into D_L
        DL = DL + _shifted_diagonal(elements, slice(3, 6))
        if quadratic_damping == "rehman":
            DQ_out = single_axis
        else:
            shifted = sum(move(p.quadratic_damping, p.rotation, p.position) for p in parts)
            DQ_out = np.diag(np.asarray(shifted, float) + _shifted_diagonal(_own_elements(parts), slice(6, 9))).copy()
            warnings.append(SHIFTED_WARNING)
    return Composite(
        mass=mass,
        volume=vol,
        inertia_cg=I,
        r_g=r_g,
        r_b=r_b,
        added_mass=np.asarray(MA),
        linear_damping=DL,
        quadratic_damping=np.diag(DQ_out),
        added_mass_diagonal_only=diag,
        parts=tuple(p.name for p in parts),
        drag_elements=kept,
        drag_element_names=kept_names,
        quadratic_damping_model=quadratic_damping,
        quadratic_damping_single_axis=single_axis,
        warnings=tuple(warnings),
    )


def _own_elements(parts: Sequence[Part]) -> np.ndarray:
    """The parts' own drag elements (not their origin elements), common axes, common origin."""
    rows = [moved_elements(p.drag_elements, p.rotation, p.position) for p in parts]
    return np.vstack(rows) if rows else _no_elements()
