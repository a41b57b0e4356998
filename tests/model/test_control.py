"""PID and S-plane controllers and the autopilot (SPEC §5, LI2021 §1.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hydrokit.errors import InputError
from hydrokit.model.control import PID, Autopilot, Reference, SPlane, euler_rates, wrap_angle

M, D = 10.0, 5.0  # first-order plant m v' = -d v + P (kg, N s/m)


def run_plant(ctrl, v_d: float, t_end: float, dt: float = 0.01, v0: float = 0.0):
    """Exact ZOH discretisation of the plant; returns final v and the state history."""
    a = math.exp(-D / M * dt)
    v, s = v0, ctrl.initial_state()
    outputs = []
    for _ in range(int(round(t_end / dt))):
        P, s = ctrl.update(s, v, v_d, dt)
        outputs.append(P)
        v = v * a + (1 - a) * P / D
    return v, s, np.array(outputs)


def test_p_only_steady_state_error() -> None:
    kp = 20.0
    v, _, _ = run_plant(PID(kp=kp), v_d=1.0, t_end=20.0)
    # closed form: -d v - kp (v - v_d) = 0 -> v = kp v_d / (d + kp) = 0.8; after 50 time
    # constants the transient is e^-50, so 1e-9 is a round-off tolerance
    assert v == pytest.approx(kp / (D + kp), rel=1e-9)


def test_integral_removes_steady_state_error() -> None:
    v, _, _ = run_plant(PID(kp=20.0, ki=10.0), v_d=1.0, t_end=60.0)
    assert v == pytest.approx(1.0, rel=1e-6)


def test_anti_windup_bounds_the_integral() -> None:
    ki, umax = 5.0, 3.0  # 3 N can hold only 0.6 m/s against 5 N s/m: v_d = 1 is out of reach
    pid = PID(kp=1.0, ki=ki, output_min=-umax, output_max=umax)
    v, s, out = run_plant(pid, v_d=1.0, t_end=100.0)
    assert np.all(np.abs(out) <= umax)
    assert v == pytest.approx(umax / D, rel=1e-6)  # saturated steady state, closed form
    assert abs(ki * s.integral) <= umax + 1e-12  # the integral alone never exceeds the range
    # After the set-point drops to a reachable 0.2 m/s, the output leaves saturation at once
    # (a wound-up integral of ~40 m would keep it at +3 N for many seconds).
    P, _ = pid.update(s, v, 0.2, 0.01)
    assert P < umax


@pytest.mark.parametrize("ki", [0.5, 5.0])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_anti_windup_holds_the_output_at_either_limit(ki: float, sign: float) -> None:
    # the same out-of-reach set-point (±1 m/s, 3 N holds 0.6), forwards and backwards and with an
    # integral gain below 1: the integral stops where the output sits exactly at the limit, so
    # once the set-point is reachable again (±0.2 m/s) the output leaves saturation at once
    umax = 3.0
    pid = PID(kp=1.0, ki=ki, output_min=-umax, output_max=umax)
    v, s, out = run_plant(pid, v_d=sign, t_end=100.0)
    assert v == pytest.approx(sign * umax / D, rel=1e-6)
    assert -pid.kp * (v - sign) - ki * s.integral == pytest.approx(sign * umax, rel=1e-6)  # just at the limit
    P, _ = pid.update(s, v, 0.2 * sign, 0.01)
    assert abs(P) < umax


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_saturated_pd_controller_without_integral_is_clipped(sign: float) -> None:
    # ki = 0: no integral to stop, so saturation is a clip of −kp e (the anti-windup, which divides
    # by ki, is skipped); the integral state still sums e dt (m·s) for a later look
    pid = PID(kp=10.0, output_min=-3.0, output_max=3.0)
    out, s = pid.update(pid.initial_state(), 0.0, sign, 0.1)  # e = −sign m/s → −kp e = 10 sign N
    assert out == 3.0 * sign
    assert s.integral == pytest.approx(-0.1 * sign, rel=1e-12)


def test_derivative_on_measurement_has_no_setpoint_kick() -> None:
    pid = PID(kp=0.0, kd=100.0)
    s = pid.initial_state()
    _, s = pid.update(s, 1.0, 0.0, 0.1)
    P, _ = pid.update(s, 1.0, 5.0, 0.1)  # set-point jumps, measurement steady
    assert P == 0.0
    P, _ = pid.update(s, 1.5, 0.0, 0.1)  # measurement moves +0.5 in 0.1 s -> -kd * 5
    assert P == pytest.approx(-500.0, rel=1e-12)


def test_heading_error_wraps() -> None:
    pid = PID(kp=1.0, angle=True)
    P, _ = pid.update(pid.initial_state(), 3.1, -3.1, 0.1)
    # e = wrap(6.2) = 6.2 - 2 pi
    assert P == pytest.approx(-(6.2 - 2 * math.pi), rel=1e-12)
    assert wrap_angle(math.pi + 0.1) == pytest.approx(-math.pi + 0.1)


@given(st.floats(-50, 50), st.floats(-50, 50))
def test_s_plane_output_bounded_and_odd(e: float, de: float) -> None:
    k1, k2 = 1.3, 0.7
    u = float(SPlane.surface(e, de, k1, k2))
    u_neg = float(SPlane.surface(-e, -de, k1, k2))
    assert -1.0 <= u <= 1.0
    assert u == pytest.approx(-u_neg, abs=1e-15)
    x = k1 * e + k2 * de
    if abs(x) < 30:  # the printed form (SPEC §5), evaluated directly, where it does not overflow
        assert u == pytest.approx(2 / (1 + math.exp(-x)) - 1, abs=1e-12)


def test_s_plane_scaled_to_actuator_range() -> None:
    sp = SPlane(k1=2.0, k2=0.0, scale=50.0)
    P, _ = sp.update(sp.initial_state(), 10.0, 0.0, 0.1)
    assert -50.0 < P < -49.0  # far from the set-point: close to the full range, never beyond
    P, _ = sp.update(sp.initial_state(), 0.1, 0.0, 0.1)
    assert P == pytest.approx(-50.0 * math.tanh(0.1), rel=1e-12)


def test_autopilot_tau_layout() -> None:
    ap = Autopilot(speed=PID(kp=10), depth=PID(kp=20), heading=PID(kp=5, angle=True))
    eta = [0, 0, 2.0, 0, 0, 0.5]
    nu = [0.2, 0, 0, 0, 0, 0]
    tau, _ = ap.update(ap.initial_state(), Reference(speed=0.5, depth=3.0, heading=0.0), eta, nu, 0.1)
    # [P_speed, 0, P_depth, 0, 0, P_heading] (LI2021 §1.4), P = -kp e
    np.testing.assert_allclose(tau, [3.0, 0, 20.0, 0, 0, -2.5], rtol=1e-12)


def test_autopilot_roll_and_pitch_hold() -> None:
    ap = Autopilot(
        speed=PID(kp=1),
        depth=PID(kp=1),
        heading=PID(kp=1, angle=True),
        roll=PID(kp=50, angle=True),
        pitch=SPlane(k1=2, k2=0, scale=30, angle=True),
    )
    eta = [0, 0, 0, 0.1, -0.2, 0]
    tau, _ = ap.update(ap.initial_state(), Reference(0, 0, 0), eta, np.zeros(6), 0.1)
    assert tau[3] == pytest.approx(-5.0, rel=1e-12)  # -kp phi
    assert tau[4] == pytest.approx(-30 * math.tanh(-0.2), rel=1e-12)  # S-plane, e = theta


@pytest.mark.parametrize("with_pitch", [False, True])
def test_each_loop_keeps_its_own_integral(with_pitch: bool) -> None:
    # loops are stored in the order speed, depth, heading, roll, pitch: each integral sums its
    # own error (rad·s here), step after step, whatever other loops exist
    pid = PID(kp=0.0, ki=1.0, angle=True)
    ap = Autopilot(PID(kp=1), PID(kp=1), PID(kp=1, angle=True), roll=pid, pitch=pid if with_pitch else None)
    eta = [0, 0, 0, 0.1, -0.2, 0]  # φ = 0.1 rad, θ = −0.2 rad
    s = ap.initial_state()
    for _ in range(3):
        tau, s = ap.update(s, Reference(0, 0, 0), eta, np.zeros(6), 0.5)
    assert s.loops[3].integral == pytest.approx(3 * 0.5 * 0.1, rel=1e-12)
    assert tau[3] == pytest.approx(-1.0 * 3 * 0.5 * 0.1, rel=1e-12)
    assert s.loops[4].integral == pytest.approx(3 * 0.5 * -0.2 if with_pitch else 0.0, rel=1e-12)
    assert tau[4] == pytest.approx(0.3 if with_pitch else 0.0, rel=1e-12)


def test_euler_rates_level_flight() -> None:
    zdot, _, _, psidot = euler_rates([0, 0, 0, 0, 0, 0], [1, 0, 0.3, 0, 0, 0.2])
    assert zdot == pytest.approx(0.3) and psidot == pytest.approx(0.2)


@given(
    angles=st.tuples(st.floats(-3.1, 3.1), st.floats(-1.5, 1.5)),
    nu=st.lists(st.floats(-2.0, 2.0), min_size=6, max_size=6),
)
def test_euler_rates_are_the_kinematics_j_of_eta_times_nu(angles, nu) -> None:
    # second method: core's J(η) (Fossen 2011 eq. 2.40, a matrix product) against the scalar
    # rows the autopilot uses: ż is row 3 of R(Θ) v, and φ̇, θ̇, ψ̇ are T(Θ) ω
    from hydrokit.core.kinematics import J_euler

    phi, theta = angles
    eta = np.array([0.0, 0.0, 0.0, phi, theta, 0.7])
    want = J_euler(eta) @ np.asarray(nu)
    got = euler_rates(eta, nu)
    np.testing.assert_allclose(got, want[[2, 3, 4, 5]], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_euler_rates_at_gimbal_lock_join_the_rates_just_beside_it(side: float) -> None:
    # at θ = ±90° the zyx rates divide by cos θ = 0; the guard holds |cos θ| at its smallest
    # value, so the rates there are those of the nearest unguarded pitch (cos θ just above
    # the guard), not a jump. Second method: the formula's own value at that nearby pitch
    nu = [0.0, 0.0, 0.0, 0.0, 0.2, 0.1]  # q, r in rad/s
    phi = 0.3
    _, phid, _, psid = euler_rates([0, 0, 0, phi, side * math.pi / 2, 0], nu)
    near = side * (math.pi / 2 - 1.000001e-9)  # cos = 1.000001e-9, outside the guard
    _, phid_n, _, psid_n = euler_rates([0, 0, 0, phi, near, 0], nu)
    assert psid == pytest.approx(psid_n, rel=1e-5)
    assert phid == pytest.approx(phid_n, rel=1e-5)
    assert abs(psid) > 1e7  # the singularity shows as a huge rate, not a finite wrong one


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"kp": "fast"}, "PID kp = 'fast': expected a number"),
        ({"kp": 1.0, "ki": -2}, "PID ki = -2.0: expected a number ≥ 0"),
        ({"kp": 1.0, "output_min": 5, "output_max": 1}, "output_min < output_max"),
    ],
)
def test_bad_gains_rejected(kw: dict, match: str) -> None:
    with pytest.raises(InputError, match=match):
        PID(**kw)


def test_bad_s_plane_scale_rejected() -> None:
    with pytest.raises(InputError, match="S-plane scale = 0.0: expected a positive"):
        SPlane(k1=1, k2=1, scale=0)
    # a negative gain turns the S-surface around: the controller would push the error up
    for k in ("k1", "k2"):
        with pytest.raises(InputError, match=rf"S-plane {k} = -1.0: expected a number ≥ 0"):
            SPlane(**{"k1": 1.0, "k2": 1.0, "scale": 1.0, k: -1.0})
    assert SPlane(k1=0.0, k2=0.0, scale=1.0).k2 == 0.0  # zero is allowed (no rate term)


# --------------------------------------------------------------------------- closed loop
# A plant written here independently of hydrokit's vehicle model: diagonal mass and linear
# damping (no Coriolis, no restoring), zyx kinematics. Lingyun-sized numbers (LI2021 Table 1
# mass 520 kg; the damping values are round numbers of our choosing).
from hydrokit.model.guidance import Path  # noqa: E402
from hydrokit.model.thrusters import Thruster, ThrusterSet  # noqa: E402
from hydrokit.simulate.closed_loop import run_closed_loop  # noqa: E402

PLANT_M = np.array([560.0, 700.0, 600.0, 40.0, 60.0, 70.0])
PLANT_D = np.array([150.0, 300.0, 300.0, 80.0, 100.0, 60.0])


def plant(t: float, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
    phi, th, psi = x[3:6]
    cf, sf, ct, st, cp, sp = (math.cos(phi), math.sin(phi), math.cos(th), math.sin(th), math.cos(psi), math.sin(psi))
    R = np.array(
        [
            [cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st],
            [sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf],
            [-st, ct * sf, ct * cf],
        ]
    )
    Tm = np.array([[1, sf * st / ct, cf * st / ct], [0, cf, -sf], [0, sf / ct, cf / ct]])
    nu = x[6:]
    return np.concatenate([R @ nu[:3], Tm @ nu[3:], (tau - PLANT_D * nu) / PLANT_M])


def lingyun_set(tc: float = 0.0) -> ThrusterSet:
    pos = [(-0.6, -0.35, 0), (-0.6, 0.35, 0), (0, -0.3, -0.4), (0, 0.3, -0.4)]
    dirs = [(1, 0, 0), (1, 0, 0), (0, 0, -1), (0, 0, -1)]
    return ThrusterSet(
        tuple(
            Thruster(f"T{i}", p, d, max_thrust=150, min_thrust=-120, time_constant=tc)
            for i, (p, d) in enumerate(zip(pos, dirs))
        )
    )


def test_closed_loop_p_speed_matches_closed_form() -> None:
    # Straight leg along +x, P-only speed loop: steady u = kp u_d / (d + kp) as for the
    # single-axis plant above, now through guidance, allocation and thrusters.
    kp, u_d = 300.0, 0.4
    ap = Autopilot(speed=PID(kp=kp), depth=PID(kp=200, kd=400), heading=PID(kp=100, kd=100, angle=True))
    path = Path(points=[[0, 0, 5], [500, 0, 5]], speeds=[u_d])
    res = run_closed_loop(plant, lingyun_set(), ap, path, [0, 0, 5, 0, 0, 0], np.zeros(6), duration=60.0, dt=0.05)
    # 60 s = 26 time constants of m/(d+kp): transient e^-26; 1e-9 covers round-off
    assert res.nu[-1, 0] == pytest.approx(kp * u_d / (PLANT_D[0] + kp), rel=1e-9)
    assert np.all(res.thrust <= 150 + 1e-9) and np.all(res.thrust >= -120 - 1e-9)


def test_closed_loop_reaches_waypoints_within_limits() -> None:
    ap = Autopilot(
        speed=PID(kp=600, ki=60, output_min=-200, output_max=200),
        depth=PID(kp=400, ki=20, kd=800, output_min=-200, output_max=200),
        heading=PID(kp=150, ki=2, kd=250, output_min=-60, output_max=60, angle=True),
    )
    path = Path(
        points=[[0, 0, 2], [15, 0, 4], [15, 15, 4], [0, 15, 6]],
        speeds=[0.5, 0.5, 0.5],
        acceptance_radius=1.0,
        lookahead=4.0,
    )
    ts = lingyun_set(tc=0.3)
    res = run_closed_loop(
        plant, ts, ap, path, [0, 0, 2, 0, 0, 0], np.zeros(6), duration=200.0, dt=0.05, stop_when_done=True
    )
    m = res.metrics(ts)
    assert m["completed"], m["waypoint_times"]
    assert all(np.diff([t for t in m["waypoint_times"]]) > 0)
    # a 90 deg turn with 4 m lookahead cuts the corner by about a metre (measured 0.61 m)
    assert m["cross_track_max"] < 1.5
    assert np.all(res.thrust <= ts.f_max + 1e-9) and np.all(res.thrust >= ts.f_min - 1e-9)
    # rotor lag: the reached command never jumps more than the lag allows in one step
    step = np.abs(np.diff(res.command, axis=0))
    assert np.all(step <= (270.0 * (1 - math.exp(-0.05 / 0.3))) + 1e-9)
    # repeatable: a second run from the same inputs gives identical arrays
    res2 = run_closed_loop(
        plant, ts, ap, path, [0, 0, 2, 0, 0, 0], np.zeros(6), duration=200.0, dt=0.05, stop_when_done=True
    )
    np.testing.assert_array_equal(res.eta, res2.eta)


# ------------------------------------------------- the vehicle model as the closed loop sees it
from hydrokit.io.vehicle import parse_vehicle  # noqa: E402
from hydrokit.simulate.closed_loop import rk4_step  # noqa: E402
from hydrokit.simulate.compiled import make_dynamics  # noqa: E402


def lingyun_like(z_g: float = 0.10, damped: bool = True):
    """LI2021 Table 1 mass and inertia with diagonal added mass and damping (W = B)."""
    m = 519.798
    doc = {
        "gravity": 9.81,
        "fluid": {"density": 1000.0},
        "mass": m,
        "volume": m / 1000.0,
        "inertia": [30.717279, 47.148837, 65.763013],
        "center_of_gravity": [0, 0, z_g],
        "center_of_buoyancy": [0, 0, 0],
        "added_mass": [58.7, 381.5, 117.4, 10, 20.9, 8.9],
        "linear_damping": [20.0, 40, 40, 20, 20, 20] if damped else [0] * 6,
        "quadratic_damping": [108.8, 629.5, 1110, 4385, 209, 300] if damped else [0] * 6,
    }
    return parse_vehicle(doc, "lingyun-like")


def test_loop_dynamics_steady_surge_closed_form() -> None:
    f = make_dynamics(lingyun_like())
    x = np.zeros(12)
    tau = np.array([30.0, 0, 0, 0, 0, 0])  # LI2021 open-loop surge force
    for _ in range(2000):  # 200 s at 0.1 s; the time constant near 0.5 m/s is ~5 s
        x = rk4_step(f, 0.0, x, 0.1, u=tau)
    # D_L u + D_Q u^2 = X  ->  u = (-D_L + sqrt(D_L^2 + 4 D_Q X)) / (2 D_Q)
    u = (-20 + math.sqrt(20**2 + 4 * 108.8 * 30)) / (2 * 108.8)
    assert x[6] == pytest.approx(u, rel=1e-6)  # converged to 1e-6 (transient ~e^-40)
    assert x[0] == pytest.approx(x[6] * 200, rel=0.05)  # travelled ~u t (start-up lag)


def test_loop_dynamics_restoring_moment() -> None:
    v = lingyun_like()
    f = make_dynamics(v)
    phi = 0.2
    x = np.zeros(12)
    x[3] = phi
    xdot = f(0.0, x, np.zeros(6))
    # Fossen 2011 eq. 4.6 with W = B, r_b = 0: g(eta) = [0, 0, 0, W z_g cos(theta) sin(phi), 0, 0]
    g = np.array([0, 0, 0, v.weight * 0.10 * math.sin(phi), 0, 0])
    expected = np.linalg.solve(v.M, -g)
    np.testing.assert_allclose(xdot[6:], expected, rtol=1e-12, atol=1e-15)


def test_loop_dynamics_conserves_energy_without_damping() -> None:
    # C(nu) is skew-symmetric: with no damping, no forces and W = B at the same point, kinetic
    # energy 1/2 nu^T M nu is conserved.
    v = lingyun_like(z_g=0.0, damped=False)
    f = make_dynamics(v)
    x = np.zeros(12)
    x[6:] = [0.4, 0.1, -0.2, 0.05, -0.03, 0.1]
    e0 = 0.5 * x[6:] @ v.M @ x[6:]
    for _ in range(500):
        x = rk4_step(f, 0.0, x, 0.01, u=np.zeros(6))
    # RK4 at h = 0.01 s over 5 s: energy drift far below 1e-6 relative
    assert 0.5 * x[6:] @ v.M @ x[6:] == pytest.approx(e0, rel=1e-6)


def test_control_callback_matches_closed_loop_driver() -> None:
    # Second method: the same autopilot as a tau(t, eta, nu) callback in plain RK4 loops.
    from hydrokit.simulate.closed_loop import control_callback

    ap = Autopilot(
        speed=PID(kp=600, ki=60, output_min=-200, output_max=200),
        depth=PID(kp=400, ki=20, kd=800, output_min=-200, output_max=200),
        heading=PID(kp=150, kd=250, output_min=-60, output_max=60, angle=True),
    )
    path = Path(points=[[0, 0, 2], [15, 0, 4], [15, 15, 4]], speeds=[0.5, 0.5])
    ts, dt = lingyun_set(), 0.05
    ref = run_closed_loop(plant, ts, ap, path, [0, 0, 2, 0, 0, 0], np.zeros(6), duration=30.0, dt=dt)
    x0 = np.array([0, 0, 2, 0, 0, 0] + [0] * 6, dtype=float)

    # (a) a driver that asks for tau once per step and holds it (what run_closed_loop does,
    # rotors without lag): identical arithmetic, so agreement to round-off (1e-9 m)
    cb = control_callback(ts, ap, path, period=dt)
    x = x0.copy()
    for k in range(600):
        x = rk4_step(plant, k * dt, x, dt, u=cb(k * dt, x[:6], x[6:]))
    np.testing.assert_allclose(x[:6], ref.eta[-1], atol=1e-9)

    # (b) a driver that calls tau inside every RK4 stage: the last stage of a step falls on
    # the next sampling instant and already sees the next sample, a 1/6-weight O(h) change
    # per step; over 30 s that moves the vehicle by well under a millimetre (measured 8e-5 m).
    cb = control_callback(ts, ap, path, period=dt)
    f = lambda t, x, _u: plant(t, x, cb(t, x[:6], x[6:]))  # noqa: E731
    x = x0.copy()
    for k in range(600):
        x = rk4_step(f, k * dt, x, dt, u=np.zeros(6))
    np.testing.assert_allclose(x[:6], ref.eta[-1], atol=1e-3)


def test_mission_metrics_closed_form() -> None:
    # A hand-made run: the vehicle moves along y = 0.5 m beside a path on y = 0 with two
    # thrusters at a constant 20 N; metrics by hand.
    from hydrokit.simulate.closed_loop import ClosedLoopResult, mission_metrics

    n, h = 101, 0.1
    t = np.arange(n) * h
    eta = np.zeros((n, 6))
    eta[:, 0] = np.linspace(0, 5, n)
    eta[:, 1] = 0.5
    path = Path(points=[[0, 0, 0], [10, 0, 0]], speeds=[0.5])
    ts = ThrusterSet(
        (Thruster("A", (0, 0, 0), (1, 0, 0), 50, diameter=0.1), Thruster("B", (0, 0, 0), (1, 0, 0), 50, diameter=0.1)),
        density=1000.0,
    )
    thrust = np.full((n, 2), 20.0)
    limited = np.zeros(n, dtype=bool)
    limited[:10] = True
    res = ClosedLoopResult(
        time=t,
        eta=eta,
        nu=np.zeros((n, 6)),
        reference=np.zeros((n, 3)),
        tau_demand=np.zeros((n, 6)),
        command_demand=thrust,
        command=thrust,
        thrust_demand=thrust,
        thrust=thrust,
        limited=limited,
        leg=np.ones(n, dtype=int),
        waypoint_times=[None],
        thruster_names=["A", "B"],
        dt=h,
        path=path,
    )
    m = mission_metrics(res, ts)
    assert m["cross_track_rms"] == pytest.approx(0.5, rel=1e-12)
    assert m["cross_track_max"] == pytest.approx(0.5, rel=1e-12)
    assert not m["completed"]
    assert m["saturation_time"] == pytest.approx(1.0, rel=1e-12)
    # actuator disk: P = f^1.5 / sqrt(2 rho A), A = pi 0.05^2; 2 thrusters x 101 samples x h
    P = 20.0**1.5 / math.sqrt(2 * 1000.0 * math.pi * 0.05**2)
    assert m["thruster_energy"] == pytest.approx(2 * P * n * h, rel=1e-12)
    assert m["thrust_impulse"] == pytest.approx(2 * 20.0 * n * h, rel=1e-12)
