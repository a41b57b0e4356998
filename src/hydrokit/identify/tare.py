"""Tare tests (ENG2009 §IV.A): the rig alone, swung in air.

In air B ≈ 0 and m_a ≈ 0, so the equation-error coefficients of θ̈ = α sin θ − β θ̇ − γ|θ̇|θ̇
give the effective pendulum length r = −g/α (ENG2009: α = −25.128 → r = 0.3904 m against
0.39 m measured) and the pivot friction β, γ, expressed as K_L = β m, K_Q = γ m / r in the
units of the in-water result, from which they are subtracted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig


@dataclass(frozen=True)
class AirTare:
    """Result of an in-air tare.

    effective_length : float — r = −g/α, m
    linear_damping : float — pivot friction as K_L, N·s/m
    quadratic_damping : float — pivot/air friction as K_Q, N·s²/m²
    """

    effective_length: float
    linear_damping: float
    quadratic_damping: float


def air_tare(alpha: float, beta: float, gamma: float, mass: float, gravity: float = 9.81) -> AirTare:
    """Effective length and pivot friction from in-air pendulum coefficients (ENG2009 eq. 5–7).

    Parameters
    ----------
    alpha : float — coefficient of sin θ, 1/s² (negative: restoring)
    beta : float — linear damping coefficient β, 1/s
    gamma : float — quadratic coefficient γ, 1/rad
    mass : float — swinging mass, kg
    gravity : float — m/s²
    """
    if not (alpha < 0 and math.isfinite(alpha)):
        raise InputError(f"alpha = {alpha}: expected a negative number (1/s², restoring in air)")
    if mass <= 0:
        raise InputError(f"mass = {mass}: expected a positive mass (kg)")
    r = -gravity / alpha
    return AirTare(r, beta * mass, gamma * mass / r)


def apply_tare(rig: Rig, tare: AirTare) -> Rig:
    """The rig with the effective length and the tare damping to subtract."""
    return replace(
        rig,
        pendulum_length=tare.effective_length,
        tare_linear_damping=tare.linear_damping,
        tare_quadratic_damping=tare.quadratic_damping,
    )
