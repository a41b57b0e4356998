"""``hydrokit manoeuvre`` says what happened: refusals up front, units on what it prints, clean
numbers in manoeuvre.json (issue #49 item 3)."""

from __future__ import annotations

import json
import re

import pytest

from hydrokit.manoeuvre import run as M


@pytest.fixture
def never_flown(monkeypatch):
    """Make flying anything an error: a refusal must come before the approach starts."""

    def refuse(*a, **k):
        raise AssertionError("the manoeuvre was flown before the refusal")

    monkeypatch.setattr(M, "fly_manoeuvre", refuse)


@pytest.mark.parametrize("option", [("--depth-change", "5"), ("--vertical-zigzag", "10/10")])
def test_planar_vehicle_refuses_depth_manoeuvres_up_front(run_cli, tmp_path, never_flown, option):
    out = tmp_path / "dz"
    code, stdout, err = run_cli("manoeuvre", "mariner", "--out", out, *option, "--force", "727000,0,0,0,0,0")
    assert code == 2, err
    assert "vehicle 'mariner' is planar (dofs: surge, sway, yaw)" in err
    assert "expected a vehicle with heave and pitch in its dofs" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err and stdout == ""
    assert not out.exists() or not any(out.iterdir())


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


def test_printed_metrics_carry_units_and_the_json_has_no_float_noise(run_cli, tmp_path):
    boat = tmp_path / "boat.yaml"
    boat.write_text(BOAT)
    out = tmp_path / "tc"
    code, stdout, err = run_cli(
        "manoeuvre",
        boat,
        "--out",
        out,
        "--turning-circle",
        "15",
        "--force",
        "20,0,0,0,0,0",
        "--dt",
        "0.1",
        "--no-plots",
    )
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    metrics = doc["turning_circle"]
    # every metric printed, one per line, its value followed by the unit of manoeuvre.json's "units"
    lines = dict(line.strip().split(": ", 1) for line in stdout.splitlines()[1:] if line.startswith("  "))
    for key, value in metrics.items():
        unit = doc["units"].get(key, "°" if key.endswith("_deg") else "")
        text = lines[key.replace("_", " ")]
        if isinstance(value, float) and unit not in ("", "–"):
            number, _, printed_unit = text.partition(" ") if unit != "°" else (text[:-1], "", "°")
            assert float(number) == pytest.approx(value, rel=1e-3) and printed_unit == unit, (key, text)
    assert lines["advance"].endswith(" m") and lines["steady yaw rate"].endswith(" rad/s")
    # 15° goes in as radians and comes back as 15.0; no float in the file carries more than 9 digits
    assert doc["parameters"]["deflection_deg"] == 15.0
    raw = (out / "manoeuvre.json").read_text()
    long = [m for m in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", raw) if len(re.sub(r"e.*|\D", "", m).lstrip("0")) > 9]
    assert long == []


def test_pull_out_prints_both_sides_with_units(run_cli, tmp_path):
    """The user's report: ``--pull-out`` printed ``pull_out:`` and nothing else (a course-stable boat:
    the sway and yaw damping of docs/manoeuvre.md's propeller boat)."""
    boat = tmp_path / "boat.yaml"
    boat.write_text(BOAT.replace("linear_damping: [0, 40, 0, 0, 0, 30]", "linear_damping: [0, 300, 0, 0, 0, 200]"))
    out = tmp_path / "po"
    code, stdout, err = run_cli(
        "manoeuvre", boat, "--out", out, "--pull-out", "20", "--force", "20,0,0,0,0,0", "--dt", "0.1", "--no-plots"
    )
    assert code == 0, err
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["complete"] is True and doc["pull_out"]["opposite"] is True
    sides = doc["pull_out"]["sides"]
    assert [s["deflection_deg"] for s in sides] == [20.0, -20.0]
    assert sides[0]["yaw_rate_before"] * sides[1]["yaw_rate_before"] < 0
    assert stdout.startswith("pull-out at ±20°, rudder:")
    for s, line in zip(sides, [ln for ln in stdout.splitlines() if ln.strip().startswith("side ")]):
        assert line.strip().startswith(f"side {s['deflection_deg']:+.4g}°: yaw rate before ")
        assert f"residual yaw rate {s['residual_yaw_rate']:.4g} rad/s" in line
        assert f"time to settle {s['time_to_settle']:.4g} s" in line


def test_pull_out_of_a_boat_that_cannot_leave_its_turn_is_an_error(run_cli, tmp_path):
    """The lightly damped boat locks into its turn: even the full opposite rudder cannot straighten it,
    and its −20° side turns the same way as its +20° side; that is said, with exit 2."""
    boat = tmp_path / "boat.yaml"
    boat.write_text(BOAT)
    out = tmp_path / "po"
    code, stdout, err = run_cli(
        "manoeuvre", boat, "--out", out, "--pull-out", "20", "--force", "20,0,0,0,0,0", "--dt", "0.1", "--no-plots"
    )
    assert code == 2 and stdout == ""
    assert "pull-out: the -20° side turned the same way as the +20° side (yaw rates " in err
    assert "the vehicle was not brought back to a straight course between them" in err
    assert sorted(p.name for p in out.iterdir()) == ["trajectory.csv"]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("--initial-velocity", "1,0,0,0,0,nan"), "--initial-velocity"),
        (("--command", "prop=20"), "vehicle 'mariner' has no thrusters"),
        (("--surface", "fin"), "--surface 'fin': the vehicle has rudder"),
        (("--turning-circle", "45"), "expected at most the surface's max_deflection_deg 40°"),
    ],
)
def test_every_option_is_checked_before_the_dynamics_are_built(run_cli, tmp_path, monkeypatch, args, match):
    """A bad setting is refused before the (compiled) dynamics are built and anything is flown."""
    import hydrokit.simulate.compiled as compiled

    def never(*a, **k):
        raise AssertionError("the dynamics were built before the refusal")

    monkeypatch.setattr(compiled, "make_dynamics", never)
    monkeypatch.setattr(M, "fly_manoeuvre", never)
    manoeuvre = () if "--turning-circle" in args else ("--zigzag", "10/10")
    code, stdout, err = run_cli("manoeuvre", "mariner", "--out", tmp_path / "bad", *manoeuvre, *args)
    assert code == 2 and match in err, err
    assert len(err.strip().splitlines()) == 1 and stdout == ""
    assert not (tmp_path / "bad").exists() or not any((tmp_path / "bad").iterdir())
