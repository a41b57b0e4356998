"""The virtual rig's unmodelled effects (sensor lag, random encoder zero, hand release) and the
bundled campaigns being honest data (independent launches)."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

from hydrokit.data import campaign_files, campaign_rigs
from hydrokit.errors import InputError
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch
from hydrokit.io.rig import load_rig


def test_lag_is_the_exact_first_order_filter_on_a_ramp() -> None:
    # ramp y = s t sampled at Δt: the discrete filter's steady error is s Δt (1 − a)/a, a = 1 − e^(−Δt/τ)
    tau, rate, s = 0.01, 1000.0, 2.0
    sensor = SensorModel(rate, 0.0, 0.0, 0.0, "lagged", lag=tau)
    t = np.arange(2000) / rate
    out = sensor.measure(s * t, np.random.default_rng(0))
    a = 1.0 - math.exp(-1.0 / (rate * tau))
    assert s * t[-1] - out[-1] == pytest.approx(s * (1.0 / rate) * (1 - a) / a, rel=1e-9)
    # and without lag the sensor is transparent
    assert np.array_equal(SensorModel(rate, 0.0, 0.0, 0.0).measure(s * t, np.random.default_rng(0)), s * t)


def test_lag_filters_every_sample_after_the_first() -> None:
    # a unit step at sample 1, filter started at rest on sample 0: y_f[k] = 1 − (1 − a)^k for
    # k ≥ 1 (closed form of the recursion), so the first filtered sample is a, not the step
    tau, rate = 0.05, 100.0
    y = np.ones(50)
    y[0] = 0.0
    out = SensorModel(rate, 0.0, 0.0, 0.0, "lagged", lag=tau).measure(y, np.random.default_rng(0))
    a = 1.0 - math.exp(-1.0 / (rate * tau))
    k = np.arange(50)
    np.testing.assert_allclose(out, np.where(k == 0, 0.0, 1.0 - (1.0 - a) ** k), rtol=1e-12, atol=1e-15)


def test_random_zero_shifts_the_grid_per_launch() -> None:
    step = 1e-3 / 2.45
    sensor = SensorModel(100.0, 0.0, step, 0.0, "enc", random_zero=True)
    y = np.linspace(-0.02, 0.02, 401)
    rng = np.random.default_rng(3)
    a, b = sensor.measure(y, rng), sensor.measure(y, rng)
    assert np.max(np.abs(a - y)) <= step / 2 + 1e-15  # still a quantiser of that step
    assert not np.array_equal(a, b)  # two launches: two grids
    offsets = {round(float(np.mean(a - np.round(a / step) * step) / step), 6)}
    assert len(offsets) == 1  # every sample of one launch on one shifted grid


def test_hand_release_scatters_the_amplitude() -> None:
    rig_file, _ = campaign_files("udrobot", "spring_x")
    rig = load_rig(rig_file)
    rng = np.random.default_rng(7)
    starts = [
        simulate_launch(rig, 0.2866, 2.68, 5.6, 0.02, 1.0, SensorModel(100, 0, 0, 0.1), rng, amplitude_jitter=0.03).y[0]
        for _ in range(400)
    ]
    rel = np.asarray(starts) / 0.02 - 1.0
    assert abs(np.mean(rel)) < 0.006 and np.std(rel) == pytest.approx(0.03, rel=0.15)
    with pytest.raises(InputError, match="amplitude_jitter"):
        simulate_launch(rig, 0.2866, 2.68, 5.6, 0.02, 1.0, amplitude_jitter=-0.1)
    with pytest.raises(InputError, match="sensor lag"):
        SensorModel(100.0, 0.0, 0.0, 0.5, "bad", lag=-1.0)


@pytest.mark.parametrize("campaign", ["udrobot", "rov2"])
def test_bundled_launches_are_independent(campaign: str) -> None:
    """No two launch files of a bundled campaign hold the same record (repeated records made
    every rank-sum test between amplitude groups degenerate)."""
    for rig in campaign_rigs(campaign):
        _, files = campaign_files(campaign, rig)
        bodies = [
            hashlib.sha256(
                b"".join(ln for ln in f.read_bytes().splitlines(True) if not ln.startswith(b"#"))
            ).hexdigest()
            for f in files
        ]
        assert len(set(bodies)) == len(bodies), f"{campaign}/{rig}: repeated launch records"


def test_bundled_readme_says_virtual() -> None:
    rig_file, _ = campaign_files("udrobot", "spring_x")
    assert "**These launches are virtual**" in (rig_file.parent / "README.md").read_text(encoding="utf-8")
