"""The bundled REMUS 100 models behave as torpedo AUVs do (issue #49 item 4): course-stable when
running straight, turning on smaller circles at larger rudder angles, coming out of a turn when the
rudder is put back, checking a zigzag, and holding depth through pitch on their stern planes.

Propulsion is Prestero's (2001, MIT/WHOI MS thesis) steady run: 3.86 N of thrust (u → 1.54 m/s
with X_u|u| = −1.62 kg/m) and −0.543 N·m of propeller torque."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.io.vehicle import load_vehicle, parse_vehicle, resolve_vehicle
from hydrokit.io.yamlfile import read_yaml
from hydrokit.manoeuvre.run import pull_out, run_manoeuvre, turning_circle, zigzag
from hydrokit.simulate.compiled import make_dynamics
from hydrokit.simulate.mission import fly_mission

THRUST = 3.86  # N, Prestero's steady run
TORQUE = -0.543  # N·m, his propeller torque
PROPULSION = (THRUST, 0.0, 0.0, TORQUE, 0.0, 0.0)
APPROACH = (1.5, 0, 0, 0, 0, 0)
U_STEADY = math.sqrt(THRUST / 1.62)  # m/s

# Prestero (2001) inputs (ch. 2-3 tables): fluid, fin and hull data, added mass, mass
RHO, C_LA, S_FIN, X_FIN = 1030.0, 3.12, 0.00665, -0.638
D_HULL, C_YDB, X_CP = 0.191, 1.20, -0.321
X_UDOT, Y_VDOT, Y_RDOT, MASS = -0.93, -35.5, 1.93, 30.48


def _terms(name: str) -> dict[str, float]:
    v = load_vehicle(name)
    return dict(zip(v.terms.names, v.terms.coef))


def test_remus100_lift_terms_are_prestero_inputs():
    """Each combined term of remus100 is its Munk part plus the body lift (−½ρd²c_ydβ at x_cp, on
    the cross-flow v + x_cp r) plus the fin lift (ρ c_Lα S_fin per pair at x_fin, on v + x_fin r),
    all from Prestero's own inputs; the file prints them to 3 digits: rtol 0.5 %."""
    k = RHO * C_LA * S_FIN  # 21.4 kg/m
    body = -0.5 * RHO * D_HULL**2 * C_YDB  # −22.5 kg/m
    expected = {
        "Y_uv": body - k,
        "N_uv": (Y_VDOT - X_UDOT) + X_CP * body - X_FIN * k,
        "Y_ur": X_UDOT + X_CP * body - X_FIN * k,
        "N_ur": Y_RDOT + X_CP**2 * body - X_FIN**2 * k,
        "Y_uu*delta(rudder)": k,
        "N_uu*delta(rudder)": X_FIN * k,
    }
    mirror = {"Y_uv": ("Z_uw", 1), "N_uv": ("M_uw", -1), "Y_ur": ("Z_uq", -1), "N_ur": ("M_uq", 1)}
    mirror |= {
        "Y_uu*delta(rudder)": ("Z_uu*delta(sternplane)", -1),
        "N_uu*delta(rudder)": ("M_uu*delta(sternplane)", 1),
    }
    t = _terms("remus100")
    for name, value in expected.items():
        assert t[name] == pytest.approx(value, rel=5e-3), name
        other, sign = mirror[name]  # axisymmetric hull, fins in a cross
        assert t[other] == pytest.approx(sign * value, rel=5e-3), other


def test_remus100_cross_flow_strips_give_prestero_pure_sway_drag():
    """remus100's cross-flow drag is the strip integral of Prestero's profile with his C_dc = 1.1;
    in pure sway it must give his Y_v|v| = −131 kg/m (the value with his fins' −3.8, which the
    hull strips leave out: rtol 3 %), and nothing in surge."""
    from hydrokit.model.dynamics import hydro_force, pack

    v = load_vehicle("remus100")
    f = hydro_force(pack(v), np.array([0.0, 0.2, 0, 0, 0, 0]), np.eye(3), np.zeros(2))
    assert f[1] == pytest.approx(-131.0 * 0.2 * 0.2, rel=0.03)
    assert f[0] == 0.0


