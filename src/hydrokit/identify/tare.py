"""Tare tests (ENG2009 §IV.A): the rig alone, swung in air.

In air B ≈ 0 and m_a ≈ 0, so the equation-error coefficients of θ̈ = α sin θ − β θ̇ − γ|θ̇|θ̇
give the effective pendulum length r = −g/α (ENG2009: α = −25.128 → r = 0.3904 m against
0.39 m measured) and the pivot friction β, γ, expressed as K_L = β m, K_Q = γ m / r in the
units of the in-water result, from which they are subtracted. (ENG2009 writes K_Q = γ m r;
``convention="eng2009"`` reproduces that, see :func:`air_tare`.)

:func:`fit_air_tare` fits α, β, γ to the in-air launches; :func:`air_tare` turns them into the
effective length and the tare damping; :func:`apply_tare` puts those into the rig.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit.core.constants import GRAVITY
from hydrokit.core.validate import record
from hydrokit.errors import InputError
from hydrokit.identify.types import Launch, Rig


@dataclass(frozen=True)
class AirTare:
    """Result of an in-air tare.

    effective_length : float — r = −g/α, m
    linear_damping : float — pivot friction as K_L, N·s/m
    quadratic_damping : float — pivot/air friction as K_Q, N·s²/m²
    """

    effective_length: float
    linear_damping: float
    quadratic_damping: float


#: how γ (1/rad) becomes K_Q: "physics" K_Q = γ m / r (N·s²/m²), "eng2009" K_Q = γ m r (the paper's)
TARE_CONVENTIONS = ("physics", "eng2009")


def check_convention(convention: str) -> str:
    """``convention`` if it is one of :data:`TARE_CONVENTIONS`; otherwise a one-line InputError."""
    if convention not in TARE_CONVENTIONS:
        raise InputError(f"convention = {convention!r}: expected one of {', '.join(TARE_CONVENTIONS)}")
    return convention


def quadratic_factor(mass: float, length: float, convention: str = "physics") -> float:
    """The factor K_Q / γ of ``convention``: m / r (physics, kg/m) or m·r (eng2009, kg·m).

    Parameters
    ----------
    mass : float — swinging mass m, kg
    length : float — effective pendulum length r, m
    convention : str — "physics" or "eng2009" (see :func:`air_tare`)
    """
    check_convention(convention)
    return mass / length if convention == "physics" else mass * length


def air_tare(
    alpha: float, beta: float, gamma: float, mass: float, gravity: float = GRAVITY, *, convention: str = "physics"
) -> AirTare:
    """Effective length and pivot friction from in-air pendulum coefficients (ENG2009 eq. 5–7).

    Parameters
    ----------
    alpha : float — coefficient of sin θ, 1/s² (negative: restoring)
    beta : float — linear damping coefficient β, 1/s
    gamma : float — quadratic coefficient γ, 1/rad
    mass : float — swinging mass, kg
    gravity : float — m/s²
    convention : str — how γ becomes K_Q: "physics" (default) K_Q = γ m / r, or "eng2009"
        K_Q = γ m r as ENG2009 writes it

    Returns
    -------
    AirTare — r = −g/α (m), K_L = β m (N·s/m), K_Q (N·s²/m² in the physics convention)

    Raises
    ------
    InputError
        α not negative, a non-positive mass, an unknown ``convention``.

    Notes
    -----
    The body at the end of the rod moves at x = r θ, so the friction moment m r² γ |θ̇| θ̇ seen as a
    force at the body, m r γ |θ̇| θ̇ = (γ m / r) |ẋ| ẋ, gives K_Q = γ m / r in N·s²/m², the unit
    of the in-water K_Q it is subtracted from. ENG2009 converts with K_Q = γ m r, which has the
    unit kg·m and differs from the physics value by the factor r² (0.152 at r = 0.39 m); it is
    offered only to reproduce the paper's numbers, hence "physics" is the default.
    """
    check_convention(convention)
    if not (alpha < 0 and math.isfinite(alpha)):
        raise InputError(f"alpha = {alpha}: expected a negative number (1/s², restoring in air)")
    if not (math.isfinite(mass) and mass > 0):
        raise InputError(f"mass = {mass}: expected a positive mass (kg)")
    r = -gravity / alpha
    return AirTare(r, beta * mass, gamma * quadratic_factor(mass, r, convention))


def apply_tare(rig: Rig, tare: AirTare) -> Rig:
    """The rig with the effective length and the tare damping to subtract."""
    return replace(
        rig,
        pendulum_length=tare.effective_length,
        tare_linear_damping=tare.linear_damping,
        tare_quadratic_damping=tare.quadratic_damping,
    )


@dataclass
class _Smoothed:
    """One launch through the Savitzky–Golay differentiator (edges of the filter dropped).

    q, qd, qdd : θ (rad), θ̇ (rad/s), θ̈ (rad/s²); kernels : the three filters' dot-product
    weights (θ̇, θ̈ ones include 1/Δt, 1/Δt²); noise_var : white sensor-noise variance, rad²,
    from the smoothing residual; window : samples
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    kernels: tuple[np.ndarray, np.ndarray, np.ndarray]
    noise_var: float
    window: int


