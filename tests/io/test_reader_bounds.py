"""The readers' bounds and echoes: ``output_every`` within the step count, long values cut in
messages, and the non-physical signs that still fly said as warnings (docs/hostile-input.md)."""

from __future__ import annotations

import pytest
import yaml

from hydrokit.core.validate import cut, cut_repr
from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.mission import parse_mission
from hydrokit.io.vehicle import parse_vehicle

MISSION = yaml.safe_load((DATA_DIR / "missions" / "minerva_square.yaml").read_text())  # 200 s at 0.05 s
VEHICLE = yaml.safe_load((DATA_DIR / "vehicles" / "minerva.yaml").read_text())
LONG = "y" * 100_000


def mission(**changes: object) -> dict:
    return {**MISSION, **changes}


def test_output_every_up_to_the_step_count_is_accepted():
    assert parse_mission(mission(output_every=4000), "m.yaml").output_every == 4000
    # dt that does not divide the duration: floor(10 / 0.3) = 33 steps
    assert parse_mission(mission(duration=10, dt=0.3, output_every=33), "m.yaml").output_every == 33


@pytest.mark.parametrize(
    ("changes", "says"),
    [
        ({"output_every": 4001}, "= 4001: expected a whole number from 1 to 4000"),
        ({"output_every": 10**30}, f"= {10**30}: expected a whole number from 1 to 4000"),
        ({"duration": 10, "dt": 0.3, "output_every": 34}, "= 34: expected a whole number from 1 to 33"),
    ],
)
def test_output_every_beyond_the_step_count_is_refused(changes, says):
    with pytest.raises(InputError) as info:
        parse_mission(mission(**changes), "m.yaml")
    assert str(info.value) == f"m.yaml: field 'output_every' {says} (the step count, duration / dt)"


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({"dt": LONG}, "field 'dt' = 'yyyy"),
        ({"vehicle": [LONG]}, "field 'vehicle' = ['yyyy"),
        ({"controller": LONG}, "field 'controller' = 'yyyy"),
        ({"output_every": LONG}, "field 'output_every' = 'yyyy"),
        ({LONG: 1}, "unknown field 'yyyy"),
        ({"initial": {LONG: 1}}, "field 'initial.yyyy"),
        ({"allocation": {"weights": LONG}}, "field 'allocation.weights' = 'yyyy"),
        ({"guidance": {**MISSION["guidance"], LONG: 1}}, "field 'guidance.yyyy"),
        ({"controllers": {LONG: {}}}, "field 'controllers.yyyy"),
        ({"controllers": {"pid": {LONG: {}}}}, "field 'controllers.pid.yyyy"),
    ],
)
def test_mission_messages_cut_long_values_and_keys(changes, field):
    with pytest.raises(InputError) as info:
        parse_mission(mission(**changes), "m.yaml")
    msg = str(info.value)
    assert field in msg and "(1000" in msg, msg  # cut, with the length said
    assert len(msg) < 300, msg[:400]


def test_vehicle_messages_cut_long_values():
    with pytest.raises(InputError) as info:
        parse_vehicle({**VEHICLE, "mass": LONG, "terms": {}}, "v.yaml")
    msg = str(info.value)
    assert msg.startswith("v.yaml: field 'mass' = 'yyyy") and msg.endswith("expected a number"), msg
    assert len(msg) < 200


def test_cut_keeps_short_text_and_shortens_long_text():
    assert cut("short") == "short"
    assert cut_repr(-2.0) == "-2.0"
    long = cut_repr(LONG)
    assert long.startswith("'yyy") and long.endswith("yyy' (100002 characters)") and len(long) < 110


# --- signs: said, not refused ------------------------------------------------------------------


def _with_diagonal(field: str, first: float) -> dict:
    values = list(VEHICLE[field])
    values[0] = first
    return {**VEHICLE, field: values}


