"""System identification of the propeller–rudder features (issue #48 item 2, the sysid side):
free ``control_surfaces.NAME.FIELD`` and ``thrusters.NAME.FIELD`` names, T()/n() columns in the
force table, the table rebuilt per candidate vehicle when a thruster's field is free, and the
recovery of a race rudder's lift slope, a T()·δ term and the wake fraction from generated
zigzags."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest
from tests.simulate.test_sysid_surfaces import SHIP

from hydrokit.errors import InputError
from hydrokit.io.runlog import RunLog
from hydrokit.model.uncertainty import parameter_value, with_coefficients
from hydrokit.sysid.model import force_table, free_parameters, prepare_run, vehicle_tables

#: the rudder of SHIP made a physical fin in the MMG race of the propeller (our numbers, of the
#: size of a 3 m ship model's rudder), and the rudder's yaw moment grown with the thrust
RACE_RUDDER: dict[str, Any] = {
    "name": "rudder",
    "position": [-1.5, 0, 0],
    "max_deflection_deg": 35,
    "axis": [0, 0, 1],
    "area": 0.02,
    "lift_slope": 2.7,
    "stall_angle_deg": 30,
    "slipstream": {"thruster": "prop", "inflow": "mmg", "epsilon": 1.0, "kappa": 0.5, "eta": 0.8},
}
#: N per (N of thrust · rad of rudder): N·m/(N·rad) = m
N_T_DELTA = -0.3


def race_ship(**terms: float) -> Any:
    from hydrokit.api import vehicle_from_dict

    d = copy.deepcopy(SHIP)
    d["control_surfaces"] = [copy.deepcopy(RACE_RUDDER)]
    d["terms"] = {k: v for k, v in SHIP["terms"].items() if "delta" not in k}
    d["terms"]["N_T(prop)*delta(rudder)"] = N_T_DELTA
    d["terms"].update(terms)
    return vehicle_from_dict(d, "race-ship")


def _steady_run(u: float, n: float) -> RunLog:
    t = np.round(np.arange(0.0, 2.0, 0.1), 6)
    rudder = np.where(t >= 0.5, 0.2, 0.0)
    chans = {"u": (t, np.full(t.size, u))}
    return RunLog("steady", "steady", t, chans, {"prop": np.full(t.size, n)}, deflections={"rudder": rudder})


def test_free_field_names_join_the_fit_with_their_units() -> None:
    v = race_ship()
    names = [
        "control_surfaces.rudder.lift_slope",
        "control_surfaces.rudder.neutral_deflection_deg",
        "control_surfaces.rudder.kappa",
        "thrusters.prop.wake_fraction",
        "terms.N_T(prop)*delta(rudder)",
        "terms.Y_n(prop)*delta(rudder)",
    ]
    veh, params = free_parameters(v, names)
    assert [p.kind for p in params] == ["surface", "surface", "surface", "thruster", "term", "term"]
    assert [p.unit for p in params[:4]] == ["1/rad", "deg", "–", "–"]
    assert "Y_n(prop)*delta(rudder)" in veh.terms.names  # absent: added at 0
    assert [parameter_value(veh, n) for n in names] == [2.7, 0.0, 0.5, 0.3, N_T_DELTA, 0.0]


def test_a_bad_field_name_is_one_line_with_the_nearest_names() -> None:
    v = race_ship()
    with pytest.raises(InputError, match=r"rudder.lift_slop.*\(nearest: control_surfaces.rudder.lift_slope") as exc:
        free_parameters(v, ["control_surfaces.rudder.lift_slop"])
    assert "\n" not in str(exc.value)
    with pytest.raises(InputError, match=r"'rudderr' names no surface.*\(nearest: control_surfaces.rudder\."):
        free_parameters(v, ["control_surfaces.rudderr.lift_slope"])
    with pytest.raises(InputError, match=r"\(nearest: thrusters.prop.wake_fraction"):
        free_parameters(v, ["thrusters.prop.wake_fractio"])
    with pytest.raises(InputError, match=r"T\(screw\)"):
        free_parameters(v, ["terms.N_T(screw)*delta(rudder)"])


def test_force_table_carries_thrust_and_rate_at_the_wake_of_each_candidate() -> None:
    """At a steady measured surge speed u and propeller speed n the T column is the open-water
    curve by hand, K_T(J) ρ D⁴ n² with J = (1 − w) u/(n D) and K_T = 0.33 − 0.28 J (SHIP's
    kt_forward, highest power first), the n column is n; a candidate with another wake fraction
    gets its own table (its thrust by the same hand formula), one with the same thrusters none."""
    v = race_ship()
    u, n, D = 0.37, 20.0, 0.084
    run = _steady_run(u, n)
    tab = force_table(run, v.thrusters, 0.05, v.surfaces.names)
    assert tab.shape[1] == 1 + 6 + 1 + 2 + 1  # t, X..N, δ, T, n, the propeller's rotor state

    def by_hand(w: float) -> float:
        J = (1 - w) * u / (n * D)
        return (0.33 - 0.28 * J) * 1000.0 * D**4 * n**2

    np.testing.assert_allclose(tab[:, 8], by_hand(0.3), rtol=1e-12)  # same formula, round-off only
    np.testing.assert_allclose(tab[:, 9], n, rtol=0)
    np.testing.assert_allclose(tab[:, 10], n, rtol=0)  # the rotor state the simulation drives it from
    np.testing.assert_allclose(tab[:, 1], tab[:, 8], rtol=1e-12)  # X = T (no thrust deduction)
    prep = prepare_run(run, v.thrusters, 0.05, surfaces=v.surfaces.names)
    assert vehicle_tables(prep, [v, with_coefficients(v, {"control_surfaces.rudder.lift_slope": 3.0})]) is None
    other = with_coefficients(v, {"thrusters.prop.wake_fraction": 0.1, "thrusters.prop.thrust_deduction": 0.2})
    both = vehicle_tables(prep, [v, other])
    assert both is not None and both.shape == (2, *prep.table.shape)
    np.testing.assert_array_equal(both[0], prep.table)
    np.testing.assert_allclose(both[1][:, 8], by_hand(0.1), rtol=1e-12)
    np.testing.assert_allclose(both[1][:, 1], 0.8 * by_hand(0.1), rtol=1e-12)  # (1 − t) T


def test_race_rudder_lift_slope_thrust_term_and_wake_fraction_are_recovered() -> None:
    """Generated zigzags of the race-rudder ship (the compiled RK4 at 0.01 s with the thrust at
    the true advance speed, sysid_ship) fitted at 0.02 s from a start 30 % off: the rudder's lift
    slope, the T()·δ yaw term and the wake fraction each within 3σ of the truth (on seeds 5–7
    the largest miss was 2.2σ). The wake fraction is seen only through the thrust, so it is
    identified only because each candidate's force table is its own."""
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.ship import ship_runs

    truth = race_ship()
    runs = ship_runs(truth, 2, 30.0, seed=7, dt=0.01, hold=(3.0, 8.0))
    free = ["terms.N_T(prop)*delta(rudder)", "control_surfaces.rudder.lift_slope", "thrusters.prop.wake_fraction"]
    base = with_coefficients(
        race_ship(**{"N_T(prop)*delta(rudder)": 0.7 * N_T_DELTA}),
        {"control_surfaces.rudder.lift_slope": 2.0, "thrusters.prop.wake_fraction": 0.2},
    )
    res = identify(base, runs, free, dt=0.02, samples=0, check_step=False, window=None)
    assert res.units == ("m", "1/rad", "–") or res.units[1:] == ("1/rad", "–")
    for name, value, sigma in zip(res.parameters, res.values, res.sigma):
        true = parameter_value(truth, name)
        assert 0 < sigma < 0.2 * abs(true), (name, sigma)
        assert abs(value - true) < 3 * sigma, (name, value, sigma, true)
        assert abs(value - parameter_value(base, name)) > 3 * sigma  # it moved from the start
    assert math.isclose(parameter_value(res.vehicle, "thrusters.prop.wake_fraction"), res.values[2])


