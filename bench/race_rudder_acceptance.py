"""Issue #48's acceptance chain over many seeds: how often the fitted parameters lie within kσ of
the truth and the truth's turning circles inside the predicted 95 % intervals.

The chain is the acceptance test's (tests/simulate/test_acceptance_race_rudder.py): a generated
3 m ship with a rudder in its propeller's race (MMG inflow), a Blendermann wind model flown in a
logged wind and a neutral rudder of 1.5°, two 40 s zigzag-like runs, four free parameters
started 25–30 % off, and 24 draws per 35° turning circle to each side. The test runs one seed;
this prints, per seed, each parameter's error in units of its stated σ and whether each metric's
interval held the truth, then the RMS of the errors (1 for honest σ) and the coverage (0.95 for
honest intervals, less with 24 draws).

    python bench/race_rudder_acceptance.py [FIRST_SEED] [N_SEEDS]

About 45 s per seed on 2 cores.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository's tests package

from tests.simulate.test_acceptance_race_rudder import identify_and_predict  # noqa: E402

from hydrokit.model.uncertainty import parameter_value  # noqa: E402


def main() -> None:
    first = int(sys.argv[1]) if len(sys.argv) > 1 else 11
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    z_all: list[list[float]] = []
    held: list[bool] = []
    names: tuple[str, ...] = ()
    for seed in range(first, first + count):
        t0 = time.perf_counter()
        truth, res, turns = identify_and_predict(seed)
        names = res.parameters
        z = [(v - parameter_value(truth, n)) / s for n, v, s in zip(res.parameters, res.values, res.sigma)]
        z_all.append(z)
        cells = []
        for side, (true, predicted) in turns.items():
            for metric in ("advance", "tactical_diameter"):
                iv = predicted.intervals[metric]
                ok = iv["low95"] is not None and iv["low95"] < true.metrics[metric] < iv["high95"]
                held.append(ok)
                cells.append(f"{'port' if side > 0 else 'stbd'} {metric[:8]} {'in' if ok else 'OUT'}")
        print(
            f"seed {seed}: z = {' '.join(f'{x:+.2f}' for x in z)}; {', '.join(cells)} "
            f"({time.perf_counter() - t0:.0f} s)",
            flush=True,
        )
    zs = np.array(z_all)
    print("parameters:", ", ".join(names))
    print("RMS z per parameter (1 for honest σ):", " ".join(f"{x:.2f}" for x in np.sqrt(np.mean(zs**2, axis=0))))
    print("mean z per parameter (0 unbiased):", " ".join(f"{x:+.2f}" for x in zs.mean(axis=0)))
    print(
        f"|z| < 3: {np.mean(np.abs(zs) < 3):.0%} of {zs.size}; intervals holding the truth: {np.mean(held):.0%} of {len(held)}"
    )


if __name__ == "__main__":
    main()
