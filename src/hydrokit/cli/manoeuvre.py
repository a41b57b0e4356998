"""``hydrokit manoeuvre``: the standard manoeuvres (turning circle, zigzag, spiral, pull-out, depth
change, vertical zigzag) of a vehicle with control surfaces (a thin layer over
:func:`hydrokit.simulate.manoeuvre.run_manoeuvre`)."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._types import SECONDS, Number, Numbers

DEG = Number("deg", at_least=-90, at_most=90)


@click.command()
@click.argument("vehicle", metavar="VEHICLE")
@click.option("--out", "out_dir", required=True, metavar="DIR", help="Output folder (created if missing).")
@click.option("--turning-circle", type=DEG, help="Turning circle at this deflection, deg.")
@click.option("--zigzag", metavar="A/B", help="Zigzag: deflection A, check heading B, deg/deg (e.g. 20/20).")
@click.option(
    "--spiral", type=click.Choice(["direct", "reverse"]), help="Spiral: direct (Dieudonné) or reverse (Bech)."
)
@click.option("--pull-out", type=DEG, help="Pull-out from steady turns at ±this deflection, deg.")
@click.option("--depth-change", metavar="M[/A]", help="Depth change by M m (+ deeper) with planes at A deg (15).")
@click.option("--vertical-zigzag", metavar="A/B", help="Vertical zigzag on the stern planes: A, B in deg/deg.")
@click.option("--surface", help="The surface that steers (default: the rudder, or the stern plane; by name).")
@click.option(
    "--force",
    type=Numbers(6, "N, N·m"),
    default="0,0,0,0,0,0",
    show_default=True,
    help="Constant force X,Y,Z,K,M,N (body): N, N·m (the propulsion).",
)
@click.option("--initial-velocity", type=Numbers(6, "m/s, rad/s"), help="Approach start u,v,w,p,q,r: m/s, rad/s.")
@click.option("--dt", type=SECONDS, default=0.02, show_default=True, help="Integration step, s.")
@click.option(
    "--duration",
    type=SECONDS,
    default=1800.0,
    show_default=True,
    help="Longest manoeuvre after the execute, s (it ends sooner once measured).",
)
@click.option(
    "--loop",
    type=click.Choice(["compiled", "python"]),
    default="compiled",
    show_default=True,
    help="Right-hand side (no unit): compiled (numba) or python (numpy).",
)
@click.option(
    "--hold/--no-hold",
    default=None,
    help="Hold depth and pitch with the stern planes during a turn or zigzag, heading with the rudder during a "
    "depth change (PID; no unit). Default: on for a 6-DOF vehicle with such a second surface.",
)
@click.option("--no-plots", is_flag=True, help="Skip the PNG figures and the report (no unit).")
def manoeuvre(
    vehicle: str,
    out_dir: str,
    turning_circle: float | None,
    zigzag: str | None,
    spiral: str | None,
    pull_out: float | None,
    depth_change: str | None,
    vertical_zigzag: str | None,
    surface: str | None,
    force: list[float],
    initial_velocity: list[float] | None,
    dt: float,
    duration: float,
    loop: str,
    hold: bool | None,
    no_plots: bool,
) -> None:
    """Fly a standard manoeuvre with VEHICLE (a vehicle YAML file or bundled name): a straight
    approach until steady, then the execute; every metric is measured from the execute point
    (IMO MSC.137(76), ITTC 7.5-04-02-01).

    Writes DIR/manoeuvre.json (metrics under the manoeuvre's name; SI, *_deg in degrees),
    DIR/trajectory.csv (time,x,y,z,phi,theta,psi,u,v,w,p,q,r then one column per surface, rad;
    positions from the execute point, time 0 at the execute), track.png, time.png and report.html.
    A manoeuvre that never reaches the heading it measures at is an error (exit 2); the track is
    still written.
    """
    from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all
    from hydrokit.errors import InputError
    from hydrokit.io.trajectory import table_csv
    from hydrokit.io.vehicle import load_vehicle
    from hydrokit.simulate.manoeuvre import from_options, run_manoeuvre

    out = check_out_dir(out_dir)
    m = from_options(
        {
            "turning_circle": turning_circle,
            "zigzag": zigzag,
            "spiral": spiral,
            "pull_out": pull_out,
            "depth_change": depth_change,
            "vertical_zigzag": vertical_zigzag,
        }
    )
    v = load_vehicle(vehicle)
    with progress_bar(time_based=True) as bar:
        task = bar.add_task(m.kind.replace("_", " "), total=duration)
        res = run_manoeuvre(
            v,
            m,
            surface=surface,
            tau=force,
            nu0=initial_velocity,
            dt=dt,
            duration=duration,
            loop=loop,
            hold=hold,
            progress=lambda t: bar.update(task, completed=t),
        )
    files: dict[Any, Any] = {out / "trajectory.csv": table_csv(*_columns(res))}
    if res.problem:
        write_all(files)
        raise InputError(f"{res.problem}; the track was written to {out / 'trajectory.csv'}")
    files[out / "manoeuvre.json"] = json_text(res.to_dict())
    if not no_plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.manoeuvre import figures
        from hydrokit.report.manoeuvre import render

        pngs = {k: to_png(f) for k, f in figures(res).items()}
        files |= {out / k: p for k, p in pngs.items()}
        files[out / "report.html"] = render(res, pngs)
    write_all(files)
    for w in res.warnings:
        click.echo(f"warning: {w}", err=True)
    if res.hold:
        click.echo("held: " + ", ".join(f"{k} by {n}" for k, n in res.hold.items()), err=True)
    shown = {k: val for k, val in res.metrics.items() if isinstance(val, (int, float)) and not isinstance(val, bool)}
    click.echo(f"{m.kind}: " + ", ".join(f"{k} = {val:.4g}" for k, val in shown.items()))
    for c in res.imo():
        verdict = "–" if c["passed"] is None else "pass" if c["passed"] else "FAIL"
        click.echo(f"IMO {c['criterion']}: {verdict}")
    click.echo(f"wrote {len(files)} files to {out}", err=True)


def _columns(res: Any) -> tuple[list[str], Any]:
    return res.columns, res.array()
