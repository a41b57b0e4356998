"""Simulation benchmark (issue #3, extended by issue #4). Prints, on BlueROV2 Heavy at dt = 0.01 s:

- compiled RK4 steps per second (numba, one vehicle; target ≥ 500 000),
- a straightforward per-step numpy RK4 of the same model (what most Python users write),
- their ratio,
- batch vehicle-steps per second for 10 000 vehicles (target ≥ 1 000 000),
- closed-loop steps per second with controller + allocation + thrusters in the loop,
- the LI2021 open-loop check on the bundled Lingyun: settled velocities under τ = [30 0 3 0 0 3].

    python bench/simulate.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from hydrokit.io.vehicle import load_vehicle
from hydrokit.simulate.batch import simulate_batch
from hydrokit.simulate.driver import simulate

TAU = [30, 0, 3, 0, 0, 3]


def compiled_speed(v, seconds: float = 600.0) -> float:
    simulate(v, 1.0, 0.01, TAU)  # compile / load cache
    best = 0.0
    for _ in range(3):
        t0 = time.perf_counter()
        simulate(v, seconds, 0.01, TAU)
        best = max(best, seconds / 0.01 / (time.perf_counter() - t0))
    return best


def numpy_speed(v, seconds: float = 20.0) -> float:
    t0 = time.perf_counter()
    simulate(v, seconds, 0.01, TAU, integrator="rk4-numpy")
    return seconds / 0.01 / (time.perf_counter() - t0)


def batch_speed(v, n: int = 10_000, seconds: float = 10.0) -> float:
    rng = np.random.default_rng(0)
    vs = []
    from dataclasses import replace

    for _ in range(n):  # Monte Carlo over ±10 % damping uncertainty
        vs.append(replace(v, D_Q=v.D_Q * rng.uniform(0.9, 1.1, 6)))
    simulate_batch(vs[:4], 0.1, 0.01, TAU)  # compile
    t0 = time.perf_counter()
    res = simulate_batch(vs, seconds, 0.01, TAU)
    elapsed = time.perf_counter() - t0
    assert np.all(res["steps"] == int(seconds / 0.01))
    return n * seconds / 0.01 / elapsed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs")
    args = ap.parse_args()
    v = load_vehicle("bluerov2-heavy")
    c = compiled_speed(v, 60.0 if args.quick else 600.0)
    p = numpy_speed(v, 5.0 if args.quick else 20.0)
    b = batch_speed(v, 2000 if args.quick else 10_000, 10.0)
    print("BlueROV2 Heavy, dt = 0.01 s, tau = [30 0 3 0 0 3]")
    print(
        f"  compiled RK4 (numba), one vehicle : {c:12,.0f} steps/s   (target ≥ 500,000) {'PASS' if c >= 5e5 else 'FAIL'}"
    )
    print(f"  per-step numpy RK4, same model    : {p:12,.0f} steps/s")
    print(f"  ratio compiled / numpy            : {c / p:12,.0f} x")
    print(
        f"  batch, {2000 if args.quick else 10_000} vehicles              : {b:12,.0f} vehicle-steps/s (target ≥ 1,000,000) "
        f"{'PASS' if b >= 1e6 else 'FAIL'}"
    )
    lv = load_vehicle("lingyun")
    tr = simulate(lv, 300.0, 0.05, TAU)
    late = tr.nu[tr.time > 250]
    print("Lingyun (LI2021 open-loop check), RK4 dt = 0.05 s, 300 s:")
    print(
        "  settled u, v, w (m/s) = "
        + ", ".join(f"{x:.4f}" for x in tr.nu[-1, :3])
        + "; p, q, r (rad/s) = "
        + ", ".join(f"{x:.5f}" for x in tr.nu[-1, 3:])
    )
    print(f"  largest change over the last 50 s: {np.max(np.ptp(late, axis=0)):.2e}")
    sys.path.insert(0, str(Path(__file__).parent))
    from closed_loop import closed_loop_speed

    for loop in ("compiled", "python"):
        cl = closed_loop_speed("lingyun_path", "pid", 20.0 if args.quick else 60.0, loop=loop)
        print(
            f"Closed loop ({loop}: guidance + PID + allocation + thrusters + Lingyun model), dt = 0.05 s: "
            f"{cl:,.0f} steps/s"
        )


if __name__ == "__main__":
    main()
