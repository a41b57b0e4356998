"""Pins the closed-loop speed refactor to the per-thruster scalar definitions.

ThrusterSet.thrust / command_for_thrust evaluate the thrusters in groups (one np.interp per
distinct table, precomputed propeller constants with the K_T polynomial and the regula-falsi
inversion written inline). Each result must equal — bit for bit — what the curve's own scalar
``thrust`` / ``command`` give, clipped as the ThrusterSet documents.
"""

from __future__ import annotations

import numpy as np
import pytest

from hydrokit.model.allocation import Allocator, allocate_constrained
from hydrokit.model.control import PID, Autopilot, Reference, SPlane, euler_rates
from hydrokit.model.guidance import Path
from hydrokit.model.thrusters import IdealCurve, PropellerCurve, TableCurve, Thruster, ThrusterSet

TABLE = TableCurve((-1.0, -0.5, -0.1, 0.0, 0.1, 0.5, 1.0), (-40.0, -18.0, -2.0, 0.0, 2.5, 22.0, 50.0))
TABLE2 = TableCurve((1100.0, 1300.0, 1500.0, 1700.0, 1900.0), (-30.0, -10.0, 0.0, 12.0, 36.0))
PROP = PropellerCurve(
    diameter=0.12,
    kt_forward=(-0.05, -0.1, -0.25, 0.42),
    kt_reverse=(0.02, 0.05, 0.3, 0.3),
    max_speed=40.0,
    thrust_loss_forward=0.9,
    thrust_loss_reverse=0.8,
)
PROP_LINEAR = PropellerCurve(diameter=0.2, kt_forward=(-0.3, 0.35), max_speed=25.0)  # padded to a cubic
PROP_QUARTIC = PropellerCurve(diameter=0.1, kt_forward=(0.01, -0.05, -0.1, -0.25, 0.4), max_speed=50.0)


def _set() -> ThrusterSet:
    # an equal copy of TABLE2 (a separate object), and each kind more than once
    copy2 = TableCurve(TABLE2.commands, TABLE2.thrusts)
    curves = [TABLE, TABLE2, TABLE, PROP, PROP_LINEAR, PROP_QUARTIC, IdealCurve(), PROP, copy2]
    rng = np.random.default_rng(1)
    ths = []
    for i, cv in enumerate(curves):
        d = rng.normal(size=3)
        ths.append(
            Thruster(
                name=f"T{i}",
                position=tuple(rng.normal(size=3)),  # type: ignore[arg-type]
                direction=tuple(d),  # type: ignore[arg-type]
                max_thrust=35.0 if i != 6 else 20.0,
                min_thrust=-25.0 if i != 6 else -5.0,
                wake_fraction=0.1 * (i % 3),
                curve=cv,
            )
        )
    return ThrusterSet(tuple(ths), density=1000.0)


def _advance_speeds(rng: np.random.Generator, m: int) -> np.ndarray:
    va = rng.uniform(-3.0, 3.0, m)
    kind = rng.integers(0, 4, m)
    va[kind == 0] = 0.0  # bollard pull: closed form
    va[kind == 1] *= 1e-4  # small inflow
    return va


def test_grouped_thrust_matches_scalar_curves() -> None:
    ts = _set()
    rng = np.random.default_rng(2)
    m = len(ts)
    span = np.maximum(np.abs(ts.command_min), np.abs(ts.command_max))
    for _ in range(400):
        c = rng.uniform(-1.3, 1.3, m) * span  # beyond the limits: clipped
        c[rng.random(m) < 0.1] = 0.0
        va = _advance_speeds(rng, m)
        got = ts.thrust(c, va)
        cc = np.clip(c, ts.command_min, ts.command_max)
        want = np.clip([cv.thrust(cc[i], va[i]) for i, cv in enumerate(ts.curves)], ts.f_min, ts.f_max)
        np.testing.assert_array_equal(got, want)


def test_grouped_command_matches_scalar_curves() -> None:
    ts = _set()
    rng = np.random.default_rng(3)
    m = len(ts)
    span = np.maximum(np.abs(ts.f_min), np.abs(ts.f_max))
    for _ in range(400):
        f = rng.uniform(-1.3, 1.3, m) * span  # saturating demands and reverse thrust
        f[rng.random(m) < 0.1] = 0.0
        va = _advance_speeds(rng, m)
        got = ts.command_for_thrust(f, va)
        ff = np.clip(f, ts.f_min, ts.f_max)
        want = [cv.command(ff[i], va[i]) for i, cv in enumerate(ts.curves)]
        np.testing.assert_array_equal(got, want)
    # no advance speed given = bollard pull
    f = rng.uniform(-1.0, 1.0, m) * span
    np.testing.assert_array_equal(ts.command_for_thrust(f), ts.command_for_thrust(f, np.zeros(m)))
    np.testing.assert_array_equal(ts.thrust(f), ts.thrust(f, np.zeros(m)))


