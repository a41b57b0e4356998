"""The manoeuvre runner against independent integrations and closed forms.

Models: Nomoto's first-order yaw model T ṙ + r = K δ with constant surge speed (12-state form,
so the runner sees what it sees with a vehicle), and Norrbin's course-unstable variant
T ṙ − r + n₃ r³ = K δ, whose steady states are known in closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.manoeuvre import metrics as mm
from hydrokit.manoeuvre import run as M

K, T, U, L = 0.2, 5.0, 2.0, 4.0
SERVO = (np.array([0.6]), np.array([np.inf]), np.array([0.0]))


def nomoto(n1=1.0, n3=0.0, pitch=False):
    """ẋ of a constant-speed vehicle steered by T ṙ + n1 r + n3 r³ = K δ (or the pitch analogue)."""

    def f(t, x, tau, d):
        xd = np.zeros(12)
        u = x[6]
        psi, th = x[5], x[4]
        xd[0] = u * math.cos(psi) * math.cos(th)
        xd[1] = u * math.sin(psi) * math.cos(th)
        xd[2] = -u * math.sin(th)
        xd[6] = (tau[0] - 10 * u * abs(u)) / 50.0  # steady at U = 2 m/s under 40 N
        i = 10 if pitch else 11
        a = 4 if pitch else 5
        xd[a] = x[i]
        xd[i] = (K * d[0] - n1 * x[i] - n3 * x[i] ** 3) / T
        return xd

    return f


def fly(m, f=None, planar=True, **kw):
    kw.setdefault("dt", 0.02)
    t, x, d, logic, w = M.fly_manoeuvre(f or nomoto(), m, 0, SERVO, tau=(40, 0, 0, 0, 0, 0), length=L, **kw)
    return M.measure(
        m,
        t,
        x,
        d,
        logic,
        vehicle="nomoto",
        surface_names=("rudder",),
        surface="rudder",
        reference_length=L,
        planar=planar,
        warnings=w,
    )


def test_turning_circle_against_solve_ivp():
    from scipy.integrate import solve_ivp

    delta = 0.3
    res = fly(M.turning_circle(delta))
    m = res.metrics

    def rhs(t, y):  # x, y, ψ, r with the rudder held from the execute
        return [U * math.cos(y[2]), U * math.sin(y[2]), y[3], (K * delta - y[3]) / T]

    hit = [lambda t, y, a=a: y[2] - a for a in (math.pi / 2, math.pi)]
    sol = solve_ivp(rhs, (0, 100), [0, 0, 0, 0], events=hit, rtol=1e-11, atol=1e-11)
    (t90,), (t180,) = sol.t_events
    (y90,), (y180,) = sol.y_events
    # RK4 at dt = 0.02 s against DOP853-grade tolerances: global error ~ (dt/T)^4 ≈ 1e-10 relative;
    # the metrics interpolate linearly between samples 0.02 s apart on a curve of radius 33 m:
    # ≈ R (r dt)²/8 ≈ 1e-5 m → rtol 1e-5
    assert m["advance"] == pytest.approx(y90[0], rel=1e-5)
    assert m["transfer"] == pytest.approx(y90[1], rel=1e-5)
    assert m["tactical_diameter"] == pytest.approx(y180[1], rel=1e-5)
    assert m["time_to_90_deg"] == pytest.approx(t90, rel=1e-5)
    # steady circle: radius U / (K δ) in closed form
    assert m["steady_turning_diameter"] == pytest.approx(2 * U / (K * delta), rel=1e-4)
    assert m["steady_yaw_rate"] == pytest.approx(K * delta, rel=1e-4)
    assert m["steady_speed"] == pytest.approx(U, rel=1e-4)
    assert m["drift_angle_deg"] == pytest.approx(0.0, abs=1e-9)
    assert res.problem is None and res.time[0] < 0 and res.eta[np.searchsorted(res.time, 0), 0] == 0
    d = res.to_dict()
    assert set(d["turning_circle"]) >= {
        "advance",
        "transfer",
        "tactical_diameter",
        "steady_turning_diameter",
        "steady_speed",
        "steady_yaw_rate",
        "drift_angle_deg",
        "time_to_90_deg",
    }
    assert [r["criterion"] for r in d["imo_criteria"]] == ["advance ≤ 4.5 L", "tactical diameter ≤ 5 L"]
    assert res.columns[-1] == "rudder" and res.array().shape[1] == 14


def test_zigzag_against_solve_ivp():
    from scipy.integrate import solve_ivp

    A = B = math.radians(10)
    dt = 0.02
    res = fly(M.zigzag(A, B), dt=dt)
    m = res.metrics
    # the reference: switch exactly at ψ = ±B (solve_ivp events), peaks at r = 0
    t0, y, cmd, ex, peaks = 0.0, [0.0, 0.0], A, [0.0], []
    while len(ex) < 4:
        lvl = B if cmd > 0 else -B
        hit = lambda t, y, lvl=lvl: y[0] - lvl  # noqa: E731
        hit.terminal = True
        top = lambda t, y: y[1]  # noqa: E731
        s = solve_ivp(
            lambda t, y, c=cmd: [y[1], (K * c - y[1]) / T], (t0, t0 + 100), y, events=[hit, top], rtol=1e-11, atol=1e-12
        )
        peaks += [yy[0] for tt, yy in zip(s.t_events[1], s.y_events[1]) if tt > t0 + 1e-9]
        t0, y, cmd = s.t[-1], s.y[:, -1], -cmd
        ex.append(t0)
    # the runner checks the heading once per step, so each execute comes up to one step late
    # (dt = 0.02 s); that lag shifts an overshoot by at most |r|·dt·(1 + …) ≈ 0.04°·… → abs 0.06°
    assert m["initial_turning_time"] == pytest.approx(ex[1], abs=dt + 1e-9)
    assert m["first_overshoot_deg"] == pytest.approx(math.degrees(peaks[0] - B), abs=0.06)
    assert m["second_overshoot_deg"] == pytest.approx(math.degrees(-peaks[1] - B), abs=0.06)
    assert m["period"] == pytest.approx(ex[3] - ex[1], abs=3 * dt)
    assert res.problem is None
    assert res.deflection[res.time >= 0][0, 0] == pytest.approx(A)  # instant: no lag or rate limit


def test_vertical_zigzag_mirrors_the_horizontal_one():
    A = B = math.radians(10)
    h = fly(M.zigzag(A, B)).metrics
    v = fly(M.vertical_zigzag(A, B), nomoto(pitch=True)).metrics
    for key in ("first_overshoot_deg", "second_overshoot_deg", "initial_turning_time", "period"):
        assert v[key] == pytest.approx(h[key], rel=1e-9)  # the same equation on another angle
    assert v["max_depth_change"] > 0.1


def test_spirals_and_pull_out_on_a_course_unstable_model():
    n3 = 100.0  # Norrbin: steady −r + n3 r³ = K δ has three roots for |K δ| < 2/(3√(3 n3))
    f = nomoto(-1.0, n3)
    loop = 2 / (3 * math.sqrt(3 * n3)) / K  # rad: half-width of the hysteresis loop, closed form
    direct = fly(M.spiral("direct"), f, duration=6000, dt=0.1).metrics
    assert direct["course_stable"] is False
    steps = sorted({abs(p["deflection_deg"]) for p in direct["points"]})
    inside = max(s for s in steps if s < math.degrees(loop))
    assert direct["loop_width_deg"] == pytest.approx(inside, abs=1e-6)
    for p in direct["points"]:  # every steady rate solves the cubic (rtol of the steady test)
        r, d = p["yaw_rate"], math.radians(p["deflection_deg"])
        assert -r + n3 * r**3 == pytest.approx(K * d, abs=2e-4)
    reverse = fly(M.spiral("reverse"), f, duration=3000, dt=0.1).metrics
    assert reverse["course_stable"] is False
    pull = fly(M.pull_out(0.3), f, duration=3000, dt=0.1).metrics
    # released, the rate settles on the stable roots ±1/√n3 of −r + n3 r³ = 0
    assert pull["residual_yaw_rate"] == pytest.approx([1 / math.sqrt(n3), -1 / math.sqrt(n3)], rel=1e-3)
    assert pull["course_stable"] is False


def test_stable_model_direct_spiral():
    direct = fly(M.spiral("direct"), dt=0.1).metrics
    assert direct["course_stable"] is True and direct["loop_width_deg"] == 0.0
    for p in direct["points"]:  # steady r = K δ
        assert p["yaw_rate"] == pytest.approx(K * math.radians(p["deflection_deg"]), abs=1e-4)


def test_stable_model_reverse_spiral_and_pull_out():
    assert fly(M.spiral("reverse"), dt=0.1).metrics["course_stable"] is True
    pull = fly(M.pull_out(0.3), dt=0.05).metrics
    assert pull["course_stable"] is True
    assert pull["sides"][0]["time_to_half"] == pytest.approx(T * math.log(2), rel=0.02)  # e^(−t/T) = ½


def biased(f, bias):
    """``f`` with a constant yaw acceleration ``bias``/T (rad/s²): the steady rate at δ = 0 of the
    stable model is bias/n1 (a propeller's torque that rolls an AUV into a slow turn)."""

    def g(t, x, tau, d):
        xd = f(t, x, tau, d)
        xd[11] += bias / T
        return xd

    return g


def test_pull_out_of_a_biased_but_stable_model_is_course_stable():
    """Both sides settle on the same residual, bias/n1 in closed form (T ṙ + r = K δ + b), so the
    model is course stable though neither residual is zero; the course-unstable model with the
    same bias settles on two different residuals (the stable roots of −r + n3 r³ = b) and is not."""
    bias = 0.004  # rad/s at n1 = 1: a fifth of the turn's rate K·0.1 = 0.02 rad/s
    pull = fly(M.pull_out(0.1), biased(nomoto(), bias), dt=0.05).metrics
    assert pull["residual_yaw_rate"] == pytest.approx([bias, bias], rel=1e-3)
    assert pull["course_stable"] is True and pull["opposite"] is True
    assert pull["residual_bias"] == pytest.approx(bias, rel=1e-3)
    assert abs(pull["residual_difference"]) < 1e-5
    n3 = 100.0
    unstable = fly(M.pull_out(0.3), biased(nomoto(-1.0, n3), 0.01), duration=3000, dt=0.1).metrics
    roots = sorted(r.real for r in np.roots([n3, 0, -1, -0.01]) if abs(r.imag) < 1e-12)
    stable_roots = [roots[-1], roots[0]]  # the outer two of the three: −1 + 3 n3 r² > 0
    assert unstable["residual_yaw_rate"] == pytest.approx(stable_roots, rel=1e-3)
    assert unstable["course_stable"] is False and unstable["residual_bias"] is None
    assert unstable["residual_difference"] == pytest.approx(stable_roots[0] - stable_roots[1], rel=1e-3)


def test_pull_out_rule_on_given_sides():
    side = {"deflection": 0.1, "time_to_half": 1.0, "turn_settled": True, "decay_settled": True}
    same = [
        side | {"yaw_rate_before": 0.2, "residual_yaw_rate": -0.022},
        side | {"yaw_rate_before": -0.2, "residual_yaw_rate": -0.0215},
    ]
    assert mm.pull_out_summary(same)["course_stable"] is True  # |Δ| = 0.0005 ≤ 5 % of 0.2
    apart = [same[0], same[1] | {"residual_yaw_rate": 0.022}]
    assert mm.pull_out_summary(apart)["course_stable"] is False
    locked = [same[0], same[1] | {"yaw_rate_before": 0.2}]  # both sides turned one way
    assert mm.pull_out_summary(locked)["course_stable"] is False


def test_depth_change():
    res = fly(M.depth_change(3.0, 0.2), nomoto(pitch=True))
    m = res.metrics
    assert res.problem is None
    assert m["depth_overshoot"] > 0 and m["time_to_target"] < m["time_to_level"]
    z = res.eta[:, 2]
    assert np.interp(m["time_to_target"], res.time, z) == pytest.approx(3.0, abs=U * 0.02)


def test_not_reached_is_said():
    res = fly(M.turning_circle(0.3), duration=10.0)
    assert res.problem.startswith("turning circle: the heading changed by at most")
    assert "never reached 90°" in res.problem and res.metrics["advance"] is None
    assert res.to_dict()["complete"] is False
    res = fly(M.zigzag(math.radians(10), math.radians(10)), duration=5.0)
    assert "never reached 10° off the original course" in res.problem
    res = fly(M.depth_change(50.0, 0.2), nomoto(pitch=True), duration=5.0)
    assert "asked 50 m deeper, the vehicle sank" in res.problem and "never reached it" in res.problem


def test_figures_report_and_table():
    from hydrokit.plot.manoeuvre import figures, time_figure
    from hydrokit.report.manoeuvre import render

    spiral = fly(M.spiral("direct"), dt=0.1, duration=150.0)  # the first steps only: cheap
    vert = fly(M.vertical_zigzag(math.radians(10), math.radians(10)), nomoto(pitch=True), dt=0.1)
    pull = fly(M.pull_out(0.3), dt=0.1)
    short = fly(M.turning_circle(0.3), duration=10.0)
    assert spiral.problem.startswith("spiral: only") and len(spiral.metrics["points"]) >= 2
    assert list(figures(spiral)) == ["track.png", "time.png", "spiral.png"]
    assert time_figure(vert).axes[0].get_ylabel() == "pitch change [deg]"
    auv = fly(M.zigzag(0.2, 0.2), planar=False)  # a 6-DOF vehicle's zigzag: its depth is drawn too
    assert time_figure(auv).axes[3].get_ylabel() == "depth change [m]" and "max_depth_change" in auv.metrics
    assert "imo_criteria" not in auv.to_dict()
    png = {"track.png": b"\x89PNG"}  # the report embeds what it is given
    html = render(spiral, png)
    assert html.count("data:image/png;base64") == 1 and "<h2>IMO MSC.137(76) criteria" in html
    assert "settled" in html  # the spiral's table of steps
    assert "residual_yaw_rate" in render(pull, {}) and "never reached 90°" in render(short, {})
    cols, rows = vert.table()
    assert cols[-1] == "rudder" and len(rows) == vert.time.size and len(rows[0]) == 14
    assert dict(vert.summary_rows())["problem"] == "none"
    assert vert.to_dict()["parameters"] == {"kind": "vertical_zigzag", "deflection_deg": 10.0, "check_angle_deg": 10.0}
    assert vert.plot().get_xlabel() == "east y from the execute point [m]"


def test_from_options_and_runner_input():
    rad = math.radians
    assert M.from_options({"turning_circle": 20.0, "zigzag": None}) == M.turning_circle(rad(20))
    assert M.from_options({"zigzag": "20/10"}) == M.zigzag(rad(20), rad(10))
    assert M.from_options({"vertical_zigzag": "5/5"}).kind == "vertical_zigzag"
    assert M.from_options({"spiral": "reverse"}) == M.spiral("reverse")
    assert M.from_options({"pull_out": 15.0}) == M.pull_out(rad(15))
    assert M.from_options({"depth_change": "3"}) == M.depth_change(3.0, rad(15), M.HOLD_MAX_PITCH)
    assert M.from_options({"depth_change": "-2/10"}, 12.0) == M.depth_change(-2.0, rad(10), rad(12))
    assert M.from_options({"depth_change": "-2/10"}, None, True) == M.depth_change(-2.0, rad(10))
    with pytest.raises(InputError, match="--max-pitch with --zigzag: expected it with --depth-change only"):
        M.from_options({"zigzag": "10/10"}, 10.0)
    with pytest.raises(InputError, match="--max-pitch with --open-loop"):
        M.from_options({"depth_change": "5"}, 10.0, True)
    with pytest.raises(InputError, match="manoeuvre option 'circle'"):
        M.from_options({"circle": 1})
    with pytest.raises(InputError, match=r"--depth-change 'x/y': expected A/B"):
        M.from_options({"depth_change": "x/y"})
    # propulsion as a function of the state (here constant): the same run as the constant force
    res = fly(M.zigzag(0.2, 0.2))
    t, x, d, logic, w = M.fly_manoeuvre(
        nomoto(), M.zigzag(0.2, 0.2), 0, SERVO, tau=lambda x: (40, 0, 0, 0, 0, 0), length=L
    )
    assert logic.executes == pytest.approx(res.executes)
    with pytest.raises(InputError, match="expected 6 finite numbers"):
        M.fly_manoeuvre(nomoto(), M.zigzag(0.2, 0.2), 0, SERVO, tau=(1, 2))
    with pytest.raises(InputError, match="expected 12 finite numbers"):
        M.fly_manoeuvre(nomoto(), M.zigzag(0.2, 0.2), 0, SERVO, x0=np.zeros(3))
    with pytest.raises(InputError, match="surface index 2: expected 0 … 0"):
        M.fly_manoeuvre(nomoto(), M.zigzag(0.2, 0.2), 2, SERVO)
    with pytest.raises(InputError, match="expected 0 < dt ≤ duration"):
        M.fly_manoeuvre(nomoto(), M.zigzag(0.2, 0.2), 0, SERVO, dt=0.0)

    def blows_up(t, x, tau, d):
        return np.full(12, np.inf)

    from hydrokit.errors import SimulationError

    with pytest.raises(SimulationError, match="the state became non-finite at t = 0.02 s"):
        M.fly_manoeuvre(blows_up, M.zigzag(0.2, 0.2), 0, SERVO)
    boat = vehicle(BOAT)
    with pytest.raises(InputError, match=r"initial velocity \[1.0\]: expected 6 finite numbers"):
        M.run_manoeuvre(boat, M.turning_circle(0.3), nu0=[1.0])


def test_bad_input():
    with pytest.raises(InputError, match="expected one of turning_circle"):
        M.Manoeuvre("circle")
    with pytest.raises(InputError, match="expected a finite non-zero angle"):
        M.turning_circle(0.0)
    with pytest.raises(InputError, match="expected between 0° and 90°"):
        M.zigzag(0.2, 0.0)
    with pytest.raises(InputError, match="expected at most the surface's max_deflection_deg 34.38°"):
        fly(M.turning_circle(0.7))
    with pytest.raises(InputError, match="expected a finite non-zero depth change"):
        M.depth_change(0.0, 0.1)
    with pytest.raises(InputError, match="expected direct or reverse"):
        M.spiral("inverse")
    assert M.steering_surface(("fin", "rudder"), "zigzag") == 1
    assert M.steering_surface(("rudder", "sternplane"), "depth_change") == 1
    with pytest.raises(InputError, match="expected --surface NAME"):
        M.steering_surface(("a", "b"), "zigzag")
    with pytest.raises(InputError, match="the vehicle has a, b"):
        M.steering_surface(("a", "b"), "zigzag", "c")
    with pytest.raises(InputError, match="no control_surfaces"):
        M.steering_surface((), "zigzag")


# --- vehicles defined by delta() terms: the compiled loop, a second integration, the hold ------

BOAT = """
name: boat
mass: 100.0
volume: 0.09756
inertia: [10, 50, 50]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [10, 80, 80, 1, 20, 20]
linear_damping: [0, 40, 0, 0, 0, 30]
quadratic_damping: [20, 0, 0, 0, 0, 0]
reference_length: 2.0
dofs: [surge, sway, yaw]
control_surfaces:
  - {name: rudder, position: [-1.0, 0, 0], max_deflection_deg: 35}
terms:
  Y_uu*delta(rudder): 20.0
  N_uu*delta(rudder): -20.0
"""

# a slightly buoyant 6-DOF torpedo (B − W = 4.9 N)
TORPEDO = """
name: torpedo
mass: 50.0
volume: 0.04927
inertia: [0.5, 10, 10]
center_of_gravity: [0, 0, 0.05]
center_of_buoyancy: [0, 0, 0]
added_mass: [2, 20, 20, 0.1, 8, 8]
linear_damping: [5, 60, 60, 2, 60, 60]
quadratic_damping: [10, 0, 0, 0, 0, 0]
reference_length: 2.0
control_surfaces:
  - {name: rudder, position: [-0.9, 0, 0], max_deflection_deg: 25}
  - {name: sternplane, position: [-0.9, 0, 0], max_deflection_deg: 25}
terms:
  Y_uu*delta(rudder): 15.0
  N_uu*delta(rudder): -13.5
  Z_uu*delta(sternplane): -15.0
  M_uu*delta(sternplane): -13.5
"""


def vehicle(text):
    import yaml

    from hydrokit.io.vehicle import parse_vehicle

    return parse_vehicle(yaml.safe_load(text), "inline")


def test_compiled_and_python_loops_agree():
    boat = vehicle(BOAT)
    kw = {"tau": (20, 0, 0, 0, 0, 0), "dt": 0.1, "duration": 20.0}
    tc = M.turning_circle(math.radians(35))
    c = M.run_manoeuvre(boat, tc, loop="compiled", **kw)
    p = M.run_manoeuvre(boat, tc, loop="python", **kw)
    # the same equations, summed in another order: round-off (1e-16) grows over the approach and
    # 200 steps of the turn to ~1e-13; 1e-9 leaves the margin and would catch any difference in a law
    assert c.metrics["tactical_diameter"] is not None
    for key, val in c.metrics.items():
        if isinstance(val, float):
            assert val == pytest.approx(p.metrics[key], rel=1e-9, abs=1e-12), key
    np.testing.assert_allclose(c.array(), p.array(), rtol=1e-9, atol=1e-9)
    with pytest.raises(InputError, match="expected compiled or python"):
        M.run_manoeuvre(boat, M.turning_circle(0.3), loop="fortran")


def test_turning_circle_of_a_delta_term_vehicle_against_dop853():
    """The runner (RK4, the rudder through the servo law, metrics by crossing interpolation) against
    scipy's DOP853 on the numpy right-hand side with the rudder held from the execute, metrics by
    events (advance, transfer, tactical diameter) and by the steady state (D = 2 U / |r|)."""
    from scipy.integrate import solve_ivp

    from hydrokit.model.dynamics import vehicle_dynamics

    boat = vehicle(BOAT)
    tau = np.array([20.0, 0, 0, 0, 0, 0])
    delta = math.radians(35)
    dt = 0.05
    res = M.run_manoeuvre(boat, M.turning_circle(delta), tau=tau, dt=dt)
    m = res.metrics
    assert res.problem is None and m["direction"] == "port"  # N_uuδ < 0: a positive rudder turns to port
    k0 = int(np.searchsorted(res.time, 0.0))
    x0 = np.concatenate([res.eta[k0], res.nu[k0]])
    f = vehicle_dynamics(boat)
    held = np.array([delta])

    def rhs(t, y):
        return f(t, y, tau, held)

    hit = [lambda t, y, a=a: y[5] - x0[5] + a for a in (math.pi / 2, math.pi)]  # to port: ψ falls
    hit[1].terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0, 200), x0, method="DOP853", events=hit, rtol=1e-11, atol=1e-11)
    (t90,), (t180,) = (e[:1] for e in sol.t_events)
    y90, y180 = sol.y_events[0][0], sol.y_events[1][0]
    psi0 = x0[5]
    along = lambda y: y[0] * math.cos(psi0) + y[1] * math.sin(psi0)  # noqa: E731
    port = lambda y: y[0] * math.sin(psi0) - y[1] * math.cos(psi0)  # noqa: E731
    # RK4 at dt = 0.05 s on a turn of time scale ~1 s: global error ~(dt/T)^4 ~ 1e-5 relative; the
    # crossings are interpolated linearly between samples r·dt ≈ 0.03 rad apart on a radius of
    # ~3 m: R (r dt)²/8 ≈ 3e-4 m. rtol 2e-4 on distances of ~3 m, abs 2 dt·1e-3 on times
    assert m["advance"] == pytest.approx(along(y90), rel=2e-4, abs=1e-3)
    assert m["transfer"] == pytest.approx(port(y90), rel=2e-4, abs=1e-3)
    assert m["tactical_diameter"] == pytest.approx(port(y180), rel=2e-4, abs=1e-3)
    assert m["time_to_90_deg"] == pytest.approx(t90, abs=1e-3)
    # the steady turn: the same metric code on the reference's dense track, sampled 10× finer
    t_end = float(res.time[-1])
    dense = solve_ivp(rhs, (0, t_end), x0, method="DOP853", rtol=1e-11, atol=1e-11, dense_output=True)
    grid = np.linspace(0.0, t_end, int(round(10 * t_end / dt)) + 1)
    y = dense.sol(grid).T
    ref = mm.turning_circle_metrics(grid, y[:, :6], y[:, 6:])
    for key in ("steady_turning_diameter", "steady_speed", "steady_yaw_rate", "drift_angle_deg"):
        # the window starts at the first sample past (total − 360°): samples 10× apart shift it by
        # up to r·dt = 0.03 rad of a turn steady to TURN_STEADY (1 % over 360°): ~1e-4, rtol 2e-4
        assert m[key] == pytest.approx(getattr(ref, key), rel=2e-4), key
    # and the steady circle by plain geometry, D = 2 U / |r|, at the reference's end: the runner
    # stops once U and r vary by at most TURN_STEADY (1 %) over the last 360°, so rtol 1e-2
    end = y[-1]
    assert m["steady_turning_diameter"] == pytest.approx(2 * math.hypot(end[6], end[7]) / abs(end[11]), rel=1e-2)


