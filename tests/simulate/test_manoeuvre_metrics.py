"""Manoeuvre metrics against closed forms: a circle entered from a straight line, its geometry by
hand; a first-order Nomoto zigzag integrated by scipy's solve_ivp with events (a second method)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.manoeuvre import metrics as mm


def circle_record(R=20.0, U=2.0, beta=0.1, turns=1.75, side=1.0, psi0=0.0, origin=(0.0, 0.0), n=40000):
    """Straight approach then a circle of radius R entered at the execute (t = 0).

    Course χ along the circle; heading ψ = χ + β (bow into the turn); u = U cos β, v = −U sin β.
    ``side`` −1 mirrors it to port; the whole record is then turned by ψ0 and moved to ``origin``.
    """
    chi = np.linspace(0.0, turns * 2 * np.pi, n)
    x, y = R * np.sin(chi), R * (1 - np.cos(chi))
    psi = chi + beta
    psi[0] = 0.0  # the execute sample: still on the straight course
    u = np.full(n, U * math.cos(beta))
    v = np.full(n, -U * math.sin(beta))
    u[0], v[0] = U, 0.0
    r = np.full(n, U / R)
    t = chi * R / U
    y, psi, v, r = side * y, side * psi, side * v, side * r
    c, s = math.cos(psi0), math.sin(psi0)
    X, Y = origin[0] + c * x - s * y, origin[1] + s * x + c * y
    eta = np.column_stack([X, Y, np.zeros(n), np.zeros(n), np.zeros(n), psi + psi0])
    nu = np.column_stack([u, v, np.zeros(n), np.zeros(n), np.zeros(n), r])
    return t, eta, nu


@pytest.mark.parametrize("side", [1.0, -1.0])
@pytest.mark.parametrize("psi0", [0.0, 2.5])
def test_turning_circle_geometry(side, psi0):
    R, U, beta = 20.0, 2.0, 0.1
    t, eta, nu = circle_record(R, U, beta, side=side, psi0=psi0, origin=(100.0, -40.0))
    m = mm.turning_circle_metrics(t, eta, nu)
    # 90° of heading is reached at course 90° − β: advance R cos β, transfer R (1 − sin β);
    # 180° at course 180° − β: across R (1 + cos β). Linear interpolation between samples 1e-4 rad
    # apart on a circle errs by about R·(1e-4)²/8: rtol 1e-7 leaves a margin of 100.
    assert m.advance == pytest.approx(R * math.cos(beta), rel=1e-7)
    assert m.transfer == pytest.approx(R * (1 - math.sin(beta)), rel=1e-7)
    assert m.tactical_diameter == pytest.approx(R * (1 + math.cos(beta)), rel=1e-7)
    assert m.time_to_90_deg == pytest.approx((math.pi / 2 - beta) * R / U, rel=1e-7)
    assert m.time_to_180_deg == pytest.approx((math.pi - beta) * R / U, rel=1e-7)
    # steady values over the last 360°: exact on a circle (the fit is algebraic, exact for points on it)
    assert m.steady_turning_diameter == pytest.approx(2 * R, rel=1e-9)
    assert m.steady_speed == pytest.approx(U, rel=1e-12)
    assert m.steady_yaw_rate == pytest.approx(side * U / R, rel=1e-12)
    assert m.drift_angle_deg == pytest.approx(math.degrees(beta), rel=1e-9)
    assert m.direction == ("starboard" if side > 0 else "port")
    assert m.speed_ratio == pytest.approx(1.0, rel=1e-12)
    assert m.missing() is None


def test_turning_circle_missing_parts_are_named():
    t, eta, nu = circle_record(turns=0.4)  # 144°: advance yes, tactical diameter no
    m = mm.turning_circle_metrics(t, eta, nu)
    assert m.advance is not None and m.tactical_diameter is None and m.steady_turning_diameter is None
    assert "180°" in m.missing()
    t, eta, nu = circle_record(turns=1.2)  # 432°: not yet the 540° the steady window needs
    assert "steady" in mm.turning_circle_metrics(t, eta, nu).missing()
    t, eta, nu = circle_record(turns=0.2)
    assert "90°" in mm.turning_circle_metrics(t, eta, nu).missing()
    with pytest.raises(InputError, match=r"expected \(n,\), \(n, 6\), \(n, 6\)"):
        mm.turning_circle_metrics(t[:5], eta, nu)


def test_fit_circle_and_crossing():
    th = np.linspace(0, 1.0, 7)
    cx, cy, r = mm.fit_circle(3 + 2 * np.cos(th), -1 + 2 * np.sin(th))
    # exact for points on a circle (rtol at round-off)
    assert (cx, cy, r) == pytest.approx((3.0, -1.0, 2.0), rel=1e-10, abs=1e-10)
    c = mm.first_reach(np.array([0.0, 1.0, 3.0]), 2.0)
    assert (c.i, c.w) == (2, 0.5)
    assert c.at(np.array([0.0, 10.0, 20.0])) == pytest.approx(15.0)
    assert mm.first_reach(np.array([0.0, 1.0]), 5.0) is None
    assert mm.first_reach(np.array([3.0, 1.0]), 2.0).i == 0


# --- the zigzag against an independent integration --------------------------------------------

K, T = 0.2, 5.0  # Nomoto gain 1/s and time constant s: T ṙ + r = K δ, ψ̇ = r


def nomoto_zigzag_reference(A, B, n_exec=4):
    """Executes, overshoot peaks and dense record of a Nomoto A/B zigzag by solve_ivp with events."""
    from scipy.integrate import solve_ivp

    t0, y, cmd = 0.0, np.array([0.0, 0.0]), A
    executes, peaks, ts, ys = [0.0], [], [], []
    while len(executes) < n_exec + 1 or len(peaks) < n_exec - 1:
        level = B if cmd > 0 else -B
        hit = lambda t, y, level=level: y[0] - level  # noqa: E731
        hit.terminal = True
        top = lambda t, y: y[1]  # noqa: E731
        sol = solve_ivp(
            lambda t, y, cmd=cmd: [y[1], (K * cmd - y[1]) / T],
            (t0, t0 + 200),
            y,
            events=[hit, top],
            rtol=1e-11,
            atol=1e-12,
            dense_output=True,
        )
        peaks += [float(yy[0]) for tt, yy in zip(sol.t_events[1], sol.y_events[1]) if tt > t0 + 1e-9]
        grid = np.linspace(t0, sol.t[-1], 4001)
        ts.append(grid)
        ys.append(sol.sol(grid)[0])
        t0, y, cmd = float(sol.t[-1]), sol.y[:, -1], -cmd
        executes.append(t0)
    t = np.concatenate(ts)
    keep = np.concatenate([[True], np.diff(t) > 0])
    return executes, peaks, t[keep], np.concatenate(ys)[keep]


def test_zigzag_metrics_against_events():
    A, B = math.radians(10), math.radians(10)
    executes, peaks, t, psi = nomoto_zigzag_reference(A, B)
    m = mm.zigzag_metrics(t, psi, executes[:4], B)
    # the overshoots are the heading at the yaw-rate-zero events beyond ±B; sampled peaks of a
    # smooth record (spacing ≤ 0.05 s, |ψ̈| ≤ K·A/T) err by < ψ̈·h²/8 ≈ 1e-6 deg: abs 1e-4 deg
    assert m.first_overshoot_deg == pytest.approx(math.degrees(peaks[0] - B), abs=1e-4)
    assert m.second_overshoot_deg == pytest.approx(math.degrees(-peaks[1] - B), abs=1e-4)
    assert m.initial_turning_time == pytest.approx(executes[1], rel=1e-12)
    assert m.period == pytest.approx(executes[3] - executes[1], rel=1e-12)
    assert m.missing() is None
    assert m.first_overshoot_deg > 0.5  # a real overshoot, not a vacuous one
    # port first: the same numbers
    mp = mm.zigzag_metrics(t, -psi, executes[:4], B)
    assert mp.first_overshoot_deg == pytest.approx(m.first_overshoot_deg, abs=1e-12)
    short = mm.zigzag_metrics(t[t < executes[1] - 1], psi[t < executes[1] - 1], executes[:1], B)
    assert short.initial_turning_time is None and "second execute" in short.missing()
    with pytest.raises(InputError, match="expected a positive angle"):
        mm.zigzag_metrics(t, psi, executes, -1.0)


def test_a_replayed_heading_that_never_gets_back_past_b_has_no_overshoot():
    """A replay imposes the trial's executes: a sluggish model's heading may peak short of the check
    angle before the next one. Its peak minus B is negative — no overshoot, reported as not
    reached (it read as an overshoot of −45° on a real pond trial)."""
    B = math.radians(10)
    t = np.linspace(0.0, 40.0, 4001)
    # up to 15° (past B: first overshoot 5°), then down to −6° only (short of −B), then up again
    psi = np.radians(np.interp(t, [0, 8, 12, 20, 26, 40], [0, 15, 12, -6, -4, 20]))
    m = mm.zigzag_metrics(t, psi, [0.0, 6.0, 18.0, 30.0], B)
    assert m.first_overshoot_deg == pytest.approx(5.0, abs=1e-6)
    assert m.second_overshoot_deg is None  # −6° never passed −10°: not −4°
    assert "second overshoot" in m.missing()


def test_imo_limits():
    # IMO MSC.137(76) 5.3.3: 10/10 first overshoot 10° below L/V 10 s, 20° from 30 s, 5 + L/V/2 between
    rows = mm.imo_criteria(
        "zigzag",
        {"deflection_deg": 10.0, "check_angle_deg": 10.0},
        {"first_overshoot_deg": 12.0, "second_overshoot_deg": 30.0, "distance_at_second_execute": 100.0},
        100.0,
        5.0,
    )
    by = {r["criterion"]: r for r in rows}
    assert by["10°/10° first overshoot"]["limit"] == pytest.approx(5 + 0.5 * 20)
    assert by["10°/10° first overshoot"]["passed"] is True
    assert by["10°/10° second overshoot"]["limit"] == pytest.approx(17.5 + 0.75 * 20)
    assert by["initial turning: distance at 10° ≤ 2.5 L"]["passed"] is True
    rows = mm.imo_criteria(
        "turning_circle", {"deflection_deg": 35.0}, {"advance": 460.0, "tactical_diameter": 400.0}, 100.0, 5.0
    )
    assert [r["passed"] for r in rows] == [False, True]
    assert mm.imo_criteria("zigzag", {"deflection_deg": 20.0, "check_angle_deg": 20.0}, {}, 50, 10)[0]["limit"] == 25
    assert mm.imo_criteria("turning_circle", {}, {}, None, 5.0) == []
