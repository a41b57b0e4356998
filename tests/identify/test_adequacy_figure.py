"""The model-adequacy figure (issue #16): residual autocorrelation against lag in periods with the
white-noise band, residual against time with the noise floor; in ``--plots`` and in the report
next to the escaped verdict."""

from __future__ import annotations

import base64
import html
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from hydrokit.identify.rig_model import rig_constants, simulate_extended
from hydrokit.identify.types import Launch
from hydrokit.io.launch import launch_csv
from hydrokit.io.rig import parse_rig
from hydrokit.plot.adequacy import adequacy_figure, launch_adequacy, period_lag, residual_acf

FS = 50.0  # Hz
RIG_DOC = yaml.safe_load((Path(__file__).parent / "data" / "kvlcc2_roll_rig.yaml").read_text())


def cubic_decay(seed: int = 0, b3: float = 60.0, noise_deg: float = 0.01) -> Launch:
    """A 12° roll release, 60 s at 50 Hz, B1 = 1.5, B2 = 12, B3 = ``b3`` (N·m·s/rad, N·m·s²/rad²,
    N·m·s³/rad³), I_a = 19 kg·m², white noise of ``noise_deg`` degrees. Fitted with the quadratic
    model the cubic term leaves an error that repeats every cycle."""
    c = rig_constants(parse_rig(RIG_DOC, "roll.yaml"))
    A = c.inertia(19.0)
    t = np.arange(int(60 * FS)) / FS
    q, _, _ = simulate_extended(t, [c.S / A, 1.5 / A, 12.0 / A, b3 / A, 0.0, 0.0], math.radians(12.0), 0.0, None, 8)
    rng = np.random.default_rng(seed)
    return Launch(t, q + rng.normal(0.0, math.radians(noise_deg), t.size), "cubic<&>.csv")


def _acf_marker(fig) -> float:  # noqa: ANN001
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == "one period"]
    return float(line.get_ydata()[0])


def test_residual_acf_of_a_sine_is_the_overlap_fraction() -> None:
    # closed form: for r = sin(2π k/P) over whole periods, ρ(P) = Σ_{k<n−P} r_k² / Σ r_k² = (n − P)/n
    P, n = 40, 400
    r = np.sin(2 * np.pi * np.arange(n) / P)
    acf = residual_acf(r, 2 * P)
    assert acf[0] == pytest.approx(1.0)
    assert acf[P] == pytest.approx((n - P) / n, rel=1e-9)  # FFT round-off only
    assert acf[P // 2] == pytest.approx(-(n - P // 2) / n, rel=1e-9)


def test_figure_acf_at_one_period_equals_the_json_number(tmp_path: Path) -> None:
    """Second path to the same number: the figure's FFT autocorrelation at the one-period lag
    against ``adequacy.acf_at_period`` in the written JSON (a direct dot product)."""
    from hydrokit.identify.result import identify_launches
    from hydrokit.io.results import dumps

    res = identify_launches(parse_rig(RIG_DOC, "roll.yaml"), [cubic_decay()])
    out = tmp_path / "r.json"
    out.write_text(dumps(res.to_dict()))
    adequacy = json.loads(out.read_text())["launches"][0]["extra"]["adequacy"]
    assert adequacy["verdict"].startswith("model error")  # the cubic term the model lacks repeats
    fig = launch_adequacy(res.launches[0], "rad", "cubic")
    # rel 1e-9: the two sums differ by floating-point round-off only
    assert _acf_marker(fig) == pytest.approx(adequacy["acf_at_period"], rel=1e-9)
    assert adequacy["acf_at_period"] > 0.3
    # the marker sits at one period on the lag axis (whole samples: within half a sample)
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == "one period"]
    assert line.get_xdata()[0] == pytest.approx(1.0, abs=0.5 / (FS * res.results[0].extra["period"]))


def test_white_noise_residual_stays_inside_the_band() -> None:
    rng = np.random.default_rng(7)
    n, period = 3000, 2.5  # samples, s
    t = np.arange(n) / FS
    r = rng.normal(0.0, 1e-3, n)
    fig = adequacy_figure(t, r, period, noise=1e-3, unit="rad")
    (acf_line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == "residual autocorrelation ρ"]
    acf = np.asarray(acf_line.get_ydata())[1:]
    band = 1.96 / math.sqrt(n)
    # white noise: 95 % of lags inside ±1.96/√N; 375 lags, so ≥ 90 % inside fails with p < 1e-4
    assert np.mean(np.abs(acf) <= band) >= 0.90
    assert abs(_acf_marker(fig)) < band
    # and a residual that repeats every period is far outside it
    periodic = np.sin(2 * np.pi * t / period) * 3e-3 + r  # ρ(P) ≈ 4.5/5.5 · (n − P)/n
    assert _acf_marker(adequacy_figure(t, periodic, period, noise=1e-3)) > 10 * band


def test_period_lag_is_whole_samples() -> None:
    t = np.arange(500) / FS
    assert period_lag(t, 2.5) == 125
    assert period_lag(t, float("nan")) == 0


def test_figure_rejects_mismatched_arrays() -> None:
    with pytest.raises(ValueError, match="equal length"):
        adequacy_figure(np.arange(10.0), np.zeros(9), 1.0, 0.1)


