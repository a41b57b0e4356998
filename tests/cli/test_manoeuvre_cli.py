"""``hydrokit manoeuvre`` end to end on inline vehicles defined by delta() terms: a planar boat and
a 6-DOF torpedo whose stern plane holds depth (the compiled loop, the default)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

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


@pytest.fixture
def run(run_cli, tmp_path):
    boat = tmp_path / "boat.yaml"
    boat.write_text(BOAT)
    return lambda *a: run_cli("manoeuvre", boat, "--force", "20,0,0,0,0,0", *a)


@pytest.fixture
def run_torpedo(run_cli, tmp_path):
    torpedo = tmp_path / "torpedo.yaml"
    torpedo.write_text(TORPEDO)
    return lambda *a: run_cli("manoeuvre", torpedo, "--force", "40,0,0,0,0,0", "--dt", "0.05", *a)


def test_turning_circle_outputs(run, tmp_path):
    out = tmp_path / "tc"
    code, stdout, err = run("--out", out, "--turning-circle", "35", "--dt", "0.1")
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    tc = doc["turning_circle"]
    for key in (
        "advance",
        "transfer",
        "tactical_diameter",
        "steady_turning_diameter",
        "steady_speed",
        "steady_yaw_rate",
        "drift_angle_deg",
        "time_to_90_deg",
    ):
        assert isinstance(tc[key], float), key
    # the track in the CSV gives back the JSON's advance: along-course distance where ψ crosses 90°
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    head = (out / "trajectory.csv").read_text().splitlines()[0]
    assert head == "time,x,y,z,phi,theta,psi,u,v,w,p,q,r,rudder"
    after = data[data[:, 0] >= 0]
    turn = np.abs(after[:, 6])
    k = int(np.argmax(turn >= math.pi / 2))
    w = (math.pi / 2 - turn[k - 1]) / (turn[k] - turn[k - 1])
    # 9 significant digits in the CSV: the same number to 1e-7
    assert tc["advance"] == pytest.approx(after[k - 1, 1] + w * (after[k, 1] - after[k - 1, 1]), rel=1e-7)
    assert abs(after[0, 13]) == pytest.approx(math.radians(35))
    assert [c["criterion"] for c in doc["imo_criteria"]] == ["advance ≤ 4.5 L", "tactical diameter ≤ 5 L"]
    assert "IMO advance ≤ 4.5 L" in stdout
    assert (out / "report.html").read_text().count("data:image/png;base64") == 2
    assert (out / "track.png").stat().st_size > 1000


def test_not_reached_writes_the_track_and_exits_2(run, tmp_path):
    out = tmp_path / "zz"
    code, _, err = run("--out", out, "--zigzag", "10/10", "--dt", "0.1", "--duration", "3")
    assert code == 2
    assert "zigzag: the heading never reached" in err and "the track was written" in err
    assert sorted(p.name for p in out.iterdir()) == ["trajectory.csv"]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("--zigzag", "10"), r"--zigzag '10': expected A/B"),
        (("--turning-circle", "10", "--zigzag", "10/10"), "2 manoeuvres given: expected exactly one"),
        (("--turning-circle", "40"), "expected at most the surface's max_deflection_deg 35°"),
        (("--turning-circle", "10", "--surface", "fin"), "--surface 'fin': the vehicle has rudder"),
    ],
)
def test_bad_input(run, tmp_path, args, match):
    code, _, err = run("--out", tmp_path / "bad", *args)
    assert code == 2 and match in err, err
    assert not (tmp_path / "bad" / "manoeuvre.json").exists()


def test_auv_turn_holds_depth(run_torpedo, tmp_path):
    out = tmp_path / "auv"
    code, _, err = run_torpedo("--out", out, "--turning-circle", "15", "--no-plots")
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["hold"] == {"depth": "sternplane", "heading": "rudder (approach)"}
    assert "held: depth by sternplane" in err
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    # the depth column gives back the JSON's max_depth_change (9 significant digits in the CSV)
    after = data[data[:, 0] >= 0]
    assert doc["turning_circle"]["max_depth_change"] == pytest.approx(
        np.max(np.abs(after[:, 3] - after[0, 3])), rel=1e-7
    )
    assert sorted(p.name for p in out.iterdir()) == ["manoeuvre.json", "trajectory.csv"]
    # without the hold: nothing held; 3 s of the turn are not enough (exit 2, the track written)
    code, _, err = run_torpedo("--out", tmp_path / "free", "--turning-circle", "15", "--no-hold", "--duration", "3")
    assert code == 2 and "held:" not in err and "never reached 90°" in err
    assert sorted(p.name for p in (tmp_path / "free").iterdir()) == ["trajectory.csv"]


def test_auv_bad_input(run_torpedo, tmp_path):
    code, _, err = run_torpedo("--out", tmp_path / "bad", "--depth-change", "2/30")
    assert code == 2 and "deflection 30°: expected at most the surface's max_deflection_deg 25°" in err
    assert not (tmp_path / "bad").exists() or not any((tmp_path / "bad").iterdir())


# the boat with a propeller astern (K_T(J) = 0.4 − 0.4 J, D = 0.2 m, no wake) and an ideal bow thruster
PROP_BOAT = (
    BOAT.replace("reference_length: 2.0\n", "reference_length: 2.0\nfluid: {density: 1025.0}\n")
    + """thrusters:
  - {name: prop, position: [-1.0, 0, 0], direction: [1, 0, 0], max_thrust: 500, diameter: 0.2,
     kt_forward: [-0.4, 0.4], max_rpm: 1800, time_constant: 0.3}
  - {name: bow, position: [0.8, 0, 0], direction: [0, 1, 0], max_thrust: 50}
