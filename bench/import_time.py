"""How long ``import hydrokit`` and ``hydrokit --help`` take in a fresh interpreter.

Prints the median of several runs (target from the API issue: import under 0.3 s) and which
heavy modules the import loaded (should be none of numba, scipy, matplotlib).

    .venv/bin/python bench/import_time.py [RUNS]
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

CODE = (
    "import sys, time; t = time.perf_counter(); import hydrokit; dt = time.perf_counter() - t; "
    "print(dt, [m for m in ('numba', 'scipy', 'matplotlib', 'numpy') if m in sys.modules])"
)


def main(runs: int = 7) -> None:
    times, heavy = [], ""
    for _ in range(runs):
        out = subprocess.run(
            [sys.executable, "-X", "importtime", "-c", CODE], capture_output=True, text=True, check=True
        )
        dt, heavy = out.stdout.split(" ", 1)
        times.append(float(dt))
    cli = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "hydrokit", "--help"], capture_output=True, check=True)
        cli.append(time.perf_counter() - t0)
    print(
        f"import hydrokit: median {1e3 * statistics.median(times):.1f} ms over {runs} runs "
        f"(target < 300 ms); heavy modules loaded: {heavy.strip()}"
    )
    print(f"hydrokit --help (whole process): median {1e3 * statistics.median(cli):.0f} ms")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7)
