"""The compiled rig integrator against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.identify.rig_model import rig_constants, simulate_normalised, simulate_rig


def test_linear_oscillator_matches_closed_form():
    # q̈ + 2ζω q̇ + ω² q = 0 from q0 = 1, q̇0 = 0: q = e^{-ζωt}(cos ω_d t + ζω/ω_d sin ω_d t)
    w, zeta = 2.0, 0.05
    t = np.linspace(0, 10, 1001)
    q, _, _ = simulate_normalised(t, w * w, 2 * zeta * w, 0.0, 1.0)
    wd = w * math.sqrt(1 - zeta**2)
    exact = np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    # RK4 with 4 substeps of 2.5 ms: global error ~ (ωh)^4 ~ 1e-9
    np.testing.assert_allclose(q, exact, atol=1e-8)


def test_sensitivities_match_finite_differences():
    t = np.linspace(0, 8, 401)
    p = np.array([4.0, 0.2, 0.3, 0.5, 0.1])
    _, _, J = simulate_normalised(t, *p[:3], p[3], p[4], True, 4, True)
    for k in range(5):
        h = 1e-6 * max(1.0, abs(p[k]))
        up, dn = p.copy(), p.copy()
        up[k] += h
        dn[k] -= h
        qu, _, _ = simulate_normalised(t, *up[:3], up[3], up[4], True)
        qd, _, _ = simulate_normalised(t, *dn[:3], dn[3], dn[4], True)
        # central differences are accurate to ~h² · q''' ≈ 1e-10; rounding ~1e-10 / h
        np.testing.assert_allclose(J[:, k], (qu - qd) / (2 * h), atol=1e-6)


def test_quadratic_damping_dissipates_energy(pendulum_rig):
    # with damping the oscillation energy never grows: peaks of |q| decrease
    t = np.linspace(0, 20, 2001)
    q = simulate_rig(pendulum_rig, t, 0.05, 0.02, 0.3, 0.2)
    peaks = [abs(q[i]) for i in range(1, q.size - 1) if abs(q[i]) >= abs(q[i - 1]) and abs(q[i]) >= abs(q[i + 1])]
    assert len(peaks) > 5
    assert all(b < a for a, b in zip(peaks, peaks[1:]))


def test_point_pendulum_constants_reduce_to_P1(pendulum_rig):
    # SPEC P2: α = (B − W)/((m + m_a) r) is −ω² for small angles
    c = rig_constants(pendulum_rig)
    m_a = 0.05
    w2, b, g = c.to_normalised(m_a, 0.02, 0.3)
    r = pendulum_rig.pendulum_length
    alpha = (pendulum_rig.buoyancy - pendulum_rig.weight) / ((pendulum_rig.mass + m_a) * r)
    assert w2 == pytest.approx(-alpha, rel=1e-12)
    assert b == pytest.approx(0.02 / (pendulum_rig.mass + m_a), rel=1e-12)  # β = K_L/(m + m_a)
    assert g == pytest.approx(0.3 * r / (pendulum_rig.mass + m_a), rel=1e-12)  # γ = K_Q r/(m + m_a)
    assert c.from_normalised(w2, b, g) == pytest.approx((m_a, 0.02, 0.3), rel=1e-12)


def test_buoyant_pendulum_is_supported(pendulum_rig):
    from dataclasses import replace

    buoyant = replace(pendulum_rig, volume=3e-4)  # B = 2.9 N > W = 1.43 N: swings above the pivot
    assert buoyant.buoyancy > buoyant.weight
    c = rig_constants(buoyant)
    assert c.S == pytest.approx((buoyant.buoyancy - buoyant.weight) * 0.39)
    q = simulate_rig(buoyant, np.linspace(0, 5, 501), 0.1, 0.01, 0.1, 0.1)
    assert np.max(np.abs(q)) <= 0.1 + 1e-12  # oscillates about the (upright) equilibrium


def test_neutral_pendulum_is_rejected(pendulum_rig):
    from dataclasses import replace

    neutral = replace(pendulum_rig, volume=pendulum_rig.mass / pendulum_rig.density)
    with pytest.raises(InputError, match="no restoring force"):
        rig_constants(neutral)


def test_physical_pendulum_adds_rod_and_body_inertia(pendulum_rig):
    from dataclasses import replace

    r = 0.39
    phys = replace(pendulum_rig, inertia=1e-3, rod_mass=0.05, rod_volume=1e-5)
    c = rig_constants(phys)
    assert c.base_inertia == pytest.approx(0.146 * r * r + 1e-3 + 0.05 * r * r / 3)
    g = phys.gravity
    assert c.S == pytest.approx((phys.weight - phys.buoyancy) * r + (0.05 * g - 998.2 * g * 1e-5) * r / 2)


@pytest.mark.parametrize("a", [0.0, 0.05, 0.4, 1.2])
def test_frequency_ratio_is_the_harmonic_balance_closed_form(a):
    # first-harmonic balance ω(a)²/ω0² = (1/(π a)) ∫ ρ(a cos θ) cos θ dθ, by hand:
    # ρ = q → 1; ρ = sin q → 2 J1(a)/a (the pendulum); ρ = q + a3 q³ + a5 q⁵ → 1 + ¾ a3 a² + ⅝ a5 a⁴;
    # every one → 1 as a → 0 (small oscillations see only ρ'(0) = 1)
    from scipy.special import j1

    from hydrokit.identify.rig_model import LINEAR, SINE, Restoring

    a3, a5 = -0.3, 0.05
    sine = 2.0 * j1(a) / a if a > 0 else 1.0
    assert Restoring(LINEAR).frequency_ratio(a) == 1.0
    assert Restoring(SINE).frequency_ratio(a) == pytest.approx(math.sqrt(sine), rel=1e-12)
    poly = Restoring.polynomial(2.0, 2.0 * a3, 2.0 * a5)
    assert poly.frequency_ratio(a) == pytest.approx(math.sqrt(1 + 0.75 * a3 * a**2 + 0.625 * a5 * a**4), rel=1e-12)
