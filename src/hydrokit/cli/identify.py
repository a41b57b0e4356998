"""``hydrokit identify``, ``hydrokit scale`` and ``hydrokit rig simulate|plan``.

Heavy imports stay inside the command functions so ``hydrokit --help`` starts fast.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import click

from hydrokit.errors import InputError

METHOD_CHOICE = click.Choice(["output-error", "equation-error", "morison", "log-decrement"])


def _floats(text: str, option: str) -> list[float]:
    try:
        vals = [float(x) for x in text.replace(";", ",").split(",") if x.strip()]
    except ValueError:
        raise InputError(f"{option} {text!r}: expected comma-separated numbers") from None
    if not vals or not all(math.isfinite(v) for v in vals):
        raise InputError(f"{option} {text!r}: expected finite comma-separated numbers")
    return vals


def progress_bar():  # noqa: ANN201
    """A rich progress bar on stderr (transient)."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                    console=Console(stderr=True), transient=True)


@click.command()
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@click.argument("launches", metavar="LAUNCH.csv...", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option("--json", "json_out", required=True, type=click.Path(dir_okay=False),
              help="Write the results (coefficients in SI: kg, N·s/m, N·s²/m²; rad/s) to this JSON file.")
@click.option("--method", type=METHOD_CHOICE, default="output-error", show_default=True,
              help="Estimator (no unit): output-error (most accurate), equation-error (CHIN2012), "
                   "morison (CELY2019, K_L = 0) or log-decrement (CELY2019 graphical).")
@click.option("--plots", "plots_dir", type=click.Path(file_okay=False), default=None,
              help="Write one fit/residual PNG per launch and coefficients-vs-Reynolds here (directory).")
@click.option("--report", "report_out", type=click.Path(dir_okay=False), default=None,
              help="Also write a self-contained HTML report (file).")
@click.option("--release", type=float, default=None, help="Release time in every launch, s (default: detected).")
@click.option("--end", type=float, default=None, help="Last useful time in every launch, s (default: detected).")
def identify(rig_file: str, launches: tuple[str, ...], json_out: str, method: str, plots_dir: str | None,
             report_out: str | None, release: float | None, end: float | None) -> None:
    """Identify added mass, linear and quadratic damping from free-decay LAUNCH files.

    RIG.yaml describes the rig and body (SI units; see docs/identify.md). Each LAUNCH.csv has
    columns time (s) and position (m, spring) or angle (rad) / angle_deg (pendulum, torsion).
    Nothing is written unless every launch is identified.
    """
    from hydrokit._atomic import write_bytes, write_text
    from hydrokit.io.results import dumps, identify_files, results_document
    from hydrokit.io.rig import load_rig

    rig = load_rig(rig_file)
    with progress_bar() as bar:
        task = bar.add_task(f"identifying ({method})", total=len(launches))
        items = identify_files(rig, launches, method, release, end, progress=lambda f: bar.advance(task))
    doc = results_document(rig, items, method)
    text = dumps(doc)
    files: dict[str, bytes] = {}
    if plots_dir or report_out:
        figs = _figures(rig, items, method, per_launch=bool(plots_dir))
        if plots_dir:
            files.update({str(Path(plots_dir) / name): png for name, (png, _) in figs.items()})
        if report_out:
            from hydrokit.report.identify import Run, identify_report

            run = Run(f"{rig.test} rig, {rig.axis}", rig, {method: doc}, list(figs.values())[:8])
            files[report_out] = identify_report("hydrokit identification", [run]).encode("utf-8")
    write_text(json_out, text)
    for path, data in files.items():
        write_bytes(path, data)
    _print_summary(doc, rig)
    click.echo(f"wrote {json_out}" + (f" and {len(files)} more file(s)" if files else ""), err=True)


def _figures(rig: Any, items: list[Any], method: str, per_launch: bool = True) -> dict[str, tuple[bytes, str]]:
    import numpy as np

    from hydrokit.plot._mpl import pyplot, to_png
    from hydrokit.plot.identify import coefficients_vs_reynolds, drag_per_cycle, launch_fit

    plt = pyplot()
    unit = "m" if rig.test == "spring" else "rad"
    out: dict[str, tuple[bytes, str]] = {}
    chosen = items if per_launch else items[:: max(1, len(items) // 4)][:4]
    for it in chosen:
        t = np.asarray(it.launch.t)
        stem = Path(it.result.file).stem
        fig = launch_fit(t, np.asarray(it.launch.y), it.estimator.predict(t), f"{stem} ({method})", unit)
        out[f"{stem}_fit.png"] = (to_png(fig), f"{stem}: measured and fitted signal, residual")
        plt.close(fig)
    fig = coefficients_vs_reynolds({f"{rig.axis} ({method})": [it.result for it in items]})
    out["coefficients_vs_reynolds.png"] = (to_png(fig), "coefficients against peak Reynolds number")
    plt.close(fig)
    cycles = [c for it in items for c in it.result.extra.get("cycles", [])]
    if cycles:
        fig = drag_per_cycle(cycles, f"{rig.axis}: C_D per cycle")
        out["drag_per_cycle.png"] = (to_png(fig), "C_D per cycle against the cycle's Reynolds number")
        plt.close(fig)
    return out


def _print_summary(doc: dict[str, Any], rig: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    from hydrokit.report.html import fmt

    u = doc["units"]
    tab = Table(title=f"{rig.test} rig, {rig.axis}: {doc['method']} ({len(doc['launches'])} launches)")
    for col in ("coefficient", "mean", "std", "95 % CI", "n", "rejected"):
        tab.add_column(col, justify="left" if col == "coefficient" else "right")
    for key in ("added_mass", "added_mass_coefficient", "linear_damping", "quadratic_damping", "drag_coefficient",
                "natural_frequency", "damping_ratio"):
        s = doc["summary"][key]
        if s["mean"] is None:
            continue
        label = f"{key} ({u[key]})" if key in u else key
        ci = s["ci"]
        tab.add_row(label, fmt(s["mean"]), fmt(s["std"]), f"[{fmt(ci[0])}, {fmt(ci[1])}]" if ci[0] is not None else "–",
                    str(s["n"]), str(len(s["rejected"])))
    Console().print(tab)


@click.command()
@click.option("--ratio", type=float, required=True, help="Model/full-size length ratio, e.g. 0.3 for a 30 % model (no unit).")
@click.option("--added-mass", type=float, default=None, help="Model added mass, kg (kg·m² with --rotational).")
@click.option("--linear-damping", type=float, default=None, help="Model K_L, N·s/m (N·m·s/rad with --rotational).")
@click.option("--quadratic-damping", type=float, default=None, help="Model K_Q, N·s²/m² (N·m·s²/rad² with --rotational).")
@click.option("--rotational", is_flag=True, help="Coefficients of a rotational DOF (added inertia and damping ∝ λ⁵).")
def scale(ratio: float, added_mass: float | None, linear_damping: float | None, quadratic_damping: float | None,
          rotational: bool) -> None:
    """Scale model-test coefficients to full size (ENG2009 similitude) and print the assumptions."""
    from hydrokit.identify.scaling import SCALING_ASSUMPTIONS, scale_coefficients, scale_factor

    lam = scale_factor(ratio)
    vals = {k: v for k, v in (("added_mass", added_mass), ("linear_damping", linear_damping),
                              ("quadratic_damping", quadratic_damping)) if v is not None}
    if not vals:
        raise InputError("give at least one of --added-mass, --linear-damping, --quadratic-damping")
    full = scale_coefficients(vals, lam, rotational)
    click.echo(f"λ = L_full / L_model = {lam:.6g}")
    for k, v in vals.items():
        click.echo(f"{k}: model {v:.6g} → full scale {full[k]:.6g}")
    click.echo("assumptions:")
    for a in SCALING_ASSUMPTIONS:
        click.echo(f"  - {a}")


@click.group()
def rig() -> None:
    """Virtual rig: simulate launches like a real test, or plan an experiment."""


def _sensor(rig_obj: Any, sample_rate: float | None, noise: float | None, resolution: float | None, hold: float) -> Any:
    from hydrokit.identify.virtual_rig import SensorModel

    if rig_obj.test == "spring":
        base = SensorModel.encoder(hold_time=hold)
        noise_si = 0.0 if noise is None else noise * 1e-3
        res_si = base.resolution if resolution is None else resolution * 1e-3
    else:
        base = SensorModel.imu(hold_time=hold)
        noise_si = base.noise_std if noise is None else math.radians(noise)
        res_si = 0.0 if resolution is None else math.radians(resolution)
    rate = base.sample_rate if sample_rate is None else sample_rate
    unit = "mm" if rig_obj.test == "spring" else "°"
    name = f"{rate:g} Hz, noise {noise_si * (1e3 if unit == 'mm' else 180 / math.pi):.3g} {unit}, step {res_si * (1e3 if unit == 'mm' else 180 / math.pi):.3g} {unit}"
    return SensorModel(rate, noise_si, res_si, hold, name)


_COMMON = [
    click.option("--added-mass", type=float, required=True, help="True added mass m_a, kg (kg·m² torsion)."),
    click.option("--linear-damping", type=float, required=True, help="True K_L, N·s/m (N·m·s/rad torsion)."),
    click.option("--quadratic-damping", type=float, required=True, help="True K_Q, N·s²/m² (N·m·s²/rad² torsion)."),
    click.option("--amplitudes", required=True, help="Release displacements, comma-separated: mm (spring) or degrees (pendulum, torsion)."),
    click.option("--duration", type=float, default=20.0, show_default=True, help="Recorded time after the release, s."),
    click.option("--sample-rate", type=float, default=None, help="Sensor sample rate, Hz (default 100)."),
    click.option("--noise", type=float, default=None, help="Sensor noise std: mm (spring, default 0) or degrees (default 0.05)."),
    click.option("--resolution", type=float, default=None, help="Sensor step: mm (spring, default 1/2.45 = 0.408) or degrees (default 0)."),
]


def _common(f):  # noqa: ANN001, ANN202
    for opt in reversed(_COMMON):
        f = opt(f)
    return f


def _amplitudes(text: str, rig_obj: Any) -> list[float]:
    vals = _floats(text, "--amplitudes")
    if any(v == 0 for v in vals):
        raise InputError(f"--amplitudes {text!r}: expected non-zero displacements")
    return [v * 1e-3 for v in vals] if rig_obj.test == "spring" else [math.radians(v) for v in vals]


@rig.command("simulate")
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@_common
@click.option("--launches", type=int, default=6, show_default=True, help="Launches per amplitude (count).")
@click.option("--hold", type=float, default=0.5, show_default=True, help="Still record before each release, s.")
@click.option("--seed", type=int, default=0, show_default=True, help="Random seed for the sensor noise (integer).")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Directory for the launch CSVs.")
def rig_simulate(rig_file: str, added_mass: float, linear_damping: float, quadratic_damping: float, amplitudes: str,
                 duration: float, sample_rate: float | None, noise: float | None, resolution: float | None,
                 launches: int, hold: float, seed: int, out_dir: str) -> None:
    """Write launch CSVs of RIG.yaml with the given true coefficients, like a real test."""
    import numpy as np

    from hydrokit._atomic import write_text
    from hydrokit.identify.virtual_rig import simulate_launch
    from hydrokit.io.launch import launch_csv
    from hydrokit.io.rig import load_rig

    r = load_rig(rig_file)
    amps = _amplitudes(amplitudes, r)
    if launches < 1:
        raise InputError(f"--launches {launches}: expected at least 1")
    sensor = _sensor(r, sample_rate, noise, resolution, hold)
    rng = np.random.default_rng(seed)
    texts = {}
    column = "position" if r.test == "spring" else "angle"
    for i, a in enumerate(amps):
        for j in range(launches):
            L = simulate_launch(r, added_mass, linear_damping, quadratic_damping, a, duration, sensor, rng)
            name = f"{r.test}_{r.axis}_L{i + 1}_{j + 1:02d}.csv"
            comments = [f"virtual rig: {r.test} {r.axis}, amplitude {a:g} {'m' if column == 'position' else 'rad'}",
                        f"true m_a = {added_mass:g}, K_L = {linear_damping:g}, K_Q = {quadratic_damping:g} (SI)",
                        f"sensor: {sensor.name}, seed {seed}"]
            texts[name] = launch_csv(L.t, L.y, column, comments)
    for name, text in texts.items():
        write_text(Path(out_dir) / name, text)
    click.echo(f"wrote {len(texts)} launch files to {out_dir}")


@rig.command("plan")
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@_common
@click.option("--launches", type=int, default=6, show_default=True, help="Launches per amplitude (count).")
def rig_plan(rig_file: str, added_mass: float, linear_damping: float, quadratic_damping: float, amplitudes: str,
             duration: float, sample_rate: float | None, noise: float | None, resolution: float | None, launches: int) -> None:
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
    for row, a in zip(plan, amplitudes.split(",")):
        tab.add_row(a.strip() + (" mm" if r.test == "spring" else "°"), f"{row['speed_max']:.3g}",
                    f"{row['added_mass']:.3g} ({100 * row['added_mass_rel']:.2g} %)",
                    f"{row['linear_damping']:.3g} ({100 * row['linear_damping_rel']:.2g} %)",
                    f"{row['quadratic_damping']:.3g} ({100 * row['quadratic_damping_rel']:.2g} %)",
                    f"{100 * row['damping_force_rel']:.2g} %")
    Console().print(tab)
    click.echo(recommend(plan))
