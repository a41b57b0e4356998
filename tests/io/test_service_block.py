"""The ``service:`` block of a vehicle file (issue #55 item 2): read into ``Vehicle.service``,
refused in one line naming the file and the field when it is not as docs/model.md says, and kept
when a vehicle file is written."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
import yaml

import hydrokit
from hydrokit.errors import InputError
from hydrokit.io.vehicle import bundled_vehicles, load_vehicle, resolve_vehicle, vehicle_text
from hydrokit.model.vehicle import Service


def _remus(tmp_path: Path, service: Any) -> Path:
    doc = yaml.safe_load(resolve_vehicle("remus100").read_text())
    if service is None:
        doc.pop("service")
    else:
        doc["service"] = service
    path = tmp_path / "v.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_the_block_is_read_in_si():
    v = hydrokit.load_vehicle("remus100")
    assert v.service == Service(1.526, (("propeller", 11.567),), (0.0, 0.0, 0.0, -0.543, 0.0, 0.0))
    assert v.service.commands == {"propeller": 11.567} and v.service.tau[3] == -0.543
    mariner = load_vehicle("mariner").service
    assert mariner is not None and mariner.command == () and mariner.tau == (727000.0, 0, 0, 0, 0, 0)


def test_a_file_without_the_block_states_none(tmp_path):
    assert load_vehicle(_remus(tmp_path, None)).service is None


def test_a_bundled_vehicle_without_the_block_says_why():
    for name in bundled_vehicles():
        if load_vehicle(name).service is None:
            assert "No service: block (issue #55 item 2):" in resolve_vehicle(name).read_text(), name


BAD = [
    ({"command": {"stern": 10}, "speed": 1.5}, r"field 'service.command.stern': the vehicle has thrusters propeller; "
     r"expected one of them"),
    ({"force": [1, 0, 0, 0, 0, 0], "speed": -1.5}, r"field 'service.speed' = -1.5: expected a speed > 0 \(m/s\)"),
    ({"force": [1, 0, 0, 0, 0, 0], "speed": 0}, r"field 'service.speed' = 0.0: expected a speed > 0 \(m/s\)"),
    ({"force": [1, 0, 0], "speed": 1.5}, r"field 'service.force' = \[1, 0, 0\]: expected 6 numbers X, Y, Z \(N\), K, M, N \(N·m\)"),
    ({"force": [1, 0, 0, 0, 0, "x"], "speed": 1.5}, r"field 'service.force"),
    ({"command": {"propeller": "fast"}, "speed": 1.5}, r"field 'service.command.propeller' = 'fast'"),
    ({"command": {"propeller": 11.0}}, r"field 'service' has no 'speed': expected the steady speed it reaches \(m/s\)"),
    ({"speed": 1.5}, r"field 'service': no 'command' and no 'force'; expected one of them or both"),
    ({"force": [1, 0, 0, 0, 0, 0], "speed": 1.5, "rpm": 600}, r"unknown field 'service.rpm'; expected one of command, force, speed"),
    ({"command": [11.0], "speed": 1.5}, r"field 'service.command'"),
    ([1.5], r"field 'service'"),
]  # fmt: skip


@pytest.mark.parametrize(("service", "message"), BAD, ids=[str(i) for i in range(len(BAD))])
def test_a_bad_block_is_one_line_naming_the_file_and_field(tmp_path, service, message):
    path = _remus(tmp_path, service)
    with pytest.raises(InputError, match=message) as info:
        hydrokit.load_vehicle(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_a_command_beyond_the_thruster_limits_is_refused(tmp_path):
    # max_rpm 1525: ±25.4167 rev/s
    path = _remus(tmp_path, {"command": {"propeller": 30}, "speed": 1.5})
    with pytest.raises(
        InputError, match=re.escape("field 'service.command': command propeller=30 rev/s: expected within")
    ):
        hydrokit.load_vehicle(path)


def test_a_command_needs_thrusters(tmp_path):
    doc = yaml.safe_load(resolve_vehicle("mariner").read_text())
    doc["service"] = {"command": {"prop": 10}, "speed": 7.7}
    path = tmp_path / "ship.yaml"
    path.write_text(yaml.safe_dump(doc))
    with pytest.raises(InputError, match=r"service.command.prop': the vehicle has no 'thrusters:' block"):
        load_vehicle(path)


def test_the_writer_keeps_the_block(tmp_path):
    doc = yaml.safe_load(resolve_vehicle("remus100-fins").read_text())
    path = tmp_path / "w.yaml"
    path.write_text(vehicle_text(doc, "written"))
    assert hydrokit.load_vehicle(path).service == hydrokit.load_vehicle("remus100-fins").service
