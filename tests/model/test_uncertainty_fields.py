"""Surface and thruster fields as free parameters (issue #48 item 2): the frozen names
``control_surfaces.NAME.FIELD`` and ``thrusters.NAME.FIELD``."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from tests.model.test_propeller_rudder import SHIP

from hydrokit.api import vehicle_from_dict
from hydrokit.errors import InputError
from hydrokit.model.dynamics import pack, vehicle_dynamics
from hydrokit.model.uncertainty import (
    check_parameter,
    field_unit,
    location,
    parameter_value,
    with_coefficients,
)

FIN = {"axis": [0, 0, 1], "area": 0.02, "lift_slope": 3.0, "stall_angle_deg": 25}


def ship(mmg: bool = True) -> dict:
    doc = copy.deepcopy(SHIP)
    doc["thrusters"][0]["wake_fraction"] = 0.3
    race = {"thruster": "prop"}
    if mmg:
        race.update({"inflow": "mmg", "kappa": 0.5, "epsilon": 1.05, "eta": 0.8, "l_R": -1.2})
    doc["control_surfaces"][0].update({**FIN, "slipstream": race})
    return doc


def test_the_frozen_names_parse_and_bad_ones_are_one_line():
    surfaces, thrusters = ("rudder", "fin.port"), ("prop", "bow")
    ref = check_parameter("control_surfaces.fin.port.neutral_deflection_deg", "p", "", surfaces, thrusters)
    assert (ref.kind, ref.index, ref.field) == ("surface", 1, "neutral_deflection_deg")
    ref = check_parameter("thrusters.bow.wake_fraction", "p", "", surfaces, thrusters)
    assert (ref.kind, ref.index, ref.field, ref.dof) == ("thruster", 1, "wake_fraction", 0)
    assert location(ref) == ("thruster", 1, "wake_fraction")
    for name, match in (
        ("control_surfaces.rudder.chord", r"field one of lift_slope, neutral_deflection_deg"),
        ("control_surfaces.flap.lift_slope", r"'flap' names no surface of the vehicle \(control_surfaces: rudder"),
        ("thrusters.screw.wake_fraction", r"'screw' names no thruster of the vehicle \(thrusters: prop, bow\)"),
        ("thrusters.prop.max_rpm", r"field one of wake_fraction, thrust_deduction"),
    ):
        with pytest.raises(InputError, match=match) as err:
            check_parameter(name, "--free", "", surfaces, thrusters)
        assert "\n" not in str(err.value)
    assert field_unit("control_surfaces.rudder.lift_slope") == "1/rad"
    assert field_unit("control_surfaces.rudder.neutral_deflection_deg") == "deg"
    assert field_unit("thrusters.prop.thrust_deduction") == "–"


def test_fields_read_and_set_on_a_vehicle():
    v = vehicle_from_dict(ship(), "s")
    assert parameter_value(v, "control_surfaces.rudder.lift_slope") == 3.0
    assert parameter_value(v, "control_surfaces.rudder.kappa") == 0.5
    assert parameter_value(v, "thrusters.prop.wake_fraction") == 0.3
    w = with_coefficients(
        v,
        {
            "control_surfaces.rudder.lift_slope": 4.5,
            "control_surfaces.rudder.neutral_deflection_deg": 2.0,
            "control_surfaces.rudder.kappa": 0.7,
            "thrusters.prop.wake_fraction": 0.1,
            "thrusters.prop.thrust_deduction": 0.2,
        },
    )
    fin = w.surfaces.surfaces[0].fin
    assert fin.lift_slope == 4.5 and fin.kappa == 0.7
    assert fin.neutral_deflection == pytest.approx(math.radians(2.0))
    assert parameter_value(w, "control_surfaces.rudder.neutral_deflection_deg") == pytest.approx(2.0)
    # the race follows the thruster's wake fraction; the thruster set is rebuilt with it
    assert fin.wake_fraction == 0.1 and w.thrusters.thrusters[0].wake_fraction == 0.1
    assert w.thrusters.advance_speed([1.0, 0, 0, 0, 0, 0])[0] == pytest.approx(0.9)
    np.testing.assert_allclose(w.thrusters.configuration_matrix()[0, 0], 0.8, rtol=1e-15)
    # the base vehicle is untouched
    assert v.surfaces.surfaces[0].fin.lift_slope == 3.0 and v.thrusters.thrusters[0].thrust_deduction == 0.0
    # the packed fin row carries the new values into both right-hand sides
    first = pack(w).scal
    assert 4.5 in first and 0.7 in first


def test_a_free_lift_slope_scales_the_fin_force():
    # attached flow, no drag (C_D0 = 0, no aspect ratio): the fin's force is linear in C_Lα
    v = vehicle_from_dict(ship(mmg=False), "s")
    w = with_coefficients(v, {"control_surfaces.rudder.lift_slope": 6.0})
    x = np.zeros(12)
    x[6] = 0.8
    tau = np.zeros(6)
    d = np.array([0.1])
    rest_v = vehicle_dynamics(v)(0.0, x, tau)[6:]
    rest_w = vehicle_dynamics(w)(0.0, x, tau)[6:]
    fin_v = vehicle_dynamics(v)(0.0, x, tau, d)[6:] - rest_v
    fin_w = vehicle_dynamics(w)(0.0, x, tau, d)[6:] - rest_w
    np.testing.assert_allclose(fin_w, 2.0 * fin_v, rtol=1e-12, atol=1e-15)


def test_a_field_the_surface_does_not_have_is_one_line():
    v = vehicle_from_dict(ship(mmg=False), "s")
    with pytest.raises(
        InputError, match=r"'rudder' has no kappa; expected a surface with a slipstream with inflow: mmg"
    ):
        with_coefficients(v, {"control_surfaces.rudder.kappa": 0.4})
    bare = vehicle_from_dict(copy.deepcopy(SHIP), "s")
    with pytest.raises(InputError, match=r"has no lift_slope; expected a surface with a physical fin"):
        parameter_value(bare, "control_surfaces.rudder.lift_slope")
    with pytest.raises(InputError, match=r"wake_fraction = 1\.2: expected 0 ≤ w < 1"):
        with_coefficients(v, {"thrusters.prop.wake_fraction": 1.2})


def test_an_uncertainty_block_draws_surface_and_thruster_fields():
    doc = ship()
    doc["uncertainty"] = {
        "parameters": ["control_surfaces.rudder.lift_slope", "thrusters.prop.wake_fraction", "terms.X_0"],
        "covariance": [[0.04, 0, 0], [0, 0.0004, 0], [0, 0, 1.0]],
    }
    doc["terms"] = {"X_0": -2.0}
    v = vehicle_from_dict(doc, "s")
    vehicles, values, clipped = v.uncertainty.sample_vehicles(v, 200, seed=3)
    assert clipped == 0 and values.shape == (200, 3)
    # each vehicle carries its own draw; the sample's spread is the stated σ (200 draws: ±15 %)
    slopes = np.array([x.surfaces.surfaces[0].fin.lift_slope for x in vehicles])
    np.testing.assert_array_equal(slopes, values[:, 0])
    assert np.std(values[:, 0]) == pytest.approx(0.2, rel=0.15)
    assert np.std(values[:, 1]) == pytest.approx(0.02, rel=0.15)
    wakes = np.array([x.surfaces.surfaces[0].fin.wake_fraction for x in vehicles])
    np.testing.assert_array_equal(wakes, values[:, 1])
    bad = copy.deepcopy(doc)
    bad["uncertainty"]["parameters"][0] = "control_surfaces.rudder.lift_slope_deg"
    with pytest.raises(InputError, match=r"uncertainty\.parameters\[0\]' = .*expected 'control_surfaces\.<name>"):
        vehicle_from_dict(bad, "s")


def test_parameter_ref_is_the_hook_for_a_fit():
    from hydrokit.model.uncertainty import parameter_ref

    v = vehicle_from_dict(ship(), "s")
    ref = parameter_ref(v, "thrusters.prop.thrust_deduction")
    assert (ref.kind, ref.index, ref.field) == ("thruster", 0, "thrust_deduction")
    with pytest.raises(InputError, match=r"^--free 'thrusters\.bow\.kappa': expected 'thrusters\.<name>\.<field>'"):
        parameter_ref(v, "thrusters.bow.kappa", "--free")
