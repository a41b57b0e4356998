"""Similitude scaling of model-test coefficients to full size (SPEC §1.6, ENG2009 §II.D).

With λ = L_full / L_model and equal drag coefficients at equal speed: added mass ∝ λ³,
added inertia ∝ λ⁵, translational damping K_L, K_Q ∝ λ², rotational damping ∝ λ⁵.
"""

from __future__ import annotations

import math

from hydrokit.errors import InputError

SCALING_ASSUMPTIONS: tuple[str, ...] = (
    "geometric similarity: every length scales by λ = L_full / L_model",
    "equal fluid density in model and full-scale tests (else multiply by ρ_full/ρ_model)",
    "equal drag coefficients: the flow is in a Reynolds-insensitive range (ENG2009 checked 0–0.5 m/s by CFD)",
    "comparison at equal speed — this is NOT Reynolds similarity; Re grows by λ at full scale",
    "added mass ∝ λ³, added inertia ∝ λ⁵, K_L and K_Q ∝ λ² (translation), rotational damping ∝ λ⁵",
)

EXPONENTS = {
    False: {"added_mass": 3, "linear_damping": 2, "quadratic_damping": 2, "mass": 3, "volume": 3},
    True: {"added_mass": 5, "linear_damping": 5, "quadratic_damping": 5, "mass": 3, "inertia": 5},
}


def scale_factor(ratio: float) -> float:
    """λ from the model/full-scale ratio (e.g. 0.3 for a 30 % model → λ = 3.333)."""
    if not (isinstance(ratio, (int, float)) and math.isfinite(ratio) and ratio > 0):
        raise InputError(f"scale ratio = {ratio}: expected a positive model/full-size length ratio (e.g. 0.3)")
    return 1.0 / ratio


def scale_coefficients(values: dict[str, float], lam: float, rotational: bool = False) -> dict[str, float]:
    """Full-scale values of model-test coefficients.

    Parameters
    ----------
    values : dict — any of added_mass (kg or kg·m²), linear_damping, quadratic_damping (N·s/m,
        N·s²/m² or rotational units), mass (kg), volume (m³), inertia (kg·m²)
    lam : float — λ = L_full / L_model (> 0)
    rotational : bool — coefficients of a rotational DOF (torsion rig)

    Returns
    -------
    dict with the same keys, scaled; unknown keys raise InputError.
    """
    if not (math.isfinite(lam) and lam > 0):
        raise InputError(f"λ = {lam}: expected a positive length ratio L_full/L_model")
    table = EXPONENTS[bool(rotational)]
    out = {}
    for key, v in values.items():
        if key not in table:
            raise InputError(f"cannot scale {key!r}: expected one of {', '.join(table)}")
        try:
            out[key] = float(v) * lam ** table[key]
        except OverflowError:
            out[key] = math.inf
        if not math.isfinite(out[key]):
            raise InputError(
                f"{key} = {float(v):.4g} × λ^{table[key]} (λ = {lam:.4g}) is beyond the float range at full scale; "
                "expected a model value and scale ratio of a realistic size"
            )
    return out