@pytest.mark.parametrize(
    ("field", "first", "says"),
    [
        ("linear_damping", -29, "linear_damping has negative diagonal entries [-29.0, 41.0,"),
        ("added_mass", -293, "added_mass has negative diagonal entries [-293.0, 302.0,"),
    ],
)
def test_negative_diagonal_entries_that_still_fly_are_warned_about(field, first, says):
    # negative damping flies only when the file says it is intended (issue 32 class 6)
    doc = _with_diagonal(field, first) | ({"allow_negative_damping": True} if "damping" in field else {})
    veh = parse_vehicle(doc, "v.yaml")
    warned = [w for w in veh.warnings if w.startswith(says)]
    assert len(warned) == 1, veh.warnings
    assert ("energy is fed in at low speed" if field == "linear_damping" else "easier to accelerate") in warned[0]


@pytest.mark.parametrize(
    ("field", "says"),
    [
        ("linear_damping", r"field 'linear_damping': linear_damping has negative diagonal entries \[-29\.0, 41\.0,"),
        ("quadratic_damping", r"field 'quadratic_damping': quadratic_damping has negative entries \[-29\.0,"),
    ],
)
def test_negative_damping_is_refused_unless_allowed(field, says):
    with pytest.raises(InputError, match=says + r".*; expected entries ≥ 0, or 'allow_negative_damping: true'"):
        parse_vehicle(_with_diagonal(field, -29), "v.yaml")
    with pytest.raises(InputError, match=r"'allow_negative_damping' = 'yes': expected true or false"):
        parse_vehicle(_with_diagonal(field, -29) | {"allow_negative_damping": "yes"}, "v.yaml")
    allowed = parse_vehicle(_with_diagonal(field, -29) | {"allow_negative_damping": True}, "v.yaml")
    assert sum(w.startswith(f"{field} has negative") for w in allowed.warnings) == 1, allowed.warnings


def test_a_damping_derivative_with_the_wrong_sign_is_refused_unless_allowed():
    # SNAME: X_u|u| < 0 is drag; +50 pushes along the motion (a cross term such as X_vr is no damping)
    doc = dict(VEHICLE) | {"terms": {"X_u|u|": 50.0, "X_vr": 3.0, "X_uu": 2.0}}
    with pytest.raises(InputError, match=r"field 'terms\.X_u\|u\|': terms\.X_u\|u\| = 50 is positive .* ≤ 0, or"):
        parse_vehicle(doc, "v.yaml")
    allowed = parse_vehicle(doc | {"allow_negative_damping": True}, "v.yaml")
    assert [w for w in allowed.warnings if w.startswith("terms.")] == [
        "terms.X_u|u| = 50 is positive (a damping derivative is negative in SNAME): energy is fed in"
    ]
    assert not [
        w for w in parse_vehicle(dict(VEHICLE) | {"terms": {"X_u|u|": -50.0}}, "v.yaml").warnings if "terms" in w
    ]


def test_a_negative_added_mass_from_a_term_is_warned_about():
    # X_udot = +293 (the wrong SNAME sign) puts -293 on the diagonal of M_A
    doc = {**_with_diagonal("added_mass", 0.0), "terms": {"X_udot": 293.0}}
    veh = parse_vehicle(doc, "v.yaml")
    assert any(w.startswith("added_mass has negative diagonal entries [-293.0,") for w in veh.warnings), veh.warnings


def test_positive_diagonals_give_no_sign_warning():
    veh = parse_vehicle(dict(VEHICLE), "v.yaml")
    assert not [w for w in veh.warnings if "negative" in w], veh.warnings


@pytest.mark.parametrize("cog", [[0.0, 0.0, 6.25142268131704e152], [1e300, 0.0, 0.0]])
def test_a_centre_of_gravity_that_overflows_the_mass_matrix_is_one_line(cog):
    # found by the fuzz test: M_RB + M_A overflowed and LAPACK raised LinAlgError
    with pytest.raises(InputError, match=r"v\.yaml: fields .*center_of_gravity.* expected values of a realistic size"):
        parse_vehicle({**VEHICLE, "center_of_gravity": cog}, "v.yaml")
