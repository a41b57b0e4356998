"""The verdict of a system identification (issue #49 item 1): does the identified model
describe the runs? A correct model on generated dives passes; a wrong base vehicle (buoyancy,
centre of gravity or of buoyancy, inertia) fails with a reason naming the channels it spoils."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from hydrokit.sysid.stats import (
    COLOURED,
    EXCESS,
    NRMSE_LIMIT,
    PREFILTERED,
    SYSTEMATIC,
    channel_checks,
    verdict,
    whiteness,
)

#: the free yaw coefficients (the wrong vehicles differ elsewhere: nothing free can absorb it)
FREE = ["added_mass.yaw", "linear_damping.yaw", "quadratic_damping.yaw"]


def _row(name: str, holdout: bool, channels: dict[str, tuple[np.ndarray, np.ndarray, float]]) -> dict[str, Any]:
    """A run row as identify writes it, from (measured, residual, sensor σ) per channel."""
    out = {}
    for c, (y, e, s) in channels.items():
        out[c] = {"residual_rms": float(np.sqrt(np.mean(e**2))), "whiteness": whiteness(e), **channel_checks(y, e, s)}
    return {"name": name, "holdout": holdout, "channels": out}


def test_white_residuals_at_the_sensor_noise_pass_and_a_slow_error_fails() -> None:
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 20.0, 0.02)
    y = np.sin(0.5 * t)  # a channel that moves: std 0.71 against σ = 0.01
    sigma = 0.01
    white = sigma * rng.standard_normal(t.size)
    good = verdict([_row("d1", False, {"p": (y, white, sigma)}), _row("d2", True, {"p": (y, white, sigma)})])
    assert good["fits"] is True and len(good["reasons"]) == 1
    assert "describes these runs" in good["reasons"][0]
    # a slow model error of 20 % of the motion on top of the noise: ratio ≈ 14, lag-1 ρ ≈ 1
    slow = 0.2 * np.sin(0.5 * t + 1.0) + white
    bad = verdict([_row("d1", False, {"p": (y, slow, sigma)})])
    assert bad["fits"] is False
    assert bad["details"][0].startswith("d1 (fitted): residuals of p at")
    assert "the model does not describe these runs — check the base vehicle" in bad["details"][0]
    # what a user reads: the verdict, then one line for the run with its systematic share
    assert bad["reasons"][0].startswith("The model does not describe these runs: 1 of 1 run(s)")
    e = channel_checks(y, slow, sigma)
    assert bad["reasons"][1].startswith(f"d1 (fitted): systematic error of p {100 * e['systematic']:.0f} %")
    assert "check the base vehicle" in bad["reasons"][1]
    # the checks it relies on, from their definitions
    e = channel_checks(y, slow, sigma)
    rms = np.sqrt(np.mean(slow**2))
    assert e["noise_ratio"] == pytest.approx(rms / sigma) and e["noise_ratio"] > EXCESS
    assert e["systematic"] == pytest.approx(np.sqrt(rms**2 - sigma**2) / np.std(y)) and e["systematic"] > SYSTEMATIC
    assert whiteness(slow)["lag1"] > COLOURED


def test_a_channel_smoother_than_a_sensor_is_named_beside_its_ratio() -> None:
    # r logged pre-filtered: its smoother's noise is 2e-6 of its motion (std 0.71), a real gyro's is
    # 1e-3–1e-2. A 20 % model error then reads as ~7e4 × "the noise": the reason says the channel is
    # smoother than a sensor, with that share (σ / std from the definitions); u, at a sensor's noise,
    # is not named so
    t = np.arange(0.0, 20.0, 0.02)
    y = np.sin(0.5 * t)
    err = 0.2 * np.sin(0.5 * t + 1.0)
    tiny, real = 1.5e-6, 0.01
    res = verdict([_row("pond", False, {"r": (y, err, tiny), "u": (y, err, real)})])
    assert res["fits"] is False
    share = tiny / np.std(y)
    assert share < PREFILTERED
    assert f"r is smoother than a sensor (noise {share:.1g} of its motion" in res["details"][0]
    assert "u is" not in res["details"][0] and "r, u are" not in res["details"][0]
    assert "r smoother than a sensor" in res["reasons"][1]
    # at a sensor's noise the sentence is absent
    plain = verdict([_row("pond", False, {"r": (y, err, real)})])
    assert "smoother than a sensor" not in plain["details"][0] and "smoother" not in plain["reasons"][1]


def test_a_held_out_channel_that_is_not_predicted_fails_on_its_nrmse() -> None:
    rng = np.random.default_rng(1)
    t = np.arange(0.0, 20.0, 0.02)
    y = np.sin(0.5 * t)
    e = 0.8 * y + 0.01 * rng.standard_normal(t.size)  # the prediction misses 80 % of the motion
    res = verdict([_row("d3", True, {"phi": (y, e, 0.01)})])
    assert res["fits"] is False
    nrmse = np.sqrt(np.mean(e**2)) / np.std(y)  # the definition: RMS error over the channel's spread
    assert f"held-out NRMSE of φ {nrmse:.2f} > {NRMSE_LIMIT:g} and residuals lag-1 ρ 1.00" in res["details"][0]
    assert res["reasons"][1].startswith("d3 (held out): ") and f"held-out NRMSE φ {nrmse:.2f}" in res["reasons"][1]
    assert "understate" in res["reasons"][0]


def test_a_still_channel_is_not_judged_by_its_nrmse() -> None:
    # a channel that barely moves (std below 3 σ): its NRMSE is noise over noise, about 1
    rng = np.random.default_rng(2)
    y = 0.01 * rng.standard_normal(1000)
    e = 0.01 * rng.standard_normal(1000)
    row = _row("d3", True, {"theta": (y, e, 0.01)})
    assert row["channels"]["theta"]["nrmse"] > NRMSE_LIMIT and not row["channels"]["theta"]["moving"]
    assert verdict([row])["fits"] is True


@pytest.fixture(scope="module")
def dives() -> tuple[Any, list[Any]]:
    """Three 8 s dives (integrated at 10 ms) of a vehicle with hidden coefficients, and the fit's
    start: the truth with its free yaw coefficients 30 % off."""
    import hydrokit
    from hydrokit.sysid.data import generate_runs, hidden_vehicle
    from hydrokit.sysid.model import free_parameters, values_of, with_values

    truth = hidden_vehicle(hydrokit.load_vehicle("bluerov2-sysid"), 2)
    v, params = free_parameters(truth, FREE)
    start = with_values(v, params, values_of(v, params) * np.array([1.3, 0.7, 1.3]))
    return start, generate_runs(truth, 3, 8.0, seed=5, dt=0.01)


#: wrong base vehicles: what is changed and the channels it must spoil (measured on these
#: dives: residuals 3–11 × the sensor noise with lag-1 ρ 0.85–0.96 in them; < 1.7 × elsewhere)
WRONG = {
    "buoyancy": (lambda v: replace(v, volume=v.volume * 1.01), ("z",)),
    "centre of buoyancy": (lambda v: replace(v, r_b=v.r_b + np.array([0, 0, 0.01])), ("p", "q", "φ", "θ")),
    "centre of gravity": (lambda v: replace(v, r_g=v.r_g + np.array([0, 0, 0.01])), ("p", "q", "φ", "θ")),
    "roll and pitch inertia": (
        lambda v: replace(v, inertia=v.inertia * np.array([1.5, 1.5, 1.0])[:, None]),
        ("p", "q"),
    ),
}


@pytest.mark.needs_jit(reason="an output-error fit of three yaw coefficients over 2 × 8 s of dives")
def test_the_correct_base_vehicle_fits(dives: Any) -> None:
    from hydrokit.sysid.fit import identify

    start, runs = dives
    res = identify(start, runs[:1], FREE, holdout=runs[2:], samples=0, check_step=False)
    assert res.verdict["fits"] is True, res.verdict["reasons"]
    assert res.to_dict()["verdict"] == {"fits": True, "reasons": res.verdict["reasons"], "details": []}
    # the residuals are the sensor noise: within 2 × its σ in every channel of every run
    ratios = [d["noise_ratio"] for r in res.runs for d in r["channels"].values()]
    assert max(ratios) < EXCESS


@pytest.mark.needs_jit(reason="an output-error fit of three yaw coefficients over 2 × 8 s of dives")
@pytest.mark.parametrize("what", list(WRONG))
def test_a_wrong_base_vehicle_never_passes_silently(dives: Any, what: str) -> None:
    from hydrokit.sysid.fit import identify

    start, runs = dives
    change, spoiled = WRONG[what]
    res = identify(change(start), runs[:1], FREE, holdout=runs[2:], samples=0, check_step=False, max_iter=10)
    assert res.verdict["fits"] is False
    reasons = res.verdict["reasons"]
    assert any("the model does not describe these runs — check the base vehicle" in r for r in reasons)
    named = " ".join(r.split(":")[1] for r in reasons[1:])  # the evidence of each failing run
    assert any(f" {c} " in named or f" {c}," in named for c in spoiled), reasons


def test_one_line_per_run_with_advice_for_the_channel() -> None:
    """Windows of one run make one line (issue #56 item 6: 67–109 sentences, one per window, each
    pointing at the buoyancy of a floating ship whose worst channel was its speed): a speed channel
    points at the resistance, propeller curve, wake and thrust deduction; a yaw channel at the hull's
    manoeuvring terms and the rudder; neither at the base vehicle's buoyancy."""
    t = np.arange(0.0, 20.0, 0.02)
    y = np.sin(0.5 * t)
    sigma = 0.01
    err = 0.3 * np.sin(0.5 * t + 1.0)
    rows = [_row(f"pond_1@{a:g}s", False, {"u": (y, err, sigma), "r": (y, 0.5 * err, sigma)}) for a in (0, 20, 40)]
    rows += [_row(f"zigzag_2@{a:g}s", True, {"r": (y, err, sigma)}) for a in (0, 20.5)]
    res = verdict(rows)
    assert res["fits"] is False
    assert len(res["details"]) == 5  # every window, for sysid.json
    assert len(res["reasons"]) == 3  # the verdict and one line per run
    assert "2 of 2 run(s)" in res["reasons"][0]
    speed, turn = res["reasons"][1], res["reasons"][2]
    assert speed.startswith("pond_1 (fitted, 3 of 3 windows): systematic error of u ")
    assert "propeller curve" in speed and "thrust deduction" in speed and "buoyancy" not in speed
    assert turn.startswith("zigzag_2 (held out, 2 of 2 windows)") and "held-out NRMSE r " in turn
    assert "rudder" in turn and "buoyancy" not in turn
