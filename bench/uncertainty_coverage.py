"""Does the stated uncertainty survive model error? (issue #16 item 4)

Records are generated as a tank would record them, with effects the fitted model lacks: cubic
damping in the truth fitted with the quadratic model, a hand heel before the release, a slow
drift and AR(1) coloured noise (the generator of tests/identify/test_release_window.py). For each
record B_e(5°) is identified with its standard error; the truth is covered when it lies within
±1.96 σ. Printed: the coverage with the cycle-clustered σ hydrokit states and with the formal
white-noise σ, each with its binomial tolerance.

    .venv/bin/python bench/uncertainty_coverage.py [--records 200]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--records", type=int, default=200)
    ap.add_argument("--noise", type=float, default=0.02, help="coloured noise std, degrees")
    args = ap.parse_args()
    spec = importlib.util.spec_from_file_location("gen", ROOT / "tests" / "identify" / "test_release_window.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches

    a = math.radians(5.0)
    truth = gen.true_equivalent(a)
    hit = hit_formal = 0
    ratio = []
    t0 = time.perf_counter()
    n = 0
    for seed in range(args.records):
        launch = trim_launch(gen.hand_heel_record(seed=seed, noise=args.noise))
        res = identify_launches(gen.rig(), [launch], equivalent_at=[a])
        r = res.results[0]
        be = r.extra["equivalent_damping"][0]
        formal = be.get("std_error_formal")
        n += 1
        hit += abs(be["value"] - truth) <= 1.96 * be["std_error"]
        if formal is not None:
            hit_formal += abs(be["value"] - truth) <= 1.96 * formal
            ratio.append(be["std_error"] / formal)
    tol = 1.96 * math.sqrt(0.95 * 0.05 / n)
    print(
        f"{n} records in {time.perf_counter() - t0:.0f} s; B_e(5°) truth {truth:.4g} N·m·s/rad (quadratic model, cubic truth)"
    )
    print(f"coverage of ±1.96 σ, cycle-clustered (stated): {100 * hit / n:.1f} %  (95 % ± {100 * tol:.1f} %)")
    if ratio:
        print(f"coverage of ±1.96 σ, formal (white noise):     {100 * hit_formal / n:.1f} %")
        print(f"stated σ / formal σ: median {sorted(ratio)[len(ratio) // 2]:.2f}")


if __name__ == "__main__":
    main()