def test_remus100_is_course_stable_by_two_methods():
    """Clarke's criterion C = Y_uv N_ur − N_uv (Y_ur − m) > 0 from the file's terms (the header:
    +254), and independently the eigenvalues of the compiled right-hand side linearised in sway and
    yaw at 1.54 m/s: both negative. Prestero's table as printed gives C = −549 (his −28.6, −2.0,
    −24.0, 5.22): the same formula says unstable, as the +0.95 /s eigenvalue it flew with."""
    t = _terms("remus100")
    clarke = t["Y_uv"] * t["N_ur"] - t["N_uv"] * (t["Y_ur"] - MASS)
    assert clarke == pytest.approx(254.0, rel=0.01)
    assert -28.6 * -2.0 - -24.0 * (5.22 - MASS) < 0  # the printed table
    f = make_dynamics(load_vehicle("remus100"))
    x0 = np.zeros(12)
    x0[6] = U_STEADY
    tau = np.array([THRUST, 0, 0, 0, 0, 0])
    jac = np.zeros((2, 2))
    for j, i in enumerate((7, 11)):
        e = np.zeros(12)
        e[i] = 1e-6
        jac[:, j] = (np.asarray(f(0.0, x0 + e, tau)) - np.asarray(f(0.0, x0 - e, tau)))[[7, 11]] / 2e-6
    eig = np.linalg.eigvals(jac)
    assert eig.real.max() < -0.1  # s⁻¹: a margin, not round-off


ANGLES = (5.0, 10.0, 15.0, 20.0)  # deg


@pytest.fixture(scope="module", params=["remus100", "remus100-fins"])
def turns(request):
    v = load_vehicle(request.param)
    runs = {
        deg: run_manoeuvre(v, turning_circle(math.radians(deg)), tau=PROPULSION, nu0=APPROACH, dt=0.05, duration=600)
        for deg in ANGLES
    }
    return v, runs


def test_turning_diameter_falls_as_the_rudder_grows(turns):
    """A course-stable AUV turns on a smaller circle at a larger rudder angle (the printed table
    settled on 2.0 m at every angle). Each circle is the least-squares circle of the last 360°;
    the steps between angles are tens of percent, far beyond its resolution."""
    v, runs = turns
    d = [runs[a].metrics["steady_turning_diameter"] for a in ANGLES]
    # at 20° remus100 keeps a third of its speed, and at 0.5 m/s the stern planes cannot hold
    # REMUS's 7 N of buoyancy: the manoeuvre may say the depth hold was lost; the circle is still
    # measured
    assert all(runs[a].problem is None for a in (5.0, 10.0, 15.0))
    assert d[0] > d[1] > d[2] > d[3]
    assert d[0] > 1.3 * d[2]
    assert d[3] > 2.0 * v.reference_length  # not the 1.5 L of a vehicle unstable on its course
    # a smaller circle costs speed: the hull drifts more (X_vr v r and m v r act against thrust)
    ratio = [runs[a].metrics["speed_ratio"] for a in ANGLES]
    assert ratio[0] > ratio[1] > ratio[2] > ratio[3] > 0.2
    drift = [runs[a].metrics["drift_angle_deg"] for a in ANGLES]
    assert drift[0] < drift[1] < drift[2] < drift[3] < 30.0


def test_a_depth_holding_turn_holds_depth(turns):
    """With the stern planes holding depth through pitch (the default hold), turns at 5°, 10° and
    15° stay within 1 m of the approach depth (REMUS is 7 N buoyant: the planes and the body lift
    at a few degrees of pitch carry it, less well as the turn slows the vehicle)."""
    _, runs = turns
    for deg in (5.0, 10.0, 15.0):
        assert runs[deg].hold
        assert runs[deg].metrics["max_depth_change"] < 1.0
    assert runs[5.0].metrics["max_depth_change"] < 0.5