@pytest.mark.parametrize("curve", [PROP, PROP_LINEAR, PROP_QUARTIC])
def test_propeller_fast_paths_match_reference(curve: PropellerCurve) -> None:
    rng = np.random.default_rng(4)
    lo, hi = curve.limits()
    for _ in range(3000):
        va = float(rng.choice([0.0, rng.uniform(-4, 4), rng.uniform(-1e-3, 1e-3)]))
        f = float(rng.uniform(1.2 * lo, 1.2 * hi))
        n = float(rng.uniform(-1.2, 1.2) * curve.max_speed)
        assert PropellerCurve.command_batch([curve], np.array([f]), np.array([va]))[0] == curve.command(f, va)
        assert PropellerCurve.thrust_batch([curve], np.array([n]), np.array([va]))[0] == curve.thrust(n, va)


def test_table_batch_with_mixed_tables() -> None:
    curves = [TABLE, TABLE2, TABLE, TABLE2]
    c = np.array([-2.0, 1000.0, 0.33, 1650.0])
    np.testing.assert_array_equal(
        TableCurve.thrust_batch(curves, c, np.zeros(4)), [cv.thrust(x) for cv, x in zip(curves, c)]
    )
    f = np.array([-50.0, 40.0, 3.3, -7.0])
    np.testing.assert_array_equal(
        TableCurve.command_batch(curves, f, np.zeros(4)), [cv.command(x) for cv, x in zip(curves, f)]
    )


def test_allocator_matches_allocate_constrained() -> None:
    ts = _set()
    T = ts.configuration_matrix()
    alloc = Allocator(T, ts.f_min, ts.f_max)
    rng = np.random.default_rng(5)
    n_sat = 0
    for _ in range(60):
        tau = rng.normal(size=6) * rng.choice([1.0, 30.0, 200.0])
        f, limited = alloc(tau)
        if limited:
            n_sat += 1
            want = allocate_constrained(T, tau, ts.f_min, ts.f_max, dof_weights=alloc.Q).thrust
            np.testing.assert_array_equal(f, want)
        else:  # the law's ordered sum (model.allocation.pinv_allocate) against numpy's product: round-off
            np.testing.assert_allclose(f, alloc.P @ tau, rtol=0, atol=1e-14 * np.max(np.abs(alloc.P @ tau)))
    assert n_sat > 5


def test_guidance_and_autopilot_match_array_formulas() -> None:
    path = Path(
        np.array([[0.0, 0.0, 1.0], [20.0, 5.0, 3.0], [20.0, 5.0, 8.0], [0.0, 30.0, 8.0]]), np.array([1.0, 0.5, 1.2])
    )
    rng = np.random.default_rng(6)
    g = path.initial_state()
    for _ in range(300):
        p = rng.uniform(-5, 35, 3)
        ref, g2 = path.update(g, p, vehicle_heading=float(rng.uniform(-3, 3)))
        # reference: the leg arithmetic with numpy arrays, as the definition states it
        k = g2.leg
        if k <= path.n_legs:
            a, b = path.points[k - 1], path.points[k]
            d = b - a
            L = float(np.linalg.norm(d))
            s = float((p - a) @ d) / (L * L)
            s_ahead = min(max(s + path.lookahead * abs(d[2]) / (L * L), 0.0), 1.0)
            # two implementations: numpy's @ and norm round differently per CPU (BLAS/SIMD kernel)
            # from the law's scalar sums, so to round-off (a few ulps of s, times |d_z| ≤ 5 m), not
            # bit for bit; the depths are 1–8 m
            assert ref.depth == pytest.approx(float(a[2] + s_ahead * d[2]), rel=1e-13)
        g = g2 if rng.random() < 0.5 else path.initial_state()
    ap = Autopilot(
        speed=PID(200.0, 10.0, 5.0, -100.0, 100.0),
        depth=SPlane(1.0, 2.0, 80.0),
        heading=PID(50.0, 1.0, 10.0, -30.0, 30.0, angle=True),
        roll=SPlane(2.0, 1.0, 10.0, angle=True),
        pitch=PID(20.0, 0.0, 3.0, angle=True),
    )
    s = ap.initial_state()
    for _ in range(100):
        eta, nu = rng.normal(size=6), rng.normal(size=6)
        ref = Reference(*rng.normal(size=5))
        tau, s = ap.update(s, ref, eta, nu, 0.05)
        zdot, phidot, _, _ = euler_rates(eta, nu)
        e = float(eta[2] - ref.depth)
        want = -80.0 * float(SPlane.surface(e, zdot, 1.0, 2.0))
        assert tau[2] == want
        assert tau[1] == 0.0
