"""Predictions with intervals (``manoeuvre --samples``, issue #48 item 7) on the Mariner.

The rudder's yaw moment N_uu·δ is given a σ; each draw flies a short turning circle at
dt = 0.5 s. Checks: a σ of ~0 collapses every interval onto the nominal metric; the interval of
the tactical diameter holds the nominal and widens with σ; and, independently of the draw, a
linear-in-the-parameter prediction from the ±1.96σ vehicles (flown with ``with_coefficients``)
gives the same interval.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from hydrokit.api import load_vehicle
from hydrokit.errors import InputError
from hydrokit.manoeuvre import run as M
from hydrokit.manoeuvre.samples import add_intervals, intervals, numeric_metrics
from hydrokit.model.uncertainty import make_uncertainty, parameter_value, with_coefficients

RUDDER = "terms.N_uu*delta(rudder)"
SETTINGS = {"tau": (727000, 0, 0, 0, 0, 0), "nu0": (7.7, 0, 0, 0, 0, 0), "dt": 0.5}
TURN = M.turning_circle(math.radians(35))


@pytest.fixture(scope="module")
def mariner():
    return load_vehicle("mariner")


def with_sigma(vehicle, rel):
    n = parameter_value(vehicle, RUDDER)
    unc = make_uncertainty([RUDDER], [[(rel * n) ** 2]], {}, "test", surfaces=tuple(vehicle.surfaces.names))
    return replace(vehicle, uncertainty=unc)


def fly(vehicle):
    return M.run_manoeuvre(vehicle, TURN, **SETTINGS)


@pytest.fixture(scope="module")
def nominal(mariner):
    return fly(mariner)


def sampled(vehicle, rel, nominal, n):
    res = replace(nominal, warnings=[])
    v = with_sigma(vehicle, rel)
    drawn = add_intervals(res, v, n, 7, fly)
    return res, drawn


def test_a_zero_sigma_collapses_every_interval_onto_the_nominal(mariner, nominal):
    res, _ = sampled(mariner, 1e-12, nominal, 3)
    assert res.problem is None
    flat = numeric_metrics(nominal.metrics)
    assert set(res.intervals) == set(flat) and "tactical_diameter" in flat
    for name, value in flat.items():
        iv = res.intervals[name]
        assert iv["samples"] == 3
        for key in ("median", "low95", "high95"):
            # a relative change of 1e-12 in one coefficient: the same run to round-off
            assert iv[key] == pytest.approx(value, rel=1e-7, abs=1e-9), (name, key)
    doc = res.to_dict()
    assert doc["intervals"]["advance"]["samples"] == 3 and doc["sampling"]["parameters"] == [RUDDER]


def test_the_tactical_diameter_interval_holds_the_nominal_widens_with_sigma_and_matches_the_1_96_sigma_vehicles(
    mariner, nominal
):
    td = nominal.metrics["tactical_diameter"]
    widths = []
    for rel in (0.04, 0.08):
        res, drawn = sampled(mariner, rel, nominal, 8)
        iv = res.intervals["tactical_diameter"]
        assert iv["samples"] == 8
        assert iv["low95"] < td < iv["high95"]
        widths.append(iv["high95"] - iv["low95"])
        assert len(res.sample_tracks) == 8
    # the same seed draws the same standard normals: twice the σ, about twice the width
    assert widths[1] > 1.6 * widths[0]
    # independent: the ±1.96σ vehicles, set by hand, give the slope of TD in N_uu·δ; the draw's own
    # 2.5–97.5 % values of the coefficient then predict the interval (linear within ~1 % here:
    # the two ±1.96σ diameters straddle the nominal by +11 % and −9 %)
    n0 = parameter_value(mariner, RUDDER)
    sigma = 0.08 * abs(n0)
    lo_v, hi_v = (fly(with_coefficients(mariner, {RUDDER: n0 + s * sigma})) for s in (-1.96, 1.96))
    slope = (hi_v.metrics["tactical_diameter"] - lo_v.metrics["tactical_diameter"]) / (2 * 1.96 * sigma)
    predicted = sorted(td + slope * (np.percentile(drawn.values[:, 0], [2.5, 97.5]) - n0))
    assert [iv["low95"], iv["high95"]] == pytest.approx(predicted, rel=0.02)


def test_intervals_of_draws_that_missed_a_metric_and_the_refusals(mariner):
    found = intervals({"a": 1.0, "b": 2.0, "flag": True, "word": "port"}, [{"a": 1.0, "b": None}, {"a": 3.0}])
    assert set(found) == {"a", "b"}
    assert found["a"]["samples"] == 2 and found["a"]["median"] == pytest.approx(2.0)
    assert found["a"]["low95"] == pytest.approx(1.05) and found["a"]["high95"] == pytest.approx(2.95)
    assert found["b"] == {"median": None, "low95": None, "high95": None, "samples": 0}
    with pytest.raises(InputError, match="no 'uncertainty:' block"):
        add_intervals(None, mariner, 4, 1, fly)
    with pytest.raises(InputError, match="--samples 1: expected a whole number ≥ 2"):
        add_intervals(None, with_sigma(mariner, 0.1), 1, 1, fly)


def test_a_draw_that_diverges_is_counted_not_fatal(mariner, nominal):
    """A drawn vehicle whose flight fails (here every other one, by a stand-in flight) is left out
    of the intervals and said in a warning; the others still give them."""
    from hydrokit.errors import SimulationError

    calls = []

    def flaky(vehicle):
        calls.append(vehicle)
        if len(calls) % 2:
            raise SimulationError("the state became non-finite at t = 1 s")
        return nominal

    res = replace(nominal, warnings=[])
    add_intervals(res, with_sigma(mariner, 0.1), 4, 1, flaky)
    assert res.intervals["advance"]["samples"] == 2
    assert res.intervals["advance"]["median"] == pytest.approx(nominal.metrics["advance"])
    assert res.sampling["failed"] == 2
    assert any("2 of 4 drawn vehicle(s) could not fly" in w for w in res.warnings)


def test_the_draws_fly_on_threads_and_give_what_one_after_the_other_gives(mariner):
    """The fleet on two threads (the loop's kernels release the GIL) against the same draws flown one
    after the other: every metric of every draw the same, bit for bit, in the draws' order."""
    from hydrokit.manoeuvre.samples import fly_samples

    v = with_sigma(mariner, 0.1)
    seen = []
    threaded = fly_samples(v, 6, 3, fly, progress=lambda k, n: seen.append((k, n)), workers=2)
    serial = fly_samples(v, 6, 3, fly, workers=1)
    assert threaded.metrics == serial.metrics
    assert len({m["advance"] for m in serial.metrics}) == 6  # six different vehicles, not one
    assert seen == [(k, 6) for k in range(1, 7)]
    for a, b in zip(threaded.tracks, serial.tracks):
        np.testing.assert_array_equal(a, b)
