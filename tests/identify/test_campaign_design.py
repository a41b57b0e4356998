from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2

from hydrokit.identify.campaign import describe
from hydrokit.identify.design import plan_experiment
from hydrokit.identify.estimators import identify_launch
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch


def test_describe_statistics_and_outlier_rule():
    vals = [1.0, 1.1, 0.9, 1.05, 0.95, 5.0]
    s = describe(vals, [f"f{i}" for i in range(6)])
    assert s["rejected"] == ["f5"]
    kept = np.array(vals[:5])
    assert s["mean"] == pytest.approx(kept.mean())
    assert s["std"] == pytest.approx(kept.std(ddof=1))
    # t-interval with 4 dof: t_0.975 = 2.776 (table value)
    half = 2.776 * kept.std(ddof=1) / math.sqrt(5)
    assert s["ci"][1] - s["mean"] == pytest.approx(half, rel=1e-3)


@pytest.mark.needs_jit(reason="200 output-error fits")
def test_cramer_rao_bound_predicts_output_error_spread(pendulum_rig):
    # output-error is efficient on white noise, so the Cramér-Rao bound of the plan is the std of
    # the fits. With N = 200 launches (N - 1) s² / CRB² ~ χ²(199) must lie within its 0.1 % and
    # 99.9 % quantiles, 143.0 and 266.4 (s / CRB within 0.848 - 1.157). Power: a bound 1.5x too
    # small gives 1.5² · 199 = 448 on average (passes with probability P(χ²(199) < 118.4) = 1e-6),
    # 1.5x too large gives 199 / 1.5² = 88 < 143.0. Over 2000 launches s / CRB is 0.998 (m_a),
    # 1.001 (K_L), 0.994 (K_Q).
    n = 200
    truth = (0.05, 0.02, 0.3)
    sensor = SensorModel.imu(hold_time=0)
    plan = plan_experiment(pendulum_rig, *truth, [0.15], sensor, duration=10.0)[0]
    streams = np.random.SeedSequence(37).spawn(n)
    fits = [
        identify_launch(
            pendulum_rig,
            simulate_launch(pendulum_rig, *truth, 0.15, 10.0, sensor, rng=np.random.default_rng(s)),
            "output-error",
        )
        for s in streams
    ]
    low, high = chi2.ppf([0.001, 0.999], n - 1)
    for c in ("added_mass", "linear_damping", "quadratic_damping"):
        stat = (n - 1) * np.var([getattr(f, c) for f in fits], ddof=1) / plan[c] ** 2
        assert low < stat < high, (c, stat, low, high)


def test_plan_prefers_large_amplitude_for_quadratic_damping(pendulum_rig):
    plan = plan_experiment(pendulum_rig, 0.05, 0.02, 0.3, [0.05, 0.25], SensorModel.imu())
    assert plan[1]["quadratic_damping_rel"] < plan[0]["quadratic_damping_rel"]


def test_a_perfect_sensor_has_no_bound_and_says_so(pendulum_rig):
    # zero noise and no quantisation: the Fisher information is infinite, the bound zero
    from hydrokit.errors import InputError
    from hydrokit.identify.design import cramer_rao

    with pytest.raises(InputError) as err:
        cramer_rao(pendulum_rig, 0.05, 0.02, 0.3, 0.1, 5.0, SensorModel(100.0, 0.0, 0.0))
    assert str(err.value) == (
        "sensor noise_std = 0 and resolution = 0: the bound is zero; expected a noise_std or resolution > 0 (m or rad)"
    )
    # quantisation alone is a noise of variance r²/12: the same bound as white noise of std r/√12
    r = 1e-3
    q = cramer_rao(pendulum_rig, 0.05, 0.02, 0.3, 0.1, 5.0, SensorModel(100.0, 0.0, r))
    w = cramer_rao(pendulum_rig, 0.05, 0.02, 0.3, 0.1, 5.0, SensorModel(100.0, r / math.sqrt(12.0), 0.0))
    np.testing.assert_allclose(q.pop("covariance"), w.pop("covariance"), rtol=1e-12)
    assert q == pytest.approx(w, rel=1e-12)


def test_damping_force_spread_is_the_gradient_through_the_covariance(pendulum_rig):
    # F = K_L u + K_Q u² at the peak speed u: var F = gᵀ C g with g = (0, u, u²); relative to F
    from hydrokit.identify.design import cramer_rao

    out = cramer_rao(pendulum_rig, 0.05, 0.02, 0.3, 0.2, 10.0, SensorModel.imu())
    C = np.asarray(out["covariance"])
    assert np.sqrt(np.diag(C)) == pytest.approx([out["added_mass"], out["linear_damping"], out["quadratic_damping"]])
    u = out["speed_max"]
    g = np.array([0.0, u, u * u])
    assert out["damping_force_rel"] == pytest.approx(math.sqrt(g @ C @ g) / (0.02 * u + 0.3 * u * u), rel=1e-9)
    assert 0.1 < u < 1.0  # u² ≠ 1: a force written K_Q u/u would not pass


