"""The manoeuvre runner measures and says what happened (issue #49 item 3): pull-out sides that
are truly opposite, spiral steps ended by steady-state detection within a budget scaled by the
vehicle, and depth changes and holds described as they went.

Models as in test_manoeuvre.py: Nomoto's first-order yaw T ṙ + n1 r + n3 r³ = K δ (+ a bias) at
constant speed, whose steady states and decays are known in closed form.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hydrokit.manoeuvre import run as M

K, T = 0.2, 5.0
SERVO = (np.array([0.6]), np.array([np.inf]), np.array([0.0]))


def nomoto(n1=1.0, n3=0.0, bias=0.0, t_const=T):
    """ẋ of a constant-speed (2 m/s under 40 N) vehicle steered by T ṙ + n1 r + n3 r³ = K δ + bias."""

    def f(t, x, tau, d):
        xd = np.zeros(12)
        u, psi = x[6], x[5]
        xd[0] = u * math.cos(psi)
        xd[1] = u * math.sin(psi)
        xd[6] = (tau[0] - 10 * u * abs(u)) / 50.0
        xd[5] = x[11]
        xd[11] = (K * d[0] + bias - n1 * x[11] - n3 * x[11] ** 3) / t_const
        return xd

    return f


def fly(m, f, length=4.0, **kw):
    kw.setdefault("dt", 0.05)
    t, x, d, logic, w = M.fly_manoeuvre(f, m, 0, SERVO, tau=(40, 0, 0, 0, 0, 0), length=length, **kw)
    return M.measure(
        m, t, x, d, logic, vehicle="nomoto", surface_names=("rudder",), surface="rudder", reference_length=length
    )


def test_pull_out_sides_are_opposite_on_a_course_unstable_model():
    """Norrbin's unstable model inside its hysteresis loop (|K δ| < 2/(3√(3 n3))): −δ flown straight
    after the +δ side's residual turn would keep turning the same way; each side starts straight."""
    n3 = 100.0
    delta = 0.15  # rad, inside the loop's half-width 0.192 rad (closed form)
    assert K * delta < 2 / (3 * math.sqrt(3 * n3))
    res = fly(M.pull_out(delta), nomoto(-1.0, n3), dt=0.1)
    assert res.problem is None, res.problem
    sides = res.metrics["sides"]
    assert [s["deflection_deg"] for s in sides] == pytest.approx([math.degrees(delta), -math.degrees(delta)])
    assert sides[0]["yaw_rate_before"] * sides[1]["yaw_rate_before"] < 0 and res.metrics["opposite"] is True
    # released, the rate settles on the stable roots ±1/√n3 of −r + n3 r³ = 0 (rel: the steady test)
    r_inf = 1 / math.sqrt(n3)
    signs = [math.copysign(1.0, s["yaw_rate_before"]) for s in sides]
    assert res.metrics["residual_yaw_rate"] == pytest.approx([signs[0] * r_inf, signs[1] * r_inf], rel=2e-3)
    assert all(s["settled"] and math.isfinite(s["time_to_settle"]) for s in sides)
    assert res.metrics["course_stable"] is False


def test_pull_out_time_to_settle_of_a_first_order_decay():
    """Stable Nomoto: released, r = r0 e^(−t/T), so |r| stays within 5 % of r0 after T ln 20."""
    res = fly(M.pull_out(0.3), nomoto(), dt=0.02)
    assert res.problem is None
    for s in res.metrics["sides"]:
        assert s["time_to_settle"] == pytest.approx(T * math.log(20), rel=0.02)
        assert s["time_to_half"] == pytest.approx(T * math.log(2), rel=0.02)
    assert res.metrics["course_stable"] is True


def test_pull_out_that_turns_the_same_way_both_sides_is_not_complete():
    """A yaw bias larger than K δ: both deflections turn to starboard; the run must say so."""
    res = fly(M.pull_out(0.1), nomoto(bias=0.03), dt=0.1)
    rates = [s["yaw_rate_before"] for s in res.metrics["sides"]]
    assert rates == pytest.approx([K * 0.1 + 0.03, -K * 0.1 + 0.03], rel=2e-3)  # steady r = K δ + bias
    assert res.metrics["opposite"] is False and res.to_dict()["complete"] is False
    assert "the -5.73° side turned the same way as the +5.73° side" in res.problem


