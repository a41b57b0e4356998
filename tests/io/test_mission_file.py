"""Mission files: parsing, unit conversion at the edge, and one-line errors."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.io.mission import load_mission, parse_mission
from hydrokit.model.control import PID, SPlane

BASE = {
    "name": "t",
    "vehicle": "lingyun",
    "duration": 100,
    "dt": 0.05,
    "controller": "pid",
    "controllers": {
        "pid": {
            "speed": {"kp": 400, "ki": 20, "limit": 150},
            "depth": {"kp": 300, "kd": 600, "limit": 150},
            "heading": {"kp": 200, "kd": 300, "limit": 60},
        },
        "s-plane": {
            "speed": {"k1": 8, "k2": 0, "scale": 150},
            "depth": {"k1": 2, "k2": 4, "scale": 150},
            "heading": {"k1": 3, "k2": 5, "scale": 60},
        },
    },
    "guidance": {
        "acceptance_radius": 1.0,
        "lookahead": 4.0,
        "speed": 0.5,
        "waypoints": [[0, 0, 2], {"x": 20, "y": 0, "z": 4, "speed": 0.6}, [20, 20, 4]],
    },
    "initial": {"attitude_deg": [0, 0, 90]},
    "current": [0.1, 0, 0],
}


def parse(doc: dict):
    return parse_mission(doc, source="m.yaml")


def test_parses_units_and_controllers() -> None:
    m = parse(BASE)
    assert m.eta0[5] == pytest.approx(math.pi / 2, rel=1e-15)  # degrees converted at the edge
    np.testing.assert_array_equal(m.eta0[:3], [0, 0, 2])  # start defaults to waypoint 0
    np.testing.assert_allclose(m.path.speeds, [0.6, 0.5])
    np.testing.assert_array_equal(m.current, [0.1, 0, 0])
    ap = m.autopilot()
    assert isinstance(ap.speed, PID) and ap.speed.output_max == 150 and ap.heading.angle
    sp = m.autopilot("s-plane")
    assert isinstance(sp.depth, SPlane) and sp.depth.scale == 150
    # a parsed mission is shared by the sweep's runs: frozen
    import dataclasses

    with pytest.raises(dataclasses.FrozenInstanceError):
        m.current = np.zeros(3)  # type: ignore[misc]


def test_waypoint_times_give_leg_speeds() -> None:
    doc = copy.deepcopy(BASE)
    doc["guidance"]["waypoints"] = [
        {"x": 0, "y": 0, "z": 2, "time": 0},
        {"x": 30, "y": 0, "z": 2, "time": 60},
        {"x": 30, "y": 40, "z": 2, "time": 140},
    ]
    m = parse(doc)
    np.testing.assert_allclose(m.path.speeds, [30 / 60, 40 / 80], rtol=1e-15)


def _set(doc: dict, dotted: str, value) -> dict:
    d = copy.deepcopy(doc)
    node = d
    keys = dotted.split(".")
    for k in keys[:-1]:
        node = node[int(k)] if isinstance(node, list) else node[k]
    if value is _DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    return d


_DELETE = object()


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("controllers.pid.speed.kp", "fast", "field 'controllers.pid.speed.kp' = 'fast': expected a number"),
        ("controllers.pid.speed.kp", None, "controllers.pid.speed.kp' = None: expected a number"),
        ("controllers.pid.depth.kq", 3, "unknown gain"),
        ("controllers.s-plane.heading.scale", 0, "scale' = 0: expected a positive"),
        ("guidance.waypoints", [], "0 given; expected a list of at least 2 waypoints"),
        ("guidance.waypoints", [[0, 0, 1]], "expected a list of at least 2 waypoints"),
        ("guidance.waypoints", [[0, 0, 1], [0, 0, 1]], r"waypoints\[1\]' repeats waypoint 0"),
        (
            "guidance.waypoints",
            [{"x": 0, "y": 0, "z": 0, "time": 10}, {"x": 5, "y": 0, "z": 0, "time": 5}],
            "waypoints out of order",
        ),
        (
            "guidance.waypoints",
            [{"x": 0, "y": 0, "z": 0, "time": 0}, {"x": 5, "y": 0, "z": 0}],
            "'time' given for some waypoints only",
        ),
        ("guidance.waypoints", [[0, 0], [1, 1, 1]], r"waypoints\[0\]' = \[0, 0\]: expected a list of 3 numbers"),
        ("duration", -5, "field 'duration' = -5: expected a positive number"),
        ("dt", 500, "expected a step no longer than duration"),
        ("controller", "fuzzy", "field 'controller' = 'fuzzy'"),
        ("current", [1, 2], "field 'current'"),
        ("vehicle", _DELETE, "missing field 'vehicle'"),
        ("controllers.pid.heading", _DELETE, "missing the 'heading' loop"),
    ],
)
def test_bad_missions_one_line(field: str, value, match: str) -> None:
    with pytest.raises(InputError, match=match) as exc:
        parse(_set(BASE, field, value))
    assert "\n" not in str(exc.value) and str(exc.value).startswith("m.yaml: ")


def test_unknown_top_level_field() -> None:
    with pytest.raises(InputError, match="unknown field 'wayponits'"):
        parse({**BASE, "wayponits": []})


def test_load_from_file_resolves_relative_vehicle(tmp_path: Path) -> None:
    (tmp_path / "veh.yaml").write_text("name: v\n")
    doc = {**BASE, "vehicle": "veh.yaml"}
    p = tmp_path / "mission.yaml"
    p.write_text(yaml.safe_dump(doc))
    m = load_mission(p)
    assert Path(m.vehicle) == tmp_path / "veh.yaml"


def test_missing_mission_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file or bundled mission"):
        load_mission(tmp_path / "none.yaml")


@pytest.mark.parametrize(
    ("first", "heading"),
    [([3.0, 4.0, 2.0], math.atan2(4.0, 3.0)), ([-2.0, -2.0, 3.0], -0.75 * math.pi), ([0.0, 0.0, 6.0], 0.0)],
)
def test_without_attitude_the_vehicle_starts_facing_the_first_leg(first, heading) -> None:
    # the bearing atan2(Δy, Δx) of waypoint 0 → 1 (NED: north x, east y), 0 for a vertical leg;
    # the file reader and create_mission agree
    from hydrokit.model.mission import create_mission

    doc = copy.deepcopy(BASE)
    del doc["initial"]
    doc["guidance"]["waypoints"] = [[0, 0, 2], first, [30, 30, 4]]
    m = parse(doc)
    assert m.eta0[3:] == pytest.approx([0.0, 0.0, heading], abs=1e-15)
    py = create_mission(doc["guidance"]["waypoints"], doc["controllers"])
    np.testing.assert_array_equal(py.eta0, m.eta0)  # level (φ = θ = 0) at waypoint 0, the same heading


def test_guidance_distances_default_to_the_documented_1_and_5_m() -> None:
    # docs/control.md: acceptance_radius and lookahead default to 1 m and 5 m
    import copy

    doc = copy.deepcopy(BASE)
    del doc["guidance"]["acceptance_radius"], doc["guidance"]["lookahead"]
    m = parse(doc)
    assert (m.path.acceptance_radius, m.path.lookahead) == (1.0, 5.0)
    assert (parse(BASE).path.acceptance_radius, parse(BASE).path.lookahead) == (1.0, 4.0)
