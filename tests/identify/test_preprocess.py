from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.identify.preprocess import check_record, trim_launch
from hydrokit.identify.types import Launch
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch


def test_release_and_end_are_detected(pendulum_rig):
    # K_L = 0.1 N s/m: decays as e^{-t/4}, into the 0.05° noise after about 25 s
    launch = simulate_launch(
        pendulum_rig, 0.05, 0.1, 0.3, math.radians(10), 40.0, SensorModel.imu(hold_time=1.0), rng=0
    )
    trimmed = trim_launch(launch)
    # the still hold lasts 1.0 s (100 samples); the release is found within 3 samples
    dropped = launch.t.size - trimmed.t.size
    assert any("release detected" in n for n in trimmed.notes)
    start = next(n for n in trimmed.notes if "release" in n)
    t_rel = float(start.split("t = ")[1].split(" s")[0])
    assert abs(t_rel - 1.0) <= 0.03
    assert trimmed.t[0] == 0.0
    assert dropped > 100  # the noisy tail was cut too
    assert any("end detected" in n for n in trimmed.notes)


def test_override_release_and_end(pendulum_rig):
    launch = simulate_launch(pendulum_rig, 0.05, 0.02, 0.3, 0.2, 10.0, SensorModel.imu(hold_time=0.5), rng=0)
    tr = trim_launch(launch, release=0.5, end=8.0)
    assert tr.t[-1] == pytest.approx(7.5, abs=0.011)
    with pytest.raises(InputError, match="release = 99"):
        trim_launch(launch, release=99.0)


def test_records_that_cannot_be_fitted():
    t = np.linspace(0, 10, 500)
    with pytest.raises(InputError, match="does not oscillate"):
        check_record(Launch(t, np.exp(-t), file="mono.csv"))
    # crossings of cos(2π f t) on 0–10 s at t = (k + ½)/(2f): 3 at f = 0.15 Hz, 2 at 0.1 Hz, 1 at 0.05 Hz
    for f, why in (
        (0.15, "only 1.5 cycles; expected at least two cycles of free decay"),
        (0.1, "only 1 cycles; expected at least two cycles of free decay"),
        (0.05, "the record does not oscillate (1 crossing(s) of the rest value"),
    ):
        with pytest.raises(InputError) as err:
            check_record(Launch(t, np.cos(2 * np.pi * f * t) * np.exp(-0.05 * t), file="short.csv"))
        assert str(err.value).startswith(f"short.csv: {why}")
    with pytest.raises(InputError, match="grows"):
        check_record(Launch(t, np.exp(0.3 * t) * np.cos(2 * np.pi * t), file="grow.csv"))


def test_trim_launch_names_a_bad_sample_before_using_the_record(pendulum_rig):
    launch = simulate_launch(pendulum_rig, 0.05, 0.03, 0.1, 0.1, 8.0, SensorModel(100, 0, 0, 0), rng=0)
    t, y = np.asarray(launch.t, float), np.asarray(launch.y, float)
    n = t.size
    bad = y.copy()
    bad[40] = np.nan
    with pytest.raises(InputError) as err:
        trim_launch(Launch(t, bad, "nan.csv"))
    assert str(err.value) == (
        f"nan.csv: column 'y' (m or rad) holds nan at sample 40 (of {n} samples; 1 bad): expected finite numbers"
    )
    dup = t.copy()
    dup[300] = dup[299]  # a repeated stamp inside the decay
    with pytest.raises(InputError) as err:
        trim_launch(Launch(dup, y, "dup.csv"))
    assert str(err.value) == (
        f"dup.csv: column 't' (s) goes from {dup[299]:g} to {dup[299]:g} at sample 300: "
        "expected strictly increasing values"
    )
    with pytest.raises(InputError, match=r"^short.csv: time and signal must be 1-D of equal length, got \(\d+,\) and"):
        trim_launch(Launch(t, y[:-1], "short.csv"))


