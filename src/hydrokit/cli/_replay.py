"""``hydrokit manoeuvre VEHICLE --replay TRIAL.csv`` (issue #48): the trial's run file read here
(:func:`hydrokit.io.runlog.read_run`), its arrays replayed by :func:`hydrokit.manoeuvre.replay.replay`,
manoeuvre.json, trajectory.csv and the overlay plots written whole or not at all."""

from __future__ import annotations

from typing import Any

import click


def run_replay(
    *,
    vehicle: str,
    replay: str,
    out_dir: str,
    surface: str | None,
    force: list[float],
    dt: float,
    loop: str,
    no_plots: bool,
    duration: float | None = None,
    samples: int = 0,
    seed: int = 1,
    strict: bool = False,
    **others: Any,
) -> None:
    """Replay the trial ``replay`` with ``vehicle`` into ``out_dir`` (the arguments of ``hydrokit
    manoeuvre``; ``duration`` is unused: the trial sets it). ``others``: the options that set a
    manoeuvre, its propulsion or its start — each must be None or False (a replay reads them from
    the trial; ``strict`` was checked before). ``samples`` vehicles drawn from the file's covariance replay the trial too: the
    predicted metrics' 95 % intervals (manoeuvre.json's ``intervals``)."""
    from hydrokit.api import load_vehicle
    from hydrokit.cli._common import check_out_dir, json_text, progress_bar, write_all
    from hydrokit.errors import InputError
    from hydrokit.io.runlog import read_run
    from hydrokit.io.trajectory import table_csv
    from hydrokit.manoeuvre.replay import replay as replay_trial
    from hydrokit.manoeuvre.samples import add_intervals, check_samples

    trial = replay
    given = [k for k, v in others.items() if v is not None and v is not False]
    if given:
        raise InputError(
            f"--replay with --{given[0].replace('_text', '').replace('_', '-')}: a replay reads its manoeuvre and inputs from the trial; "
            "expected neither a manoeuvre option nor --command, --initial-velocity or --hold"
        )
    out = check_out_dir(out_dir)
    v = load_vehicle(vehicle)
    check_samples(v, samples)
    ts = getattr(v, "thrusters", None)
    run = read_run(trial, tuple(ts.names) if ts is not None else (), tuple(v.surfaces.names), v.surfaces.max_deflection)
    with progress_bar(time_based=True) as bar:
        task = bar.add_task(f"replaying {run.name}", total=run.duration)
        try:
            res = replay_trial(
                v,
                run,
                surface=surface,
                tau=force,
                dt=dt,
                loop=loop,
                progress=lambda t: bar.update(task, completed=t),
            )
        except InputError as exc:
            raise InputError(exc.detail, exc.source or trial) from None
    if samples:
        with progress_bar() as bar:
            drawn = bar.add_task(f"{samples} drawn vehicles", total=samples)
            add_intervals(
                res.predicted,
                v,
                samples,
                seed,
                lambda veh: replay_trial(veh, run, surface=surface, tau=force, dt=dt, loop=loop).predicted,
                lambda k, n: bar.update(drawn, completed=k, total=n),
            )
        res.warnings.extend(w for w in res.predicted.warnings if "drawn vehicle" in w)
    cols, rows = res.table()
    import numpy as np

    files: dict[Any, Any] = {
        out / "manoeuvre.json": json_text(res.to_dict()),
        out / "trajectory.csv": table_csv(cols, np.asarray(rows)),
    }
    if not no_plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.replay import figures

        files |= {out / k: to_png(f) for k, f in figures(res).items()}
    write_all(files)
    for w in res.warnings:
        click.echo(f"warning: {w}", err=True)
    diff = res.difference()
    mm, pm = res.measured.metrics, res.predicted.metrics

    def shown(x: Any) -> str:
        return "–" if x is None else f"{x:.4g}"

    click.echo(f"{res.kind} in {run.name} (measured, predicted, difference):")
    for k, d in diff["absolute"].items():
        if mm.get(k) is None and pm.get(k) is None:
            continue
        rel = diff["relative"][k]
        click.echo(f"  {k}: {shown(mm.get(k))}, {shown(pm.get(k))}, {shown(d)}" + (f" ({rel:+.1%})" if rel else ""))
    click.echo(f"wrote {len(files)} files to {out}", err=True)
