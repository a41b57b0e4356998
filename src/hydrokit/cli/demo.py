"""``hydrokit demo``: identify a bundled campaign and write an HTML report."""

from __future__ import annotations

import time
from pathlib import Path

import click

METHODS = {
    "spring": ("output-error", "equation-error", "log-decrement"),
    "pendulum": ("output-error", "equation-error", "morison"),
    "torsion": ("output-error", "equation-error", "log-decrement"),
}


@click.command()
@click.option(
    "--out",
    "out_dir",
    default="demo-report",
    show_default=True,
    type=click.Path(file_okay=False),
    help="Directory for report.html, results.json and the figures (directory).",
)
@click.option(
    "--campaign",
    type=click.Choice(["udrobot", "rov2"]),
    default="udrobot",
    show_default=True,
    help="Bundled campaign (no unit): udrobot (CELY2019-like spring and pendulum, 3 axes × 4 amplitudes × "
    "6 launches) or rov2 (ENG2009-like surge pendulum).",
)
def demo(out_dir: str, campaign: str) -> None:
    """Identify the bundled campaign with every method and write a self-contained HTML report."""
    from hydrokit.api import identify_campaign, load_rig
    from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all
    from hydrokit.data import campaign_files, campaign_rigs
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.identify import campaign_figures, coefficients_vs_reynolds
    from hydrokit.report.identify import Run, identify_report

    out = check_out_dir(out_dir)  # before the fits: they must not be lost to a bad folder
    start = time.perf_counter()
    jobs = []
    for name in campaign_rigs(campaign):
        rig_file, launches = campaign_files(campaign, name)
        jobs.append((load_rig(rig_file), launches))
    total = sum(len(files) * len(METHODS[rig.test]) for rig, files in jobs)
    runs = []
    all_docs = {}
    re_groups = {}
    with progress_bar() as bar:
        task = bar.add_task(f"identifying {campaign}", total=total)
        for rig, files in jobs:
            results = {
                m: identify_campaign(rig, files, m, progress=lambda f: bar.advance(task)) for m in METHODS[rig.test]
            }
            title = f"{rig.test} rig, {rig.axis}"
            figs = campaign_figures(results["output-error"], per_launch=False)
            runs.append(Run(title, rig, {m: r.to_dict() for m, r in results.items()}, list(figs.values())))
            all_docs[title] = runs[-1].documents
            re_groups[title] = results["output-error"].results
    fig = coefficients_vs_reynolds(re_groups, "output-error, all rigs and axes")
    closing = [
        (to_png(fig), "C_m, C_D, K_L and K_Q per launch against the launch's peak Reynolds number (output-error)")
    ]
    elapsed = time.perf_counter() - start
    intro = (
        f"Bundled {campaign} campaign (virtual-rig launches; true values and choices in "
        f"src/hydrokit/data/campaigns/{campaign}/README.md), {total} fits in {elapsed:.1f} s. "
        "Methods: output-error (default, most accurate), equation-error (CHIN2012), Morison (CELY2019, K_L = 0) "
        "and log-decrement (CELY2019 graphical)."
    )
    html = identify_report(f"hydrokit identification: {campaign} campaign", runs, intro, closing)
    outputs: dict[str | Path, str | bytes] = {out / "results.json": json_text(all_docs), out / "report.html": html}
    for r in runs:
        for i, (png, _) in enumerate(r.figures):
            outputs[out / "figures" / f"{r.rig.test}_{r.rig.axis}_{i + 1}.png"] = png
    write_all(outputs)
    _print_overview(all_docs)
    click.echo(f"wrote {out / 'report.html'} and {out / 'results.json'} ({elapsed:.1f} s)", err=True)


def _print_overview(all_docs: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    from hydrokit.report.html import fmt

    tab = Table(title="output-error: mean ± std over launches (SI)")
    for c in ("rig", "m_a", "C_m", "K_L", "K_Q", "C_D", "n"):
        tab.add_column(c, justify="left" if c == "rig" else "right")
    for title, docs in all_docs.items():
        s = docs["output-error"]["summary"]
        cell = lambda k, s=s: "–" if s[k]["mean"] is None else f"{fmt(s[k]['mean'])} ± {fmt(s[k]['std'], 2)}"
        tab.add_row(
            title,
            cell("added_mass"),
            cell("added_mass_coefficient"),
            cell("linear_damping"),
            cell("quadratic_damping"),
            cell("drag_coefficient"),
            str(s["added_mass"]["n"]),
        )
    Console().print(tab)
