"""Standard errors that survive model error (issue #16 item 4): the cycle-wise jackknife
against the formal white-noise errors, on records whose truth the fitted model lacks."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from hydrokit.identify.estimators import cycle_jackknife


def _generator():
    spec = importlib.util.spec_from_file_location("gen", Path(__file__).parent / "test_release_window.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    return gen


def test_cycle_jackknife_reduces_to_the_formal_errors_for_white_noise():
    # linear regression y = X β + e, white e: the cycle jackknife estimates σ² (XᵀX)⁻¹
    rng = np.random.default_rng(1)
    n, B = 4000, 40
    X = np.column_stack([np.ones(n), np.sin(np.linspace(0, 60, n)), np.linspace(-1, 1, n)])
    ratios = []
    for _ in range(30):
        e = rng.normal(0, 0.3, n)
        beta, *_ = np.linalg.lstsq(X, e, rcond=None)
        r = e - X @ beta
        formal = r @ r / (n - 3) * np.linalg.inv(X.T @ X)
        cyc = np.repeat(np.arange(B), n // B)
        ratios.append(np.diag(cycle_jackknife(-X, r, cyc, 0 * formal)) / np.diag(formal))
    # the jackknife errs on the safe side (Efron–Stein: its variance is biased up, here by the
    # clusters' leverage, ~1/B each): about σ² (XᵀX)⁻¹, never below it on average
    mean = np.mean(ratios, axis=0)
    assert np.all(mean > 0.97) and np.all(mean < 1.2), mean


@pytest.mark.parametrize("B", [3, 12])
def test_cycle_jackknife_is_the_delete_one_cycle_refit_for_a_linear_model(B):
    # second method: actually refit without each cycle; for a linear model one Gauss–Newton step
    # from the full solution lands exactly on the refit. Three cycles are the fewest it uses:
    # with two, deleting one leaves a single cycle to spread over, and the formal one is kept
    rng = np.random.default_rng(4)
    n = 600
    X = np.column_stack([np.ones(n), np.sin(np.linspace(0, 30, n)), np.linspace(-1, 1, n) ** 2])
    y = X @ np.array([0.5, -1.0, 2.0]) + rng.normal(0, 0.2, n)
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    cyc = np.repeat(np.arange(B), n // B)
    refits = np.array([np.linalg.lstsq(X[cyc != b], y[cyc != b], rcond=None)[0] for b in range(B)])
    dev = refits - refits.mean(axis=0)
    expected = (B - 1) / B * dev.T @ dev
    got = cycle_jackknife(X, X @ beta - y, cyc, np.zeros((3, 3)))  # r = Xβ − y, J = X
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-15)
    formal = np.eye(3)
    two = cycle_jackknife(X, X @ beta - y, (np.arange(n) >= n // 2).astype(int), formal)
    np.testing.assert_array_equal(two, formal)


def test_cycle_jackknife_sees_residuals_correlated_within_a_cycle():
    # residual = a random level per cycle (model error repeating over a cycle) + white noise
    rng = np.random.default_rng(2)
    n, B = 4000, 40
    X = np.column_stack([np.ones(n), np.linspace(-1, 1, n)])
    cyc = np.repeat(np.arange(B), n // B)
    e = rng.normal(0, 0.3, B)[cyc] + rng.normal(0, 0.05, n)
    beta, *_ = np.linalg.lstsq(X, e, rcond=None)
    r = e - X @ beta
    formal = r @ r / (n - 2) * np.linalg.inv(X.T @ X)
    clustered = cycle_jackknife(-X, r, cyc, formal)
    # the mean of 40 independent levels of sd 0.3 has sd 0.3/√40 = 0.047; formal says ~0.005
    assert math.sqrt(clustered[0, 0]) > 5 * math.sqrt(formal[0, 0])
    assert math.sqrt(clustered[0, 0]) == pytest.approx(0.3 / math.sqrt(B), rel=0.35)


@pytest.mark.needs_jit(reason="30 hand-heel records fitted")
def test_equivalent_damping_sigma_covers_the_truth_under_model_error():
    """Cubic damping in the truth, quadratic model fitted and B_e taken from it
    (equivalent_model "fitted"), coloured noise, drift, hand heel, one condition: the formal σ
    covers the truth of B_e(5°) in about a third of records, the cycle-jackknife σ in about all."""
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    gen = _generator()
    a = math.radians(5.0)
    truth = gen.true_equivalent(a)
    hit = hit_formal = 0
    n = 30
    for seed in range(n):
        launch = trim_launch(gen.hand_heel_record(seed=seed))
        res = identify_launches(gen.rig(), [launch], equivalent_at=[a], equivalent_model="fitted")
        be = res.results[0].extra["equivalent_damping"][0]
        hit += abs(be["value"] - truth) <= 1.96 * be["std_error"]
        hit_formal += abs(be["value"] - truth) <= 1.96 * be["std_error_formal"]
        assert res.results[0].extra["uncertainty_method"].startswith("cycle-wise jackknife")
    # binomial: 30 records at 95 % → at least 24 covered with probability > 0.99
    assert hit >= 24
    assert hit_formal <= 20  # the formal σ is overconfident here: that is what the issue is about


def varied_record(gen, rng: np.random.Generator, seed: int, drift: float | None = None):  # noqa: ANN001, ANN201
    """A hand-heel record (cubic damping, coloured noise, drift) under conditions drawn at random:
    one fixed condition makes coverage a matter of that condition's bias (all or nothing), not a
    rate. ``drift`` (°/min) overrides the drawn one. Returns the record and its truth."""
    truth = {"I_a": 19.0, "B1": rng.uniform(0.5, 2.5), "B2": rng.uniform(6, 18), "B3": rng.uniform(0, 40)}
    heel = math.radians(rng.uniform(8, 14))
    noise, drawn = rng.uniform(0.01, 0.04), rng.uniform(-0.5, 0.5)
    drift = drawn if drift is None else drift
    record = gen.hand_heel_record(seed=seed, noise=noise, drift=drift, truth=truth, heel=heel)
    return record, truth


@pytest.mark.needs_jit(reason="40 varied long records fitted")
def test_equivalent_damping_from_the_cubic_fit_covers_where_the_quadratic_is_biased():
    """Varied conditions: B_e(5°) from the cubic refit (the default) keeps ±1.96 σ around the
    truth; the quadratic model's own B_e (kept as value_fitted_model) is biased beyond its σ in
    many records (bench/uncertainty_coverage.py prints both over 200+ records)."""
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    gen = _generator()
    rng = np.random.default_rng(7)
    a = math.radians(5.0)
    n = 40
    hit = hit_fitted = 0
    for seed in range(n):
        record, truth = varied_record(gen, rng, seed)
        res = identify_launches(gen.rig(), [trim_launch(record)], equivalent_at=[a])
        assert res.results[0].extra["equivalent_damping_model"] == "cubic"
        be = res.results[0].extra["equivalent_damping"][0]
        true_be = gen.true_equivalent(a, truth)
        hit += abs(be["value"] - true_be) <= 1.96 * be["std_error"]
        hit_fitted += abs(be["value_fitted_model"] - true_be) <= 1.96 * be["std_error_fitted_model"]
    # at a true 95 %, 40 records cover ≥ 34 with probability 0.986; the quadratic's ~60 % gives
    # ≤ 30 with probability > 0.99
    assert hit >= 34, (hit, hit_fitted)
    assert hit_fitted <= 30, (hit, hit_fitted)


def test_each_launch_carries_its_covariance_in_reported_units():
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    gen = _generator()
    r = identify_launches(gen.rig(), [trim_launch(gen.hand_heel_record(seed=3))]).results[0]
    cov = np.array(r.extra["covariance"])
    assert r.extra["covariance_parameters"] == ["added_mass", "linear_damping", "quadratic_damping"]
    assert np.allclose(np.sqrt(np.diag(cov)), [r.std_error[k] for k in r.extra["covariance_parameters"]], rtol=1e-9)
    assert np.all(
        np.sqrt(np.diag(cov)) >= [r.extra["std_error_formal"][k] * (1 - 1e-9) for k in r.extra["covariance_parameters"]]
    )


def test_adequacy_verdict_tells_noise_from_model_error():
    from hydrokit.identify.estimators import adequacy

    rng = np.random.default_rng(5)
    t = np.arange(2000) * 0.01
    noise = rng.normal(0, 0.01, t.size)
    white = adequacy(noise, t, period=2.0, noise=0.01)
    assert white["verdict"].startswith("adequate") and abs(white["acf_at_period"]) < 0.1
    assert white["residual_to_noise"] == pytest.approx(1.0, rel=0.05)
    # a residual that repeats each 2 s cycle (model error) on top of the noise
    periodic = 0.2 * np.sin(2 * np.pi * t / 2.0) * np.exp(-t / 10) + noise
    bad = adequacy(periodic, t, period=2.0, noise=0.01)
    assert bad["verdict"].startswith("model error") and bad["acf_at_period"] > 0.5
    drift = adequacy(0.05 * (t - t.mean()) + noise, t, period=2.0, noise=0.01)
    assert drift["residual_to_noise"] > 2.0


def test_launches_carry_the_verdict():
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    gen = _generator()
    r = identify_launches(gen.rig(), [trim_launch(gen.hand_heel_record(seed=4))]).results[0]
    a = r.extra["adequacy"]
    # cubic damping fitted with the quadratic model and AR(1) noise: a model-error verdict
    assert a["residual_to_noise"] > 1.0 and isinstance(a["verdict"], str) and a["acf_at_period"] is not None


@pytest.mark.slow
def test_equivalent_damping_coverage_over_200_varied_records():
    """Issue #16 acceptance: over ≥ 200 records with model error the fit lacks (cubic damping in
    the truth, coloured noise, hand heel, drift; conditions drawn per record) the truth of B_e(5°)
    lies inside ±1.96 σ in 95 % of them within the binomial tolerance; the formal σ's coverage is
    printed beside. ~4 min (pytest -m slow); bench/uncertainty_coverage.py prints the same."""
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    gen = _generator()
    rng = np.random.default_rng(1)
    a = math.radians(5.0)
    n = 200
    hit = hit_formal = 0
    for seed in range(n):
        record, truth = varied_record(gen, rng, seed)
        be = identify_launches(gen.rig(), [trim_launch(record)], equivalent_at=[a]).results[0]
        row = be.extra["equivalent_damping"][0]
        err = abs(row["value"] - gen.true_equivalent(a, truth))
        hit += err <= 1.96 * row["std_error"]
        hit_formal += err <= 1.96 * row["std_error_formal"]
    tol = 1.96 * math.sqrt(0.95 * 0.05 / n)
    print(f"coverage {hit / n:.3f} (formal σ {hit_formal / n:.3f}), 0.95 ± {tol:.3f}")
    assert abs(hit / n - 0.95) <= tol, (hit, hit_formal)
    assert hit_formal / n < 0.95 - tol  # the white-noise σ does not survive model error
