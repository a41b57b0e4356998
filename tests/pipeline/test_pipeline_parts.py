"""The pieces of ``hydrokit run`` against independent computations: cache keys, sampling,
envelopes, the choice rule and the vehicle's uncertainty block."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hydrokit
from hydrokit.core.names import DOF_NAMES
from hydrokit.data import DATA_DIR
from hydrokit.pipeline.cache import StepCache, digest
from hydrokit.pipeline.fleet import MC_METRICS, containment, draw_samples, summarize_runs

# --- cache ------------------------------------------------------------------------------------


def test_cache_round_trip_and_force(tmp_path):
    cache = StepCache(tmp_path)
    key = digest("identify", 1, [("a.csv", "abc")])
    assert cache.load("identify-surge", key) is None
    cache.store("identify-surge", key, {"x": [1.0, 2.0]})
    assert cache.load("identify-surge", key) == {"x": [1.0, 2.0]}
    assert StepCache(tmp_path, force=True).load("identify-surge", key) is None


def test_a_changed_input_changes_the_key_and_replaces_the_old_entry(tmp_path):
    cache = StepCache(tmp_path)
    k1, k2 = digest("identify", [("a.csv", "abc")]), digest("identify", [("a.csv", "abd")])
    assert k1 != k2
    cache.store("identify-surge", k1, 1)
    cache.store("identify-surge", k2, 2)
    assert cache.load("identify-surge", k1) is None and cache.load("identify-surge", k2) == 2
    assert len(list(tmp_path.glob("identify-surge-*.json"))) == 1


def test_a_corrupt_entry_is_recomputed_not_trusted(tmp_path):
    cache = StepCache(tmp_path)
    key = digest("x")
    cache.store("step", key, 1)
    next(tmp_path.glob("step-*.json")).write_text("{not json")
    assert cache.load("step", key) is None


def test_cache_entries_are_json_not_pickle(tmp_path):
    cache = StepCache(tmp_path)
    cache.store("step", digest("x"), {"a": 1})
    doc = json.loads(next(tmp_path.glob("step-*.json")).read_text())
    assert doc["output"] == {"a": 1}


# --- sampling and envelopes --------------------------------------------------------------------


def test_samples_have_the_requested_covariance_and_are_reproducible():
    mean = np.array([10.0, 30.0, 60.0])
    a = np.array([[0.04, 0.01, 0.0], [0.01, 0.09, -0.05], [0.0, -0.05, 0.64]])
    x, clipped = draw_samples(mean, a, 40_000, seed=3)
    assert clipped == 0
    # sample covariance of 40 000 draws: relative error ~ sqrt(2/n) ≈ 0.7 %; allow 4 %
    assert np.allclose(np.cov(x, rowvar=False), a, atol=0.04 * np.sqrt(np.outer(np.diag(a), np.diag(a))))
    assert np.allclose(x.mean(axis=0), mean, atol=0.02)
    y, _ = draw_samples(mean, a, 10, seed=3)
    assert np.array_equal(y, draw_samples(mean, a, 10, seed=3)[0])


def test_negative_draws_are_clipped_and_counted():
    x, clipped = draw_samples(np.array([0.1]), np.array([[1.0]]), 1000, seed=0)
    # P(N(0.1, 1) < 0) = Φ(−0.1) = 0.4602
    assert abs(clipped / 1000 - 0.4602) < 0.05 and x.min() == 0.0


def test_envelope_percentiles_and_containment():
    grid = np.arange(5)
    # 101 runs whose x at every time is 0, 1, …, 100 — percentiles are known exactly
    runs = [
        {
            "metrics": {"cross_track_rms": float(k), "completed": k % 2 == 0},
            "path": np.column_stack([np.full(5, k), 0 * grid, 0 * grid]),
        }
        for k in range(101)
    ]
    for r in runs:
        r["metrics"].update({k: 1.0 for k in MC_METRICS if k != "cross_track_rms"})
    s = summarize_runs(runs)
    assert s["metrics"]["cross_track_rms"] == {"median": 50.0, "p5": 5.0, "p95": 95.0}
    assert s["completed_fraction"] == pytest.approx(51 / 101)
    env = s["envelope"]
    assert np.all(env["p5"][:, 0] == 5.0) and np.all(env["max"][:, 0] == 100.0)
    inside = np.column_stack([np.full(5, 50.0), 0 * grid, 0 * grid])
    half = inside.copy()
    half[:2, 0] = 101.0  # outside at 2 of 5 times
    assert containment(inside, env) == 1.0
    assert containment(half, env) == pytest.approx(3 / 5)
    assert containment(np.column_stack([np.full(5, 3.0), 0 * grid, 0 * grid]), env, ("p5", "p95")) == 0.0


def test_nominal_of_a_parameter_reads_vectors_and_matrices():
    from hydrokit.pipeline.fleet import _nominal

    assert _nominal({"added_mass": [1, 2, 3, 4, 5, 6]}, "added_mass.heave") == 3.0
    m = np.diag([1.0, 2, 3, 4, 5, 6]).tolist()
    assert _nominal({"linear_damping": m}, "linear_damping.yaw") == 6.0


def test_with_coefficients_changes_only_the_named_diagonal_entries():
    import hydrokit
    from hydrokit.pipeline.fleet import with_coefficients

    v = hydrokit.load_vehicle("minerva")
    w = with_coefficients(v, {"added_mass.sway": 7.0, "quadratic_damping.yaw": 3.0, "linear_damping.surge": 2.0})
    assert w.M_A[1, 1] == 7.0 and w.D_Q[5] == 3.0 and w.D_L[0, 0] == 2.0
    changed = np.argwhere(w.M_A != v.M_A).tolist()
    assert changed == [[1, 1]] and np.count_nonzero(w.D_Q != v.D_Q) == 1
    assert w.thrusters is v.thrusters and not math.isclose(w.M[1, 1], v.M[1, 1])


def test_a_negative_identified_damping_is_said_and_not_written_into_the_vehicle():
    """Issue 32 class 6: a tank K_L of −0.4 N·s/m was chosen and written into vehicle.yaml (which the
    reader now refuses); it falls back along the chain and the report says why."""
    from types import SimpleNamespace

    from hydrokit.pipeline.compare import comparison
    from hydrokit.pipeline.steps import negative_damping_warnings

    base = hydrokit.load_vehicle(DATA_DIR / "projects" / "udrobot" / "base.yaml")
    full = {
        "added_mass": {"mean": 10.0, "se": 0.1, "ci": [9.8, 10.2]},
        "linear_damping": {"mean": -0.4, "se": 0.3, "ci": [-1.0, 0.2]},
        "quadratic_damping": {"mean": 60.0, "se": 2.0, "ci": [56.0, 64.0]},
    }
    tank = {"surge": {"full_scale": full, "truth": None}}
    cfd = {"surge": {"linear_damping": 1.05, "quadratic_damping": -3.0, "se": {"linear_damping": 0.01}}}
    project = SimpleNamespace(choose=dict.fromkeys(DOF_NAMES, "tank"), published={})
    _, chosen = comparison(project, tank, {"cfd": cfd}, base)  # type: ignore[arg-type]
    # K_L: the tank's negative value is skipped for the CFD fit's; K_Q: the tank's (positive) stays
    assert chosen["surge"]["linear_damping"] == {
        "value": 1.05,
        "source": "cfd",
        "se": 0.01,
        "negative": {"tank": -0.4},
    }
    assert chosen["surge"]["quadratic_damping"]["value"] == 60.0
    assert chosen["surge"]["quadratic_damping"]["negative"] == {"cfd": -3.0}
    assert chosen["surge"]["added_mass"] == {"value": 10.0, "source": "tank", "se": 0.1}
    said = negative_damping_warnings(chosen)
    assert said[0] == (
        "surge linear_damping: the tank value -0.4 (SI, full scale) is negative — energy would be fed in; "
        "not written into the vehicle, which takes the cfd value 1.05"
    )
    assert len(said) == 2 and said[1].startswith("surge quadratic_damping: the cfd value -3 ")
