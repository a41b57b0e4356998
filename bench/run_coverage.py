"""Coverage of the main job's confidence intervals on virtual campaigns with known truth.

For each seed, the bundled udrobot project's three campaigns (spring surge, pendulum sway and
heave: 4 amplitudes × 6 launches each, with the bundled sensor lag, quantisation, release
scatter and push) are simulated anew and identified as ``hydrokit run`` does; a coefficient is
covered when its true value lies inside the 95 % interval: both the Student-t CI of the launch
mean and the interval ``hydrokit run`` states (launch scatter plus between-amplitude-group
variance, the ``uncertainty:`` block of vehicle.yaml) are counted. Scaling to full size
multiplies value and interval by the same factor, so coverage at model scale is coverage of
the chosen full-scale values. Prints the coverage per coefficient and over all DOF × coefficient
pairs (acceptance: ≥ 90 %).

    .venv/bin/python bench/run_coverage.py [--seeds N]   (default 50; about 1.5 s per seed)
"""

from __future__ import annotations

import argparse
import importlib.util
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _generator():
    """The bundled campaigns' generator (scripts/make_campaigns.py): sensors and release model."""
    spec = importlib.util.spec_from_file_location("make_campaigns", ROOT / "scripts" / "make_campaigns.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seeds", type=int, default=50)
    args = ap.parse_args()
    import math

    from hydrokit.api import load_rig
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.identify.result import identify_launches
    from hydrokit.identify.virtual_rig import simulate_launch
    from hydrokit.io.project import load_project
    from hydrokit.pipeline.tank import campaign_covariance, t95

    gen = _generator()
    project = load_project("udrobot")
    setups = {
        "surge": (gen.ENCODER, [0.010, 0.020, 0.030, 0.040], 8.0),
        "sway": (gen.IMU, [math.radians(a) for a in (2.5, 5, 10, 15)], 15.0),
        "heave": (gen.IMU, [math.radians(a) for a in (2.5, 5, 10, 15)], 15.0),
    }
    coefs = ("added_mass", "linear_damping", "quadratic_damping")
    hits = {(c.dof, k): 0 for c in project.campaigns for k in coefs}
    hits_total = dict(hits)
    t0 = time.perf_counter()
    for seed in range(args.seeds):
        for camp in project.campaigns:
            rig = load_rig(camp.rig)
            sensor, amps, duration = setups[camp.dof]
            rng = np.random.default_rng([10_000 + seed, ("surge", "sway", "heave").index(camp.dof)])
            truth = [camp.truth[k] for k in coefs]
            launches = []
            for a in amps:
                for j in range(6):
                    raw = simulate_launch(
                        rig,
                        *truth,
                        a,
                        duration,
                        sensor,
                        rng,
                        file=f"{camp.dof}_{a:.4g}_{j}",
                        amplitude_jitter=gen.AMPLITUDE_JITTER,
                        release_rate_std=gen.PUSH * abs(a),
                    )
                    launches.append(trim_launch(raw))
            res = identify_launches(rig, launches, camp.method)
            total = campaign_covariance(res.results, res.summary, res.groups)["total"]
            for i, k in enumerate(coefs):
                lo, hi = res.summary[k]["ci"]
                hits[(camp.dof, k)] += int(lo is not None and lo <= camp.truth[k] <= hi)
                half = t95(res.summary[k]["n"]) * math.sqrt(total[i, i])
                hits_total[(camp.dof, k)] += int(abs(res.summary[k]["mean"] - camp.truth[k]) <= half)
        print(f"seed {seed + 1}/{args.seeds} done ({time.perf_counter() - t0:.0f} s)", flush=True)
    print(f"{'DOF':<7}{'coefficient':<20}{'launch CI':>11}{'stated CI':>11}")
    for key, n in hits.items():
        print(f"{key[0]:<7}{key[1]:<20}{n:>7}/{args.seeds}{hits_total[key]:>7}/{args.seeds}")
    for label, h in (("launch-mean Student-t CI", hits), ("stated CI (launches + amplitude groups)", hits_total)):
        cover = sum(h.values()) / (len(h) * args.seeds)
        print(
            f"coverage of the 95 % {label} over {len(h)} DOF × coefficient pairs and {args.seeds} seeds: "
            f"{100 * cover:.1f} % (acceptance >= 90 %)"
        )


if __name__ == "__main__":
    main()
