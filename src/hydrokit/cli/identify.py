"""``hydrokit identify`` and ``hydrokit scale`` (thin layers over :func:`hydrokit.identify_campaign`).

Heavy imports stay inside the command functions so ``hydrokit --help`` starts fast.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import click

from hydrokit.cli._common import progress_bar, write_all
from hydrokit.errors import InputError

METHOD_CHOICE = click.Choice(["output-error", "equation-error", "morison", "log-decrement"])


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
    from hydrokit.api import identify_campaign, load_rig
    from hydrokit.io.results import dumps

    rig = load_rig(rig_file)
    with progress_bar() as bar:
        task = bar.add_task(f"identifying ({method})", total=len(launches))
        res = identify_campaign(rig, launches, method, release=release, end=end, progress=lambda f: bar.advance(task))
    doc = res.to_dict()
    files: dict[str | Path, Any] = {json_out: dumps(doc)}
    if plots_dir or report_out:
        from hydrokit.plot.identify import campaign_figures

        figs = campaign_figures(res, per_launch=bool(plots_dir))
        if plots_dir:
            files.update({Path(plots_dir) / name: png for name, (png, _) in figs.items()})
        if report_out:
            from hydrokit.report.identify import Run, identify_report

            run = Run(f"{rig.test} rig, {rig.axis}", rig, {method: doc}, list(figs.values())[:8])
            files[report_out] = identify_report("hydrokit identification", [run])
    write_all(files)
    _print_summary(doc, rig)
    click.echo(f"wrote {json_out}" + (f" and {len(files) - 1} more file(s)" if len(files) > 1 else ""), err=True)


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
