"""Composite rigid bodies (SPEC §2.3, REHMAN §2.3–2.6).

Parts, each with its own mass properties and hydrodynamic matrices about its own origin and a
pose (position r and rotation R of the part frame in the common frame), combine into one body
about the common origin: masses sum; the inertia tensor by the parallel-axis theorem; centres
of gravity and buoyancy as weighted means; added mass and damping moved with the 6×6 transform
M' = Hᵀ(r) (R₆ M R₆ᵀ) H(r), R₆ = diag(R, R) (Fossen 2011 eq. 7.14) — the full matrix, not only
its diagonal.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from hydrokit.core.rigid_body import move_matrix, parallel_axis
from hydrokit.errors import InputError


@dataclass(frozen=True)
class Part:
    """One rigid part.

    name : str; mass : kg; volume : m³; inertia : (3, 3) about the part's CG, part axes, kg·m²;
    r_g, r_b : (3,) CG and CB in part axes from the part origin, m; added_mass, linear_damping,
    quadratic_damping : (6, 6) about the part origin in part axes; position : (3,) part origin in
    the common frame, m; rotation : (3, 3) part axes → common axes; source : str
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


@dataclass(frozen=True)
class Composite:
    """The combined body about the common origin (SI)."""

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

    def weight(self, gravity: float) -> float:
        return self.mass * gravity

    def buoyancy(self, density: float, gravity: float) -> float:
        return density * gravity * self.volume


def combine(parts: Sequence[Part]) -> Composite:
    """Combine ``parts`` (see module docstring).

    ``added_mass_diagonal_only`` is what REHMAN does: the sum of each part's diagonal entries
    (turned into the common axes), without the shift to the common origin — for comparison.
    """
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
    DL = sum(move(p.linear_damping, p.rotation, p.position) for p in parts)
    DQ = sum(move(p.quadratic_damping, p.rotation, p.position) for p in parts)
    diag = np.zeros((6, 6))
    for p in parts:  # REHMAN: each part's diagonal, turned into the common axes, no shift
        R6 = np.zeros((6, 6))
        R6[:3, :3] = p.rotation
        R6[3:, 3:] = p.rotation
        diag += np.diag(np.diag(R6 @ np.diag(np.diag(p.added_mass)) @ R6.T))
    return Composite(
        mass, vol, I, r_g, r_b, np.asarray(MA), np.asarray(DL), np.asarray(DQ), diag, tuple(p.name for p in parts)
    )