"""
)


@pytest.fixture
def run_prop(run_cli, tmp_path):
    boat = tmp_path / "prop.yaml"
    boat.write_text(PROP_BOAT)
    return lambda *a: run_cli("manoeuvre", boat, "--dt", "0.1", *a)


def test_turning_circle_on_propeller_commands(run_prop, tmp_path):
    """--command prop=20 (rev/s): the approach settles where K_T(J) ρ D⁴ n² = 20 u², J = u/(n D)
    (closed form: the positive root of 20 u² + 0.4 ρ D³ n u − 0.4 ρ D⁴ n² = 0); rtol 2e-5 as the
    approach stops once u varies by ≤ 1e-4 of itself over 2 s (tests/simulate/test_manoeuvre_propulsion.py)."""
    out = tmp_path / "tc"
    code, stdout, err = run_prop("--out", out, "--turning-circle", "35", "--command", "prop=20", "--no-plots")
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    rho, d, n = 1025.0, 0.2, 20.0
    b, c = 0.4 * rho * d**3 * n, 0.4 * rho * d**4 * n**2
    u = (-b + math.sqrt(b * b + 80 * c)) / 40
    assert doc["approach_speed"] == pytest.approx(u, rel=2e-5)
    p = doc["propulsion"]
    assert p["commands"] == {"prop": 20.0, "bow": 0.0} and p["command_units"] == {"prop": "rev/s", "bow": "N"}
    assert p["thrust_at_execute"]["prop"] == pytest.approx(20 * u * u, rel=4e-5)
    assert p["thrust_at_end"]["prop"] > p["thrust_at_execute"]["prop"]  # slower in the turn: lower J, more K_T
    assert "thrust: prop" in err and "\n  advance: " in stdout


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("--command", "stern=3"), "command 'stern': the vehicle has thrusters prop, bow; expected one of them"),
        (("--command", "prop=31"), "command prop=31 rev/s: expected within thruster 'prop''s command limits [-30, 30]"),
        (("--command", "bow=60"), "command bow=60 N: expected within thruster 'bow''s command limits [-50, 50] N"),
        (("--command", "prop:20"), "--command 'prop:20': expected NAME=VALUE"),
    ],
)
def test_bad_commands(run_prop, tmp_path, args, match):
    code, _, err = run_prop("--out", tmp_path / "bad", "--turning-circle", "20", *args)
    assert code == 2 and match in err, err
    assert not (tmp_path / "bad").exists() or not any((tmp_path / "bad").iterdir())


def test_command_on_a_vehicle_without_thrusters(run, tmp_path):
    code, _, err = run("--out", tmp_path / "bad", "--turning-circle", "20", "--command", "prop=20")
    assert code == 2 and "vehicle 'boat' has no thrusters; expected a vehicle file with a 'thrusters:' block" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "bad").exists() or not any((tmp_path / "bad").iterdir())


def test_samples_write_intervals_about_the_nominal(run_cli, tmp_path):
    """``--samples`` (issue #48 item 7): each drawn boat flies the turn; every numeric metric gets
    its median and 95 % interval, and a σ of 10 % on the rudder's yaw moment puts the nominal
    tactical diameter inside its interval."""
    boat = tmp_path / "sigma.yaml"
    boat.write_text(BOAT + "uncertainty:\n  parameters: [terms.N_uu*delta(rudder)]\n  covariance: [[4.0]]\n")
    out = tmp_path / "tc"
    code, stdout, err = run_cli(
        "manoeuvre", boat, "--force", "20,0,0,0,0,0", "--out", out, "--turning-circle", "35", "--dt", "0.2",
        "--samples", "5", "--seed", "3",
    )  # fmt: skip
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    td, iv = doc["turning_circle"]["tactical_diameter"], doc["intervals"]["tactical_diameter"]
    assert iv["samples"] == 5 and iv["low95"] < td < iv["high95"]
    assert set(doc["intervals"]) >= {"advance", "transfer", "steady_speed", "time_to_90_deg"}
    assert doc["sampling"]["seed"] == 3 and doc["sampling"]["sigma"] == [2.0]
    assert "tactical diameter: median" in stdout and "95 % intervals" in (out / "report.html").read_text()


def test_samples_without_an_uncertainty_block_are_refused_before_the_run(run, tmp_path):
    code, _, err = run("--out", tmp_path / "no", "--turning-circle", "35", "--samples", "3")
    assert code == 2 and "Traceback" not in err
    assert "--samples 3: vehicle 'boat' has no 'uncertainty:' block" in err
    assert not (tmp_path / "no").exists() or not any((tmp_path / "no").iterdir())


def test_depth_change_closed_loop_keeps_the_pitch_limit_and_open_loop_is_kept(run_torpedo, tmp_path):
    """``--depth-change 3 --max-pitch 8``: the depth reached (within 0.3 m at the end) with |θ| ≤ 8°
    throughout; ``--open-loop`` flies the old execute (planes held at A), which pitches beyond it."""
    out = tmp_path / "closed"
    code, stdout, err = run_torpedo("--out", out, "--depth-change", "3/20", "--max-pitch", "8", "--no-plots")
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["parameters"]["loop"] == "closed" and doc["parameters"]["max_pitch_deg"] == 8.0
    track = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    after = track["time"] >= 0
    assert np.degrees(np.max(np.abs(track["theta"]))) <= 8.0
    assert track["z"][-1] - track["z"][after][0] == pytest.approx(3.0, abs=0.3)
    assert "pitch within ±8°" in stdout and "time to settle:" in stdout
    code, stdout, err = run_torpedo("--out", tmp_path / "open", "--depth-change", "3/20", "--open-loop", "--no-plots")
    assert code == 0, err
    doc = json.loads((tmp_path / "open" / "manoeuvre.json").read_text())
    assert doc["parameters"]["loop"] == "open" and abs(doc["depth_change"]["max_pitch_deg"]) > 8.0
    code, _, err = run_torpedo("--out", tmp_path / "bad", "--turning-circle", "10", "--open-loop")
    assert code == 2 and "--open-loop with --turning-circle: expected it with --depth-change only" in err