def test_plots_and_report_carry_the_figure_next_to_the_escaped_verdict(run_cli, tmp_path: Path) -> None:
    rig_path = tmp_path / "roll.yaml"
    rig_path.write_text(yaml.safe_dump(RIG_DOC))
    L = cubic_decay()
    csv = tmp_path / "a<b>&c.csv"  # a file name that must be escaped in HTML
    csv.write_text(launch_csv(L.t, np.degrees(L.y), "angle_deg"))
    report = tmp_path / "r.html"
    code, _, err = run_cli(
        "identify", rig_path, csv, "--json", tmp_path / "r.json", "--plots", tmp_path / "plots", "--report", report
    )
    assert code == 0, err
    png = tmp_path / "plots" / "a<b>&c_adequacy.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    verdict = json.loads((tmp_path / "r.json").read_text())["launches"][0]["extra"]["adequacy"]["verdict"]
    text = report.read_text()
    assert "a<b>&c" not in text and "a&lt;b&gt;&amp;c" in text
    blocks = re.findall(r'<div class="adequacy">(.*?)</div>', text, flags=re.S)
    assert len(blocks) == 1
    # the verdict (escaped) and the figure in the same block: the picture beside its words
    assert html.escape(verdict, quote=True) in blocks[0]
    data = re.search(r'<img[^>]*src="data:image/png;base64,([^"]+)"', blocks[0])
    assert data is not None and base64.b64decode(data.group(1)) == png.read_bytes()


def test_report_escapes_a_hostile_verdict() -> None:
    from hydrokit.report.identify import Run, run_section

    rig = parse_rig(RIG_DOC, "roll.yaml")
    launch = {
        "file": "x.csv",
        "amplitude": 0.1,
        "extra": {"adequacy": {"residual_to_noise": 1.0, "acf_at_period": 0.0, "verdict": "<script>x</script>"}},
    }
    for key in ("added_mass", "linear_damping", "quadratic_damping", "drag_coefficient", "reynolds_max", "kc"):
        launch[key] = 1.0
    launch["rms_residual"] = 0.0
    summary = {k: {"mean": None, "n": 1, "rejected": []} for k in ("added_mass", "added_mass_coefficient")}
    summary.update(
        {k: {"mean": None, "rejected": []} for k in ("linear_damping", "quadratic_damping", "drag_coefficient")}
    )
    summary.update({k: {"mean": None, "rejected": []} for k in ("natural_frequency", "damping_ratio")})
    summary["outlier_rule"] = ""
    doc = {"summary": summary, "launches": [{**launch, "warnings": []}]}
    fig = (b"\x89PNG fake", "caption")
    out = run_section(Run("t", rig, {"output-error": doc}, [], {"x_adequacy.png": fig}))
    assert "<script>" not in out and "&lt;script&gt;x&lt;/script&gt;" in out
    assert '<div class="adequacy">' in out


def test_report_selection_keeps_the_flagged_launch() -> None:
    """Without --plots at most four figures, the launches not found adequate among them."""
    from types import SimpleNamespace

    from hydrokit.identify.result import IdentifiedLaunch
    from hydrokit.plot.adequacy import adequacy_figures

    rng = np.random.default_rng(3)
    t = np.arange(500) / FS
    items = []
    for k in range(7):
        verdict = "model error: …" if k == 5 else "adequate: …"
        extra = {"period": 2.5, "noise": 1e-3, "adequacy": {"verdict": verdict}}
        result = SimpleNamespace(file=f"run{k}.csv", extra=extra)
        launch = Launch(t, rng.normal(0.0, 1e-3, t.size), f"run{k}.csv")
        items.append(IdentifiedLaunch(launch, result, None, prediction=np.zeros(t.size)))  # type: ignore[arg-type]
    campaign = SimpleNamespace(rig=parse_rig(RIG_DOC, "roll.yaml"), method="output-error", launches=items)
    few = adequacy_figures(campaign, per_launch=False)
    assert len(few) == 4 and "run5_adequacy.png" in few
    assert list(few) == sorted(few)  # launch order
    assert len(adequacy_figures(campaign)) == 7


def test_verdict_tells_drift_from_error_that_repeats_every_cycle() -> None:
    """A residual that changes sign with the oscillation (model error, ρ(T/2) ≈ −ρ(T)) and a slow
    ramp (a drifting rest value, ρ high at every lag) both have ρ(T) ≥ 0.3; only the first is
    called model error."""
    from hydrokit.identify.estimators import adequacy

    t = np.arange(0, 60.0, 0.02)
    period = 2.5
    rng = np.random.default_rng(3)
    noise = 0.01
    cyclic = 0.2 * np.sin(2 * np.pi * t / period) * np.exp(-t / 40) + rng.normal(0, noise, t.size)
    ramp = 0.004 * t + rng.normal(0, noise, t.size)
    a_cyc = adequacy(cyclic, t, period, noise)
    a_ramp = adequacy(ramp, t, period, noise)
    assert a_cyc["acf_at_period"] > 0.3 and a_ramp["acf_at_period"] > 0.3
    assert a_cyc["acf_at_half_period"] < -0.5  # a sine half a period on: the sign flips
    assert a_ramp["acf_at_half_period"] > a_ramp["acf_at_period"]
    assert a_cyc["verdict"].startswith("model error")
    assert a_ramp["verdict"].startswith("drift")
    # no noise floor measured: still words, no crash
    assert adequacy(ramp, t, period, 0.0)["verdict"].startswith("drift")
