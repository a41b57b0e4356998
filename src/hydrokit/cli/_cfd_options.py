"""Options of ``hydrokit cfd``, SI with the unit in each help text; degrees only here, at the edge."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._cfd_mesh_options import MESH_OPTIONS
from hydrokit.cli._types import Count, Number, Numbers

_MODELS = click.Choice(["auto", "laminar", "kOmegaSST", "kEpsilon"])
# (flags, click keyword arguments) in the order --help shows them
_OPTIONS: list[tuple[tuple[str, ...], dict[str, Any]]] = [
    (("--out", "out_dir"), {"required": True, "type": click.Path(file_okay=False), "help": "Output folder."}),
    (
        ("--speeds",),
        {
            "type": Numbers(unit="m/s", positive=True),
            "default": "0.5,1,1.5,2",
            "help": "Straight-ahead speeds, m/s (comma-separated).",
        },
    ),
    (("--drift",), {"type": Numbers(unit="deg"), "help": "Drift angles β = atan2(v, u), deg (|β| < 90)."}),
    (("--attack",), {"type": Numbers(unit="deg"), "help": "Angles of attack α = atan2(w, u), deg (|α| < 90)."}),
    (("--yaw-rates",), {"type": Numbers(unit="rad/s"), "help": "Rotating-arm yaw rates r, rad/s."}),
    (("--pitch-rates",), {"type": Numbers(unit="rad/s"), "help": "Rotating-arm pitch rates q, rad/s."}),
    (("--axes",), {"default": "x", "help": "Body axes with a speed sweep: x, y (pure sway), z (pure heave)."}),
    (
        ("--reference-speed",),
        {
            "type": Number("m/s", above=0),
            "help": "Speed of the angle and rate cases, m/s [default: the largest of --speeds].",
        },
    ),
    (("--density",), {"type": Number("kg/m³", above=0), "default": 1025.0, "help": "Fluid density ρ, kg/m³."}),
    (
        ("--viscosity",),
        {
            "type": Number("m²/s", above=0),
            "default": 1.19e-6,
            "help": "Kinematic viscosity ν, m²/s (sea water at 15 °C: 1.19e-6; fresh water, 20 °C: 1.0e-6).",
        },
    ),
    (("--area",), {"type": Number("m²", above=0), "help": "Reference area of C_D, m² [default: frontal area]."}),
    (
        ("--turbulence",),
        {"type": _MODELS, "default": "auto", "help": "Flow model; auto: laminar below Re_L = 2000, else k-ω SST."},
    ),
    (
        ("--inflow-intensity",),
        {
            "type": Number("dimensionless", above=0, at_most=0.5),
            "default": 0.01,
            "help": "Free-stream turbulence intensity at the inlet (dimensionless, 0.01 = 1 %); with "
            "--inflow-viscosity-ratio 10 k-ω SST's boundary layer is turbulent from the nose (a tripped model).",
        },
    ),
    (
        ("--inflow-viscosity-ratio",),
        {
            "type": Number("dimensionless", above=0, at_most=1e4),
            "default": 10.0,
            "help": "Free-stream eddy-to-molecular viscosity ratio ν_t/ν at the inlet (dimensionless); "
            "an intensity of 0.005 with a ratio of 1 leaves a laminar run of uncertain length (natural transition).",
        },
    ),
    (
        ("--turbulence-order",),
        {
            "type": Count(1, 2),
            "default": 1,
            "help": "Order of the convection of k and ω (1 or 2, dimensionless): 1 first-order upwind; 2 upwind "
            "until the forces settle, then second-order linearUpwind on from there (a grid study wants 2).",
        },
    ),
    *MESH_OPTIONS,
    (
        ("--iterations",),
        {
            "type": Count(10, 1_000_000),
            "default": 1500,
            "help": "Most solver iterations per case (count); a case stops once its forces settle.",
        },
    ),
    (("--timeout",), {"type": Number("s", above=0), "default": 3600.0, "help": "Wall-clock limit per program, s."}),
    (
        ("--processes",),
        {
            "type": Count(1, 1024),
            "default": 1,
            "help": "MPI processes for each case's solver (count; decomposePar + mpirun, for a big case).",
        },
    ),
    (("--workers",), {"type": Count(0, 256), "help": "Local Dask worker processes (count; 0 or 1: serial)."}),
    (("--scheduler",), {"help": "Address of a running Dask scheduler, e.g. tcp://127.0.0.1:8786."}),
    (("--keep-cases",), {"is_flag": True, "help": "Keep each OpenFOAM case in OUT/cases/ (to open in ParaView)."}),
]


def cfd_options(f: Any) -> Any:
    """Apply every option of ``hydrokit cfd`` to the command function ``f``."""
    for flags, kw in reversed(_OPTIONS):
        kw = {"show_default": "default" in kw and not kw.get("is_flag"), **kw}
        f = click.option(*flags, **kw)(f)
    return f


def sweep_inputs(opts: dict[str, Any]) -> tuple[Any, Any]:
    """(Settings, SweepSpec) from the parsed options, in SI (degrees → rad)."""
    import dataclasses
    import math

    from hydrokit.cfd.case import Settings
    from hydrokit.cfd.sweep import SweepSpec

    axes = tuple(a.strip() for a in opts["axes"].split(",") if a.strip())
    if not axes or any(a not in ("x", "y", "z") for a in axes):
        raise click.BadParameter(
            f"{opts['axes']!r}: expected body axes among x, y, z (comma-separated)", param_hint="'--axes'"
        )
    # every option named as a Settings field goes there; two are named for the user
    field = {"cells_per_length": "base_cells", "iterations": "max_iterations"}
    known = {f.name for f in dataclasses.fields(Settings)}
    settings = Settings(**{field.get(k, k): v for k, v in opts.items() if field.get(k, k) in known})
    rad = lambda v: tuple(math.radians(x) for x in v or ())  # noqa: E731
    angles = (rad(opts["drift"]), rad(opts["attack"]), tuple(opts["yaw_rates"] or ()), tuple(opts["pitch_rates"] or ()))
    spec = SweepSpec(tuple(opts["speeds"]), *angles, axes, int(opts["grids"]), opts["reference_speed"])
    return settings, spec
