"""The path matrix of issue #56: does every path that flies a vehicle fly the same model?

For each vehicle of tests/simulate/test_paths_agree.py (one feature of the input vector each:
``delta()``, ``T()``, ``n()`` factors, a physical fin, a race rudder with each inflow, a
propeller with lag and wake, a table thruster, a current) and each manoeuvre loop (compiled,
Python), this prints

* ``step err``: the largest relative difference between the manoeuvre's steps and simulate's
  open-loop driver fed the same state, held deflections and propeller command (round-off is
  ~1e-14; a dropped input shows as 1e-4 or more);
* ``moves °``: how far the heading after 30 s of a 35° turn moves when the feature's
  coefficient is moved (the factor in the table), in degrees — 0.00 means the path does not see
  the feature;
* ``TD m``: the tactical diameter of the full turning circle;
* then, per feature with a propeller, sysid's batch simulation of a run flown by ``simulate
  --command`` and logged at 1 Hz, against that run (in each channel's standard deviation;
  ~1e-4 before sysid evaluated the thrust at the simulated state).

    python bench/paths.py

About a minute on 2 cores.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository's tests package

from tests.simulate.test_paths_agree import (  # noqa: E402
    FEATURES,
    N_PROP,
    feature_vehicle,
    fly,
    loops_for,
    step_errors,
    sysid_error,
)


def main() -> None:
    t0 = time.perf_counter()
    print(f"{'feature':<22} {'loop':<9} {'step err':>9} {'factor':>7} {'moves °':>8} {'TD m':>8}")
    for feature, (_, _, factor, options) in FEATURES.items():
        base, moved = feature_vehicle(feature), feature_vehicle(feature, factor)
        name = base.thruster_names[0]
        cmd = {name: options.get("command", N_PROP)}
        kw = {"current_ned": options["current_ned"]} if "current_ned" in options else {}
        for loop in loops_for(feature):
            a = fly(base, loop, options, duration=30.0)
            b = fly(moved, loop, options, duration=30.0)
            err = step_errors(base, a, cmd, **kw)
            full = fly(base, loop, options)
            td = full.metrics.get("tactical_diameter")
            moves = math.degrees(abs(a.eta[-1, 5] - b.eta[-1, 5]))
            loop_name = "compiled" if loop else "python"
            td_text = f"{td:8.2f}" if td is not None else "       -"
            print(f"{feature:<22} {loop_name:<9} {err:9.1e} {factor:7.2f} {moves:8.2f} {td_text}")
    print(f"{'feature':<22} {'path':<9} {'err / std':>9}")
    for feature in ("T()", "n()", "race (actuator disc)", "race (MMG)", "propeller lag + wake", "wind"):
        print(f"{feature:<22} {'sysid':<9} {sysid_error(feature):9.1e}")
    print(f"({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