@pytest.mark.parametrize("name", ["remus100", "remus100-fins"])
def test_pull_out_returns_to_a_straight_course(name):
    """ITTC 7.5-04-02-01 §2.2.6: after steady turns at ±10° and the rudder back to zero, a
    course-stable vehicle's yaw rate decays to (nearly) zero from both sides. Without the
    propeller's roll torque the vehicle is symmetric: the residual is within 5 % of the turn's
    rate. With it (−0.543 N·m rolls REMUS by ≈ 5°, and the stern planes holding 7 N of buoyancy
    then push sideways) both sides settle on the same small rate — the same value from both
    sides is the ITTC mark of a stable vehicle with a bias; an unstable one keeps turning to the
    side it came from."""
    v = load_vehicle(name)
    r = run_manoeuvre(v, pull_out(math.radians(10)), tau=(THRUST, 0, 0, 0, 0, 0), nu0=APPROACH, dt=0.05, duration=900)
    assert r.problem is None
    for side in r.metrics["sides"]:
        assert abs(side["residual_yaw_rate"]) < 0.05 * abs(side["yaw_rate_before"])
    r = run_manoeuvre(v, pull_out(math.radians(10)), tau=PROPULSION, nu0=APPROACH, dt=0.05, duration=900)
    port, starboard = r.metrics["sides"]
    assert np.sign(port["yaw_rate_before"]) != np.sign(starboard["yaw_rate_before"])
    assert r.problem is None
    assert port["residual_yaw_rate"] == pytest.approx(
        starboard["residual_yaw_rate"], abs=0.02 * abs(port["yaw_rate_before"])
    )
    assert abs(port["residual_yaw_rate"]) < 0.15 * abs(port["yaw_rate_before"])


def test_zigzag_checks_with_small_overshoots():
    """A 15°/15° zigzag is checked each time (the printed table never checked; the old physical-fin
    file overshot by 185°): overshoots of a few degrees, as an AUV on its rudder."""
    r = run_manoeuvre(
        load_vehicle("remus100"),
        zigzag(math.radians(15), math.radians(15)),
        tau=PROPULSION,
        nu0=APPROACH,
        dt=0.05,
        duration=300,
    )
    assert r.problem is None
    assert 0.0 < r.metrics["first_overshoot_deg"] < 15.0
    assert 0.0 < r.metrics["second_overshoot_deg"] < 20.0


def test_a_5_m_depth_change_through_pitch_stays_within_the_pitch_limit(tmp_path):
    """A mission from 5 m to 10 m depth, depth through pitch on the stern planes (depth_pitch: gain
    0.3 rad/m, 20° at most), a propeller holding 1.5 m/s: the vehicle reaches the new depth within
    0.5 m and never pitches beyond the limit (+2°: the inner pitch loop lags its set-point)."""
    data = dict(read_yaml(resolve_vehicle("remus100")))
    data["thrusters"] = [
        {"name": "prop", "position": [-0.7, 0, 0], "direction": [1, 0, 0], "model": "ideal", "max_thrust": 10}
    ]
    data.pop("service")  # the bundled service condition names the file's own propeller
    parse_vehicle(data, "remus100 with a propeller")  # loads as a vehicle
    vehicle_path = tmp_path / "remus.yaml"
    vehicle_path.write_text(yaml.safe_dump(data))
    mission = {
        "name": "remus-depth-change",
        "vehicle": str(vehicle_path),
        "duration": 90,
        "dt": 0.02,
        "controller": "pid",
        "controllers": {
            "pid": {
                "speed": {"kp": 20, "ki": 2, "kd": 0, "limit": 10},
                "depth": {"kp": 0, "ki": 0, "kd": 0, "limit": 1},
                "heading": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
                "pitch": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
                "depth_pitch": {"gain": 0.3, "max_pitch_deg": 20},
            }
        },
        "guidance": {
            "acceptance_radius": 3,
            "lookahead": 5,
            "speed": 1.5,
            "waypoints": [[0, 0, 5], [30, 0, 10], [150, 0, 10]],
        },
    }
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(mission))
    res = fly_mission(hydrokit.load_mission(path), hydrokit.load_vehicle(vehicle_path))
    z, theta = res.eta[:, 2], res.eta[:, 4]
    assert abs(z[-1] - 10.0) < 0.5
    assert z.max() < 10.5  # no deep overshoot on the way
    assert np.degrees(np.abs(theta).max()) < 22.0
    assert np.degrees(theta.min()) < -5.0  # it did dive nose down to get there