def _smooth(launch: Launch, window: int | None, polyorder: int) -> _Smoothed:
    """The differentiator of :class:`~hydrokit.identify.estimators.EquationErrorEstimator`
    applied to one trimmed launch: Savitzky–Golay, window about a sixth of the period (from
    :func:`~hydrokit.identify.preprocess.check_record`), uneven sampling resampled first."""
    from scipy.signal import savgol_coeffs, savgol_filter

    from hydrokit.identify.estimators import _savgol_window
    from hydrokit.identify.preprocess import check_record

    t, y = record(launch.t, launch.y, "angle", "rad", launch.file)
    facts = check_record(launch)  # too few samples, no oscillation, growing: InputError naming the file
    # the mean step, not the median: launch files round the time (0.1 ms), which at 30 fps puts
    # the median step 0.1 % off and α, through Δt², 0.2 % off
    dt = float(t[-1] - t[0]) / (t.size - 1)
    if np.max(np.abs(np.diff(t) - dt)) > 0.05 * dt:
        dt = float(np.median(np.diff(t)))
        # every whole step from the first sample up to and including the last one
        tu = t[0] + dt * np.arange(int(math.floor((t[-1] - t[0]) / dt * (1 + 1e-12))) + 1)
        y = np.interp(tu, t, y)
    w = window or _savgol_window(facts["period"], dt)
    if w % 2 == 0 or w <= polyorder or w >= y.size:
        raise InputError(
            f"window = {w}: expected an odd number of samples between {polyorder + 1} and {y.size - 1}", launch.file
        )
    edge = w // 2
    sl = slice(edge, y.size - edge)
    q = savgol_filter(y, w, polyorder)[sl]
    qd = savgol_filter(y, w, polyorder, deriv=1, delta=dt)[sl]
    qdd = savgol_filter(y, w, polyorder, deriv=2, delta=dt)[sl]
    kernels = tuple(savgol_coeffs(w, polyorder, deriv=d, delta=dt, use="dot") for d in (0, 1, 2))
    # smoothing residual of white noise σ²: E[(y − ŷ)²] = σ² (1 − 2 K0[centre] + Σ K0²)
    k0 = kernels[0]
    shrink = 1.0 - 2.0 * k0[edge] + float(k0 @ k0)
    noise_var = float(np.mean((y[sl] - q) ** 2)) / shrink
    return _Smoothed(q, qd, qdd, kernels, noise_var, w)  # type: ignore[arg-type]


