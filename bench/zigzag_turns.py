"""Fits that predict manoeuvres outside their runs (issue #56 items 4 and 5).

Twelve zigzag trials (10/10, 15/15, 20/20, 25/5, 30/5, 35/5, each to starboard and to port, 150 s
at 20 Hz, sensor noise and a smoothed heading) of the KVLCC2-like 7 m tanker of
``hydrokit.sysid.ship`` (``TANKER``: course-unstable, a single screw's side moment that makes
its turn to starboard 9 % wider) are fitted by each estimator from a start 20–30 % off on its 21
terms; the fitted model then flies the ±35° turning circles at the service 11.8 rev/s
(``hydrokit.manoeuvre``, the model ``manoeuvre --turning-circle`` flies) with ``--draws``
vehicles drawn from the fit's covariance (``manoeuvre --samples``). Printed per estimator: the
advance, tactical diameter and steady speed in the turn against the truth's, per side (%), how
many of the six 95 % intervals hold the truth, the Mahalanobis distance d² of the estimate from
the truth (χ² with 21 degrees of freedom: mean 21, 95 % below 32 when the σ are honest), the
integrator check and the wall time. ``--asymmetry`` fits the default estimator with each way of
writing the side-to-side difference free (item 5).

    .venv/bin/python bench/zigzag_turns.py [--seeds 56] [--estimators default,ee,w30,...]
        [--draws 40] [--dt 0.01] [--asymmetry] [--runs 12] [--smoothing 1.0]

BLAS is pinned to one thread (as bench/sysid.py does): the compiled simulations use both cores.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import contextlib
import sys
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository's tests package

from tests.simulate.test_acceptance_zigzag_turns import turn  # noqa: E402

#: the estimators compared: label → (what it is, identify() options)
ESTIMATORS: dict[str, tuple[str, dict[str, Any]]] = {
    "default": ("hydrokit sysid's default (window auto)", {"window": "auto"}),
    "ee": ("equation error", {"method": "equation-error", "window": None}),
    "w30": ("output error, 30 s windows", {"window": 30.0}),
    "w30c": ("30 s windows joined by continuity (W = 1)", {"window": 30.0, "window_continuity": 1.0}),
    "w75": ("output error, 75 s windows", {"window": 75.0}),
    "whole": ("output error, whole runs, every column at the fit's step", {"window": None}),
    "w30+whole": ("30 s windows, then whole runs from their estimate", {"window": "auto", "drifts": True}),
}
#: the side-to-side terms tried by --asymmetry: label → the free names that replace the truth's
ASYMMETRY: dict[str, tuple[str, ...]] = {
    "propeller side force T": ("terms.Y_T(prop)", "terms.N_T(prop)"),
    "u² terms": ("terms.Y_uu", "terms.N_uu"),
    "neutral rudder (u² and T)": ("terms.Y_uu", "terms.N_uu", "terms.Y_T(prop)", "terms.N_T(prop)"),
    "constant": ("terms.Y_0", "terms.N_0"),
    "none": (),
}
L = 7.0
METRICS = ("advance", "tactical_diameter", "steady_speed")
#: the surge terms that set the speed loss in the turn
SURGE = ("terms.X_vv", "terms.X_vr", "terms.X_rr")


def predicted_turns(res: Any, draws: int, seed: int) -> dict[float, Any]:
    """Per side the fitted vehicle's turning circle with ``draws`` draws from the fit's covariance."""
    from hydrokit.manoeuvre.samples import add_intervals

    fitted = res.uncertain_vehicle()
    out = {}
    for side in (1.0, -1.0):
        tr = replace(turn(fitted, side), warnings=[])
        add_intervals(tr, fitted, draws, seed, lambda veh, side=side: turn(veh, side))
        out[side] = tr
    return out


def evaluate(label: str, res: Any, wall: float, truth_turns: dict[float, Any], true: np.ndarray, draws: int) -> dict:
    """One row of the table: errors per side (%), intervals holding, d², integrator check, time."""
    pred = predicted_turns(res, draws, 0)
    row: dict[str, Any] = {"label": label, "wall": wall, "iterations": res.iterations, "step_check": res.step_check}
    held = 0
    for side in (1.0, -1.0):
        for m in METRICS:
            t, f = truth_turns[side].metrics[m], pred[side].metrics[m]
            row[(side, m)] = 100 * (f / t - 1)
            iv = pred[side].intervals.get(m, {})
            held += bool(iv and iv["low95"] < t < iv["high95"])
            row[(side, m, "width")] = 100 * (iv["high95"] - iv["low95"]) / t if iv else float("nan")
    row["held"] = held
    e = res.values - true
    row["d2"] = float(e @ np.linalg.solve(res.covariance, e))
    row["estimator"] = getattr(res, "estimator", {}).get("why", "")
    row["timing"] = res.timing
    row["sigma"] = dict(zip(res.parameters, res.sigma))
    return row


def fmt(row: dict) -> str:
    cells = [f"{row['label']:8s}", f"{row['wall']:6.0f}", f"{row['iterations']:3d}"]
    for m in METRICS:
        cells.append(f"{row[(1.0, m)]:+6.2f}/{row[(-1.0, m)]:+6.2f}")
    cells += [f"{row['held']}/6", f"{row['d2']:7.0f}", f"{row['step_check']:5.2f}"]
    return "  ".join(cells)


HEAD = (
    f"{'fit':8s}  {'wall s':>6s}  {'it':>3s}  {'advance % p/s':>13s}  {'tactical % p/s':>13s}  "
    f"{'speed % p/s':>13s}  held  {'d²':>7s}  check"
)


def main() -> None:
    from hydrokit.api import vehicle_from_dict
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.model import free_parameters, values_of
    from hydrokit.sysid.ship import TANKER, TANKER_FREE, tanker_start, zigzag_runs

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="56", help="comma-separated seeds of the data sets")
    ap.add_argument("--estimators", default=",".join(ESTIMATORS), help=f"some of {', '.join(ESTIMATORS)}")
    ap.add_argument("--draws", type=int, default=40, help="vehicles drawn per turning circle")
    ap.add_argument("--dt", type=float, default=0.01, help="integration step of the fits, s")
    ap.add_argument("--runs", type=int, default=12, help="the first RUNS zigzags (each side in turn)")
    ap.add_argument("--smoothing", type=float, default=1.0, help="heading smoothing of the records, s")
    ap.add_argument("--asymmetry", action="store_true", help="item 5: each side-to-side term free in turn")
    args = ap.parse_args()

    truth = vehicle_from_dict(TANKER, "kvlcc2-like")
    truth_turns = {side: turn(truth, side) for side in (1.0, -1.0)}
    print(
        "truth: ±35° turning circles at 11.8 rev/s from 1.168 m/s: advance "
        + ", ".join(f"{truth_turns[s].metrics['advance'] / L:.3f}" for s in (1.0, -1.0))
        + " L, tactical diameter "
        + ", ".join(f"{truth_turns[s].metrics['tactical_diameter'] / L:.3f}" for s in (1.0, -1.0))
        + " L, steady speed "
        + ", ".join(f"{truth_turns[s].metrics['steady_speed']:.4f}" for s in (1.0, -1.0))
        + " m/s (port, starboard)"
    )
    _, params = free_parameters(truth, list(TANKER_FREE))
    true = values_of(truth, params)
    for seed in (int(s) for s in args.seeds.split(",")):
        runs = zigzag_runs(truth, seed, smoothing=args.smoothing)[: args.runs]
        start = vehicle_from_dict(tanker_start(seed), "start")
        print(
            f"\nseed {seed}: {len(runs)} zigzags × 150 s at 20 Hz, 21 free terms from 20–30 % off, dt {args.dt:g} s, "
            f"{args.draws} draws per turn (load average {os.getloadavg()[0]:.1f})"
        )
        if args.asymmetry:
            _asymmetry(truth, truth_turns, start, runs, args)
            continue
        print(HEAD)
        for key in args.estimators.split(","):
            what, opts = ESTIMATORS[key]
            t = time.perf_counter()
            with _drifting(opts.get("drifts", False)):
                fit_opts = {k: v for k, v in opts.items() if k != "drifts"}
                res = identify(start, runs, list(TANKER_FREE), samples=0, dt=args.dt, **fit_opts)
            row = evaluate(key, res, time.perf_counter() - t, truth_turns, true, args.draws)
            print(fmt(row), f"  {what}", flush=True)
            widths = "/".join(f"{row[(side, m, 'width')]:.2f}" for m in METRICS for side in (1.0, -1.0))
            sig = ", ".join(f"{n.removeprefix('terms.')} {row['sigma'][n]:.3g}" for n in SURGE)
            print(f"          95 % interval widths % (advance, tactical, speed; port/stbd) {widths}; σ {sig}")
            stages = ", ".join(f"{k} {v:.1f}" for k, v in row["timing"].items() if v >= 0.5)
            print(f"          seconds: {stages}")
            if row["estimator"]:
                print(f"          estimator: {row['estimator']}")


@contextlib.contextmanager
def _drifting(force: bool) -> Iterator[None]:
    """With ``force``, window="auto" takes every run for one that drifts at the start values (as
    the issue's runs did): the windows' stage runs before the whole runs'."""
    import hydrokit.sysid.window as W

    keep = W.drift
    if force:
        W.drift = lambda *a, **k: [f"{p.name} (forced by the bench)" for p in a[3]]  # type: ignore[assignment]
    try:
        yield
    finally:
        W.drift = keep


def _asymmetry(truth: Any, truth_turns: dict, start: Any, runs: list, args: Any) -> None:
    """Item 5: the truth's asymmetry is the propeller's side force (Y_T, N_T); each way of writing
    it is freed with the 19 symmetric terms, the truth's own asymmetric terms removed from the start."""
    from hydrokit.model.uncertainty import with_coefficients
    from hydrokit.sysid.fit import identify
    from hydrokit.sysid.ship import TANKER_FREE

    symmetric = [n for n in TANKER_FREE if n not in ASYMMETRY["propeller side force T"]]
    base = with_coefficients(start, dict.fromkeys(ASYMMETRY["propeller side force T"], 0.0))
    print(f"{'asymmetry free':24s} {'TD port':>8s} {'TD stbd':>8s}  stbd/port  (truth {_ratio(truth_turns):.3f})")
    for label, names in ASYMMETRY.items():
        res = identify(base, runs, symmetric + list(names), samples=0, dt=args.dt, window="auto")
        tr = {side: turn(res.vehicle, side) for side in (1.0, -1.0)}
        err = [
            100 * (tr[s].metrics["tactical_diameter"] / truth_turns[s].metrics["tactical_diameter"] - 1)
            for s in (1, -1)
        ]
        vals = ", ".join(
            f"{n} = {v:.4g} ± {s:.2g}" for n, v, s in zip(res.parameters, res.values, res.sigma) if n in names
        )
        print(f"{label:24s} {err[0]:+7.2f}% {err[1]:+7.2f}%  {_ratio(tr):.3f}  {vals}", flush=True)


def _ratio(turns: dict) -> float:
    return float(turns[-1.0].metrics["tactical_diameter"] / turns[1.0].metrics["tactical_diameter"])


if __name__ == "__main__":
    main()
