"""``--samples N`` of ``hydrokit simulate`` and ``hydrokit mission``: vehicles drawn from the
vehicle file's ``uncertainty:`` block, flown, and their envelope written (shared by both)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from hydrokit.errors import InputError

F = TypeVar("F", bound=Callable[..., Any])

#: most samples one command draws (each is a whole run)
MAX_SAMPLES = 100_000


def samples_options(writes: str) -> Callable[[F], F]:
    """The ``--samples N`` and ``--seed`` options of a command that then also writes ``writes``."""

    def add(command: F) -> F:
        from hydrokit.cli._types import SEED, Count

        seed = click.option(
            "--seed", type=SEED, default=1, show_default=True, help="Seed of the --samples draw (integer)."
        )
        samples = click.option(
            "--samples",
            type=Count(0, MAX_SAMPLES),
            default=0,
            help=f"Also fly N vehicles drawn from the vehicle file's uncertainty: block (count); writes {writes}.",
        )
        return samples(seed(command))  # type: ignore[no-any-return]

    return add


def check_samples(
    vehicle: Any, samples: int, force_csv: Any = None, integrator: str = "rk4", attitude: str = "euler"
) -> None:
    """Refuse ``--samples`` the run cannot honour, before any work (0: no samples, nothing to check)."""
    if samples == 0:
        return
    if samples < 2:
        raise InputError(f"--samples {samples}: expected a whole number from 2 to {MAX_SAMPLES} (vehicles to draw)")
    if vehicle.uncertainty is None:
        raise InputError(
            f"--samples {samples}: vehicle '{vehicle.name}' has no 'uncertainty:' block with a σ > 0; expected a "
            "vehicle file written by 'hydrokit run' (or one with standard errors, SI)"
        )
    for option, value, wanted in (("--force-csv", force_csv, None), ("--integrator", integrator, "rk4")) + (
        ("--attitude", attitude, "euler"),
    ):
        if value != wanted:
            raise InputError(
                f"{option} {str(value)[:80]!r} with --samples: the samples fly the compiled RK4 in Euler angles "
                f"under a constant --force; expected {option} {wanted or 'not given'}"
            )


def sampled_files(
    vehicle: Any, nominal: Any, samples: int, seed: int, run: tuple[Any, ...], out_file: str, plots_dir: str | None
) -> tuple[dict[str, bytes], str]:
    """Fly ``samples`` drawn vehicles (``run`` = duration s, dt s, τ N/N·m, η₀, ν₀, current, output
    step count, constant deflections rad or None) and return the files OUT_envelope.csv, OUT_samples.csv (and envelope.png in
    ``plots_dir``) with a line on the final velocity's 5–95 % spread (empty for no samples)."""
    if samples == 0:
        return {}, ""
    from hydrokit.io.trajectory import table_csv
    from hydrokit.simulate.samples import simulate_samples

    duration, dt, tau, eta0, nu0, cur, every, deflection = run
    res = simulate_samples(vehicle, samples, seed, duration, dt, tau, eta0, nu0, cur, every, deflection)
    out = Path(out_file)
    stem = out.with_name(out.stem)
    files = {
        f"{stem}_envelope{out.suffix}": table_csv(*res.envelope_table()).encode(),
        f"{stem}_samples{out.suffix}": table_csv(*res.samples_table(), int_columns=("sample",)).encode(),
    }
    if plots_dir:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.vehicle import envelope_figure

        title = f"{vehicle.name}: {samples} vehicles from the file's covariance (seed {seed})"
        files[str(Path(plots_dir) / "envelope.png")] = to_png(envelope_figure(res.time, res.envelope, nominal, title))
    lo, hi = res.envelope["p5"][-1, 6:9], res.envelope["p95"][-1, 6:9]
    line = (
        f"\n{samples} samples of {len(res.parameters)} coefficient(s), final velocity 5–95 %: "
        + ", ".join(f"{n} {a:.4g} to {b:.4g} m/s" for n, a, b in zip("uvw", lo, hi))
        + (f"; {res.failed} run(s) diverged" if res.failed else "")
        + (f"; {res.clipped} drawn value(s) below 0 set to 0" if res.clipped else "")
    )
    return files, line


def mission_samples(
    mission: Any, vehicle: Any, results: dict[str, Any], samples: int, seed: int, duration: float | None, plots: bool
) -> tuple[dict[str, Any], str]:
    """Fly ``samples`` drawn vehicles with each controller of ``results`` (the nominal flights)
    and return monte_carlo.json (metric medians and 5–95 %, SI), envelope.csv (x, y, z bands per
    controller on a 0.5 s grid, m) and envelope.png, with a one-line summary."""
    if samples == 0:
        return {}, ""
    from dataclasses import replace

    import numpy as np

    from hydrokit._result import jsonable
    from hydrokit.cli._common import json_text
    from hydrokit.io.trajectory import table_csv
    from hydrokit.pipeline.fleet import SHOWN_PATHS, fly_one, grid_for, summarize_runs
    from hydrokit.simulate.samples import BANDS

    mis = mission if duration is None else replace(mission, duration=duration)
    grid = grid_for(mis)
    vehicles, values, clipped = vehicle.uncertainty.sample_vehicles(vehicle, samples, seed)
    doc: dict[str, Any] = {"samples": samples, "seed": seed, "parameters": list(vehicle.uncertainty.parameters)}
    doc |= {"sigma": vehicle.uncertainty.std, "clipped_at_zero": clipped, "controllers": {}}
    cols, table, envs, nominal, said = ["time"], [grid], {}, {}, []
    for kind, res in results.items():
        runs = [fly_one(mis, v, kind, grid) for v in vehicles]
        summary = summarize_runs(runs)
        doc["controllers"][kind] = {k: summary[k] for k in ("n", "completed_fraction", "metrics")}
        env = summary["envelope"]
        cols += [f"{kind}_{axis}_{band}" for axis in "xyz" for band in BANDS]
        table += [env[band][:, k] for k in range(3) for band in BANDS]
        paths = np.stack([r["path"] for r in runs[:SHOWN_PATHS]])
        envs[res.label] = {**env, "sample_paths": paths}
        nominal[res.label] = np.column_stack([np.interp(grid, res.time, res.eta[:, k], right=np.nan) for k in range(3)])
        x = summary["metrics"]["cross_track_rms"]
        if x["p5"] is not None:
            said.append(f"{x['p5']:.3f} to {x['p95']:.3f} m ({res.label})")
    files: dict[str, Any] = {
        "monte_carlo.json": json_text(jsonable(doc)),
        "envelope.csv": table_csv(cols, np.column_stack(table)),
    }
    if plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.mission import envelope_figure

        title = f"{mis.name}: {samples} vehicles from the file's covariance (seed {seed})"
        files["envelope.png"] = to_png(
            envelope_figure(np.asarray(mis.path.points, float), grid, envs, nominal, None, title)
        )
    line = f"{samples} samples of {len(vehicle.uncertainty.parameters)} coefficient(s): cross-track RMS 5–95 % " + (
        "; ".join(said) or "–"
    )
    return files, line + (f"; {clipped} drawn value(s) below 0 set to 0" if clipped else "")
