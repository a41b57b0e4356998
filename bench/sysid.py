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
  < 60 s), how much of it is simulation, and the integrator check (halving the step must move
  no estimate by more than 0.1 σ).

- plan: a D-optimal 60 s schedule for the 12 parameters (``hydrokit sysid plan``), its
  Cramér–Rao σ over that of the generator's random multi-sines, and the Fisher σ of a fit of
  a dive flown with it over the planned σ (1 = the plan's promise kept).

    python bench/sysid.py [--datasets 100] [--duration 30] [--skip-speed] [--skip-coverage] [--skip-plan]

``--datasets 10`` gives a quick look (coverage then has a ± 7 % sampling error).
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--datasets", type=int, default=100, help="generated data sets for the coverage (count)")
    ap.add_argument("--duration", type=float, default=30.0, help="length of each coverage dive, s")
    ap.add_argument("--runs", type=int, default=2, help="training dives per coverage data set (count)")
    ap.add_argument("--skip-speed", action="store_true")
    ap.add_argument("--skip-coverage", action="store_true")
    ap.add_argument("--skip-plan", action="store_true")
    args = ap.parse_args()

    import numba

    import hydrokit
    from hydrokit.simulate.sysid import identify
    from hydrokit.simulate.sysid_data import HIDDEN, generate_runs, hidden_vehicle
    from hydrokit.simulate.sysid_model import free_parameters, values_of

    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    base = hydrokit.load_vehicle("bluerov2-sysid")
    names = list(HIDDEN)

    if not args.skip_speed:
        truth = hidden_vehicle(base, 1000)
        runs = generate_runs(truth, 5, 90.0, seed=1000)
        identify(base, runs[:1], names[:2], samples=0, check_step=False)  # load compiled kernels
        t = time.perf_counter()
        res = identify(base, runs[:4], names, holdout=runs[4:], samples=40)
        wall = time.perf_counter() - t
        sim = res.timing["simulation"]
        print(
            f"speed: 12 parameters from 4 × 90 s on 2 threads: {wall:.1f} s wall (target < 60 s), of which "
            f"simulation {sim:.1f} s ({100 * sim / wall:.0f} %), {res.iterations} iterations; "
            f"{'PASS' if wall < 60 else 'FAIL'}"
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


def _plan(base: object, names: list[str]) -> None:
    from hydrokit.simulate.sysid import identify
    from hydrokit.simulate.sysid_data import generate_runs
    from hydrokit.simulate.sysid_plan import plan_excitation

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
