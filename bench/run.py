"""The main job's benchmark: ``hydrokit run`` on the bundled udrobot project.

Prints the time of each step of a forced (uncached) run, the Monte Carlo's missions per second,
how often the true vehicle's path lies inside the Monte Carlo envelope, and the cached re-run:
a second run with nothing changed (a new process through the CLI: wall time, whether every
file of the folder is untouched) and its own work (hashing inputs and outputs, in process).

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
    from hydrokit.report.run import write_run_folder

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        t0 = time.perf_counter()
        res = hydrokit.run_project("udrobot", out, force=True, workers=args.workers, samples=args.samples)
        write_run_folder(res, out)
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
        before = _snapshot(out)
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
        untouched = _snapshot(out) == before
        print(f"second run, nothing changed (new process, CLI): {again:.2f} s wall (target < 3 s)")
        print(f"  files untouched (inode, mtime, bytes of every file, cache included): {untouched}")
        # its own work, without the interpreter's start and imports: hash the inputs and outputs
        from hydrokit.io.project import parse_project, resolve_project
        from hydrokit.io.yamlfile import read_yaml
        from hydrokit.pipeline import up_to_date

        t0 = time.perf_counter()
        path = resolve_project("udrobot")
        current = up_to_date(parse_project(read_yaml(path), path), out, samples=args.samples)
        own = time.perf_counter() - t0
        print(
            f"  its own work (parse the project, hash inputs and outputs): {own:.3f} s, up to date: {current} "
            "(target < 1 s)"
        )


def _snapshot(out: Path) -> dict[str, tuple[int, int, bytes]]:
    return {
        str(p.relative_to(out)): (p.stat().st_ino, p.stat().st_mtime_ns, p.read_bytes())
        for p in sorted(out.rglob("*"))
        if p.is_file()
    }


if __name__ == "__main__":
    main()
