"""Repeats against their stated uncertainties (issue #16 item 5): χ² of the differences."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from hydrokit.identify.campaign import consistency


def test_two_repeats_closed_form():
    # two values: χ² = (x1 − x2)² / (σ1² + σ2²), one degree of freedom
    c = consistency([3.242, 3.230], [0.013, 0.014])
    expected = (3.242 - 3.230) ** 2 / (0.013**2 + 0.014**2)
    assert c["chi2"] == pytest.approx(expected, rel=1e-12) and c["dof"] == 1
    assert c["p"] == pytest.approx(stats.chi2.sf(expected, 1), rel=1e-12)
    assert c["weighted_mean"] == pytest.approx((3.242 / 0.013**2 + 3.230 / 0.014**2) / (1 / 0.013**2 + 1 / 0.014**2))


def test_overconfident_errors_are_caught_honest_ones_pass():
    rng = np.random.default_rng(7)
    sigma = rng.uniform(0.5, 2.0, size=(400, 6))
    x = 10 + rng.normal(size=(400, 6)) * sigma
    honest = np.array([consistency(a, s)["p"] for a, s in zip(x, sigma)])
    # with right errors p is uniform: 5 % below 0.05, binomial sd √(0.05·0.95/400) = 1.1 %
    assert abs(np.mean(honest < 0.05) - 0.05) < 0.035
    shrunk = np.array([consistency(a, s / 1.5)["p"] for a, s in zip(x, sigma)])
    assert np.mean(shrunk < 0.05) > 0.25  # errors stated 1.5× too small are flagged often
    birge = np.median([consistency(a, s / 1.5)["birge_ratio"] for a, s in zip(x, sigma)])
    assert birge == pytest.approx(1.5 * np.sqrt(stats.chi2.median(5) / 5), rel=0.15)


def test_missing_errors_are_skipped_and_one_value_has_no_test():
    c = consistency([1.0, 2.0, None, 4.0], [0.1, None, 0.3, float("nan")])
    assert c["n"] == 1 and c["chi2"] is None and c["p"] is None
    assert c == {"n": 1, "chi2": None, "dof": 0, "p": None, "birge_ratio": None, "weighted_mean": None}
    # a zero standard error is no error estimate (its weight would be infinite): skipped too
    z = consistency([1.0, 1.1, 1.3], [0.1, 0.0, 0.1])
    assert (z["n"], z["dof"], z["weighted_mean"]) == (2, 1, pytest.approx(1.15, rel=1e-12))
    assert z["chi2"] == pytest.approx(0.3**2 / (2 * 0.1**2), rel=1e-12)  # two equal weights: Δ²/(2σ²)


def test_campaign_summary_holds_the_test_per_amplitude_group(pendulum_rig):
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

    sensor = SensorModel(100.0, 1e-4, 0.0, 0.5, "test")
    rng = np.random.default_rng(3)
    launches = [
        trim_launch(simulate_launch(pendulum_rig, 0.06, 0.05, 0.8, a, 12.0, sensor, rng, file=f"l{a}_{j}"))
        for a in (0.1, 0.2)
        for j in range(3)
    ]
    res = identify_launches(pendulum_rig, launches)
    cons = res.summary["consistency"]
    assert set(cons) == {"added_mass", "linear_damping", "quadratic_damping"}
    assert len(cons["added_mass"]) == 2 and all(g["n"] == 3 for g in cons["added_mass"].values())
    assert all(g["dof"] == 2 and 0 <= g["p"] <= 1 for g in cons["added_mass"].values())
