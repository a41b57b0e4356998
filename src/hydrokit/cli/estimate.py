"""``hydrokit estimate`` and ``hydrokit fit-forces``: coefficients from geometry and force curves."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from hydrokit.cli._common import json_text, write_all
from hydrokit.cli._types import Count, Number
from hydrokit.core.names import DOF_NAMES as DOF
from hydrokit.errors import InputError


@click.command()
@click.argument("geometry", metavar="GEOMETRY.yaml", type=click.Path(dir_okay=False))
@click.option(
    "--out",
    "out_file",
    required=True,
    type=click.Path(dir_okay=False),
    help="Vehicle-file fragment to write (YAML, SI: kg, kg·m², m, N·s/m, N·s²/m²).",
)
@click.option(
    "--bem",
    is_flag=True,
    help="Added mass of shape and mesh parts by the boundary-element solver (Capytaine; pip install 'hydrokit[bem]').",
)
@click.option(
    "--resolution",
    type=Count(6, 200),
    default=None,
    help="BEM panels around the circumference (count, 6 to 200; default 48 or the part's own).",
)
@click.option(
    "--damping-model",
    type=click.Choice(["elements", "rehman", "shifted"]),
    default="elements",
    show_default=True,
    help="How parts' quadratic damping combines. elements: each part's translational drag (N·s²/m²) becomes a "
    "drag element at its origin, seen at that point's own velocity (drag moment d·r³·ω²); rehman: one diagonal, "
    "rotational += d·r³ (N·m·s²/rad²; right for motion about one axis only); shifted: diagonal of HᵀDH, "
    "d·r² (kg·m, dimensionally wrong; for comparison).",
)
def estimate(geometry: str, out_file: str, bem: bool, resolution: int | None, damping_model: str) -> None:
    """Estimate added mass, damping and mass properties of GEOMETRY (one shape or a composite)
    and write them as a vehicle-file fragment; print the coefficients with their source."""
    import numpy as np
    import yaml
    from rich.console import Console
    from rich.table import Table

    from hydrokit.api import estimate_geometry

    est = estimate_geometry(geometry, bem=bem, resolution=resolution, quadratic_damping=damping_model)
    geo, comp, frag = est.geometry, est.composite, est.to_dict()
    console = Console()
    tab = Table(title=f"{geo.name}: parts (added-mass diagonal about each part's origin; quadratic damping)")
    for c in ("part", "mass (kg)", "A11..A33 (kg)", "A44..A66 (kg·m²)", "d_Q x,y,z (N·s²/m²)"):
        tab.add_column(c)
    for gp in geo.parts:
        p = gp.part
        a = np.diag(p.added_mass)
        tab.add_row(
            p.name,
            f"{p.mass:.4g}",
            ", ".join(f"{x:.4g}" for x in a[:3]),
            ", ".join(f"{x:.4g}" for x in a[3:]),
            ", ".join(f"{x:.4g}" for x in np.diag(p.quadratic_damping)[:3]),
        )
    console.print(tab)
    console.print("sources:")
    for gp in geo.parts:
        for k, v in gp.sources.items():
            console.print(f"  {gp.part.name} {k}: {v}", highlight=False)
    comp_tab = Table(title="combined about the common origin: full 6×6 transform vs diagonal only (REHMAN)")
    for c in ("DOF", "added mass, full (diag)", "diagonal only", "largest off-diagonal in row"):
        comp_tab.add_column(c, justify="right")
    full, dg = comp.added_mass, comp.added_mass_diagonal_only
    for i, name in enumerate(DOF):
        off = np.abs(full[i]).copy()
        off[i] = 0
        off[off < 1e-9 * np.abs(full).max()] = 0  # symmetry zeros, not rounding noise
        j = int(np.argmax(off))
        comp_tab.add_row(
            name, f"{full[i, i]:.4g}", f"{dg[i, i]:.4g}", f"{full[i, j]:.4g} ({DOF[j]})" if off[j] > 0 else "0"
        )
    console.print(comp_tab)
    quad = ", ".join(f"{x:.4g}" for x in np.diag(comp.quadratic_damping))
    one = ", ".join(f"{x:.4g}" for x in comp.quadratic_damping_single_axis)
    console.print(f"quadratic damping ({damping_model}) diagonal: {quad}; motion along/about one axis: {one}")
    console.print(f"drag elements: {', '.join(comp.drag_element_names) or 'none'}", highlight=False)
    for w in comp.warnings:
        console.print(f"warning: {w}", highlight=False)
    console.print(
        f"mass {comp.mass:.4g} kg, weight {comp.weight(geo.gravity):.4g} N, buoyancy "
        f"{comp.buoyancy(geo.density, geo.gravity):.4g} N, CG {np.round(comp.r_g, 4).tolist()} m, "
        f"CB {np.round(comp.r_b, 4).tolist()} m"
    )
    text = "# vehicle-file fragment written by hydrokit estimate (SI units; matrices about the common origin)\n"
    write_all({out_file: text + yaml.safe_dump(frag, sort_keys=False)})
    click.echo(f"wrote {out_file}", err=True)


@click.command("fit-forces")
@click.argument("forces", metavar="FORCES.csv", type=click.Path(dir_okay=False))
@click.option("--area", type=Number("m²", above=0), required=True, help="Reference area A_ref for C_D, m².")
@click.option("--density", type=Number("kg/m³", above=0), required=True, help="Fluid density ρ, kg/m³.")
@click.option(
    "--json", "json_out", type=click.Path(dir_okay=False), default=None, help="Write the fits to this JSON file."
)
@click.option(
    "--plot", "plot_out", type=click.Path(dir_okay=False), default=None, help="Write data and fits to this PNG."
)
def fit_forces(forces: str, area: float, density: float, json_out: str | None, plot_out: str | None) -> None:
    """Fit F = K_L U + K_Q|U|U (Chin) and F = K_D|U|U (Morison) to FORCES.csv (columns speed m/s, force N)."""
    from hydrokit.api import fit_forces as fit
    from hydrokit.io.forces import read_forces

    U, F = read_forces(forces)
    try:
        res = fit(U, F, area, density)
    except InputError as exc:  # the fit's words, with the file they are about
        raise InputError(exc.detail, exc.source or forces) from None
    click.echo(
        f"Chin:    K_L = {res.K_L:.6g} ± {res.K_L_se:.3g} N·s/m, K_Q = {res.K_Q:.6g} ± {res.K_Q_se:.3g} N·s²/m², "
        f"R² = {res.r2_chin:.4f}"
    )
    click.echo(
        f"Morison: K_D = {res.K_D:.6g} ± {res.K_D_se:.3g} N·s²/m², C_D = {res.C_D:.6g} (A_ref = {area:g} m², "
        f"ρ = {density:g} kg/m³), R² = {res.r2_morison:.4f}"
    )
    files: dict[str | Path, Any] = {}
    if json_out:
        files[json_out] = json_text(res.to_dict())
    if plot_out:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.forces import force_fit_figure

        files[plot_out] = to_png(force_fit_figure(U, F, res, Path(forces).stem))
    write_all(files)
