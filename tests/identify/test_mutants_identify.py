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

from hydrokit.errors import InputError
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
    # the estimator samples its fitted velocity on a grid of 4 points a sample (at least 2000):
    # 6404 points over 8 s, so the peak is missed by at most (ω Δt)²/8 ≈ 1e-5 (2000 points: 1e-4)
    assert res.extra["speed_max"] == pytest.approx(U, rel=1e-5)
    assert res.reynolds_max == pytest.approx(U * L / nu, rel=1e-5)
    # KC uses the period measured from the record's extremes: within 1e-3 of 2π/ω_d here
    assert res.kc == pytest.approx(U * (2 * math.pi / WD) / L, rel=1e-3)


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


# --- second batch (issue #13): survivors of the seed-13 sample -------------------------------


def test_log_decrement_replay_starts_at_the_recorded_release(spring_rig):
    # the rest value 0.004 m is found from the peaks and taken off; the replayed decay must
    # still start where the record starts: q(0) = a0 + rest (closed form, released from rest)
    from hydrokit.identify.estimators import LogDecrementEstimator

    rest = 0.004
    launch = linear_decay()
    y = np.asarray(launch.y) + rest
    est = LogDecrementEstimator(spring_rig).fit(launch.t, y)
    assert est.offset_ == pytest.approx(rest, abs=1e-5)  # geometric peaks: exact up to peak refinement
    # the fitted ζ, ω_n differ from the truth by ~1e-4: the start value does not depend on them
    assert float(est.predict(np.array([0.0]))[0]) == pytest.approx(A0 + rest, rel=1e-4)


@pytest.mark.parametrize(("samples_per_period", "window"), [(48, 9), (54, 9), (60, 11), (30, 7), (90, 15)])
def test_savgol_window_is_the_odd_count_nearest_above_a_sixth_of_a_period(samples_per_period, window):
    # a sixth of the period, rounded; an even count goes up by one (so 48/6 = 8 → 9), at least 7
    from hydrokit.identify.estimators import _savgol_window

    assert _savgol_window(samples_per_period * 0.01, 0.01) == window


def test_jackknife_cycles_are_whole_periods_counted_from_the_release(spring_rig):
    # samples every quarter period from a release at t = 100 s: four to a cycle, cycle 0 first
    # (a 0.5 s period, so that dividing by it and multiplying by it differ)
    from hydrokit.identify.estimators import OutputErrorEstimator

    est = OutputErrorEstimator(spring_rig)
    est.period_ = 0.5
    t = 100.0 + 0.125 * np.arange(13)  # binary fractions: the cycle edges are exact
    assert est._cycles(t).tolist() == [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3]


def test_equivalent_damping_names_the_model_it_came_from(spring_rig):
    # "fitted" keeps the fitted damping model (quadratic by default, or the method itself for
    # the other methods); a cubic fit is its own cubic model, with no refit and no fitted-model
    # columns; the default for a quadratic fit is the cubic refit, the fitted value kept beside it
    from hydrokit.identify.result import fit_launch

    launch = linear_decay()

    def used(method, model, **settings):
        extra = fit_launch(spring_rig, launch, method, [0.02], model, **settings).result.extra
        return extra["equivalent_damping_model"], sorted(extra["equivalent_damping"][0])

    assert used("output-error", "fitted")[0] == "quadratic"
    assert used("log-decrement", "fitted")[0] == "log-decrement"
    assert used("log-decrement", "cubic")[0] == "log-decrement"
    model, keys = used("output-error", "cubic", damping_model="cubic")
    assert model == "cubic" and "value_fitted_model" not in keys
    model, keys = used("output-error", "cubic")
    assert model == "cubic" and "value_fitted_model" in keys


def test_log_decrement_skips_a_pair_of_peaks_that_grows(spring_rig):
    # the closed-form decay (16 same-sign peak pairs in 8 s) with a bump at the fifth positive
    # peak that lifts it above the fourth: that pair grows, has no logarithmic decrement, and is
    # left out (15 cycles, every ζ positive); the pair after it decays the more (ζ > 0.03)
    from hydrokit.identify.estimators import LogDecrementEstimator

    launch = linear_decay()
    t = np.asarray(launch.t)
    y = np.asarray(launch.y) + 0.006 * np.exp(-0.5 * ((t - 4 * 2 * math.pi / WD) / 0.05) ** 2)
    est = LogDecrementEstimator(spring_rig).fit(t, y)
    zetas = [c["damping_ratio"] for c in est.cycles_]
    assert len(zetas) == 15 and min(zetas) > 0
    assert sum(z == pytest.approx(ZETA, rel=0.02) for z in zetas) == 14


def test_significantly_negative_means_below_zero_by_two_standard_errors():
    from hydrokit.identify.estimators import _significantly_negative

    assert _significantly_negative(-0.3, 0.1) and not _significantly_negative(-0.2, 0.1)
    assert not _significantly_negative(0.5, None) and not _significantly_negative(0.0, None)
    assert _significantly_negative(-1e-9, None)  # no standard error: any negative value


@pytest.mark.parametrize(("k_l", "warned"), [(-0.05, True), (-0.0008, False), (0.02, False)])
def test_negative_linear_damping_is_named_only_beyond_two_standard_errors(spring_rig, k_l, warned):
    # a true K_L of −0.05 N·s/m (K_Q = 10 keeps it decaying) is fitted at ≈ −0.05 ± 0.0005: named;
    # −0.0008 (fitted −0.00081 ± 0.00053, 1.5 standard errors) is within two: not named, nor is a
    # positive K_L
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

    launch = simulate_launch(spring_rig, 0.2866, k_l, 10.0, 0.03, 6.0, SensorModel(200.0, 2e-5, 0.0, 0.0), rng=4)
    res = identify_launch(spring_rig, trim_launch(launch), "output-error")
    assert res.std_error["linear_damping"] < 0.001
    named = [w for w in res.warnings if w.startswith("negative linear damping fitted")]
    assert bool(named) == warned


def test_formal_standard_errors_match_the_cramer_rao_bound(spring_rig):
    # white sensor noise σ: the formal σ̂² (JᵀJ)⁻¹ of the output-error fit estimates σ² from the
    # residual sum of squares / (N − p), so it must agree with the Cramér–Rao bound at the true
    # parameters and the known σ (a second computation, no fitted residuals). N ≈ 1600 samples
    # put the σ̂ sampling error near 2 %; the bound is evaluated at the truth, not the estimate
    # (a few % apart): allow 10 %.
    from hydrokit.identify.design import cramer_rao

    truth = (0.2866, 0.5, 5.0)
    sensor = SensorModel(200.0, 2e-5, 0.0, 0.0)
    launch = simulate_launch(spring_rig, *truth, 0.03, 8.0, sensor, rng=3)
    res = identify_launch(spring_rig, launch, "output-error")
    duration = float(launch.t[-1] - launch.t[0])
    crb = cramer_rao(spring_rig, *truth, 0.03, duration, sensor)
    for k in ("added_mass", "linear_damping", "quadratic_damping"):
        assert res.extra["std_error_formal"][k] == pytest.approx(crb[k], rel=0.1), k


def test_plan_relative_errors_are_the_errors_over_the_truth(spring_rig):
    # by definition: "_rel" = standard error / |true value|, and n launches shrink it by 1/√n
    from hydrokit.identify.design import cramer_rao, plan_experiment

    sensor = SensorModel(100.0, 1e-4, 0.0, 0.0)
    truth = {"added_mass": 0.2866, "linear_damping": 0.5, "quadratic_damping": 5.0}
    (row,) = plan_experiment(spring_rig, *truth.values(), [0.03], sensor, duration=6.0, launches=4)
    crb = cramer_rao(spring_rig, *truth.values(), 0.03, 6.0, sensor)
    for k, v in truth.items():
        assert row[k] == pytest.approx(crb[k] / 2.0, rel=1e-12)
        assert row[k + "_rel"] == pytest.approx(crb[k] / 2.0 / v, rel=1e-12)
    assert row["damping_force_rel"] == pytest.approx(crb["damping_force_rel"] / 2.0, rel=1e-12)


def test_outlier_exactly_at_the_threshold_is_kept():
    # the rule flags values *more than* OUTLIER_Z scaled MADs from the median; here the median
    # is 0 and the median |deviation| is 1, so ±Z·1.4826 sit exactly on the line: kept
    from hydrokit.identify.campaign import OUTLIER_Z, outliers

    v = OUTLIER_Z * (1.4826 * 1.0)
    assert not outliers([0.0, 0.0, 0.0, 1.0, -1.0, v, -v]).any()
    assert list(outliers([0.0, 0.0, 0.0, 1.0, -1.0, 1.01 * v, -v])) == [False] * 5 + [True, False]


def test_campaign_document_holds_full_scale_only_when_scaled(spring_rig):
    # issue #2 contract: "full_scale" is added when the rig has a scale, absent otherwise
    from hydrokit.identify.result import CampaignResult

    bare = CampaignResult(rig=spring_rig, method="output-error", launches=[], summary={}, pairwise={}, groups={})
    assert "full_scale" not in bare.to_dict()
    fs = {"added_mass": 12.0, "linear_damping": None}
    scaled = CampaignResult(
        rig=spring_rig, method="output-error", launches=[], summary={}, pairwise={}, groups={}, full_scale=fs
    )
    assert scaled.to_dict()["full_scale"] == fs


def test_gz_table_warning_names_the_last_tabulated_angle():
    # a table that ends at 20°: a 15° launch is inside it (no warning); a 30° launch is beyond
    # it and the warning quotes 20°, the table's last row
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.io.rig import parse_rig

    table = [[0, 0], [10, 0.05], [20, 0.09]]
    body = {"mass": 100.0, "volume": 0.1, "reference_area": 0.5, "reference_length": 1.0, "inertia": 8.0}
    rig_doc = {
        "test": "floating",
        "axis": "roll",
        "gravity": 9.81,
        "fluid": {"density": 1000.0, "kinematic_viscosity": 1.0e-6},
        "body": body,
        "floating": {"gz": table},
    }
    rig = parse_rig(rig_doc, "float.yaml")
    sensor = SensorModel(50.0, 0.0, 0.0, 1.0)
    inside = simulate_launch(rig, 2.0, 1.0, 3.0, math.radians(15.0), 15.0, sensor, 0)
    assert not [w for w in identify_launch(rig, trim_launch(inside)).warnings if "GZ table" in w]
    beyond = simulate_launch(rig, 2.0, 1.0, 3.0, math.radians(30.0), 15.0, sensor, 0)
    (w,) = [w for w in identify_launch(rig, trim_launch(beyond)).warnings if "GZ table" in w]
    assert "last angle 20°" in w


def test_gz_table_restoring_between_rows_is_the_pchip_curve():
    # second method: scipy's PCHIP through the odd-extended table, evaluated between rows
    from scipy.interpolate import PchipInterpolator

    from hydrokit.identify.rig_model import Restoring

    x = np.radians([0.0, 10.0, 20.0, 30.0, 40.0])
    y = np.array([0.0, 0.05, 0.09, 0.11, 0.10])  # m (GZ)
    shape, slope = Restoring.table(x, y)
    ref = PchipInterpolator(np.concatenate([-x[:0:-1], x]), np.concatenate([-y[:0:-1], y]))
    q = np.radians([3.0, 7.5, 14.0, 26.0, 33.0, -17.0])
    assert slope == pytest.approx(float(ref.derivative()(0.0)), rel=1e-12)
    # both are the same cubic Hermite pieces: agreement to rounding
    np.testing.assert_allclose(slope * shape(q), ref(q), rtol=1e-9)


