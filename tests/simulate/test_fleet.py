"""Fleets: every member equals the single compiled run of its configuration; memory is
bounded by the path decimation; a diverging member stops with its time."""

from __future__ import annotations

import dataclasses
import math
import tracemalloc

import numpy as np
import pytest

import hydrokit
from hydrokit import load_mission, load_vehicle
from hydrokit.errors import InputError, SimulationError
from hydrokit.simulate.fleet import FLEET_METRICS, fly_fleet, vary
from hydrokit.simulate.mission import fly_mission

DURATION = 20.0


def _configs(mission, kind: str, n: int) -> list[dict]:  # noqa: ANN001
    rng = np.random.default_rng(3)
    out = []
    for i in range(n):
        g = {lp: dict(v) for lp, v in mission.gains[kind].items()}
        for lp in g:
            for key in g[lp]:
                if key != "limit" and key != "scale":
                    g[lp][key] *= float(rng.uniform(0.5, 2.0)) if i else 1.0
        out.append(
            {
                "damping": float(rng.uniform(0.5, 2.0)) if i else 1.0,
                "gains": g,
                "current": np.array([0.1, -0.05, 0.0]) * rng.uniform(-1, 1) if i else np.zeros(3),
                "eta0": mission.eta0 + np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), 0, 0, 0, 0.2]) * (i > 0),
            }
        )
    return out


@pytest.mark.parametrize(("kind", "n"), [("pid", 1), ("s-plane", 17)])
def test_each_member_equals_the_single_compiled_run(kind: str, n: int) -> None:
    mis = load_mission("lingyun_path")
    veh = load_vehicle(mis.vehicle)
    cfg = _configs(mis, kind, n)
    vehicles = [vary(veh, {"linear_damping.surge": veh.D_L[0, 0] * c["damping"]}) for c in cfg]
    every = mis.output_every
    fleet = fly_fleet(
        mis,
        vehicles,
        kind,
        gains=[c["gains"] for c in cfg],
        currents=np.array([c["current"] for c in cfg]),
        eta0=np.array([c["eta0"] for c in cfg]),
        duration=DURATION,
        paths_every=every,
    )
    assert fleet.n == n and fleet.paths is not None and fleet.path_time is not None
    for i, c in enumerate(cfg):
        mis_i = dataclasses.replace(mis, gains={kind: c["gains"]}, eta0=c["eta0"], current=c["current"])
        one = fly_mission(mis_i, vehicles[i], kind, duration=DURATION)
        got = fleet.member(i)
        for k in FLEET_METRICS:
            assert got[k] == pytest.approx(one.metrics[k], rel=1e-12, abs=1e-12), (i, k)
        assert got["completed"] == one.metrics["completed"]
        assert got["waypoint_times"] == one.metrics["waypoint_times"]
        assert got["diverged_at"] is None
        np.testing.assert_allclose(fleet.paths[i], one.eta, rtol=0, atol=1e-12)
        np.testing.assert_allclose(fleet.path_time, one.time, rtol=0, atol=1e-12)


def _peak(mis, veh, n: int, duration: float, every: int):  # noqa: ANN001, ANN202
    tracemalloc.start()
    try:
        fleet = fly_fleet(mis, veh, n=n, duration=duration, paths_every=every)
        return fleet, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.needs_jit(reason="a 100 000-step fleet run (the step count is what is tested)")
def test_decimated_paths_bound_the_memory() -> None:
    """Peak memory follows steps / paths_every, not the step count: 10× the steps with 10×
    the decimation costs no more than the short run (a full record would cost 10× more)."""
    mis = load_mission("minerva_square")
    veh = load_vehicle(mis.vehicle)
    n = 3
    _peak(mis, veh, n, 100.0, 100)  # warm-up: the compiled kernel and its dispatch
    short, p_short = _peak(mis, veh, n, 100.0, 100)
    long, p_long = _peak(mis, veh, n, 1000.0, 1000)
    assert long.steps == 10 * short.steps > 10_000
    assert long.paths is not None and long.paths.shape == (n, long.steps // 1000 + 1, 6)
    assert short.paths is not None and long.paths.shape == short.paths.shape
    full_record = n * long.steps * 6 * 8  # one η per step and copy, bytes
    assert p_long < p_short + 50_000 < full_record, (p_short, p_long, full_record)
    assert fly_fleet(mis, veh, n=2, duration=5.0).paths is None


def test_diverging_member_stops_with_its_time() -> None:
    mis = load_mission("minerva_square")
    veh = load_vehicle(mis.vehicle)
    bad = vary(veh, {"linear_damping.surge": -1e5})
    fleet = fly_fleet(mis, [veh, bad], duration=30.0)
    assert fleet.diverged_at[0] != fleet.diverged_at[0]  # NaN: the nominal one does not diverge
    t_div = fleet.diverged_at[1]
    assert math.isfinite(t_div) and 0 < t_div < 30.0
    with pytest.raises(SimulationError, match=f"t = {t_div:.6g} s"):
        fly_mission(mis, bad, duration=30.0)
    assert fleet.member(1)["diverged_at"] == t_div


def test_fly_batch_api_result_and_bad_input() -> None:
    fleet = hydrokit.fly_batch("minerva_square", {"added_mass.surge": [1.0, 2.0, 3.0]}, duration=3.0)
    assert fleet.n == 3
    cols, rows = fleet.table()
    assert cols[0] == "run" and len(rows) == 3 and "cross_track_rms" in cols
    d = fleet.to_dict()
    assert len(d["runs"]) == 3 and d["units"]["cross_track_rms"] == "m"
    ax = fleet.plot()
    assert ax.get_xlabel() == "cross-track RMS (m)"
    assert "FleetResult" in fleet._repr_html_()
    with pytest.raises(InputError, match="copies"):
        hydrokit.fly_batch("minerva_square", n=2, currents=np.zeros((3, 3)), duration=3.0)
    with pytest.raises(InputError, match="variation 'nope'"):
        hydrokit.fly_batch("minerva_square", {"nope": [1.0]}, duration=3.0)
    with pytest.raises(InputError, match="paths_every"):
        hydrokit.fly_batch("minerva_square", n=1, duration=3.0, paths_every=0)


def test_monte_carlo_chunks_fly_as_a_fleet_like_one_by_one() -> None:
    from hydrokit.pipeline.fleet import fly_many, fly_one, grid_for, with_coefficients

    mis = load_mission("src/hydrokit/data/projects/udrobot/mission.yaml")
    veh = load_vehicle(mis.vehicle)
    vs = [with_coefficients(veh, {"linear_damping.surge": veh.D_L[0, 0] * f}) for f in (0.7, 1.0, 1.4)]
    grid = grid_for(mis)
    for a, b in zip([fly_one(mis, v, "pid", grid) for v in vs], fly_many(mis, vs, "pid", grid)):
        np.testing.assert_allclose(b["path"], a["path"], rtol=0, atol=1e-12)
        for k, v in a["metrics"].items():
            assert b["metrics"][k] == (v if v is None or isinstance(v, bool) else pytest.approx(v, rel=1e-12)), k
    assert fly_many(mis, [], "pid", grid) == []
