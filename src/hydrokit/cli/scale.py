"""``hydrokit scale``: model-test coefficients to full size (ENG2009 similitude)."""

from __future__ import annotations

import math

import click

from hydrokit.cli._types import FINITE, Number
from hydrokit.errors import InputError

RATIO = Number("model/full-size length ratio", above=0)
VOLUME = Number("m³", above=0)


@click.command()
@click.option(
    "--ratio", type=RATIO, required=True, help="Model/full-size length ratio, e.g. 0.3 for a 30 % model (no unit)."
)
@click.option("--added-mass", type=FINITE, default=None, help="Model added mass, kg (kg·m² with --rotational).")
@click.option("--linear-damping", type=FINITE, default=None, help="Model K_L, N·s/m (N·m·s/rad with --rotational).")
@click.option(
    "--quadratic-damping", type=FINITE, default=None, help="Model K_Q, N·s²/m² (N·m·s²/rad² with --rotational)."
)
@click.option("--rotational", is_flag=True, help="Coefficients of a rotational DOF (added inertia and damping ∝ λ⁵).")
@click.option(
    "--model-volume",
    type=VOLUME,
    default=None,
    help="Model displaced volume, m³ (with --full-volume: CELY2019's C_m form).",
)
@click.option(
    "--full-volume",
    type=VOLUME,
    default=None,
    help="Full-scale displaced volume, m³: also print the added mass as C_m ρ V_full, CELY2019's convention.",
)
def scale(
    ratio: float,
    added_mass: float | None,
    linear_damping: float | None,
    quadratic_damping: float | None,
    rotational: bool,
    model_volume: float | None,
    full_volume: float | None,
) -> None:
    """Scale model-test coefficients to full size (ENG2009 similitude) and print the assumptions."""
    from hydrokit.identify.scaling import SCALING_ASSUMPTIONS, scale_coefficients, scale_factor

    lam = scale_factor(ratio)
    vals = {
        k: v
        for k, v in (
            ("added_mass", added_mass),
            ("linear_damping", linear_damping),
            ("quadratic_damping", quadratic_damping),
        )
        if v is not None
    }
    if not vals:
        raise InputError("give at least one of --added-mass, --linear-damping, --quadratic-damping")
    if (model_volume is None) != (full_volume is None):
        raise InputError("--model-volume and --full-volume go together (m³): give both or neither")
    full = scale_coefficients(vals, lam, rotational)
    click.echo(f"λ = L_full / L_model = {lam:.6g}")
    for k, v in vals.items():
        click.echo(f"{k}: model {v:.6g} → full scale {full[k]:.6g}")
    if model_volume is not None and full_volume is not None and added_mass is not None and not rotational:
        cm_form = added_mass * full_volume / model_volume  # C_m ρ V_full with C_m = m_a / (ρ V_model)
        if not (math.isfinite(100 * (cm_form / full["added_mass"] - 1)) and math.isfinite(model_volume * lam**3)):
            raise InputError(
                f"--model-volume {model_volume:.4g} m³ against --full-volume {full_volume:.4g} m³: the C_m form "
                f"({cm_form:.4g}) is beyond the float range of a comparison; expected volumes of a realistic size"
            )
        click.echo(
            f"added_mass as C_m ρ V_full (CELY2019 Table 10 convention): {cm_form:.6g}; "
            f"λ³ similitude gives {full['added_mass']:.6g} ({100 * (cm_form / full['added_mass'] - 1):+.1f} %): "
            f"they agree only when V_full = λ³ V_model = {model_volume * lam**3:.6g} m³"
        )
    click.echo("assumptions:")
    for a in SCALING_ASSUMPTIONS:
        click.echo(f"  - {a}")
