"""Issue #32 class 5: input that used to be taken without a word. An unknown key in an input
file is refused in one line naming the file, the key and the keys accepted (a format that
allows other tools' keys names them in a warning instead); a size or mass no physical body has
(below a micrometre, above a kilometre) is refused with the number."""

from __future__ import annotations

import re
import shutil
from pathlib import Path
from typing import Any

import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError

SPHERE = DATA_DIR / "geometry" / "sphere.yaml"
RIG = DATA_DIR / "campaigns" / "udrobot" / "spring_x.yaml"
ASSEMBLY = DATA_DIR / "assemblies" / "rehman_transport.yaml"
VEHICLE = DATA_DIR / "vehicles" / "minerva.yaml"


def _doc(path: Path) -> dict[str, Any]:
    return yaml.safe_load(path.read_text())


def _write(path: Path, doc: dict[str, Any]) -> Path:
    path.write_text(yaml.safe_dump(doc))
    return path


def _geometry(tmp: Path, **part: Any) -> Path:
    doc = _doc(SPHERE)
    doc["parts"][0].update(part)
    return _write(tmp / "g.yaml", doc)


def _load(kind: str, path: Path) -> Any:
    from hydrokit.io.assembly import load_assembly
    from hydrokit.io.geometry import load_geometry
    from hydrokit.io.mission import load_mission
    from hydrokit.io.project import load_project
    from hydrokit.io.rig import load_rig
    from hydrokit.io.vehicle import load_vehicle

    loaders = {"geometry": load_geometry, "rig": load_rig, "project": load_project, "assembly": load_assembly}
    return (loaders | {"vehicle": load_vehicle, "mission": load_mission})[kind](path)


def _mission(guidance: dict[str, Any]) -> dict[str, Any]:
    doc = _doc(DATA_DIR / "missions" / "minerva_square.yaml")
    doc["guidance"].update(guidance)
    return doc


def _project(tmp: Path, change: Any) -> Path:
    shutil.copytree(DATA_DIR / "projects" / "udrobot", tmp / "a" / "b" / "p")
    (tmp / "a" / "campaigns").symlink_to(DATA_DIR / "campaigns")
    path = tmp / "a" / "b" / "p" / "project.yaml"
    doc = _doc(path)
    change(doc)
    return _write(path, doc)


# (file kind, make(tmp) -> path, the misspelt key as named, a key the message must offer)
UNKNOWN_KEYS = {
    "geometry-top": ("geometry", lambda t: _write(t / "g.yaml", _doc(SPHERE) | {"speeed": 2}), "speeed", "speed"),
    "geometry-fluid": (
        "geometry",
        lambda t: _write(t / "g.yaml", _doc(SPHERE) | {"fluid": {"densty": 1025}}),
        "fluid.densty",
        "density",
    ),
    "geometry-part": ("geometry", lambda t: _geometry(t, diamter=0.5), "parts[0].diamter", "diameter"),
    "vehicle-top": ("vehicle", lambda t: _write(t / "v.yaml", _doc(VEHICLE) | {"masss": 460}), "masss", "mass"),
    "vehicle-fluid": (
        "vehicle",
        lambda t: _write(t / "v.yaml", _doc(VEHICLE) | {"fluid": {"density": 1025, "temprature": 15}}),
        "fluid.temprature",
        "kinematic_viscosity",
    ),
    "mission-guidance": (
        "mission",
        lambda t: _write(t / "m.yaml", _mission({"lookahaed": 2.0})),
        "guidance.lookahaed",
        "lookahead",
    ),
    "rig-body": (
        "rig",
        lambda t: _write(t / "r.yaml", _doc(RIG) | {"body": _doc(RIG)["body"] | {"masss": 1}}),
        "body.masss",
        "mass",
    ),
    "rig-top": ("rig", lambda t: _write(t / "r.yaml", _doc(RIG) | {"scael": 0.3}), "scael", "scale"),
    "project-top": ("project", lambda t: _project(t, lambda d: d.update(speeed=2)), "speeed", "scale_ratio"),
    "project-campaign": (
        "project",
        lambda t: _project(t, lambda d: d["campaigns"][0].update(methd="morison")),
        "campaigns[0].methd",
        "method",
    ),
    "assembly-part": (
        "assembly",
        lambda t: _write(
            t / "a.yaml", _doc(ASSEMBLY) | {"parts": [{**_doc(ASSEMBLY)["parts"][0], "jiont": [0, 0, 0]}]}
        ),
        "parts[0].jiont",
        "joint",
    ),
}


