"""Bundled vehicles carry their service condition (issue #55 item 2): ``hydrokit manoeuvre`` and
``hydrokit simulate`` given no propulsion fly the vehicle file's ``service:`` block, say so in one
stderr line and record it in manoeuvre.json; every manoeuvre kind runs on every bundled vehicle
with control surfaces without a propulsion option, and each vehicle reaches the speed its block
states."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.io.vehicle import bundled_vehicles, resolve_vehicle
from hydrokit.manoeuvre.definitions import KINDS

VEHICLES = {name: hydrokit.load_vehicle(name) for name in bundled_vehicles()}
STEERED = sorted(n for n, v in VEHICLES.items() if len(v.surfaces))
UNSTEERED = sorted(n for n, v in VEHICLES.items() if not len(v.surfaces))
SERVED = sorted(n for n, v in VEHICLES.items() if v.service is not None)

# the shortest sensible option of every kind (docs/manoeuvre.md), each run ending once measured
MANOEUVRES = {
    "turning_circle": ["--turning-circle", "15"],
    "zigzag": ["--zigzag", "10/10"],
    "spiral-direct": ["--spiral", "direct"],
    "spiral-reverse": ["--spiral", "reverse"],
    "pull_out": ["--pull-out", "15"],
    "depth_change": ["--depth-change", "2"],
    "depth_change-open": ["--depth-change", "2/10", "--open-loop"],
    "vertical_zigzag": ["--vertical-zigzag", "10/10"],
}
# a step of about L/U / 20 (REMUS: 0.87 s, the Mariner: 21 s), where every metric is within a
# few per cent of the default step's and a run takes about a second
DT = {"mariner": "0.5"}
# the approach settles to 1e-4 of its speed (docs/manoeuvre.md) and the step moves it by less than
# 1e-5 (the Mariner's 7.71698 m/s at dt 0.1 s, 7.71694 at 0.5 s); the files state 4 digits
SPEED_RTOL = 2e-3


def _line(name: str) -> str:
    return f"propulsion: {name}'s service condition — "


def test_every_kind_is_listed():
    assert {k.split("-")[0] for k in MANOEUVRES} == set(KINDS)


def test_each_vehicle_with_surfaces_has_a_service_condition():
    """So no bundled vehicle that can fly a manoeuvre needs a propulsion option."""
    assert STEERED and set(STEERED) <= set(SERVED)


@pytest.mark.parametrize("kind", sorted(MANOEUVRES))
@pytest.mark.parametrize("name", STEERED)
def test_every_manoeuvre_flies_without_a_propulsion_option(run_cli, tmp_path, name, kind):
    vehicle = VEHICLES[name]
    out = tmp_path / "out"
    args = [*MANOEUVRES[kind], "--dt", DT.get(name, "0.05"), "--no-plots", "--out", out]
    code, stdout, err = run_cli("manoeuvre", name, *args)
    lines = err.strip().splitlines()
    if kind.split("-")[0] in ("depth_change", "vertical_zigzag") and vehicle.planar:
        assert code == 2 and len(lines) == 1 and "is planar" in lines[0] and "Traceback" not in err, err
        return
    assert code == 0, err
    said = [ln for ln in lines if ln.startswith("propulsion:")]
    assert len(said) == 1 and said[0].startswith(_line(name)), err
    assert f"(about {vehicle.service.speed:.3g} m/s)" in said[0]
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["propulsion_source"] == "service"
    assert doc["service"]["commands"] == vehicle.service.commands
    assert doc["service"]["force"] == list(vehicle.service.tau)
    # the straight approach, held on depth and course, is the run at the service speed
    assert doc["approach_speed"] == pytest.approx(vehicle.service.speed, rel=SPEED_RTOL)


@pytest.mark.parametrize("name", UNSTEERED)
def test_a_vehicle_without_surfaces_is_refused_in_one_line(run_cli, tmp_path, name):
    code, _, err = run_cli("manoeuvre", name, "--turning-circle", "15", "--out", tmp_path / "o")
    assert code == 2 and err.strip().splitlines() == [
        "error: the vehicle has no control_surfaces; a manoeuvre needs a surface to steer with"
    ], err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("args", "propulsion"),
    [
        (["--force", "3.86,0,0,-0.543,0,0"], None),
        (["--command", "propeller=11.567"], {"propeller": 11.567}),
    ],
    ids=["force", "command"],
)
def test_a_propulsion_option_overrides_the_service_condition(run_cli, tmp_path, args, propulsion):
    out = tmp_path / "o"
    init = ["--initial-velocity", "1.5,0,0,0,0,0"]
    code, _, err = run_cli(
        "manoeuvre", "remus100", "--zigzag", "10/10", *args, *init, "--dt", "0.05", "--no-plots", "--out", out
    )
    assert code == 0, err
    assert "propulsion:" not in err
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["propulsion_source"] == "options" and "service" not in doc
    assert (doc.get("propulsion") or {}).get("commands") == propulsion


def test_the_api_flies_the_service_condition_too():
    from hydrokit.manoeuvre.definitions import zigzag

    v = VEHICLES["remus100-fins"]
    res = hydrokit.manoeuvre(v, zigzag(math.radians(10), math.radians(10)), dt=0.05)
    assert res.propulsion["commands"] == v.service.commands
    assert res.propulsion["force"] == list(v.service.tau)
    assert res.approach_speed == pytest.approx(v.service.speed, rel=SPEED_RTOL)


# --- simulate ----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(set(SERVED) - set(STEERED)))
def test_simulate_reaches_the_stated_speed_in_a_straight_run(run_cli, tmp_path, name):
    """The vehicles without surfaces fly straight open loop (course-stable at their service
    condition: the file says so); from rest, the surge and heave settle in under 60 s."""
    out = tmp_path / "t.csv"
    code, stdout, err = run_cli("simulate", name, "--duration", "80", "--dt", "0.1", "--out", out)
    assert code == 0, err
    assert [ln for ln in err.splitlines() if ln.startswith("propulsion:")] == [
        next(ln for ln in err.splitlines() if ln.startswith(_line(name)))
    ]
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    speed = np.linalg.norm(rows[:, 7:10], axis=1)
    assert speed[-1] == pytest.approx(VEHICLES[name].service.speed, rel=SPEED_RTOL)
    assert abs(speed[-1] - speed[-50]) < 1e-4 * speed[-1]  # steady over the last 5 s
    assert np.all(np.abs(rows[-1, 4:7]) < 0.01)  # level and on its course: rad


@pytest.mark.parametrize("name", STEERED)
def test_simulate_of_a_steered_vehicle_says_its_service_condition(run_cli, tmp_path, name):
    code, _, err = run_cli("simulate", name, "--duration", "2", "--dt", "0.1", "--out", tmp_path / "t.csv")
    assert code == 0, err
    assert sum(ln.startswith(_line(name)) for ln in err.splitlines()) == 1, err


@pytest.mark.parametrize(
    ("args", "moves"),
    [(["--force", "40,0,0,0,0,0"], True), (["--no-service"], False), (["--command", "A1=5"], True)],
    ids=["force", "no-service", "command"],
)
def test_simulate_flies_the_options_given_instead(run_cli, tmp_path, args, moves):
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", "minerva", "--duration", "2", "--dt", "0.1", *args, "--out", out)
    assert code == 0, err
    assert "propulsion:" not in err
    u = np.loadtxt(out, delimiter=",", skiprows=1)[-1, 7]
    assert bool(u > 0.01) is moves


def _with_uncertainty(tmp_path: Path, name: str) -> Path:
    doc: dict[str, Any] = yaml.safe_load(resolve_vehicle(name).read_text())
    doc["uncertainty"] = {"quadratic_damping": [10.0, 0, 0, 0, 0, 0]}
    path = tmp_path / "v.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--samples", "3"], "--samples 3 with no propulsion given: the service: condition of vehicle 'minerva'"),
        (["--integrator", "dop853"], "--integrator dop853 with no propulsion given: the service: condition of"),
        (["--attitude", "quaternion"], "expected --attitude euler, a --force or --no-service"),
    ],
    ids=["samples", "adaptive", "quaternion"],
)
def test_a_run_that_cannot_fly_the_thruster_commands_is_refused(run_cli, tmp_path, args, message):
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", _with_uncertainty(tmp_path, "minerva"), "--duration", "1", *args, "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err, err
    assert not out.exists()


def test_samples_fly_a_service_force(run_cli, tmp_path):
    """The Mariner's service condition is a constant force: the samples fly it."""
    out = tmp_path / "t.csv"
    path = _with_uncertainty(tmp_path, "mariner")
    code, _, err = run_cli("simulate", path, "--duration", "20", "--dt", "0.5", "--samples", "3", "--out", out)
    assert code == 0, err
    assert sum(ln.startswith(_line("mariner")) for ln in err.splitlines()) == 1, err
    assert np.loadtxt(out, delimiter=",", skiprows=1)[-1, 7] > 0.5  # m/s after 20 s from rest
