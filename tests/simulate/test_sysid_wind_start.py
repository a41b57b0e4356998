"""The equation-error start of sysid in a logged wind (issue #48 item 4): the wind force of the
vehicle's ``wind:`` model enters the regression, so a wind-blown run does not bias the damping.

Runs of a small ship are generated in a varying wind (Blendermann 1994 loads) and written as run
files twice: with the wind columns and without them. The truth is the generating vehicle."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

SHIP = """name: windship
gravity: 9.81
fluid: {density: 1000.0}
dofs: [surge, sway, yaw]
mass: 100.0
volume: 0.1
inertia: [10, 60, 60]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [5, 50, 0, 0, 0, 30]
linear_damping: [20, 40, 0, 0, 0, 15]
quadratic_damping: [10, 80, 0, 0, 0, 5]
wind: {frontal_area: 0.135, lateral_area: 0.52, length: 3.0, model: blendermann1994, vessel: tanker_loaded}
thrusters:
  - {name: main, position: [0, 0, 0], direction: [1, 0, 0], max_thrust: 50}
"""
FREE = ["linear_damping.sway", "linear_damping.yaw", "linear_damping.surge"]


def _runs(tmp: Path, truth: Any) -> tuple[list[Path], list[Path]]:
    from hydrokit.io.runlog import run_csv
    from hydrokit.model.dynamics import environment_table
    from hydrokit.simulate.driver import simulate

    rng = np.random.default_rng(5)
    windy, calm = [], []
    for k, psi0 in enumerate((0.0, 2.0)):
        t = np.round(np.arange(0.0, 40.0 + 1e-9, 0.1), 9)
        speed, direction = 3.0 + 0.5 * np.sin(0.2 * t + k), 1.0 + 0.3 * np.sin(0.05 * t)
        env = environment_table(None, np.column_stack([t, speed, direction]))
        cmd = np.where((t // 10) % 2 == 0, 5.0, 2.0)
        force = np.column_stack([t, cmd, *([0 * t] * 5)])
        tr = simulate(truth, 40.0, 0.01, force, [0, 0, 0, 0, 0, psi0], [0.3, 0, 0, 0, 0, 0], env)
        s = slice(0, None, 10)
        noisy = {
            c: a + rng.normal(0.0, sd, a.shape)
            for c, a, sd in (
                ("x", tr.eta[s, 0], 0.005),
                ("y", tr.eta[s, 1], 0.005),
                ("psi", tr.eta[s, 5], 0.001),
                ("u", tr.nu[s, 0], 0.001),
                ("v", tr.nu[s, 1], 0.001),
                ("r", tr.nu[s, 5], 0.0005),
            )
        }
        lines = run_csv(t, noisy, {"main": cmd}).splitlines()
        (tmp / f"calm{k}.csv").write_text("\n".join(lines) + "\n")
        lines[0] += ",wind_speed,wind_direction"
        lines[1:] = [f"{ln},{a:.9g},{b:.9g}" for ln, a, b in zip(lines[1:], speed, direction)]
        (tmp / f"wind{k}.csv").write_text("\n".join(lines) + "\n")
        windy.append(tmp / f"wind{k}.csv")
        calm.append(tmp / f"calm{k}.csv")
    return windy, calm


def test_equation_error_start_takes_the_logged_wind(tmp_path: Path) -> None:
    """The equation-error estimates (sysid's start) from the wind-logged runs are within 5 % of
    the generating truth and closer to it than those from the same runs without the wind
    columns, which must absorb the wind's sway force and yaw moment in the damping. 5 %: the
    smoother's velocities at 1 mm/s noise bias the regression by about 1 % here."""
    from hydrokit.api import load_vehicle
    from hydrokit.io.runlog import read_runs
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.model import free_parameters, values_of

    (tmp_path / "truth.yaml").write_text(SHIP)
    truth = load_vehicle(tmp_path / "truth.yaml")
    _, params = free_parameters(truth, FREE)
    true = values_of(truth, params)
    windy, calm = _runs(tmp_path, truth)
    errors = {}
    for label, paths in (("wind", windy), ("calm", calm)):
        res = identify(truth, read_runs(paths, truth), FREE, method="equation-error", samples=0, check_step=False)
        errors[label] = np.abs(np.asarray(res.equation_error["values"]) - true) / true
    np.testing.assert_array_less(errors["wind"], 0.05)
    # the sway and yaw damping carry the wind's side force and moment when the wind is left out
    assert np.all(errors["wind"][:2] < 0.5 * errors["calm"][:2]), errors
