"""The main job's benchmark: ``hydrokit run`` on the bundled udrobot project.

Prints the time of each step of a forced (uncached) run, the Monte Carlo's missions per second,
the time of a second run with nothing changed (all steps from the cache), and how often the
true vehicle's path lies inside the Monte Carlo envelope.

    .venv/bin/python bench/run.py [--workers N] [--samples N]   (default: one worker per core, 200)
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--workers", type=int, default=None, help="Dask workers (default: one per core)")
    ap.add_argument("--samples", type=int, default=200, help="Monte Carlo samples per controller")
    args = ap.parse_args()
    import hydrokit
    from hydrokit.report.run import write_run

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        t0 = time.perf_counter()
        res = hydrokit.run_project("udrobot", out, force=True, workers=args.workers, samples=args.samples)
        write_run(res, out)
        total = time.perf_counter() - t0
        print(f"engine: {res.document['engine']}")
        print(f"{'step':<22}{'time (s)':>10}")
        for t in res.timings:
            print(f"{t['step']:<22}{t['seconds']:>10.2f}")
        print(f"{'whole run + report':<22}{total:>10.2f}")
        mc = res.document["monte_carlo"]
        mc_time = next(t["seconds"] for t in res.timings if t["step"] == "monte carlo")
        n = mc["samples"] * len(mc["controllers"])
        print(
            f"Monte Carlo: {n} missions in {mc_time:.1f} s = {n / mc_time:.1f} missions/s "
            f"({200 / (n / mc_time):.1f} s per 200 missions; target <= 30 s)"
        )
        for c, s in mc["controllers"].items():
            inside = s.get("truth_inside") or {}
            x = s["metrics"]["cross_track_rms"]
            print(
                f"  {c:<8} cross-track RMS median {x['median']:.3f} m [5-95 %: {x['p5']:.3f}, {x['p95']:.3f}], "
                f"true path inside min-max envelope at {100 * inside.get('min_max', float('nan')):.0f} % of times, "
                f"inside 5-95 % at {100 * inside.get('p5_p95', float('nan')):.0f} %"
            )
        # a second run with nothing changed, as a user runs it: a new process, the CLI
        t0 = time.perf_counter()
        done = subprocess.run(
            [
                sys.executable,
                "-m",
                "hydrokit",
                "run",
                "udrobot",
                "--out",
                str(out),
                "--quiet",
                "--samples",
                str(args.samples),
            ],
            capture_output=True,
            text=True,
        )
        again = time.perf_counter() - t0
        assert done.returncode == 0, done.stderr
        print(f"second run, nothing changed (new process, CLI): {again:.2f} s (target < 3 s)")


if __name__ == "__main__":
    main()
