"""Records as people record them (issue #16 items 2, 3): a hand heel before the release, a slow
drift, coloured noise and cubic damping in the truth; release detection, --detrend,
--amplitude-window, --start, equivalent damping B_e(a) and the damping curve."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.identify.damping import model_curve
from hydrokit.identify.preprocess import detect_release, trim_launch
from hydrokit.identify.rig_model import rig_constants, simulate_extended
from hydrokit.identify.types import Launch, Rig
from hydrokit.io.launch import launch_csv
from hydrokit.io.rig import parse_rig

FS = 50.0  # Hz
RIG_DOC = yaml.safe_load((Path(__file__).parent / "data" / "kvlcc2_roll_rig.yaml").read_text())
TRUTH = {"I_a": 19.0, "B1": 1.5, "B2": 12.0, "B3": 20.0}  # kg m², N m s/rad, N m s²/rad², N m s³/rad³
T_RELEASE = 6.013  # s, between samples
HEEL = math.radians(10.0)


def rig() -> Rig:
    return parse_rig(RIG_DOC, "kvlcc2-like.yaml")


def true_equivalent(a: float, truth: dict[str, float] = TRUTH) -> float:
    c = rig_constants(rig())
    w0 = math.sqrt(c.S / c.inertia(truth["I_a"]))
    return truth["B1"] + 8 / (3 * math.pi) * w0 * a * truth["B2"] + 0.75 * w0 * w0 * a * a * truth["B3"]


def free_decay(t: np.ndarray, q0: float, v0: float, truth: dict[str, float] = TRUTH) -> np.ndarray:
    c = rig_constants(rig())
    A, S = c.inertia(truth["I_a"]), c.S
    p = [S / A, truth["B1"] / A, truth["B2"] / A, truth["B3"] / A, 0.0, 0.0]
    q, _, _ = simulate_extended(t, p, q0, v0, c.restoring, 8)
    return q


def hand_heel_record(
    seed: int = 0,
    duration: float = 70.0,
    drift: float = 0.3,
    noise: float = 0.02,
    truth: dict[str, float] = TRUTH,
    heel: float = HEEL,
) -> Launch:
    """Rest 2 s, a hand heel ramped to ``heel`` (default 10°) over 1.5 s, held 2.5 s with a 0.1°
    wobble, released at T_RELEASE, free decay with the cubic damping of ``truth``; a drift of
    ``drift`` degrees per minute and AR(1) (coloured) noise of ``noise`` degrees std, all in
    radians."""
    t = np.arange(int(duration * FS)) / FS
    y = np.zeros(t.size)
    ramp = (t >= 2.0) & (t < 3.5)
    y[ramp] = heel * 0.5 * (1 - np.cos(math.pi * (t[ramp] - 2.0) / 1.5))
    wob = math.radians(0.1)
    f_w = 0.6  # Hz: a hand's slow wobble, moving inwards at the release
    hold = (t >= 3.5) & (t < T_RELEASE)
    y[hold] = heel + wob * np.sin(2 * math.pi * f_w * (T_RELEASE - t[hold]))
    free = t >= T_RELEASE
    tf = np.concatenate([[T_RELEASE], t[free]])
    v0 = -wob * 2 * math.pi * f_w
    y[free] = free_decay(tf - T_RELEASE, heel, v0, truth)[1:]
    rng = np.random.default_rng(seed)
    e = rng.normal(0.0, 1.0, t.size)
    ar = np.empty(t.size)
    ar[0] = e[0]
    for i in range(1, t.size):
        ar[i] = 0.9 * ar[i - 1] + math.sqrt(1 - 0.81) * e[i]
    y = y + math.radians(drift / 60.0) * t + math.radians(noise) * ar
    return Launch(t, y, f"heel{seed}.csv")


def test_release_found_after_hand_heel_within_one_sample() -> None:
    for seed in range(3):
        L = hand_heel_record(seed)
        tr = detect_release(L.t, L.y)
        assert abs(tr - T_RELEASE) <= 1.0 / FS, (seed, tr)
        trimmed = trim_launch(L, detrend="linear")
        assert abs(trimmed.info["release_time"] - T_RELEASE) <= 1.0 / FS
        assert trimmed.info["release"] == "detected"
        assert trimmed.info["detrend"]["method"] == "linear"
        # the drift (0.3°/min) is found
        assert math.degrees(trimmed.info["detrend"]["slope"]) * 60 == pytest.approx(0.3, abs=0.1)


@pytest.mark.needs_jit(reason="two 70 s cubic-model fits")
def test_equivalent_damping_within_two_percent_of_truth() -> None:
    from hydrokit.api import identify_campaign

    launches = [trim_launch(hand_heel_record(seed), detrend="linear") for seed in (0, 1)]
    a = math.radians(5.0)
    res = identify_campaign(rig(), launches, damping_model="cubic", equivalent_at=[a])
    doc = res.to_dict()
    truth = true_equivalent(a)
    for launch in doc["launches"]:
        (be,) = launch["equivalent_damping"]
        assert be["amplitude"] == pytest.approx(a)
        assert be["value"] == pytest.approx(truth, rel=0.02), (be, truth)
        assert 0 < be["std_error"] < 0.1 * be["value"]
        assert launch["release_time"] == pytest.approx(T_RELEASE, abs=1.0 / FS)
        # the model-free curve scatters about the true B_e(a) without bias (the noise moves each
        # half cycle's decrement; the scatter grows as the decrement shrinks with the amplitude)
        curve = launch["damping_curve"]
        assert len(curve) > 20
        amps = np.array([p["amplitude"] for p in curve])
        ratio = np.array([p["value"] for p in curve]) / np.array([true_equivalent(x) for x in amps])
        assert float(np.median(ratio)) == pytest.approx(1.0, abs=0.05)
        assert float(np.median(np.abs(ratio[amps > math.radians(6)] - 1))) < 0.12
    # the model curve helper is the closed form
    r = res.results[0]
    assert model_curve(a, r.linear_damping, r.quadratic_damping, r.extra["cubic_damping"], r.natural_frequency) == (
        pytest.approx(doc["launches"][0]["equivalent_damping"][0]["value"], rel=1e-9)
    )


def test_amplitude_window_cuts_where_stated() -> None:
    L = hand_heel_record(0, drift=0.0, noise=0.005)
    hi, lo = math.radians(8.0), math.radians(4.0)
    trimmed = trim_launch(L, amplitude_window=(hi, lo))
    w = trimmed.info["amplitude_window"]
    # the noise-free truth: extremes of the free decay
    t = np.arange(int(70 * FS * 4)) / (FS * 4)
    q = free_decay(t, HEEL, -math.radians(0.1) * 2 * math.pi * 0.6)
    k = np.nonzero((np.abs(q[1:-1]) >= np.abs(q[:-2])) & (np.abs(q[1:-1]) >= np.abs(q[2:])))[0] + 1
    ext_t, ext_a = t[k] + T_RELEASE, np.abs(q[k])
    start = ext_t[np.argmax(ext_a <= hi)]
    end = ext_t[np.argmax(ext_a < lo)]
    assert w["start_time"] == pytest.approx(start, abs=1.5 / FS)
    assert w["end_time"] == pytest.approx(end, abs=1.5 / FS)
    assert (w["high"], w["low"]) == (hi, lo)
    assert w["start_amplitude"] <= hi and w["end_amplitude"] < lo
    # cycles inside the window: the truth's half cycles from its first extreme ≤ HI to its
    # first extreme < LO, two to a cycle
    assert w["cycles"] == (np.argmax(ext_a < lo) - np.argmax(ext_a <= hi)) / 2
    assert w["cycles"] >= 2
    assert float(np.max(np.abs(trimmed.y))) <= hi + math.radians(0.05)
    assert any("amplitude window" in n for n in trimmed.notes)


@pytest.mark.parametrize("detrend", ["mean", "none"])
def test_amplitude_window_measures_amplitudes_about_the_rest_value(detrend: str) -> None:
    # the same launch resting at 2° instead of 0: amplitudes are measured from the rest value
    # whether or not it is taken off the returned record, so the window is cut at the same times
    from dataclasses import replace

    L = hand_heel_record(0, drift=0.0, noise=0.005)
    hi, lo = math.radians(8.0), math.radians(4.0)
    ref = trim_launch(L, amplitude_window=(hi, lo)).info["amplitude_window"]
    shifted = replace(L, y=np.asarray(L.y) + math.radians(2.0))
    got = trim_launch(shifted, amplitude_window=(hi, lo), detrend=detrend).info["amplitude_window"]
    assert got["start_time"] == pytest.approx(ref["start_time"], abs=1.5 / FS)
    assert got["end_time"] == pytest.approx(ref["end_time"], abs=1.5 / FS)


def test_no_free_decay_is_rejected() -> None:
    t = np.arange(3000) / FS
    rng = np.random.default_rng(0)
    still = Launch(t, rng.normal(0, 1e-4, t.size), "still.csv")
    with pytest.raises(InputError, match="free decay"):
        trim_launch(still)
    # a hand rocking the body steadily: forced throughout
    forced = Launch(t, 0.1 * np.sin(2 * math.pi * 0.4 * t) + rng.normal(0, 1e-4, t.size), "forced.csv")
    with pytest.raises(InputError, match="no free decay"):
        trim_launch(forced)
    with pytest.raises(InputError, match="amplitude window .*only .* cycles"):
        trim_launch(hand_heel_record(0), amplitude_window=(math.radians(10), math.radians(9)))


# -- the command line -------------------------------------------------------------------------


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    rig_path = tmp_path / "rig.yaml"
    rig_path.write_text(yaml.safe_dump(RIG_DOC))
    L = hand_heel_record(0)
    csv = tmp_path / "heel.csv"
    csv.write_text(launch_csv(L.t, np.degrees(L.y), "angle_deg"))
    return rig_path, csv


@pytest.mark.needs_jit(reason="70 s cubic-model fits through the CLI")
def test_cli_window_equivalent_and_plots(run_cli, files, tmp_path) -> None:
    rig_path, csv = files
    out = tmp_path / "out.json"
    code, _, err = run_cli(
        "identify", rig_path, csv, "--json", out, "--damping-model", "cubic", "--detrend", "linear",
        "--amplitude-window", "20deg,3.5deg", "--equivalent-at", "5deg,0.1", "--plots", tmp_path / "plots",
    )  # fmt: skip
    assert code == 0, err
    (launch,) = json.loads(out.read_text())["launches"]
    assert launch["release_time"] == pytest.approx(T_RELEASE, abs=1.0 / FS)
    assert launch["amplitude_window"]["high"] == pytest.approx(math.radians(20))
    assert launch["detrend"]["method"] == "linear"
    assert [e["amplitude"] for e in launch["equivalent_damping"]] == [pytest.approx(math.radians(5)), 0.1]
    assert launch["equivalent_damping"][0]["value"] == pytest.approx(true_equivalent(math.radians(5)), rel=0.02)
    assert (tmp_path / "plots" / "heel_damping.png").stat().st_size > 1000


@pytest.mark.needs_jit(reason="70 s cubic-model fits through the CLI")
def test_cli_start_overrides_the_detector(run_cli, files, tmp_path) -> None:
    rig_path, csv = files
    out = tmp_path / "start.json"
    code, _, err = run_cli("identify", rig_path, csv, "--json", out, "--start", "5.0")
    assert code == 0, err
    (launch,) = json.loads(out.read_text())["launches"]
    assert launch["release_time"] == 5.0
    assert any("release given at t = 5.000" in n for n in launch["notes"])


@pytest.mark.parametrize(
    ("kind", "expected"),
    [("still", "free decay"), ("forced", "no free decay"), ("window", "amplitude window")],
)
def test_cli_bad_records_one_line_exit_2(run_cli, files, tmp_path, kind, expected) -> None:
    rig_path, csv = files
    args: list[object] = []
    if kind == "window":
        args = ["--amplitude-window", "10deg,9deg"]
    else:
        t = np.arange(3000) / FS
        y = np.zeros(t.size) if kind == "still" else 5.0 * np.sin(2 * math.pi * 0.4 * t)
        y = y + np.random.default_rng(1).normal(0, 0.005, t.size)
        csv = tmp_path / f"{kind}.csv"
        csv.write_text(launch_csv(t, y, "angle_deg"))
    out = tmp_path / "bad.json"
    code, _, err = run_cli("identify", rig_path, csv, "--json", out, *args)
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert code == 2 and len(lines) == 1 and expected in lines[0], err
    assert "Traceback" not in err and not out.exists()


def test_cli_equivalent_at_rejects_degrees_for_positions(run_cli, tmp_path) -> None:
    doc = dict(RIG_DOC, axis="heave", floating={"waterplane_area": 1.0})
    p = tmp_path / "heave.yaml"
    p.write_text(yaml.safe_dump(doc))
    csv = tmp_path / "h.csv"
    t = np.arange(500) / FS
    csv.write_text(launch_csv(t, 0.01 * np.cos(2 * t) * np.exp(-0.05 * t), "position"))
    code, _, err = run_cli("identify", p, csv, "--json", tmp_path / "h.json", "--equivalent-at", "5deg")
    assert code == 2
    assert err.splitlines() == [
        "error: --equivalent-at '5deg': degrees given for a translational signal; expected metres"
    ]
    assert not (tmp_path / "h.json").exists()


def test_release_thrown_toward_rest_is_put_at_the_search_window_end() -> None:
    # a hand holds the body at 5 cm, then pushes it toward rest with a constant acceleration for
    # 1.4 s and lets go at t_r = 3.4 s, so fast that the free motion (closed-form linear decay,
    # T = 2 s) crosses zero only 0.1 T later. The search window for the release ends 0.15 T
    # before that crossing, so the detector answers its last candidate: just before t_r − 0.05 T,
    # before the true release, the refinement between candidates skipped (there is no later one)
    rate, period, sigma, hold, push, frac = 100.0, 2.0, 0.05, 0.05, 1.4, 0.1
    wd = 2 * math.pi / period
    phi = math.pi / 2 - wd * frac * period  # the free motion crosses zero frac·T after the release
    k = -(sigma * math.cos(phi) + wd * math.sin(phi)) / math.cos(phi)  # rate / position at the release
    y_r = hold / (1 - 0.5 * k * push)  # the push's end position = the free motion's start (C¹ join)
    acc = -k * y_r / push
    s = np.arange(0.0, push, 1 / rate)
    sf = np.arange(0.0, 14.0, 1 / rate)
    y = np.concatenate(
        [
            np.full(200, hold),
            hold - 0.5 * acc * s**2,
            y_r / math.cos(phi) * np.exp(-sigma * sf) * np.cos(wd * sf + phi),
        ]
    )
    y += np.random.default_rng(1).normal(0.0, 2e-5, y.size)
    t = np.arange(y.size) / rate
    t_release = 2.0 + push
    crossing = t_release + frac * period
    tr = detect_release(t, y)
    assert crossing - 0.15 * period - 2.0 / rate <= tr < crossing - 0.15 * period


def test_damping_curve_skips_extremes_at_one_instant(monkeypatch: pytest.MonkeyPatch) -> None:
    # two refined extremes at the same time (a repeated time stamp) give no half cycle to
    # divide by: that pair is skipped, the next one kept (time = the middle of its half cycle)
    from types import SimpleNamespace

    import hydrokit.identify.estimators as estimators
    from hydrokit.identify.damping import damping_curve

    monkeypatch.setattr(estimators, "_peaks", lambda t, z, band: [(1.0, 0.5), (1.0, -0.4), (2.0, 0.3)])
    est = SimpleNamespace(offset_=0.0, noise_=0.0, constants_=rig_constants(rig()))
    t = np.linspace(0.0, 3.0, 31)
    rows = damping_curve(t, np.cos(t), est, rig())
    assert [r["time"] for r in rows] == [1.5]
    assert rows[0]["value"] > 0


@pytest.mark.parametrize(("noise", "band"), [(0.01, 0.04), (1e-4, 0.01)])
def test_damping_curve_counts_extremes_beyond_four_sigma_or_one_percent(monkeypatch, noise, band) -> None:
    # docs/identify.md, "Equivalent damping and the damping curve": the band is 4 σ of the
    # noise floor or 1 % of the largest excursion (here 1), whichever is larger
    from types import SimpleNamespace

    import hydrokit.identify.estimators as estimators
    from hydrokit.identify.damping import damping_curve

    seen = []
    monkeypatch.setattr(estimators, "_peaks", lambda t, z, b: seen.append(b) or [])
    est = SimpleNamespace(offset_=0.0, noise_=noise, constants_=rig_constants(rig()))
    t = np.linspace(0.0, 3.0, 31)
    assert damping_curve(t, np.cos(2 * t), est, rig()) == []
    assert seen == [pytest.approx(band, rel=1e-12)]


@pytest.mark.parametrize("lead", [0.35, 0.4, 0.45, 0.5, 0.52, 0.55, 0.6])
def test_record_starting_in_outward_free_motion_releases_at_the_extreme(lead: float) -> None:
    # a free decay (T = 2 s) recorded from `lead` periods before its first zero crossing: the
    # body still swings outwards at the start, so the free decay the model can use starts at
    # the extreme (t = 0), whichever candidate join time fits best (here the window's first).
    # From 0.52 on the record starts before the previous crossing, the window's first 5 % of a
    # period is the join candidates' margin: a join there (almost no "hand" before it) would fit
    # best and land on the record's start instead of the extreme
    period, sigma = 2.0, 0.05
    wd = 2 * math.pi / period
    t0 = period / 4 - lead * period
    t = np.arange(t0, 14.0, 0.01)
    y = 0.05 * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    y += np.random.default_rng(1).normal(0.0, 2e-5, t.size)
    assert detect_release(t - t0, y) + t0 == pytest.approx(0.0, abs=1e-3)


def test_damping_curve_takes_the_rest_value_from_three_extremes(monkeypatch: pytest.MonkeyPatch) -> None:
    # three extremes of a geometric decay about c = 0.01: c + 1, c − 0.8, c + 0.64. The rest
    # value (p1 p3 − p2²)/(p1 + p3 − 2 p2) = c exactly, so the half-cycle amplitudes are the
    # means of 1, 0.8 and 0.8, 0.64
    from types import SimpleNamespace

    import hydrokit.identify.estimators as estimators
    from hydrokit.identify.damping import damping_curve

    est = SimpleNamespace(offset_=0.0, noise_=0.0, constants_=rig_constants(rig()))
    rows = {}
    for c in (0.0, 0.01):
        peaks = [(1.0, c + 1.0), (2.0, c - 0.8), (3.0, c + 0.64)]
        monkeypatch.setattr(estimators, "_peaks", lambda t, z, band, peaks=peaks: peaks)
        rows[c] = damping_curve(np.linspace(0.0, 4.0, 41), np.zeros(41), est, rig())
    assert [r["amplitude"] for r in rows[0.01]] == pytest.approx([0.9, 0.72], rel=1e-12)
    # the energy lost per half cycle depends on each extreme, not only their mean: the same
    # values as about zero (unshifted, 1.01 and 0.79 would lose more energy than 1 and 0.8)
    assert [r["value"] for r in rows[0.01]] == pytest.approx([r["value"] for r in rows[0.0]], rel=1e-9)


def test_damping_curve_of_a_spring_uses_the_spring_energy(monkeypatch: pytest.MonkeyPatch, spring_rig) -> None:
    # a linear spring k: the energy lost between extremes 1 and −0.8 m one second apart is
    # ΔE = k (1² − 0.8²)/2, and B_e = 2 ΔE / (π ω a²) with ω = π/1 s and a = 0.9 m (energy balance
    # of a linear damper over half a cycle: ΔE = π B ω a² / 2)
    from types import SimpleNamespace

    import hydrokit.identify.estimators as estimators
    from hydrokit.identify.damping import damping_curve
    from hydrokit.identify.rig_model import rig_constants

    monkeypatch.setattr(estimators, "_peaks", lambda t, z, band: [(0.0, 1.0), (1.0, -0.8)])
    est = SimpleNamespace(offset_=0.0, noise_=0.0, constants_=rig_constants(spring_rig))
    (row,) = damping_curve(np.linspace(0.0, 2.0, 21), np.zeros(21), est, spring_rig)
    k = 63.6  # N/m, the fixture's spring
    assert row["amplitude"] == pytest.approx(0.9, rel=1e-12)
    assert row["value"] == pytest.approx(2.0 * (k * (1.0 - 0.64) / 2.0) / (math.pi * math.pi * 0.81), rel=1e-12)


def test_equivalent_damping_error_is_the_delta_method_by_finite_differences() -> None:
    # B_e(a) = (S/ω²)(b + (8/3π) ω a g + ¾ ω² a² d) with every parameter of (ω², b, g, d) set:
    # with unit variances one at a time, the standard error is |∂B_e/∂p|, here by central differences
    from types import SimpleNamespace

    from hydrokit.identify.damping import equivalent_damping

    c = rig_constants(rig())
    p = np.array([0.4, 0.03, 0.8, 2.5])  # ω² 1/s², b 1/s, g, d (normalised)
    a = 0.15

    def value(q: np.ndarray) -> float:
        w = math.sqrt(q[0])
        return c.S / q[0] * (q[1] + 8 / (3 * math.pi) * w * a * q[2] + 0.75 * q[0] * a * a * q[3])

    for k in range(4):
        cov = np.zeros((4, 4))
        cov[k, k] = 1.0
        est = SimpleNamespace(constants_=c, p_=tuple(p[:3]), ext_=np.r_[p, 0.0, 0.0], pcov4_=cov, pcov4_formal_=None)
        (row,) = equivalent_damping(est, rig(), [a])
        h = np.zeros(4)
        h[k] = 1e-6 * p[k]
        assert row["value"] == pytest.approx(value(p), rel=1e-12)
        assert row["std_error"] == pytest.approx(abs(value(p + h) - value(p - h)) / (2 * h[k]), rel=1e-6), k


def test_equivalent_damping_is_net_of_the_rig_tare() -> None:
    # B_e of the body = B_e of the fitted record − (tare K_L + (8/3π) ω a tare K_Q)
    import dataclasses
    from types import SimpleNamespace

    from hydrokit.identify.damping import equivalent_damping

    c = rig_constants(rig())
    p = (0.4, 0.03, 0.8)
    est = SimpleNamespace(constants_=c, p_=p, pcov4_=None, pcov4_formal_=None)
    a = 0.15
    (bare,) = equivalent_damping(est, rig(), [a])
    tared = dataclasses.replace(rig(), tare_linear_damping=0.5, tare_quadratic_damping=0.2)
    (net,) = equivalent_damping(est, tared, [a])
    w = math.sqrt(p[0])
    assert net["value"] == pytest.approx(bare["value"] - 0.5 - 8 / (3 * math.pi) * w * a * 0.2, rel=1e-12)


def test_the_damping_curve_is_net_of_the_rig_tare() -> None:
    # each half cycle's model-free B_e drops by tare K_L + (8/3π) ω a tare K_Q, with ω = π/(t2 − t1)
    # = ω_d for a linear decay (its extremes are exactly half a damped period apart)
    import dataclasses
    from types import SimpleNamespace

    from hydrokit.identify.damping import damping_curve

    wn, zeta = 2.0, 0.02
    wd = wn * math.sqrt(1 - zeta**2)
    t = np.arange(6000) * 0.005
    y = 0.2 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))
    est = SimpleNamespace(offset_=0.0, noise_=0.0, constants_=rig_constants(rig()))
    bare = damping_curve(t, y, est, rig())
    tared = dataclasses.replace(rig(), tare_linear_damping=0.5, tare_quadratic_damping=0.2)
    net = damping_curve(t, y, est, tared)
    assert len(bare) == len(net) >= 10
    for b, n in zip(bare, net):
        drop = 0.5 + 8 / (3 * math.pi) * wd * b["amplitude"] * 0.2
        assert b["value"] - n["value"] == pytest.approx(drop, rel=1e-4)


@pytest.mark.parametrize(("noise", "found"), [(0.1296 / 4.5, True), (0.1296 / 3.5, False)])
def test_release_needs_two_cycles_beyond_four_sigma(noise: float, found: bool) -> None:
    # a decay losing 40 % a half cycle: extremes 1, 0.6, 0.36, 0.216, 0.13, 0.078 (rest 0). Its
    # fifth excursion, 0.13, lies 4.5 σ out at the first noise level: five excursions past 4 σ
    # close four half cycles, two cycles, and the record is a decay from its start. At 3.5 σ
    # only four excursions leave the band (three closed half cycles): refused, in words
    t = np.arange(0.0, 8.0, 1 / 200.0)
    y = np.exp(-2 * math.log(1 / 0.6) * t) * np.cos(2 * math.pi * t)
    if found:
        assert detect_release(t, y, sigma=noise) == 0.0
    else:
        with pytest.raises(InputError, match=r"only 1\.5 cycles \(half cycles with an extreme: 3\)"):
            detect_release(t, y, sigma=noise)
