"""A direct spiral on every bundled vehicle with a steering surface completes (issue #49 item 3):
all 29 steps ended by steady-state detection, each settled, the depth held throughout.

The steps are checked against a second method, the turning circle flown separately at the same
deflection and propulsion: a spiral step held until steady is that circle's steady turn, so its
yaw rate and speed must agree with the circle's (rtol 1 %: both are the last window's means of a
rate that ripples with the depth hold's corrections by a fraction of a percent). And a course-stable
vehicle (the REMUS models' linear sway–yaw is stable, Clarke's C > 0 in tests/model/
test_auv_behaviour.py) has a single-valued spiral: no loop, the same yaw rate on the way down and
back up.

REMUS runs on its propeller at fixed rpm (the vehicle files' header): under a constant thrust a
20° step slows it to a third of its speed, where the stern planes cannot carry its 7 N of net
buoyancy (docs/manoeuvre.md). Slow: thousands of L/U per spiral.
"""

from __future__ import annotations

import math

import pytest
from tests.simulate.test_manoeuvre_bundled import RUNS, steered

from hydrokit.api import load_vehicle
from hydrokit.manoeuvre import run as M

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("name", steered())
def test_direct_spiral_completes_with_every_step_steady(name):
    vehicle = load_vehicle(name)
    options, _, _ = RUNS[name]
    res = M.run_manoeuvre(vehicle, M.spiral("direct"), **options)
    assert res.problem is None, res.problem
    assert res.hold_lost is None
    points = res.metrics["points"]
    assert len(points) == 29 and all(p["settled"] for p in points)
    if not name.startswith("remus100"):  # the Mariner's stability is not the point here
        return
    assert res.metrics["course_stable"] is True
    # single-valued: the first pass (down from +max) and the second (back up) give the same rate
    by_step: dict[float, list[float]] = {}
    for p in points:
        by_step.setdefault(round(p["deflection_deg"], 6), []).append(p["yaw_rate"])
    for deg, rates in by_step.items():
        scale = max(abs(r) for r in rates) + 1e-3
        assert max(rates) - min(rates) <= 0.01 * scale, f"{name} at {deg}°: {rates}"
    # the extreme step is the steady turning circle at that deflection (second method)
    top = points[0]
    circle = M.run_manoeuvre(vehicle, M.turning_circle(math.radians(top["deflection_deg"])), **options)
    assert circle.problem is None, circle.problem
    assert top["yaw_rate"] == pytest.approx(circle.metrics["steady_yaw_rate"], rel=0.01)
    assert top["speed"] == pytest.approx(circle.metrics["steady_speed"], rel=0.01)
