"""Closed forms that catch one-line mutations of the identification diagnostics (issue #13, item 1).

Written because deliberate mutations passed the whole suite: Reynolds and KC numbers halved,
the per-cycle Reynolds number halved, and the 4/(3π) of the equivalent damping ratio doubled.
Every expected value is worked out here from the launch itself (a closed-form decay or the
record's own peaks), never from the estimator's internals.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.identify.estimators import identify_launch
from hydrokit.identify.types import Launch
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

# a linear free decay q(t) = a0 e^{−σt} (cos ω_d t + σ/ω_d sin ω_d t), released from rest
A0 = 0.04  # m
WN = 7.1  # rad/s (spring rig: √(63.6 / 1.26))
ZETA = 0.03
SIGMA = ZETA * WN
WD = WN * math.sqrt(1 - ZETA**2)


def linear_decay(duration: float = 8.0, rate: float = 200.0) -> Launch:
    t = np.arange(int(duration * rate) + 1) / rate
    y = A0 * np.exp(-SIGMA * t) * (np.cos(WD * t) + SIGMA / WD * np.sin(WD * t))
    return Launch(t=t, y=y, file="closed-form")


def test_reynolds_and_kc_of_a_closed_form_decay(spring_rig):
    # q̇ = −a0 (ω_n²/ω_d) e^{−σt} sin ω_d t peaks at ω_d t* = atan2(ω_d, σ) with
    # |q̇|max = a0 ω_n e^{−σ t*}; Re = U L / ν and KC = U T / L (T = 2π/ω_d)
    res = identify_launch(spring_rig, linear_decay(), "output-error")
    t_star = math.atan2(WD, SIGMA) / WD
    U = A0 * WN * math.exp(-SIGMA * t_star)
    L, nu = spring_rig.reference_length, spring_rig.kinematic_viscosity
    # the estimator samples its fitted velocity on a grid of ≥ 2000 points: (ω Δt)²/8 ≈ 1e-4
    assert res.extra["speed_max"] == pytest.approx(U, rel=2e-3)
    assert res.reynolds_max == pytest.approx(U * L / nu, rel=2e-3)
    assert res.kc == pytest.approx(U * (2 * math.pi / WD) / L, rel=2e-3)


def test_per_cycle_reynolds_follows_the_envelope(spring_rig):
    # peaks of the linear decay fall at t = k T_d/2 with |q| = a0 e^{−σ t} exactly; the
    # log-decrement cycle from a peak at t1 to the next same-sign peak has the geometric-mean
    # amplitude a0 e^{−σ (t1 + T_d/2)} and speed amplitude ω_n times that
    res = identify_launch(spring_rig, linear_decay(), "log-decrement")
    cycles = res.extra["cycles"]
    assert len(cycles) >= 8
    L, nu = spring_rig.reference_length, spring_rig.kinematic_viscosity
    half = math.pi / WD
    for c in cycles:
        amp = A0 * math.exp(-SIGMA * (c["time"] + half))
        # parabolic peak refinement at 200 Hz: amplitude and time good to ~1e-4
        assert c["amplitude"] == pytest.approx(amp, rel=2e-3)
        assert c["reynolds"] == pytest.approx(WN * amp * L / nu, rel=2e-3)


@pytest.mark.parametrize("rest", [0.0, 0.004])
def test_log_decrement_cycles_recover_zeta_and_omega_exactly(spring_rig, rest):
    # a linear decay with ζ = 0.1: every cycle's decrement is δ = 2πζ/√(1 − ζ²) and
    # ζ = δ/√(4π² + δ²) exactly; ω_n = ω_d/√(1 − ζ²). δ² = 0.4 is 1 % of 4π², so the
    # √(4π² ± δ²) sign matters at this damping (not at ζ = 0.03). A rest value ``rest`` away
    # from zero (m) must be found from the peaks and taken off before the ratios.
    zeta, wn, a0 = 0.1, 7.1, 0.04
    sigma, wd = zeta * wn, wn * math.sqrt(1 - zeta**2)
    t = np.arange(2001) / 500.0
    y = a0 * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    res = identify_launch(spring_rig, Launch(t=t, y=y + rest, file="zeta"), "log-decrement")
    cycles = res.extra["cycles"]
    assert len(cycles) >= 4
    for c in cycles:
        # parabolic peak refinement at 500 Hz: ~1e-5 on the ratio of two peaks
        assert c["damping_ratio"] == pytest.approx(zeta, rel=1e-3)
        assert c["natural_frequency"] == pytest.approx(wn, rel=1e-3)


def first_cycle_peak(launch: Launch, period: float) -> float:
    """The positive peak one period after the release, refined by a parabola through 3 samples."""
    t, y = np.asarray(launch.t), np.asarray(launch.y)
    window = (t > 0.5 * period) & (t < 1.5 * period)
    i = int(np.argmax(np.where(window, y, -np.inf)))
    ym, y0, yp = y[i - 1], y[i], y[i + 1]
    return float(y0 - 0.125 * (yp - ym) ** 2 / (yp - 2 * y0 + ym))


@pytest.mark.parametrize("K_L,K_Q", [(0.0, 5.5959), (0.5, 0.0)])
def test_equivalent_damping_ratio_matches_the_first_cycle_decay(spring_rig, K_L, K_Q):
    # Second method: the record's own first-cycle decrement, a0 → a1.
    # Linear damping: ζ = δ/√(4π² + δ²), δ = ln(a0/a1) (exact).
    # Quadratic damping (harmonic balance, Fossen-style c_eq = 8/(3π) c_Q ω a, so
    # ζ_eq(a) = 4 g a/(3π)): d(1/a)/dt = 4 g ω/(3π) over a cycle, 1/a1 − 1/a0 = 8g/3, hence
    # ζ_eq(a0) = (a0/a1 − 1)/(2π).
    m_a, a0 = 0.2866, 0.02
    launch = simulate_launch(spring_rig, m_a, K_L, K_Q, a0, 4.0, SensorModel(1000, 0, 0, 0), rng=0)
    res = identify_launch(spring_rig, launch, "output-error")
    period = 2 * math.pi * math.sqrt((spring_rig.mass + m_a) / spring_rig.stiffness)
    a1 = first_cycle_peak(launch, period)
    if K_Q == 0:
        delta = math.log(a0 / a1)
        # exact for linear damping; the peak refinement at 1 kHz is good to ~1e-8
        assert res.damping_ratio == pytest.approx(delta / math.sqrt(4 * math.pi**2 + delta**2), rel=1e-5)
    else:
        # averaging is first-order in ζ ≈ 0.04: a relative error of ~ζ/10 (0.4 % seen), allow 2 %
        assert res.damping_ratio == pytest.approx((a0 / a1 - 1) / (2 * math.pi), rel=0.02)


def test_encoder_sensor_is_the_cely2019_encoder():
    # CELY2019 spring rig: 2.45 counts/mm, no analogue noise: quantisation only
    enc = SensorModel.encoder()
    assert enc.noise_std == 0.0
    assert enc.resolution == pytest.approx(1e-3 / 2.45, rel=1e-12)
    assert enc.sample_rate == 100.0