def trim(v, tau):
    """Straight, level flight at constant depth by root-finding the numpy right-hand side: unknowns
    u, v, w (m/s), φ, θ (rad), δ_rudder, δ_plane (rad); ν̇ = 0 and ż = 0 (p = q = r = 0, so ψ̇ = 0)."""
    from scipy.optimize import root

    from hydrokit.model.dynamics import vehicle_dynamics

    f = vehicle_dynamics(v)

    def eqs(p):
        x = np.zeros(12)
        x[3], x[4], x[6], x[7], x[8] = p[3], p[4], p[0], p[1], p[2]
        xd = f(0.0, x, tau, np.array(p[5:]))
        return [*xd[6:12], xd[2]]

    sol = root(eqs, [1.0, 0, 0, 0, 0, 0, 0], tol=1e-13)
    assert sol.success
    return sol.x


def test_hold_flies_the_approach_at_the_trim():
    """A buoyant, pitch-unstable torpedo with a yaw-moment disturbance: with the hold, the approach
    settles at the depth and heading it started at, on the trim found by root-finding."""
    torpedo = vehicle(TORPEDO)
    tau = np.array([40.0, 0, 0, 0, 0, 0.8])
    res = M.run_manoeuvre(torpedo, M.turning_circle(0.3), tau=tau, dt=0.05, duration=0.05)
    assert res.hold == {"depth": "sternplane", "heading": "rudder (approach)"}
    assert not res.warnings  # the approach was steady
    k0 = int(np.searchsorted(res.time, 0.0))
    u, v, w, phi, theta, d_r, d_s = trim(torpedo, tau)
    # the approach stops once ν is steady and |z − z0|, |ψ − ψ0| ≤ HOLD_TOLERANCE (1e-3 m, rad):
    # the depth loop's set-point is then within k_z·1e-3 m = 1e-4 rad of its end (k_z = 1/(5L))
    # (and w ≈ u θ within u·3e-4 rad)
    assert res.nu[k0, 0] == pytest.approx(u, rel=1e-4)
    assert res.nu[k0, 1:3] == pytest.approx([v, w], abs=u * 3e-4)
    assert res.eta[k0, 3:5] == pytest.approx([phi, theta], abs=3e-4)
    assert res.deflection[k0 - 1] == pytest.approx([d_r, d_s], abs=3e-4)
    assert abs(res.eta[k0, 2]) <= M.HOLD_TOLERANCE
    assert d_s < -0.01  # the plane works against the buoyancy: not a vacuous hold
    # during the turn the plane keeps holding, the rudder steers
    assert res.to_dict()["hold"]["depth"] == "sternplane"


