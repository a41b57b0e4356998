"""Point drag elements (issue #11): drag evaluated at a point's own relative velocity.

A drag element sits at ``position`` r (m, body axes, from the body origin) and sees the
velocity of that point relative to the water, v_P = v_r + ω × r (body axes). Its force is

    f = −L ∘ v_P − Q ∘ |v_P| ∘ v_P        (component-wise, N)

with ``linear`` L (N·s/m) and ``quadratic`` Q (N·s²/m², = ½ ρ C_D A per axis), applied at r:
the body wrench is [f; r × f]. A part of a composite body rotating at ω about the origin at
lever arm ρ therefore feels a drag moment Q ρ³ ω² — not the Q ρ² ω² that moving a diagonal
quadratic damping with Hᵀ D H gives (REHMAN §2.6: 35.1 = 83.28 · 0.75³).

Packed form: an (n, 9) float array, one row [x, y, z, Lx, Ly, Lz, Qx, Qy, Qz] per element.
numpy only (rank 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]

#: columns of a packed element row
PACKED_WIDTH = 9


@dataclass(frozen=True)
class DragElement:
    """One point drag element.

    name : str
    position : (3,) — point in body axes from the body origin, m
    linear : (3,) — linear drag per body axis, N·s/m (≥ 0)
    quadratic : (3,) — quadratic drag per body axis, N·s²/m² (≥ 0)
    """

    name: str
    position: tuple[float, float, float]
    linear: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quadratic: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def row(self) -> Array:
        """The packed row [position, linear, quadratic]."""
        return np.concatenate([self.position, self.linear, self.quadratic]).astype(float)


def pack_elements(elements: tuple[DragElement, ...] | list[DragElement]) -> Array:
    """(n, 9) packed rows of ``elements`` (an empty (0, 9) array for none)."""
    if not elements:
        return np.zeros((0, PACKED_WIDTH))
    return np.vstack([e.row() for e in elements])


def drag_wrench(packed: ArrayLike, nu_r: ArrayLike) -> Array:
    """Body wrench [F; M] (N, N·m, body axes, moments about the origin) of packed elements at
    the relative velocity ``nu_r`` = [u, v, w, p, q, r] (m/s, rad/s)."""
    P = np.ascontiguousarray(np.asarray(packed, dtype=float).reshape(-1, PACKED_WIDTH))
    out = np.zeros(6)
    add_drag_wrench(P.ravel(), 0, P.shape[0], np.asarray(nu_r, dtype=float), out)
    return out


def add_drag_wrench(rows, start, n, nr, f):  # noqa: ANN001, ANN201
    """Add the wrench of ``n`` packed elements, stored from ``rows[start]`` on, to ``f``.

    Each element at r sees v_P = v_r + ω × r and gives F = −L v_P − Q |v_P| v_P per axis and
    r × F. The one implementation of the law: :func:`drag_wrench` calls it as Python, the
    compiled integrators compile it (plain floats and loops, so that both can).
    """
    p, q, r = nr[3], nr[4], nr[5]
    for e in range(n):
        b = start + PACKED_WIDTH * e
        rx, ry, rz = rows[b], rows[b + 1], rows[b + 2]
        vx = nr[0] + (q * rz - r * ry)
        vy = nr[1] + (r * rx - p * rz)
        vz = nr[2] + (p * ry - q * rx)
        fx = -rows[b + 3] * vx - rows[b + 6] * abs(vx) * vx
        fy = -rows[b + 4] * vy - rows[b + 7] * abs(vy) * vy
        fz = -rows[b + 5] * vz - rows[b + 8] * abs(vz) * vz
        f[0] += fx
        f[1] += fy
        f[2] += fz
        f[3] += ry * fz - rz * fy
        f[4] += rz * fx - rx * fz
        f[5] += rx * fy - ry * fx


def moved_elements(packed: ArrayLike, rotation: ArrayLike, position: ArrayLike) -> Array:
    """Elements given in a part's axes about the part origin → common axes about the common
    origin (the part origin at ``position``, m; ``rotation`` part → common axes).

    Positions rotate and shift exactly. The per-axis coefficients turn with |R| (each
    coefficient goes to the common axis its part axis maps onto): exact for rotations that
    permute axes (multiples of 90°), an approximation otherwise — a per-axis drag law is not
    invariant under a general rotation.
    """
    P = np.asarray(packed, dtype=float).reshape(-1, PACKED_WIDTH).copy()
    R = np.asarray(rotation, dtype=float)
    absR = np.abs(R)
    P[:, 0:3] = P[:, 0:3] @ R.T + np.asarray(position, dtype=float)
    P[:, 3:6] = P[:, 3:6] @ absR.T
    P[:, 6:9] = P[:, 6:9] @ absR.T
    return P
