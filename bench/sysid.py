"""System identification from free-running logs (issue #44). Prints:

- coverage: over N generated data sets (each: a BlueROV2-like vehicle with 12 hidden
  coefficients — added mass, linear and quadratic damping in surge, sway, heave and yaw —
  drawn ±30 % about bluerov2-sysid, its own commands and sensor noise), the fraction of stated
  95 % intervals that hold the truth (target 95 ± 3 %), per parameter and over all;
- accuracy vs the Cramér–Rao bound: per parameter the RMS of (estimate − truth)/σ_CRB, with
  σ_CRB from the Fisher information at the estimate (1 = efficient), and the mean σ stated
  (the coloured-residual sandwich) over σ_CRB;
- held-out NRMSE per channel (a third dive of each data set, predicted open loop);
- speed: one identification of the 12 parameters from 4 × 90 s of dives on 2 threads (target
  < 15 s wall, issue #50; wall and CPU printed with the load average), how much of it is simulation, and the integrator check (halving the step must move
  no estimate by more than 0.1 σ).

- plan: a D-optimal 60 s schedule for the 12 parameters (``hydrokit sysid plan``), its
  Cramér–Rao σ over that of the generator's random multi-sines, and the Fisher σ of a fit of
  a dive flown with it over the planned σ (1 = the plan's promise kept).

- windows: a planar ship (3 m model, propeller and rudder; a yaw-rate disturbance on a
  straight course doubles in about 20 s, but its quadratic hull terms damp it in the turns of
  its runs) in 12 runs × 200 s, 17 free hull, rudder and asymmetry terms, fitted in 30 s
  windows on 2 threads: wall and CPU time (target < 60 s wall), iterations, and per parameter
  the error against the generating truth in σ and σ/|value|; what ``window="auto"`` decides
  (the largest growth of an initial velocity error). ``--whole`` also fits whole runs for
  comparison (minutes).

    python bench/sysid.py [--datasets 100] [--duration 30] [--skip-speed] [--skip-coverage] [--skip-plan]
                          [--skip-windows] [--whole]

``--datasets 10`` gives a quick look (coverage then has a ± 7 % sampling error).
"""

from __future__ import annotations

import argparse
import os
import time

