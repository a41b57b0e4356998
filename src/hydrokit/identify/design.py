"""Experiment design: predicted uncertainty before the test (SPEC §1.5).

For a candidate launch the Cramér–Rao bound gives the smallest covariance any unbiased
estimator can reach: cov ≥ σ² (JᵀJ)⁻¹, with J the sensitivity of the sampled signal to the
parameters (ω², b, g, q0, v0, sensor offset) — the same sensitivities the output-error fit
uses — and σ² the sensor's noise variance plus its quantisation variance (step²/12).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from hydrokit.core.names import COEFFICIENTS
from hydrokit.errors import InputError
from hydrokit.identify.rig_model import rig_constants, simulate_normalised
from hydrokit.identify.types import Rig
from hydrokit.identify.virtual_rig import SensorModel


def cramer_rao(
    rig: Rig,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    amplitude: float,
    duration: float,
    sensor: SensorModel,
) -> dict[str, Any]:
    """Cramér–Rao standard deviations of (m_a, K_L, K_Q) for one launch.

    Parameters are those of :func:`hydrokit.identify.virtual_rig.simulate_launch`.
    Returns a dict of standard deviations in the reported units (kg, N·s/m, N·s²/m² or the
    rotational ones), their ``covariance`` (3 × 3, the same units), and the damping-force
    standard deviation at the peak speed (``damping_force_rel``: relative).
    """
    var = sensor.noise_std**2 + sensor.resolution**2 / 12.0
    if var <= 0:
        raise InputError(
            f"sensor noise_std = {sensor.noise_std:g} and resolution = {sensor.resolution:g}: the bound is zero; "
            "expected a noise_std or resolution > 0 (m or rad)"
        )
    c = rig_constants(rig)
    w2, b, g = c.to_normalised(added_mass, linear_damping, quadratic_damping)
    t = np.arange(int(round(duration * sensor.sample_rate)) + 1) / sensor.sample_rate
    _, v, J = simulate_normalised(t, w2, b, g, amplitude, 0.0, c.sine, 4, True, restoring=c.restoring)
    J = np.column_stack([J, np.ones(t.size)])
    fisher = J.T @ J / var
    cov = np.linalg.inv(fisher)[:3, :3]
    T = c.jacobian_from_normalised(w2, b, g)
    cov_r = T @ cov @ T.T
    sd = np.sqrt(np.clip(np.diag(cov_r), 0, None))
    u = float(np.max(np.abs(v))) * c.speed_factor
    grad = np.array([0.0, u, u * u])  # ∂(K_L u + K_Q u²)/∂(m_a, K_L, K_Q)
    f = linear_damping * u + quadratic_damping * u * u
    out: dict[str, Any] = {k: float(s) for k, s in zip(COEFFICIENTS, sd)}
    out["covariance"] = cov_r.tolist()  # of (m_a, K_L, K_Q), reported units
    out["damping_force_rel"] = float(math.sqrt(grad @ cov_r @ grad) / abs(f)) if f else float("nan")
    out["speed_max"] = u
    return out


def plan_experiment(
    rig: Rig,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    amplitudes: Sequence[float],
    sensor: SensorModel,
    duration: float = 20.0,
    launches: int = 1,
) -> list[dict[str, Any]]:
    """Predicted standard errors of each coefficient for each candidate amplitude.

    Parameters
    ----------
    amplitudes : sequence of float — release displacements, m (spring) or rad
    launches : int — launches per amplitude (standard errors shrink as 1/√n)
    Other parameters as :func:`cramer_rao`.

    Returns
    -------
    list of dicts: amplitude, speed_max (m/s), predicted std error per coefficient (per
    amplitude group of ``launches``), relative errors.
    """
    if launches < 1:
        raise InputError(f"launches = {launches}: expected at least 1")
    rows = []
    truth = {"added_mass": added_mass, "linear_damping": linear_damping, "quadratic_damping": quadratic_damping}
    for a in amplitudes:
        if not (a != 0 and math.isfinite(a)):
            raise InputError(f"amplitude = {a}: expected a non-zero displacement")
        try:
            with np.errstate(all="ignore"):
                crb = cramer_rao(rig, added_mass, linear_damping, quadratic_damping, a, duration, sensor)
        except np.linalg.LinAlgError:
            crb = {k: math.nan for k in COEFFICIENTS}
        if not all(math.isfinite(crb[k]) for k in COEFFICIENTS):
            # the model's response leaves the float range, or one coefficient no longer moves it
            raise InputError(
                f"added_mass = {added_mass:.4g}, linear_damping = {linear_damping:.4g}, quadratic_damping = "
                f"{quadratic_damping:.4g} at amplitude {a:.4g}: the launch carries no finite information on "
                "every coefficient (a singular or non-finite Fisher matrix); expected coefficients of a realistic "
                "size for this rig (SI)"
            )
        row: dict[str, Any] = {"amplitude": float(a), "speed_max": crb["speed_max"], "launches": launches}
        for k in COEFFICIENTS:
            se = crb[k] / math.sqrt(launches)
            row[k] = se
            row[k + "_rel"] = se / abs(truth[k]) if truth[k] else float("nan")
        row["damping_force_rel"] = crb["damping_force_rel"] / math.sqrt(launches)
        rows.append(row)
    return rows


def recommend(plan: Sequence[dict[str, Any]]) -> str:
    """A one-paragraph recommendation from :func:`plan_experiment`'s rows."""
    if not plan:
        return "no candidate amplitudes"

    # the truth is the same in every row, so the smallest error is the smallest relative error;
    # ranking by the absolute one also works when a true coefficient is 0 (relative: nan)
    def best(k: str) -> dict[str, Any]:
        return min(plan, key=lambda r: float(r[k]))

    best_q, best_l, best_m = best("quadratic_damping"), best("linear_damping"), best("added_mass")

    def err(row: dict[str, Any], k: str) -> str:
        rel = row[k + "_rel"]
        return f"±{100 * rel:.2g} %" if math.isfinite(rel) else f"±{row[k]:.2g} SI, the true value being 0"

    return (
        f"quadratic damping is best resolved by the largest speeds (amplitude {best_q['amplitude']:.4g}: "
        f"{err(best_q, 'quadratic_damping')}), linear damping at amplitude {best_l['amplitude']:.4g} "
        f"({err(best_l, 'linear_damping')}), added mass at {best_m['amplitude']:.4g} "
        f"({err(best_m, 'added_mass')}). Run launches over the whole operating speed range "
        "so the damping force curve is covered; K_L and K_Q trade off, the force curve does not."
    )
