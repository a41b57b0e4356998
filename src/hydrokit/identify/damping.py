"""Equivalent linear damping at a stated amplitude and the model-free damping curve (issue #16).

For the rig equation A q̈ + B1 q̇ + B2 |q̇| q̇ + B3 q̇³ + S ρ(q) = 0, a harmonic motion
q = a cos ω0 t dissipates per cycle what a linear damper B_e dissipates when

    B_e(a) = B1 + 8/(3π)·ω0·a·B2 + 3/4·ω0²·a²·B3

(Fossen-style energy balance; B3 = 0 outside the cubic damping model). Its standard error comes
from the fit's covariance of (ω², b, g, d) by the delta method.

The **damping curve** needs no damping model: between two successive extremes a1, a2 (one half
cycle, duration T½) the restoring loses ΔE = S (R(a1) − R(a2)), R(a) = ∫₀ᵃ ρ, and a linear
damper loses (π/2)·ω·B_e·a_m² with ω = π/T½ and a_m = (a1 + a2)/2; so each half cycle gives
B_e = 2 ΔE / (π ω a_m²) at its mean amplitude a_m (linear restoring: 2 S (a1 − a2) / (π ω a_m),
the logarithmic decrement in energy form). Plotted with the fitted model's B_e(a), it shows at
a glance whether the model's amplitude dependence matches the record.

Units: amplitude m or rad; B_e in N·s/m (spring, heave) or N·m·s/rad (torsion, roll, pitch).
The pendulum (damping along the path, sin θ restoring) is not covered.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig

K2 = 8.0 / (3.0 * math.pi)
K3 = 0.75


def model_curve(a: Any, B1: float, B2: float, B3: float, w0: float) -> np.ndarray:
    """B_e(a) of the fitted model (a in m or rad; B's in reported units; w0 rad/s)."""
    a = np.asarray(a, float)
    return B1 + K2 * w0 * a * B2 + K3 * w0 * w0 * a * a * B3


def check_rig(rig: Rig, what: str = "--equivalent-at") -> None:
    """Equivalent damping needs damping in the recorded coordinate: not the pendulum (``what``
    names the feature in the message)."""
    if rig.test == "pendulum":
        raise InputError(
            f"{what} applies to the spring, torsion and floating rigs, not to the pendulum "
            "(its damping acts along the path)"
        )


def equivalent_damping(est: Any, rig: Rig, amplitudes: Sequence[float]) -> list[dict[str, float | None]]:
    """B_e at each amplitude with its delta-method standard error, net of the rig's tare.

    Parameters
    ----------
    est : a fitted estimator (``p_`` = (ω², b, g), ``pcov4_`` the covariance of (ω², b, g, d),
        ``ext_`` the extended parameters when fitted, ``constants_``)
    rig : Rig
    amplitudes : m or rad
    """
    c = est.constants_
    w2, b, g = (float(v) for v in est.p_)
    ext = getattr(est, "ext_", None)
    d = float(ext[3]) if ext is not None else 0.0
    A = c.S / w2
    w = math.sqrt(w2)
    cov = getattr(est, "pcov4_", None)
    formal = getattr(est, "pcov4_formal_", None)

    def delta(m: Any, grad: np.ndarray) -> float | None:
        if m is None or not np.all(np.isfinite(m)):
            return None
        return math.sqrt(max(float(grad @ m @ grad), 0.0))

    out: list[dict[str, float | None]] = []
    for a in amplitudes:
        inner = b + K2 * w * a * g + K3 * w2 * a * a * d
        value = A * inner - rig.tare_linear_damping - K2 * w * a * rig.tare_quadratic_damping
        grad = np.array(
            [
                -c.S / w2**2 * inner + A * (K2 * a * g / (2.0 * w) + K3 * a * a * d),
                A,
                A * K2 * w * a,
                A * K3 * w2 * a * a,
            ]
        )
        entry: dict[str, float | None] = {"amplitude": float(a), "value": float(value), "std_error": delta(cov, grad)}
        if formal is not None:
            entry["std_error_formal"] = delta(formal, grad)
        out.append(entry)
    return out


def _potential(c: Any, a: float) -> float:
    """R(a) = ∫₀ᵃ ρ(q) dq of the rig's restoring shape (a ≥ 0; the pendulum's sin θ is refused by
    :func:`check_rig`): :func:`hydrokit.identify.estimators.restoring_potential`, the one law."""
    from hydrokit.identify.estimators import restoring_potential

    return float(restoring_potential(a, c))


def damping_curve(t: Any, y: Any, est: Any, rig: Rig) -> list[dict[str, float]]:
    """Model-free equivalent damping of each half cycle of a trimmed launch.

    Parameters
    ----------
    t : s; y : m or rad (the record the estimator fitted)
    est : the fitted estimator (``offset_``, ``noise_``, the rig constants); the rest value is
        refined from the extremes
    rig : Rig (its tare is subtracted as in the fitted coefficients); not the pendulum

    Returns
    -------
    list of {time (s, middle of the half cycle, launch time), amplitude (mean of the two
    extremes, m or rad), value (B_e, reported units)}
    """
    from hydrokit.identify.estimators import _peaks

    check_rig(rig, "the damping curve")
    t = np.asarray(t, float)
    z = np.asarray(y, float) - float(est.offset_)
    c = est.constants_
    band = max(4.0 * float(est.noise_), 0.01 * float(np.max(np.abs(z))))
    peaks = _peaks(t, z, band)
    # the rest value from the extremes themselves: an error δ in it moves every other half cycle's
    # decrement by ±2δ, so the fitted offset (a compromise over the record) is not good enough;
    # three successive extremes of a geometric decay give it exactly, (p1 p3 − p2²)/(p1 + p3 − 2 p2)
    ap = np.array([p for _, p in peaks])
    shift = 0.0
    if ap.size >= 3:
        den = ap[:-2] + ap[2:] - 2 * ap[1:-1]
        ok = den != 0
        if np.any(ok):
            shift = float(np.median((ap[:-2] * ap[2:] - ap[1:-1] ** 2)[ok] / den[ok]))
    out: list[dict[str, float]] = []
    for (t1, a1), (t2, a2) in zip(peaks[:-1], peaks[1:]):
        a1, a2 = abs(a1 - shift), abs(a2 - shift)
        if t2 <= t1 or a1 <= 0 or a2 <= 0:
            continue
        w = math.pi / (t2 - t1)
        am = 0.5 * (a1 + a2)
        dE = c.S * (_potential(c, a1) - _potential(c, a2))
        value = 2.0 * dE / (math.pi * w * am * am)
        value -= rig.tare_linear_damping + K2 * w * am * rig.tare_quadratic_damping
        out.append({"time": 0.5 * (t1 + t2), "amplitude": am, "value": value})
    return out