def test_cramer_rao_is_the_fisher_bound_of_an_independent_simulation(spring_rig):
    # the bound from scratch: the physical spring ODE (m + m_a) ẍ + K_L ẋ + K_Q |ẋ| ẋ + k x = 0
    # integrated by scipy (DOP853, rtol 1e-12), its sensitivities to (m_a, K_L, K_Q, x0, ẋ0,
    # offset) by central differences on the sample times 0, 0.05, …, 3 s (61 samples), and
    # cov = σ² (JᵀJ)⁻¹; no normalised parameters, no compiled RK4. They agree to ~1e-4 (the
    # RK4's and the differences' own errors); one sample more or fewer moves the bound by 3–6 %
    from scipy.integrate import solve_ivp

    from hydrokit.identify.design import cramer_rao

    m, k = spring_rig.mass, spring_rig.stiffness
    truth, a, rate, duration, sigma = (0.2866, 0.5, 5.0), 0.03, 20.0, 3.0, 1e-4
    t = np.arange(61) / rate

    def signal(p: np.ndarray) -> np.ndarray:
        ma, kl, kq, x0, v0, off = p

        def rhs(_: float, s: np.ndarray) -> list[float]:
            return [s[1], -(kl * s[1] + kq * abs(s[1]) * s[1] + k * s[0]) / (m + ma)]

        sol = solve_ivp(rhs, (0.0, t[-1]), [x0, v0], t_eval=t, rtol=1e-12, atol=1e-15, method="DOP853")
        return sol.y[0] + off

    p0 = np.array([*truth, a, 0.0, 0.0])
    J = np.empty((t.size, 6))
    for i in range(6):
        dp = np.zeros(6)
        dp[i] = 1e-6 * max(abs(p0[i]), 1e-3)
        J[:, i] = (signal(p0 + dp) - signal(p0 - dp)) / (2 * dp[i])
    sd = np.sqrt(np.diag(sigma**2 * np.linalg.inv(J.T @ J))[:3])
    crb = cramer_rao(spring_rig, *truth, a, duration, SensorModel(rate, sigma, 0.0, 0.0))
    got = [crb[c] for c in ("added_mass", "linear_damping", "quadratic_damping")]
    np.testing.assert_allclose(got, sd, rtol=1e-3)


def test_plan_defaults_to_one_twenty_second_launch_per_amplitude(pendulum_rig):
    sensor = SensorModel.imu()
    args = (pendulum_rig, 0.05, 0.02, 0.3, [0.1], sensor)
    (default,) = plan_experiment(*args)
    assert default == plan_experiment(*args, duration=20.0, launches=1)[0]
    assert default["launches"] == 1
    assert default["added_mass"] != plan_experiment(*args, duration=10.0)[0]["added_mass"]


@pytest.mark.parametrize("amplitude", [0.0, math.nan, math.inf, -math.inf])
def test_plan_refuses_a_zero_or_non_finite_amplitude(pendulum_rig, amplitude):
    from hydrokit.errors import InputError

    with pytest.raises(InputError, match=rf"amplitude = {amplitude}: expected a non-zero displacement"):
        plan_experiment(pendulum_rig, 0.05, 0.02, 0.3, [0.1, amplitude], SensorModel.imu())
    # any other amplitude is a candidate, a whole radian or a release to the other side
    rows = plan_experiment(pendulum_rig, 0.05, 0.02, 0.3, [1.0, -0.1], SensorModel.imu(), duration=5.0)
    assert [r["amplitude"] for r in rows] == [1.0, -0.1]


def test_recommendation_names_the_best_amplitude_per_coefficient():
    from hydrokit.identify.design import recommend

    assert recommend([]) == "no candidate amplitudes"
    # truth m_a 1, K_L 2, K_Q 10: relative errors are the absolute ones over these
    rows = [
        {"amplitude": 0.1, "quadratic_damping": 5.0, "linear_damping": 0.02, "added_mass": 0.03},
        {"amplitude": 0.3, "quadratic_damping": 0.5, "linear_damping": 0.04, "added_mass": 0.002},
    ]
    for r in rows:
        for k, true in (("added_mass", 1.0), ("linear_damping", 2.0), ("quadratic_damping", 10.0)):
            r[k + "_rel"] = r[k] / true
    text = recommend(rows)
    assert "largest speeds (amplitude 0.3: ±5 %)" in text
    assert "linear damping at amplitude 0.1 (±1 %)" in text
    assert "added mass at 0.3 (±0.2 %)" in text


def test_recommendation_with_a_true_coefficient_of_zero_names_the_absolute_error():
    # rig plan with --linear-damping 0 printed "amplitude 0.01 (±nan %)": nan ranks first in min()
    from hydrokit.identify.design import recommend

    nan = float("nan")
    rows = [
        {"amplitude": 0.01, "quadratic_damping": 1.6, "linear_damping": 0.06, "added_mass": 3e-4},
        {"amplitude": 0.02, "quadratic_damping": 0.27, "linear_damping": 0.018, "added_mass": 1.6e-4},
    ]
    for r in rows:
        r |= {"quadratic_damping_rel": r["quadratic_damping"] / 5, "linear_damping_rel": nan, "added_mass_rel": 1.0}
    text = recommend(rows)
    assert "linear damping at amplitude 0.02 (±0.018 SI, the true value being 0)" in text
    assert "nan" not in text
