"""Identified surface, thruster and wind fields written back into a vehicle document
(:mod:`hydrokit.io.fields`): the written document loads back with each value where the model
reads it (:func:`hydrokit.model.uncertainty.parameter_value`, the one reader of the names), the
base document is not changed, and a name the document cannot hold is one line."""

from __future__ import annotations

import copy
from typing import Any

import pytest
from tests.simulate.test_acceptance_race_rudder import HULL, NEUTRAL_DEG, RACE_RUDDER, SHIP, WIND
from tests.simulate.test_sysid_wind import TABLE

from hydrokit.errors import InputError
from hydrokit.io.fields import is_field, write_fields
from hydrokit.model.uncertainty import parameter_value

VALUES = {
    "control_surfaces.rudder.lift_slope": 3.1,
    "control_surfaces.rudder.neutral_deflection_deg": -0.8,
    "control_surfaces.rudder.kappa": 0.45,
    "control_surfaces.rudder.l_R": -1.4,
    "thrusters.prop.wake_fraction": 0.25,
    "thrusters.prop.thrust_deduction": 0.15,
    "wind.CD_t": 0.81,
    "wind.s_L": -0.05,
    "wind.lateral_area": 0.45,
}


def _doc(**extra: Any) -> dict[str, Any]:
    d = copy.deepcopy(SHIP)
    d["control_surfaces"] = [{**copy.deepcopy(RACE_RUDDER), "neutral_deflection_deg": NEUTRAL_DEG}]
    d["terms"] = {**{k: v for k, v in SHIP["terms"].items() if "delta" not in k}, **HULL}
    d["wind"] = copy.deepcopy(WIND)
    d.update(extra)
    return d


def test_written_fields_load_back_where_the_model_reads_them() -> None:
    from hydrokit.api import vehicle_from_dict

    base = _doc()
    before = copy.deepcopy(base)
    doc = write_fields({**base}, list(VALUES.items()))
    assert base == before  # the base document is not changed
    v = vehicle_from_dict(doc, "written")
    for name, value in VALUES.items():
        assert parameter_value(v, name) == pytest.approx(value, rel=1e-12), name
    assert "vessel" not in doc["wind"] and doc["wind"]["parameters"] == [0.81, 0.90, 0.55, 0.40]
    assert all(is_field(n) for n in VALUES) and not is_field("terms.Y_uv")

    table = write_fields(_doc(wind=copy.deepcopy(TABLE)), [("wind.coefficients.C_Y.90", -1.2)])
    assert parameter_value(vehicle_from_dict(table, "t"), "wind.coefficients.C_Y.90") == -1.2
    assert table["wind"]["coefficients"]["C_Y"] == [0.0, -1.2, 0.0]


def test_a_field_the_document_cannot_hold_is_one_line() -> None:
    with pytest.raises(InputError, match=r"no row at 45° to write wind.coefficients.C_Y.45"):
        write_fields(_doc(wind=copy.deepcopy(TABLE)), [("wind.coefficients.C_Y.45", -1.0)])
    with pytest.raises(InputError, match=r"'control_surfaces': no entry named 'fin'"):
        write_fields(_doc(), [("control_surfaces.fin.lift_slope", 3.0)])
    with pytest.raises(InputError, match=r"field 'wind': none to write"):
        write_fields(_doc(wind=None), [("wind.CD_t", 0.8)])