def test_spiral_budget_scales_with_the_vehicle():
    """A slow vehicle (T = 50 s, L/U = 50 s): each step needs ≥ 10 L/U = 500 s, so 29 steps cannot
    fit in 1800 s; the default budget, in L/U, completes the spiral and every step is steady."""
    f = nomoto(t_const=50.0)
    short = fly(M.spiral("direct"), f, length=100.0, dt=0.5, duration=1800.0)
    assert short.problem.startswith("spiral: only") and "of 29 steps" in short.problem
    res = fly(M.spiral("direct"), f, length=100.0, dt=0.5)
    assert res.problem is None, res.problem
    assert len(res.metrics["points"]) == 29 and all(p["settled"] for p in res.metrics["points"])
    for p in res.metrics["points"]:  # steady r = K δ; abs: the steady test's drift tolerance
        assert p["yaw_rate"] == pytest.approx(K * math.radians(p["deflection_deg"]), abs=2e-4)
    assert res.metrics["course_stable"] is True and res.metrics["loop_width_deg"] == 0.0


def test_spiral_that_never_reverses_is_not_complete():
    """A bias beyond the rudder's reach (K δ_max = 0.12 < 0.2): the vehicle turns one way at every step."""
    res = fly(M.spiral("direct", 0.3), nomoto(bias=0.2), dt=0.1)
    assert "kept turning to starboard (r > 0) at every deflection from +17.19° to −17.19°" in res.problem
    assert res.to_dict()["complete"] is False


def _record(z, kind_m, hold=None, length=1.33):
    """A synthetic record (straight ahead at 1 m/s) whose depth follows ``z`` (m) after the execute."""
    n = len(z)
    t = np.arange(n) * 1.0
    x = np.zeros((n, 12))
    x[:, 0] = t
    x[:, 2] = z
    x[:, 6] = 1.0
    logic = SimpleNamespace(executes=[0.0], notes=[])
    return M.measure(
        kind_m,
        t,
        x,
        np.zeros((n, 1)),
        logic,
        vehicle="auv",
        surface_names=("rudder",),
        surface="rudder",
        reference_length=length,
        hold=hold,
    )


def test_a_depth_change_that_rises_says_so():
    z = -np.linspace(0.0, 238.2, 300)  # asked 5 m deeper, it rose 238.2 m
    res = _record(z, M.depth_change(5.0, 0.26))
    assert res.problem.startswith("depth change: asked 5 m deeper, the vehicle rose 238 m in 299 s")
    assert "it went the other way: depth control lost" in res.problem


def test_a_lost_depth_hold_is_not_called_holding():
    z = -np.linspace(0.0, 224.0, 300)
    res = _record(z, M.zigzag(0.26, 0.26), hold={"depth": "sternplane"})
    assert res.problem.startswith(
        "zigzag: depth hold lost — the vehicle rose 224 m and ended 224 m from the depth at the execute (more than 2.66 m)"
    )
    assert "sank" not in res.problem  # it never went below where it started
    assert res.hold_lost is not None and res.to_dict()["hold_lost"] == res.hold_lost
    assert any("the depth hold by sternplane was lost" in w for w in res.warnings)
    kept = _record(np.linspace(0.0, 0.5, 300), M.zigzag(0.26, 0.26), hold={"depth": "sternplane"})
    assert kept.hold_lost is None and "depth hold lost" not in (kept.problem or "")


def test_a_depth_transient_that_comes_back_is_warned_of_not_lost():
    """Sinks 3.45 m (beyond 2 L = 2.66 m, within 4 × that) and comes back to 0.3 m: said, not lost."""
    t = np.linspace(0.0, 1.0, 301)  # the peak at a sample
    z = np.interp(t, [0.0, 0.5, 1.0], [0.0, 3.45, 0.3])
    res = _record(z, M.zigzag(0.26, 0.26), hold={"depth": "sternplane"})
    assert res.hold_lost is None and "depth hold lost" not in (res.problem or "")
    assert any(
        w.startswith("zigzag: the depth hold by sternplane let the vehicle stray: it sank 3.45 m (more than 2.66 m)")
        and w.endswith("before it was brought back to within 0.3 m of the depth at the execute")
        for w in res.warnings
    ), res.warnings
    wild = _record(12.0 * np.sin(math.pi * t), M.zigzag(0.26, 0.26), hold={"depth": "sternplane"})
    assert wild.hold_lost == "the vehicle sank 12 m (more than 10.6 m from the depth at the execute)"  # came back