def test_windowed_fit_keeps_the_physical_signs_during_the_fit() -> None:
    """A windowed fit of a damping that the runs push negative (the truth has no linear yaw
    damping, the base a rudder 45 % too weak: fitted unbounded it goes to about −46 N·m·s/rad):
    no evaluated vehicle leaves the bound during the fit (the Jacobian's nudges go inwards), and
    the result is held on it with the bound's message."""
    from hydrokit.sysid import fit as sysid_mod
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.ship import ship_runs

    truth = race_ship()
    runs = ship_runs(truth, 1, 40.0, seed=3, dt=0.01, hold=(3.0, 8.0))
    base = with_coefficients(race_ship(), {"control_surfaces.rudder.lift_slope": 1.5})
    seen: list[float] = []
    original = sysid_mod.with_values

    def spy(vehicle: Any, params: Any, values: Any) -> Any:
        out = original(vehicle, params, values)
        seen.append(parameter_value(out, "linear_damping.yaw"))
        return out

    import hydrokit.sysid.problem as prob
    import hydrokit.sysid.window as win

    try:
        sysid_mod.with_values = spy
        win.with_values = spy
        prob.with_values = spy
        res = identify(base, runs, ["linear_damping.yaw"], dt=0.02, samples=0, check_step=False, window=10.0)
    finally:
        sysid_mod.with_values = original
        win.with_values = original
        prob.with_values = original
    assert len(seen) > 3 and min(seen) >= 0.0, min(seen)
    assert res.values[0] == 0.0 and any("held at its physical bound" in m for m in res.messages)
