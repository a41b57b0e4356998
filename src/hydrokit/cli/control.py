"""``hydrokit allocate`` and ``hydrokit mission``: thrust allocation and closed-loop missions.

Heavy imports (numpy, scipy, matplotlib) stay inside the command functions so that
``hydrokit --help`` starts fast.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import click

from hydrokit.errors import InputError

DOF = ("surge", "sway", "heave", "roll", "pitch", "yaw")


def _parse_tau(text: str) -> list[float]:
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 6 or not all(math.isfinite(v) for v in values):
        raise InputError(
            f"--tau {text!r}: expected 6 comma-separated finite numbers X,Y,Z,K,M,N (N and N·m)"
        )
    return values


def _parse_weights(text: str | None, m: int) -> list[float] | None:
    if text is None:
        return None
    try:
        values = [float(p) for p in text.split(",")]
    except ValueError:
        values = []
    if len(values) != m or not all(math.isfinite(v) and v > 0 for v in values):
        raise InputError(f"--weights {text!r}: expected {m} comma-separated positive numbers")
    return values


@click.command()
@click.argument("vehicle")
@click.option("--tau", required=True, help="Demanded force/moment X,Y,Z,K,M,N in body axes (N, N·m), comma-separated.")
@click.option(
    "--method",
    type=click.Choice(["constrained", "pinv"]),
    default="constrained",
    show_default=True,
    help="constrained: least residual within the thrust limits (N), then least thrust; "
    "pinv: unconstrained (weighted) pseudo-inverse.",
)
@click.option("--weights", default=None, help="pinv only: per-thruster weights (dimensionless, larger = used less), comma-separated in file order.")
@click.option("--json", "json_out", type=click.Path(dir_okay=False), default=None, help="Write the result as JSON to this file (forces in N, moments in N·m, speeds in rpm).")
def allocate(vehicle: str, tau: str, method: str, weights: str | None, json_out: str | None) -> None:
    """Allocate a demanded force/moment TAU to the thrusters of VEHICLE (file or bundled name).

    Prints the configuration matrix, thrust per thruster (N), the achieved τ and the DOF the
    layout cannot actuate. Propeller thrusters also get the speed (rpm) that gives the
    thrust at zero advance speed.
    """
    from hydrokit._atomic import write_text
    from hydrokit.io.thrusters import load_thrusters
    from hydrokit.model.allocation import allocate_constrained, allocate_pinv

    tau_v = _parse_tau(tau)
    ts = load_thrusters(vehicle)
    w = _parse_weights(weights, len(ts))
    if w is not None and method != "pinv":
        raise InputError("--weights applies only to --method pinv")
    T = ts.configuration_matrix()
    if method == "pinv":
        res = allocate_pinv(T, tau_v, weights=w, f_min=ts.f_min, f_max=ts.f_max, names=ts.names)
    else:
        res = allocate_constrained(T, tau_v, ts.f_min, ts.f_max, names=ts.names)
    command = ts.command_for_thrust(res.thrust)
    units = []
    shown = []
    for th, c in zip(ts.thrusters, command):
        if th.model == "propeller":
            units.append("rpm")
            shown.append(float(c) * 60.0)  # rev/s -> rpm at the edge
        elif th.model == "table":
            units.append("table command")
            shown.append(float(c))
        else:
            units.append("N")
            shown.append(float(c))
    doc: dict[str, Any] = {
        "vehicle": vehicle,
        "method": res.method,
        "thrusters": ts.names,
        "tau": tau_v,
        "configuration_matrix": [[float(x) for x in row] for row in T],
        "thrust": [float(x) for x in res.thrust],
        "thrust_limits": [[float(a), float(b)] for a, b in zip(ts.f_min, ts.f_max)],
        "command": shown,
        "command_unit": units,
        "achieved_tau": [float(x) for x in res.achieved_tau],
        "residual": float(res.residual),
        "uncontrollable": res.uncontrollable,
        "saturated": res.saturated,
        "warnings": res.warnings,
        "units": {"thrust": "N", "tau": "N, N·m (X,Y,Z,K,M,N)", "configuration_matrix": "-, m"},
    }
    doc["warnings"] = list(ts.notes) + doc["warnings"]
    for msg in doc["warnings"]:
        click.echo(f"warning: {msg}", err=True)
    _print_allocation(doc)
    if json_out:
        write_text(json_out, json.dumps(doc, indent=2) + "\n")


def _print_allocation(doc: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    mt = Table(title="Configuration matrix T (rows X Y Z K M N; m for moments)")
    mt.add_column("DOF")
    for name in doc["thrusters"]:
        mt.add_column(str(name), justify="right")
    for dof, row in zip(DOF, doc["configuration_matrix"]):
        mt.add_row(dof, *[f"{x:.4g}" for x in row])
    console.print(mt)
    tt = Table(title=f"Allocation ({doc['method']})")
    for col in ("thruster", "thrust (N)", "min (N)", "max (N)", "command", "unit", "saturated"):
        tt.add_column(col, justify="left" if col in ("thruster", "unit") else "right")
    for i, name in enumerate(doc["thrusters"]):
        lo, hi = doc["thrust_limits"][i]
        tt.add_row(
            str(name), f"{doc['thrust'][i]:.4g}", f"{lo:.4g}", f"{hi:.4g}",
            f"{doc['command'][i]:.4g}", doc["command_unit"][i],
            "yes" if name in doc["saturated"] else "",
        )
    console.print(tt)
    at = Table(title="Demanded and achieved τ (N, N·m)")
    for col in ("DOF", "demanded", "achieved"):
        at.add_column(col, justify="right")
    scale = max([abs(x) for x in doc["tau"] + doc["achieved_tau"]] + [1.0])
    for dof, a, b in zip(DOF, doc["tau"], doc["achieved_tau"]):
        b = 0.0 if abs(b) < 1e-12 * scale else b  # show round-off as 0
        at.add_row(dof, f"{a:.4g}", f"{b:.4g}")
    console.print(at)
    unc = ", ".join(doc["uncontrollable"]) or "none"
    console.print(f"residual |Tf − τ| = {doc['residual']:.4g}; not actuated: {unc}")


CONTROLLER_LABEL = {"pid": "PID", "s-plane": "S-plane"}


@click.command()
@click.argument("mission_file", metavar="MISSION")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Output directory (created if missing) for the CSV (SI: m, rad, s, N), plots and metrics JSON.")
@click.option(
    "--controller",
    type=click.Choice(["file", "pid", "s-plane", "both"]),
    default="file",
    show_default=True,
    help="Which gain set of the mission file to fly (dimensionless choice): the file's "
    "'controller', pid, s-plane, or both for a side-by-side comparison.",
)
@click.option("--duration", type=float, default=None, help="Override the mission duration, s.")
@click.option("--no-plots", is_flag=True, help="Skip the PNG figures (no unit).")
def mission(mission_file: str, out_dir: str, controller: str, duration: float | None, no_plots: bool) -> None:
    """Fly MISSION (a mission YAML file or bundled name) in closed loop and write results.

    Writes trajectory.csv (time,x,y,z,phi,theta,psi,u,v,w,p,q,r in m, rad, m/s, rad/s, then
    per thruster the demanded and reached command and the allocated and actual thrust in N;
    with --controller both, one trajectory_<controller>.csv per controller), metrics.json,
    path.png (3-D path and projections), tracking.png and thrusters.png.
    """
    from hydrokit.io.mission import load_mission

    mis = load_mission(mission_file)
    if duration is not None and not (math.isfinite(duration) and duration >= mis.dt):
        raise InputError(f"--duration {duration}: expected a time ≥ the step dt = {mis.dt} s")
    kinds = {"file": [mis.controller], "both": ["pid", "s-plane"]}.get(controller, [controller])
    for kind in kinds:
        mis.autopilot(kind)  # validates the gains before any work

    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    from hydrokit.io.mission import fly, prepare_vehicle

    prepared = prepare_vehicle(mis)  # all input validated before the run starts
    for note in prepared[0].notes:
        click.echo(f"warning: {note}", err=True)
    results = {}
    console_err = _stderr_console()
    with Progress(
        TextColumn("{task.description}"), BarColumn(), TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(), console=console_err, transient=True,
    ) as bar:
        for kind in kinds:
            total = duration if duration is not None else mis.duration
            task = bar.add_task(f"{CONTROLLER_LABEL[kind]} mission", total=total)
            results[kind] = fly(
                mis, kind, duration=duration, prepared=prepared,
                progress=lambda t, task=task: bar.update(task, completed=t),
            )
    thrusters = next(iter(results.values())).thrusters
    metrics = {CONTROLLER_LABEL[k]: r.result.metrics(r.thrusters) for k, r in results.items()}

    # everything computed: build the outputs in memory, then write them
    files: dict[str, bytes] = {}
    for kind, run in results.items():
        name = "trajectory.csv" if len(results) == 1 else f"trajectory_{kind}.csv"
        files[name] = _trajectory_csv(run.result).encode("utf-8")
    doc = {
        "mission": mis.name,
        "source": mis.source,
        "vehicle": mis.vehicle,
        "thrusters": thrusters.names,
        "command_units": [_command_unit(t) for t in thrusters.thrusters],
        "controllers": metrics,
        "units": {
            "cross_track_rms": "m", "cross_track_max": "m", "depth_error_rms": "m",
            "heading_error_rms": "rad", "waypoint_times": "s", "final_time": "s",
            "thrust_impulse": "N s", "thruster_energy": "J (ideal actuator-disk, lower bound)",
            "saturation_time": "s", "saturation_fraction": "-",
        },
    }
    files["metrics.json"] = (json.dumps(doc, indent=2) + "\n").encode("utf-8")
    if not no_plots:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.mission import path_figure, thruster_figure, tracking_figure

        runs = {CONTROLLER_LABEL[k]: r.result for k, r in results.items()}
        files["path.png"] = to_png(path_figure(runs, f"{mis.name}: 3-D path and projections"))
        files["tracking.png"] = to_png(tracking_figure(runs, f"{mis.name}: tracking error"))
        for kind, run in results.items():
            name = "thrusters.png" if len(results) == 1 else f"thrusters_{kind}.png"
            files[name] = to_png(thruster_figure(run.result, thrusters.f_min, thrusters.f_max,
                                                 f"{mis.name} ({CONTROLLER_LABEL[kind]}): thruster usage"))
    from hydrokit._atomic import write_bytes

    out = Path(out_dir)
    for name, data in files.items():
        write_bytes(out / name, data)
    _print_metrics(metrics)
    click.echo(f"wrote {', '.join(sorted(files))} to {out}", err=True)


def _stderr_console():
    from rich.console import Console

    return Console(stderr=True)


def _command_unit(th: Any) -> str:
    return {"propeller": "rev/s", "table": "table command", "ideal": "N"}[th.model]


def _trajectory_csv(res: Any) -> str:
    import numpy as np

    cols = ["time", "x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r"]
    blocks = [res.time[:, None], res.eta, res.nu]
    for prefix, arr in (("cmd_demand_", res.command_demand), ("cmd_", res.command),
                        ("thrust_demand_", res.thrust_demand), ("thrust_", res.thrust)):
        cols += [prefix + n for n in res.thruster_names]
        blocks.append(arr)
    cols += ["saturated", "leg"]
    blocks += [res.limited[:, None].astype(float), res.leg[:, None].astype(float)]
    data = np.hstack(blocks)
    lines = [",".join(cols)]
    ncol = data.shape[1]
    for row in data:
        vals = [f"{v:.9g}" for v in row[: ncol - 2]]
        vals += [str(int(row[ncol - 2])), str(int(row[ncol - 1]))]
        lines.append(",".join(vals))
    return "\n".join(lines) + "\n"


def _print_metrics(metrics: dict[str, dict[str, Any]]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="Mission metrics")
    table.add_column("metric")
    for label in metrics:
        table.add_column(label, justify="right")
    rows = [
        ("cross-track RMS (m)", "cross_track_rms", "{:.3f}"),
        ("cross-track max (m)", "cross_track_max", "{:.3f}"),
        ("depth error RMS (m)", "depth_error_rms", "{:.3f}"),
        ("heading error RMS (deg)", "heading_error_rms", "deg"),
        ("thrust impulse (N s)", "thrust_impulse", "{:.4g}"),
        ("thruster energy (J)", "thruster_energy", "{:.4g}"),
        ("saturation time (s)", "saturation_time", "{:.2f}"),
        ("completed", "completed", "{}"),
    ]
    for title, key, f in rows:
        cells = []
        for m in metrics.values():
            v = m[key]
            if v is None:
                cells.append("–")
            elif f == "deg":
                cells.append(f"{math.degrees(v):.2f}")
            else:
                cells.append(f.format(v))
        table.add_row(title, *cells)
    n_wp = len(next(iter(metrics.values()))["waypoint_times"])
    for i in range(n_wp):
        cells = []
        for m in metrics.values():
            t = m["waypoint_times"][i]
            cells.append("not reached" if t is None else f"{t:.1f}")
        table.add_row(f"time to waypoint {i + 1} (s)", *cells)
    Console().print(table)
