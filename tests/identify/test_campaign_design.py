from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.identify.campaign import describe
from hydrokit.identify.design import plan_experiment
from hydrokit.identify.estimators import identify_launch
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch


def test_describe_statistics_and_outlier_rule():
    vals = [1.0, 1.1, 0.9, 1.05, 0.95, 5.0]
    s = describe(vals, [f"f{i}" for i in range(6)])
    assert s["rejected"] == ["f5"]
    kept = np.array(vals[:5])
    assert s["mean"] == pytest.approx(kept.mean())
    assert s["std"] == pytest.approx(kept.std(ddof=1))
    # t-interval with 4 dof: t_0.975 = 2.776 (table value)
    half = 2.776 * kept.std(ddof=1) / math.sqrt(5)
    assert s["ci"][1] - s["mean"] == pytest.approx(half, rel=1e-3)


def test_cramer_rao_bound_predicts_output_error_spread(pendulum_rig):
    truth = (0.05, 0.02, 0.3)
    sensor = SensorModel.imu(hold_time=0)
    plan = plan_experiment(pendulum_rig, *truth, [0.15], sensor, duration=10.0)[0]
    fits = [
        identify_launch(
            pendulum_rig, simulate_launch(pendulum_rig, *truth, 0.15, 10.0, sensor, rng=s), "output-error"
        ).added_mass
        for s in range(12)
    ]
    ratio = np.std(fits, ddof=1) / plan["added_mass"]
    assert 0.5 < ratio < 1.6  # efficient estimator: spread ≈ bound (12-sample std: ±50 %)


def test_plan_prefers_large_amplitude_for_quadratic_damping(pendulum_rig):
    plan = plan_experiment(pendulum_rig, 0.05, 0.02, 0.3, [0.05, 0.25], SensorModel.imu())
    assert plan[1]["quadratic_damping_rel"] < plan[0]["quadratic_damping_rel"]
