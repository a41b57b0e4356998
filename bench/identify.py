"""Identification benchmark (issue #2): a 72-launch campaign, wall time and accuracy.

    python bench/identify.py [--workers N]

Virtual CELY2019-like pendulum campaign (3 axes × 4 amplitudes × 6 launches, IMU 100 Hz with
0.05° noise, true values of the bundled UDrobot campaign). Prints the total wall time of
identifying all 72 launches with output-error (target ≤ 10 s on 2 cores) and, for every method,
the bias and spread of the added mass and of the damping force at the peak speed against truth,
next to the Cramér–Rao bound (target: output-error spread ≤ 1.5× the bound).
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from hydrokit.identify.design import cramer_rao
from hydrokit.identify.estimators import identify_launch
from hydrokit.identify.preprocess import trim_launch
from hydrokit.identify.types import Rig
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

RHO = 998.2
# CELY2019 Table 10 (full scale) brought to the 22 % model (see data/campaigns/udrobot/README.md)
AXES = {
    "x": (0.9024 * RHO * 107597e-9, 1.0745 * 0.22**2, 50.8618 * 0.22**2, 0.00210),
    "y": (0.2404 * RHO * 107597e-9, 0.6508 * 0.22**2, 17.4666 * 0.22**2, 0.00290),
    "z": (0.8283 * RHO * 107597e-9, 0.3834 * 0.22**2, 55.7484 * 0.22**2, 0.00485),
}
AMPS_DEG = (2.5, 5.0, 10.0, 15.0)
METHODS = ("output-error", "equation-error", "morison", "log-decrement")
SENSOR = SensorModel.imu()
DURATION = 15.0


def rig_for(axis: str) -> Rig:
    return Rig(
        test="pendulum",
        axis={"x": "surge", "y": "sway", "z": "heave"}[axis],
        gravity=9.79,
        density=RHO,
        kinematic_viscosity=1e-6,
        mass=0.146,
        volume=107597e-9,
        reference_area=AXES[axis][3],
        reference_length=0.066,
        pendulum_length=0.30,
    )


def campaign() -> list[tuple[str, float, object]]:
    rng = np.random.default_rng(2026)
    out = []
    for axis, (ma, kl, kq, _) in AXES.items():
        rig = rig_for(axis)
        for a in AMPS_DEG:
            for _ in range(6):
                out.append((axis, a, simulate_launch(rig, ma, kl, kq, math.radians(a), DURATION, SENSOR, rng)))
    return out


def _fit(job: tuple[str, float, object, str]) -> tuple[str, float, str, float, float, float]:
    axis, a, launch, method = job
    res = identify_launch(rig_for(axis), trim_launch(launch), method)
    return axis, a, method, res.added_mass, res.linear_damping, res.quadratic_damping


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="processes (default 2 = this machine's cores)")
    args = ap.parse_args()
    launches = campaign()
    _fit((launches[0][0], launches[0][1], launches[0][2], "output-error"))  # compile / load numba cache
    results = {}
    for method in METHODS:
        jobs = [(ax, a, L, method) for ax, a, L in launches]
        t0 = time.perf_counter()
        if args.workers > 1:
            with ProcessPoolExecutor(args.workers) as pool:
                rows = list(pool.map(_fit, jobs, chunksize=6))
        else:
            rows = [_fit(j) for j in jobs]
        results[method] = (time.perf_counter() - t0, rows)
    wall = results["output-error"][0]
    print(
        f"campaign: {len(launches)} launches (3 axes × 4 amplitudes × 6), pendulum, {SENSOR.name}, {DURATION:g} s each"
    )
    print(
        f"output-error wall time for all {len(launches)} launches: {wall:.2f} s with {args.workers} worker(s) "
        f"(target ≤ 10 s) -> {'PASS' if wall <= 10 else 'FAIL'}"
    )
    for m in METHODS[1:]:
        print(f"  {m}: {results[m][0]:.2f} s")
    print()
    print("per axis and amplitude group (6 launches): added mass and damping force at the peak speed")
    print(
        f"{'axis':>4} {'amp°':>5} {'method':>15} {'m_a bias %':>11} {'m_a spread %':>13} {'CRB %':>7} {'ratio':>6}"
        f" {'F_d bias %':>11} {'F_d spread %':>13} {'CRB %':>7}"
    )
    worst = 0.0
    for axis, (ma, kl, kq, _) in AXES.items():
        rig = rig_for(axis)
        for a in AMPS_DEG:
            crb = cramer_rao(rig, ma, kl, kq, math.radians(a), DURATION, SENSOR)
            u = crb["speed_max"]
            fd = kl * u + kq * u * u
            for m in METHODS:
                rows = [r for r in results[m][1] if r[0] == axis and r[1] == a]
                m_est = np.array([r[3] for r in rows])
                f_est = np.array([r[4] * u + r[5] * u * u for r in rows])
                spread = 100 * np.std(m_est, ddof=1) / ma
                bound = 100 * crb["added_mass"] / ma
                ratio = spread / bound
                if m == "output-error":
                    worst = max(worst, ratio)
                print(
                    f"{axis:>4} {a:>5g} {m:>15} {100 * (m_est.mean() / ma - 1):>11.3f} {spread:>13.3f} {bound:>7.3f} "
                    f"{ratio:>6.2f} {100 * (f_est.mean() / fd - 1):>11.2f} {100 * np.std(f_est, ddof=1) / fd:>13.2f} "
                    f"{100 * crb['damping_force_rel']:>7.2f}"
                )
    print()
    print(
        f"output-error: worst spread/CRB ratio of added mass over the 12 groups = {worst:.2f} (target ≤ 1.5; "
        f"a 6-sample std scatters ±30 % about the true std) -> {'PASS' if worst <= 1.5 else 'CHECK'}"
    )


if __name__ == "__main__":
    main()
