"""The plain-float thruster laws of model/thrusters.py against independent references: the
open-water curve evaluated by numpy's polyval, the bollard closed form, the inverse by a root
finder of scipy, the exact first-order lag, and the table curve against numpy's np.interp."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.model.thrusters import (
    PropellerCurve,
    TableCurve,
    propeller_speed,
    propeller_thrust,
    rotor_lag,
    table_interp,
)
from hydrokit.simulate.compiled import table_interp_compiled

KF = (-0.05, -0.1, -0.25, 0.42)
KR = (0.02, 0.05, 0.3, 0.3)
ARGS = (0.12, 1025.0, -0.5, 1.0, KF, KR, 0.9, 0.8)  # D m, ρ kg/m³, J range, K_T, losses
ULPS = 4 * np.finfo(float).eps  # a few ulps: two implementations of one formula round apart


@pytest.mark.parametrize("n, va", [(17.5, 0.4), (5.0, 0.0), (-12.0, 0.3), (30.0, -0.2), (2.0, 1.5)])
def test_propeller_thrust_is_the_open_water_curve(n, va):
    D, rho, lo, hi = 0.12, 1025.0, -0.5, 1.0
    J = min(max(va / (n * D), lo), hi)
    kt = max(float(np.polyval(KF if n > 0 else KR, J)), 0.0)
    loss = 0.9 if n > 0 else 0.8
    # polyval's Horner is the law's operation order: rel 1e-14 covers the product's rounding
    assert propeller_thrust(n, va, *ARGS) == pytest.approx(loss * kt * rho * D**4 * abs(n) * n, rel=1e-14)


@pytest.mark.parametrize("f", [3.0, -2.0])
def test_propeller_speed_at_rest_is_the_bollard_closed_form(f):
    kt0, loss = (0.42, 0.9) if f > 0 else (0.3, 0.8)
    n = math.copysign(math.sqrt(abs(f) / (loss * kt0 * 1025.0 * 0.12**4)), f)
    assert propeller_speed(f, 0.0, 40.0, *ARGS) == pytest.approx(n, rel=1e-14)


@pytest.mark.parametrize("f, va", [(3.0, 0.5), (-2.0, 0.3), (10.0, 1.2)])
def test_propeller_speed_inverts_the_thrust_as_brentq_does(f, va):
    from scipy.optimize import brentq

    n_max = 40.0
    lo, hi = (0.0, n_max) if f > 0 else (-n_max, 0.0)
    ref = brentq(lambda n: propeller_thrust(n, va, *ARGS) - f, lo, hi, xtol=1e-14, rtol=1e-14)
    n = propeller_speed(f, va, n_max, *ARGS)
    assert n == pytest.approx(ref, rel=1e-9)
    assert propeller_thrust(n, va, *ARGS) == pytest.approx(f, rel=1e-10)


def test_propeller_speed_beyond_the_curve_is_the_speed_limit():
    big = 10 * propeller_thrust(40.0, 0.5, *ARGS)
    assert propeller_speed(big, 0.5, 40.0, *ARGS) == 40.0


def test_the_curve_calls_the_laws():
    p = PropellerCurve(0.12, KF, 40.0, KR, 0.9, 0.8, density=1025.0)
    assert p.thrust(17.5, 0.4) == propeller_thrust(17.5, 0.4, *ARGS)
    assert p.command(3.0, 0.5) == propeller_speed(3.0, 0.5, 40.0, *ARGS)


def test_rotor_lag_is_the_exact_first_order_response():
    # τ ċ = c_t − c from c = 2 to c_t = 10 with τ = 0.5 s: c(t) = 10 − 8 e^(−t/τ); two half steps
    # give one whole step (the law is exact for a held target)
    c1 = rotor_lag(2.0, 10.0, 0.3, 0.5)
    assert c1 == pytest.approx(10.0 - 8.0 * math.exp(-0.6), rel=1e-15)
    assert rotor_lag(rotor_lag(2.0, 10.0, 0.15, 0.5), 10.0, 0.15, 0.5) == pytest.approx(c1, rel=1e-14)
    assert rotor_lag(2.0, 10.0, 0.3, 0.0) == 10.0


def test_the_laws_compile_to_the_same_values():
    # compile_law (the numba path of the compiled loops) on the same code objects: the compiled
    # inversion gives the Python one's value (same operations; rel 1e-12 allows a fused multiply-add)
    from hydrokit.simulate.compiled import compile_law

    thrust = compile_law(propeller_thrust)
    speed = compile_law(propeller_speed, propeller_thrust=thrust)
    kf, kr = np.array(KF), np.array(KR)
    args = (0.12, 1025.0, -0.5, 1.0, kf, kr, 0.9, 0.8)
    for f, va in ((3.0, 0.5), (-2.0, 0.3), (3.0, 0.0)):
        assert speed(f, va, 40.0, *args) == pytest.approx(propeller_speed(f, va, 40.0, *ARGS), rel=1e-12)
    assert thrust(17.5, 0.4, *args) == pytest.approx(propeller_thrust(17.5, 0.4, *ARGS), rel=1e-12)


def _random_table(rng: np.random.Generator, repeat: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = int(rng.integers(2, 9))
    xs = np.sort(rng.normal(size=n)) * 10.0
    if repeat and n >= 3:
        j = int(rng.integers(0, n - 1))
        xs[j + 1] = xs[j]  # a repeated abscissa (np.interp takes the last of the equal points)
    ys = rng.normal(size=n) * 5.0
    # queries: the points themselves, beyond both ends, between points, and random ones
    x = np.concatenate(
        [xs, [xs[0] - 1.0, xs[-1] + 1.0, -np.inf, np.inf], (xs[:-1] + xs[1:]) / 2, rng.normal(size=20) * 12]
    )
    return xs, ys, x


@pytest.mark.parametrize("law", [table_interp, table_interp_compiled], ids=["python", "compiled"])
@pytest.mark.parametrize("repeat", [False, True], ids=["increasing", "repeated-x"])
def test_table_interp_is_np_interp(law, repeat):
    # numpy's C interpolation is the independent reference; the law follows its operation
    # order, at the ends, the points, a repeated x and between. Two implementations: numpy's C
    # may be compiled with a fused multiply-add (ARM) where the law is not, so to a few ulps of
    # the table's values rather than bit for bit (a wrong segment or weight is off by far more)
    rng = np.random.default_rng(50 + repeat)
    for _ in range(200):
        xs, ys, x = _random_table(rng, repeat)
        ref = np.interp(x, xs, ys)
        got = np.array([law(float(v), xs, ys, len(xs)) for v in x])
        np.testing.assert_allclose(got, ref, rtol=ULPS, atol=ULPS * np.abs(ys).max())


def test_table_interp_uses_only_the_first_n_points():
    # a compiled table is padded with zeros beyond its n points: they must not count
    xs, ys = np.array([0.0, 1.0, 2.0, 0.0, 0.0]), np.array([1.0, 3.0, 7.0, 0.0, 0.0])
    for law in (table_interp, table_interp_compiled):
        assert law(1.5, xs, ys, 3) == 5.0  # halfway between 3 and 7
        assert law(9.0, xs, ys, 3) == 7.0  # held at the last used point
        assert law(-9.0, xs, ys, 3) == 1.0


def test_table_curves_call_the_law_one_point_and_batch():
    a = TableCurve((-1.0, 0.0, 0.5, 1.0), (-30.0, -1.0, 2.0, 40.0))
    b = TableCurve((0.0, 1.0), (0.0, 10.0))
    x = np.array([-2.0, 0.25, 0.7, 3.0])
    curves = [a, b, a, b]
    thrusts = TableCurve.thrust_batch(curves, x, np.zeros(4))
    # the batch and the one-point method: the same law, bit for bit
    np.testing.assert_array_equal([cv.thrust(v) for v, cv in zip(x, curves, strict=True)], thrusts)
    # np.interp: a second implementation (see above), to a few ulps of the tables (40 N, 1)
    ref = [np.interp(v, cv.commands, cv.thrusts) for v, cv in zip(x, curves, strict=True)]
    np.testing.assert_allclose(thrusts, ref, rtol=ULPS, atol=ULPS * 40.0)
    back = TableCurve.command_batch(curves, thrusts, np.zeros(4))
    ref_c = [np.interp(f, cv.thrusts, cv.commands) for f, cv in zip(thrusts, curves, strict=True)]
    np.testing.assert_allclose(back, ref_c, rtol=ULPS, atol=ULPS * 1.0)
    # inside both tables the inverse returns the command (round-off of one division)
    np.testing.assert_allclose(back[1:3], x[1:3], rtol=1e-14)


def test_the_advance_speed_law_is_the_inflow_along_the_shaft() -> None:
    """V_a = (1 − w) e · (v + ω × r_p), written by the law as (1 − w)(e · v + (r_p × e) · ω): against
    np.cross on random propellers and motions, Python and compiled alike."""
    from hydrokit.model.thrusters import advance_speed_law
    from hydrokit.simulate.compiled import advance_speed_compiled

    rng = np.random.default_rng(11)
    for _ in range(50):
        e = rng.normal(size=3)
        e /= np.linalg.norm(e)
        r_p, nu, wake = rng.normal(size=3), rng.normal(size=6), rng.uniform(0.5, 1.0)
        want = wake * float(e @ (nu[:3] + np.cross(nu[3:], r_p)))
        a = np.cross(r_p, e)
        for law in (advance_speed_law, advance_speed_compiled):
            got = law(wake, *e, *a, *nu)
            assert got == pytest.approx(want, rel=1e-12, abs=1e-12)
