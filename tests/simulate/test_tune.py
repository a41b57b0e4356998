"""Gain tuning: a tiny seeded search through the CLI, its outputs, and bad input (exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hydrokit import fly, load_mission, load_vehicle
from hydrokit.errors import InputError
from hydrokit.simulate.fleet import fly_fleet, vary
from hydrokit.simulate.tune import DIVERGED_COST, costs, parse_weights, tune_gains


def test_tiny_tune_cli_writes_a_loadable_mission(run_cli, tmp_path: Path) -> None:  # noqa: ANN001
    out = tmp_path / "t"
    code, stdout, err = run_cli(
        "tune", "minerva_square", "--controller", "pid", "--out", out, "--maxiter", 2, "--popsize", 1,
        "--duration", 40, "--workers", 1, "--weights", "energy=0.002,saturation=0",
    )  # fmt: skip
    assert code == 0, err
    assert "cross-track RMS" in stdout
    assert {p.name for p in out.iterdir()} == {"tune.json", "tuned_mission.yaml", "convergence.png"}
    doc = json.loads((out / "tune.json").read_text())
    assert doc["cost_after"] <= doc["cost_before"] + 1e-12  # the hand-picked gains are in the population
    assert doc["evaluations"] > 0 and doc["time_s"] > 0 and doc["weights"]["energy"] == 0.002
    assert len(doc["convergence"]) >= 2
    tuned = load_mission(out / "tuned_mission.yaml")
    assert tuned.controller == "pid"
    for loop, gains in doc["gains_after"].items():
        assert tuned.gains["pid"][loop] == pytest.approx(gains, rel=1e-12)
    code, _, err = run_cli(
        "mission", out / "tuned_mission.yaml", "--out", tmp_path / "m", "--duration", 2, "--no-plots"
    )
    assert code == 0, err
    # the CLI flies the tuned file as the API does
    metrics = json.loads((tmp_path / "m" / "metrics.json").read_text())["controllers"]["PID"]
    api = fly(out / "tuned_mission.yaml", duration=2.0).metrics
    for key in ("cross_track_rms", "cross_track_max", "thrust_impulse", "final_time"):
        assert metrics[key] == pytest.approx(api[key], rel=1e-12), key
    assert metrics["final_time"] == 2.0


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--bounds", "5,0.2"), "--bounds 5,0.2"),
        (("--weights", "speed=3"), "weights item 'speed=3'"),
        (("--weights", "energy=-1"), "weights item 'energy=-1'"),
    ],
)
def test_bad_tuner_input_is_one_line_exit_2(run_cli, tmp_path: Path, args: tuple, needle: str) -> None:  # noqa: ANN001
    code, _, err = run_cli("tune", "minerva_square", "--controller", "pid", "--out", tmp_path / "x", *args)
    assert code == 2
    assert needle in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x").exists()


def test_empty_waypoint_list_is_exit_2(run_cli, tmp_path: Path) -> None:  # noqa: ANN001
    from hydrokit.io.mission import resolve_mission

    text = resolve_mission("minerva_square").read_text()
    import yaml

    doc = yaml.safe_load(text)
    doc["guidance"]["waypoints"] = []
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(doc))
    code, _, err = run_cli("tune", bad, "--controller", "pid", "--out", tmp_path / "x")
    assert code == 2 and "waypoints" in err and len(err.strip().splitlines()) == 1


def test_diverging_run_costs_high_and_bad_bounds_raise() -> None:
    mis = load_mission("minerva_square")
    veh = load_vehicle(mis.vehicle)
    fleet = fly_fleet(mis, [veh, vary(veh, {"linear_damping.surge": -1e5})], duration=20.0)
    j, _ = costs(fleet, parse_weights(None))
    assert j[0] < 100 and j[1] == DIVERGED_COST
    with pytest.raises(InputError, match="0 < min ≤ max"):
        tune_gains(mis, veh, "pid", bounds=(2.0, 1.0))
