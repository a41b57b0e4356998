"""Free coefficients of a vehicle's wind-load model (issue #48 item 4, ``--free wind.FIELD``): the
names, their units and values, a bad name's one-line error with the nearest names, a draw that
keeps a table coefficient's sign, and the recovery of Blendermann's CD_t from generated runs in a
logged wind."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from tests.simulate.test_acceptance_race_rudder import wind_ship, wind_ship_runs

from hydrokit.errors import InputError
from hydrokit.model.uncertainty import make_uncertainty, parameter_value, with_coefficients
from hydrokit.sysid.model import free_parameters

#: a wind table of our own (rows at 0, 90, 180°: the port side mirrors), dimensionless
TABLE: dict[str, Any] = {
    "frontal_area": 0.06,
    "lateral_area": 0.4,
    "length": 3.0,
    "coefficients": {
        "angle_deg": [0, 90, 180],
        "C_X": [-0.6, 0.05, 0.5],
        "C_Y": [0.0, -0.8, 0.0],
        "C_N": [0.0, -0.05, 0.0],
    },
}


def test_wind_fields_are_free_names_with_their_units_and_values() -> None:
    v = wind_ship()
    names = ["wind.CD_t", "wind.lateral_area", "wind.s_L", "wind.CD_l_AF_bow", "wind.delta"]
    _, params = free_parameters(v, names)
    assert [p.kind for p in params] == ["wind"] * 5
    assert [p.unit for p in params] == ["–", "m²", "m", "–", "–"]
    # Blendermann's loaded tanker, as the MSS toolbox's blendermann94.m tabulates it
    assert [parameter_value(v, n) for n in names] == [0.70, 0.4, 0.1, 0.90, 0.40]
    moved = with_coefficients(v, {"wind.CD_t": 0.8, "wind.s_L": -0.2})
    assert moved.wind.parameters == (0.8, 0.90, 0.55, 0.40) and moved.wind.s_L == -0.2
    assert moved.wind.vessel is None  # no longer Blendermann's tanker
    assert v.wind.parameters[0] == 0.70  # the base is not changed
    # the new CD_t acts: the beam-wind side force scales with it (C_Y = −CD_t at 90°, den = 1)
    assert moved.wind.coefficients(math.pi / 2)[1] == pytest.approx(-0.8, rel=1e-12)

    t = wind_ship(wind=copy.deepcopy(TABLE))
    _, params = free_parameters(t, ["wind.coefficients.C_Y.90", "wind.coefficients.C_N.90", "wind.frontal_area"])
    assert [p.unit for p in params] == ["–", "–", "m²"]
    assert parameter_value(t, "wind.coefficients.C_Y.90.0") == -0.8  # the angle as any number
    moved = with_coefficients(t, {"wind.coefficients.C_Y.90": -1.1})
    assert moved.wind.C_Y == (0.0, -1.1, 0.0)
    assert moved.wind.coefficients(math.pi / 4)[1] == pytest.approx(-0.55, rel=1e-12)  # halfway to the row


def test_a_bad_wind_name_is_one_line_with_the_nearest_names() -> None:
    v = wind_ship()
    with pytest.raises(InputError, match=r"'wind.CD_T'.*\(nearest: wind.CD_t") as exc:
        free_parameters(v, ["wind.CD_T"])
    assert "\n" not in str(exc.value)
    with pytest.raises(InputError, match=r"wind model is 'blendermann1994', which has no table"):
        free_parameters(v, ["wind.coefficients.C_Y.90"])
    t = wind_ship(wind=copy.deepcopy(TABLE))
    with pytest.raises(InputError, match=r"no row of the wind table at 45°; expected one of its angle_deg: 0, 90, 180"):
        free_parameters(t, ["wind.coefficients.C_Y.45"])
    with pytest.raises(InputError, match=r"'table', which has no CD_t"):
        free_parameters(t, ["wind.CD_t"])
    no_wind = wind_ship(wind=None)
    with pytest.raises(InputError, match=r"has no wind model; expected a 'wind:' block"):
        free_parameters(no_wind, ["wind.CD_t"])
    with pytest.raises(InputError, match=r"names 'wind.coefficients.C_Y.90.0' twice \(as 'wind.coefficients.C_Y.90'\)"):
        make_uncertainty(["wind.coefficients.C_Y.90", "wind.coefficients.C_Y.90.0"], np.eye(2), {}, "v.yaml")


def test_a_draw_keeps_a_table_coefficients_sign_and_clips_an_area_at_zero() -> None:
    t = wind_ship(wind=copy.deepcopy(TABLE))
    unc = make_uncertainty(["wind.coefficients.C_Y.90", "wind.frontal_area"], np.diag([0.01, 0.01]), {}, "v.yaml")
    assert unc is not None
    _, values, clipped = unc.sample_vehicles(t, 400, 1)
    assert np.all(values[:, 0] < 0)  # −0.8 ± 0.1: never clipped at 0
    assert np.min(values[:, 1]) == 0.0 and clipped > 0  # 0.06 ± 0.1: below 0 set to 0


@pytest.mark.needs_jit(reason="two 30 s runs fitted by output error")
def test_blendermann_cd_t_is_recovered_from_runs_in_a_logged_wind() -> None:
    """Two 30 s zigzag-like runs in a logged 2.5 m/s wind (:func:`wind_ship_runs`), fitted from
    CD_t 30 % low and Y_uv 30 % low: both within 3σ of the truth, σ(CD_t) under 10 % of it, and
    CD_t moved from its start by more than 3σ (the runs, not the start, decide it)."""
    from hydrokit.sysid.fit import identify

    truth = wind_ship()
    runs = wind_ship_runs(truth, 2, 30.0, seed=3)
    assert runs[0].environment_table() is not None  # the wind is in the runs, logged
    free = ["wind.CD_t", "terms.Y_uv"]
    start = with_coefficients(truth, {n: 0.7 * parameter_value(truth, n) for n in free})
    res = identify(start, runs, free, dt=0.02, samples=0, check_step=False, window=None)
    for name, value, sigma in zip(res.parameters, res.values, res.sigma):
        true = parameter_value(truth, name)
        assert abs(value - true) < 3 * sigma, (name, value, sigma, true)
        assert abs(value - parameter_value(start, name)) > 3 * sigma, (name, value, sigma)
    assert 0 < res.sigma[0] < 0.1 * parameter_value(truth, "wind.CD_t")
    assert parameter_value(res.vehicle, "wind.CD_t") == pytest.approx(res.values[0], rel=1e-12)


def _ship_file(tmp_path: Path, **extra: Any) -> Path:
    """The wind ship (:func:`wind_ship`) as a vehicle file, with ``extra`` top-level fields."""
    import yaml
    from tests.simulate.test_acceptance_race_rudder import HULL, NEUTRAL_DEG, RACE_RUDDER, SHIP, WIND

    d = copy.deepcopy(SHIP)
    d["control_surfaces"] = [{**copy.deepcopy(RACE_RUDDER), "neutral_deflection_deg": NEUTRAL_DEG}]
    d["terms"] = {**{k: v for k, v in SHIP["terms"].items() if "delta" not in k}, **HULL}
    d["wind"] = copy.deepcopy(WIND)
    d.update(extra)
    path = tmp_path / "ship.yaml"
    path.write_text(yaml.safe_dump(d, sort_keys=False))
    return path


def test_a_vehicle_file_whose_uncertainty_names_wind_fields_loads_and_draws(tmp_path: Path) -> None:
    """What ``sysid`` writes for a free wind field — its name in ``uncertainty.parameters`` —
    loads back, and the draws of ``--samples`` move the wind model (σ of CD_t 0.1: the draws'
    spread within 25 % of it over 200 draws)."""
    from hydrokit.api import load_vehicle

    unc = {"parameters": ["wind.CD_t", "control_surfaces.rudder.lift_slope"], "covariance": [[0.01, 0], [0, 0.04]]}
    v = load_vehicle(str(_ship_file(tmp_path, uncertainty=unc)))
    assert v.uncertainty is not None and v.uncertainty.parameters[0] == "wind.CD_t"
    drawn, values, _ = v.uncertainty.sample_vehicles(v, 200, 4)
    cd_t = np.array([d.wind.parameters[0] for d in drawn])
    np.testing.assert_array_equal(cd_t, values[:, 0])
    assert abs(float(np.std(cd_t)) - 0.1) < 0.025 and abs(float(np.mean(cd_t)) - 0.70) < 0.03


def test_the_command_line_refuses_a_bad_wind_name_in_one_line(tmp_path: Path, run_cli: Any) -> None:
    vehicle = _ship_file(tmp_path)
    run = tmp_path / "run.csv"
    run.write_text("time,x,y,psi,u,v,r,prop,rudder,wind_speed,wind_direction\n0,0,0,0,0.37,0,0,20,0,2,0\n")
    code, out, err = run_cli(
        "sysid", run, "--vehicle", vehicle, "--free", "wind.CD_T,terms.Y_uv", "--out", tmp_path / "fit"
    )
    assert code == 2 and "Traceback" not in err
    assert "'wind.CD_T'" in err and "(nearest: wind.CD_t" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "fit").exists()


def test_a_fit_keeps_wind_fields_inside_the_range_the_file_accepts() -> None:
    """The fit's bounds on wind fields are the wind block's own checks (model/wind.make_wind):
    areas and CD_t > 0, the longitudinal drag numbers ≥ 0, δ within 0–1; s_L and a table's
    coefficients take either sign — so a fit never writes a wind block hydrokit refuses."""
    from hydrokit.model.wind import make_wind
    from hydrokit.sysid.fit import _bounds

    v = wind_ship()
    names = ["wind.CD_t", "wind.lateral_area", "wind.s_L", "wind.delta", "wind.CD_l_AF_stern"]
    _, params = free_parameters(v, names)
    lower, upper = _bounds(v, params)
    cd_t_floor, area_floor = float(lower[0]), float(lower[1])
    assert 0.0 < cd_t_floor < 1e-6 and 0.0 < area_floor < 1e-6
    assert list(lower[2:]) == [-math.inf, 0.0, 0.0]
    assert list(upper) == [math.inf, math.inf, math.inf, 1.0, math.inf]
    t = wind_ship(wind=copy.deepcopy(TABLE))
    _, params = free_parameters(t, ["wind.coefficients.C_Y.90", "wind.frontal_area"])
    lower, upper = _bounds(t, params)
    assert lower[0] == -math.inf and 0.0 < lower[1] < 1e-6 and list(upper) == [math.inf, math.inf]
    # every end of those ranges is accepted by the file's checks, and the next step past is refused
    make_wind(area_floor, area_floor, 3.0, model="blendermann1994", parameters=[cd_t_floor, 0.0, 0.0, 1.0])
    for bad in ([0.0, 0.9, 0.5, 0.4], [0.7, 0.9, 0.5, 1.0 + 1e-9], [0.7, -1e-9, 0.5, 0.4]):
        with pytest.raises(InputError, match="wind.parameters"):
            make_wind(0.1, 0.4, 3.0, model="blendermann1994", parameters=bad)
    with pytest.raises(InputError, match="wind.frontal_area"):
        make_wind(0.0, 0.4, 3.0, model="blendermann1994", vessel="tanker_loaded")