def test_a_ship_that_does_not_go_straight_at_zero_rudder_is_approached_on_a_straight_course():
    """A constant yaw moment N_0 and side force Y_0 = −N_0 (a propeller's asymmetry): at zero rudder the
    boat turns, so the approach's heading hold must find the rudder angle that cancels both — closed
    form δ = N_0 / (20 u²) with u² = 40 / 20 (surge: thrust 40 N against 20 u²), and v = r = 0 — and
    the turn starts from a straight course (before, its advance was measured from a curve)."""
    import yaml

    doc = yaml.safe_load(BOAT)
    doc["terms"].update({"N_0": 0.5, "Y_0": -0.5})
    from hydrokit.api import vehicle_from_dict

    boat = vehicle_from_dict(doc, "asymmetric boat")
    kw = {"tau": (40, 0, 0, 0, 0, 0), "dt": 0.05, "duration": 5.0}
    res = M.run_manoeuvre(boat, M.turning_circle(math.radians(35)), **kw)
    assert res.hold == {"heading": "rudder (approach)"}
    at_execute = np.nonzero(res.time >= 0)[0][0]
    assert abs(res.nu[at_execute, 5]) < 1e-4  # no yaw rate: a straight approach
    # the closed form within the approach's steadiness test (it ends when the velocities stop changing,
    # with the heading loop's integral still settling by about 1 %)
    assert res.approach_deflection["rudder"] == pytest.approx(0.5 / (20 * 2.0), rel=0.02)
    assert res.to_dict()["approach_deflection_deg"]["rudder"] == pytest.approx(math.degrees(0.0125), rel=0.02)
    free = M.run_manoeuvre(boat, M.turning_circle(math.radians(35)), hold=False, **kw)
    assert abs(free.nu[np.nonzero(free.time >= 0)[0][0], 5]) > 1e-2  # without: already turning


