"""Missions steered by control surfaces (issue #45 item 5): a finned AUV with one propeller
turns with its rudder and holds pitch with its stern plane, in the Python loop, the compiled
loop and the fleet alike (one law, :func:`hydrokit.model.surfaces.steer_surfaces`)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.model.dynamics import pack, scal_fins
from hydrokit.model.surfaces import steer_surfaces, steer_work_size
from hydrokit.simulate.fleet import fly_fleet
from hydrokit.simulate.mission import fly_mission

FIN = {"area": 0.0133, "aspect_ratio": 2.21, "lift_slope": 3.12, "stall_angle_deg": 15, "max_deflection_deg": 15}
AUV = {
    "name": "finned-auv",
    "gravity": 9.81,
    "fluid": {"density": 1030.0},
    "mass": 30.48,
    "volume": 30.48 / 1030.0,  # neutrally buoyant
    "inertia": [0.177, 3.45, 3.45],
    "center_of_gravity": [0.0, 0.0, 0.0196],
    "center_of_buoyancy": [0.0, 0.0, 0.0],
    "added_mass": [0.93, 35.5, 35.5, 0.0141, 4.88, 4.88],
    "linear_damping": [0, 0, 0, 0, 0, 0],
    "quadratic_damping": [0, 0, 0, 0, 0, 0],
    "hull": {"profile": "remus100", "origin_from_nose": 0.611, "lift": True},
    "terms": {"X_u|u|": -1.62, "K_p|p|": -0.0013},
    "control_surfaces": [
        {"name": "rudder", "position": [-0.638, 0, 0], "axis": [0, 0, 1], "rate_limit_deg_s": 20, **FIN},
        {"name": "sternplane", "position": [-0.638, 0, 0], "axis": [0, 1, 0], "rate_limit_deg_s": 20, **FIN},
    ],
    "thrusters": [
        {
            "name": "prop",
            "position": [-0.7, 0, 0],
            "direction": [1, 0, 0],
            "model": "ideal",
            "max_thrust": 10,
            "min_thrust": -10,
        }
    ],
}
MISSION = {
    "name": "fin-square",
    "duration": 60,
    "dt": 0.05,
    "controller": "pid",
    "controllers": {
        "pid": {
            "speed": {"kp": 20, "ki": 2, "kd": 0, "limit": 10},
            "depth": {"kp": 0, "ki": 0, "kd": 0, "limit": 1},
            "heading": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
            "pitch": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
        }
    },
    "guidance": {
        "acceptance_radius": 3,
        "lookahead": 5,
        "speed": 1.5,
        "waypoints": [[0, 0, 0], [30, 0, 0], [30, 30, 0]],
    },
}


@pytest.fixture
def setup(tmp_path):
    v = tmp_path / "auv.yaml"
    v.write_text(yaml.safe_dump(AUV))
    m = tmp_path / "mission.yaml"
    m.write_text(yaml.safe_dump(dict(MISSION, vehicle=str(v))))
    return hydrokit.load_mission(m), hydrokit.load_vehicle(v)


def test_the_rudder_steers_the_mission_and_both_loops_agree(setup):
    mission, vehicle = setup
    a = fly_mission(mission, vehicle, loop="python")
    b = fly_mission(mission, vehicle, loop="compiled")
    # the same run to round-off: the law is one function, called as Python and compiled
    np.testing.assert_allclose(b.eta, a.eta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.run.deflection, a.run.deflection, rtol=0, atol=1e-9)
    assert a.metrics["completed"] and a.metrics["waypoint_times"][1] is not None
    assert abs(a.eta[-1, 5] - np.pi / 2) < 0.3  # heading the second leg, north-east → east (ψ ≈ 90°)
    assert np.max(np.abs(a.run.deflection[:, 0])) > 0.1  # the rudder worked …
    assert np.max(np.abs(a.run.deflection)) <= np.radians(15) + 1e-12  # … within its limit
    rate = np.abs(np.diff(a.run.deflection[:, 0])) / np.diff(a.time)
    assert rate.max() <= np.radians(20) * (1 + 1e-9)  # and its rate limit


def test_without_surfaces_the_same_vehicle_cannot_turn(setup):
    mission, vehicle = setup
    bare = dataclasses.replace(vehicle, surfaces=type(vehicle.surfaces)(), terms=vehicle.terms)
    flown = fly_mission(mission, vehicle)
    adrift = fly_mission(mission, bare)
    assert (
        adrift.metrics["waypoint_times"][1] is None
        or adrift.metrics["cross_track_rms"] > 3 * flown.metrics["cross_track_rms"]
    )


def test_the_fleet_flies_fins_like_the_single_run(setup):
    mission, vehicle = setup
    fleet = fly_fleet(mission, [vehicle, vehicle], duration=30.0, paths_every=mission.output_every)
    one = fly_mission(mission, vehicle, duration=30.0)
    np.testing.assert_allclose(fleet.paths[1], one.eta, rtol=0, atol=1e-12)


def _steer(vehicle, tau_d, nr, delta=None, dt=10.0):
    p = pack(vehicle)
    first, n = scal_fins(p.scal)
    s = vehicle.surfaces
    d = np.zeros(len(s)) if delta is None else np.array(delta, float)
    work = np.zeros(steer_work_size(len(s)))
    args = (p.t_dof, p.t_coef, p.t_kind, p.t_idx, p.scal, first, n, s.max_deflection, s.rate_limit, s.time_constant)
    steer_surfaces(np.asarray(tau_d, float), np.asarray(nr, float), 0.0, *args, dt, d, work)
    return d


def test_surface_allocation_inverts_the_delta_terms():
    # remus100: N = N_uuδr u² δr and M = M_uuδs u² δs (ρ c_Lα S_fin x_fin = −13.6 each from
    # Prestero's fin data), no servo lag: the deflection giving the demand is δ = τ / (−13.6 u²)
    # — the closed form
    v = hydrokit.load_vehicle("remus100")
    u = 1.5
    d = _steer(v, [0, 0, 0, 0, 2.0, -3.0], [u, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(d, [-3.0 / (-13.6 * u * u), 2.0 / (-13.6 * u * u)], rtol=1e-6)
    # at rest a surface has no effect: it is held at 0, not driven to its stop
    assert np.all(_steer(v, [0, 0, 0, 0, 2.0, -3.0], [0, 0, 0, 0, 0, 0]) == 0)
    # beyond the limit: the mechanical stop
    assert _steer(v, [0, 0, 0, 0, 0, -300.0], [u, 0, 0, 0, 0, 0])[0] == pytest.approx(np.radians(20))  # remus100: 20°


def test_two_surfaces_on_one_moment_share_it():
    data = dict(AUV)
    data["control_surfaces"] = [
        {"name": "upper", "position": [-0.638, 0, -0.1], "axis": [0, 0, 1], **FIN},
        {"name": "lower", "position": [-0.638, 0, 0.1], "axis": [0, 0, 1], **FIN},
    ]
    v = hydrokit.vehicle_from_dict(data)
    d = _steer(v, [0, 0, 0, 0, 0, -0.5], [1.5, 0, 0, 0, 0, 0])
    assert d[0] == pytest.approx(d[1], rel=1e-9) and d[0] > 0
    # together they give the demanded yaw moment (to the linearisation's accuracy)
    f = hydrokit.model.dynamics.hydro_force(pack(v), np.array([1.5, 0, 0, 0, 0, 0]), np.eye(3), d)
    f0 = hydrokit.model.dynamics.hydro_force(pack(v), np.array([1.5, 0, 0, 0, 0, 0]), np.eye(3), np.zeros(2))
    assert f[5] - f0[5] == pytest.approx(-0.5, rel=2e-3)


def test_depth_through_pitch_dives_with_the_stern_planes(tmp_path):
    # depth_pitch: the pitch loop's set-point is clip(gain (z − z_d), ±max) — the AUV has no heave
    # thruster, so it can only reach 4 m by pitching nose down with its stern plane
    v = tmp_path / "auv.yaml"
    v.write_text(yaml.safe_dump(AUV))
    gains = dict(MISSION["controllers"]["pid"], depth_pitch={"gain": 0.3, "max_pitch_deg": 20})
    way = [[0, 0, 0], [80, 0, 4], [160, 0, 4]]
    data = dict(MISSION, vehicle=str(v), duration=100, controllers={"pid": gains})
    data["guidance"] = dict(MISSION["guidance"], waypoints=way)
    m = tmp_path / "dive.yaml"
    m.write_text(yaml.safe_dump(data))
    mission, vehicle = hydrokit.load_mission(m), hydrokit.load_vehicle(v)
    a = fly_mission(mission, vehicle, loop="python")
    b = fly_mission(mission, vehicle, loop="compiled")
    np.testing.assert_allclose(b.eta, a.eta, rtol=0, atol=1e-9)
    assert abs(a.eta[-1, 2] - 4.0) < 0.3  # at depth
    assert a.eta[:, 4].min() < -0.05  # it pitched nose down to get there
    assert np.max(np.abs(a.run.deflection[:, 1])) > 0.02  # with the stern plane
    # without the cascade the same AUV stays near the surface
    flat = dict(data, controllers={"pid": MISSION["controllers"]["pid"]})
    m.write_text(yaml.safe_dump(flat))
    c = fly_mission(hydrokit.load_mission(m), vehicle)
    assert abs(c.eta[-1, 2]) < 1.0


def test_depth_to_pitch_law_and_its_file_errors(tmp_path):
    from hydrokit.errors import InputError
    from hydrokit.model.control import depth_to_pitch

    assert depth_to_pitch(1.0, 4.0, 0.1, 0.35) == pytest.approx(-0.3)  # too shallow: nose down
    assert depth_to_pitch(1.0, 9.0, 0.1, 0.35) == -0.35 and depth_to_pitch(9.0, 1.0, 0.1, 0.35) == 0.35
    v = tmp_path / "auv.yaml"
    v.write_text(yaml.safe_dump(AUV))
    for extra, message in (
        (
            {"depth_pitch": {"gain": 0.3, "max_pitch_deg": 20}, "pitch": None},
            r"depth_pitch': depth through pitch needs",
        ),
        ({"depth_pitch": {"gain": 0.3, "max_pitch_deg": 95}}, r"max_pitch_deg' = 95: expected an angle below 90"),
        ({"depth_pitch": {"gain": 0.3}}, r"depth_pitch': missing 'max_pitch_deg'"),
    ):
        gains = {k: w for k, w in dict(MISSION["controllers"]["pid"], **extra).items() if w is not None}
        m = tmp_path / "bad.yaml"
        m.write_text(yaml.safe_dump(dict(MISSION, vehicle=str(v), controllers={"pid": gains})))
        with pytest.raises(InputError, match=message):
            hydrokit.load_mission(m)
