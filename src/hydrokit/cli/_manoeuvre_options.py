"""The options of ``hydrokit manoeuvre`` (kept apart so the command module stays short)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from hydrokit.cli._types import SECONDS, Number, Numbers

DEG = Number("deg", at_least=-90, at_most=90)

_OPTIONS: tuple[tuple[tuple[str, ...], dict[str, Any]], ...] = (
    (("--out", "out_dir"), {"required": True, "metavar": "DIR", "help": "Output folder (created if missing)."}),
    (("--turning-circle",), {"type": DEG, "help": "Turning circle at this deflection, deg."}),
    (("--zigzag",), {"metavar": "A/B", "help": "Zigzag: deflection A, check heading B, deg/deg (e.g. 20/20)."}),
    (
        ("--spiral",),
        {"type": click.Choice(["direct", "reverse"]), "help": "Spiral: direct (Dieudonné) or reverse (Bech)."},
    ),
    (("--pull-out",), {"type": DEG, "help": "Pull-out from steady turns at ±this deflection, deg."}),
    (
        ("--depth-change",),
        {
            "metavar": "M[/A]",
            "help": "Depth change by M m (+ deeper), planes within ±A deg (15): flown through the pitch-limited "
            "depth-to-pitch law (see --max-pitch), or with --open-loop the planes held at A until the depth is reached.",
        },
    ),
    (
        ("--max-pitch",),
        {
            "type": Number("deg", at_least=0.1, at_most=89),
            "default": None,
            "help": "Pitch limit of the closed-loop depth change, deg (default 20).",
        },
    ),
    (
        ("--open-loop",),
        {"is_flag": True, "default": None, "help": "Depth change: planes held at A, open loop (no unit)."},
    ),
    (("--vertical-zigzag",), {"metavar": "A/B", "help": "Vertical zigzag on the stern planes: A, B in deg/deg."}),
    (
        ("--replay",),
        {
            "type": click.Path(dir_okay=False),
            "metavar": "TRIAL.csv",
            "help": "Replay a trial instead: a run file (time s, x y psi … in m, rad, m/s, rad/s, thruster commands, "
            "deflections in rad); the model flies its inputs from its first state, the turning circle or zigzag is "
            "detected from the rudder and measured on both tracks.",
        },
    ),
    (("--surface",), {"help": "The surface that steers (default: the rudder, or the stern plane; by name)."}),
    (
        ("--force",),
        {
            "type": Numbers(6, "N, N·m"),
            "default": "0,0,0,0,0,0",
            "show_default": True,
            "help": "Constant force X,Y,Z,K,M,N (body): N, N·m — the propulsion, or added to --command's thrust "
            "(e.g. the propeller's torque K). All zero and no --command: no propulsion given, so the vehicle "
            "file's service: condition (its commands and force) is flown; a file without one coasts from "
            "--initial-velocity, and is refused from rest.",
        },
    ),
    (
        ("--command", "command_text"),
        {
            "metavar": "NAME=VALUE[,NAME=VALUE]",
            "help": "Propulsion by the vehicle's thrusters, held from rest: each thruster's command in its unit "
            "(rev/s for a propeller, the table's unit for a table curve, N for an ideal thruster); others 0. "
            "The thrust follows each propeller's advance ratio. Given (or a non-zero --force), the file's service: "
            "condition is not used.",
        },
    ),
    (
        ("--initial-velocity",),
        {
            "type": Numbers(6, "m/s, rad/s"),
            "help": "Approach start u,v,w,p,q,r: m/s, rad/s (default: at rest, or at the service speed ahead when "
            "the service: condition is flown).",
        },
    ),
    (("--dt",), {"type": SECONDS, "default": 0.02, "show_default": True, "help": "Integration step, s."}),
    (
        ("--duration",),
        {
            "type": SECONDS,
            "default": None,
            "help": "Longest manoeuvre after the execute, s (it ends sooner once measured). Default: scaled by the "
            "vehicle's L/U at the execute — 2000 L/U for a turning circle, 500 L/U for a zigzag or depth change, "
            "up to 1000 L/U per spiral step or pull-out phase.",
        },
    ),
    (
        ("--loop",),
        {
            "type": click.Choice(["compiled", "python"]),
            "default": "compiled",
            "show_default": True,
            "help": "Right-hand side (no unit): compiled (numba) or python (numpy).",
        },
    ),
    (
        ("--hold/--no-hold",),
        {
            "default": None,
            "help": "Hold depth and pitch with the stern planes during a turn or zigzag, heading with the rudder "
            "during a depth change (PID; no unit). Default: on for a 6-DOF vehicle with such a second surface.",
        },
    ),
    (("--no-plots",), {"is_flag": True, "help": "Skip the PNG figures and the report (no unit)."}),
)


def manoeuvre_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add every option of ``hydrokit manoeuvre`` to ``f`` (in the order of --help)."""
    for decls, kw in reversed(_OPTIONS):
        f = click.option(*decls, **kw)(f)
    return f
