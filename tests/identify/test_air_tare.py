"""In-air tare (ENG2009 §IV.A): fit α, β, γ to in-air launches, then take the pivot friction off
the in-water result and use the effective pendulum length."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.stats import chi2

import hydrokit
from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.identify.tare import AirTare, air_tare, apply_tare, fit_air_tare
from hydrokit.identify.types import Launch

G = 9.81
R = 0.3904  # m, ENG2009's effective length
MASS = 5.0  # kg


def in_air(r, beta, gamma, amplitude, rate, noise, rng, duration=20.0, rest=0.0):
    """θ̈ = −(g/r) sin θ − β θ̇ − γ |θ̇| θ̇ from rest at ``amplitude`` (rad), sampled at ``rate``
    (Hz) for ``duration`` s, plus white noise (rad) and a sensor zero ``rest`` (rad)."""
    t = np.arange(int(round(duration * rate)) + 1) / rate
    sol = solve_ivp(
        lambda _t, z: (z[1], -(G / r) * math.sin(z[0]) - beta * z[1] - gamma * abs(z[1]) * z[1]),
        (0.0, t[-1]),
        (amplitude, 0.0),
        method="DOP853",
        t_eval=t,
        rtol=1e-11,
        atol=1e-13,
    )
    return Launch(t=t, y=sol.y[0] + rest + rng.normal(0.0, noise, t.size), file=f"air {amplitude:.3f} rad")


def test_fit_recovers_length_and_pivot_friction() -> None:
    # a stiff pivot (β = 0.02 1/s, γ = 0.05 1/rad) seen by a 100 Hz, 0.005° sensor
    beta, gamma = 0.02, 0.05
    rng = np.random.default_rng(11)
    launches = [
        in_air(R, beta, gamma, math.radians(a), 100.0, math.radians(0.005), rng, rest=z)
        for a, z in ((20, 1e-3), (30, -2e-3), (40, 0.0))
    ]
    tare, fit = fit_air_tare(launches, MASS, G)
    assert tare.effective_length == pytest.approx(R, rel=0.002)
    assert fit["beta"] == pytest.approx(beta, rel=0.05)
    assert fit["gamma"] == pytest.approx(gamma, rel=0.03)
    # (the standard errors cover the sensor noise only; at this little noise the differentiator's
    # own bias, +0.01 % on r and about +1 % on β, is larger)
    assert all(0 < v < 0.02 * abs(fit[k]) for k, v in fit["std_error"].items()), fit["std_error"]
    # conversion to the in-water units: K_L = β m, K_Q = γ m / r
    assert tare.linear_damping == pytest.approx(fit["beta"] * MASS)
    assert tare.quadratic_damping == pytest.approx(fit["gamma"] * MASS / tare.effective_length)
    assert fit["rest_values"] == pytest.approx([1e-3, -2e-3, 0.0], abs=2e-5)
    assert fit["launches"] == 3 and fit["n"] > 5000 and fit["rms_residual"] > 0
    assert fit["noise_std"] == pytest.approx([math.radians(0.005)] * 3, rel=0.1)


def test_noise_correction_removes_the_length_bias() -> None:
    # at 30 fps and 0.2° the smoothed θ and the filtered θ̈ share noise: plain least squares
    # makes |α| about 0.15 % too large (r 0.6 mm short), several standard errors
    rng = np.random.default_rng(5)
    launches = [in_air(R, 0.004, 0.01, math.radians(a), 30.0, math.radians(0.2), rng) for a in (20, 30, 40)]
    _, fit = fit_air_tare(launches, MASS, G)
    _, plain = fit_air_tare(launches, MASS, G, noise_correction=False)
    se = fit["std_error"]["alpha"]
    assert abs(fit["alpha"] + G / R) < 3 * se
    assert plain["alpha"] - fit["alpha"] < -3 * se


def test_standard_errors_match_the_scatter() -> None:
    # the smoothing correlates the residuals: σ̂²(HᵀH)⁻¹ would be 5× off for β here. N noisy copies
    # of one 30 fps launch (0.2° white noise): with s the std of the N fitted values and SE their
    # mean standard error, (N - 1) s² / SE² ~ σ²/SE² · χ²(N - 1). The correction of the smoothing
    # is approximate: over 1000 copies s/SE is 1.057 (α), 0.947 (β), 0.941 (γ). So the check
    # allows σ/SE in 0.9-1.1 beyond the chi-square spread: the statistic must lie within
    # [0.9² q(0.1 %), 1.1² q(99.9 %)] of χ²(399) = [257.1, 595.3] (s/SE in 0.80-1.22). Power: an
    # SE 1.5x too small gives 1.5² · 399 = 898 on average and passes with probability
    # P(χ²(399) < 264.6) = 3e-8; 1.5x too large gives 399 / 1.5² = 177 (passes with 1e-8).
    n = 400
    clean = in_air(R, 0.004, 0.01, math.radians(30), 30.0, 0.0, np.random.default_rng(0))
    noise = math.radians(0.2)
    fits = [
        fit_air_tare([Launch(t=clean.t, y=clean.y + rng.normal(0.0, noise, clean.t.size), file="air")], MASS, G)[1]
        for rng in map(np.random.default_rng, np.random.SeedSequence(2).spawn(n))
    ]
    low, high = 0.9**2 * chi2.ppf(0.001, n - 1), 1.1**2 * chi2.ppf(0.999, n - 1)
    for key in ("alpha", "beta", "gamma"):
        se = float(np.mean([f["std_error"][key] for f in fits]))
        stat = (n - 1) * float(np.var([f[key] for f in fits], ddof=1)) / se**2
        assert low < stat < high, (key, stat, low, high)


def test_eng2009_printed_alpha_gives_the_effective_length() -> None:
    # ENG2009 §IV.A: in air α = −25.128 1/s², hence r = g/|α| = 0.3904 m (0.39 m measured)
    tare = air_tare(-25.128, 0.0, 0.0, MASS, 9.81)
    assert tare.effective_length == pytest.approx(0.3904, abs=5e-5)
    assert tare == AirTare(tare.effective_length, 0.0, 0.0)


def test_errors_name_the_problem() -> None:
    with pytest.raises(InputError, match="no in-air launches"):
        fit_air_tare([], MASS, G)
    rng = np.random.default_rng(0)
    good = in_air(R, 0.004, 0.01, math.radians(20), 30.0, 1e-4, rng)
    short = Launch(t=good.t[:10], y=good.y[:10], file="air_short.csv")
    with pytest.raises(InputError, match="air_short.csv: only 10 samples"):
        fit_air_tare([good, short], MASS, G)
    with pytest.raises(InputError, match="mass = 0"):
        fit_air_tare([good], 0.0, G)
    # a record whose angles are not radians of a hanging pendulum: θ̈ against sin θ is not restoring
    t = np.arange(0.0, 20.0, 1 / 30)
    y = 5.0 * np.exp(-0.01 * t) * np.cos(2 * math.pi * t / 1.25)
    with pytest.raises(InputError, match="fitted alpha = .* expected a negative"):
        fit_air_tare([Launch(t=t, y=y, file="deg.csv")], MASS, G)


def test_rov2_air_tare_takes_the_pivot_friction_off() -> None:
    """The bundled rov2 campaign: water launches made with ENG2009 Table II means plus the pivot
    friction (README: β_p = 0.004 1/s, γ_p = 0.01 1/rad, r = 0.3904 m), air launches in tare/."""
    base = DATA_DIR / "campaigns" / "rov2"
    rig = hydrokit.load_rig(base / "pendulum_surge.yaml")
    assert rig.pendulum_length == 0.39 and rig.tare_linear_damping == 0 == rig.tare_quadratic_damping
    air = [hydrokit.read_launch(f, rig) for f in sorted((base / "tare").glob("air_*.csv"))]
    assert len(air) == 3
    tare, fit = fit_air_tare(air, rig.mass, rig.gravity)
    KL_p, KQ_p = 0.004 * rig.mass, 0.01 * rig.mass / 0.3904
    se_KL = fit["std_error"]["beta"] * rig.mass
    se_KQ = fit["std_error"]["gamma"] * rig.mass / tare.effective_length
    assert tare.effective_length == pytest.approx(0.3904, rel=0.001)
    assert abs(tare.linear_damping - KL_p) < 2 * se_KL
    assert abs(tare.quadratic_damping - KQ_p) < 2 * se_KQ

    files = sorted((base / "surge").glob("*.csv"))
    raw = hydrokit.identify_campaign(rig, files)
    tared = hydrokit.identify_campaign(apply_tare(rig, tare), files)
    # ENG2009 Table II means
    ma, KL, KQ = 0.58, 1.5515, 9.5439
    # without the tare K_L and K_Q come out high by about the pivot friction (and by 0.1 %, 0.2 %
    # more from the 0.39 m length instead of 0.3904 m, which also puts m_a 1 % high)
    assert raw.mean("linear_damping") - KL == pytest.approx(KL_p, abs=0.01)
    # K_Q scatters more than the friction: groups of three launches are not screened for outliers
    # (the rule needs five), so the total K_Q + K_Q,p is only required inside the stated 95 % CI
    lo, hi = raw.summary["quadratic_damping"]["ci"]
    assert lo < KQ + KQ_p < hi and hi - lo < 0.1 * KQ
    assert raw.mean("added_mass") == pytest.approx(ma * 1.01, rel=0.005)
    # with it: the length is right, so is m_a; the damping is as good as the tare, whose β, γ
    # carry the camera noise (at 30 fps, 0.2°, three launches: K_L ± 0.13, K_Q ± 0.16, i.e.
    # larger than the friction itself)
    assert tared.mean("added_mass") == pytest.approx(ma, rel=0.01)
    lo, hi = tared.summary["quadratic_damping"]["ci"]
    assert lo < KQ < hi  # (the launch scatter alone, ±3.4 %; the 2.7 % high comes from surge_L1_3)
    assert abs(tared.mean("linear_damping") - KL) < 0.03 * KL + 2 * se_KL
    assert abs(tared.mean("quadratic_damping") - KQ) < 0.01 * KQ + 2 * se_KQ


def test_eng2009_convention_is_gamma_m_r_and_r_squared_times_physics() -> None:
    # ENG2009 §IV.A: α = −25.128 1/s² (r = g/|α| = 0.3904 m); β, γ of a stiff pivot (our choice)
    alpha, beta, gamma, g = -25.128, 0.004, 0.01, 9.81
    r = g / 25.128
    phys = air_tare(alpha, beta, gamma, MASS, g)
    eng = air_tare(alpha, beta, gamma, MASS, g, convention="eng2009")
    # closed forms: physics K_Q = γ M / r, ENG2009 K_Q = γ M r; K_L = β M and r alike in both
    assert phys.quadratic_damping == pytest.approx(gamma * MASS / r, rel=1e-12)
    assert eng.quadratic_damping == pytest.approx(gamma * MASS * r, rel=1e-12)
    assert eng.quadratic_damping / phys.quadratic_damping == pytest.approx(r**2, rel=1e-12)
    assert (eng.effective_length, eng.linear_damping) == (phys.effective_length, phys.linear_damping)
    assert air_tare(alpha, beta, gamma, MASS, g, convention="physics") == phys  # the default


def test_fit_air_tare_convention_switch() -> None:
    rng = np.random.default_rng(3)
    launch = in_air(R, 0.004, 0.01, math.radians(30), 30.0, math.radians(0.05), rng, duration=12.0)
    phys, fit_p = fit_air_tare([launch], MASS, G)
    eng, fit_e = fit_air_tare([launch], MASS, G, convention="eng2009")
    assert (fit_p["convention"], fit_e["convention"]) == ("physics", "eng2009")
    assert fit_e["gamma"] == fit_p["gamma"]  # the conversion alone differs
    r = phys.effective_length
    assert eng.quadratic_damping == pytest.approx(fit_e["gamma"] * MASS * r, rel=1e-12)
    assert eng.quadratic_damping == pytest.approx(phys.quadratic_damping * r**2, rel=1e-12)


def test_unknown_convention_is_one_line() -> None:
    with pytest.raises(InputError, match=r"convention = 'ENG': expected one of physics, eng2009$"):
        air_tare(-25.0, 0.0, 0.0, MASS, convention="ENG")
    with pytest.raises(InputError, match=r"convention = 'paper': expected one of physics, eng2009$"):
        fit_air_tare([], MASS, G, convention="paper")


def test_project_tare_block_takes_the_convention() -> None:
    from hydrokit.io.project import PROJECTS_DIR, parse_project
    from hydrokit.io.yamlfile import read_yaml

    path = PROJECTS_DIR / "rov2" / "project.yaml"
    data = read_yaml(path)
    glob_ = data["campaigns"][0]["tare"]
    assert parse_project(data, path).campaigns[0].tare_convention == "physics"  # plain glob: default
    n = len(parse_project(data, path).campaigns[0].tare)
    data["campaigns"][0]["tare"] = {"launches": glob_, "convention": "eng2009"}
    spec = parse_project(data, path).campaigns[0]
    assert spec.tare_convention == "eng2009" and len(spec.tare) == n == 3
    data["campaigns"][0]["tare"] = {"launches": glob_, "convention": "paper"}
    with pytest.raises(
        InputError, match=r"'campaigns\[0\]\.tare\.convention' = 'paper': expected one of physics, eng2009"
    ):
        parse_project(data, path)


def test_noise_map_is_the_linearised_equation_residual_for_each_launch() -> None:
    # _noise_terms promises Hᵀ Δe = Mᵀ n to first order in the raw-sample noise n (per launch,
    # stacked, M scaled by √σ²). A second method: perturb the raw samples, differentiate again
    # and take the change of the equation residual e = θ̈ − (α sin θ − β θ̇ − γ|θ̇|θ̇ + c_k cos θ)
    # by finite differences. Two launches with different rest terms c_k: launch 2 must use c_2.
    from dataclasses import replace

    from hydrokit.identify.tare import _noise_terms, _smooth

    rng = np.random.default_rng(5)
    launches = [
        in_air(R, 0.02, 0.05, math.radians(a), 50.0, math.radians(0.01), rng, duration=8.0, rest=z)
        for a, z in ((25, 0.0), (35, 4e-3))
    ]
    window = 11
    parts = [_smooth(L, window, 4) for L in launches]
    coef = np.array([-G / R, 0.3, 0.8, 0.6, -1.7])  # α, β, γ, c_1, c_2: c_k far from γ and each other

    def residual_and_regressors(smoothed, j):
        q, qd, qdd = smoothed.q, smoothed.qd, smoothed.qdd
        H = np.zeros((q.size, coef.size))
        H[:, 0], H[:, 1], H[:, 2], H[:, 3 + j] = np.sin(q), -qd, -np.abs(qd) * qd, np.cos(q)
        return qdd - H @ coef, H

    _, M = _noise_terms(parts, coef)
    eps = 1e-7
    start = 0
    for j, (L, s) in enumerate(zip(launches, parts)):
        n = rng.normal(size=np.asarray(L.y).size)
        e0, H = residual_and_regressors(s, j)
        e1, _ = residual_and_regressors(_smooth(replace(L, y=np.asarray(L.y) + eps * n), window, 4), j)
        numeric = H.T @ (e1 - e0) / eps
        rows = M[start : start + n.size] / math.sqrt(s.noise_var)
        np.testing.assert_allclose(rows.T @ n, numeric, rtol=1e-4, atol=1e-6 * np.max(np.abs(numeric)))
        start += n.size
    assert start == M.shape[0]


def test_a_sensor_zero_beyond_a_quarter_turn_is_refused() -> None:
    # θ measured from a zero θ0 off the hanging position: θ̈ = −(g/r) sin(θ − θ0) =
    # −(g/r) cos θ0 · sin θ + (g/r) sin θ0 · cos θ, so the fit's α = −(g/r) cos θ0. At θ0 = 92°
    # α = +0.88 1/s² (no longer restoring in sin θ) and r = −g/α would be negative: refused by
    # name, with the fitted α in the message
    rng = np.random.default_rng(2)
    launch = in_air(R, 0.02, 0.05, math.radians(20), 50.0, math.radians(0.01), rng, rest=math.radians(92))
    alpha = -(G / R) * math.cos(math.radians(92))
    assert 0.0 < alpha < 1.0
    with pytest.raises(InputError) as err:
        fit_air_tare([launch], MASS, G)
    msg = str(err.value)
    assert float(msg.split()[3]) == pytest.approx(alpha, rel=2e-3)
    assert msg.startswith("fitted alpha = ") and "expected a negative coefficient of sin θ" in msg
    assert "zero within 90° of hanging" in msg


def test_a_nan_or_infinite_sample_in_either_column_is_named() -> None:
    rng = np.random.default_rng(3)
    good = in_air(R, 0.004, 0.01, math.radians(20), 30.0, 1e-4, rng)
    n = good.t.size
    y = good.y.copy()
    y[7] = np.nan
    with pytest.raises(InputError) as err:
        fit_air_tare([Launch(t=good.t, y=y, file="air_nan.csv")], MASS, G)
    assert str(err.value) == (
        f"air_nan.csv: column 'y' (rad) holds nan at sample 7 (of {n} samples; 1 bad): expected finite numbers"
    )
    t = good.t.copy()
    t[[4, 9]] = np.inf
    with pytest.raises(InputError) as err:
        fit_air_tare([Launch(t=t, y=good.y, file="air_inf.csv")], MASS, G)
    assert str(err.value) == (
        f"air_inf.csv: column 't' (s) holds inf at sample 4 (of {n} samples; 2 bad): expected finite numbers"
    )


def test_unevenly_sampled_launches_are_resampled_over_the_whole_record() -> None:
    # camera frames with ±20 % timing jitter: resampled to the median step over the whole
    # record, the fit finds the same length as the evenly sampled launch
    rng = np.random.default_rng(8)
    even = in_air(R, 0.004, 0.01, math.radians(20), 30.0, 1e-4, rng)
    t = even.t + rng.uniform(-0.2, 0.2, even.t.size) / 30.0
    t[0], t[-1] = even.t[0], even.t[-1]
    jittered = Launch(t=t, y=np.interp(t, even.t, even.y), file="jitter.csv")
    a = fit_air_tare([even], MASS, G)[0].effective_length
    b = fit_air_tare([jittered], MASS, G)[0].effective_length
    assert b == pytest.approx(a, rel=2e-3)
    assert b == pytest.approx(R, rel=5e-3)


def test_effective_length_scales_with_the_gravity_given() -> None:
    # r = g/ω²: the same swing read with g = 0.5 m/s² (any g > 0 is a valid input) gives a
    # length 0.5/9.81 of the one read with g = 9.81, the friction terms unchanged
    rng = np.random.default_rng(12)
    launch = in_air(R, 0.004, 0.01, math.radians(20), 50.0, 1e-4, rng)
    earth, fit_e = fit_air_tare([launch], MASS, G)
    low, fit_l = fit_air_tare([launch], MASS, 0.5)
    assert low.effective_length == pytest.approx(earth.effective_length * 0.5 / G, rel=1e-9)
    assert fit_l["beta"] == pytest.approx(fit_e["beta"], rel=1e-9)
    with pytest.raises(InputError, match=r"gravity = 0"):
        fit_air_tare([launch], MASS, 0.0)


def test_noise_bias_is_the_monte_carlo_mean_of_the_linearised_products() -> None:
    # _noise_terms' bias promises E[ΔHᵀ Δe] for white raw-sample noise of the launch's variance.
    # A second method: draw the noise 4000 times, filter it with the three kernels (the filters
    # are linear, so ε_d is exact), form ΔH = [cos θ ε₀, −ε₁, −2|θ̇| ε₁, −sin θ ε₀] and
    # Δe = ε₂ − A ε₀ + B ε₁, and average ΔHᵀ Δe: each entry within 4 Monte Carlo standard errors
    from numpy.lib.stride_tricks import sliding_window_view

    from hydrokit.identify.tare import _noise_terms, _smooth

    rng = np.random.default_rng(11)
    launch = in_air(R, 0.02, 0.05, math.radians(30), 50.0, math.radians(0.05), rng, duration=6.0)
    part = _smooth(launch, 11, 4)
    coef = np.array([-G / R, 0.3, 0.8, 0.6])  # α, β, γ, c
    bias, _ = _noise_terms([part], coef)
    q, qd = part.q, part.qd
    A = coef[0] * np.cos(q) - coef[3] * np.sin(q)
    B = coef[1] + 2.0 * coef[2] * np.abs(qd)
    n = rng.normal(0.0, math.sqrt(part.noise_var), size=(4000, q.size + part.window - 1))
    windows = sliding_window_view(n, part.window, axis=1)
    e0, e1, e2 = (windows @ k for k in part.kernels)
    de = e2 - A * e0 + B * e1
    dH = (np.cos(q) * e0, -e1, -2.0 * np.abs(qd) * e1, -np.sin(q) * e0)
    samples = np.stack([np.sum(h * de, axis=1) for h in dH], axis=1)
    mean, se = samples.mean(axis=0), samples.std(axis=0) / math.sqrt(len(samples))
    assert np.all(np.abs(bias - mean) < 4.0 * se), (bias, mean, se)
    assert abs(bias[1]) > 10.0 * se[1]  # β's term is resolved, not lost in the Monte Carlo noise


def test_uneven_stamps_are_resampled_over_the_whole_launch() -> None:
    # stamps jittered by up to ±20 % of the 20 ms step (a webcam): resampled at the median
    # step from the first stamp through the last whole step, so the smoothed record keeps all
    # but the filter's edges (the 11-sample window's 10)
    from hydrokit.identify.tare import _smooth

    rng = np.random.default_rng(4)
    even = in_air(R, 0.02, 0.05, math.radians(30), 50.0, math.radians(0.01), rng, duration=6.0)
    t = np.asarray(even.t).copy()
    t[1:-1] += rng.uniform(-0.004, 0.004, t.size - 2)
    jittered = Launch(t=t, y=np.asarray(even.y), file="webcam")
    dt = float(np.median(np.diff(t)))
    part = _smooth(jittered, 11, 4)
    steps = int((t[-1] - t[0]) // dt)  # whole median steps within the launch
    assert steps * dt <= t[-1] - t[0] < (steps + 1) * dt
    assert part.q.size == steps + 1 - 10
    # the clock's origin does not matter: the same launch recorded from t = 100 s
    later = _smooth(Launch(t=t + 100.0, y=np.asarray(even.y), file="webcam"), 11, 4)
    assert later.q.size == part.q.size
    np.testing.assert_allclose(later.qdd, part.qdd, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(part.qdd))))


def test_a_dropped_frame_is_resampled_up_to_the_last_stamp_despite_rounding() -> None:
    # 5 s at 50 Hz (251 stamps) with the middle frame dropped: the median step is 20 ms and
    # the span 250 steps, but in floating point span / step = 249.99999999999977; the last
    # stamp is still a whole step and is kept: 251 resampled samples, 241 after the 11-sample
    # window's edges (a division by the same 1 + 1e-12 instead of the product would lose it)
    from hydrokit.identify.tare import _smooth

    even = in_air(R, 0.02, 0.05, math.radians(30), 50.0, math.radians(0.01), np.random.default_rng(4), duration=5.0)
    t, y = np.delete(np.asarray(even.t), 125), np.delete(np.asarray(even.y), 125)
    dt = float(np.median(np.diff(t)))
    assert dt == pytest.approx(0.02, rel=1e-12) and (t[-1] - t[0]) / dt < 250.0  # the rounding at issue
    part = _smooth(Launch(t=t, y=y, file="webcam"), 11, 4)
    assert part.q.size == 251 - 10
    # the resampled record is the even one (the dropped frame interpolated back)
    full = _smooth(even, 11, 4)
    np.testing.assert_allclose(part.q[:110], full.q[:110], rtol=0, atol=1e-12)


def test_as_many_smoothed_samples_as_unknowns_is_refused() -> None:
    # one 60-sample launch through a 57-sample window leaves 4 smoothed samples for the 4
    # unknowns (α, β, γ and the launch's rest term): an exact solve with no residual to judge
    # it by, so more samples than unknowns are required
    t = np.arange(60) * 0.01
    y = 0.3 * np.exp(-0.5 * t) * np.cos(2 * math.pi * t / 0.2) + np.random.default_rng(0).normal(0, 1e-4, 60)
    with pytest.raises(InputError, match=r"only 4 samples left after smoothing 1 launch\(es\); expected more than 4"):
        fit_air_tare([Launch(t, y, "air.csv")], 1.2, G, window=57)


@pytest.mark.parametrize(("window", "polyorder"), [(10, 4), (3, 4), (3, 3), (401, 4)])
def test_an_even_too_short_or_too_long_smoothing_window_is_refused(window, polyorder) -> None:
    # Savitzky–Golay needs a centre sample (odd) and more samples than its polynomial order:
    # a window of 3 cannot carry a quartic, nor a cubic (3 samples, 4 coefficients); and the
    # window must leave samples outside it: the whole record (8 s at 50 Hz: 401) is too long
    launch = in_air(R, 0.004, 0.01, math.radians(20), 50.0, 1e-4, np.random.default_rng(2), duration=8.0)
    assert launch.t.size == 401
    lowest = polyorder + 1
    with pytest.raises(
        InputError, match=rf"window = {window}: expected an odd number of samples between {lowest} and 400"
    ):
        fit_air_tare([launch], MASS, G, window=window, polyorder=polyorder)


@pytest.mark.parametrize("alpha", [0.0, 4.0, -math.inf, math.nan])
def test_air_tare_needs_a_finite_restoring_alpha(alpha) -> None:
    # α multiplies sin θ in θ̈ = α sin θ + …: only a negative finite α restores (r = −g/α > 0)
    from hydrokit.identify.tare import air_tare

    with pytest.raises(InputError, match=rf"alpha = {alpha}: expected a negative number \(1/s², restoring in air\)"):
        air_tare(alpha, 0.01, 0.02, MASS)
    assert air_tare(-G / 0.39, 0.01, 0.02, MASS, G).effective_length == pytest.approx(0.39, rel=1e-12)


@pytest.mark.parametrize("mass", [0.0, -1.0, math.nan, math.inf])
def test_air_tare_needs_a_positive_finite_mass(mass) -> None:
    # the pivot friction is taken off as forces on the body's mass: none, a negative one or a
    # non-number is refused by name (a NaN once slipped through `mass <= 0`)
    from hydrokit.identify.tare import air_tare

    with pytest.raises(InputError, match=rf"mass = {mass}: expected a positive mass \(kg\)"):
        air_tare(-G / 0.39, 0.01, 0.02, mass, G)


def test_rounded_stamps_of_a_clip_starting_late_use_the_mean_step() -> None:
    # a 30 fps clip cut from a longer video: stamps from t = 12.3456 s, rounded to 0.1 ms as the
    # launch files store them. The steps are then 33.3 or 33.4 ms (under 5 % apart: no
    # resampling), and the step used is the mean, (t_last − t_first)/(n − 1), which is 1/30 s to
    # 1e-7 relative; the median (33.3 ms) would be 0.1 % short and α 0.2 % off. The samples are
    # used as they are: the same length as the exactly timed launch to 1e-6 (resampled to a grid,
    # as uneven stamps are, the interpolation alone moves it by 7e-5)
    rng = np.random.default_rng(12)
    exact = in_air(R, 0.004, 0.01, math.radians(20), 30.0, 1e-4, rng)
    late = Launch(t=np.round(np.asarray(exact.t) + 12.3456, 4), y=np.asarray(exact.y), file="clip")
    assert float(np.median(np.diff(late.t))) == pytest.approx(0.0333, abs=1e-9)
    a = fit_air_tare([exact], MASS, G)[0].effective_length
    b = fit_air_tare([late], MASS, G)[0].effective_length
    assert b == pytest.approx(a, rel=1e-6)


def test_noise_bias_of_two_launches_with_sensor_zeros_is_the_monte_carlo_mean() -> None:
    # as the one-launch Monte Carlo check above, for two launches whose sensor zeros (25°, −15°)
    # make Σ sin θ large, so each launch's own rest term (entries 3 and 4, the coefficients of
    # cos θ) carries a resolved bias: every entry of the summed bias within 4 Monte Carlo standard
    # errors of the mean of ΔHᵀ Δe drawn launch by launch
    from numpy.lib.stride_tricks import sliding_window_view

    from hydrokit.identify.tare import _noise_terms, _smooth

    rng = np.random.default_rng(13)
    parts = [
        _smooth(in_air(R, 0.02, 0.05, math.radians(30), 50.0, math.radians(0.05), rng, 6.0, math.radians(z)), 11, 4)
        for z in (25.0, -15.0)
    ]
    coef = np.array([-G / R, 0.3, 0.8, 0.6 * G / R, -0.3 * G / R])  # α, β, γ, c₁, c₂
    bias, _ = _noise_terms(parts, coef)
    draws = 3000
    total = np.zeros((draws, coef.size))
    for j, part in enumerate(parts):
        q, qd = part.q, part.qd
        A = coef[0] * np.cos(q) - coef[3 + j] * np.sin(q)
        B = coef[1] + 2.0 * coef[2] * np.abs(qd)
        n = rng.normal(0.0, math.sqrt(part.noise_var), size=(draws, q.size + part.window - 1))
        e0, e1, e2 = (sliding_window_view(n, part.window, axis=1) @ k for k in part.kernels)
        de = e2 - A * e0 + B * e1
        for col, h in zip((0, 1, 2, 3 + j), (np.cos(q) * e0, -e1, -2.0 * np.abs(qd) * e1, -np.sin(q) * e0)):
            total[:, col] += np.sum(h * de, axis=1)
    mean, se = total.mean(axis=0), total.std(axis=0) / math.sqrt(draws)
    assert np.all(np.abs(bias - mean) < 4.0 * se), (bias, mean, se)
    assert np.all(np.abs(bias[3:]) > 10.0 * se[3:])  # the rest terms' bias is resolved


@pytest.mark.parametrize("mass", [0.0, math.nan])
def test_a_bad_mass_is_named_before_the_launches_are_examined(mass) -> None:
    # argument errors first: with a bad mass and a too-short launch, the message is the mass's
    # (the user fixes the command line before re-recording anything)
    rng = np.random.default_rng(0)
    good = in_air(R, 0.004, 0.01, math.radians(20), 30.0, 1e-4, rng)
    short = Launch(t=good.t[:10], y=good.y[:10], file="air_short.csv")
    with pytest.raises(InputError, match=rf"^mass = {mass}: expected a positive mass \(kg\)$"):
        fit_air_tare([good, short], mass, G)


def test_a_light_body_is_tared_in_proportion_to_its_mass() -> None:
    # the tare's forces are the fitted per-unit-mass coefficients times the body's mass: a 0.5 kg
    # body gets a tenth of the 5 kg body's linear friction, the same length
    launch = in_air(R, 0.02, 0.05, math.radians(30), 50.0, math.radians(0.01), np.random.default_rng(6))
    heavy, fit = fit_air_tare([launch], MASS, G)
    light, _ = fit_air_tare([launch], 0.5, G)
    assert light.effective_length == heavy.effective_length
    assert light.linear_damping == pytest.approx(0.5 * fit["beta"], rel=1e-12)
    assert light.linear_damping == pytest.approx(heavy.linear_damping / 10.0, rel=1e-12)
    assert air_tare(fit["alpha"], fit["beta"], fit["gamma"], 0.5, G) == light


def test_a_swing_too_small_to_show_quadratic_friction_is_refused() -> None:
    # 1e-4 rad (0.006°) of swing: |θ̇| θ̇ is ~1e-7 of sin θ's scale, the normal matrix's condition
    # number is far beyond 1e14 though its inverse is still finite: α, β and γ are not separated
    launch = in_air(R, 0.004, 0.01, 1e-4, 30.0, 1e-7, np.random.default_rng(1))
    with pytest.raises(InputError, match=r"^the in-air launches do not separate α, β and γ \(singular regression\)$"):
        fit_air_tare([launch], MASS, G)
    # a millirad swing is separated (γ poorly, but with a standard error that says so)
    launch = in_air(R, 0.004, 0.01, 1e-3, 30.0, 1e-6, np.random.default_rng(1))
    _, fit = fit_air_tare([launch], MASS, G)
    assert fit["std_error"]["gamma"] > abs(fit["gamma"] - 0.01)
