"""``hydrokit transport ASSEMBLY``: fly a joined assembly (REHMAN's two-HAUV payload transport)."""

from __future__ import annotations

import re
from pathlib import Path

import click

from hydrokit.cli._types import SECONDS, Count

MODELS = ("rigid", "multibody", "independent")


def _pairs(values: tuple[str, ...], option: str, what: str) -> list[tuple[str, str]]:
    from hydrokit.errors import InputError

    out = []
    for v in values:
        name, sep, rest = v.partition("=")
        if not sep or not name.strip() or not rest.strip():
            raise InputError(f"{option} {v!r}: expected {what}")
        out.append((name.strip(), rest.strip()))
    return out


@click.command()
@click.argument("assembly")
@click.option("--duration", type=SECONDS, required=True, help="Simulated time, s.")
@click.option("--dt", type=SECONDS, required=True, help="Integration step, s (e.g. 0.01).")
@click.option(
    "--model",
    type=click.Choice(MODELS),
    default="rigid",
    show_default=True,
    help="rigid: one composite body, joint loads from Newton-Euler on each subtree; multibody: every "
    "part a 6-DOF body joined by stiff spring-dampers; independent: each vehicle with its arm and a "
    "share of the payload, flying alone (REHMAN's separate bodies).",
)
@click.option(
    "--rpm",
    multiple=True,
    metavar="PART.THRUSTER=RPM",
    help="Constant propeller speed of one thruster, rpm (repeat; others are off), e.g. minerva-1.V1=1000.",
)
@click.option(
    "--force",
    multiple=True,
    metavar="PART=fx,fy,fz,mx,my,mz",
    help="Constant force (N) and moment (N·m) in the part's body axes at its origin (repeat).",
)
@click.option(
    "--damping-model",
    type=click.Choice(("elements", "rehman", "shifted")),
    default="elements",
    show_default=True,
    help="Quadratic drag of the composite: elements (each part's drag at its own point), rehman "
    "(d·r³ diagonal), shifted (Hᵀ D H, dimensionally wrong; for comparison).",
)
@click.option("--every", type=Count(1), default=1, show_default=True, help="Record every n-th step (count).")
@click.option("--out", "out", required=True, type=click.Path(file_okay=False), help="Output folder (path).")
@click.option("--plots", is_flag=True, help="Also write path.png, separation.png and loads.png.")
def transport(
    assembly: str,
    duration: float,
    dt: float,
    model: str,
    rpm: tuple[str, ...],
    force: tuple[str, ...],
    damping_model: str,
    every: int,
    out: str,
    plots: bool,
) -> None:
    """Fly ASSEMBLY (an assembly file or bundled name: rehman_transport, rehman_transport_public).

    Writes OUT/trajectory.csv (time, x, y, z, phi, theta, psi, u, v, w, p, q, r of the assembly
    origin; m, rad, m/s, rad/s, NED), OUT/trajectory_<part>.csv for every part's origin,
    OUT/loads.csv (time, joint, fx, fy, fz, mx, my, mz: what the parent exerts on the child
    subtree at the joint point, assembly body axes, N and N·m) and OUT/summary.json.
    """
    from hydrokit.api import load_assembly
    from hydrokit.api import transport as fly
    from hydrokit.cli._common import check_out_dir, json_text, write_all
    from hydrokit.cli._types import floats
    from hydrokit.errors import InputError
    from hydrokit.io.trajectory import table_csv
    from hydrokit.simulate.transport import COLUMNS

    rpms = {}
    for name, text in _pairs(rpm, "--rpm", "PART.THRUSTER=RPM, e.g. minerva-1.V1=1000"):
        rpms[name] = floats(text, f"--rpm {name}", n=1, unit="rpm")[0]
    forces = {}
    for name, text in _pairs(force, "--force", "PART=fx,fy,fz,mx,my,mz (N, N·m)"):
        forces[name] = floats(text, f"--force {name}", n=6, unit="N and N·m")
    d = check_out_dir(out)  # before the run: it must not be lost to a bad folder
    asm = load_assembly(assembly, damping_model=damping_model)
    res = fly(asm, duration, dt, model, rpms, forces, every)
    import numpy as np

    files: dict[Path, str | bytes] = {}
    files[d / "trajectory.csv"] = table_csv(list(COLUMNS), np.column_stack([res.time, res.assembly]))
    used: set[str] = set()
    for name, states in res.parts.items():
        safe = re.sub(r"[^A-Za-z0-9_.-]", "_", name)
        if safe in used:
            raise InputError(f"part name '{name}': two parts map to the file name trajectory_{safe}.csv")
        used.add(safe)
        files[d / f"trajectory_{safe}.csv"] = table_csv(list(COLUMNS), np.column_stack([res.time, states]))
    cols, rows = res.load_rows()
    lines = [",".join(cols)] + [f"{r[0]:.9g},{r[1]}," + ",".join(f"{v:.9g}" for v in r[2:]) for r in rows]
    files[d / "loads.csv"] = "\n".join(lines) + "\n"
    files[d / "summary.json"] = json_text(res.summary())
    if plots:
        from hydrokit.plot.transport import figure_bytes

        files.update({d / k: v for k, v in figure_bytes(res).items()})
    write_all(files)  # creates the folder with the files: nothing is left when a write fails
    s = res.summary()
    click.echo(f"{model}: moved {np.round(s['displacement_m'], 3).tolist()} m in {s['duration_s']:g} s")
    for name, j in s["joints"].items():  # results on stdout; stderr keeps warnings and the one 'wrote' line
        click.echo(
            f"  joint {name}: max force {j['max_force_N']:.1f} N, max moment {j['max_moment_Nm']:.1f} N·m, "
            f"max separation {j['max_separation_m']:.4g} m"
        )
    for w in s["warnings"]:
        click.echo(f"warning: {w}", err=True)
    click.echo(f"wrote {d}", err=True)
