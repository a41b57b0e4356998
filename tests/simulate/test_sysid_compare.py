"""Model structures compared (issue #48 item 5): candidates fitted on the same generated dives
are ranked by held-out error and BIC. The true structure beats one that misses a term that
matters (no quadratic yaw damping) on both; a candidate with an extra useless parameter predicts
as well but is not preferred by BIC, so the simpler true one is kept."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any, cast

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.sysid.compare import (
    EQUIVALENT,
    Scored,
    choose,
    effective_fraction,
    heldout_nrmse,
    information,
)

#: the yaw coefficients of the true structure
FREE = ("added_mass.yaw", "linear_damping.yaw", "quadratic_damping.yaw")


# ------------------------------------------------------------------------------ the criteria
def test_the_likelihood_is_the_gaussian_one_at_the_fitted_variance() -> None:
    """−2 ln L of white residuals equals −2 Σ log N(e; 0, σ̂) summed by scipy (second method),
    and AIC/BIC add 2k and k ln N to it."""
    from scipy.stats import norm

    rng = np.random.default_rng(0)
    a, b = 0.02 * rng.standard_normal(800), 0.5 * rng.standard_normal(300)
    out = information([("run1", "psi", a), ("run1", "u", b)], k=3)
    expected = -2 * sum(float(np.sum(norm.logpdf(e, scale=np.sqrt(np.mean(e**2))))) for e in (a, b))
    assert out["minus_2_log_likelihood"] == pytest.approx(expected, rel=1e-12)  # same sums: rounding only
    assert out["n"] == out["n_eff"] == 1100
    assert out["aic"] - out["minus_2_log_likelihood"] == pytest.approx(6.0)
    assert out["bic"] - out["minus_2_log_likelihood"] == pytest.approx(3 * math.log(1100))


def test_the_effective_count_of_an_ar1_series_is_its_closed_form() -> None:
    """An AR(1) series with ρ = 0.8 counts as N (1 − ρ)/(1 + ρ) = N/9 samples; white noise as N.
    Tolerance 0.01: the lag-1 estimate over 20 000 samples has σ ≈ √((1 − ρ²)/N) ≈ 0.004, which
    moves the fraction by ≈ 0.003."""
    rng = np.random.default_rng(1)
    n, rho = 20000, 0.8
    w = rng.standard_normal(n)
    x = np.empty(n)
    x[0] = w[0]
    for i in range(1, n):
        x[i] = rho * x[i - 1] + math.sqrt(1 - rho**2) * w[i]
    frac = effective_fraction([("r", "p", x), ("r", "u", w)])
    assert frac["p"] == pytest.approx((1 - rho) / (1 + rho), abs=0.01)
    assert frac["u"] == pytest.approx(1.0, abs=0.03)
    # the same residuals weighed at N/9 samples: the likelihood term shrinks by that factor
    full = information([("r", "p", x)], 1)
    eff = information([("r", "p", x)], 1, frac)
    assert eff["minus_2_log_likelihood"] == pytest.approx(full["minus_2_log_likelihood"] * frac["p"], rel=1e-12)


def _scored(name: str, k: int, heldout: float, bic: float, fits: bool = True) -> Scored:
    result = cast(Any, SimpleNamespace(verdict={"fits": fits, "reasons": []}))
    info = {"n": 1000.0, "n_eff": 1000.0, "minus_2_log_likelihood": bic, "aic": bic, "bic": bic}
    return Scored(name, name, (), k, result, {"psi": heldout}, heldout, info)


def test_the_lowest_held_out_error_is_kept_and_the_sentence_says_why() -> None:
    ranking, keep, text = choose([_scored("A", 7, 0.21, -900.0), _scored("B", 3, 0.08, -935.0)])
    assert (ranking, keep) == (("B", "A"), "B")
    assert text == (
        "Keep B: lowest held-out error (0.08 vs 0.21 for A) and lowest BIC (ΔBIC 35 to A); "
        "A's extra 4 parameters do not pay."
    )


def test_candidates_that_predict_equally_keep_the_lowest_bic() -> None:
    # within 5 %: the simpler one has the lower BIC (a useless parameter costs ln N)
    ranking, keep, text = choose([_scored("A", 3, 0.100, -1000.0), _scored("B", 4, 0.098, -994.0)])
    assert keep == "A" and ranking == ("A", "B")
    assert "A and B predict equally (held-out within 5 %" in text and "keep the simpler A" in text
    # within 5 %, but the larger one's parameters pay on the training runs
    _, keep, text = choose([_scored("A", 3, 0.100, -1000.0), _scored("B", 5, 0.099, -1100.0)])
    assert keep == "B" and "its extra 2 parameters pay on the training runs (ΔBIC 100 to A)" in text
    # just outside 5 %: the held-out error decides alone
    _, keep, _ = choose([_scored("A", 3, 0.100 * (1 + EQUIVALENT) * 1.01, -1000.0), _scored("B", 5, 0.1, -900.0)])
    assert keep == "B"


def test_a_lower_bic_that_does_not_predict_is_said() -> None:
    # the real-data case (Esso Osaka zigzags): the most flexible structure fits the training runs
    # best but predicts worse than two that predict equally
    ranking, keep, text = choose(
        [_scored("A", 7, 0.742, -1255.0), _scored("B", 8, 0.750, -1132.0), _scored("C", 9, 0.925, -1390.0)]
    )
    assert keep == "A" and ranking == ("A", "B", "C")
    assert "keep the simpler A" in text
    assert "C has a lower BIC (by 135) but predicts the held-out runs worse (0.93)" in text


def test_a_kept_candidate_that_does_not_fit_is_said() -> None:
    _, _, text = choose([_scored("A", 3, 0.6, -10.0, fits=False), _scored("B", 3, 0.9, -5.0, fits=False)])
    assert text.endswith("but even A does not describe the runs (its verdict): try another structure.")


def test_one_candidate_is_refused() -> None:
    with pytest.raises(InputError, match=r"1 candidate\(s\): expected two or more"):
        choose([_scored("A", 3, 0.1, 0.0)])


# ------------------------------------------------------------------------------ the fits
@pytest.fixture(scope="module")
def compared() -> Any:
    """Two 12 s dives of a vehicle with hidden coefficients (one fitted, one held out) and three
    candidates started 30 % off the truth: the true structure, one without quadratic yaw damping
    (fixed at 0), and the true one with a useless extra free parameter (heave linear damping, at
    its true value already)."""
    import hydrokit
    from hydrokit.sysid.compare import Candidate, compare
    from hydrokit.sysid.data import generate_runs, hidden_vehicle
    from hydrokit.sysid.model import free_parameters, values_of, with_values

    truth = hidden_vehicle(hydrokit.load_vehicle("bluerov2-sysid"), 2)
    runs = generate_runs(truth, 2, 12.0, seed=5, dt=0.01)
    v, params = free_parameters(truth, FREE)
    start = with_values(v, params, values_of(v, params) * np.array([1.3, 0.7, 1.3]))
    v2, p2 = free_parameters(start, ["quadratic_damping.yaw"])
    linear = with_values(v2, p2, np.array([0.0]))
    cands = [
        Candidate("true", start, FREE, runs[:1], runs[1:]),
        Candidate("linear", linear, FREE[:2], runs[:1], runs[1:]),
        Candidate("extra", start, (*FREE, "linear_damping.heave"), runs[:1], runs[1:]),
    ]
    return compare(cands, samples=0, check_step=False)


@pytest.mark.needs_jit(reason="three output-error fits over 12 s of dives")
def test_the_true_structure_beats_a_missing_term_on_held_out_error_and_bic(compared: Any) -> None:
    true, linear = compared.by_name("true"), compared.by_name("linear")
    # measured: held-out NRMSE 0.07 vs 0.16, BIC lower by ~10⁴ (the missing term leaves ψ and r
    # residuals many times the sensor noise)
    assert true.heldout < 0.8 * linear.heldout
    assert true.bic < linear.bic - 100
    assert compared.ranking.index("true") < compared.ranking.index("linear")
    assert linear.verdict["fits"] is False and true.verdict["fits"] is True


@pytest.mark.needs_jit(reason="three output-error fits over 12 s of dives")
def test_a_useless_parameter_predicts_as_well_but_bic_keeps_the_simpler(compared: Any) -> None:
    true, extra = compared.by_name("true"), compared.by_name("extra")
    assert extra.heldout == pytest.approx(true.heldout, rel=EQUIVALENT)
    assert extra.bic > true.bic
    assert compared.keep == "true" and compared.ranking[0] == "true"
    assert "keep the simpler true" in compared.recommendation


@pytest.mark.needs_jit(reason="three output-error fits over 12 s of dives")
def test_held_out_nrmse_is_the_prediction_error_over_the_channel_spread(compared: Any) -> None:
    """The score recomputed from the held-out predictions (second path: measured and simulated
    series, not the run rows)."""
    res = compared.by_name("linear").result
    scores = heldout_nrmse(res)
    (pred,) = [p for p in res.predictions if p["holdout"]]
    for c, v in scores.items():
        d = pred["channels"][c]
        e = np.asarray(d["measured"]) - np.asarray(d["simulated"])
        assert v == pytest.approx(np.sqrt(np.mean(e**2)) / np.std(d["measured"]), rel=1e-12)
    assert compared.by_name("linear").heldout == pytest.approx(np.mean(list(scores.values())))


@pytest.mark.needs_jit(reason="three output-error fits over 12 s of dives")
def test_compare_json_lists_every_candidate_and_the_ranking(compared: Any) -> None:
    import json

    doc = json.loads(json.dumps(compared.to_dict(), allow_nan=False))
    assert [c["name"] for c in doc["candidates"]] == ["true", "linear", "extra"]
    assert [c["k"] for c in doc["candidates"]] == [3, 2, 4]
    assert doc["ranking"][0] == doc["keep"] == "true"
    assert doc["recommendation"] == compared.recommendation
    first = doc["candidates"][0]
    assert {"aic", "bic", "heldout_nrmse", "verdict", "parameters", "free", "vehicle"} <= set(first)
    assert [p["name"] for p in first["parameters"]] == list(FREE)


@pytest.mark.needs_jit(reason="three output-error fits over 12 s of dives")
def test_the_report_shows_the_candidates_side_by_side_with_user_text_escaped(compared: Any) -> None:
    from dataclasses import replace

    from hydrokit.report.sysid_compare import report_html

    first = replace(compared.candidates[0], source="<script>alert(1)</script>.yaml")
    html = report_html(replace(compared, candidates=(first, *compared.candidates[1:])))
    assert "<script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;.yaml" in html
    assert html.count("<img") == 1  # the per-channel held-out bars
    # one column per candidate in the parameter table, in the order given
    head = html.split('<th class="l">parameter</th>', 1)[1].split("</tr>", 1)[0]
    assert [h.split(">", 1)[1].split("<", 1)[0] for h in head.split("<th")[1:]] == ["true", "linear", "extra"]
