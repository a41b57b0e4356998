"""``hydrokit cfd``: a virtual tow tank and rotating arm on OpenFOAM (forces → coefficients)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._cfd_options import cfd_options, sweep_inputs
from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all


@click.command()
@click.argument("body", metavar="BODY")
@cfd_options
def cfd(body: str, **opts: Any) -> None:
    """Compute the hydrodynamic forces on BODY with OpenFOAM and fit them into coefficients.

    BODY: a surface mesh (.stl, .obj; m, body axes x forward, y starboard, z down, origin = moment
    reference point), a body-of-revolution profile (.csv with columns x, r in m; zero incidence runs
    as an axisymmetric wedge), a geometry file (.yaml) or a bundled body (myring, lingyun). Writes forces.csv,
    resistance.csv, coefficients.yaml, cfd.json and report.html to OUT, all or nothing.
    """
    from hydrokit.api import load_cfd_body
    from hydrokit.cfd.foam import SolverError, find_openfoam
    from hydrokit.cfd.sweep import make_cases

    out = check_out_dir(opts["out_dir"])
    settings, spec = sweep_inputs(opts)
    b = load_cfd_body(body, opts["area"])
    cases = make_cases(b, spec, settings)  # bad input is named before OpenFOAM is looked for
    find_openfoam()
    _announce(b, cases)
    result = _run(b, spec, settings, cases, out, opts["workers"], opts["scheduler"], opts["keep_cases"])
    if len(result.failed) == len(cases):
        raise SolverError(f"every case failed; the first: {result.failed[0].get('reason', 'no reason')}")
    written = _write(result, out)
    for w in result.warnings:
        click.echo(f"warning: {w}", err=True)
    click.echo(f"{len(cases)} case(s), {len(result.failed)} failed; wrote {', '.join(written)} to {out}")


def _announce(b: Any, cases: list[Any]) -> None:
    from hydrokit.cfd.mesh3d import estimate_cells

    res = sorted({c.reynolds for c in cases})
    cells = sum(estimate_cells(c) for c in cases)
    models = sorted({c.model for c in cases})
    click.echo(
        f"{b.name}: L = {b.length:.4g} m, A = {b.area:.4g} m²; {len(cases)} case(s), Re_L {res[0]:.3g}–{res[-1]:.3g} "
        f"({', '.join(models)}); ≈ {cells / 1e3:.0f} k cells in all, expected ≈ {cells * 2.5e-3 / 60:.0f}–"
        f"{cells * 1e-2 / 60:.0f} min of solver time on one core (cached cases are free)"
    )


def _run(
    b: Any,
    spec: Any,
    settings: Any,
    cases: list[Any],
    out: Path,
    workers: int | None,
    scheduler: str | None,
    keep: bool,
) -> Any:
    import threading

    from hydrokit.cfd.run import running_iterations
    from hydrokit.cfd.sweep import run_sweep

    cache = out / ".cache" / "cfd"
    labels = {c.key(): c.label for c in cases}
    with progress_bar() as bar:
        total = bar.add_task("cases", total=len(cases))
        per_case: dict[str, Any] = {}
        stop = threading.Event()

        def poll() -> None:  # one bar per running case, from its force history on disk
            while not stop.wait(1.0):
                for key, (it, top) in running_iterations(cache).items():
                    if key not in per_case and key in labels:
                        per_case[key] = bar.add_task(f"  {labels[key]}", total=None)
                    if key in per_case:  # the most iterations are known once controlDict is written
                        bar.update(per_case[key], completed=it, total=top or None)

        watcher = threading.Thread(target=poll, daemon=True)
        watcher.start()
        try:
            return run_sweep(
                b,
                spec,
                settings,
                cache,
                keep_dir=out / "cases" if keep else None,
                workers=workers,
                scheduler=scheduler,
                progress=lambda n: bar.advance(total, n),
                cases=cases,
            )
        finally:
            stop.set()


def _write(result: Any, out: Path) -> list[str]:
    """Write the outputs, all or nothing; return the names written."""
    import yaml

    from hydrokit.report.cfd import render

    files: dict[Path, Any] = {
        out / "forces.csv": result.forces_csv(),
        out / "cfd.json": json_text(result.to_dict()),
        out / "coefficients.yaml": "# hydrokit cfd: coefficients computed with OpenFOAM (SI; se = standard error)\n"
        + yaml.safe_dump(result.coefficients(), sort_keys=False, allow_unicode=True),
        out / "report.html": render(result),
    }
    resistance = result.resistance_csv()
    if resistance is not None:
        files[out / "resistance.csv"] = resistance
    write_all(files)
    return [p.name for p in files]
