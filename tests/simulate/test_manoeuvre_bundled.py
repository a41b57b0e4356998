"""Every standard manoeuvre on every bundled vehicle that has a steering surface (issue #49 item 3):
each run is either complete with every metric finite, or refused up front (a planar model has no
depth manoeuvres), or — when the vehicle itself cannot fly it (a course it cannot hold, a depth
its planes cannot keep) — incomplete with a problem that names the manoeuvre and says what
happened, ``complete`` false. Nothing is ever ``complete`` with a metric missing.

No REMUS number is asserted here (tests/simulate/test_spiral_bundled.py checks the spirals'
physics); every bundled vehicle must complete every manoeuvre it is not refused, the REMUS models
on their propeller at fixed rpm (under a constant thrust they slow in a tight turn until the planes
cannot carry their 7 N of buoyancy: docs/manoeuvre.md). Steps: Mariner dt = 0.5 s (L/U = 21 s, rudder
rate 2.3°/s: the manoeuvre's time scale is hundreds of steps), REMUS dt = 0.05 s (L/U ≈ 0.9 s);
the spirals (thousands of L/U) are marked slow.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hydrokit.api import load_vehicle
from hydrokit.errors import InputError
from hydrokit.manoeuvre import run as M

VEHICLES = Path(__file__).resolve().parents[2] / "src" / "hydrokit" / "data" / "vehicles"
#: REMUS propulsion: its propeller held at the speed that gives Prestero's 3.86 N at 1.54 m/s
#: (the vehicle files' header), plus his propeller torque as a constant force
REMUS = {"tau": (0, 0, 0, -0.543, 0, 0), "commands": {"propeller": 11.567}, "nu0": (1.5, 0, 0, 0, 0, 0), "dt": 0.05}
#: propulsion: Mariner's 15 kn (docs/manoeuvre.md), the REMUS propeller at fixed rpm
RUNS = {
    "mariner": ({"tau": (727000.0, 0, 0, 0, 0, 0), "nu0": (7.7, 0, 0, 0, 0, 0), "dt": 0.5}, 35.0, 20.0),
    "remus100": (REMUS, 15.0, 15.0),
    "remus100-fins": (REMUS, 15.0, 15.0),
}
#: metrics that may be None in a complete run, and why: a residual turn that never halves
OPTIONAL = {"time_to_half", "residual_bias"}  # residual_bias: only a course-stable pull-out has one


def steered() -> list[str]:
    """Every bundled vehicle file with control surfaces (a new one must be added to RUNS)."""
    import yaml

    return sorted(p.stem for p in VEHICLES.glob("*.yaml") if yaml.safe_load(p.read_text()).get("control_surfaces"))


def test_every_steered_vehicle_is_covered():
    assert set(steered()) <= set(RUNS), "a bundled vehicle with control_surfaces has no propulsion in RUNS"
    assert {"mariner", "remus100", "remus100-fins"} <= set(steered())


def manoeuvres(turn: float, zig: float) -> dict[str, M.Manoeuvre]:
    rad = math.radians
    return {
        "turning_circle": M.turning_circle(rad(turn)),
        "zigzag": M.zigzag(rad(zig), rad(zig)),
        "spiral_direct": M.spiral("direct"),
        "spiral_reverse": M.spiral("reverse"),
        "pull_out": M.pull_out(rad(turn)),
        "depth_change": M.depth_change(5.0, rad(15.0)),
        "vertical_zigzag": M.vertical_zigzag(rad(10.0), rad(10.0)),
    }


def _numbers(obj, path=""):
    """Every (path, value) leaf of a metrics dict that should be a number (bools and words skipped)."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _numbers(v, f"{path}.{k}" if path else k)
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _numbers(v, f"{path}[{i}]")
    elif not isinstance(obj, (bool, str)):
        yield path, obj


CASES = [
    pytest.param(v, k, marks=[pytest.mark.slow] if k.startswith("spiral") else [], id=f"{v}-{k}")
    for v in RUNS
    for k in manoeuvres(15, 15)
]


