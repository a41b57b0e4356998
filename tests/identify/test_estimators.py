"""Estimators recover known coefficients from virtual-rig launches (issue #2 acceptance).

Tolerances reflect each method's known bias: output-error is unbiased (1 % on added mass, 3 %
on the damping force curve over the tested speeds); equation-error inherits the smoothing
differentiator's bias; log-decrement suffers from peak timing on quantised or heavily damped
records; Morison lumps the linear damping into K_Q.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2

from hydrokit.errors import InputError
from hydrokit.identify.estimators import identify_launch, make_estimator
from hydrokit.identify.preprocess import trim_launch
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

TRUTH = {
    "pendulum": (0.05, 0.02, 0.3),  # kg, N s/m, N s²/m²
    "spring": (0.2866, 2.6793, 5.5959),  # CELY2019 Table 7 x-axis m_a; K_Q = ½ρC_D A
    "torsion": (0.008, 0.002, 0.004),  # kg m², N m s/rad, N m s²/rad²
}
SENSORS = {
    "pendulum": SensorModel.imu(),  # 100 Hz, 0.05° noise
    "spring": SensorModel.encoder(),  # 2.45 counts/mm = 0.41 mm steps
    "torsion": SensorModel(100.0, math.radians(0.05), 0.0, 0.5, "IMU"),
}
AMPS = {"pendulum": [math.radians(5), math.radians(15)], "spring": [0.02, 0.04], "torsion": [0.3, 0.6]}


def force_curve_error(rig, res, truth, u_max):
    u = np.linspace(0.05 * u_max, u_max, 50)
    ref = truth[1] * u + truth[2] * u * u
    got = res.linear_damping * u + res.quadratic_damping * u * u
    return float(np.max(np.abs(got - ref) / ref))


@pytest.mark.parametrize("test", ["pendulum", "spring", "torsion"])
def test_output_error_recovers_truth_on_noisy_data(test, request):
    rig = request.getfixturevalue(f"{test}_rig")
    truth = TRUTH[test]
    for k, amp in enumerate(AMPS[test]):
        launch = trim_launch(simulate_launch(rig, *truth, amp, 10.0, SENSORS[test], rng=k, file=f"{test}{k}"))
        res = identify_launch(rig, launch, "output-error")
        assert res.added_mass == pytest.approx(truth[0], rel=0.01)
        u_max = res.extra["speed_max"]
        assert force_curve_error(rig, res, truth, u_max) < 0.03
        assert res.std_error["added_mass"] > 0
        # residual at the sensor noise floor
        floor = math.hypot(SENSORS[test].noise_std, SENSORS[test].resolution / math.sqrt(12))
        assert res.rms_residual < 1.3 * floor


@pytest.mark.parametrize(
    "test,method,tol_ma,tol_force",
    [
        ("pendulum", "equation-error", 0.03, 0.15),
        ("pendulum", "log-decrement", 0.05, 0.25),
        ("pendulum", "morison", 0.03, 0.25),
        ("spring", "equation-error", 0.06, 0.2),
        ("spring", "log-decrement", 0.25, 0.3),
        ("torsion", "equation-error", 0.03, 0.15),
        ("torsion", "log-decrement", 0.05, 0.25),
    ],
)
def test_other_methods_within_their_known_bias(test, method, tol_ma, tol_force, request):
    rig = request.getfixturevalue(f"{test}_rig")
    truth = TRUTH[test]
    vals = []
    for k, amp in enumerate(AMPS[test]):
        launch = trim_launch(simulate_launch(rig, *truth, amp, 10.0, SENSORS[test], rng=10 + k))
        vals.append(identify_launch(rig, launch, method))
    ma = np.mean([v.added_mass for v in vals])
    assert ma == pytest.approx(truth[0], rel=tol_ma)
    for v in vals:
        u = v.extra["speed_max"]
        if method == "morison":
            # K_L = 0 by construction: only the force at the peak speed can match
            err = abs(v.quadratic_damping * u * u - (truth[1] * u + truth[2] * u * u)) / (
                truth[1] * u + truth[2] * u * u
            )
        else:
            err = force_curve_error(rig, v, truth, u)
        assert err < tol_force


def test_noise_free_linear_damping_is_exact_for_every_method(pendulum_rig):
    # with K_Q = 0 every method's model is exact (Morison excepted): an independent check of
    # the unit conversions of all estimators
    truth = (0.05, 0.03, 0.0)
    launch = simulate_launch(pendulum_rig, *truth, math.radians(3), 15.0, SensorModel(200, 0, 0, 0), rng=0)
    for method in ("output-error", "equation-error", "log-decrement"):
        res = identify_launch(pendulum_rig, launch, method)
        assert res.added_mass == pytest.approx(0.05, rel=0.01), method
        assert res.linear_damping == pytest.approx(0.03, rel=0.05), method


def test_estimator_conventions(pendulum_rig):
    est = make_estimator("output-error", pendulum_rig)
    assert not hasattr(est, "added_mass_")  # __init__ stores settings only
    launch = simulate_launch(pendulum_rig, *TRUTH["pendulum"], 0.2, 10.0, SensorModel.imu(hold_time=0), rng=3)
    assert est.fit(launch.t, launch.y) is est
    pred = est.predict(launch.t)
    assert pred.shape == launch.t.shape
    assert np.sqrt(np.mean((pred - launch.y) ** 2)) < 2 * SensorModel.imu().noise_std


# Replicate check of the standard errors (second method: repetition). With N launches the sample
# variance s² of N estimates whose true std is σ obeys (N - 1) s² / σ² ~ χ²(N - 1) (estimates
# normal: measured skewness 0.07 and excess kurtosis 0.14 over 2000 launches). The statistic
# (N - 1) s² / SE² must lie between the 0.1 % and 99.9 % quantiles, for N = 200: 143.0 and 266.4,
# i.e. s/SE within 0.848 - 1.157. Power: an SE 1.5x too small puts the statistic at
# 1.5² · 199 = 448 on average, and it stays below 266.4 with probability P(χ²(199) < 118.4) = 1e-6;
# an SE 1.5x too large gives 199 / 1.5² = 88 < 143.0 (missed with probability 8e-8). Over 2000
# launches s/SE is 0.998 (m_a), 1.001 (K_L), 0.994 (K_Q), and each of ten blocks of 200 passes.
N_REPLICATES = 200
CHI2_LOW, CHI2_HIGH = chi2.ppf([0.001, 0.999], N_REPLICATES - 1)
COEFFICIENTS = ("added_mass", "linear_damping", "quadratic_damping")


def replicate_fits(rig, entropy: int):
    """N_REPLICATES white-noise output-error fits of the pendulum at 0.15 rad for 10 s."""
    sensor = SensorModel.imu(hold_time=0)
    streams = np.random.SeedSequence(entropy).spawn(N_REPLICATES)
    launches = (
        simulate_launch(rig, *TRUTH["pendulum"], 0.15, 10.0, sensor, rng=np.random.default_rng(s)) for s in streams
    )
    return [identify_launch(rig, launch, "output-error") for launch in launches]


def chi2_variance_statistic(values, predicted_se: float) -> float:
    """(N - 1) s² / SE², χ²(N - 1)-distributed when SE is the true std of ``values``."""
    return (len(values) - 1) * float(np.var(values, ddof=1)) / predicted_se**2


@pytest.mark.needs_jit(reason="200 output-error fits")
def test_covariance_matches_monte_carlo_spread(pendulum_rig):
    # the Jacobian covariance of each fit predicts the launch-to-launch spread (see above)
    fits = replicate_fits(pendulum_rig, entropy=122)
    for c in COEFFICIENTS:
        se = float(np.mean([r.std_error[c] for r in fits]))
        stat = chi2_variance_statistic([getattr(r, c) for r in fits], se)
        assert CHI2_LOW < stat < CHI2_HIGH, (c, stat, CHI2_LOW, CHI2_HIGH)


def test_unknown_method_is_one_line(pendulum_rig):
    with pytest.raises(InputError, match="method = 'magic': expected one of output-error"):
        make_estimator("magic", pendulum_rig)


def test_log_decrement_reports_drag_per_cycle(spring_rig):
    launch = simulate_launch(spring_rig, 0.2866, 0.5, 5.5959, 0.04, 8.0, SensorModel(200, 0, 0, 0), rng=0)
    res = identify_launch(spring_rig, launch, "log-decrement")
    cyc = res.extra["cycles"]
    assert len(cyc) >= 4
    re = [c["reynolds"] for c in cyc]
    assert max(re) > min(re)
    # S3: ζ = ζ_L + (2/(3π)) ρ C_D A a/(m + m_a) -> C_D per cycle scatters about the truth
    cd_true = 2 * 5.5959 / (998.2 * 0.008)
    assert np.median([c["drag_coefficient"] for c in cyc[:4]]) == pytest.approx(cd_true, rel=0.15)


def test_log_decrement_drag_per_cycle_on_a_pendulum_is_in_the_bodys_units(pendulum_rig):
    # on a pendulum the fitted c_Q is r³ K_Q (rig_model.RigConstants.quadratic_factor): each
    # cycle's C_D = 2 K_Q/(ρ A) must undo that factor like the fitted K_Q does; at r = 0.39 m a
    # missing or doubled r³ moves it by 17× or 1/17
    m_a, K_L, K_Q = TRUTH["pendulum"]
    launch = simulate_launch(pendulum_rig, m_a, K_L, K_Q, 0.3, 10.0, SensorModel(200, 0, 0, 0), rng=0)
    res = identify_launch(pendulum_rig, launch, "log-decrement")
    cd = [c["drag_coefficient"] for c in res.extra["cycles"]]
    cd_true = 2 * K_Q / (pendulum_rig.density * pendulum_rig.reference_area)
    assert len(cd) >= 4
    assert np.median(cd) == pytest.approx(cd_true, rel=0.25)


def test_wall_proximity_warning(pendulum_rig):
    from dataclasses import replace

    rig = replace(pendulum_rig, wall_distance=0.03)
    launch = simulate_launch(rig, *TRUTH["pendulum"], 0.15, 10.0, SensorModel.imu(), rng=1)
    res = identify_launch(rig, trim_launch(launch), "output-error")
    assert res.gap_ratio == pytest.approx(0.03 / 0.087)
    assert any("gap ratio" in w for w in res.warnings)
    # the warning says "closer than one body size": a wall exactly one body size (L = 0.087 m)
    # away is not closer, a wall 0.086 m away is
    for wall, warned in ((0.087, False), (0.086, True)):
        rig = replace(pendulum_rig, wall_distance=wall)
        res = identify_launch(rig, trim_launch(launch), "output-error")
        assert any("gap ratio" in w for w in res.warnings) is warned


def test_tare_is_subtracted(pendulum_rig):
    from dataclasses import replace

    rig = replace(pendulum_rig, tare_linear_damping=0.005, tare_quadratic_damping=0.01)
    launch = trim_launch(simulate_launch(pendulum_rig, 0.05, 0.025, 0.31, 0.2, 10.0, SensorModel.imu(), rng=2))
    res = identify_launch(rig, launch, "output-error")
    assert res.linear_damping == pytest.approx(0.02, abs=0.002)
    assert res.quadratic_damping == pytest.approx(0.30, rel=0.05)


def test_log_decrement_warns_of_negative_per_cycle_drag(spring_rig):
    # a noise-free launch whose sensor gain steps up by 20 % at t = 3 s (smoothly, over ~0.1 T):
    # the cycle across the step decays by ln(1.2) = 0.18 less, so its ζ falls below the fitted
    # linear part and its per-cycle C_D comes out negative
    from hydrokit.identify.types import Launch

    launch = simulate_launch(spring_rig, 0.2866, 0.5, 5.5959, 0.04, 8.0, SensorModel(200, 0, 0, 0), rng=0)
    t, y = np.asarray(launch.t), np.asarray(launch.y)
    period = 2 * math.pi / math.sqrt(63.6 / (0.97 + 0.2866))  # undamped, closed form: 0.883 s
    y = y * (1.0 + 0.2 * 0.5 * (1.0 + np.tanh((t - 3.0) / (0.1 * period))))
    res = identify_launch(spring_rig, Launch(t=t, y=y, file="gain.csv"), "log-decrement")
    cycles = res.extra["cycles"]
    bad = [(k, c) for k, c in enumerate(cycles, start=1) if c["drag_coefficient"] < 0]
    msgs = [w for w in res.warnings if "negative per-cycle C_D" in w]
    assert len(msgs) == 1 and bad, res.warnings
    k, worst = min(bad, key=lambda kc: kc[1]["drag_coefficient"])
    assert f"{len(bad)} of {len(cycles)} cycles" in msgs[0]
    assert f"lowest {worst['drag_coefficient']:.3g} at cycle {k}," in msgs[0]
    # the flagged cycle is the one that spans the gain step (independent: where the step is)
    assert worst["time"] < 3.0 < worst["time"] + period


@pytest.mark.parametrize("linear,quadratic", [(0.5, 5.5959), (2.0, 0.0)])
def test_log_decrement_clean_record_has_no_negative_drag_warning(spring_rig, linear, quadratic):
    # noise-free decays (quadratic-dominated, and purely linear with true C_D = 0): no cycle
    # decays less than the linear part beyond the peak-interpolation resolution
    launch = simulate_launch(spring_rig, 0.2866, linear, quadratic, 0.04, 8.0, SensorModel(200, 0, 0, 0), rng=0)
    res = identify_launch(spring_rig, launch, "log-decrement")
    assert not [w for w in res.warnings if "per-cycle" in w], res.warnings
    cd = [c["drag_coefficient"] for c in res.extra["cycles"]]
    cd_true = 2 * quadratic / (998.2 * 0.008)  # C_D = 2 K_Q / (ρ A)
    assert np.median(cd) == pytest.approx(cd_true, abs=0.15 * cd_true + 1e-3)


def test_log_decrement_corrects_a_large_pendulum_swing_to_small_amplitude(pendulum_rig):
    # a 30° pendulum swing is slower than a small one: T = T0 (1 + a²/16 + 11a⁴/3072 + …) (the
    # complete elliptic integral's series). The log-decrement corrects each cycle's ω by the
    # first term, leaving ≈ 11a⁴/3072 < 0.03 % in ω; the correction's sign flipped puts m_a
    # (0.05 of 0.196 kg) 11 % high, so 1 % tells them apart
    truth = (0.05, 0.03, 0.0)
    launch = simulate_launch(pendulum_rig, *truth, math.radians(30), 15.0, SensorModel(200, 0, 0, 0), rng=0)
    res = identify_launch(pendulum_rig, launch, "log-decrement")
    assert res.added_mass == pytest.approx(0.05, rel=0.01)
    assert res.linear_damping == pytest.approx(0.03, rel=0.05)


def test_fit_names_the_column_holding_a_nan_or_infinite_sample(pendulum_rig):
    launch = simulate_launch(pendulum_rig, *TRUTH["pendulum"], 0.1, 5.0, SensorModel(200, 0, 0, 0), rng=0)
    t, y = np.asarray(launch.t, float), np.asarray(launch.y, float)
    bad_y = y.copy()
    bad_y[11] = np.inf
    with pytest.raises(InputError) as err:
        make_estimator("log-decrement", pendulum_rig).fit(t, bad_y, file="run.csv")
    assert str(err.value) == (
        f"run.csv: column 'y' (m or rad) holds inf at sample 11 (of {t.size} samples; 1 bad): expected finite numbers"
    )
    bad_t = t.copy()
    bad_t[3] = np.nan
    with pytest.raises(InputError) as err:
        make_estimator("log-decrement", pendulum_rig).fit(bad_t, y, file="run.csv")
    assert str(err.value).startswith("run.csv: column 't' (s) holds nan at sample 3 ")


def test_replay_before_the_release_is_the_closed_form_run_backwards(spring_rig):
    # a linear decay q = a e^{−σt}(cos ω_d t + σ/ω_d sin ω_d t) holds for t < 0 too: the fitted
    # model integrated backwards from the release (descending times, small steps) must give it
    m_a, K_L, a = 0.3, 0.8, 0.04
    launch = simulate_launch(spring_rig, m_a, K_L, 0.0, a, 10.0, SensorModel(200, 0, 0, 0), rng=0)
    _, est = identify_launch(spring_rig, trim_launch(launch), "output-error", return_estimator=True)
    A = spring_rig.mass + m_a
    sigma = K_L / (2 * A)
    wd = math.sqrt(spring_rig.stiffness / A - sigma**2)
    t = np.linspace(-1.0, -0.005, 200)
    q = a * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    assert np.max(np.abs(est.predict(t + est.t0_) - est.offset_ - q)) < 1e-9
    v = -a * (wd**2 + sigma**2) / wd * np.exp(-sigma * t) * np.sin(wd * t)  # q̇ of the same closed form
    assert np.max(np.abs(est.velocity(t + est.t0_) - v)) < 1e-8


def test_equation_error_fits_the_rest_value(pendulum_rig):
    # the rest value is a fitted parameter (ρ(q − c) ≈ ρ(q) − c ρ'(q)): a 6 s, heavily damped
    # record whose mean is far from its rest still gets it to 1e-4 of the 0.1 amplitude
    launch = simulate_launch(pendulum_rig, 0.05, 0.15, 0.0, 0.1, 6.0, SensorModel(100, 1e-5, 0, 0), rng=0)
    for rest in (0.0, 0.01):
        est = make_estimator("equation-error", pendulum_rig).fit(launch.t, np.asarray(launch.y) + rest)
        assert est.offset_ == pytest.approx(rest, abs=1e-5)
        assert est.added_mass_ == pytest.approx(0.05, rel=1e-3)


def test_log_decrement_separates_quadratic_damping_by_harmonic_balance(spring_rig):
    # per-cycle ζ = ζ_L + (4/3π)(c_Q/A)·a, so c_Q = (3π/4)·slope: noise-free quadratic decays
    # give K_Q within 1 % (the first-harmonic balance is not exact; output-error is)
    for truth in ((0.3, 0.2, 5.0), (0.3, 0.0, 8.0)):
        launch = simulate_launch(spring_rig, *truth, 0.04, 15.0, SensorModel(200, 0, 0, 0), rng=0)
        res = identify_launch(spring_rig, launch, "log-decrement")
        assert res.quadratic_damping == pytest.approx(truth[2], rel=0.01), truth
        assert res.added_mass == pytest.approx(truth[0], rel=0.01), truth
