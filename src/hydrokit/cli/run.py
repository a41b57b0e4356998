"""``hydrokit run PROJECT``: the main job, from tank launches to a flown vehicle and one report."""

from __future__ import annotations

import time
from pathlib import Path

import click

from hydrokit.cli._types import Count


@click.command()
@click.argument("project")
@click.option(
    "--out",
    "out_dir",
    default=None,
    metavar="DIR",  # checked by check_out_dir (one line naming --out), not by click
    help="Run folder for report.html, results.json, vehicle.yaml, mission/ and the step cache "
    "(directory; default: <project name>-run).",
)
@click.option("--force", is_flag=True, help="Redo every step, ignoring the cache (no unit).")
@click.option("--bem", is_flag=True, help="Boundary-element added mass from the geometry (needs hydrokit[bem]).")
@click.option(
    "--workers",
    type=Count(0),
    default=None,
    help="Dask local workers (count) for launch fits and the Monte Carlo; 1 = serial in this process; "
    "default: one per core when hydrokit[dask] is installed, else serial.",
)
@click.option(
    "--scheduler", default=None, help="Address of a running Dask scheduler, e.g. tcp://127.0.0.1:8786 (no unit)."
)
@click.option(
    "--samples", type=Count(0, 100_000), default=None, help="Monte Carlo samples (count); default: the project's."
)
@click.option("--quiet", is_flag=True, help="No progress bars or summary table.")
def run(
    project: str,
    out_dir: str | None,
    force: bool,
    bem: bool,
    workers: int | None,
    scheduler: str | None,
    samples: int | None,
    quiet: bool,
) -> None:
    """Run PROJECT (a project file, a folder holding project.yaml, or a bundled name: udrobot, rov2, udrobot_cfd, lingyun).

    Identifies every campaign, scales it to full size, compares with geometry/BEM/CFD, chooses per
    the project's rule, writes vehicle.yaml with an uncertainty block, flies the mission with PID
    and S-plane, runs the Monte Carlo and writes report.html. Steps whose inputs did not change
    are taken from the cache in OUT/.cache; when nothing changed (inputs, options, hydrokit, the
    folder's files) nothing is computed, rendered or written.
    """
    from hydrokit.cli._common import check_out_dir
    from hydrokit.io.project import check_inputs, parse_project, resolve_project
    from hydrokit.io.yamlfile import read_yaml
    from hydrokit.pipeline import run_project, up_to_date

    start = time.perf_counter()
    path = resolve_project(project)
    proj = parse_project(read_yaml(path), path)
    out = Path(out_dir) if out_dir else Path(f"{proj.name}-run")
    if not force and up_to_date(proj, out, bem=bem, samples=samples):  # nothing to compute, render or write
        if not quiet:
            _print_summary(_stored_result(out), steps=False)
        click.echo(
            f"{out / 'report.html'}, results.json, vehicle.yaml: up to date, nothing changed; nothing written "
            f"({time.perf_counter() - start:.2f} s)",
            err=True,
        )
        return
    check_inputs(proj)
    out = check_out_dir(out)
    if quiet:
        result = run_project(proj, out, force=force, bem=bem, workers=workers, scheduler=scheduler, samples=samples)
    else:
        from hydrokit.cli._common import progress_bar

        with progress_bar() as bar:

            def progress(label: str, total: int):  # noqa: ANN202
                task = bar.add_task(label, total=total)
                return lambda n: bar.advance(task, n)

            result = run_project(
                proj,
                out,
                force=force,
                bem=bem,
                workers=workers,
                scheduler=scheduler,
                samples=samples,
                progress=progress,
            )
    from hydrokit.report.run import write_run_folder

    write_run_folder(result, out, force=force)  # the folder's files replace the old ones as one set
    if not quiet:
        _print_summary(result)
    click.echo(
        f"wrote {out / 'report.html'}, results.json, vehicle.yaml ({time.perf_counter() - start:.1f} s)", err=True
    )


def _stored_result(out: Path):  # noqa: ANN202
    """The RunResult of the run folder's results.json (document and timings; no figures)."""
    import json

    from hydrokit.pipeline.result import RunResult

    doc = json.loads((out / "results.json").read_text(encoding="utf-8"))
    return RunResult(doc, timings=doc.pop("timings", []))


def _print_summary(result, steps: bool = True) -> None:  # noqa: ANN001
    from rich.console import Console
    from rich.table import Table

    from hydrokit.report.html import fmt

    tab = Table(title=f"{result.document['project']['name']}: chosen full-scale coefficients (SI)")
    rows = result.document["comparison"]
    has_tank = any(r["tank"] is not None for r in rows)
    has_sysid = bool(result.document.get("sysid"))
    cols = ("DOF", "coefficient") + ("tank [95 % CI]",) * has_tank + ("sysid ± σ",) * has_sysid + ("chosen", "source")
    for c in cols:
        tab.add_column(c)
    for r in rows:
        ci = r["tank_ci"] or [None, None]
        tank = [f"{fmt(r['tank'])} [{fmt(ci[0])}, {fmt(ci[1])}]" if r["tank"] is not None else "–"] * has_tank
        sid = r.get("sysid")
        sysid = [f"{fmt(sid)} ± {fmt(r.get('sysid_sigma'), 2)}" if sid is not None else "–"] * has_sysid
        tab.add_row(r["dof"], r["coefficient"], *tank, *sysid, fmt(r["chosen"]), r["chosen_source"])
    console = Console(stderr=True)
    console.print(tab)
    if not steps:
        return
    said = ", ".join(f"{t['step']} {t['seconds']:.1f} s" + (" (cached)" if t["cached"] else "") for t in result.timings)
    console.print(f"steps: {said}")
