"""``hydrokit manoeuvre`` says what happened: refusals up front, units on what it prints, clean
numbers in manoeuvre.json (issue #49 item 3)."""

from __future__ import annotations

import json
import re

import pytest

from hydrokit.simulate import manoeuvre as M


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