def held_then_released(
    amps: tuple[float, ...], rate: float = 100.0, hold_samples: int = 200
) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Rest → smooth lift → hold (2 s) → release into the closed-form linear decay (12 s), per
    amplitude (m); returns t, y and the index of the last held sample before each release."""
    rng = np.random.default_rng(5)
    td = np.arange(int(12.0 * rate)) / rate
    ys, releases, n0 = [], [], 0
    for a in amps:
        rest = rng.normal(0.0, 2e-5, 100)
        lift = 0.5 * (1 - np.cos(np.linspace(0, np.pi, 150))) * a + rng.normal(0.0, 2e-5, 150)
        hold = a + rng.normal(0.0, 2e-5, hold_samples)
        decay = a * np.exp(-SIGMA * td) * (np.cos(WD * td) + SIGMA / WD * np.sin(WD * td))
        decay[1:] += rng.normal(0.0, 2e-5, td.size - 1)
        releases.append(n0 + 100 + 150 + hold_samples)  # the first decay sample is the held value
        seg = np.concatenate([rest, lift, hold, decay])
        ys.append(seg)
        n0 += seg.size
    y = np.concatenate(ys)
    return np.arange(y.size) / rate, y, releases


def test_split_launches_finds_each_release_of_a_closed_form_session():
    from hydrokit.identify.split import split_launches, still_runs

    t, y, releases = held_then_released((0.04, -0.03))
    segs = split_launches(t, y)
    assert len(segs) == 2
    for s, r in zip(segs, releases):
        assert abs(s.release - r) <= 2  # the detector's index: within two samples (20 ms)
        assert s.start < s.release < s.end
    # still stretches: the rest at the start, each hold; every run starts before it ends
    runs = still_runs(t, y)
    assert runs and all(a < b for a, b in runs)
    assert any(a <= r - 150 and b >= r - 1 for r in releases for a, b in runs)  # a hold is still


def test_split_launches_default_takes_holds_of_one_second():
    # holds of 1.3 s: longer than the default shortest hold (min_hold = 1 s), so every launch is
    # found, each starting the default keep_hold = 1 s before its release (inside the hold);
    # asking for 2 s holds finds none of these releases
    from hydrokit.identify.split import split_launches, still_runs

    t, y, releases = held_then_released((0.04, -0.03, 0.05), hold_samples=130)
    segs = split_launches(t, y)
    assert [abs(s.release - r) <= 2 for s, r in zip(segs, releases)] == [True, True, True]
    assert [round(t[s.release] - t[s.start], 2) for s in segs] == [1.0, 1.0, 1.0]
    assert all(p.end < n.start for p, n in zip(segs, segs[1:]))  # each ends before the next hold
    found = [s.release for s in split_launches(t, y, min_hold=2.0)]
    assert not any(abs(f - r) <= 2 for f in found for r in releases)
    # the still-run finder has the same default: each 1.3 s hold is one still run
    runs = still_runs(t, y)
    assert [any(a <= r - 129 and b >= r - 1 for a, b in runs) for r in releases] == [True, True, True]
    assert runs == still_runs(t, y, min_hold=1.0) != still_runs(t, y, min_hold=2.0)


def test_a_coarse_decay_after_a_hold_is_released_at_the_hold_end():
    # rest 1.5 s, smooth lift, 1.5 s hold (its last still sample is 399), then a decay sampled 8
    # times a period, too coarse to fit the hand before the release: the release is the hold's
    # last still sample (it was once where the lift crossed the band, 1 s early). 60 samples of
    # decay make a launch; 19 (fewer than MIN_SAMPLES from the hold's end) make none
    from hydrokit.identify.preprocess import MIN_SAMPLES
    from hydrokit.identify.split import split_launches, still_runs

    found = {}
    for n in (MIN_SAMPLES - 1, 60):
        k = np.arange(1, n + 1)
        decay = 0.05 * np.exp(-0.02 * k) * np.cos(2 * np.pi / 8 * k)
        lift = 0.025 * (1 - np.cos(np.linspace(0, np.pi, 100)))
        y = np.concatenate([np.zeros(150), lift, np.full(150, 0.05), decay])
        y += np.random.default_rng(0).normal(0.0, 1e-5, y.size)
        t = np.arange(y.size) / 100.0
        assert still_runs(t, y)[-1][1] == 399  # the hold's last still sample
        found[n] = [(s.start, s.release, s.end > 440) for s in split_launches(t, y)]
    assert found == {MIN_SAMPLES - 1: [], 60: [(299, 399, True)]}


def test_a_hold_released_into_a_coarsely_sampled_decay_releases_at_its_end():
    # rest 2 s, a 1 s lift, held until 5.0 s, then a 1 s-period decay, read with 1 mm of noise at
    # 6, 8 and 12 samples a period: too few to fit the hand, so the hold's last sample within
    # 2 % of its level is the release — 5.0 s exactly, a sample of each grid
    from hydrokit.identify.preprocess import detect_release

    for fs in (6.0, 8.0, 12.0):
        t = np.arange(0.0, 20.0, 1.0 / fs)
        s = np.maximum(t - 5.0, 0.0)
        y = np.where(t < 2, 0.0, np.where(t < 3, t - 2, 1.0))
        y = np.where(t < 5.0, y, np.exp(-0.1 * s) * np.cos(2 * np.pi * s))
        y = y + np.random.default_rng(1).normal(0.0, 1e-3, t.size)
        assert detect_release(t, y) == pytest.approx(5.0, abs=1e-12), fs


def test_a_dropout_over_the_release_falls_back_to_the_last_held_sample():
    # the record above at 200 Hz, with the samples from 4.74 s to 5.11 s lost (a logger dropout):
    # plenty of samples around the release half cycle but none where the join is searched, so no
    # join can be fitted; the release is the hold's last sample before the gap
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(0.0, 20.0, 1.0 / 200.0)
    t = t[(t < 4.74) | (t > 5.11)]
    s = np.maximum(t - 5.0, 0.0)
    y = np.where(t < 2, 0.0, np.where(t < 3, t - 2, 1.0))
    y = np.where(t < 5.0, y, np.exp(-0.1 * s) * np.cos(2 * np.pi * s))
    y = y + np.random.default_rng(1).normal(0.0, 1e-3, t.size)
    assert detect_release(t, y) == pytest.approx(t[t < 4.74][-1], abs=1e-12)


def test_find_release_of_a_record_without_free_decay_is_its_first_sample():
    # still noise, a slow drift and a growing oscillation hold no free decay (detect_release
    # raises); find_release then points at the first sample and leaves the verdict to
    # check_record, which ingest calls next
    from hydrokit.identify.preprocess import detect_release
    from hydrokit.identify.split import find_release

    t = np.arange(0.0, 10.0, 0.01)
    noise = np.random.default_rng(0).normal(0.0, 1e-3, t.size)
    for y in (noise, 0.1 * t + noise, np.exp(0.1 * t) * np.sin(2 * np.pi * t)):
        with pytest.raises(InputError):
            detect_release(t, y)
        assert find_release(t, y) == 0


@pytest.mark.parametrize("zeta", [0.03, 0.2])
def test_release_time_of_a_hand_decelerating_into_the_release(zeta):
    # before the release the hand brings the body to rest at q0 with constant deceleration
    # (q = q0 − c s², s < 0), after it the closed-form linear decay from rest: the detector's
    # pre-release quadratic and post-release free response are both exact, so the best join is
    # the true release time t_r. Noise-free at 1 kHz; the detector takes period and decrement
    # from sample-index extremes (1 ms in T ≈ 1 s), which leaves ~1e-5 s: allow 2 % of a sample.
    # At ζ = 0.2 the ω_n = ω_d/√(1 − ζ²) correction moves the join by ~1e-4 s if it is wrong.
    wn, q0, c, tr = 6.0, 0.05, 0.3, 1.2345
    sigma, wd = zeta * wn, wn * math.sqrt(1 - zeta**2)
    t = np.arange(12001) / 1000.0
    s = t - tr
    sp = np.maximum(s, 0.0)
    free = q0 * np.exp(-sigma * sp) * (np.cos(wd * sp) + sigma / wd * np.sin(wd * sp))
    y = np.where(s < 0, np.maximum(q0 - c * s * s, 0.0), free)
    from hydrokit.identify.preprocess import detect_release

    assert detect_release(t, y, sigma=1e-9) == pytest.approx(tr, abs=2e-5)


# --- survivors of the seed-29 mutation sample (bench/mutation.py --sample 15 --seed 29) --------


def test_simulated_velocity_starts_at_the_given_initial_velocity() -> None:
    # the first sample is the initial state itself: q(0) = q0, q̇(0) = v0 (a released body may
    # be moving); then q̇ = dq/dt of the undamped closed form q0 cos ωt + v0/ω sin ωt
    from hydrokit.identify.rig_model import simulate_normalised

    w = 2.0
    t = np.linspace(0.0, 1.0, 201)
    q, v, _ = simulate_normalised(t, w * w, 0.0, 0.0, 0.1, v0=0.3, substeps=8)
    assert (q[0], v[0]) == (0.1, 0.3)
    np.testing.assert_allclose(v, -0.1 * w * np.sin(w * t) + 0.3 * np.cos(w * t), atol=1e-8)


def test_quantised_sensor_without_random_zero_reads_whole_steps() -> None:
    # an encoder whose zero is at the origin: every reading is a whole number of steps
    from hydrokit.identify.virtual_rig import SensorModel

    s = SensorModel(resolution=3e-4)  # m; 1/3e-4 is no whole number, so a shifted grid shows
    y = np.linspace(-0.01, 0.01, 333)
    out = s.measure(y, np.random.default_rng(0))
    steps = out / s.resolution
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-9)
    assert np.max(np.abs(out - y)) <= s.resolution / 2 + 1e-15


def test_amplitude_window_that_the_record_never_leaves_ends_at_its_last_extreme() -> None:
    # a decay from 1.0 that never falls below LO: the window runs to the record's end and its
    # end amplitude is the last extreme, e^(−ζ ω t) of the last half-cycle (closed form)
    from hydrokit.identify.preprocess import _amplitude_window

    zeta, w = 0.01, 2 * np.pi
    t = np.arange(0.0, 4.0, 0.001)
    z = np.exp(-zeta * w * t) * np.cos(w * np.sqrt(1 - zeta**2) * t)
    i0, i1, info = _amplitude_window(t, z, 0.0, (0.99, 0.05), "rec")
    assert i1 == z.size - 1
    last_peak = np.max(np.abs(z[int(3.4 / 0.001) :]))  # the half-cycle extreme near t = 3.5 s
    assert info["end_amplitude"] == pytest.approx(float(last_peak), rel=1e-9)
    assert info["end_amplitude"] < info["start_amplitude"]


def test_peaks_refines_the_extreme_one_sample_before_the_record_ends():
    # the half cycle z = 0.5, 1.0 ends at the last sample (−1.0, beyond the band): its extreme,
    # at the last-but-one sample, is refined like any other by the parabola through 0.5, 1, −1:
    # vertex offset d = ½(y0 − y2)/(y0 − 2y1 + y2) = −0.3 samples, height 1 − ¼(y0 − y2)d = 1.1125
    from hydrokit.identify.estimators import _peaks

    t = np.array([0.0, 0.1, 0.2, 0.3])
    ((tp, ap),) = _peaks(t, np.array([0.0, 0.5, 1.0, -1.0]), 0.1)
    assert tp == pytest.approx(0.2 - 0.3 * 0.1, rel=1e-12)
    assert ap == pytest.approx(1.1125, rel=1e-12)


def test_camera_sensor_defaults_to_30_fps_and_a_fifth_of_a_degree():
    # ENG2009 filmed the rod at 30 fps; 0.2° is the tracking noise assumed for such video
    from hydrokit.identify.virtual_rig import SensorModel

    cam = SensorModel.camera()
    assert (cam.sample_rate, cam.noise_std, cam.resolution) == (30.0, pytest.approx(math.radians(0.2)), 0.0)
    assert cam.name == "camera 30 fps, 0.2° noise"
    # CELY2019's pendulum IMU: 100 Hz; its angle noise, 0.05°, is stored in rad
    imu = SensorModel.imu()
    assert (imu.sample_rate, imu.noise_std, imu.resolution) == (100.0, pytest.approx(math.radians(0.05)), 0.0)
    assert imu.name == "IMU 100 Hz, 0.05° noise"


def grabbed_session(a1: float = 0.04, a2: float = -0.03) -> tuple[np.ndarray, np.ndarray]:
    """Rest 1 s, lift, hold at a1 (m) for 2 s, released (sample 450), grabbed 4 s later while still
    swinging and lifted into a hold at a2 for 2 s, released again: t (s, 100 Hz) and y (m)."""
    rate = 100.0
    ramp = 0.5 * (1 - np.cos(np.linspace(0, np.pi, 150)))
    td = np.arange(400) / rate
    dec1 = a1 * np.exp(-SIGMA * td) * (np.cos(WD * td) + SIGMA / WD * np.sin(WD * td))
    grab = dec1[-1] + (a2 - dec1[-1]) * ramp
    td2 = np.arange(1200) / rate
    dec2 = a2 * np.exp(-SIGMA * td2) * (np.cos(WD * td2) + SIGMA / WD * np.sin(WD * td2))
    y = np.concatenate([np.zeros(100), a1 * ramp, np.full(200, a1), dec1, grab, np.full(200, a2), dec2])
    y += np.random.default_rng(5).normal(0.0, 2e-5, y.size)
    return np.arange(y.size) / rate, y


def test_a_launch_grabbed_mid_decay_ends_at_its_last_pass_near_the_rest_value():
    # hold at 4 cm, released, grabbed after 4 s (still swinging) and lifted into a −3 cm hold.
    # The launch must end at its last sample near the rest value before the grab: within the
    # band max(4σ, 2 % of the hold's height above it) of the motion's median (the rest value
    # the splitter sees between this hold and the next), not a sample later
    from hydrokit.identify.split import split_launches, still_runs

    a1 = 0.04
    t, y = grabbed_session(a1)
    first = split_launches(t, y)[0]
    assert first.release == pytest.approx(450, abs=2)
    nxt = next(a for a, _ in still_runs(t, y) if a > first.release)  # the next hold starts
    motion = y[first.release + 1 : nxt]
    centre = float(np.median(motion))
    near = np.nonzero(np.abs(motion - centre) <= 0.02 * abs(a1 - centre))[0] + first.release + 1
    assert first.end == near[-1] < 850  # before the grab (sample 850 on)


def test_adequacy_without_a_period_measures_no_autocorrelation():
    # an unknown (NaN) period: no lag to correlate at; the verdict rests on the noise ratio alone
    from hydrokit.identify.estimators import adequacy

    r = np.random.default_rng(0).normal(0.0, 1e-3, 500)
    out = adequacy(r, np.arange(500) * 0.01, float("nan"), 1e-3)
    assert out["acf_at_period"] is None and out["acf_at_half_period"] is None
    assert out["residual_to_noise"] == pytest.approx(1.0, rel=0.1)
    assert out["verdict"].startswith("adequate")


def test_adequacy_calls_white_residuals_up_to_twice_the_noise_adequate():
    # the documented rule: adequate when RMS ≤ 2× the noise and |ρ(T)| < 0.3. White residuals
    # (ρ(T) ≈ 0): exactly 2× the noise is adequate (the edge belongs to it), 2.5× is not
    from hydrokit.identify.estimators import adequacy

    r = np.random.default_rng(3).normal(0.0, 1.0, 2000)
    r -= r.mean()
    rms = float(np.sqrt(np.mean(r**2)))
    t = np.arange(r.size) * 0.01
    edge = adequacy(r, t, 0.5, rms / 2.0)  # division by two is exact: the ratio is 2.0 exactly
    assert edge["residual_to_noise"] == 2.0 and abs(edge["acf_at_period"]) < 0.1
    assert edge["verdict"].startswith("adequate")
    above = adequacy(r, t, 0.5, rms / 2.5)
    assert above["residual_to_noise"] == pytest.approx(2.5)
    assert above["verdict"].startswith("residual above the noise floor (2× the noise)")  # 2.5 → "2"


def test_default_sensor_holds_half_a_second_before_the_release():
    from hydrokit.identify.types import Rig
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

    rig = Rig("spring", "surge", 9.81, 1000.0, 1e-6, 0.97, 344868e-9, 0.008, 0.09, stiffness=63.6)
    sensor = SensorModel()
    assert sensor.hold_time == 0.5
    # SensorModel's docstring: the named sensors hold as long by default
    assert [s().hold_time for s in (SensorModel.imu, SensorModel.encoder, SensorModel.camera)] == [0.5] * 3
    launch = simulate_launch(rig, 0.3, 0.8, 0.0, A0, 4.0, sensor, rng=0)
    assert np.all(launch.y[:50] == A0) and launch.y[51] < A0  # 50 samples at 100 Hz, then it moves


def test_slow_rigs_start_the_output_error_fit_from_the_other_methods_too():
    # a rig slower than 1 rad/s (ω² < 1 1/s²) still gets the equation-error and log-decrement
    # estimates as starting points, besides the one from the period alone
    from hydrokit.identify.estimators import OutputErrorEstimator
    from hydrokit.identify.preprocess import check_record, trim_launch
    from hydrokit.identify.types import Rig
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

    rig = Rig("spring", "surge", 9.81, 1000.0, 1e-6, 10.0, 0.005, 0.05, 0.3, stiffness=5.0)
    launch = trim_launch(simulate_launch(rig, 2.0, 0.5, 0.0, 0.05, 60.0, SensorModel(20.0, 1e-5), rng=1))
    est = OutputErrorEstimator(rig).fit(launch.t, launch.y)
    assert est.p_[0] == pytest.approx(5.0 / 12.0, rel=0.01)  # ω² = k/(m + m_a) < 1
    facts = check_record(launch)
    starts = est._starts(launch.t - launch.t[0], launch.y, facts)
    assert len(starts) == 3 and starts[0][0] == pytest.approx(5.0 / 12.0, rel=0.05)


def test_adequacy_with_a_period_as_long_as_the_record_has_no_autocorrelation_there():
    from hydrokit.identify.estimators import adequacy

    r = np.random.default_rng(1).normal(0.0, 1e-3, 400)
    out = adequacy(r, np.arange(400) * 0.01, 4.0, 1e-3)  # one period = 400 samples: no pairs
    assert out["acf_at_period"] is None
    assert out["acf_at_half_period"] == pytest.approx(float(r[:-200] @ r[200:]) / float(r @ r), abs=0.05)


def test_a_fit_without_a_restoring_omega_squared_is_refused(spring_rig, monkeypatch):
    # ω² ≤ 0 (or not finite) is no oscillation: whatever a fit returns, the coefficients are not
    # formed from it. A real decay never fits so; the fit is made to return −ω² here
    from hydrokit.errors import InputError
    from hydrokit.identify.estimators import EquationErrorEstimator

    fit = EquationErrorEstimator._fit

    def flipped(self, t, y, facts):  # noqa: ANN001, ANN202
        fit(self, t, y, facts)
        w2, b, g = self.p_
        self.p_ = (-w2, b, g)

    launch = linear_decay()
    assert identify_launch(spring_rig, launch, "equation-error").added_mass > 0
    monkeypatch.setattr(EquationErrorEstimator, "_fit", flipped)
    with pytest.raises(InputError, match=r"fitted ω² = -\d.* 1/s²: not a restoring oscillation"):
        identify_launch(spring_rig, launch, "equation-error")


def test_air_tare_is_immutable():
    # one tare is applied to every launch of a campaign: it must not change under them
    import dataclasses

    from hydrokit.identify.tare import AirTare

    tare = AirTare(0.5, 0.1, 0.02)
    with pytest.raises(dataclasses.FrozenInstanceError):
        tare.linear_damping = 0.0  # type: ignore[misc]
    assert {tare: 1}[AirTare(0.5, 0.1, 0.02)] == 1  # frozen dataclasses hash by value
    # so is a sensor model: one model records every launch of a virtual campaign
    sensor = SensorModel.imu()
    with pytest.raises(dataclasses.FrozenInstanceError):
        sensor.noise_std = 0.0  # type: ignore[misc]


def test_simulate_rig_defaults_to_four_rk4_substeps_within_the_closed_form(spring_rig):
    # the documented default (4 RK4 steps per sample) against the linear decay's closed form:
    # at 200 Hz the global RK4 error is ~ ω t (ω h)⁴ / 120 ≈ 1e-9 of the amplitude
    from hydrokit.identify.rig_model import rig_constants, simulate_normalised, simulate_rig

    t = np.arange(1601) / 200.0
    y = simulate_rig(spring_rig, t, 0.3, 0.5, 0.0, A0)
    np.testing.assert_array_equal(y, simulate_rig(spring_rig, t, 0.3, 0.5, 0.0, A0, substeps=4))
    w2, b, _ = rig_constants(spring_rig).to_normalised(0.3, 0.5, 0.0)
    q, _, _ = simulate_normalised(t, w2, b, 0.0, A0)  # the same integrator and default underneath
    np.testing.assert_array_equal(q, y)
    assert not np.array_equal(y, simulate_rig(spring_rig, t, 0.3, 0.5, 0.0, A0, substeps=5))
    w2, b, _ = rig_constants(spring_rig).to_normalised(0.3, 0.5, 0.0)
    s, wd = b / 2, math.sqrt(w2 - b * b / 4)
    exact = A0 * np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    assert np.max(np.abs(y - exact)) < 1e-8 * A0


@pytest.mark.parametrize("test", ["spring", "torsion"])
@pytest.mark.parametrize("stiffness", [0.0, -1.0, float("nan"), None])
def test_a_spring_or_torsion_rig_needs_a_positive_stiffness(spring_rig, test, stiffness):
    import dataclasses

    from hydrokit.errors import InputError
    from hydrokit.identify.rig_model import rig_constants

    rig = dataclasses.replace(spring_rig, test=test, axis="yaw" if test == "torsion" else "surge", inertia=0.01)
    assert rig_constants(rig).S == spring_rig.stiffness
    assert rig_constants(dataclasses.replace(rig, stiffness=0.5)).S == 0.5  # a soft torsion wire: fine
    with pytest.raises(InputError, match=rf"{test}.stiffness = {stiffness}: expected a positive number"):
        rig_constants(dataclasses.replace(rig, stiffness=stiffness))


def test_an_end_time_on_the_last_sample_is_within_the_record():
    from hydrokit.errors import InputError
    from hydrokit.identify.preprocess import trim_launch

    launch = linear_decay()
    t = np.asarray(launch.t)
    assert trim_launch(launch, release=0.0, end=float(t[-1])).t[-1] == pytest.approx(t[-1] - t[0])
    with pytest.raises(InputError, match=r"end = 8\.01 s: expected a time after the release"):
        trim_launch(launch, release=0.0, end=8.01)


@pytest.mark.parametrize("cycles", [3.3, 4.2])
def test_the_rest_value_is_the_mean_over_whole_cycles_of_the_second_half(cycles):
    # a decay about c = 0.01 (amplitude 0.1) whose first guess of the rest value is pulled 3–33 %
    # of the amplitude away by the partial cycle at its end; the mean between the last two
    # same-direction crossings (one whole cycle) is off only by the decay within that cycle,
    # 1.6–1.9 % of the amplitude here: 2.5 % is the bound
    from hydrokit.identify.preprocess import check_record

    t = np.arange(int(cycles * 200)) / 200.0
    y = 0.01 + 0.1 * np.exp(-0.15 * t) * np.cos(2 * math.pi * t)
    y += np.random.default_rng(0).normal(0.0, 1e-4, t.size)
    assert abs(check_record(Launch(t, y, "offset")).get("offset") - 0.01) < 0.0025


def test_nearest_sample_rounds_to_the_closer_neighbour():
    from hydrokit.identify.preprocess import _nearest

    t = np.array([0.0, 1.0, 2.0, 3.0])
    assert [_nearest(t, x) for x in (-0.5, 0.4, 0.6, 1.9, 2.2, 9.0)] == [0, 0, 1, 2, 2, 3]


def test_a_lightly_damped_decay_of_three_cycles_is_free_from_the_start():
    # six extremes falling 1.5 % over two cycles (ζ = 0.0012): under the 2 % band a short record's
    # first-to-last rule needs, but a steady fall for the trend test over six extremes
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(601) / 200.0
    y = 0.1 * np.exp(-0.0012 * 2 * math.pi * t) * np.cos(2 * math.pi * t)
    y += np.random.default_rng(1).normal(0.0, 2e-5, t.size)
    assert 0.0 <= detect_release(t, y) < 0.1


@pytest.mark.parametrize("fixture", ["spring_rig", "pendulum_rig", "torsion_rig"])
def test_covariance_jacobian_is_the_derivative_of_the_unit_map(fixture, request):
    # second method: central differences of from_normalised at a typical fitted (ω², b, g);
    # the pendulum's and the torsion rig's factors (r, r², r³; L/2) make every entry differ
    from hydrokit.identify.rig_model import rig_constants

    c = rig_constants(request.getfixturevalue(fixture))
    p = np.array(c.to_normalised(0.4 * c.base_inertia, 0.05 * c.base_inertia, 0.3 * c.base_inertia))
    J = c.jacobian_from_normalised(*p)
    numeric = np.zeros((3, 3))
    for k in range(3):
        h = np.zeros(3)
        h[k] = 1e-6 * p[k]
        numeric[:, k] = (np.array(c.from_normalised(*(p + h))) - np.array(c.from_normalised(*(p - h)))) / (2 * h[k])
    np.testing.assert_allclose(J, numeric, rtol=1e-6, atol=1e-9 * np.abs(numeric).max())


@pytest.mark.parametrize("duration, cycles", [(2.1, 3), (2.5, 4)])
def test_log_decrement_slope_variance_is_scipys_linregress(spring_rig, duration, cycles):
    # g = 3π/4 κ from the straight line ζ = ζ_L + κ a through the cycles: its variance is
    # (3π/4)² times the OLS slope variance with n − 2 degrees of freedom (scipy.stats.linregress,
    # a second method); three cycles leave one degree of freedom
    from scipy import stats

    from hydrokit.identify.rig_model import simulate_rig

    t = np.arange(int(duration * 200) + 1) / 200.0
    y = simulate_rig(spring_rig, t, 0.3, 0.5, 30.0, 0.05) + np.random.default_rng(0).normal(0, 1e-5, t.size)
    _, est = identify_launch(spring_rig, Launch(t, y, "short"), "log-decrement", return_estimator=True)
    a = [c["amplitude"] for c in est.cycles_]
    assert len(a) == cycles
    fit = stats.linregress(a, [c["damping_ratio"] for c in est.cycles_])
    assert est.p_[2] == pytest.approx(3 * math.pi / 4 * fit.slope, rel=1e-9)
    assert est.pcov_[2, 2] == pytest.approx((3 * math.pi / 4 * fit.stderr) ** 2, rel=1e-6)


def test_a_release_or_end_leaving_fewer_than_twenty_samples_is_refused():
    # the release is inside the record, but what follows it is too short to be a launch: one
    # line naming both ends, not a 1-sample launch for the estimator to trip over
    from hydrokit.errors import InputError
    from hydrokit.identify.preprocess import MIN_SAMPLES, trim_launch

    launch = linear_decay()
    t = np.asarray(launch.t)
    assert trim_launch(launch, release=float(t[-MIN_SAMPLES])).t.size == MIN_SAMPLES
    # (the last two hold nothing above the noise either: too short is said first)
    for release, n in (
        (float(t[-MIN_SAMPLES + 1]), "19 samples"),
        (float(t[-2]), "2 samples"),
        (float(t[-1]) - 0.001, "1 sample"),
    ):
        with pytest.raises(
            InputError,
            match=rf"the launch from the release \(given, t = .* to the end .* holds {n}; expected at least 20",
        ):
            trim_launch(launch, release=release)
    with pytest.raises(InputError, match=r"holds 11 samples; expected at least 20"):
        trim_launch(launch, release=1.0, end=1.05)
    with pytest.raises(InputError, match=r"release = 8\.0 s: expected a time within the record \[0, 8\] s"):
        trim_launch(launch, release=8.0)


def test_every_extreme_is_refined_by_its_parabola_even_on_the_second_sample():
    # z = cos(ω(t − t_p)) sampled so that the first maximum falls 0.3 samples after sample 1:
    # the parabola through samples 0, 1, 2 puts it within (ω h)² of t_p, and every later
    # extreme too; the raw sample would be 0.3 h off
    from hydrokit.identify.estimators import _peaks

    h, w = 0.01, 2 * math.pi
    tp = 1.3 * h
    t = np.arange(301) * h
    z = np.cos(w * (t - tp))
    peaks = _peaks(t, z, 0.05)
    assert len(peaks) == 6  # t_p + k/2 s, k = 0 … 5 (the half cycle cut by the end at 3 s is skipped)
    for k, (time, value) in enumerate(peaks):
        assert time == pytest.approx(tp + 0.5 * k, abs=0.01 * h)
        assert abs(value) == pytest.approx(1.0, abs=(w * h) ** 2)


@pytest.mark.parametrize("detrend", ["mean", "linear", "none"])
def test_trim_reports_the_rest_line_it_removed(detrend):
    # a decay about the rest line 0.01 + 0.002 t: "linear" removes (and reports) both terms,
    # "mean" only the offset at the release (slope 0), "none" nothing
    from hydrokit.identify.preprocess import trim_launch

    base = linear_decay()
    t = np.asarray(base.t)
    launch = Launch(t, np.asarray(base.y) + 0.01 + 0.002 * t, "drift")
    info = trim_launch(launch, release=0.0, detrend=detrend).info["detrend"]
    assert info["method"] == detrend
    if detrend == "linear":
        assert (info["offset"], info["slope"]) == (pytest.approx(0.01, abs=1e-4), pytest.approx(0.002, abs=1e-4))
    elif detrend == "mean":
        # the rest value at the release (the rest line's intercept), the drift left in the record
        assert info["slope"] == 0.0 and info["offset"] == pytest.approx(0.01, abs=1e-4)
    else:
        assert (info["offset"], info["slope"]) == (0.0, 0.0)


def test_the_morison_fit_has_no_linear_damping(spring_rig):
    # CELY2019's Morison variant fits K_Q alone: K_L is zero by construction, not fitted small
    res = identify_launch(spring_rig, linear_decay(), "morison")
    assert res.linear_damping == 0.0 and res.quadratic_damping > 0


@pytest.mark.parametrize("duration", [0.0, -1.0, math.inf, math.nan])
def test_a_virtual_launch_needs_a_positive_finite_duration(spring_rig, duration):
    from hydrokit.errors import InputError

    with pytest.raises(InputError, match=rf"duration = {duration}: expected a positive time \(s\)"):
        simulate_launch(spring_rig, 0.3, 0.5, 30.0, A0, duration, SensorModel(200.0, 0, 0, 0), rng=0)


@pytest.mark.parametrize("rate, ok", [(0.5, True), (0.0, False), (-10.0, False)])
def test_a_slow_sensor_is_valid_a_zero_rate_is_not(rate, ok):
    # a 0.5 Hz sample rate (a diver's stopwatch readings) is slow but a rate; 0 Hz is none
    from hydrokit.errors import InputError

    if ok:
        assert SensorModel(rate).sample_rate == rate
    else:
        with pytest.raises(InputError, match=rf"sample_rate = {rate}: expected a positive number \(Hz\)"):
            SensorModel(rate)


def test_torsion_re_and_kc_use_the_tip_speed(torsion_rig):
    # a body turning on a torsion spring: its tip, L/2 from the axis, moves at (L/2)|φ̇|
    from hydrokit.identify.preprocess import trim_launch

    L = torsion_rig.reference_length
    launch = simulate_launch(
        torsion_rig, 0.005, 0.002, 0.004, math.radians(20), 20.0, SensorModel(200.0, 0, 0, 0), rng=0
    )
    res = identify_launch(torsion_rig, trim_launch(launch), "output-error")
    t, y = np.asarray(launch.t), np.asarray(launch.y)
    rate = float(np.max(np.abs(np.gradient(y, t))))  # rad/s
    assert res.extra["speed_max"] == pytest.approx(0.5 * L * rate, rel=0.01)


def test_extended_sensitivities_are_finite_differences_of_the_solution():
    # ∂q/∂(ω², b, g, d, a3, a5, q0, v0) integrated with the state, against central differences
    # of the solution itself, with every parameter (C3 and C5 included) non-zero
    from hydrokit.identify.rig_model import simulate_extended

    t = np.arange(401) / 100.0
    p = np.array([9.0, 0.2, 0.8, 0.3, -0.2, 0.05])
    q0, v0 = 0.5, 0.1
    _, _, J = simulate_extended(t, p, q0, v0, None, 8, True)
    x = np.concatenate([p, [q0, v0]])
    for k in range(8):
        h = 1e-6 * max(abs(x[k]), 1.0)
        up, dn = x.copy(), x.copy()
        up[k] += h
        dn[k] -= h
        qu = simulate_extended(t, up[:6], up[6], up[7], None, 8)[0]
        qd = simulate_extended(t, dn[:6], dn[6], dn[7], None, 8)[0]
        np.testing.assert_allclose(J[:, k], (qu - qd) / (2 * h), rtol=1e-5, atol=1e-7 * np.abs(J[:, k]).max())


def test_the_air_tare_rms_residual_is_the_equation_residual_of_the_fit():
    # second method: the residual of θ̈ = α sin θ − β θ̇ − γ|θ̇|θ̇ + c cos θ recomputed from the
    # smoothed launch with the reported coefficients and rest value
    from hydrokit.identify.tare import _smooth, fit_air_tare

    rng = np.random.default_rng(7)
    t = np.arange(1501) / 50.0
    from scipy.integrate import solve_ivp

    r, beta, gamma = 0.4, 0.05, 0.1
    sol = solve_ivp(
        lambda _t, z: (z[1], -(9.81 / r) * math.sin(z[0]) - beta * z[1] - gamma * abs(z[1]) * z[1]),
        (0, t[-1]), (0.5, 0.0), t_eval=t, rtol=1e-11, atol=1e-13,
    )  # fmt: skip
    launch = Launch(t, sol.y[0] + 0.002 + rng.normal(0, 2e-4, t.size), "air")
    _, fit = fit_air_tare([launch], 1.0, 9.81)
    s = _smooth(launch, fit["windows"][0], 4)
    c = -fit["alpha"] * fit["rest_values"][0]
    e = s.qdd - (fit["alpha"] * np.sin(s.q) - fit["beta"] * s.qd - fit["gamma"] * np.abs(s.qd) * s.qd + c * np.cos(s.q))
    assert fit["rms_residual"] == pytest.approx(math.sqrt(float(e @ e) / e.size), rel=1e-9)


def test_a_decay_released_below_the_rest_value_counts_the_same_cycles():
    # the mirror image −q of a decay crosses the rest value at the same samples: the same cycles
    # and period; and the count is the record's own sign changes (no noise: the hysteresis band
    # is zero) halved
    from hydrokit.identify.preprocess import check_record

    launch = linear_decay()
    up = check_record(launch)
    down = check_record(Launch(launch.t, -launch.y, "mirrored"))
    changes = int(np.count_nonzero(np.diff(np.sign(launch.y)) != 0))
    assert up["cycles"] == down["cycles"] == changes / 2.0
    assert down["period"] == pytest.approx(up["period"], rel=1e-12)
    assert up["period"] == pytest.approx(2 * math.pi / WD, rel=2e-3)


def test_the_rest_value_equals_the_closed_form_mean_of_the_second_half_cycles():
    # a clean decay about 0.01 m: the documented rest value is the record's mean over the whole
    # cycles between the first and last same-direction crossings in its second half. For the
    # linear decay, q = −(q̈ + 2σ q̇)/ω_n², so between two zeros ∫q dt = −[q̇]/ω_n² exactly; the
    # downward zeros fall at ω_d t = φ + π/2 + 2kπ, φ = atan(σ/ω_d)
    from hydrokit.identify.preprocess import check_record

    launch = linear_decay()
    t = launch.t
    phi = math.atan2(SIGMA, WD)
    zeros = (phi + math.pi / 2 + 2 * math.pi * np.arange(20)) / WD
    inside = zeros[(zeros >= t[t.size // 2]) & (zeros < t[-1])]
    ta, tb = inside[0], inside[-1]

    def rate(x):
        return -A0 * WN**2 / WD * math.exp(-SIGMA * x) * math.sin(WD * x)

    mean = -(rate(tb) - rate(ta)) / WN**2 / (tb - ta)
    facts = check_record(Launch(t, launch.y + 0.01, "offset"))
    # samples stand for the integral to ~1e-5 A0 at 200 Hz; the bias itself is ~1e-2 A0
    assert facts["offset"] - 0.01 == pytest.approx(mean, abs=1e-4 * A0)
    assert abs(mean) > 20 * 1e-4 * A0


def test_rig_constants_are_immutable(spring_rig):
    # one RigConstants is shared by an estimator, its replays and the derived coefficients
    import dataclasses

    from hydrokit.identify.rig_model import rig_constants

    c = rig_constants(spring_rig)
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.S = 2.0 * c.S


@pytest.mark.parametrize("damping_model", ["quadratic", "cubic"])
def test_the_residual_warning_states_the_fit_own_rms(spring_rig, damping_model):
    # a second mode the rig equation cannot hold (2.3 ω_n, steady): the fit warns, and the RMS it
    # names is the record minus the fitted model's replay, recomputed here from predict()
    from hydrokit.identify.estimators import OutputErrorEstimator

    launch = linear_decay()
    y = launch.y + 0.002 * np.sin(2.3 * WN * launch.t)
    est = OutputErrorEstimator(spring_rig, damping_model=damping_model).fit(launch.t, y)
    rms = float(np.sqrt(np.mean((est.predict(launch.t) - y) ** 2)))
    said = [w for w in est.warnings_ if w.startswith("RMS residual")]
    assert len(said) == 1
    assert float(said[0].split()[2]) == pytest.approx(rms, rel=2e-3)  # printed to 3 digits


def test_log_decrement_covariance_is_the_delta_method_over_its_own_cycles(spring_rig):
    # (ω², b, g) = (w², 2 w ζ_L, 3π/4 κ) from the mean ω_n of the cycles (variance of a mean) and
    # the straight line ζ = ζ_L + κ a over them (numpy.polyfit's covariance, residual-scaled):
    # the delta method with a central-difference Jacobian must give the estimator's pcov_
    from hydrokit.identify.estimators import LogDecrementEstimator
    from hydrokit.identify.preprocess import trim_launch

    launch = trim_launch(simulate_launch(spring_rig, 0.3, 0.8, 15.0, A0, 8.0, SensorModel(200.0, 2e-5), rng=3))
    est = LogDecrementEstimator(spring_rig).fit(launch.t, launch.y)
    cyc = est.cycles_
    wn = np.array([c["natural_frequency"] for c in cyc])
    (kappa, zl), cz = np.polyfit([c["amplitude"] for c in cyc], [c["damping_ratio"] for c in cyc], 1, cov=True)
    x = np.array([wn.mean(), zl, kappa])
    cin = np.zeros((3, 3))
    cin[0, 0] = wn.var(ddof=1) / wn.size
    cin[1:, 1:] = cz[::-1, ::-1]  # polyfit orders (slope, intercept)

    def f(v):
        return np.array([v[0] ** 2, 2 * v[0] * v[1], 0.75 * math.pi * v[2]])

    h = 1e-6 * np.maximum(np.abs(x), 1e-3)
    J = np.column_stack([(f(x + h[i] * np.eye(3)[i]) - f(x - h[i] * np.eye(3)[i])) / (2 * h[i]) for i in range(3)])
    assert len(cyc) >= 5 and cz[0, 1] != 0.0  # a real slope and a correlated line fit
    np.testing.assert_allclose(est.pcov_, J @ cin @ J.T, rtol=1e-6, atol=1e-12 * np.max(np.abs(est.pcov_)))


def test_equation_error_standard_errors_match_the_scatter_of_independent_launches(spring_rig):
    # Monte Carlo, 40 launches with independent sensor noise: the scatter of the fitted (ω², b, g)
    # against the mean stated standard error. Measured 0.47, 0.23, 0.24: the formal errors of the
    # equation error are conservative (its regressors q, q̇ carry the smoothed noise too), but of
    # the right order; an error scaled by the wrong degrees of freedom is ~40× off
    from hydrokit.identify.estimators import EquationErrorEstimator
    from hydrokit.identify.preprocess import trim_launch

    fits, ses = [], []
    for seed in range(40):
        launch = trim_launch(simulate_launch(spring_rig, 0.26, 0.8, 15.0, A0, 8.0, SensorModel(200.0, 2e-4), rng=seed))
        est = EquationErrorEstimator(spring_rig).fit(launch.t, launch.y)
        fits.append(est.p_)
        ses.append(np.sqrt(np.diag(est.pcov_)))
    ratio = np.std(fits, axis=0, ddof=1) / np.mean(ses, axis=0)
    assert np.all((ratio > 0.12) & (ratio < 1.2)), ratio


def test_per_cycle_reynolds_of_a_torsion_rig_uses_the_tip_speed(torsion_rig):
    # the closed-form decay as a yaw angle (rad): the body's tip, L_ref/2 from the axis, moves at
    # ω_n a L_ref/2 in a cycle of angular amplitude a
    res = identify_launch(torsion_rig, linear_decay(), "log-decrement")
    L, nu = torsion_rig.reference_length, torsion_rig.kinematic_viscosity
    half = math.pi / WD
    cycles = res.extra["cycles"]
    assert len(cycles) >= 8
    for c in cycles:
        amp = A0 * math.exp(-SIGMA * (c["time"] + half))
        assert c["reynolds"] == pytest.approx(WN * amp * (L / 2) * L / nu, rel=2e-3)


def test_rest_line_from_just_two_extreme_triples():
    # 1.8 s of a decay about 0.01 (amplitude 0.1): four half-cycle extremes, two triples, each
    # giving c = (p1 p3 − p2²)/(p1 + p3 − 2 p2), exact for a geometric decay; the line through the
    # two is the rest value (the record's tail alone is 5 % of the amplitude off)
    from hydrokit.identify.preprocess import equilibrium, rest_line

    t = np.arange(361) / 200.0
    y = 0.01 + 0.1 * np.exp(-0.15 * t) * np.cos(2 * math.pi * t)
    c0, c1 = rest_line(t, y, 0.0)
    assert c0 == pytest.approx(0.01, abs=2e-5) and abs(c1) < 2e-5
    assert abs(equilibrium(y) - 0.01) > 0.05


def test_the_default_sensor_samples_at_100_hz(spring_rig):
    # SensorModel() is the documented ideal 100 Hz sensor: a simulated launch is sampled 0.01 s apart
    launch = simulate_launch(spring_rig, 0.3, 0.8, 0.0, A0, 2.0, SensorModel(), rng=0)
    np.testing.assert_allclose(np.diff(launch.t), 0.01, rtol=1e-9)


def test_a_spring_campaign_groups_by_millimetres_and_tests_groups_of_two(spring_rig):
    # launches from 20, 30 and 45 mm (two, three and two of them; independent noise): three
    # amplitude groups labelled in mm (a spring moves, it does not turn), and every pair of
    # groups gets its rank-sum test (a pair needs at least two values a side, two is enough)
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    launches = [
        trim_launch(simulate_launch(spring_rig, 0.3, 0.8, 15.0, a, 6.0, SensorModel(200.0, 2e-5), rng=k, file=f"{k}"))
        for k, a in enumerate((0.02, 0.02, 0.03, 0.03, 0.03, 0.045, 0.045))
    ]
    res = identify_launches(spring_rig, launches, "log-decrement")
    labels = ["L1 (20 mm)", "L2 (30 mm)", "L3 (45 mm)"]
    assert sorted(res.groups) == labels
    assert [len(res.groups[k]) for k in labels] == [2, 3, 2]
    for c in ("added_mass", "linear_damping", "quadratic_damping"):
        pairs = [p["pair"] for p in res.pairwise[c]]
        assert pairs == [labels[:2], [labels[0], labels[2]], labels[1:]]


@pytest.mark.parametrize("rate, release", [(100.0, 0.064), (50.0, 0.075)])
def test_a_release_early_in_the_record_is_refined_between_samples(rate, release):
    # a hold at A0 let go between two samples, so early that the best join time is the second
    # candidate of the search window: the parabola through the three costs still places it to
    # within 7 % of a sample step (the best sample alone is up to half a step off)
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(int(8 * rate) + 1) / rate
    s = np.maximum(t - release, 0.0)
    y = A0 * np.exp(-SIGMA * s) * (np.cos(WD * s) + SIGMA / WD * np.sin(WD * s))
    assert detect_release(t, y) == pytest.approx(release, abs=0.07 / rate)


def test_the_rest_value_of_a_short_record_is_the_median_of_its_last_fifth():
    # equilibrium(): the median of the last fifth (at least 5 samples); 25 samples 0..24 → 20..24
    from hydrokit.identify.preprocess import equilibrium

    assert equilibrium(np.arange(25.0)) == 22.0
    assert equilibrium(np.arange(12.0)) == 9.0  # the floor of 5 samples: 7..11


def test_noise_floor_of_five_samples_is_the_mad_of_their_second_differences():
    # y = 0 1 3 3 0: second differences 1 −2 −3, median −2, absolute deviations 3 0 1, MAD 1;
    # σ = 1.4826 MAD / √6 (white noise: second differences have std √6 σ); fewer than 5: 0
    from hydrokit.identify.preprocess import noise_floor

    assert noise_floor(np.array([0.0, 1.0, 3.0, 3.0, 0.0])) == pytest.approx(1.4826 / math.sqrt(6.0), rel=1e-12)
    assert noise_floor(np.array([0.0, 1.0, 3.0, 3.0])) == 0.0


def test_morison_covariance_has_no_linear_damping_row(spring_rig):
    # Morison holds K_L = 0: the covariance of (ω², b, g) is symmetric, zero in b's row and
    # column, and positive for ω² and g (it is the regression's covariance of the two)
    from hydrokit.identify.estimators import MorisonEstimator
    from hydrokit.identify.preprocess import trim_launch

    launch = trim_launch(simulate_launch(spring_rig, 0.3, 0.0, 15.0, A0, 8.0, SensorModel(200.0, 2e-5), rng=5))
    P = MorisonEstimator(spring_rig).fit(launch.t, launch.y).pcov_
    np.testing.assert_allclose(P, P.T, rtol=1e-12)
    assert not np.any(P[1]) and not np.any(P[:, 1])
    assert P[0, 0] > 0 and P[2, 2] > 0 and P[0, 2] ** 2 < P[0, 0] * P[2, 2]


def test_adequacy_at_a_two_sample_period_uses_the_lag_one_autocorrelation():
    # period = 2 Δt: the half-period lag is one sample, r[:-1]·r[1:] / r·r (of the de-meaned residual)
    from hydrokit.identify.estimators import adequacy

    r = np.random.default_rng(3).normal(0.0, 1e-3, 200)
    out = adequacy(r, np.arange(200) * 0.01, 0.02, 1e-3)
    c = r - r.mean()
    assert out["acf_at_half_period"] == pytest.approx(float(c[:-1] @ c[1:]) / float(c @ c), rel=1e-12)
    assert out["acf_at_period"] == pytest.approx(float(c[:-2] @ c[2:]) / float(c @ c), rel=1e-12)


def _extremes_only(amps: np.ndarray, halfs: np.ndarray):  # noqa: ANN202
    """A record of its extremes alone: alternating signs, half periods ``halfs`` apart (s)."""
    t = np.concatenate([[0.0], np.cumsum(halfs)])[: amps.size]
    z = amps * (-1.0) ** np.arange(amps.size)
    return t, z, [(i, i, i) for i in range(amps.size)]


@pytest.mark.parametrize(("stretch", "start"), [(1.2, 0), (1.4, 1)])
def test_free_decay_starts_where_the_next_periods_agree_within_15_percent(stretch, start):
    # the full periods after the release extreme must agree within 15 % of their median: a
    # half period stretched by 20 % makes the first full period 10 % long (kept), by 40 %
    # makes it 20 % long (the start moves to the next extreme, whose periods all agree)
    from hydrokit.identify.preprocess import _free_start

    halfs = np.full(11, 0.5)
    halfs[1] *= stretch
    t, z, ext = _extremes_only(0.8 ** np.arange(12), halfs)
    assert _free_start(t, z, ext, band=1e-3, sigma=1e-4) == start


@pytest.mark.parametrize(("zeta", "half_cycles"), [(0.3, 4), (0.35, 3)])
def test_release_needs_two_cycles_of_extremes(zeta, half_cycles):
    # a 1 Hz decay released at 0.5 s; at ζ = 0.3 four half cycles clear the band (two cycles:
    # enough), at ζ = 0.35 three (refused with the count)
    from hydrokit.identify.preprocess import detect_release, equilibrium, half_cycle_extremes, noise_floor

    wn = 2 * math.pi
    s, wd = zeta * wn, wn * math.sqrt(1 - zeta**2)
    td = np.arange(0.0, 6.0, 0.005)
    y = np.concatenate([np.ones(100), np.exp(-s * td) * (np.cos(wd * td) + s / wd * np.sin(wd * td))])
    y += np.random.default_rng(0).normal(0.0, 1e-5, y.size)
    t = np.arange(y.size) * 0.005
    z = y - equilibrium(y)
    band = max(4 * noise_floor(y), 0.01 * np.max(np.abs(z)))
    assert len(half_cycle_extremes(t, z, band)) == half_cycles
    if half_cycles >= 4:
        assert detect_release(t, y) == pytest.approx(0.5, abs=0.005)
    else:
        with pytest.raises(InputError, match=r"only 1.5 cycles \(half cycles with an extreme: 3\)"):
            detect_release(t, y)


@pytest.mark.parametrize(("band", "start"), [(1 / 128, 0), (3 / 256, 0), (1 / 64, None)])
def test_few_extremes_must_fall_by_more_than_twice_the_band(band, start):
    # five extremes, too few for the slope test: the release extreme and the last same-sign one
    # (4 half cycles later) must differ by more than twice the band (docstring of _free_start).
    # They differ by 4/128: more than 2/128 and 3/128 (3/128 is what the opposite-sign extreme
    # before it gives), not more than 2/64 (equal: refused)
    from hydrokit.identify.preprocess import _free_start

    t, z, ext = _extremes_only(1.0 - np.arange(5) / 128, np.full(4, 0.5))
    assert _free_start(t, z, ext, band=band, sigma=1e-4) == start


@pytest.mark.parametrize(("band", "start"), [(0.04, 1), (0.06, None)])
def test_an_even_count_of_extremes_compares_the_same_sign_one(band, start):
    # the first extreme is followed by a larger same-sign one (a hand still building the swing),
    # so the decay can start at the second: from there four extremes, the last same-sign one
    # two half cycles on, 0.1 lower; an opposite-sign one (0.15 lower) must not be taken
    from hydrokit.identify.preprocess import _free_start

    t, z, ext = _extremes_only(np.array([0.9, 1.0, 0.95, 0.9, 0.85]), np.full(4, 0.5))
    assert _free_start(t, z, ext, band=band, sigma=1e-4) == start


@pytest.mark.parametrize("phase", [0.4, 0.8])
def test_a_coarse_record_starting_in_outward_free_motion_releases_at_its_first_sample(phase):
    # 8 samples a period: too few to fit the hand before the release, so the detector falls back
    # to the sample before the release half cycle; here that half cycle starts at the first
    # sample (the body already swinging outwards), and nothing of the record may be dropped
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(0.0, 12.0, 1.0 / 8)
    y = np.exp(-0.1 * t) * np.cos(2 * math.pi * t - phase)
    assert detect_release(t, y, sigma=1e-4) == 0.0


def test_still_means_a_range_within_eight_noise_sigmas(monkeypatch):
    # the documented rule: still where the range over every min_hold window is within 8 noise
    # std. With σ fixed at 1 mm, a 7.5 mm step inside 4 s of rest is still throughout; an 8.5 mm
    # step splits the rest into two still runs, either side of it
    import hydrokit.identify.split as split

    monkeypatch.setattr(split, "noise_floor", lambda y: 1e-3)
    t = np.arange(400) / 100.0
    runs = {step: split.still_runs(t, np.where(np.arange(400) < 200, 0.0, step)) for step in (7.5e-3, 8.5e-3)}
    assert runs == {7.5e-3: [(0, 399)], 8.5e-3: [(0, 199), (200, 399)]}


def test_a_still_record_exactly_one_hold_long_is_one_still_run():
    # 1 s at 100 Hz with min_hold = 1 s: one window of 100 samples, still throughout; one sample
    # fewer holds no whole window and no still run
    from hydrokit.identify.split import still_runs

    y = np.random.default_rng(2).normal(0.0, 1e-5, 100)
    t = np.arange(100) / 100.0
    assert still_runs(t, y, min_hold=1.0) == [(0, 99)]
    assert still_runs(t[:99], y[:99], min_hold=1.0) == []


def test_a_noise_free_creep_is_still_within_a_millionth_of_the_range():
    # no noise (σ ≈ 1e-16): the stillness threshold is 1e-6 of the record's range (here 2, from
    # −1 to +1), so a creep of 1e-8 per sample (1e-6 per 1 s window) is still; its last sample
    # ends the run, the jump to +1 is not
    from hydrokit.identify.split import still_runs

    y = np.array([-1.0 + 1e-8 * k for k in range(200)] + [1.0])
    assert still_runs(np.arange(y.size) / 100.0, y) == [(0, 199)]


def test_a_hold_shorter_than_five_samples_is_never_still():
    # the shortest window is five samples, whatever min_hold asks (here 10 ms at 100 Hz)
    from hydrokit.identify.split import still_runs

    y = np.zeros(5)
    assert still_runs(np.arange(5) / 100.0, y, min_hold=0.01) == [(0, 4)]
    assert still_runs(np.arange(4) / 100.0, y[:4], min_hold=0.01) == []


def test_a_launch_is_immutable_and_compared_without_its_trim_facts():
    # a launch is shared by the campaign's parallel fits: frozen. What trimming found (info) is a
    # record of the work, not part of the data: launches equal in t, y, file and notes are equal
    import dataclasses

    t, y = (0.0, 0.1, 0.2), (0.01, 0.0, -0.01)
    a = Launch(t, y, "a.csv", info={"release_time": 1.5})
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.file = "b.csv"  # type: ignore[misc]
    assert a == Launch(t, y, "a.csv") != Launch(t, y, "b.csv")


@pytest.mark.parametrize("lam", [0.0, -2.0, math.nan, math.inf])
def test_scaling_refuses_a_ratio_that_is_not_positive_and_finite(lam):
    from hydrokit.identify.scaling import scale_coefficients

    with pytest.raises(InputError, match=rf"λ = {lam}: expected a positive length ratio L_full/L_model"):
        scale_coefficients({"added_mass": 1.0}, lam)
    # a full-size body smaller than the model (λ < 1) is allowed: m_a ∝ λ³
    assert scale_coefficients({"added_mass": 8.0}, 0.5) == {"added_mass": 1.0}


@pytest.mark.parametrize(("sigmas", "found"), [(20.5, 1), (19.5, 0)])
def test_a_hold_starts_a_launch_when_the_motion_after_it_exceeds_twenty_noise_sigmas(monkeypatch, sigmas, found):
    # the documented rule: a still run is a hold when the motion after it goes more than 20 noise
    # std (or 2 % of the record's range) from its level. With the noise floor set so that the
    # decay's largest excursion from the hold is 20.5 σ, the launch is found; at 19.5 σ it is not
    import hydrokit.identify.split as split

    t, y, (release,) = held_then_released((0.04,))
    level = float(np.median(y[release - 150 : release + 1]))
    excursion = float(np.max(np.abs(y[release + 1 :] - level)))
    monkeypatch.setattr(split, "noise_floor", lambda _: excursion / sigmas)
    segs = split.split_launches(t, y)
    assert len(segs) == found
    assert all(abs(s.release - release) <= 2 for s in segs)


def test_a_segment_is_immutable():
    import dataclasses

    from hydrokit.identify.split import Segment

    seg = Segment(0, 10, 100)
    with pytest.raises(dataclasses.FrozenInstanceError):
        seg.release = 5  # type: ignore[misc]
    assert seg == Segment(0, 10, 100)


def test_a_still_stretch_runs_to_its_last_still_sample():
    # 1.5 s at rest (samples 0–149), then a smooth lift 0.05 (1 − cos 0.2 k) whose first sample
    # (k = 0) is still at rest: the still run is samples 0 to 150, both ends included
    from hydrokit.identify.split import still_runs

    k = np.arange(150)
    y = np.concatenate([np.zeros(150), 0.05 * (1 - np.cos(0.2 * k))])
    y += np.random.default_rng(0).normal(0.0, 1e-5, y.size)
    assert still_runs(np.arange(y.size) / 100.0, y, min_hold=1.0) == [(0, 150)]


def test_all_linear_fallback_does_not_also_warn_of_negative_per_cycle_drag(spring_rig):
    # K_L = 0.01 N·s/m, no K_Q, 5 s: the cycle amplitudes differ by under 5 %, so the log decrement
    # takes all damping as linear (and says so); half the cycles then decay less than the mean by
    # noise alone, which is no reason for the per-cycle drag warning (C_D means nothing here)
    from hydrokit.identify.preprocess import trim_launch

    launch = simulate_launch(spring_rig, 0.3, 0.01, 0.0, 0.04, 5.0, SensorModel(200, 2e-5, 0, 0), rng=0)
    r = identify_launch(spring_rig, trim_launch(launch), "log-decrement")
    assert any("too alike" in w for w in r.warnings)
    assert not any("negative per-cycle" in w for w in r.warnings), r.warnings
    # K_Q is then fixed at zero, not estimated: no standard error, and none in the covariance
    assert r.quadratic_damping == 0.0 and r.std_error["quadratic_damping"] == 0.0
    assert r.std_error["linear_damping"] > 0.0
    assert not np.any(np.asarray(r.extra["covariance"])[2])


def test_simulation_without_jacobian_returns_zero_sensitivities():
    # simulate_normalised's docstring: unless jacobian=True (default False) J is zeros after row 0
    # (the seed ∂q0/∂q0 = 1)
    from hydrokit.identify.rig_model import simulate_normalised

    t = np.linspace(0.0, 2.0, 101)
    q, _, J = simulate_normalised(t, WN**2, 2 * ZETA * WN, 0.0, A0)
    np.testing.assert_allclose(q, linear_decay(2.0, 50.0).y, atol=1e-7)
    assert not np.any(J[1:])
    assert np.any(simulate_normalised(t, WN**2, 2 * ZETA * WN, 0.0, A0, jacobian=True)[2][1:])


@pytest.mark.parametrize("text", ["-0.1", "0", "inf", "nan", "-5deg"])
def test_an_amplitude_must_be_positive_and_finite(text):
    from hydrokit.identify.preprocess import parse_amplitude

    with pytest.raises(InputError, match=rf"--amplitude {text!r}: expected a positive amplitude"):
        parse_amplitude(text, translational=False, name="--amplitude")
    assert parse_amplitude("5deg", translational=False, name="--amplitude") == pytest.approx(math.radians(5))


# --- split.py, exhaustive pass (session of 2026-11-26) ---------------------------------------


def test_a_one_sample_glitch_inside_a_hold_does_not_hide_the_launch():
    # a sensor glitch: one sample 1 cm off in the middle of a 3 s hold. It splits the hold into
    # two still runs one sample apart (every window holding it has a 1 cm range); the glitch is
    # the whole 'motion' after the first part, too short to be a launch, and the release after
    # the second part is found as without it
    from hydrokit.identify.split import split_launches, still_runs

    t, y, (release,) = held_then_released((0.04,), hold_samples=300)
    clean = split_launches(t, y)
    glitch = release - 150
    y = y.copy()
    y[glitch] += 0.01
    runs = still_runs(t, y)
    assert any(b == glitch - 1 and nxt == glitch + 1 for (_, b), (nxt, _) in zip(runs, runs[1:]))
    assert split_launches(t, y) == clean and len(clean) == 1
    assert abs(clean[0].release - release) <= 2


def test_a_grabbed_launch_ends_within_four_noise_sigmas_of_the_rest_value(monkeypatch):
    # as the grab test above, with the noise floor the splitter uses set to 0.44 mm: the rest band
    # is then max(4 σ, 2 % of the hold's height) = 4 σ = 1.76 mm, and the launch ends at the last
    # sample within 1.76 mm of the motion's median before the grab (a 5 σ band ends it a sample later)
    import hydrokit.identify.split as split

    a1 = 0.04
    t, y = grabbed_session(a1)
    sigma = 4.4e-4
    monkeypatch.setattr(split, "noise_floor", lambda _: sigma)
    first = split.split_launches(t, y)[0]
    assert first.release == pytest.approx(450, abs=2)
    runs = split.still_runs(t, y)
    b = next(b for a, b in runs if a <= first.release <= b)  # the hold's last still sample
    nxt = next(a for a, _ in runs if a > b)  # the next hold starts
    motion = y[b + 1 : nxt]
    centre = float(np.median(motion))
    assert 4 * sigma > 0.02 * abs(a1 - centre)
    near = {k: np.nonzero(np.abs(motion - centre) <= k * sigma)[0] + b + 1 for k in (4, 5)}
    assert first.end == near[4][-1] < near[5][-1]


# --- virtual_rig.py and campaign.py, exhaustive passes (2026-11-26) --------------------------


def test_a_virtual_launch_lasts_the_hold_and_then_the_duration_to_the_sample(spring_rig):
    # 0.5 s of hold (25 samples at 50 Hz) then 2 s of free decay sampled at both ends (101
    # samples): 126 samples, the last at 2.5 s, the first free one (the release) at 0.5 s.
    # Noise-free, the free part is the closed-form linear decay from rest at A0 (no K_Q)
    from hydrokit.identify.rig_model import rig_constants
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

    sensor = SensorModel(sample_rate=50.0, noise_std=0.0, hold_time=0.5)
    L = simulate_launch(spring_rig, 0.5, 0.4, 0.0, A0, 2.0, sensor, 0)
    assert L.t.size == 126 and L.t[-1] == pytest.approx(2.5, abs=1e-12)
    assert np.all(L.y[:25] == A0)
    w2, b, _ = rig_constants(spring_rig).to_normalised(0.5, 0.4, 0.0)
    s, wd = b / 2, math.sqrt(w2 - b * b / 4)
    tt = L.t[25:] - 0.5
    np.testing.assert_allclose(L.y[25:], A0 * np.exp(-s * tt) * (np.cos(wd * tt) + s / wd * np.sin(wd * tt)), atol=1e-8)


def test_sensor_noise_is_zero_mean_with_the_stated_std():
    # 20 000 readings of a still body at 0.03 m through a 1 mm noise sensor: the mean error is
    # within 5 standard errors (5 × 1 mm/√20 000 = 0.035 mm) of zero and the std within 3 %
    from hydrokit.identify.virtual_rig import SensorModel

    out = SensorModel(noise_std=1e-3).measure(np.full(20_000, 0.03), np.random.default_rng(3))
    err = out - 0.03
    assert abs(float(np.mean(err))) < 5 * 1e-3 / math.sqrt(err.size)
    assert float(np.std(err)) == pytest.approx(1e-3, rel=0.03)


def test_rank_sum_of_tied_groups_at_and_below_one_unit_of_spread():
    # every value tied: σ_U = 0, no evidence of a difference: z = 0, p = 1. Groups {1, 2} and
    # {1, 1}: three tied ranks give σ_U = √(2·2/12 · (5 − 24/12)) = 1 exactly, U = 3, z = 1 —
    # and scipy's tie-corrected normal p agrees
    from scipy import stats

    from hydrokit.identify.campaign import rank_sum

    same = rank_sum([1.0, 1.0, 1.0], [1.0, 1.0])
    assert (same["z"], same["p"]) == (0.0, 1.0)
    r = rank_sum([1.0, 2.0], [1.0, 1.0], continuity=False)
    assert (r["u"], r["z"]) == (3.0, pytest.approx(1.0, rel=1e-12))
    ref = stats.mannwhitneyu([1.0, 2.0], [1.0, 1.0], alternative="two-sided", method="asymptotic", use_continuity=False)
    assert r["p"] == pytest.approx(float(ref.pvalue), rel=1e-10)


def test_launch_jitter_draws_gaussian_amplitudes_and_release_rates(monkeypatch, spring_rig):
    # amplitude_jitter j: the held amplitude is A (1 + j z); release_rate_std s: the release rate is
    # s z (z standard normal, fresh per launch). 400 launches: both standardised draws pass a
    # Kolmogorov–Smirnov test against N(0, 1) (a ratio A/(1 + j z) or s/z would be skewed or
    # heavy-tailed and fail it by far). The integrator is replaced by a recorder: only the
    # draws are under test
    from scipy import stats

    import hydrokit.identify.virtual_rig as vr

    seen = []

    def record(t, w2, b, g, a0, v0, *args, **kw):
        seen.append((a0, v0))
        return np.zeros(t.size), np.zeros(t.size), None

    monkeypatch.setattr(vr, "simulate_normalised", record)
    rng = np.random.default_rng(17)
    sensor = vr.SensorModel(sample_rate=50.0, noise_std=0.0, hold_time=0.1)
    for _ in range(400):
        vr.simulate_launch(spring_rig, 0.5, 0.4, 1.0, A0, 0.1, sensor, rng, amplitude_jitter=0.3, release_rate_std=0.02)
    a0, v0 = np.array(seen).T
    assert stats.kstest((a0 / A0 - 1.0) / 0.3, "norm").pvalue > 0.01
    assert stats.kstest(v0 / 0.02, "norm").pvalue > 0.01
    assert np.corrcoef(a0, v0)[0, 1] ** 2 < 0.02  # independent draws


def test_a_cycle_periodic_residual_at_the_noise_level_is_not_called_adequate():
    # RMS only 1.4× the noise floor, but the residual is a pure sinusoid at the oscillation
    # period (autocorrelation ≈ 1 one period apart, ≈ −1 half a period apart): a model error the
    # sensor noise does not explain, however small; "adequate" needs |acf| < 0.3 as well
    from hydrokit.identify.estimators import adequacy

    t = np.arange(2000) * 0.01
    a = adequacy(np.sin(2 * np.pi * t / 2.0), t, period=2.0, noise=0.5)
    assert a["residual_to_noise"] == pytest.approx(math.sqrt(0.5) / 0.5, rel=1e-3)
    assert a["acf_at_period"] > 0.85 and a["acf_at_half_period"] < -0.85  # (n − lag)/n of ±1
    assert a["verdict"].startswith("model error")


@pytest.mark.parametrize(("t", "acf"), [([0.0], None), ([0.0, 0.5], -0.5)])
def test_adequacy_of_one_or_two_residual_samples(t, acf):
    # one sample: no time step, no lag (and no division by a zero step); two samples 0.5 s apart
    # with a 0.5 s period: a lag of one step, whose autocorrelation of ±1 about their mean is
    # r₀ r₁ / (r₀² + r₁²) = −½
    from hydrokit.identify.estimators import adequacy

    r = np.array([0.2, -0.1][: len(t)])
    a = adequacy(r, np.array(t), period=0.5, noise=0.1)
    assert a["acf_at_period"] == (pytest.approx(acf, rel=1e-12) if acf is not None else None)


def test_equation_error_resamples_jittered_stamps_onto_an_even_grid(spring_rig):
    # a closed-form linear decay (K_Q = 0) sampled at stamps jittered by up to ±20 % of the
    # 10 ms step: resampled onto the median step over the whole record, equation-error finds the
    # same added mass and linear damping as from the even record, within 1 %
    from hydrokit.identify.estimators import identify_launch
    from hydrokit.identify.rig_model import rig_constants

    ma, kl = 0.3, 0.6
    w2, b, _ = rig_constants(spring_rig).to_normalised(ma, kl, 0.0)
    s, wd = b / 2, math.sqrt(w2 - b * b / 4)

    def record(t):
        return A0 * np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))

    t = np.arange(1501) * 0.01
    tj = t.copy()
    tj[1:-1] += np.random.default_rng(8).uniform(-0.002, 0.002, t.size - 2)
    even = identify_launch(spring_rig, Launch(t, record(t), "even.csv"), "equation-error")
    jit = identify_launch(spring_rig, Launch(tj, record(tj), "jitter.csv"), "equation-error")
    assert even.added_mass == pytest.approx(ma, rel=0.01) and even.linear_damping == pytest.approx(kl, rel=0.01)
    assert jit.added_mass == pytest.approx(even.added_mass, rel=0.01)
    assert jit.linear_damping == pytest.approx(even.linear_damping, rel=0.01)
    # the grid is the median step from the first stamp, up to (not at) the last: ⌈15 s / dt⌉
    # samples (dt = 10.0145 ms here, the jitter's median); the even record is used as it is
    dt = float(np.median(np.diff(tj)))
    n = math.ceil((tj[-1] - tj[0]) / dt)
    assert n == 1498
    assert [w for w in jit.warnings if "uneven sampling" in w] == [
        f"uneven sampling (intervals off the median 10.01 ms by up to 39%): resampled onto a uniform grid of "
        f"{n} samples for the derivatives"
    ]
    assert not any("uneven sampling" in w for w in even.warnings)


@pytest.mark.parametrize(("tstat", "free_from_first"), [(3.03, True), (2.97, False)])
def test_free_decay_needs_a_falling_amplitude_slope_three_standard_errors_below_zero(tstat, free_from_first):
    # the documented rule at its edge: 20 extremes whose amplitudes are 1 − 0.01 t plus an
    # alternating ±0.02 (an offset rest value) and a residual orthogonal to both, scaled so
    # that the least-squares slope is `tstat` standard errors below zero, its variance from the
    # residual with n − 3 = 17 degrees of freedom. 3.03 σ: free from the first extreme; 2.97 σ: not
    from hydrokit.identify.preprocess import _free_start

    n = 20
    tt = np.arange(n) * 0.5
    H = np.column_stack([np.ones(n), tt, (-1.0) ** np.arange(n)])
    e = np.random.default_rng(21).normal(size=n)
    e -= H @ np.linalg.lstsq(H, e, rcond=None)[0]
    se_unit = math.sqrt(float(e @ e) / (n - 3) * float(np.linalg.inv(H.T @ H)[1, 1]))
    amps = H @ np.array([1.0, -0.01, 0.02]) + e * 0.01 / (tstat * se_unit)
    z = amps * (-1.0) ** np.arange(n)
    j = _free_start(tt, z, [(k, k, k) for k in range(n)], band=0.01, sigma=1.0)
    assert (j == 0) is free_from_first


def test_five_extremes_are_enough_to_judge_the_periods():
    # five falling extremes whose two full periods (1.0 s and 1.5 s) differ by 20 % of their
    # median, more than the 15 % allowed: the motion is not free from the first extreme; from
    # the second (four left, too few to judge periods) it is, the amplitudes falling by more
    # than twice the band
    from hydrokit.identify.preprocess import _free_start

    t = np.array([0.0, 0.5, 1.0, 1.5, 2.5])
    z = np.array([1.0, -0.9, 0.8, -0.7, 0.6])
    assert _free_start(t, z, [(k, k, k) for k in range(5)], band=0.01, sigma=1.0) == 1
    even = np.arange(5) * 0.5  # the same amplitudes evenly spaced: free from the first
    assert _free_start(even, z, [(k, k, k) for k in range(5)], band=0.01, sigma=1.0) == 0


def test_equation_error_replay_starts_from_the_smoothed_state_at_the_first_kept_sample(spring_rig):
    # noise-free closed-form linear decay: the fitted model replayed from the first sample the
    # smoothing filter keeps (its position and rate there, at that time) retraces the record over
    # the first two seconds to 0.2 % of the amplitude
    from hydrokit.identify.estimators import identify_launch
    from hydrokit.identify.rig_model import rig_constants

    w2, b, _ = rig_constants(spring_rig).to_normalised(0.3, 0.6, 0.0)
    s, wd = b / 2, math.sqrt(w2 - b * b / 4)
    t = np.arange(1501) * 0.01
    y = A0 * np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    _, est = identify_launch(spring_rig, Launch(t, y, "even.csv"), "equation-error", return_estimator=True)
    early = t <= 2.0
    assert np.max(np.abs(est.predict(t[early]) - y[early])) < 2e-3 * A0


def test_an_amplitude_window_left_at_the_very_next_extreme_holds_half_a_cycle():
    # extremes about halving every half cycle (1, 0.5, 0.25, 0.125 …): the window (HI 0.9, LO 0.3)
    # starts at about 0.5 and the very next extreme, 0.25, is already below LO: half a cycle, refused by count
    from hydrokit.identify.preprocess import _amplitude_window

    t = np.arange(0.0, 4.0, 0.001)
    z = 0.5 ** (t / 0.5) * np.cos(2 * np.pi * t)
    # (the decay moves each extreme a little past the cosine's peak: 0.5122, not 0.5)
    with pytest.raises(InputError, match=r"only 0\.5 cycles inside the window \(0\.512\d down to 0\.3\)"):
        _amplitude_window(t, z, 0.0, (0.9, 0.3), "rec")


def test_a_given_end_at_the_last_sample_drops_nothing_and_says_nothing():
    # end = the record's last time: no "samples of noise dropped" note (there are none); one sample
    # earlier: the note says exactly one was dropped
    from hydrokit.identify.preprocess import trim_launch

    t = np.arange(0.0, 6.0, 0.01)
    y = A0 * np.exp(-SIGMA * t) * np.cos(WD * t)
    whole = trim_launch(Launch(t, y, "rec.csv"), release=0.0, end=float(t[-1]))
    assert whole.t.size == t.size and not any(n.startswith("end given") for n in whole.notes)
    short = trim_launch(Launch(t, y, "rec.csv"), release=0.0, end=float(t[-2]))
    assert [n for n in short.notes if n.startswith("end given")] == [
        "end given at t = 5.980 s: 1 samples of noise dropped"
    ]


def test_a_quantised_record_has_the_noise_of_its_step():
    # a slow 2 mm swing read by a 0.1 mm encoder at 100 Hz: most samples repeat the one before, the
    # second differences are mostly zero (MAD 0), and the noise floor is the quantisation noise
    # of a uniform rounding error, step/√12 = 0.0289 mm
    from hydrokit.identify.preprocess import noise_floor

    step = 1e-4
    t = np.arange(0.0, 20.0, 0.01)
    y = np.round(0.002 * np.sin(0.5 * t) / step) * step  # a step every ≥ 10 samples
    assert noise_floor(y) == pytest.approx(step / math.sqrt(12.0), rel=1e-9)


def test_equation_error_smooths_with_a_quartic_by_default(spring_rig):
    # the documented default polynomial order is 4: the default fit is the explicit quartic's,
    # to the last bit, and a quintic (whose first derivative differs) gives other numbers
    from hydrokit.identify.estimators import identify_launch

    t = np.arange(0.0, 12.0, 0.01)
    y = A0 * np.exp(-SIGMA * t) * (np.cos(WD * t) + SIGMA / WD * np.sin(WD * t))
    y = y + np.random.default_rng(2).normal(0.0, 2e-5, t.size)
    L = Launch(t, y, "rec.csv")
    default = identify_launch(spring_rig, L, "equation-error")
    quartic = identify_launch(spring_rig, L, "equation-error", polyorder=4)
    quintic = identify_launch(spring_rig, L, "equation-error", polyorder=5)
    assert (default.added_mass, default.linear_damping) == (quartic.added_mass, quartic.linear_damping)
    assert quintic.linear_damping != quartic.linear_damping


def test_the_detected_end_is_a_quarter_period_after_the_last_sample_above_the_noise():
    # a 30 s decay sinking into 0.1 mm noise: the documented end is the last sample more than four
    # noise floors from the rest value, plus a quarter period (the swing's next zero crossing);
    # the quarter is measured from the record's crossings: T_d/4 = π/(2 ω_d) here, within a sample
    from hydrokit.identify.preprocess import equilibrium, noise_floor, trim_launch

    t = np.arange(0.0, 30.0, 0.01)
    y = A0 * np.exp(-SIGMA * t) * (np.cos(WD * t) + SIGMA / WD * np.sin(WD * t))
    # bounded noise (uniform, σ = 0.1 mm, never beyond 1.8 σ): no lone noise sample passes 4 σ
    y = y + np.random.default_rng(4).uniform(-math.sqrt(3) * 1e-4, math.sqrt(3) * 1e-4, t.size)
    trimmed = trim_launch(Launch(t, y, "rec.csv"), release=0.0)
    above = np.nonzero(np.abs(y - equilibrium(y)) > 4.0 * noise_floor(y))[0][-1]
    assert t[above] < 25.0  # the decay does sink into the noise before the record ends
    # within half a sample (0.005 s): the sample nearest that time (plain zero crossings, which
    # multiply in the noisy tail, once made the quarter 11 ms short)
    assert float(trimmed.t[-1]) == pytest.approx(t[above] + math.pi / (2 * WD), abs=0.005)


@pytest.mark.parametrize("zeta, extremes", [(0.5, 3), (0.6, 2), (0.7, 1)])
def test_the_quarter_period_past_the_end_is_measured_from_two_or_more_extremes(zeta, extremes):
    # heavy damping, 1 Hz, bounded noise 1 mm rms: the swing sinks into the noise after few half
    # cycles. Their extremes above 4 noise floors (the last, cut-off half cycle not counted)
    # measure the half period T_d/2 = π/ω_d; with a single one there is nothing to measure and the
    # launch ends at its last sample above the noise
    from hydrokit.identify.preprocess import equilibrium, half_cycle_extremes, noise_floor, trim_launch

    t = np.arange(0.0, 10.0, 0.01)
    s, wd = zeta * 2 * math.pi, 2 * math.pi * math.sqrt(1 - zeta**2)
    y = np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    y = y + np.random.default_rng(4).uniform(-math.sqrt(3) * 1e-3, math.sqrt(3) * 1e-3, t.size)
    trimmed = trim_launch(Launch(t, y, "rec.csv"), release=0.0)
    z, floor = y - equilibrium(y), 4.0 * noise_floor(y)
    above = np.nonzero(np.abs(z) > floor)[0][-1]
    assert len(half_cycle_extremes(t[: above + 1], z[: above + 1], floor)) == extremes
    quarter = math.pi / (2 * wd) if extremes >= 2 else 0.0
    assert float(trimmed.t[-1]) == pytest.approx(t[above] + quarter, abs=0.005)


def test_a_given_release_after_the_decay_has_died_out_is_refused():
    # release given at 25 s, when the 1 Hz decay (σ = 0.6 /s) is far below 1 mm of noise
    from hydrokit.identify.preprocess import trim_launch

    t = np.arange(0.0, 30.0, 0.01)
    y = np.exp(-0.6 * t) * np.cos(2 * math.pi * t) + np.random.default_rng(4).uniform(-1e-3, 1e-3, t.size)
    with pytest.raises(InputError, match=r"after the release \(t = 25 s\) the record stays within 4 noise"):
        trim_launch(Launch(t, y, "rec.csv"), release=25.0)


def test_coarse_releases_of_a_three_sample_hold_and_of_a_kick_from_rest():
    # 8 samples a period (1 s period), 1 mm noise. A hold of exactly three samples at its level
    # (3.0, 3.125, 3.25 s) is a hold: released at its last sample, 3.25 s. A body at rest kicked
    # at 1.0 s (a sine start, no hold): the release is the sample before the half cycle that
    # leaves the rest band, the last one at rest, 1.0 s
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(0.0, 20.0, 1.0 / 8.0)
    noise = np.random.default_rng(1).normal(0.0, 1e-3, t.size)
    s = np.maximum(t - 3.25, 0.0)
    held = np.where(t < 2, 0.0, np.where(t < 3, t - 2, 1.0))
    held = np.where(t < 3.25, held, np.exp(-0.1 * s) * np.cos(2 * np.pi * s))
    assert detect_release(t, held + noise) == pytest.approx(3.25, abs=1e-12)
    k = np.maximum(t - 1.0, 0.0)
    kicked = np.exp(-0.1 * k) * np.sin(2 * np.pi * k)
    assert detect_release(t, kicked + noise) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("model", [("quadratic", 1), ("linear", 1), ("quadratic", 3)])
def test_output_error_from_its_generic_start_alone_finds_the_same_fit(spring_rig, monkeypatch, model):
    # output-error starts from the equation-error and log-decrement fits and, last, from a generic
    # start (ω from the record's period, ζ = 0.05, no K_Q). With the first two failing it must
    # reach the same least-squares fit from the generic start alone (a start ω π² times too
    # small, 2/π for 2π, leaves the cubic-restoring fit at its 600-evaluation limit, far off)
    import hydrokit.identify.estimators as est_mod
    from hydrokit.identify.estimators import OutputErrorEstimator
    from hydrokit.identify.preprocess import trim_launch

    launch = trim_launch(simulate_launch(spring_rig, 0.3, 0.3, 2.0, 0.04, 8.0, SensorModel(200, 2e-5, 0, 0), rng=0))
    kw = dict(damping_model=model[0], restoring_terms=model[1])
    usual = OutputErrorEstimator(spring_rig, **kw)
    usual.fit(launch.t, launch.y)

    class Failing:
        def __init__(self, *args, **kwargs):
            raise ValueError("not available")

    monkeypatch.setattr(est_mod, "EquationErrorEstimator", Failing)
    monkeypatch.setattr(est_mod, "LogDecrementEstimator", Failing)
    alone = OutputErrorEstimator(spring_rig, **kw)
    alone.fit(launch.t, launch.y)
    np.testing.assert_allclose(alone.p_, usual.p_, rtol=1e-5, atol=1e-9)


def test_log_decrement_corrects_the_pendulum_period_for_amplitude(pendulum_rig):
    # a pendulum at 0.4 rad swings slower than at small amplitude: ω(a) ≈ ω₀ (1 − a²/16). The
    # log decrement undoes it per cycle (ω₀ = ω(a)(1 + a²/16), a the cycle's mean amplitude) and
    # must then agree with output-error, which integrates sin θ itself, to 5e-5 of ω (the
    # correction is 1 % at the first cycle; its a⁴ term is 1e-4 of it at 0.4 rad)
    launch = simulate_launch(pendulum_rig, 0.3, 0.02, 0.0, 0.4, 20.0, SensorModel(500, 1e-6, 0, 0), rng=0)
    ld = identify_launch(pendulum_rig, launch, "log-decrement")
    oe = identify_launch(pendulum_rig, launch, "output-error")
    assert ld.natural_frequency == pytest.approx(oe.natural_frequency, rel=5e-5)


def test_speed_max_of_a_launch_that_starts_at_its_fastest(spring_rig):
    # q = (V/ω_d) e^{−σt} sin ω_d t passes its rest value at t = 0 with q̇ = V and slows from
    # there (q̈(0) = −2σV): the largest speed is V, at the launch's first sample — which the
    # velocity grid must include
    V = 0.25  # m/s
    t = np.arange(0.0, 8.0 + 1e-9, 0.005)
    y = V / WD * np.exp(-SIGMA * t) * np.sin(WD * t)
    res = identify_launch(spring_rig, Launch(t, y, "closed-form"), "output-error")
    assert res.extra["speed_max"] == pytest.approx(V, rel=2e-4)
    assert res.reynolds_max == pytest.approx(V * spring_rig.reference_length / spring_rig.kinematic_viscosity, rel=2e-4)


def test_peaks_leave_out_a_last_half_cycle_that_ends_inside_the_band():
    # cos t from 0 to 3π + 1.5: maxima at 0 and 2π, minimum at π close their half cycles by
    # crossing the far side of the ±0.1 band; the minimum at 3π is followed only by samples
    # inside the band (cos(3π + 1.5) = −0.07), never crossed, so it is left out
    from hydrokit.identify.estimators import _peaks

    t = np.arange(0.0, 3 * np.pi + 1.5, 0.01)
    peaks = _peaks(t, np.cos(t), 0.1)
    np.testing.assert_allclose([tp for tp, _ in peaks], [0.0, np.pi, 2 * np.pi], atol=1e-6)
    # extended until it leaves the band upwards, that minimum closes too
    t2 = np.arange(0.0, 3 * np.pi + 1.7, 0.01)
    assert len(_peaks(t2, np.cos(t2), 0.1)) == 4


def test_a_knock_beyond_twenty_extremes_leaves_the_release_alone():
    # held at 1 until 2 s, then a 1 Hz decay (σ = 0.06 /s) and, ten cycles on, a knock as big as
    # the release. The decay test reads up to 20 extremes from the release (extremes 0–19): a knock
    # at extreme 20 is beyond them and the release stays at 2 s; at extreme 19 it is inside them,
    # the amplitudes no longer fall, and the free decay is taken to start near the knock
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(0.0, 30.0, 0.01)
    s = np.maximum(t - 2.0, 0.0)
    decay = np.where(t < 2.0, 1.0, np.exp(-0.06 * s) * np.cos(2 * np.pi * s))
    noise = np.random.default_rng(0).normal(0.0, 1e-3, t.size)
    for k, late in ((20, False), (19, True)):
        tk = 2.0 + 0.5 * k  # the time of extreme k, signed like it
        knock = np.exp(-(((t - tk) / 0.05) ** 2)) * np.sign(np.cos(np.pi * k))
        tr = detect_release(t, decay + knock + noise)
        assert (tr > tk - 1.0) if late else abs(tr - 2.0) < 0.005, (k, tr)


@pytest.mark.parametrize(("hold", "release"), [(0.035, 0.0), (0.045, 0.07)])
def test_a_record_starts_in_free_motion_only_if_its_first_crossing_comes_within_0_3_period(hold, release):
    # held at 1 for `hold` s, then a 1 s-period decay, sampled every 35 ms. The first crossing of
    # the band (0.2516 s after the release) comes at the sample 0.28 s or 0.315 s: under 0.3 period
    # from the record's start, the record is taken to start in free motion (release t[0]); from
    # 0.3 period on, the hold is found — at its last sample within 2 % of the level, 0.07 s
    # (cos(2π·0.025) = 0.988), one sample after the true release at 0.045 s
    from hydrokit.identify.preprocess import detect_release

    t = np.arange(0.0, 20.0, 0.035)
    s = np.maximum(t - hold, 0.0)
    y = np.where(t < hold, 1.0, np.exp(-0.1 * s) * np.cos(2 * np.pi * s))
    y = y + np.random.default_rng(0).normal(0.0, 1e-3, t.size)
    assert detect_release(t, y) == pytest.approx(release, abs=1e-12)


def test_simulating_a_rig_without_inertia_is_refused(spring_rig):
    # the spring rig's total inertia is m + m_a: an added mass of −m (exactly −0.97 kg) leaves
    # none (the motion would be infinitely fast), and below that it is negative
    from hydrokit.identify.rig_model import simulate_rig

    t = np.linspace(0.0, 1.0, 11)
    for ma in (-spring_rig.mass, -spring_rig.mass - 0.1):
        with pytest.raises(InputError, match=r"added_mass = .*: total inertia must be positive"):
            simulate_rig(spring_rig, t, ma, 0.1, 0.0, 0.01)
    assert np.all(np.isfinite(simulate_rig(spring_rig, t, -spring_rig.mass + 0.1, 0.1, 0.0, 0.01)))


def test_release_of_an_empty_or_single_sample_record_is_refused_in_words():
    import warnings

    from hydrokit.identify.preprocess import detect_release

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warning about empty slices on the way
        with pytest.raises(InputError, match="the record holds no samples"):
            detect_release(np.array([]), np.array([]), file="empty.csv")
    with pytest.raises(InputError, match="the record does not oscillate"):
        detect_release(np.array([0.0]), np.array([1.0]))


def test_a_smoothing_window_as_long_as_the_record_is_refused(spring_rig):
    # equation-error's Savitzky–Golay window must leave samples beyond its edges: a window of all
    # 41 samples of a record (or more) is refused in one line
    from hydrokit.identify.estimators import make_estimator

    launch = linear_decay(4.0, 10.0)  # 41 samples, 4.5 periods
    assert len(launch.t) == 41
    for window in (41, 43):
        with pytest.raises(InputError, match=rf"window = {window}: expected an odd number of samples between 5 and 40"):
            make_estimator("equation-error", spring_rig, window=window).fit(launch.t, launch.y)


def test_output_error_formal_covariance_is_curve_fits(spring_rig):
    # a second method: scipy's curve_fit on the same model (the rig ODE with free ω², b, g, q0,
    # v0 and rest), started at the estimate, gives s² (JᵀJ)⁻¹ with s² = SSR/(n − p). A short
    # record (n = 151, p = 6) makes the degrees of freedom matter: n + p would be 8 % off
    from scipy.optimize import curve_fit

    from hydrokit.identify.rig_model import simulate_normalised

    launch = simulate_launch(spring_rig, 0.2866, 0.5, 5.0, 0.03, 1.5, SensorModel(100.0, 2e-4, 0.0, 0.0), rng=8)
    _, est = identify_launch(spring_rig, launch, "output-error", return_estimator=True)
    t = np.asarray(launch.t, float) - float(launch.t[0])
    y = np.asarray(launch.y, float)
    c = est.constants_

    def model(tt: np.ndarray, w2: float, b: float, g: float, q0: float, v0: float, rest: float) -> np.ndarray:
        q, _, _ = simulate_normalised(tt, w2, b, g, q0, v0, c.sine, est.substeps, restoring=c.restoring)
        return q + rest

    x = [*est.p_, est.q0_, est.v0_, est.offset_]
    popt, pcov = curve_fit(model, t, y, p0=x, xtol=1e-14, ftol=1e-14)
    assert popt[:3] == pytest.approx(x[:3], rel=1e-5)
    np.testing.assert_allclose(est.pcov_formal_, pcov[:3, :3], rtol=1e-3, atol=1e-3 * np.abs(pcov[:3, :3]).max())


def test_adequacy_of_a_residual_that_is_all_zero_has_no_autocorrelation():
    # a fit through every sample: r = 0 about its mean, r·r = 0, so no lag has a defined
    # autocorrelation (None, not a division by zero)
    from hydrokit.identify.estimators import adequacy

    t = np.arange(200) * 0.01
    a = adequacy(np.full(200, 0.003), t, period=0.5, noise=1e-4)
    assert a["acf_at_period"] is None and a["acf_at_half_period"] is None
    assert a["residual_to_noise"] == 0.0


@pytest.mark.parametrize(
    ("r", "acf", "words"),
    [([2.0, 1, -1, -2, 0], 0.3, "model error"), ([2.0, 1, -2, -1, 0], 0.2, "residual above the noise floor")],
)
def test_adequacy_calls_an_autocorrelation_of_exactly_0_3_model_error(r, acf, words):
    # the rule is "at least 0.3 one period apart": r = (2, 1, −1, −2, 0) (mean 0, r·r = 10) has a
    # lag-one product of 3, so exactly 0.3 at a one-step period; (2, 1, −2, −1, 0) has 2 (0.2).
    # Both are 14× the noise, so neither is adequate
    from hydrokit.identify.estimators import adequacy

    a = adequacy(np.array(r), np.arange(5) * 0.1, period=0.1, noise=0.1)
    assert a["acf_at_period"] == acf
    assert a["verdict"].startswith(words)


def test_drag_coefficient_is_two_k_q_over_rho_a(spring_rig):
    # C_D = 2 K_Q / (ρ A) (SPEC §2: F = ½ ρ C_D A |u| u = K_Q |u| u), from the launch's own K_Q
    launch = simulate_launch(spring_rig, 0.2866, 0.5, 5.0, 0.03, 6.0, SensorModel(200.0, 2e-5, 0.0, 0.0), rng=3)
    res = identify_launch(spring_rig, launch, "equation-error")
    assert res.quadratic_damping > 1.0  # kg/m: a drag the two readings would tell apart
    want = 2.0 * res.quadratic_damping / (spring_rig.density * spring_rig.reference_area)
    assert res.drag_coefficient == pytest.approx(want, rel=1e-12, abs=1e-15)
    assert spring_rig.density != 1.0 and spring_rig.reference_area != 1.0  # the two factors tell
