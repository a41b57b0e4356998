"""Physical-sign bounds of a fit (issue #49 item 6): a free damping never comes out feeding
energy in, so hydrokit never writes a vehicle file it would itself refuse."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.model.uncertainty import check_parameter, physical_sign


@pytest.mark.parametrize(
    ("name", "sign"),
    [
        ("linear_damping.surge", 1),
        ("quadratic_damping.yaw", 1),
        ("added_mass.sway", 1),
        ("terms.N_r|r|", -1),  # odd in r alone: N_r|r| r|r| opposes the yaw rate when negative
        ("terms.X_u|u|", -1),
        ("terms.N_rrr", -1),
        ("terms.X_uu", 0),  # even in u: not a damping of its own DOF (the loader does not refuse it)
        # the forward speed scales the own-DOF damping (Y_v = Y_uv u): ≤ 0 for a vehicle moving
        # ahead — the Esso Osaka pond trials fitted unbounded gave Y_uv = +292 (anti-damping)
        ("terms.Y_uv", -1),
        ("terms.N_ur", -1),
        ("terms.Z_uw", -1),
        ("terms.M_uq", -1),
        ("terms.Y_|u|v", -1),
        ("terms.Y_uuv", -1),
        ("terms.Y_ur", 0),  # a cross term (sway force from yaw rate): either sign
        ("terms.N_uv", 0),  # the Munk moment and its kin: either sign
        ("terms.Y_uv|v|", -1),
        ("terms.X_uuu", -1),  # surge: u is its own velocity (odd: a resistance when negative)
        ("terms.N_r", -1),
        ("terms.Y_vdot", -1),  # −M_A[1, 1]
        ("terms.Y_rdot", 0),  # a coupling entry of M_A: either sign
    ],
)
def test_the_physical_sign_of_each_kind_of_parameter(name: str, sign: int) -> None:
    assert physical_sign(check_parameter(name, "parameter", "")) == sign


@pytest.fixture(scope="module")
def pushed() -> tuple[Any, list[Any]]:
    """Dives of a vehicle, and a base whose fixed surge quadratic damping is 3 × the truth: a
    free linear surge damping then makes up for it by going negative."""
    import hydrokit
    from hydrokit.sysid.data import generate_runs, hidden_vehicle
    from hydrokit.sysid.model import free_parameters, values_of, with_values

    truth = hidden_vehicle(hydrokit.load_vehicle("bluerov2-sysid"), 2)
    v, params = free_parameters(truth, ["quadratic_damping.surge"])
    return with_values(v, params, values_of(v, params) * 3), generate_runs(truth, 2, 8.0, seed=5, dt=0.01)


@pytest.mark.needs_jit(reason="two output-error fits of two surge coefficients over 8 s of dives")
def test_a_damping_the_data_push_negative_is_held_at_zero_and_the_file_loads(pushed: Any) -> None:
    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.vehicle import resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml
    from hydrokit.report.sysid import vehicle_document
    from hydrokit.sysid.fit import identify

    base, runs = pushed
    free = ["added_mass.surge", "linear_damping.surge"]
    kw: dict[str, Any] = {"holdout": runs[1:], "samples": 0, "check_step": False}
    loose = identify(base, runs[:1], free, bounds=False, **kw)
    assert loose.values[1] < 0  # unbounded, the fit feeds energy in …
    doc = yaml.safe_load(yaml.safe_dump(vehicle_document(loose, read_yaml(resolve_vehicle("bluerov2-sysid")))))
    with pytest.raises(InputError, match="linear_damping"):
        vehicle_from_dict(doc, "unbounded fit")  # … and hydrokit refuses what it would write
    held = identify(base, runs[:1], free, **kw)
    assert held.values[1] == 0.0
    assert any(m.startswith("linear_damping.surge is held at its physical bound 0") for m in held.messages)
    assert not any("not identifiable" in m and m.startswith("linear_damping.surge") for m in held.messages)
    doc = vehicle_document(held, read_yaml(resolve_vehicle("bluerov2-sysid")))
    v = vehicle_from_dict(yaml.safe_load(yaml.safe_dump(doc)), "bounded fit")
    assert v.D_L[0, 0] == 0.0 and v.M_A[0, 0] == pytest.approx(held.values[0])
    # the bound does not hide the cause: the wrong fixed damping still fails the verdict
    assert held.verdict["fits"] is False
    np.testing.assert_array_less(0.0, held.values[0])
