"""``hydrokit identify``: a thin layer over :func:`hydrokit.identify_campaign` (heavy imports inside)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._common import check_outputs, progress_bar, write_all
from hydrokit.cli._rig_options import trim_options, trim_settings

METHOD_CHOICE = click.Choice(["output-error", "equation-error", "morison", "log-decrement"])


@click.command()
@click.argument("rig_file", metavar="RIG.yaml", type=click.Path(dir_okay=False))
@click.argument("launches", metavar="LAUNCH.csv...", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option(
    "--json",
    "json_out",
    required=True,
    type=click.Path(dir_okay=False),
    help="Write the results (coefficients in SI: kg, N·s/m, N·s²/m²; rad/s) to this JSON file.",
)
@click.option(
    "--method",
    type=METHOD_CHOICE,
    default="output-error",
    show_default=True,
    help="Estimator (no unit): output-error (most accurate), equation-error (CHIN2012), "
    "morison (CELY2019, K_L = 0) or log-decrement (CELY2019 graphical).",
)
@click.option(
    "--plots",
    "plots_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="Write per launch fit/residual, damping-curve and adequacy PNGs and coefficients-vs-Reynolds here (directory).",
)
@click.option(
    "--report",
    "report_out",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write a self-contained HTML report (file).",
)
@click.option(
    "--damping-model",
    type=click.Choice(["linear", "quadratic", "cubic"]),
    default="quadratic",
    show_default=True,
    help="Damping fitted (no unit): B1 q̇, + B2 |q̇| q̇, + B3 q̇³ (cubic_damping: N·s³/m³ or N·m·s³/rad³). "
    "Output-error; spring, torsion and floating rigs.",
)
@click.option(
    "--restoring-terms",
    type=click.Choice(["1", "3", "5"]),
    default="1",
    show_default=True,
    help="1: the rig's restoring; 3, 5: also fit C3 q³ (and C5 q⁵) added to it (restoring_correction, SI). "
    "Output-error; spring, torsion and floating rigs.",
)
@trim_options
def identify(
    rig_file: str,
    launches: tuple[str, ...],
    json_out: str,
    method: str,
    plots_dir: str | None,
    report_out: str | None,
    damping_model: str,
    restoring_terms: str,
    **record: Any,
) -> None:
    """Identify added mass, linear and quadratic damping from free-decay LAUNCH files.

    RIG.yaml describes the rig and body (SI units; see docs/identify.md): spring, pendulum,
    torsion or floating (heave, roll, pitch). Each LAUNCH.csv has columns time (s) and position
    (m: spring, floating heave) or angle (rad) / angle_deg (pendulum, torsion, floating roll/pitch).
    Nothing is written unless every launch is identified.
    """
    from hydrokit.api import identify_campaign, load_rig
    from hydrokit.io.results import dumps

    check_outputs({"--json": json_out, "--report": report_out}, {"--plots": plots_dir})  # before the fits
    rig = load_rig(rig_file)
    # --start/--end/--detrend as given; the amplitudes converted to SI
    window, amps = trim_settings(rig, record.pop("amplitude_window"), record.pop("equivalent_at"))
    with progress_bar() as bar:
        task = bar.add_task(f"identifying ({method})", total=len(launches))
        res = identify_campaign(
            rig,
            launches,
            method,
            progress=lambda f: bar.advance(task),
            damping_model=damping_model,
            restoring_terms=int(restoring_terms),
            **record,
            amplitude_window=window,
            equivalent_at=amps,
        )
    doc = res.to_dict()
    files: dict[str | Path, Any] = {json_out: dumps(doc)}
    if plots_dir or report_out:
        from hydrokit.plot.adequacy import adequacy_figures
        from hydrokit.plot.identify import campaign_figures

        figs = campaign_figures(res, per_launch=bool(plots_dir))
        adequacy = adequacy_figures(res, per_launch=bool(plots_dir))  # <launch>_adequacy.png → (png, caption)
        if plots_dir:
            files.update({Path(plots_dir) / name: png for name, (png, _) in {**figs, **adequacy}.items()})
        if report_out:
            from hydrokit.report.identify import Run, identify_report

            run = Run(f"{rig.test} rig, {rig.axis}", rig, {method: doc}, list(figs.values())[:8], adequacy)
            files[report_out] = identify_report("hydrokit identification", [run])
    write_all(files)
    _print_summary(doc, rig)
    click.echo(f"wrote {json_out}" + (f" and {len(files) - 1} more file(s)" if len(files) > 1 else ""), err=True)


def _print_summary(doc: dict[str, Any], rig: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    from hydrokit.identify.campaign import SUMMARY_FIELDS
    from hydrokit.report.html import fmt

    u = doc["units"]
    tab = Table(title=f"{rig.test} rig, {rig.axis}: {doc['method']} ({len(doc['launches'])} launches)")
    for col in ("coefficient", "mean", "std", "95 % CI", "n", "rejected"):
        tab.add_column(col, justify="left" if col == "coefficient" else "right")
    for key in SUMMARY_FIELDS[:7]:  # the coefficients, without Re and KC
        s = doc["summary"][key]
        if s["mean"] is None:
            continue
        label = f"{key} ({u[key]})" if key in u else key
        ci = s["ci"]
        tab.add_row(
            label,
            fmt(s["mean"]),
            fmt(s["std"]),
            f"[{fmt(ci[0])}, {fmt(ci[1])}]" if ci[0] is not None else "–",
            str(s["n"]),
            str(len(s["rejected"])),
        )
    Console().print(tab)