def _noise_terms(parts: list[_Smoothed], coef: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sensor-noise bias of the normal equations and the noise map of the regression.

    With white noise n (variance σ²) the filtered signals carry ε_d = K_d · n. To first order
    the equation residual gets Δe = ε₂ − A ε₀ + B ε₁ (A = α cos θ − c sin θ, B = β + 2γ|θ̇|)
    and the regressors get ΔH = [cos θ ε₀, −ε₁, −2|θ̇| ε₁, −sin θ ε₀]. Returns

    bias : E[ΔHᵀ Δe], the expected excess of Hᵀθ̈ (the errors-in-variables bias of least
        squares: mostly the correlation of the smoothed θ with the filtered θ̈)
    noise_map : M with HᵀΔe = Mᵀ n (one row per raw sample, all launches stacked), so that
        Cov(Hᵀ Δe) = σ² MᵀM
    """
    alpha, beta, gamma = coef[:3]
    p = coef.size
    bias = np.zeros(p)
    rows = []
    for j, s in enumerate(parts):
        k0, k1, k2 = s.kernels
        c = coef[3 + j]
        A = alpha * np.cos(s.q) - c * np.sin(s.q)
        B = beta + 2.0 * gamma * np.abs(s.qd)
        p00, p02, p11 = float(k0 @ k0), float(k0 @ k2), float(k1 @ k1)
        v = s.noise_var
        bias[0] += v * float(np.sum(np.cos(s.q) * (p02 - A * p00)))
        bias[1] += -v * float(np.sum(B * p11))
        bias[2] += -v * float(np.sum(2.0 * np.abs(s.qd) * B * p11))
        bias[3 + j] += -v * float(np.sum(np.sin(s.q) * (p02 - A * p00)))
        cols = (np.sin(s.q), -s.qd, -np.abs(s.qd) * s.qd, np.cos(s.q))
        M = np.zeros((s.q.size + s.window - 1, p))
        for col, h in zip((0, 1, 2, 3 + j), cols):
            # Σ_t H_t Δe_t = Σ_i n_i Σ_t H_t (K₂ − A K₀ + B K₁)[i − t]
            M[:, col] = np.convolve(h, k2) - np.convolve(h * A, k0) + np.convolve(h * B, k1)
        rows.append(M * math.sqrt(v))
    return bias, np.vstack(rows)


def fit_air_tare(
    launches: Sequence[Launch],
    mass: float,
    gravity: float,
    *,
    window: int | None = None,
    polyorder: int = 4,
    noise_correction: bool = True,
    convention: str = "physics",
) -> tuple[AirTare, dict[str, Any]]:
    """Fit the in-air tare (ENG2009 §IV.A) to in-air launches of the rig.

    Equation-error least squares over all launches together (ENG2009 eq. 5–7 with B = m_a = 0):

        θ̈ = α sin θ − β θ̇ − γ |θ̇| θ̇ + c_k cos θ,

    with θ, θ̇, θ̈ from the Savitzky–Golay differentiator of the equation-error estimator and one
    rest-value term c_k per launch (a sensor zero θ_0k off the vertical: c_k = −α θ_0k). The
    coefficients are converted with :func:`air_tare`.

    In air the damping terms are about a thousandth of α sin θ, so two effects of the sensor
    noise matter that the in-water estimator can ignore: the smoothed θ and the filtered θ̈
    share noise samples, which biases α (at 30 fps and 0.2° noise |α| by about +0.2 %, i.e.
    r by −0.8 mm), and the residuals are correlated over the filter window, so the textbook
    σ̂² (HᵀH)⁻¹ misstates the standard errors. Both are computed from the filter weights and
    the noise variance (estimated from the smoothing residual of each launch): the expected
    noise cross-products are removed from the normal equations (``noise_correction``) and the
    covariance is the noise propagated through the filter and the regression.

    Parameters
    ----------
    launches : sequence of Launch — in-air launches, trimmed (t in s from the release), angle θ
        in rad, each with at least two cycles of free decay
    mass : float — swinging mass, kg (the model's dry mass in the in-water rig file)
    gravity : float — m/s²
    window : int, optional — Savitzky–Golay window, samples (odd); default about a sixth of
        each launch's period, as the equation-error estimator
    polyorder : int — Savitzky–Golay polynomial order (default 4, as the estimator)
    noise_correction : bool — remove the sensor-noise bias from the normal equations (default
        True; False gives plain least squares)
    convention : str — γ to K_Q: "physics" (default) K_Q = γ m / r in N·s²/m², the unit of the
        in-water K_Q; "eng2009" K_Q = γ m r as ENG2009 prints it (r² times the physics value;
        for reproducing the paper). See :func:`air_tare`.

    Returns
    -------
    tare : AirTare — effective length r = −g/α (m), K_L = β m (N·s/m), K_Q = γ m / r (N·s²/m²;
        γ m r with ``convention="eng2009"``)
    fit : dict — ``alpha`` (1/s²), ``beta`` (1/s), ``gamma`` (1/rad); ``std_error``: their
        standard errors (same units; sensor noise only, not model error); ``n``: samples in
        the regression; ``launches``: number of launches; ``rms_residual``: RMS equation
        residual, rad/s²; ``noise_std``: estimated sensor noise per launch, rad;
        ``rest_values``: fitted rest angle per launch, rad; ``windows``: Savitzky–Golay window
        per launch, samples

    Raises
    ------
    InputError
        No launches; a launch with too few samples or without two cycles of free decay
        (:func:`~hydrokit.identify.preprocess.check_record`); fewer regression samples than
        coefficients; a fitted α ≥ 0 (no restoring pendulum: not an in-air record of a
        hanging pendulum, or the angle is not in radians); a non-positive mass or gravity; an
        unknown ``convention``.

    Examples
    --------
    >>> import hydrokit
    >>> from hydrokit.data import DATA_DIR
    >>> from hydrokit.identify.tare import apply_tare, fit_air_tare
    >>> base = DATA_DIR / "campaigns" / "rov2"
    >>> rig = hydrokit.load_rig(base / "pendulum_surge.yaml")
    >>> air = [hydrokit.read_launch(f, rig) for f in sorted((base / "tare").glob("air_*.csv"))]
    >>> tare, fit = fit_air_tare(air, rig.mass, rig.gravity)
    >>> round(tare.effective_length, 3)                      # m (ENG2009: 0.3904)
    0.39
    >>> rig_tared = apply_tare(rig, tare)                    # then identify_campaign(rig_tared, …)
    """
    check_convention(convention)
    launches = list(launches)
    if not launches:
        raise InputError("no in-air launches given; expected at least one trimmed launch for the air tare")
    if not (math.isfinite(mass) and mass > 0):
        raise InputError(f"mass = {mass}: expected a positive mass (kg)")
    if not (math.isfinite(gravity) and gravity > 0):
        raise InputError(f"gravity = {gravity}: expected a positive acceleration (m/s²)")
    parts = [_smooth(L, window, polyorder) for L in launches]
    n = sum(s.q.size for s in parts)
    k = len(parts)
    p = 3 + k
    if n <= p:
        raise InputError(f"only {n} samples left after smoothing {k} launch(es); expected more than {p}")
    H = np.zeros((n, p))
    rhs = np.empty(n)
    i = 0
    for j, s in enumerate(parts):
        sl = slice(i, i + s.q.size)
        H[sl, 0] = np.sin(s.q)
        H[sl, 1] = -s.qd
        H[sl, 2] = -np.abs(s.qd) * s.qd
        H[sl, 3 + j] = np.cos(s.q)
        rhs[sl] = s.qdd
        i += s.q.size
    HtH = H.T @ H
    Hty = H.T @ rhs
    try:
        bread = np.linalg.inv(HtH)
    except np.linalg.LinAlgError:
        raise InputError("the in-air launches do not separate α, β and γ (singular regression)") from None
    if not np.all(np.isfinite(bread)) or np.linalg.cond(HtH) > 1e14:
        raise InputError("the in-air launches do not separate α, β and γ (singular regression)")
    coef = bread @ Hty
    if noise_correction:
        for _ in range(3):  # the bias depends (weakly) on the coefficients: a few fixed-point steps
            bias, _ = _noise_terms(parts, coef)
            coef = bread @ (Hty - bias)
    _, M = _noise_terms(parts, coef)
    cov = bread @ (M.T @ M) @ bread
    resid = rhs - H @ coef
    alpha, beta, gamma = (float(c) for c in coef[:3])
    if not (alpha < 0 and math.isfinite(alpha)):
        raise InputError(
            f"fitted alpha = {alpha:.4g} 1/s²: expected a negative coefficient of sin θ (a restoring pendulum in "
            "air); check that the launches are in-air records of a hanging pendulum and the angle is in radians, "
            "its zero within 90° of hanging"
        )
    se = np.sqrt(np.clip(np.diag(cov)[:3], 0.0, None))
    tare = air_tare(alpha, beta, gamma, mass, gravity, convention=convention)
    fit = {
        "convention": convention,
        "alpha": alpha,
        "beta": beta,
        "gamma": gamma,
        "std_error": {"alpha": float(se[0]), "beta": float(se[1]), "gamma": float(se[2])},
        "n": int(n),
        "launches": k,
        "rms_residual": math.sqrt(float(resid @ resid) / n),
        "noise_std": [math.sqrt(s.noise_var) for s in parts],
        "rest_values": [float(-c / alpha) for c in coef[3:]],
        "windows": [s.window for s in parts],
    }
    return tare, fit
