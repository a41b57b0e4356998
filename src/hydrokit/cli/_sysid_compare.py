"""``hydrokit sysid compare``: candidate model structures fitted on the same runs and ranked by
held-out error and BIC (issue #48 item 5)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._sysid_plan import _names
from hydrokit.cli._types import SECONDS, Count


def _split(spec: str) -> tuple[str, str]:
    """``NAME=VEHICLE`` → (NAME, VEHICLE); ``VEHICLE`` → (its file stem or bundled name, VEHICLE)."""
    from hydrokit.sysid.compare import NAME

    head, eq, tail = spec.partition("=")
    if eq and NAME.match(head) and not Path(spec).is_file():
        return head, tail
    return Path(spec).stem, spec


@click.command("compare")
@click.argument("runs", nargs=-1, required=True, metavar="RUN...")
@click.option(
    "--candidate",
    "candidates",
    multiple=True,
    required=True,
    metavar="[NAME=]VEHICLE",
    help="A candidate: base vehicle YAML or bundled name, optionally named (NAME=FILE; default: the file's stem). "
    "Repeat: two or more.",
)
@click.option(
    "--free",
    "frees",
    multiple=True,
    required=True,
    help="Comma-separated free parameters of a candidate, as for 'sysid fit' (SI: kg, N·s/m, N·s²/m², …; "
    "terms.<term>): one --free per --candidate, in the same order, or one for all.",
)
@click.option(
    "--holdout",
    multiple=True,
    required=True,
    help="Held-out run file(s) that rank the candidates (repeat or comma-separate).",
)
@click.option(
    "--out",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for compare.json, report.html and NAME/vehicle.yaml, NAME/sysid.json per candidate.",
)
@click.option(
    "--method",
    type=click.Choice(["output-error", "equation-error"]),
    default="output-error",
    show_default=True,
    help="Fit method of every candidate (as for 'sysid fit').",
)
@click.option("--dt", type=SECONDS, default=0.01, show_default=True, help="Integration step, s.")
@click.option(
    "--window",
    default="auto",
    show_default=True,
    help="Fit windows of about this length, s (as for 'sysid fit'); 'auto' or 'none'. Give a length or 'none' to "
    "weigh every candidate on the same residual series.",
)
@click.option(
    "--workers", type=Count(1), default=None, help="Threads for the batch simulations (count; default: all cores)."
)
def compare(
    runs: tuple[str, ...],
    candidates: tuple[str, ...],
    frees: tuple[str, ...],
    holdout: tuple[str, ...],
    out_dir: str,
    **opts: Any,
) -> None:
    """Fit two or more candidate vehicle files (each with its --free parameters) on the same run
    files RUN... and rank them by the NRMSE of their open-loop prediction of the --holdout runs and
    by BIC; say which to keep and why. Writes compare.json, report.html (side by side) and each
    candidate's identified vehicle.yaml."""
    from hydrokit.api import load_vehicle
    from hydrokit.cli._common import check_out_dir, progress_bar, write_all
    from hydrokit.errors import InputError
    from hydrokit.io.runlog import read_runs
    from hydrokit.io.vehicle import check_writable, resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml
    from hydrokit.report.sysid_compare import output_files
    from hydrokit.sysid.compare import Candidate, check_candidates
    from hydrokit.sysid.compare import compare as run_compare
    from hydrokit.sysid.fit import check_options
    from hydrokit.sysid.window import check_window

    check_out_dir(out_dir)
    specs = [_split(s) for s in candidates]
    check_candidates([n for n, _ in specs])
    if len(frees) not in (1, len(specs)):
        raise InputError(
            f"--free: {len(frees)} given for {len(specs)} candidates; expected one per --candidate (same order) "
            "or one for all"
        )
    free_lists = [_names((f,)) for f in (frees * len(specs) if len(frees) == 1 else frees)]
    held_paths = _names(holdout)
    if not held_paths:
        raise InputError("--holdout: no run given; expected at least one held-out run file")
    cands, docs, cache = [], {}, {}
    for (name, spec), free in zip(specs, free_lists):
        try:
            base = load_vehicle(spec)
            start, params = check_options(base, free, opts["method"], opts["dt"])
            docs[name] = read_yaml(resolve_vehicle(spec))
            check_writable(docs[name], start, [p.name for p in params])  # before the fit, not after
        except InputError as exc:
            raise InputError(f"--candidate {name}={spec}: {exc}") from None
        th = base.thrusters
        surf = base.surfaces
        key = (tuple(th.names) if th is not None else (), tuple(surf.names), repr(surf.max_deflection))
        if key not in cache:  # the run files are read once per set of thruster and surface names
            cache[key] = (read_runs(runs, base), read_runs(held_paths, base))
        train, held = cache[key]
        cands.append(Candidate(name, base, tuple(free), train, held, spec))
    for train, _ in cache.values():
        check_window(opts["window"], train)
    with progress_bar() as bar:
        task = bar.add_task("fits", total=None)

        def step(name: str, it: int, cost: float) -> None:
            bar.update(task, advance=1, description=f"{name}: iteration {it}: cost {cost:.6g}")

        result = run_compare(cands, progress=step, samples=0, **opts)
    files = output_files(result, docs, out_dir)
    write_all(files)
    click.echo(result.recommendation)
    cols, rows = result.table()
    width = max(len(n) for n in result.ranking) + 2
    click.echo(f"  {'rank':<5}{'candidate':<{width}}{'k':>3}  {'held-out NRMSE':>14}  {'BIC':>12}  verdict")
    for rank, name, k, err, _aic, bic, verdict in rows:
        click.echo(f"  {rank:<5}{name:<{width}}{k:>3}  {err:>14.3g}  {bic:>12.6g}  {verdict}")
    for m in result.notes:
        click.echo(f"note: {m}", err=True)
    click.echo(f"wrote compare.json, report.html and {len(cands)} candidate folder(s) to {out_dir}", err=True)
