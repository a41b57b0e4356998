"""``hydrokit scale``: model-test coefficients to full size (ENG2009 similitude)."""

from __future__ import annotations

import click

from hydrokit.errors import InputError


@click.command()
@click.option(
    "--ratio", type=float, required=True, help="Model/full-size length ratio, e.g. 0.3 for a 30 % model (no unit)."
)
@click.option("--added-mass", type=float, default=None, help="Model added mass, kg (kg·m² with --rotational).")
@click.option("--linear-damping", type=float, default=None, help="Model K_L, N·s/m (N·m·s/rad with --rotational).")
@click.option(
    "--quadratic-damping", type=float, default=None, help="Model K_Q, N·s²/m² (N·m·s²/rad² with --rotational)."
)
@click.option("--rotational", is_flag=True, help="Coefficients of a rotational DOF (added inertia and damping ∝ λ⁵).")
def scale(
    ratio: float,
    added_mass: float | None,
    linear_damping: float | None,
    quadratic_damping: float | None,
    rotational: bool,
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
    full = scale_coefficients(vals, lam, rotational)
    click.echo(f"λ = L_full / L_model = {lam:.6g}")
    for k, v in vals.items():
        click.echo(f"{k}: model {v:.6g} → full scale {full[k]:.6g}")
    click.echo("assumptions:")
    for a in SCALING_ASSUMPTIONS:
        click.echo(f"  - {a}")
