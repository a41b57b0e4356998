"""``hydrokit sysid plan``: a D-optimal excitation schedule for identification (issue #44)."""

from __future__ import annotations

from pathlib import Path

import click

from hydrokit.cli._types import SECONDS, SEED, Count, Number, Numbers


def _names(values: tuple[str, ...]) -> list[str]:
    """Comma-separated names of one or more option values, stripped."""
    return [n.strip() for v in values for n in v.split(",") if n.strip()]


@click.command("plan")
@click.argument("vehicle", metavar="BASE.yaml")
@click.option(
    "--free",
    multiple=True,
    required=True,
    help="Free parameters (repeat or comma-separate), as for 'sysid fit' (added_mass.surge, linear_damping.yaw, …; SI).",
)
@click.option("--duration", type=Number("s", at_least=2, at_most=3600), required=True, help="Schedule length, s.")
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Folder for schedule.csv and plan.json."
)
@click.option(
    "--amplitude",
    type=Number(above=0, at_most=1),
    default=0.6,
    show_default=True,
    help="Largest fraction of a thruster's thrust limit used (0–1).",
)
@click.option("--dofs", default="", help="Comma-separated DOFs to excite (default: those the free parameters act in).")
@click.option(
    "--channels",
    default="",
    help="Comma-separated measured channels (default all: phi theta psi p q r at 50 Hz, z 10 Hz, u v w 5 Hz).",
)
@click.option(
    "--noise", type=Number(above=0), default=1.0, show_default=True, help="Multiplier of the sensor noise σ (–)."
)
@click.option(
    "--band",
    type=Numbers(2, "Hz", positive=True),
    default="0.02,2",
    show_default=True,
    help="Usable band f_lo,f_hi, Hz.",
)
@click.option(
    "--evaluations", type=Count(1), default=40, show_default=True, help="Designs simulated in the search (count)."
)
@click.option("--dt", type=SECONDS, default=0.01, show_default=True, help="Integration step of the prediction, s.")
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the search and references (integer).")
def plan(vehicle: str, free: tuple[str, ...], duration: float, out_dir: str, **opts: object) -> None:
    """Design multi-sine thruster commands that maximise the Fisher information's determinant
    of the --free coefficients (D-optimal) within the thrust limits; write DIR/schedule.csv
    (time s, one command column per thruster, held) and DIR/plan.json (Cramér–Rao σ, SI)."""
    import json

    from hydrokit.api import load_vehicle
    from hydrokit.cli._common import check_out_dir, progress_bar, write_all
    from hydrokit.errors import InputError
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.data import SENSORS
    from hydrokit.sysid.plan import plan_excitation

    check_out_dir(out_dir)
    base = load_vehicle(vehicle)
    chans = _names((str(opts.pop("channels")),)) or list(SENSORS)
    bad = [c for c in chans if c not in SENSORS]
    if bad:
        raise InputError(f"--channels {', '.join(bad)}: expected some of {', '.join(SENSORS)}")
    scale = float(opts.pop("noise"))  # type: ignore[arg-type]
    sensors = {c: (SENSORS[c][0], scale * SENSORS[c][1]) for c in chans}
    opts["band"] = tuple(opts["band"])  # type: ignore[arg-type]
    dofs = _names((str(opts.pop("dofs")),)) or None
    names = _names(free)
    total = int(opts["evaluations"])  # type: ignore[call-overload]
    with progress_bar() as bar:
        task = bar.add_task("designing", total=total)
        step = lambda k, best: bar.update(task, completed=k, description=f"design {k}: log det {best:.4g}")  # noqa: E731
        result = plan_excitation(
            base,
            names,
            duration,
            dofs=dofs,
            sensors=sensors,
            progress=step,
            **opts,  # type: ignore[arg-type]
        )
    note = (
        f"hydrokit sysid plan: D-optimal multi-sines for {base.name}, free {', '.join(result.parameters)}\n"
        f"commands ({', '.join(sorted(set(result.command_units)))}) held until the next row; "
        f"fly from rest, open loop (manual mode)"
    )
    out = Path(out_dir)
    text = json.dumps(result.to_dict(), indent=2, allow_nan=False, ensure_ascii=False) + "\n"
    write_all({out / "schedule.csv": run_csv(result.time, {}, result.commands, comment=note), out / "plan.json": text})
    for n, u, s, r in zip(result.parameters, result.units, result.sigma, result.ratio):
        click.echo(f"σ({n}) = {s:.3g} {u}  (×{r:.2f} of the generator's random multi-sine)")
    click.echo(f"condition number {result.condition:.3g}; geometric-mean σ gain {result.gain:.2f}")
    for m in (*result.messages, *result.warnings):
        click.echo(f"note: {m}", err=True)
    click.echo(f"wrote schedule.csv and plan.json to {out_dir}", err=True)
