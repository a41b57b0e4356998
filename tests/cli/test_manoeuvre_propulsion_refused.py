"""``hydrokit manoeuvre`` refuses, fast and writing nothing, a manoeuvre with no propulsion
(no forward force, no thruster command, starting at rest, and no ``service:`` block in the vehicle
file: the bundled vehicles fly theirs, tests/cli/test_service_condition.py) and one whose approach
ends too slow to steer (below the hold's minimum speed)."""

from __future__ import annotations

import math
import time

import pytest

from hydrokit.errors import InputError
from hydrokit.manoeuvre.run import HOLD_MIN_SPEED, check_propulsion

# a planar boat: surge drag X_u|u| = 20 N/(m/s)², so a force X (N) drives it at √(X/20) m/s
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


@pytest.fixture
def boat(tmp_path):
    p = tmp_path / "boat.yaml"
    p.write_text(BOAT)
    return p


@pytest.mark.parametrize("what", [("--spiral", "direct"), ("--turning-circle", "20"), ("--zigzag", "20/20")])
def test_no_propulsion_exits_2_at_once_and_writes_nothing(run_cli, boat, tmp_path, what):
    out = tmp_path / "out"
    t0 = time.perf_counter()
    code, _, err = run_cli("manoeuvre", boat, *what, "--out", out)
    took = time.perf_counter() - t0
    assert code == 2
    assert "no propulsion" in err and "--force" in err and "--command" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()
    # refused before anything is flown (the hang it replaces ran > 120 s)
    assert took < 10.0


def test_an_initial_surge_speed_or_a_forward_force_is_propulsion_enough():
    check_propulsion([1.0, 0, 0, 0, 0, 0], 0.0)  # no error
    check_propulsion([0.0] * 6, 1.0)
    with pytest.raises(InputError, match=r"no propulsion .*force X = -1 N"):
        check_propulsion([-1.0, 0, 0, 0, 0, 0], 0.0)


def test_too_slow_at_the_execute_exits_2_and_writes_nothing(run_cli, boat, tmp_path):
    # X = 0.02 N: the boat's steady speed √(0.02/20) ≈ 0.032 m/s, under the hold's minimum
    X = 0.02
    assert math.sqrt(X / 20.0) < HOLD_MIN_SPEED
    out = tmp_path / "out"
    code, _, err = run_cli("manoeuvre", boat, "--turning-circle", "20", "--force", f"{X},0,0,0,0,0", "--out", out)
    assert code == 2
    assert "speed at the execute" in err and f"{HOLD_MIN_SPEED:g} m/s" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()
