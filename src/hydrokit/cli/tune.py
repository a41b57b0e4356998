"""``hydrokit tune``: tune a mission's controller gains (a thin layer over
:func:`hydrokit.simulate.tune.tune_gains`)."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._common import check_out_dir, json_text, write_all
from hydrokit.cli._types import SECONDS, SEED, Count, Numbers


@click.command()
@click.argument("mission_file", metavar="MISSION")
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",  # checked by check_out_dir (one line naming --out), not by click
    help="Output directory (created if missing): tuned_mission.yaml, tune.json, convergence.png.",
)
@click.option(
    "--controller",
    type=click.Choice(["pid", "s-plane"]),
    required=True,
    help="Which gain set to tune (no unit).",
)
@click.option(
    "--weights",
    default="",
    help="Cost weights as name=value,…: cross_track (m per m of cross-track RMS, default 1), "
    "energy (m per kJ of thruster energy, default 0.001), saturation (m per s with a limit "
    "active, default 0.001), incomplete (m per waypoint not reached, default 10).",
)
@click.option(
    "--bounds",
    type=Numbers(2, "factor", positive=True),
    default="0.2,5",
    show_default=True,
    help="MIN,MAX factors (no unit) around the mission's gains that the search may use.",
)
@click.option("--maxiter", type=Count(1), default=50, show_default=True, help="Generations of differential evolution.")
@click.option("--popsize", type=Count(1), default=6, show_default=True, help="Population per tuned gain (no unit).")
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the search (no unit).")
@click.option(
    "--workers", type=Count(1), default=None, help="Threads flying each generation as one fleet (default: all cores)."
)
@click.option("--duration", type=SECONDS, default=None, help="Override the mission duration, s.")
def tune(
    mission_file: str,
    out_dir: str,
    controller: str,
    weights: str,
    bounds: list[float],
    maxiter: int,
    popsize: int,
    seed: int,
    workers: int | None,
    duration: float | None,
) -> None:
    """Tune the gains of MISSION (a mission YAML file or bundled name) for its vehicle.

    Minimises cross_track·RMS(m) + energy·E(kJ) + saturation·t_sat(s) + incomplete·(missed
    waypoints) over the controller's non-zero gains (kp, ki, kd or k1, k2 of every loop;
    limits and scales are kept) with scipy's differential evolution (seeded; each generation
    flown as one compiled fleet, runs stopping at the last waypoint; a diverging run costs
    1e6), then flies the tuned gains. Writes tuned_mission.yaml (loads with hydrokit
    mission), tune.json (cost and cross-track RMS before/after, gains, evaluations, time)
    and convergence.png.
    """
    from hydrokit.api import fly, load_mission, load_vehicle
    from hydrokit.errors import InputError
    from hydrokit.simulate.tune import parse_weights, tune_gains

    out = check_out_dir(out_dir)  # before the search: hours must not be lost to a bad folder
    lo, hi = bounds
    if not lo <= hi:
        raise InputError(f"--bounds {lo:g},{hi:g}: expected MIN,MAX factors with 0 < MIN ≤ MAX")
    w = parse_weights(weights)
    mis = load_mission(mission_file)
    vehicle = load_vehicle(mis.vehicle)
    res = tune_gains(
        mis,
        vehicle,
        controller,
        weights=w,
        bounds=(lo, hi),
        maxiter=maxiter,
        popsize=popsize,
        seed=seed,
        workers=workers,
        duration=duration,
    )
    flown = {
        "before": fly(mis, controller, vehicle=vehicle, duration=duration).metrics,
        "after": fly(res.mission, controller, vehicle=vehicle, duration=duration).metrics,
    }
    doc = res.to_dict() | {"source": mis.source, "flown": flown}
    files: dict[str, Any] = {
        "tune.json": json_text(doc),
        "tuned_mission.yaml": _mission_yaml(mis, controller, res.after),
    }
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.mission import convergence_figure

    title = f"{mis.name}: {controller} gain tuning ({res.evaluations} runs, {res.elapsed:.0f} s)"
    files["convergence.png"] = to_png(convergence_figure(res.convergence, res.cost_before, title))
    write_all({out / name: data for name, data in files.items()})
    b, a = flown["before"]["cross_track_rms"], flown["after"]["cross_track_rms"]
    click.echo(
        f"{mis.name} {controller}: cost {res.cost_before:.4g} -> {res.cost_after:.4g}, cross-track RMS "
        f"{b:.4g} -> {a:.4g} m ({res.evaluations} runs in {res.elapsed:.1f} s)"
    )
    click.echo(f"wrote {', '.join(sorted(files))} to {out}", err=True)


def _mission_yaml(mis: Any, controller: str, gains: dict[str, dict[str, float]]) -> str:
    """The mission file with the tuned gains as its controller (vehicle path made absolute)."""
    import yaml

    from hydrokit.io.mission import resolve_mission
    from hydrokit.io.yamlfile import read_yaml

    doc = read_yaml(resolve_mission(mis.source))
    doc["vehicle"] = mis.vehicle
    doc["controller"] = controller
    doc["controllers"] = dict(doc["controllers"]) | {
        controller: {lp: {k: float(v) for k, v in g.items()} for lp, g in gains.items()}
    }
    head = f"# {mis.name}: {controller} gains tuned by `hydrokit tune` from {mis.source}\n"
    return head + yaml.safe_dump(doc, sort_keys=False)