def test_trim_end_is_found_about_a_rest_value_far_from_zero(pendulum_rig):
    # a sensor whose zero is 0.3 away from the rest position: the quiet tail is measured against
    # the rest value, so it is dropped just as for a rest at zero
    launch = simulate_launch(pendulum_rig, 0.05, 0.15, 0.0, 0.1, 40.0, SensorModel(100, 1e-5, 0, 0), rng=0)
    at_zero = trim_launch(launch)
    shifted = trim_launch(Launch(launch.t, np.asarray(launch.y) + 0.3, "shifted.csv"))
    assert shifted.t.size == at_zero.t.size < 0.8 * np.asarray(launch.t).size
    assert any("samples of noise dropped" in n for n in shifted.notes)


@pytest.mark.parametrize(("rise", "start"), [(1.45, 0), (1.5, 0), (1.55, 1)])
def test_free_start_allows_a_same_sign_rise_of_up_to_three_sigma(rise, start):
    # the docstring's rule: an extreme may exceed the same-sign one a cycle before by at most
    # 3 noise σ (σ = 0.5 → 1.5, exact in binary) before the motion counts as still driven. A
    # decay 10·0.9^k, extremes every half period of 1 s, with extreme 2 raised to a0 + rise
    from hydrokit.identify.preprocess import _free_start

    k = np.arange(20)
    a = 10.0 * 0.9**k
    a[2] = a[0] + rise
    z = a * (-1.0) ** k
    ext = [(int(i), int(i), int(i)) for i in k]
    assert _free_start(0.5 * k, z, ext, 0.1, 0.5) == start


def test_rest_line_of_a_record_with_two_extremes_is_flat_at_the_tail_median():
    # fewer than three extremes: no three-extreme estimate, so the rest value is the record's
    # equilibrium (the tail median) and the drift is exactly zero
    from hydrokit.identify.preprocess import equilibrium, rest_line

    t = np.linspace(0.0, 1.0, 201)
    y = 0.02 + 0.1 * np.exp(-3.0 * t) * np.cos(2 * np.pi * 0.9 * t)  # under one cycle
    assert rest_line(t, y, 1e-4) == (equilibrium(y), 0.0)


@pytest.mark.parametrize(("hi", "lo"), [(0.05, 0.05), (0.02, 0.05), (0.05, 0.0)])
def test_an_amplitude_window_needs_hi_above_lo_above_zero(hi, lo):
    from hydrokit.identify.preprocess import _amplitude_window

    t = np.linspace(0.0, 10.0, 2001)
    z = 0.1 * np.exp(-0.3 * t) * np.cos(2 * np.pi * t)
    with pytest.raises(InputError, match=r"\(HI, LO\): expected HI > LO > 0"):
        _amplitude_window(t, z, 1e-4, (hi, lo), "r.csv")


@pytest.mark.parametrize("n", [19, 20])
def test_check_record_takes_twenty_samples_and_refuses_nineteen(n):
    # MIN_SAMPLES = 20 is "at least": two cycles of a 1 s decay at 10 Hz (20 samples) pass, one
    # sample fewer is refused in words
    from hydrokit.identify.preprocess import check_record
    from hydrokit.identify.types import Launch

    t = np.arange(n) * 0.1
    launch = Launch(t=t, y=np.exp(-0.2 * t) * np.cos(2 * np.pi * t), file="r.csv")
    if n == 20:
        assert check_record(launch)["period"] == pytest.approx(1.0, rel=1e-9)
    else:
        with pytest.raises(InputError, match="r.csv: only 19 samples after trimming; expected at least 20"):
            check_record(launch)


def test_growth_is_judged_by_thirds_so_a_late_release_is_not_growth():
    # 3 s of stillness, then a decay from 1 (period 1 s, 15 %/s): the first third (to 3.3 s)
    # holds the release peak, the last third a smaller swing (0.58), so the record decays. By
    # quarters the first would hold stillness only and the decay would read as growth
    from hydrokit.identify.preprocess import check_record
    from hydrokit.identify.types import Launch

    t = np.arange(1001) * 0.01
    y = np.where(t < 3.0, 0.0, np.exp(-0.15 * (t - 3.0)) * np.cos(2 * np.pi * (t - 3.0)))
    facts = check_record(Launch(t=t, y=y, file="r.csv"))
    assert facts["cycles"] == 7.0 and facts["period"] == pytest.approx(1.0, rel=1e-9)
