"""Rotational similitude exponents against an independent geometry (issue #13, item 1).

A changed rotational damping exponent passed the whole suite: only the translational
exponents were checked (ENG2009's surge numbers in test_sources.py). Here a geometrically
similar body is worked out at two sizes in closed form and the ratio compared with
:func:`scale_coefficients`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.identify.scaling import scale_coefficients

RHO = 1000.0  # kg/m³, equal in model and full-scale tests (SCALING_ASSUMPTIONS)
C_D = 1.9  # flat plate broadside; equal at both sizes (the Reynolds-insensitive assumption)


def rotating_plate(half_span: float, height: float) -> dict[str, float]:
    """Strip theory for a flat plate (span 2R, height c) spinning about its vertical centreline.

    Each strip dr at radius r moves broadside at ω r:
    added inertia ∫ ρ π (c/2)² r² dr over −R…R = ρ π c² R³ / 6 (the classical potential-flow
    added mass ρ π (c/2)² of a 2-D plate of width c), and drag torque ∫ ½ ρ C_D c (ω r)² |r| dr = ρ C_D c R⁴ ω² / 4.
    """
    R, c = half_span, height
    return {
        "added_mass": RHO * math.pi * c**2 * R**3 / 6.0,  # kg·m²
        "quadratic_damping": RHO * C_D * c * R**4 / 4.0,  # N·m·s²/rad²
    }


@pytest.mark.parametrize("lam", [1 / 0.3, 2.0, 0.5])
def test_rotational_added_inertia_and_quadratic_damping_scale_like_the_geometry(lam):
    model = rotating_plate(0.15, 0.06)
    full = rotating_plate(0.15 * lam, 0.06 * lam)
    scaled = scale_coefficients(model, lam, rotational=True)
    for key in model:
        # both sides are products of powers: only round-off separates them
        assert scaled[key] == pytest.approx(full[key], rel=1e-12), key


@pytest.mark.parametrize("lam", [1 / 0.3, 2.0])
def test_rotational_drag_torque_curve_scales_with_lambda_to_the_fifth(lam):
    # SPEC §1.6 (ENG2009 §II.D): "rotational drag torque with λ⁵" — the whole torque curve
    # K_L ω + K_Q ω|ω| at the same rate, so K_L and K_Q share the exponent; ENG2009 print
    # λ⁵ = 411.52 for λ = 1/0.3
    if lam == 1 / 0.3:
        assert lam**5 == pytest.approx(411.52, abs=0.005)
    K_L, K_Q = 0.0029, 0.018  # N·m·s/rad, N·m·s²/rad² (a small yaw model)
    full = scale_coefficients({"linear_damping": K_L, "quadratic_damping": K_Q}, lam, rotational=True)
    w = np.linspace(-2.0, 2.0, 9)
    torque_model = K_L * w + K_Q * w * np.abs(w)
    torque_full = full["linear_damping"] * w + full["quadratic_damping"] * w * np.abs(w)
    np.testing.assert_allclose(torque_full, lam**5 * torque_model, rtol=1e-12, atol=1e-15)
    # and each coefficient on its own (the curve at 9 rates already separates ω from ω|ω|)
    assert full["linear_damping"] == pytest.approx(K_L * lam**5, rel=1e-12)
    assert full["quadratic_damping"] == pytest.approx(K_Q * lam**5, rel=1e-12)


@pytest.mark.parametrize("rotational", [False, True])
def test_mass_and_volume_scale_with_the_cube(rotational):
    # a cube of side a: V = a³, m = ρ_body a³; a 2× model's full-size twin weighs and displaces 8×
    a, rho_body = 0.1, 1200.0
    values = {"mass": rho_body * a**3} | ({} if rotational else {"volume": a**3})
    full = scale_coefficients(values, 2.0, rotational=rotational)
    assert full["mass"] == pytest.approx(rho_body * (2 * a) ** 3, rel=1e-12)
    if not rotational:
        assert full["volume"] == pytest.approx((2 * a) ** 3, rel=1e-12)


@pytest.mark.parametrize("lam", [1 / 0.3, 2.0])
def test_body_mass_and_inertia_scale_like_a_similar_solid(lam):
    # a uniform solid block a × b × c of density ρ_s: m = ρ_s abc (λ³), I_z = m (a² + b²)/12 (λ⁵)
    def body(a: float, b: float, c: float) -> dict[str, float]:
        m = 1200.0 * a * b * c
        return {"mass": m, "inertia": m * (a * a + b * b) / 12.0}

    scaled = scale_coefficients(body(0.3, 0.2, 0.1), lam, rotational=True)
    full = body(0.3 * lam, 0.2 * lam, 0.1 * lam)
    assert scaled == {k: pytest.approx(v, rel=1e-12) for k, v in full.items()}