# BLAS on one thread: the compiled batch simulations already use the 2 cores (numba threads), and
# OpenBLAS threads on top of them oversubscribe the cores — on a loaded machine its spinning
# threads make the fit's JᵀJ of a (200 000 × 50) Jacobian 50× slower (0.08 s → 4.5 s)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--datasets", type=int, default=100, help="generated data sets for the coverage (count)")
    ap.add_argument("--duration", type=float, default=30.0, help="length of each coverage dive, s")
    ap.add_argument("--runs", type=int, default=2, help="training dives per coverage data set (count)")
    ap.add_argument("--skip-speed", action="store_true")
    ap.add_argument("--skip-coverage", action="store_true")
    ap.add_argument("--skip-plan", action="store_true")
    ap.add_argument("--skip-windows", action="store_true")
    ap.add_argument("--whole", action="store_true", help="windows: also fit whole runs (minutes)")
    args = ap.parse_args()

    import numba

    import hydrokit
    from hydrokit.sysid.data import HIDDEN, generate_runs, hidden_vehicle
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.model import free_parameters, values_of

    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    base = hydrokit.load_vehicle("bluerov2-sysid")
    names = list(HIDDEN)

    if not args.skip_speed:
        truth = hidden_vehicle(base, 1000)
        runs = generate_runs(truth, 5, 90.0, seed=1000)
        identify(base, runs[:1], names[:2], samples=0, check_step=False)  # load compiled kernels
        t, c = time.perf_counter(), time.process_time()
        res = identify(base, runs[:4], names, holdout=runs[4:], samples=40)
        wall, cpu = time.perf_counter() - t, time.process_time() - c
        sim = res.timing["simulation"]
        print(
            f"speed: 12 parameters from 4 × 90 s on 2 threads: {wall:.1f} s wall (target < 15 s, issue #50), "
            f"{cpu:.1f} s CPU, of which simulation {sim:.1f} s ({100 * sim / wall:.0f} % of the wall), "
            f"{res.iterations} iterations; {'PASS' if wall < 15 else 'FAIL'} "
            f"(BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS')}; load average {os.getloadavg()[0]:.1f})"
        )
        stages = {k: v for k, v in res.timing.items() if k not in ("total", "simulation")}
        print(
            "  stages (s wall): "
            + ", ".join(f"{k} {v:.2f}" for k, v in stages.items())
            + f"; simulation inside output error and step check {sim:.2f}"
        )
        print(
            f"integrator: halving the 10 ms step moves the estimates by at most {res.step_check:.3f} σ "
            f"(target < 0.1); {'PASS' if res.step_check < 0.1 else 'FAIL'}"
        )
        _, params = free_parameters(truth, names)
        z = (res.values - values_of(truth, params)) / res.sigma
        print(
            f"  this data set: |estimate − truth|/σ max {np.max(np.abs(z)):.2f}; condition number {res.condition:.3g}"
        )
        for m in res.messages:
            print(f"  note: {m}")

    if not args.skip_windows:
        _windows(args.whole)
    if not args.skip_plan:
        _plan(base, names)
    if args.skip_coverage:
        return
    n = args.datasets
    errs, sig, crb, truths, nrmse = [], [], [], [], {}
    t0 = time.perf_counter()
    for k in range(n):
        truth = hidden_vehicle(base, k)
        runs = generate_runs(truth, args.runs + 1, args.duration, seed=10_000 + k)
        try:
            res = identify(base, runs[: args.runs], names, holdout=runs[args.runs :], samples=0, check_step=False)
        except Exception as exc:  # noqa: BLE001 - a bench counts failures instead of stopping
            print(f"data set {k}: {exc}")
            continue
        _, params = free_parameters(truth, names)
        truths.append(values_of(truth, params))
        errs.append(res.values - truths[-1])
        sig.append(res.sigma)
        crb.append(res.fisher_sigma)
        for c, d in next(r for r in res.runs if r["holdout"])["channels"].items():
            nrmse.setdefault(c, []).append(d["nrmse"])
        if (k + 1) % 10 == 0:
            cov = np.mean(np.abs(np.array(errs)) <= 1.96 * np.array(sig))
            print(
                f"  {k + 1}/{n} data sets, {time.perf_counter() - t0:.0f} s, coverage so far {100 * cov:.1f} %",
                flush=True,
            )
    E, S, C, T = np.array(errs), np.array(sig), np.array(crb), np.array(truths)
    inside = np.abs(E) <= 1.96 * S
    total = float(np.mean(inside))
    print(
        f"\ncoverage of the stated 95 % intervals over {E.shape[0]} data sets × 12 parameters "
        f"({args.runs} × {args.duration:g} s dives each): {100 * total:.1f} % (target 95 ± 3 %); "
        f"{'PASS' if abs(total - 0.95) <= 0.03 else 'FAIL'}"
    )
    print(f"{'parameter':26s} {'coverage':>9s} {'RMS err/σ_CRB':>14s} {'σ/σ_CRB':>8s} {'RMS rel. err':>12s}")
    for j, name in enumerate(names):
        eff = np.sqrt(np.mean((E[:, j] / np.maximum(C[:, j], 1e-300)) ** 2))
        rel = np.sqrt(np.mean((E[:, j] / T[:, j]) ** 2))
        print(
            f"{name:26s} {100 * np.mean(inside[:, j]):8.1f}% {eff:14.2f} {np.mean(S[:, j] / C[:, j]):8.2f} {100 * rel:11.2f}%"
        )
    print("\nheld-out NRMSE (RMS error / std of the measured channel), mean over data sets:")
    print("  " + ", ".join(f"{c} {np.mean(v):.3f}" for c, v in nrmse.items()))


#: the windows section's hull, rudder and asymmetry terms (SI)
WINDOW_TERMS = {
    "Y_uv": -300.0,
    "N_uv": -1200.0,
    "Y_ur": 100.0,
    "N_ur": -600.0,
    "Y_uu*delta(rudder)": 40.0,
    "N_uu*delta(rudder)": -80.0,
    "Y_v|v|": -800.0,
    "N_v|v|": -200.0,
    "Y_r|r|": 50.0,
    "N_r|r|": -300.0,
    "X_vr": 150.0,
    "X_vv": -100.0,
    "X_rr": -20.0,
    "X_uu*delta(rudder)^2": -20.0,
    "Y_uu": 2.0,
    "N_uu": -1.0,
}
#: the 3 m planar ship of the windows section: SI derivatives of a full-bodied ship model at
#: 0.37 m/s (our choice), N_uv large enough to make it course-unstable
WINDOW_SHIP = {
    "name": "unstable-ship",
    "fluid": {"density": 1000.0},
    "gravity": 9.81,
    "mass": 245.0,
    "volume": 0.245,
    "inertia": [20.0, 100.0, 138.0],
    "center_of_gravity": [0, 0, 0],
    "center_of_buoyancy": [0, 0, 0],
    "added_mass": [15.0, 180.0, 0, 0, 0, 90.0],
    "linear_damping": [0, 0, 0, 0, 0, 0],
    "quadratic_damping": [40.0, 0, 0, 0, 0, 0],
    "dofs": ["surge", "sway", "yaw"],
    "control_surfaces": [{"name": "rudder", "position": [-1.5, 0, 0], "max_deflection_deg": 35}],
    "thrusters": [
        {
            "name": "prop",
            "position": [-1.45, 0, 0],
            "direction": [1, 0, 0],
            "diameter": 0.084,
            "kt_forward": [-0.28, 0.33],
            "wake_fraction": 0.3,
            "max_rpm": 1800,
            "max_thrust": 30,
            "min_thrust": -30,
        }
    ],
    "terms": WINDOW_TERMS,
}
#: its 17 free parameters (no added mass: with every force term of a DOF free, a common scale
#: of that DOF's forces and its mass would be unidentifiable)
WINDOW_FREE = [
    "quadratic_damping.surge",
    *(f"terms.{t}" for t in WINDOW_TERMS),
]


