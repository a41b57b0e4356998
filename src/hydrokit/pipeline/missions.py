"""Steps 5–6 of ``hydrokit run`` as step documents: nominal flights and the Monte Carlo."""

from __future__ import annotations

import base64
from collections.abc import Callable
from typing import Any

import numpy as np

from hydrokit.simulate.mission import CONTROLLER_LABEL

CONTROLLERS = ("pid", "s-plane")


def _png64(fig: Any, dpi: int = 90) -> str:
    from hydrokit.plot._mpl import to_png

    return base64.b64encode(to_png(fig, dpi)).decode("ascii")


def fly_nominal(
    mission_file: str,
    vehicle_doc: dict[str, Any],
    truth_doc: dict[str, Any] | None,
    advance: Callable[[int], None],
) -> dict[str, Any]:
    """Fly the mission with both controllers on the identified vehicle (and on the true one).

    Returns metrics and the path on the envelope grid per controller, the trajectories as CSV
    text (``pid.csv``, ``s-plane.csv``: the columns of ``hydrokit mission``) and the figures.
    """
    from hydrokit.api import load_mission, vehicle_from_dict
    from hydrokit.io.trajectory import table_csv
    from hydrokit.pipeline.fleet import fly_one, grid_for
    from hydrokit.plot.mission import path_figure, tracking_figure
    from hydrokit.simulate.mission import fly_mission

    mission = load_mission(mission_file)
    grid = grid_for(mission)
    vehicle = vehicle_from_dict(vehicle_doc, "vehicle.yaml")
    out: dict[str, Any] = {"mission": mission.name, "grid": grid, "waypoints": mission.path.points}
    runs = {}
    csv = {}
    out["controllers"] = {}
    for c in CONTROLLERS:
        res = fly_mission(mission, vehicle, c)
        runs[CONTROLLER_LABEL[c]] = res.run
        cols, data = res.columns_and_data()
        csv[f"{c}.csv"] = table_csv(cols, data)
        path = np.column_stack([np.interp(grid, res.time, res.eta[:, k], right=np.nan) for k in range(3)])
        out["controllers"][c] = {"metrics": res.metrics, "path": path}
        advance(1)
    out["truth"] = None
    if truth_doc is not None:
        truth = vehicle_from_dict(truth_doc, "true vehicle")
        out["truth"] = {}
        for c in CONTROLLERS:
            out["truth"][c] = fly_one(mission, truth, c, grid)
            advance(1)
    out["figures"] = [
        {
            "name": "mission_path",
            "caption": "Mission flown by the identified vehicle, PID and S-plane",
            "png": _png64(path_figure(runs, f"{mission.name}: identified vehicle")),
        },
        {
            "name": "mission_tracking",
            "caption": "Tracking errors against time",
            "png": _png64(tracking_figure(runs, f"{mission.name}: tracking")),
        },
    ]
    out["csv"] = csv
    return out


def monte_carlo_step(
    mission_file: str,
    vehicle_doc: dict[str, Any],
    flights: dict[str, Any],
    samples: int,
    seed: int,
    mapper: Any,
    advance: Callable[[int], None],
) -> dict[str, Any]:
    """The Monte Carlo of :func:`hydrokit.pipeline.fleet.monte_carlo` with the truth's containment
    (fraction of grid times inside the min–max and 5–95 % envelopes) and the figure."""
    from hydrokit.pipeline.fleet import containment, monte_carlo
    from hydrokit.plot.mission import envelope_figure

    mc = monte_carlo(mission_file, vehicle_doc, CONTROLLERS, samples, seed, mapper, advance)
    truth = flights.get("truth")
    for c, s in mc["controllers"].items():
        if truth is not None:
            path = np.asarray(truth[c]["path"], float)
            s["truth_inside"] = {
                "min_max": containment(path, s["envelope"], ("min", "max")),
                "p5_p95": containment(path, s["envelope"], ("p5", "p95")),
            }
    envs = {
        CONTROLLER_LABEL[c]: {**s["envelope"], "sample_paths": s["sample_paths"]} for c, s in mc["controllers"].items()
    }
    nominal = {CONTROLLER_LABEL[c]: np.asarray(flights["controllers"][c]["path"], float) for c in CONTROLLERS}
    true_paths = None
    if truth is not None:
        true_paths = {CONTROLLER_LABEL[c]: np.asarray(truth[c]["path"], float) for c in CONTROLLERS}
    fig = envelope_figure(np.asarray(flights["waypoints"], float), mc["grid"], envs, nominal, true_paths)
    mc["figures"] = [
        {
            "name": "monte_carlo",
            "caption": f"Mission under coefficient uncertainty: {samples} samples from the covariance of the "
            "identified coefficients, each flown with PID and with S-plane",
            "png": _png64(fig),
        }
    ]
    return mc
