"""Outlier rejection within amplitude groups (issue #13): the modified z-score rule of Iglewicz &
Hoaglin (1993), |x − median| / (1.4826 MAD) > 3.5, judged per group, never a whole group, with the
statistics both with and without the rejection in the summary and the rejected launches marked
in the figures."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.identify.campaign import describe, outliers, summarize
from hydrokit.identify.types import LaunchResult

# Five tight values: sorted 0.9, 0.95, 1.0, 1.05, 1.1. With a sixth value above them all the
# median is (1.0 + 1.05)/2 = 1.025 and the absolute deviations of the five are 0.125, 0.075,
# 0.025, 0.025, 0.075, so MAD = (0.075 + 0.075)/2 = 0.075 whatever the sixth value is
# (its deviation is the largest): robust σ = 1.4826 × 0.075 = 0.111195 (worked by hand).
BASE = [1.0, 1.1, 0.9, 1.05, 0.95]
MEDIAN, SIGMA = 1.025, 1.4826 * 0.075


def with_sixth(z: float) -> list[float]:
    """BASE plus a value at modified z-score ``z`` above the median."""
    return [*BASE, MEDIAN + z * SIGMA]


def test_robust_sigma_is_the_hand_worked_value() -> None:
    x = np.array(with_sixth(3.0))
    assert float(np.median(x)) == pytest.approx(MEDIAN, abs=1e-12)
    assert 1.4826 * float(np.median(np.abs(x - np.median(x)))) == pytest.approx(0.111195, abs=1e-9)


@pytest.mark.parametrize("z", [3.1, 3.4, 3.49])
def test_just_inside_the_threshold_is_kept(z: float) -> None:
    # a rule at 3.0 would reject these
    s = describe(with_sixth(z), [f"f{i}" for i in range(6)])
    assert s["rejected"] == []
    assert s["n"] == 6
    assert s["mean"] == pytest.approx(float(np.mean(with_sixth(z))), rel=1e-12)


@pytest.mark.parametrize("z", [3.51, 3.6, 3.9])
def test_just_outside_the_threshold_is_rejected(z: float) -> None:
    # a rule at 4.0 would keep these
    vals = with_sixth(z)
    s = describe(vals, [f"f{i}" for i in range(6)])
    assert s["rejected"] == ["f5"]
    assert s["n"] == 5
    assert s["mean"] == pytest.approx(float(np.mean(BASE)), rel=1e-12)
    assert outliers(vals).tolist() == [False] * 5 + [True]


def test_with_and_without_rejection_are_both_reported_and_differ() -> None:
    vals = with_sixth(5.0)
    s = describe(vals, [f"f{i}" for i in range(6)])
    every = s["without_rejection"]
    assert s["rejected"] == ["f5"]
    # with: the five kept; without: all six (numpy, a second computation)
    assert (s["n"], every["n"]) == (5, 6)
    assert s["mean"] == pytest.approx(1.0, rel=1e-12)
    assert every["mean"] == pytest.approx(float(np.mean(vals)), rel=1e-12)
    assert every["std"] == pytest.approx(float(np.std(vals, ddof=1)), rel=1e-12)
    # Student-t half width with 5 dof: t_0.975 = 2.5706 (table value)
    assert every["ci"][1] - every["mean"] == pytest.approx(2.5706 * every["std"] / math.sqrt(6), rel=1e-4)
    assert every["mean"] > s["mean"] and every["ci"][1] - every["ci"][0] > s["ci"][1] - s["ci"][0]


def test_without_rejection_equals_with_when_nothing_is_rejected() -> None:
    s = describe(BASE + [1.02], None)
    assert s["rejected"] == []
    assert {k: s[k] for k in ("mean", "std", "ci", "n")} == s["without_rejection"]


def test_a_launch_is_judged_only_against_its_own_group() -> None:
    # three groups of six: K_Q about 2.0 at 20 and 30 mm, 2.4 ± 0.1 at 10 mm (a genuine amplitude
    # effect). Pooled, the 10 mm launches sit 9.8–16.5 robust σ from the campaign median
    # and all six would go; judged within their group none is unusual.
    low = [2.30, 2.35, 2.40, 2.45, 2.50, 2.42]
    mid = [2.00, 2.01, 1.99, 2.02, 1.98, 2.00]
    high = [1.99, 2.00, 2.01, 2.02, 1.98, 2.00]
    vals = low + mid + high
    files = [f"L{g}_{i}" for g in (1, 2, 3) for i in range(1, 7)]
    groups = [f"L{g}" for g in (1, 2, 3) for _ in range(6)]
    pooled = describe(vals, files)
    assert pooled["rejected"] == files[:6]  # the old, pooled rule throws the whole group out
    s = describe(vals, files, groups=groups)
    assert s["rejected"] == []
    assert s["n"] == 18
    assert s["mean"] == pytest.approx(float(np.mean(vals)), rel=1e-12)
    # the interval of every launch is wider than the pooled rule's (it hid the amplitude effect)
    assert s["ci"][1] - s["ci"][0] > 5 * (pooled["ci"][1] - pooled["ci"][0])


def test_an_outlier_inside_a_group_is_still_caught() -> None:
    low = with_sixth(4.0)  # the sixth is 4 robust σ from its own group's median
    mid = [2.0 + 0.01 * k for k in (0, 1, -1, 2, -2, 0)]
    files = [f"L1_{i}" for i in range(6)] + [f"L2_{i}" for i in range(6)]
    s = describe(low + mid, files, groups=["L1"] * 6 + ["L2"] * 6)
    assert s["rejected"] == ["L1_5"]
    assert s["n"] == 11


def test_a_group_is_never_rejected_whole_nor_below_four() -> None:
    # five values: median 1.01, deviations 0, 0.01, 0.02, 8.99, 9.99 -> MAD 0.02; 10 and 11 lie
    # hundreds of robust σ out, but rejecting them would leave 3 < 4 launches: none is rejected
    vals = [1.0, 1.01, 0.99, 10.0, 11.0]
    assert outliers(vals).tolist() == [False] * 5
    s = describe(vals, list("abcde"), groups=["g"] * 5)
    assert s["rejected"] == [] and s["n"] == 5
    # groups under five launches are not judged at all
    assert outliers([1.0, 1.0, 1.01, 50.0]).tolist() == [False] * 4
    # six identical-but-one: MAD = 0, the rule cannot scale the deviation and rejects nothing
    assert outliers([1.0] * 5 + [2.0]).tolist() == [False] * 6


def test_group_labels_must_match_the_values() -> None:
    from hydrokit.errors import InputError

    with pytest.raises(InputError, match="3 values, 3 files and 2 groups"):
        describe([1.0, 2.0, 3.0], ["a", "b", "c"], groups=["g", "g"])


def _launch(file: str, amplitude: float, k_q: float) -> LaunchResult:
    return LaunchResult(
        file=file,
        method="output-error",
        added_mass=0.07,
        added_mass_coefficient=None,
        linear_damping=1.43,
        quadratic_damping=k_q,
        drag_coefficient=None,
        natural_frequency=6.0,
        damping_ratio=0.1,
        reynolds_max=1e4,
        kc=1.0,
        rms_residual=1e-5,
        std_error={},
        amplitude=amplitude,
    )


def test_summarize_groups_by_amplitude_by_default() -> None:
    low = [2.30, 2.35, 2.40, 2.45, 2.50, 2.42]
    rest = [2.00, 2.01, 1.99, 2.02, 1.98, 2.00, 1.99, 2.00, 2.01, 2.02, 1.98, 2.00]
    amps = [0.010] * 6 + [0.020] * 6 + [0.030] * 6
    results = [_launch(f"f{i}", a, v) for i, (a, v) in enumerate(zip(amps, low + rest))]
    s = summarize(results)
    assert s["quadratic_damping"]["rejected"] == []
    assert s["quadratic_damping"]["n"] == 18
    # 95 % intervals by default: t_0.975 with 17 dof = 2.1098 (table value)
    q = s["quadratic_damping"]
    assert q["confidence"] == 0.95
    assert q["ci"][1] - q["mean"] == pytest.approx(2.1098 * q["std"] / math.sqrt(18), rel=1e-4)
    assert s["quadratic_damping"]["without_rejection"]["n"] == 18
    assert "within each amplitude group" in s["outlier_rule"]
    # one launch of the 20 mm group far out: caught, the 10 mm group untouched
    results[8] = _launch("f8", 0.020, 2.5)
    s = summarize(results)
    assert s["quadratic_damping"]["rejected"] == ["f8"]
    assert s["quadratic_damping"]["without_rejection"]["mean"] == pytest.approx(
        float(np.mean([r.quadratic_damping for r in results])), rel=1e-12
    )


def test_rejected_launches_are_hollow_red_in_the_campaign_figure() -> None:
    from matplotlib.colors import to_rgba

    from hydrokit.plot.identify import REJECTED_LABEL, campaign_axes

    results = [_launch(f"f{i}", 0.01, v) for i, v in enumerate(with_sixth(5.0))]
    summary = describe([r.quadratic_damping for r in results], [r.file for r in results])
    ax = campaign_axes(results, "quadratic_damping", summary, "N s^2/m^2")
    labels = ax.get_legend_handles_labels()[1]
    assert REJECTED_LABEL == "rejected (outlier rule)" and REJECTED_LABEL in labels
    assert "mean without rejection" in labels
    (line,) = [h for h, lab in zip(*ax.get_legend_handles_labels()) if lab == REJECTED_LABEL]
    assert line.get_markerfacecolor() == "none"
    assert to_rgba(line.get_markeredgecolor()) == to_rgba("C3")
    assert line.get_ydata().tolist() == [with_sixth(5.0)[5]]
    # nothing rejected: no such legend entry
    clean = describe(BASE + [1.02], None)
    ax = campaign_axes(results[:5], "quadratic_damping", clean, "N s^2/m^2")
    assert REJECTED_LABEL not in ax.get_legend_handles_labels()[1]


def test_rejected_launches_are_marked_against_reynolds_number() -> None:
    from hydrokit.plot.identify import REJECTED_LABEL, coefficients_vs_reynolds

    results = [_launch(f"f{i}", 0.01, v) for i, v in enumerate(with_sixth(5.0))]
    fig = coefficients_vs_reynolds({"sway": results}, rejected={"quadratic_damping": ["f5"]})
    kq = fig.axes[3]
    assert kq.get_ylabel().startswith("K_Q (")  # the label carries its units
    assert REJECTED_LABEL in kq.get_legend_handles_labels()[1]
    assert REJECTED_LABEL not in fig.axes[2].get_legend_handles_labels()[1]


def test_the_identify_report_warning_gives_the_all_launch_statistics() -> None:
    from hydrokit.report.html import fmt
    from hydrokit.report.identify import COEFS, rejection_note

    vals = with_sixth(5.0)
    files = [f"f{i}" for i in range(6)]
    kept = describe(BASE + [1.02], files)
    hit = describe(vals, files)
    summary = {k: kept for k, _ in COEFS} | {"linear_damping": hit, "outlier_rule": "3.5 MAD"}
    note = rejection_note("equation", summary)
    every = hit["without_rejection"]
    lo, hi = every["ci"]
    assert note == (
        "equation: outliers rejected (3.5 MAD): f5; over every launch: "
        f"K_L {fmt(every['mean'])} ± {fmt(every['std'])} [{fmt(lo)}, {fmt(hi)}]"
    )
    assert rejection_note("equation", {k: kept for k, _ in COEFS} | {"outlier_rule": "x"}) is None


def test_a_group_of_exactly_five_may_lose_one_to_leave_four() -> None:
    # the smallest judged group: five values, median 1.0, MAD 0.01 (robust σ 0.0148); 10.0 is
    # 600 robust σ out and rejecting it leaves exactly the four required
    vals = [1.0, 1.01, 0.99, 1.02, 10.0]
    assert outliers(vals).tolist() == [False] * 4 + [True]
    s = describe(vals, list("abcde"), groups=["g"] * 5)
    assert s["rejected"] == ["e"] and s["n"] == 4
    assert s["mean"] == pytest.approx(1.005, rel=1e-12)


def test_no_finite_value_gives_empty_statistics() -> None:
    # a coefficient no launch could give (all None or NaN): n = 0, no mean, no interval
    s = describe([None, math.nan], ["a", "b"])
    assert {k: s[k] for k in ("mean", "std", "ci", "n")} == {"mean": None, "std": None, "ci": [None, None], "n": 0}
    assert s["without_rejection"]["n"] == 0 and s["rejected"] == []


def test_one_launch_has_no_spread_and_two_have_the_sample_std() -> None:
    # one value: std 0 and no interval (no degrees of freedom); two: the n − 1 sample std
    # |x1 − x2|/√2 and the Student-t interval with 1 dof (t_0.975 = 12.706, table value)
    one = describe([1.5], ["a"])
    assert (one["mean"], one["std"], one["ci"], one["n"]) == (1.5, 0.0, [None, None], 1)
    two = describe([1.0, 2.0], ["a", "b"])
    assert two["std"] == pytest.approx(1 / math.sqrt(2), rel=1e-12)
    assert two["ci"][1] - two["mean"] == pytest.approx(12.706 * two["std"] / math.sqrt(2), rel=1e-4)