@pytest.mark.parametrize(("name", "key"), CASES)
def test_every_manoeuvre_is_complete_refused_or_said(name, key, monkeypatch):
    vehicle = load_vehicle(name)
    options, turn, zig = RUNS[name]
    m = manoeuvres(turn, zig)[key]
    if m.kind in M.VERTICAL and vehicle.planar:

        def never(*a, **k):
            raise AssertionError("flown before the refusal")

        monkeypatch.setattr(M, "fly_manoeuvre", never)
        with pytest.raises(
            InputError, match=rf"vehicle '{name}' is planar \(dofs: .*\); expected a vehicle with heave"
        ):
            M.run_manoeuvre(vehicle, m, **options)
        return
    res = M.run_manoeuvre(vehicle, m, **options)
    doc = res.to_dict()
    assert doc["complete"] is (res.problem is None)
    if res.problem is None:
        bad = [(p, v) for p, v in _numbers(res.metrics) if p.split(".")[-1] not in OPTIONAL]
        bad = [(p, v) for p, v in bad if not (isinstance(v, (int, float)) and math.isfinite(v))]
        assert bad == [], f"{name} {key}: complete with metrics missing {bad}"
        if m.kind == "pull_out":
            rates = [s["yaw_rate_before"] for s in res.metrics["sides"]]
            assert rates[0] * rates[1] < 0 and res.metrics["opposite"] is True
        if m.kind == "spiral":
            assert len(res.metrics["points"]) == (29 if m.mode == "direct" else 15)
            assert res.metrics["course_stable"] is not None
            assert all(p["settled"] for p in res.metrics["points"])
        if res.hold.get("depth") and m.kind not in M.VERTICAL:
            assert res.hold_lost is None
    else:  # said: the manoeuvre named, then what happened; and nothing claims to be complete
        label = "pull-out" if m.kind == "pull_out" else m.kind.replace("_", " ")
        assert res.problem.startswith(label + ":"), res.problem
        assert len(res.problem) > len(label) + 20
    # the planar ship completes every horizontal manoeuvre, the REMUS models (on their propeller) all
    assert res.problem is None, res.problem


@pytest.mark.parametrize("depth", [5.0, -5.0])
def test_remus100_depth_change_within_its_pitch_limit(depth):
    """The user's ask: a 5 m depth change reached without leaving the vehicle's pitch limit (20°,
    the depth hold's). Closed loop through the depth-to-pitch law: the depth reached within 0.5 m
    and |θ| ≤ 20° throughout; the open-loop execute at the same planes (held until the depth is
    reached) pitches far beyond it, which is why the closed loop is the default."""
    vehicle = load_vehicle("remus100")
    options = {"tau": (3.86, 0, 0, -0.543, 0, 0), "nu0": (1.5, 0, 0, 0, 0, 0), "dt": 0.05}
    limit = M.HOLD_MAX_PITCH
    res = M.run_manoeuvre(vehicle, M.depth_change(depth, math.radians(15), limit), **options)
    assert res.problem is None, res.problem
    after = res.time >= 0
    dz = res.eta[after, 2] - res.eta[after, 2][0]
    assert dz[-1] == pytest.approx(depth, abs=0.5)
    assert float(np.max(np.abs(res.eta[:, 4]))) <= limit
    m = res.metrics
    assert m["time_to_target"] is not None and m["time_to_settle"] >= m["time_to_target"]
    assert m["depth_overshoot"] == pytest.approx(max(float(np.max(np.sign(depth) * dz)) - abs(depth), 0.0))
    assert abs(m["max_abs_pitch_deg"]) == pytest.approx(math.degrees(float(np.max(np.abs(res.eta[after, 4])))))
    if depth > 0:
        open_loop = M.run_manoeuvre(vehicle, M.depth_change(depth, math.radians(15)), **options)
        assert float(np.max(np.abs(open_loop.eta[:, 4]))) > limit + math.radians(10)
