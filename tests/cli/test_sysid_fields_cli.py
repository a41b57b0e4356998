"""``hydrokit sysid --free`` and the main job's ``sysid.free`` with the fields of a race rudder
and its propeller (issue #48 item 2): accepted by name against the vehicle file, a bad name is
one line with the nearest valid names (exit 2, nothing written)."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml
from tests.simulate.test_sysid_propeller_rudder import RACE_RUDDER
from tests.simulate.test_sysid_surfaces import SHIP

from hydrokit.errors import InputError


def _vehicle(tmp_path: Path) -> Path:
    doc = copy.deepcopy(SHIP)
    doc["control_surfaces"] = [copy.deepcopy(RACE_RUDDER)]
    doc["terms"]["N_T(prop)*delta(rudder)"] = -0.3
    p = tmp_path / "ship.yaml"
    p.write_text(yaml.safe_dump(doc))
    return p


def _run_file(tmp_path: Path) -> Path:
    run = tmp_path / "run.csv"
    rows = "\n".join(f"{0.1 * k:.1f},0.3,0.0,20.0,0.0" for k in range(30))
    run.write_text("time,u,r,prop,rudder\n" + rows + "\n")
    return run


def test_a_bad_field_name_exits_2_with_the_nearest_names(run_cli: Any, tmp_path: Path) -> None:
    out = tmp_path / "out"
    for bad, near in (
        ("control_surfaces.rudder.lift_slop", "control_surfaces.rudder.lift_slope"),
        ("thrusters.prop.wake", "thrusters.prop.wake_fraction"),
        ("control_surfaces.rudder.kapa", "control_surfaces.rudder.kappa"),
    ):
        code, _, err = run_cli(
            "sysid", _run_file(tmp_path), "--vehicle", _vehicle(tmp_path), "--free", f"terms.N_ur,{bad}", "--out", out
        )
        assert code == 2, err
        line = err.strip()
        assert "\n" not in line and "Traceback" not in line, err
        assert bad in line and f"(nearest: {near}" in line, line
        assert not out.exists() or not any(out.iterdir())


def _project(tmp_path: Path, free: list[str]) -> Path:
    vehicle = _vehicle(tmp_path)
    run = _run_file(tmp_path)
    doc = {"name": "p", "vehicle": vehicle.name, "sysid": {"runs": [run.name], "free": free}}
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_project_sysid_free_takes_surface_and_thruster_fields_of_its_vehicle(tmp_path: Path) -> None:
    from hydrokit.io.project import parse_project
    from hydrokit.io.yamlfile import read_yaml

    free = [
        "control_surfaces.rudder.lift_slope",
        "thrusters.prop.wake_fraction",
        "terms.N_T(prop)*delta(rudder)",
        "terms.Y_n(prop)*delta(rudder)",
    ]
    path = _project(tmp_path, free)
    project = parse_project(read_yaml(path), path)
    assert project.sysid is not None and project.sysid.free == tuple(free)
    for bad, said in (
        ("control_surfaces.flap.lift_slope", r"'flap' names no surface of the vehicle \(control_surfaces: rudder\)"),
        ("thrusters.screw.wake_fraction", r"'screw' names no thruster of the vehicle \(thrusters: prop\)"),
        ("terms.N_T(screw)*delta(rudder)", r"T\(screw\)"),
    ):
        path = _project(tmp_path, ["terms.N_ur", bad])
        with pytest.raises(InputError, match=r"field 'sysid.free\[1\]' = .*" + said) as exc:
            parse_project(read_yaml(path), path)
        assert "\n" not in str(exc.value)
