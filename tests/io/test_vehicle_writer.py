"""The one writer of vehicle files (issue #50): :func:`hydrokit.io.vehicle.vehicle_text` and the
identified vehicle's document."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import yaml

from hydrokit.io.vehicle import identified_vehicle_document, load_vehicle, resolve_vehicle, vehicle_text
from hydrokit.io.yamlfile import read_yaml


def test_vehicle_text_reads_back_as_the_same_vehicle(tmp_path: Path) -> None:
    doc = read_yaml(resolve_vehicle("bluerov2-heavy"))
    text = vehicle_text(doc, "# written by a test\nproject: not yaml\n")
    lines = text.splitlines()
    # a header line that is not a comment is made one, so it can never be read as YAML
    assert lines[:2] == ["# written by a test", "# project: not yaml"]
    assert yaml.safe_load(text) == doc
    path = tmp_path / "v.yaml"
    path.write_text(text, encoding="utf-8")
    again, original = load_vehicle(path), load_vehicle("bluerov2-heavy")
    for attr in ("M_A", "D_L", "D_Q", "M_RB"):
        np.testing.assert_array_equal(getattr(again, attr), getattr(original, attr))


def test_identified_document_writes_values_and_sigmas() -> None:
    """Identified diagonals replace the base's; σ is the square root of the covariance's diagonal."""
    base = read_yaml(resolve_vehicle("bluerov2-heavy"))
    result = SimpleNamespace(
        parameters=["added_mass.surge", "linear_damping.yaw"],
        values=[7.5, 2.25],
        covariance=[[4.0, 0.5], [0.5, 0.09]],
        method="output-error",
        runs=[{"name": "dive1", "holdout": False}, {"name": "dive2", "holdout": True}],
    )
    doc = identified_vehicle_document(result, base)
    assert doc["added_mass"][0] == 7.5 and doc["linear_damping"][5] == 2.25
    assert doc["added_mass"][1:] == [float(x) for x in base["added_mass"][1:]]
    unc = doc["uncertainty"]
    assert unc["added_mass"][0] == 2.0 and math.isclose(unc["linear_damping"][5], 0.3)
    assert unc["parameters"] == result.parameters and unc["covariance"] == result.covariance
    assert doc["name"] == f"{base['name']}-sysid" and "from runs dive1;" in doc["sources"][-1]