def test_hold_in_the_turn_and_without_it():
    torpedo = vehicle(TORPEDO)
    kw = {"tau": (40, 0, 0, 0, 0, 0), "dt": 0.05, "duration": 15.0}  # the first 15 s of the turn
    held = M.run_manoeuvre(torpedo, M.turning_circle(0.3), **kw)
    free = M.run_manoeuvre(torpedo, M.turning_circle(0.3), hold=False, **kw)
    assert held.hold and free.hold == {}
    # without the planes the torpedo leaves its depth during the approach (rising, the Munk moment
    # pitches it nose-down and the thrust drives it down; the record keeps z)
    k0 = int(np.searchsorted(free.time, 0.0))
    assert abs(free.eta[k0, 2]) > 1.0 and abs(held.eta[k0, 2]) <= M.HOLD_TOLERANCE
    assert held.metrics["max_depth_change"] < 0.5 * free.metrics["max_depth_change"]


def test_heading_hold_in_a_depth_change():
    torpedo = vehicle(TORPEDO)
    res = M.run_manoeuvre(torpedo, M.depth_change(2.0, 0.1), tau=(40, 0, 0, 0, 0, 0.8), dt=0.05)
    assert res.problem is None and res.hold == {"depth": "sternplane (approach)", "heading": "rudder"}
    # the rudder holds the heading against the 0.8 N·m disturbance: within a degree throughout
    assert np.max(np.abs(res.eta[:, 5])) < math.radians(1.0)
    assert res.metrics["time_to_target"] < res.metrics["time_to_level"]


def test_holding_surfaces():
    from hydrokit.simulate.compiled import make_dynamics

    torpedo, boat = vehicle(TORPEDO), vehicle(BOAT)
    f = make_dynamics(torpedo)
    assert M.holding_surfaces(f, torpedo.dofs, 2, "turning_circle", 0) == (1, 0)
    assert M.holding_surfaces(f, torpedo.dofs, 2, "vertical_zigzag", 1) == (1, 0)
    assert M.holding_surfaces(f, torpedo.dofs, 2, "zigzag", 0, hold=False) == (None, None)
    g = make_dynamics(boat)
    # a planar ship: the rudder holds the approach's heading (by default too), nothing else is held
    assert M.holding_surfaces(g, boat.dofs, 1, "zigzag", 0) == (None, 0)
    assert M.holding_surfaces(g, boat.dofs, 1, "zigzag", 0, hold=True) == (None, 0)
    assert M.holding_surfaces(g, boat.dofs, 1, "zigzag", 0, hold=False) == (None, None)
    with pytest.raises(InputError, match=r"hold surface index 3: expected 0 … 0"):
        fly(M.turning_circle(0.3), hold=(3, None))