@pytest.mark.parametrize("case", sorted(UNKNOWN_KEYS))
def test_an_unknown_key_is_refused_naming_it_and_the_keys_accepted(tmp_path, case):
    kind, make, key, offered = UNKNOWN_KEYS[case]
    path = make(tmp_path)
    with pytest.raises(InputError, match=rf"{re.escape(path.name)}: .*'{re.escape(key)}'") as info:
        _load(kind, path)
    msg = str(info.value)
    assert "unknown" in msg and "expected one of" in msg and offered in msg, msg
    assert "\n" not in msg


def test_a_near_miss_is_suggested(tmp_path):
    with pytest.raises(InputError, match=r"'speeed'.*did you mean 'speed'\?"):
        _load("geometry", _write(tmp_path / "g.yaml", _doc(SPHERE) | {"speeed": 2}))


def test_thruster_keys_of_other_tools_are_named_in_a_warning(tmp_path):
    # the thrusters block explicitly tolerates other tools' fields (e.g. a simulator's plugin keys)
    from hydrokit.io.thrusters import load_thrusters

    doc = _doc(DATA_DIR / "vehicles" / "minerva.yaml")
    doc["thrusters"][0]["gz_plugin_topic"] = "/t"
    ts = load_thrusters(_write(tmp_path / "v.yaml", doc))
    assert any("gz_plugin_topic" in n and "ignored" in n for n in ts.notes), ts.notes


# --- sizes and masses no physical body has ---------------------------------------------------

SIZES = {
    "diameter-tiny": ({"diameter": 1e-200}, "parts[0].diameter", "1e-200"),
    "diameter-huge": ({"diameter": 5e3}, "parts[0].diameter", "5000"),
    "mass-tiny": ({"mass": 1e-30}, "parts[0].mass", "1e-30"),
    "mass-huge": ({"mass": 1e20}, "parts[0].mass", "1e+20"),
    "weight-huge": ({"weight": 1e21, "mass": None}, "parts[0].weight", "1e+21"),
}


@pytest.mark.parametrize("case", sorted(SIZES))
def test_a_part_no_physical_body_has_is_refused_with_the_number(tmp_path, case):
    change, field, shown = SIZES[case]
    doc = _doc(SPHERE)
    doc["parts"][0].update(change)
    doc["parts"][0] = {k: v for k, v in doc["parts"][0].items() if v is not None}
    path = _write(tmp_path / "g.yaml", doc)
    with pytest.raises(InputError, match=re.escape(f"g.yaml: field '{field}' = {shown}: expected")) as info:
        _load("geometry", path)
    assert "micrometre" in str(info.value) or "kg" in str(info.value), str(info.value)


def test_a_sphere_of_a_millimetre_is_still_a_body(tmp_path):
    geo = _load("geometry", _geometry(tmp_path, diameter=1e-3, mass=5e-4))
    assert geo.parts[0].part.added_mass[0, 0] > 0


@pytest.mark.parametrize(
    ("field", "value"),
    [("mass", 1e-30), ("volume", 1e15), ("reference_length", 1e-9), ("reference_area", 1e9)],
)
def test_a_rig_body_no_physical_body_has_is_refused(tmp_path, field, value):
    doc = _doc(RIG)
    doc["body"][field] = value
    path = _write(tmp_path / "r.yaml", doc)
    with pytest.raises(InputError, match=re.escape(f"r.yaml: field 'body.{field}' = {value:g}: expected")):
        _load("rig", path)


@pytest.mark.parametrize(("field", "value"), [("mass", 1e-30), ("mass", 1e20), ("volume", 1e-25), ("volume", 1e12)])
def test_a_vehicle_no_physical_body_has_is_refused(tmp_path, field, value):
    path = _write(tmp_path / "v.yaml", _doc(VEHICLE) | {field: value})
    with pytest.raises(InputError, match=re.escape(f"v.yaml: field '{field}' = {value:g}: expected")):
        _load("vehicle", path)
