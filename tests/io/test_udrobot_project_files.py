"""The bundled UDrobot project: base vehicle (true coefficients + our thruster layout) and mission."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import hydrokit
from hydrokit.model.allocation import uncontrollable_dofs

DATA = Path(hydrokit.__file__).resolve().parent / "data"
PROJECT = DATA / "projects" / "udrobot"
BASE = PROJECT / "base.yaml"
MISSION = PROJECT / "mission.yaml"
TRUTH = DATA / "vehicles" / "udrobot.yaml"


def test_base_vehicle_loads_with_six_thrusters() -> None:
    v = hydrokit.load_vehicle(BASE)
    assert v.name == "udrobot"
    assert v.thrusters is not None and len(v.thrusters) == 6
    assert v.thrusters.names == ["FR", "FL", "RR", "RL", "VR", "VL"]
    T = v.thrusters.configuration_matrix()
    # BlueROV2-like (non-Heavy): two side verticals cannot pitch; every other DOF is actuated
    assert uncontrollable_dofs(T) == ["pitch"]
    # horizontal four in the x-y plane vectored at ±45°, verticals push up (-z, NED)
    np.testing.assert_allclose(np.abs(T[0, :4]), np.sqrt(0.5), rtol=1e-12)
    np.testing.assert_allclose(T[2, :4], 0.0, atol=1e-12)
    np.testing.assert_allclose(T[2, 4:], -1.0, rtol=1e-12)
    # all inside UDrobot's 0.298 x 0.269 x 0.169 m frame (half-extents, m)
    for t in v.thrusters.thrusters:
        assert np.all(np.abs(t.position) <= [0.149, 0.1345, 0.0845])


def test_base_coefficients_are_the_truth() -> None:
    base = hydrokit.load_vehicle(BASE)
    truth = hydrokit.load_vehicle(TRUTH)
    assert truth.thrusters is None  # the bundled vehicle file carries no thrusters
    for field in ("mass", "volume", "gravity", "density", "reference_length"):
        assert getattr(base, field) == getattr(truth, field), field
    for field in ("inertia", "r_g", "r_b", "M_A", "D_L", "D_Q"):
        np.testing.assert_array_equal(getattr(base, field), getattr(truth, field), err_msg=field)


def test_mission_names_the_base_vehicle_next_to_it() -> None:
    m = hydrokit.load_mission(MISSION)
    assert Path(m.vehicle).resolve() == BASE.resolve()
    assert set(m.gains) == {"pid", "s-plane"}
    assert round(m.duration / m.dt) <= 2400  # flown 200+ times in a Monte Carlo: keep it short


def test_pid_makes_progress_along_the_first_leg() -> None:
    duration = 15.0  # s, well before the first corner
    run = hydrokit.fly(MISSION, "pid", duration=duration)
    m = run.mission
    start, target = m.path.points[0], m.path.points[1]
    speed = float(m.path.speeds[0])  # m/s
    end = run.eta[-1, :3]
    progress = np.linalg.norm(target - start) - np.linalg.norm(target - end)
    # the vehicle accelerates to the leg speed within about a second (≥ 0.8·v·t); it would
    # not (or drift off the leg or depth) if the thrusters pushed the wrong way or could not
    # act on surge, yaw or heave
    assert progress > 0.8 * speed * duration
    leg = (target - start) / np.linalg.norm(target - start)
    off = (end - start) - ((end - start) @ leg) * leg
    assert np.linalg.norm(off) < 0.2  # m, cross-track and depth error at the end
    assert abs(run.eta[-1, 5]) < np.radians(5.0)  # still on the first leg's course (north)
    assert run.metrics["saturation_fraction"] < 0.05


@pytest.mark.parametrize("controller", ["pid", "s-plane"])
def test_mission_completes_with_the_true_vehicle(controller: str) -> None:
    run = hydrokit.fly(MISSION, controller)
    assert run.metrics["completed"]
    assert run.metrics["cross_track_rms"] < 0.35
    assert run.metrics["saturation_fraction"] < 0.01