def _windows(whole: bool) -> None:
    from hydrokit.api import vehicle_from_dict
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.model import free_parameters, values_of, with_values
    from hydrokit.sysid.ship import ship_runs

    truth = vehicle_from_dict(WINDOW_SHIP, "unstable-ship")
    runs = ship_runs(truth, 12, 200.0, seed=48, dt=0.01)
    _, params = free_parameters(truth, WINDOW_FREE)
    true = values_of(truth, params)
    base = with_values(truth, params, true * np.random.default_rng(48).uniform(0.8, 1.2, true.size))
    identify(base, runs[:1], WINDOW_FREE[:2], samples=0, check_step=False, dt=0.05, window=50.0)  # compile
    _auto_decision(truth, params, base, runs)
    fits = [("30 s", 30.0)] + ([("whole runs", None)] if whole else [])
    for label, window in fits:
        t, c = time.perf_counter(), time.process_time()
        res = identify(base, runs, WINDOW_FREE, dt=0.05, window=window)
        wall, cpu = time.perf_counter() - t, time.process_time() - c
        note = next((w for w in res.warnings if w.startswith("windowed")), "whole runs")
        print(
            f"windows ({label}): 17 parameters from 12 × 200 s of a course-unstable ship on 2 threads: {wall:.1f} s "
            f"wall (target < 60 s, issue #48), {cpu:.1f} s CPU, {res.iterations} iterations, simulation "
            f"{res.timing['simulation']:.1f} s; {'PASS' if wall < 60 else 'FAIL'} (load average "
            f"{os.getloadavg()[0]:.1f})"
        )
        if res.windows:
            print(f"  largest jump of a measured state at a join: {res.windows['largest_jump_sigma']:.2f} σ")
        print(f"  {note}")
        print(f"  integrator: halving the 50 ms step moves the estimates by at most {res.step_check:.3f} σ")
        print(f"  {'parameter':28s} {'truth':>9s} {'estimate':>10s} {'(est−truth)/σ':>14s} {'σ/|value|':>10s}")
        for n, tv, v, sg in zip(res.parameters, true, res.values, res.sigma):
            print(f"  {n:28s} {tv:9.4g} {v:10.4g} {(v - tv) / sg:14.2f} {sg / abs(v):10.3f}")
        z = (res.values - true) / res.sigma
        print(f"  |estimate − truth|/σ: max {np.max(np.abs(z)):.2f}, RMS {np.sqrt(np.mean(z**2)):.2f} (1 expected)")


def _auto_decision(truth: object, params: list, base: object, runs: list) -> None:
    """What ``window="auto"`` decides on these runs at the base values (the growth of an initial
    velocity error over each run)."""
    from hydrokit.sysid.model import prepare_run, values_of
    from hydrokit.sysid.smooth import smooth_run
    from hydrokit.sysid.window import DRIFT_GROWTH, drift

    found = []
    for run in runs:
        prep = prepare_run(run, truth.thrusters, 0.05, surfaces=truth.surfaces.names)  # type: ignore[attr-defined]
        sm = smooth_run(run)
        found += drift(base, params, values_of(base, params), [prep], [sm.at(0.0)], [sm.known], threshold=0.0)  # type: ignore[arg-type]
    grow = [float(f.split(" grows ")[1].rstrip("×)")) for f in found if " grows " in f]
    print(
        f"windows: an initial velocity error grows at most {max(grow, default=float('nan')):.3g}× over a run "
        f"(auto windows above {DRIFT_GROWTH:g}×); {len(found) - len(grow)} run(s) diverge at the base values"
    )


def _plan(base: object, names: list[str]) -> None:
    from hydrokit.sysid.data import generate_runs
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.plan import plan_excitation

    t = time.perf_counter()
    plan = plan_excitation(base, names, 60.0, evaluations=40)  # type: ignore[arg-type]
    wall = time.perf_counter() - t
    print(
        f"plan: 12 parameters, 60 s schedule, {plan.evaluations} designs in {wall:.1f} s; σ / σ(random multi-sine) "
        f"{np.min(plan.ratio):.2f}–{np.max(plan.ratio):.2f} (geometric mean {1 / plan.gain:.2f}); "
        f"condition number {plan.condition:.3g}"
    )
    run = generate_runs(base, 1, seed=77, commands=plan.commands)  # type: ignore[arg-type]
    res = identify(base, run, names, samples=0, check_step=False)  # type: ignore[arg-type]
    q = res.fisher_sigma / plan.sigma
    print(f"  a dive flown with it: fit's Fisher σ / planned σ {np.min(q):.3f}–{np.max(q):.3f} (target 1)")
    for m in plan.messages:
        print(f"  note: {m}")


if __name__ == "__main__":
    main()
