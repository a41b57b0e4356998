"""``hydrokit rig simulate|plan``: the virtual rig and Cramér–Rao experiment planning.

Heavy imports stay inside the command functions so ``hydrokit --help`` starts fast.
"""

from __future__ import annotations

import click

from hydrokit.cli._common import check_out_dir, write_all
from hydrokit.cli._rig_options import _amplitudes, _common, _sensor
from hydrokit.cli._types import NON_NEGATIVE, SEED, Count


@click.group()
def rig() -> None:
    """Virtual rig: simulate launches like a real test, or plan an experiment."""


@rig.command("simulate")
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@_common
@click.option("--launches", type=Count(1), default=6, show_default=True, help="Launches per amplitude (count).")
@click.option("--hold", type=NON_NEGATIVE, default=0.5, show_default=True, help="Still record before each release, s.")
@click.option("--seed", type=SEED, default=0, show_default=True, help="Random seed for the sensor noise (integer).")
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Directory for the launch CSVs."
)
def rig_simulate(
    rig_file: str,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    amplitudes: list[float],
    duration: float,
    sample_rate: float | None,
    noise: float | None,
    resolution: float | None,
    launches: int,
    hold: float,
    seed: int,
    out_dir: str,
) -> None:
    """Write launch CSVs of RIG.yaml with the given true coefficients, like a real test."""
    import numpy as np

    from hydrokit.identify.virtual_rig import simulate_launch
    from hydrokit.io.launch import launch_csv
    from hydrokit.io.rig import load_rig

    out = check_out_dir(out_dir)  # before the launches are simulated
    r = load_rig(rig_file)
    amps = _amplitudes(amplitudes, r)
    sensor = _sensor(r, sample_rate, noise, resolution, hold)
    rng = np.random.default_rng(seed)
    texts = {}
    column = "position" if r.translational_signal else "angle"
    for i, a in enumerate(amps):
        for j in range(launches):
            L = simulate_launch(r, added_mass, linear_damping, quadratic_damping, a, duration, sensor, rng)
            name = f"{r.test}_{r.axis}_L{i + 1}_{j + 1:02d}.csv"
            comments = [
                f"virtual rig: {r.test} {r.axis}, amplitude {a:g} {'m' if column == 'position' else 'rad'}",
                f"true m_a = {added_mass:g}, K_L = {linear_damping:g}, K_Q = {quadratic_damping:g} (SI)",
                f"sensor: {sensor.name}, seed {seed}",
            ]
            texts[name] = launch_csv(L.t, L.y, column, comments)
    write_all({out / name: text for name, text in texts.items()})
    click.echo(f"wrote {len(texts)} launch files to {out_dir}")


@rig.command("plan")
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@_common
@click.option("--launches", type=Count(1), default=6, show_default=True, help="Launches per amplitude (count).")
def rig_plan(
    rig_file: str,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    amplitudes: list[float],
    duration: float,
    sample_rate: float | None,
    noise: float | None,
    resolution: float | None,
    launches: int,
) -> None:
    """Predict each coefficient's standard error (Cramér–Rao bound) per candidate amplitude."""
    from rich.console import Console
    from rich.table import Table

    from hydrokit.identify.design import plan_experiment, recommend
    from hydrokit.io.rig import load_rig

    r = load_rig(rig_file)
    amps = _amplitudes(amplitudes, r)
    sensor = _sensor(r, sample_rate, noise, resolution, 0.0)
    plan = plan_experiment(r, added_mass, linear_damping, quadratic_damping, amps, sensor, duration, launches)
    tab = Table(title=f"predicted standard errors, {launches} launch(es) per amplitude, sensor {sensor.name}")
    for c in ("amplitude", "peak speed (m/s)", "σ(m_a)", "σ(K_L)", "σ(K_Q)", "σ(damping force) at peak"):
        tab.add_column(c, justify="right")
    for row, a in zip(plan, amplitudes):
        tab.add_row(
            f"{a:g}" + (" mm" if r.translational_signal else "°"),
            f"{row['speed_max']:.3g}",
            *(
                f"{row[k]:.3g} ({_percent(row[k + '_rel'])})"
                for k in ("added_mass", "linear_damping", "quadratic_damping")
            ),
            f"{100 * row['damping_force_rel']:.2g} %",
        )
    Console().print(tab)
    click.echo(recommend(plan))


def _percent(rel: float) -> str:
    """A relative error as a percentage; "–" where it has no finite value (a true value of 0 or
    one so small that σ / |value| overflows)."""
    import math

    return f"{100 * rel:.2g} %" if math.isfinite(100 * rel) else "– %"
