"""Measured wind in a fit (issue #48 item 4): a small ship with a Blendermann (1994) wind model is
flown in a logged, varying wind; its sway damping is then identified from the runs with the wind
columns and, as before the wind model, without them. Prints the fitted values against the truth
and the verdict's residual colour (lag-1 ρ) of each fit.

    python bench/wind.py

Nothing here reads shared data: the runs are generated (seeded).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

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
linear_damping: [20, LINEAR, 0, 0, 0, 15]
quadratic_damping: [10, 80, 0, 0, 0, 5]
wind: {frontal_area: 0.135, lateral_area: 0.52, length: 3.0, model: blendermann1994, vessel: tanker_loaded}
thrusters:
  - {name: main, position: [0, 0, 0], direction: [1, 0, 0], max_thrust: 50}
"""
FREE = ["linear_damping.sway", "quadratic_damping.sway"]
TRUTH = (40.0, 80.0)


def _runs(out: Path, truth: object, seed: int) -> tuple[list[Path], list[Path]]:
    from hydrokit.io.runlog import run_csv
    from hydrokit.model.dynamics import environment_table
    from hydrokit.simulate.driver import simulate

    rng = np.random.default_rng(seed)
    windy, calm = [], []
    for k, psi0 in enumerate((0.0, 2.0)):
        t = np.round(np.arange(0.0, 60.0 + 1e-9, 0.1), 9)
        speed, direction = 1.5 + 0.5 * np.sin(0.2 * t + k), 1.0 + 0.3 * np.sin(0.05 * t)
        env = environment_table(None, np.column_stack([t, speed, direction]))
        cmd = np.where((t // 10) % 2 == 0, 5.0, 2.0)
        force = np.column_stack([t, cmd, *([0 * t] * 5)])
        tr = simulate(truth, 60.0, 0.01, force, [0, 0, 0, 0, 0, psi0], [0.3, 0, 0, 0, 0, 0], env)
        s = slice(0, None, 10)
        noisy = {
            c: a + rng.normal(0.0, sd, a.shape)
            for c, a, sd in (
                ("x", tr.eta[s, 0], 0.01),
                ("y", tr.eta[s, 1], 0.01),
                ("psi", tr.eta[s, 5], 0.002),
                ("u", tr.nu[s, 0], 0.002),
                ("v", tr.nu[s, 1], 0.002),
                ("r", tr.nu[s, 5], 0.001),
            )
        }
        lines = run_csv(t, noisy, {"main": cmd}).splitlines()
        calm_path = out / f"calm{k}.csv"
        calm_path.write_text("\n".join(lines) + "\n")
        lines[0] += ",wind_speed,wind_direction"
        lines[1:] = [f"{ln},{a:.9g},{b:.9g}" for ln, a, b in zip(lines[1:], speed, direction)]
        wind_path = out / f"wind{k}.csv"
        wind_path.write_text("\n".join(lines) + "\n")
        windy.append(wind_path)
        calm.append(calm_path)
    return windy, calm


def main() -> int:
    from hydrokit.api import load_vehicle
    from hydrokit.io.runlog import read_runs
    from hydrokit.sysid.fit import identify

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        (out / "truth.yaml").write_text(SHIP.replace("LINEAR", str(TRUTH[0])))
        (out / "start.yaml").write_text(SHIP.replace("LINEAR", "30.0"))
        truth, start = load_vehicle(out / "truth.yaml"), load_vehicle(out / "start.yaml")
        windy, calm = _runs(out, truth, seed=0)
        print(f"truth: {FREE[0]} = {TRUTH[0]:g}, {FREE[1]} = {TRUTH[1]:g}; start {FREE[0]} = 30")
        for label, paths in (("with the logged wind", windy), ("without it", calm)):
            runs = read_runs(paths, start)
            res = identify(start, runs[:1], FREE, holdout=runs[1:], samples=0)
            vals = ", ".join(f"{p} = {v:.4g} ± {s:.2g}" for p, v, s in zip(FREE, res.values, res.sigma))
            rho = max(abs(c["whiteness"]["lag1"]) for r in res.runs for c in r["channels"].values())
            print(
                f"{label}: {vals}; verdict {'fits' if res.verdict['fits'] else 'does not fit'}; largest |lag-1 ρ| {rho:.2f}"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
