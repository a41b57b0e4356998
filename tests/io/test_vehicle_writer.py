"""The one writer of vehicle files (issue #50): :func:`hydrokit.io.vehicle.vehicle_text` and the
identified vehicle's document."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
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


def test_identified_document_writes_surface_thruster_and_wind_fields() -> None:
    """A fit that frees a rudder's lift slope and neutral deflection, a propeller's wake fraction
    and a wind coefficient writes them where the file keeps them: the document loads back as a
    vehicle that flies the fitted values (read by the model's own reader of the names), so the
    uncertainty block is centred on what the file holds (issue #48: before, they stayed at the
    base's values while the covariance listed them)."""
    import copy

    from tests.simulate.test_acceptance_race_rudder import HULL, NEUTRAL_DEG, RACE_RUDDER, SHIP, WIND

    from hydrokit.api import vehicle_from_dict
    from hydrokit.model.uncertainty import parameter_value

    base = copy.deepcopy(SHIP)
    base["control_surfaces"] = [{**copy.deepcopy(RACE_RUDDER), "neutral_deflection_deg": NEUTRAL_DEG}]
    base["terms"] = {**{k: v for k, v in SHIP["terms"].items() if "delta" not in k}, **HULL}
    base["wind"] = copy.deepcopy(WIND)
    fitted = {
        "control_surfaces.rudder.lift_slope": 3.05,
        "control_surfaces.rudder.neutral_deflection_deg": -0.7,
        "thrusters.prop.wake_fraction": 0.21,
        "wind.CD_t": 0.77,
        "terms.Y_uv": -280.0,
    }
    n = len(fitted)
    result = SimpleNamespace(
        parameters=list(fitted),
        values=list(fitted.values()),
        covariance=np.diag(np.full(n, 1e-4)).tolist(),
        method="output-error",
        runs=[{"name": "zz1", "holdout": False}],
    )
    before = copy.deepcopy(base)
    doc = identified_vehicle_document(result, base)
    assert base == before  # the base document is left as it was
    vehicle = vehicle_from_dict(yaml.safe_load(vehicle_text(doc, "# test")), "fitted")
    for name, value in fitted.items():
        assert parameter_value(vehicle, name) == pytest.approx(value, rel=1e-12), name
    assert doc["uncertainty"]["parameters"] == list(fitted)
