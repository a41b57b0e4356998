"""The plain-float laws of the closed loop (issue #50: every law once) against independent
references, both as Python and as compiled by ``compile_law`` for the compiled loop: the LOS
guidance against the look-ahead point's bearing on a straight leg, the loops' error and rate
against complex-exponential wrapping, and the pseudo-inverse allocation against
numpy's least-squares minimum-norm solution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.model.allocation import Allocator, pinv_allocate
from hydrokit.model.control import error_and_rate
from hydrokit.model.guidance import Path, los_guidance, path_distance, point_path_distance
from hydrokit.simulate.compiled_loop import _error_and_rate, _los_guidance, _path_distance, _pinv_allocate

RNG = np.random.default_rng(50)


def _wrapped(a: float) -> float:
    """An angle in (−π, π] through the complex exponential (independent of the modulo)."""
    return float(np.angle(np.exp(1j * a)))


def _straight(alpha: float, length: float, lookahead: float, speed: float = 0.8) -> Path:
    a = np.array([3.0, -2.0, 5.0])
    b = a + length * np.array([math.cos(alpha), math.sin(alpha), 0.0])
    return Path(points=[a, b], speeds=[speed], acceptance_radius=0.5, lookahead=lookahead)


@pytest.mark.parametrize("law", [los_guidance, _los_guidance], ids=["python", "compiled"])
@pytest.mark.parametrize("case", range(6))
def test_los_heading_points_at_the_lookahead_point_of_a_straight_leg(law, case):
    alpha = float(RNG.uniform(-math.pi, math.pi))
    lookahead = float(RNG.uniform(1.0, 10.0))
    path = _straight(alpha, 100.0, lookahead)
    along, cross = float(RNG.uniform(5.0, 80.0)), float(RNG.uniform(-20.0, 20.0))
    t_hat = np.array([math.cos(alpha), math.sin(alpha)])
    n_hat = np.array([-math.sin(alpha), math.cos(alpha)])  # starboard of the leg (NED)
    p = path.points[0, :2] + along * t_hat + cross * n_hat
    # the look-ahead point: Δ beyond the vehicle's projection on the leg (Fossen 2011 §10.3.2)
    target = path.points[0, :2] + (along + lookahead) * t_hat
    want = math.atan2(target[1] - p[1], target[0] - p[0])
    psi = float(RNG.uniform(-math.pi, math.pi))
    leg, heading, speed, depth, command = law(
        p[0], p[1], 5.0, psi, True, 1, 0.0, path.leg_table, 1, path.acceptance_radius, lookahead
    )
    assert leg == 1 and heading == 0.0
    # atan of the ratio against atan2 of the two components: a few ulp of π
    assert _wrapped(command - want) == pytest.approx(0.0, abs=1e-13)
    # slowed by the heading error (module Notes), at the leg's depth
    assert speed == pytest.approx(0.8 * max(0.0, math.cos(command - psi)), rel=1e-13, abs=1e-15)
    assert depth == 5.0


@pytest.mark.parametrize("law", [los_guidance, _los_guidance], ids=["python", "compiled"])
def test_los_switches_past_the_leg_end_and_holds_the_last_waypoint(law):
    pts = [[0.0, 0.0, 2.0], [10.0, 0.0, 2.0], [10.0, 0.0, 8.0]]
    path = Path(points=pts, speeds=[1.0, 0.5], acceptance_radius=1.0, lookahead=3.0)
    args = (path.leg_table, 2, 1.0, 3.0)
    # beyond waypoint 1 along the leg (outside the radius): leg 2 is vertical, keeps the course 0
    leg, heading, speed, depth, command = law(12.0, 0.0, 2.0, 0.0, True, 1, 0.0, *args)
    assert (leg, heading, command, speed) == (2, 0.0, 0.0, 0.0)
    assert depth == pytest.approx(2.0 + 3.0, rel=1e-15)  # the full lookahead down a vertical leg
    # within the radius of the last waypoint: finished, hold its depth with zero speed
    leg, heading, speed, depth, command = law(10.0, 0.0, 7.5, 0.0, True, 2, 0.0, *args)
    assert (leg, speed, depth) == (3, 0.0, 8.0)


def test_the_compiled_guidance_equals_the_python_one():
    path = Path(points=RNG.uniform(-50.0, 50.0, size=(6, 3)), speeds=RNG.uniform(0.2, 2.0, 5), acceptance_radius=2.0)
    for _ in range(20):
        x, y, z, psi, h = RNG.uniform(-50.0, 50.0, 5)
        leg = int(RNG.integers(1, 6))
        args = (x, y, z, psi, True, leg, h, path.leg_table, 5, 2.0, path.lookahead)
        # the same law, the same operation order: equal to the last bit but for libm's
        # trigonometry (numba's and CPython's may round their last bit differently)
        assert _los_guidance(*args) == pytest.approx(los_guidance(*args), rel=1e-15, abs=1e-15)


@pytest.mark.parametrize("law", [error_and_rate, _error_and_rate], ids=["python", "compiled"])
def test_error_and_rate_wrap_angles_and_difference_the_measurement(law):
    e, r = law(3.0, -3.0, True, 0.0, False, -3.1, True, 0.1)
    assert e == pytest.approx(_wrapped(6.0), abs=1e-15)
    assert r == pytest.approx(_wrapped(3.0 - -3.1) / 0.1, rel=1e-12)
    # a measured rate is used as given; no previous measurement (or dt ≤ 0) gives no rate
    assert law(2.0, 0.5, False, 0.25, True, 0.0, False, 0.1) == (1.5, 0.25)
    assert law(2.0, 0.5, False, 7.0, False, 1.0, False, 0.1) == (1.5, 0.0)
    assert law(2.0, 0.5, False, 7.0, False, 1.0, True, 0.0) == (1.5, 0.0)
    e, r = law(2.0, 0.5, False, 0.0, False, 1.5, True, 0.1)
    assert r == pytest.approx(5.0, rel=1e-12)


def _layout(m: int) -> np.ndarray:
    return RNG.normal(size=(6, m))


@pytest.mark.parametrize("law", [pinv_allocate, _pinv_allocate], ids=["python", "compiled"])
@pytest.mark.parametrize("m", [6, 8])
def test_pinv_allocation_is_the_minimum_norm_exact_solution(law, m):
    T = _layout(m)
    P = np.linalg.pinv(T)
    tau = RNG.normal(scale=50.0, size=6)
    big = np.full(m, 1e9)
    f = np.empty(m)
    assert not law(P, tau, -big, big, f)
    # B f = τ (T has full row rank), and the minimum-norm solution, as LAPACK's SVD gives it
    np.testing.assert_allclose(T @ f, tau, rtol=0, atol=1e-10 * np.abs(tau).max())
    ref = np.linalg.lstsq(T, tau, rcond=None)[0]
    np.testing.assert_allclose(f, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


@pytest.mark.parametrize("law", [pinv_allocate, _pinv_allocate], ids=["python", "compiled"])
def test_pinv_allocation_reports_a_broken_limit(law):
    T = _layout(8)
    P = np.linalg.pinv(T)
    tau = RNG.normal(scale=50.0, size=6)
    f = np.empty(8)
    law(P, tau, np.full(8, -1e9), np.full(8, 1e9), f)
    k = int(np.argmax(np.abs(f)))
    lo, hi = np.full(8, -1e9), np.full(8, 1e9)
    # a limit just inside the largest thrust: limited; just outside it: not
    (hi if f[k] > 0 else lo)[k] = f[k] * (1 - 1e-6)
    g = np.empty(8)
    assert law(P, tau, lo, hi, g)
    np.testing.assert_array_equal(g, f)  # the unclipped P τ, for the constrained solver to replace
    (hi if f[k] > 0 else lo)[k] = f[k] * (1 + 1e-6)
    assert not law(P, tau, lo, hi, g)
    assert law(P, np.full(6, np.nan), lo, hi, g)  # NaN is never within the limits


def test_the_allocator_saturates_within_the_limits_and_keeps_the_exact_solution_inside():
    T = _layout(8)
    alloc = Allocator(T, np.full(8, -20.0), np.full(8, 20.0))
    small = np.linalg.lstsq(T, T @ RNG.uniform(-5.0, 5.0, 8), rcond=None)[0]
    f, limited = alloc(T @ small)
    assert not limited
    np.testing.assert_allclose(f, small, rtol=0, atol=1e-12 * np.abs(small).max())
    f, limited = alloc(200.0 * (T @ small))
    assert limited
    assert np.all(f >= -20.0 - 1e-9) and np.all(f <= 20.0 + 1e-9)
    assert np.any(np.isclose(np.abs(f), 20.0, rtol=1e-9))  # some thruster at its limit


@pytest.mark.parametrize("law", [point_path_distance, _path_distance], ids=["python", "compiled"])
def test_path_distance_is_the_hand_computed_polyline_distance(law):
    # polyline (0,0,0) → (10,0,0) → (10,10,0) → (10,10,-6); distances worked by hand:
    # (5,3,0): 3 to leg 1; (12,5,0): 2 to leg 2; (-3,-4,0): 5 to the first point (3-4-5);
    # (10,0,2): 2 to the corner; (13,14,-2): 3-4-5 again to leg 3 at (10,10,-2); (4,−2,1): √5
    pts = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [10, 10, -6.0]])
    cases = [((5, 3, 0), 3.0), ((12, 5, 0), 2.0), ((-3, -4, 0), 5.0), ((10, 0, 2), 2.0)]
    cases += [((13, 14, -2), 5.0), ((4, -2, 1), math.sqrt(5.0))]
    for (px, py, pz), d in cases:
        # rel 1e-15: one projection and a square root, each rounded once
        assert law(float(px), float(py), float(pz), pts) == pytest.approx(d, rel=1e-15)


def test_path_distance_of_many_positions_is_the_law_at_each():
    pts = RNG.normal(size=(5, 3)) * 20
    P = RNG.normal(size=(50, 3)) * 20
    ref = [point_path_distance(*p, pts) for p in P]
    np.testing.assert_array_equal(path_distance(P, pts), ref)  # the same Python law at each
    # compiled against Python: two implementations (numba's code and sqrt may round the last bit
    # differently on another CPU), so to round-off of the coordinates (tens of m: ulp 7e-15 m)
    np.testing.assert_allclose([_path_distance(*p, pts) for p in P], ref, rtol=1e-14, atol=1e-12)
