"""Free-decay estimators (scikit-learn conventions: ``fit`` returns self, learned attributes
end in ``_``, ``predict(t)`` replays the fitted model).

Each estimator works on the generalised rig equation of :mod:`hydrokit.identify.rig_model`

    q̈ = −ω² ρ(q) − b q̇ − g |q̇| q̇,      ω² = S/A, b = c_L/A, g = c_Q/A,

and converts (ω², b, g) to the reported added mass m_a, K_L and K_Q with the rig constants.

Methods
-------
``log-decrement``   peaks → damped period and logarithmic decrement per cycle (SPEC S2, S3);
                    ζ per cycle regressed on the cycle amplitude separates linear and
                    quadratic damping; C_D per cycle against the cycle's Reynolds number.
``equation-error``  CHIN2012 / ENG2009 eq. 5–7 least squares on [ρ(q), q̇, |q̇|q̇] with q̇, q̈
                    from a Savitzky–Golay differentiator (never raw double differences) for ω²
                    and the rest value; the damping from the same equation in energy form
                    (integrated against q̇ between the extremes), which harmonics cannot bias.
``morison``         CELY2019 eq. 11–16 made dimensionally consistent: equation error with
                    K_L = 0 (their eq. 12–16 lose the factor r between force and angle and
                    their eq. 16 omits m + m_a; we fit P1 with K_L = 0 instead).
``output-error``    integrates the rig ODE (compiled RK4 with forward sensitivities) and fits the
                    recorded signal with :func:`scipy.optimize.least_squares`; fits the initial
                    displacement, rate and the sensor offset too; covariance σ̂² (JᵀJ)⁻¹. The
                    most accurate method and the default.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from hydrokit._quiet import quiet
from hydrokit.core.names import COEFFICIENTS
from hydrokit.core.validate import record
from hydrokit.errors import InputError
from hydrokit.identify.preprocess import check_record, half_cycle_extremes
from hydrokit.identify.rig_model import RigConstants, rig_constants, simulate_extended, simulate_normalised
from hydrokit.identify.types import METHODS, Launch, LaunchResult, Rig

#: ``--damping-model``: B1 only, B1 + B2 |q̇| q̇ (default), B1 + B2 |q̇| q̇ + B3 q̇³
DAMPING_MODELS = ("linear", "quadratic", "cubic")
#: ``--restoring-terms``: the rig's restoring (1), plus a fitted C3 q³ (3), plus C3 q³ + C5 q⁵ (5)
RESTORING_TERMS = (1, 3, 5)
#: gap ratio e / L_ref below which wall proximity is flagged (CELY2019 blames the tank floor for
#: its z-axis scatter; wall effects on added mass become noticeable within about one body size)
GAP_RATIO_WARNING = 1.0


#: how the output-error standard errors are computed (named in every launch's JSON)
UNCERTAINTY_METHOD = (
    "cycle-wise jackknife (delete one oscillation cycle, one Gauss-Newton step each), never below the formal"
)
#: the method when the adequacy check finds the residual white (the sensor noise alone)
FORMAL_WHEN_ADEQUATE = "formal (the residual is white sensor noise: the adequacy check found nothing else)"


def cycle_jackknife(J: np.ndarray, r: np.ndarray, cycle: np.ndarray, formal: np.ndarray) -> np.ndarray:
    """Parameter covariance that holds when the residuals are correlated within a cycle.

    The formal s² (JᵀJ)⁻¹ assumes independent residuals; on real records the residual is
    model error that repeats every cycle, and the formal errors understate the scatter (issue
    #16). Here each oscillation cycle b is deleted in turn and the fit moved by one
    Gauss–Newton step from the full solution, δ_b = (JᵀJ − J_bᵀJ_b)⁻¹ J_bᵀ r_b (exact for a
    linear model), and the covariance is the jackknife's (B−1)/B Σ_b (δ_b − δ̄)(δ_b − δ̄)ᵀ over
    the B cycles. Per parameter the larger of this and the formal variance is kept: with few
    cycles the jackknife is itself uncertain, and model error never makes a fit more precise
    than white noise would.

    Why not the cluster sandwich (JᵀJ)⁻¹ [B/(B−1) Σ_b S_b S_bᵀ] (JᵀJ)⁻¹ with the cycle scores
    S_b = J_bᵀ r_b, which this replaced: it weighs every cycle's score with the full fit's
    (JᵀJ)⁻¹, so the cycles that carry most of the information (the first, large ones: the
    initial state and the amplitude-dependent damping live there) are under-weighted. On 200
    generated records of varied damping, heel, drift and coloured noise its σ of B_e(5°) was
    about 1.2× too small (coverage of ±1.96 σ 89 %; 86 % without drift); the jackknife's
    (B_e − truth)/σ has sd 0.97 and covers 96.0 % (bench/uncertainty_coverage.py).

    Parameters
    ----------
    J : (n, p) — Jacobian of the residuals at the solution
    r : (n,) — residuals
    cycle : (n,) int — cycle of each sample
    formal : (p, p) — the white-noise covariance
    """
    labels, index = np.unique(cycle, return_inverse=True)
    B = labels.size
    if B < 3:
        return formal
    JtJ = J.T @ J
    D = np.empty((B, J.shape[1]))
    for b in range(B):
        m = index == b
        Jb = J[m]
        # pinv: a cycle that alone fixes a parameter leaves JᵀJ − J_bᵀJ_b singular
        D[b] = np.linalg.pinv(JtJ - Jb.T @ Jb) @ (Jb.T @ r[m])
    D -= D.mean(axis=0)
    cov = (B - 1.0) / B * (D.T @ D)
    sd = np.sqrt(np.maximum(np.diag(cov), np.diag(formal)))
    corr = cov / np.sqrt(np.outer(np.diag(cov), np.diag(cov)).clip(1e-300))
    return corr * np.outer(sd, sd)


def adequacy(residual: np.ndarray, t: np.ndarray, period: float, noise: float) -> dict[str, Any]:
    """Does the fitted model explain the record? Plain words from two numbers.

    ``residual_to_noise``: RMS residual over the sensor noise floor (1 = all that is left is
    noise); ``acf_at_period``: the residual's autocorrelation one oscillation period apart (near 0
    for noise, near 1 when the same model error repeats every cycle); ``acf_at_half_period``: the
    same half a period apart, which tells the two kinds of high ``acf_at_period`` apart: an error
    that repeats every cycle changes sign with the oscillation (strongly negative at half a
    period), a drifting rest value or a slow disturbance does not (about as high as at one period).
    """
    r = np.asarray(residual, float) - float(np.mean(residual))
    dt = float(t[-1] - t[0]) / max(t.size - 1, 1)  # the mean step (0 for a single sample: no lags)
    lag = int(round(period / dt)) if dt > 0 and math.isfinite(period) else 0
    half = int(round(0.5 * period / dt)) if dt > 0 and math.isfinite(period) else 0
    denom = float(r @ r)

    def rho(k: int) -> float | None:
        return float(r[:-k] @ r[k:]) / denom if 0 < k < r.size and denom > 0 else None

    acf, acf_half = rho(lag), rho(half)
    ratio = float(np.sqrt(np.mean(r**2))) / noise if noise > 0 else None
    slow = acf is not None and acf >= 0.3 and acf_half is not None and acf_half > acf - 0.5
    times = f"{ratio:.0f}× the noise" if ratio is not None else "no noise floor measured"
    if ratio is not None and ratio <= 2.0 and (acf is None or abs(acf) < 0.3):
        verdict = "adequate: the model explains the record down to the sensor noise"
    elif slow:
        verdict = (
            f"drift: the residual is correlated at every lag, not cycle by cycle (autocorrelation "
            f"{acf:.2f} one period apart and {acf_half:.2f} half a period apart, {times}): "
            "a moving rest value or a slow disturbance; try --detrend linear"
        )
    elif acf is not None and acf >= 0.3:
        verdict = (
            f"model error: the residual repeats every cycle (autocorrelation {acf:.2f} one period apart, "
            f"{times}); the stated (cycle-jackknife) errors allow for it, the formal ones do not; "
            "a richer model (--damping-model cubic, --restoring-terms 3) may fit better"
        )
    else:
        verdict = f"residual above the noise floor ({times}) but not cycle-periodic: drift, a bad trim or disturbance"
    return {"residual_to_noise": ratio, "acf_at_period": acf, "acf_at_half_period": acf_half, "verdict": verdict}


class _DecayEstimator:
    """Common machinery: validation, conversion to reported units, prediction."""

    method = ""
    # learned by the subclasses' _fit: normalised (ω², b, g), its covariance, the initial
    # state (m or rad, m/s or rad/s), the rest value and, for log-decrement, the cycles
    p_: Any
    pcov_: np.ndarray | None
    q0_: float
    v0_: float
    offset_: float
    cycles_: list[dict[str, Any]]

    def __init__(self, rig: Rig):
        self.rig = rig

    # -- to be provided by subclasses: set self.p_ (ω², b, g), self.pcov_ (3×3 or None),
    #    self.q0_, self.v0_, self.offset_
    def _extended_errors(self) -> None:
        """``extended_``: value and standard error of each derived coefficient (B3, C3, C5) by the
        delta method, over the same covariance the three main coefficients report (formal when
        the residual is adequate, cycle jackknife otherwise)."""
        if self._derived_ is None:
            return
        grads, jackknife6, formal6 = self._derived_
        cov6 = formal6 if self.uncertainty_method_ == FORMAL_WHEN_ADEQUATE and formal6 is not None else jackknife6
        self.extended_: dict[str, tuple[float, float]] = {}
        for name, (value, grad) in grads.items():
            gv = np.zeros(6)
            for i, gi in grad.items():
                gv[i] = gi
            self.extended_[name] = (float(value), float(math.sqrt(max(float(gv @ cov6 @ gv), 0.0))))

    def _fit(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> None:
        raise NotImplementedError

    def fit(self, t: Any, y: Any, file: str = "") -> _DecayEstimator:
        """Fit the launch (t in s from the release, y in m or rad). Returns self."""
        t, y = record(t, y, "signal", "m or rad", file)
        self.file_ = file
        self.constants_: RigConstants = rig_constants(self.rig)
        facts = check_record(Launch(t=t, y=y, file=file))
        self.period_ = facts["period"]
        self.noise_ = facts["noise"]
        self.warnings_: list[str] = []
        self.t0_ = float(t[0])
        self.pcov4_: np.ndarray | None = None
        # (value and gradient over the 6 parameters of each derived coefficient, the cycle-
        # jackknife and the formal 6×6 covariance): set by fits with derived coefficients
        self._derived_: tuple[dict[str, tuple[float, dict[int, float]]], np.ndarray, np.ndarray | None] | None = None
        self._fit(t - t[0], y, facts)
        if self.pcov4_ is None and self.pcov_ is not None:
            # (ω², b, g, d): the cubic-damping d is held at zero outside the cubic model
            self.pcov4_ = np.zeros((4, 4))
            self.pcov4_[:3, :3] = self.pcov_
        formal3 = getattr(self, "pcov_formal_", None)
        if getattr(self, "pcov4_formal_", None) is None and formal3 is not None:
            self.pcov4_formal_ = np.zeros((4, 4))
            self.pcov4_formal_[:3, :3] = formal3
        pred = self.predict(t)
        self.adequacy_ = adequacy(y - pred, t, self.period_, self.noise_)
        self.uncertainty_method_ = "formal"
        if formal3 is not None and self.pcov_ is not None:
            self.uncertainty_method_ = UNCERTAINTY_METHOD
            if self.adequacy_["verdict"].startswith("adequate"):
                # the residual is the sensor's white noise: the formal errors are the right ones
                # (tests/identify/test_se_calibration.py); the jackknife, biased up by each
                # cycle's leverage (Efron–Stein), would overstate them with few cycles
                self.pcov_, self.pcov4_ = formal3, self.pcov4_formal_
                self.uncertainty_method_ = FORMAL_WHEN_ADEQUATE
        self._extended_errors()
        w2, b, g = self.p_
        if not (w2 > 0 and math.isfinite(w2)):
            raise InputError(f"fitted ω² = {w2:.4g} 1/s²: not a restoring oscillation; check the rig file", file)
        c = self.constants_
        m_a, K_L, K_Q = c.from_normalised(w2, b, g)
        self.added_mass_ = m_a
        self.linear_damping_ = K_L
        self.quadratic_damping_ = K_Q
        if self.pcov_ is not None:
            Jt = c.jacobian_from_normalised(w2, b, g)
            cov = Jt @ self.pcov_ @ Jt.T
            self.covariance_ = cov
            se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
            self.std_error_: dict[str, float | None] = {k: float(v) for k, v in zip(COEFFICIENTS, se)}
        else:
            self.covariance_ = None
            self.std_error_ = dict.fromkeys(COEFFICIENTS)
        formal = getattr(self, "pcov_formal_", None)
        self.std_error_formal_: dict[str, float | None] = dict(self.std_error_)
        if formal is not None and self.pcov_ is not None:
            Jt = c.jacobian_from_normalised(w2, b, g)
            sef = np.sqrt(np.clip(np.diag(Jt @ formal @ Jt.T), 0.0, None))
            self.std_error_formal_ = {k: float(v) for k, v in zip(COEFFICIENTS, sef)}
        self.natural_frequency_ = math.sqrt(w2)
        a0 = abs(float(y[0]) - self.offset_)
        # equivalent linear damping ratio at the launch amplitude (Fossen-style linearisation
        # of |q̇|q̇ over a cycle: c_eq = 8/(3π) c_Q ω a)
        self.damping_ratio_ = b / (2.0 * math.sqrt(w2)) + 4.0 / (3.0 * math.pi) * g * a0
        self.amplitude_ = a0
        self.rms_residual_ = float(np.sqrt(np.mean((pred - y) ** 2)))

        if _significantly_negative(K_L, self.std_error_["linear_damping"]):
            self.warnings_.append(
                f"negative linear damping fitted (K_L = {K_L:.4g}); K_L and K_Q trade off, compare force curves"
            )
        if _significantly_negative(K_Q, self.std_error_["quadratic_damping"]):
            self.warnings_.append(f"negative quadratic damping fitted (K_Q = {K_Q:.4g})")
        if m_a < 0:
            self.warnings_.append(
                f"negative added mass fitted ({m_a:.4g}); check mass, length or stiffness in the rig file"
            )
        return self

    def _replay(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """(q, q̇) of the fitted model at times t; integrates backwards for t before t0_."""
        tt = np.asarray(t, float) - self.t0_
        w2, b, g = self.p_
        ext = getattr(self, "ext_", None)
        sine = self.constants_.sine
        shape = self.constants_.restoring
        q = np.empty(tt.size)
        v = np.empty(tt.size)
        fwd = tt >= 0
        for mask, sign in ((fwd, 1.0), (~fwd, -1.0)):
            if not np.any(mask):
                continue
            part = tt[mask]
            order = np.argsort(sign * part)
            grid = np.concatenate([[0.0], part[order]])
            if ext is not None:
                qq, vv, _ = simulate_extended(grid, ext, self.q0_, self.v0_, shape, 4)
            else:
                qq, vv, _ = simulate_normalised(grid, w2, b, g, self.q0_, self.v0_, sine, 4, restoring=shape)
            idx = np.nonzero(mask)[0][order]
            q[idx] = qq[1:]
            v[idx] = vv[1:]
        return q, v

    def predict(self, t: Any) -> np.ndarray:
        """Replay the fitted model at times t (s, same clock as the fitted record)."""
        return self._replay(t)[0] + self.offset_

    def velocity(self, t: Any) -> np.ndarray:
        """Fitted rate q̇ at times t (m/s or rad/s)."""
        return self._replay(t)[1]


def _rho(q: np.ndarray, c: RigConstants) -> np.ndarray:
    if c.restoring is not None:
        return c.restoring(q)
    return np.sin(q) if c.sine else q


def _significantly_negative(value: float, std_error: float | None) -> bool:
    """A fitted damping worth a warning: below zero by more than two standard errors (any amount
    below zero when no standard error could be computed)."""
    return value < 0 and (std_error is None or -value > 2.0 * std_error)


def _rho_slope(q: np.ndarray, c: RigConstants) -> np.ndarray:
    if c.restoring is not None:
        return c.restoring.slope(q)
    return np.cos(q) if c.sine else np.ones_like(q)


def _savgol_window(period: float, dt: float) -> int:
    """Odd window spanning about a sixth of a period, at least 7 samples.

    No cap at the record length is needed: a record :func:`check_record` accepts holds at least
    two cycles and its period is measured between crossings inside it, so the window is at most
    (n − 1)/6 + 1 of its n samples, and n ≥ 20 leaves room for the floor of 7 (the callers still
    refuse a window that does not fit, naming it)."""
    w = max(7, int(round(period / dt / 6.0)))
    return w if w % 2 == 1 else w + 1


def restoring_potential(q: Any, c: RigConstants) -> np.ndarray:
    """R(q) = ∫₀^q ρ: the restoring's potential energy per S (q in m or rad, vectorised; ρ odd,
    so R even): ½ q² (linear), 1 − cos q (pendulum), or the trapezoid rule on 201 points of the
    floating rig's shape (polynomial or GZ table)."""
    q = np.asarray(q, float)
    if c.restoring is not None:
        out = np.empty(q.shape)
        for i, a in np.ndenumerate(np.abs(q)):
            x = np.linspace(0.0, float(a), 201)
            f = np.asarray(c.restoring(x), float)
            out[i] = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))
        return out
    return 1.0 - np.cos(q) if c.sine else 0.5 * q * q


#: the equation-error fit reports the energy balance's damping instead of the waveform's when the
#: two differ beyond this p-value (χ² test, see EquationErrorEstimator._check_energy)
ENERGY_CHECK_P = 1e-3


class EquationErrorEstimator(_DecayEstimator):
    """CHIN2012 / ENG2009 equation-error least squares with a smoothing differentiator.

    (ω², b, g) and the rest value come from the least squares of q̈ on [ρ(q), q̇, |q̇|q̇, 1] over
    every sample (the waveform). The damping is then checked against the same equation in energy
    form, integrated against q̇: with the energy per inertia E = ½ q̇² + ω² R(q), R = ∫ρ, at the
    first kept sample and at every extreme k, E_k = E_0 − b ∫₀^{t_k} q̇² dt − g ∫₀^{t_k} |q̇|³ dt,
    least squares in (E_0, b, g). When the two differ beyond chance (χ², p < 0.001, see
    :meth:`_check_energy`), the energy balance's (b, g) are reported with a warning.

    Why: damping is a fraction ζ (≈ 0.005 on a ship in roll) of q̈, and the waveform separates b
    from g by the shape of q̈ within each cycle, where a harmonic of the motion weighs k² times
    its share of the angle. The KVLCC2 roll decays carry a third harmonic of about 0.1 % of the
    amplitude (below their 0.005° quantisation step at small angles), and the waveform alone read
    B_e(5°) 19–21 % above the output-error and log-decrement values at zero speed; harmonics
    k ≥ 2 do no work against q̇ over a half cycle, so the energy form is blind to them (and it
    agrees with output error within 1.5–2 % there). When the model is exact the waveform
    separates b and g better (the energy form sees only the decay of the extremes), so it is kept
    then. ``waveform_damping_`` keeps the waveform's (b, g); ``energy_check_`` the test's χ², dof, p.

    Parameters
    ----------
    rig : Rig
    window : int, optional — Savitzky–Golay window (samples, odd); default about a sixth of
        the oscillation period
    polyorder : int — Savitzky–Golay polynomial order (default 4: a cubic biases q̈ at the peaks by
        about 2 % with a sixth-period window, a quartic by under 0.1 %)
    """

    method = "equation-error"
    _linear = True

    def __init__(self, rig: Rig, window: int | None = None, polyorder: int = 4):
        super().__init__(rig)
        self.window = window
        self.polyorder = polyorder

    def _fit(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> None:
        from scipy.signal import savgol_filter

        dt = float(np.median(np.diff(t)))
        dev = float(np.max(np.abs(np.diff(t) - dt)))
        if dev > 0.05 * dt:
            # uneven sampling: resample onto a uniform grid first
            tu = np.arange(t[0], t[-1], dt)
            y = np.interp(tu, t, y)
            t = tu
            self.warnings_.append(
                f"uneven sampling (intervals off the median {dt * 1e3:.4g} ms by up to {dev / dt:.0%}): "
                f"resampled onto a uniform grid of {tu.size} samples for the derivatives"
            )
        window = self.window or _savgol_window(self.period_, dt)
        if window <= self.polyorder or window >= y.size:
            raise InputError(
                f"window = {window}: expected an odd number of samples between {self.polyorder + 1} and {y.size - 1}"
            )
        self.window_ = window
        offset = facts["offset"]
        q = savgol_filter(y, window, self.polyorder) - offset
        qd = savgol_filter(y, window, self.polyorder, deriv=1, delta=dt)
        qdd = savgol_filter(y, window, self.polyorder, deriv=2, delta=dt)
        edge = window // 2
        sl = slice(edge, y.size - edge)
        q, qd, qdd = q[sl], qd[sl], qdd[sl]
        c = self.constants_
        cols = [-_rho(q, c)]
        if self._linear:
            cols.append(-qd)
        cols.append(-np.abs(qd) * qd)
        # the rest value is fitted too: ρ(q − c) ≈ ρ(q) − c ρ'(q)
        cols.append(_rho_slope(q, c))
        H = np.column_stack(cols)
        coef, *_ = np.linalg.lstsq(H, qdd, rcond=None)
        resid = qdd - H @ coef
        dof = max(1, H.shape[0] - H.shape[1])
        s2 = float(resid @ resid) / dof
        cov_small = (s2 * np.linalg.inv(H.T @ H))[:-1, :-1]
        shift = float(coef[-1]) / float(coef[0]) if coef[0] != 0 else 0.0
        offset += shift
        q = q - shift
        coef = coef[:-1]
        if self._linear:
            self.p_ = (float(coef[0]), float(coef[1]), float(coef[2]))
            wave_cov = cov_small
        else:
            self.p_ = (float(coef[0]), 0.0, float(coef[1]))
            wave_cov = np.zeros((3, 3))
            wave_cov[np.ix_([0, 2], [0, 2])] = cov_small
        self.pcov_ = wave_cov
        self.waveform_damping_ = (self.p_[1], self.p_[2])
        self._check_energy(q, qd, dt, wave_cov)
        self.offset_ = offset
        self.q0_ = float(q[0])
        self.v0_ = float(qd[0])
        # the replay starts at the first sample kept after the filter's edge
        self.t0_ = self.t0_ + float(t[edge])
        self.equation_rms_ = math.sqrt(s2)

    def _energy_damping(
        self, q: np.ndarray, qd: np.ndarray, dt: float, w2: float, var_w2: float
    ) -> tuple[float, float, np.ndarray] | None:
        """(b, g) and the covariance of (ω², b, g) from the energy balance (see the class notes).

        q : rad or m about the fitted rest value; qd : its rate (per s); dt : s; w2 : ω², 1/s²;
        var_w2 : variance of ω² from the waveform fit, 1/s⁴. None (with a warning) when there
        are too few extremes to test anything.

        The covariance sums three parts: the regression's s² (XᵀX)⁻¹ (the energies at the
        extremes as independent readings: the scatter model error leaves), ω²'s variance carried
        by the delta method (E_k moves by R(q_k) per unit ω²), and the sensor noise carried
        through the differentiator into the energies and the integrals (σ² G Gᵀ, see
        :meth:`_noise_gradient`; the noise part of s² is counted twice, which errs on the safe
        side: on 40 noisy spring launches the stated σ of b and g are 1.4× the scatter).
        """
        c = self.constants_
        band = max(4.0 * self.noise_, 0.01 * float(np.max(np.abs(q))))
        idx = np.array([0] + [k for k, _, _ in half_cycle_extremes(np.arange(q.size) * dt, q, band)])
        n_par = 3 if self._linear else 2
        if idx.size < n_par + 2:
            self.warnings_.append(
                f"equation-error: only {idx.size - 1} extremes after the {self.window_}-sample smoothing, "
                f"{n_par + 1} needed to check the damping against the energy balance; not checked"
            )
            return None
        # cumulative ∫q̇² and ∫|q̇|³ (trapezoid) at every sample
        v2, v3 = qd * qd, np.abs(qd) ** 3
        C1 = np.concatenate([[0.0], np.cumsum(0.5 * (v2[1:] + v2[:-1]) * dt)])
        C2 = np.concatenate([[0.0], np.cumsum(0.5 * (v3[1:] + v3[:-1]) * dt)])
        R = restoring_potential(q[idx], c)
        E = 0.5 * v2[idx] + w2 * R
        cols = [np.ones(idx.size)] + ([-C1[idx]] if self._linear else []) + [-C2[idx]]
        X = np.column_stack(cols)
        XtX_inv = np.linalg.inv(X.T @ X)
        theta = XtX_inv @ (X.T @ E)
        resid = E - X @ theta
        s2 = float(resid @ resid) / max(1, idx.size - n_par)
        dtheta_dw2 = XtX_inv @ (X.T @ R)
        G = self._noise_gradient(q, qd, dt, w2, idx, X, E)
        cov_t = s2 * XtX_inv + var_w2 * np.outer(dtheta_dw2, dtheta_dw2) + self.noise_**2 * (G @ G.T)
        # (ω², b, g): b is held at zero (Morison) by leaving its row and column empty
        rows = [1, 2] if self._linear else [2]
        cov = np.zeros((3, 3))
        cov[0, 0] = var_w2
        cov[np.ix_(rows, rows)] = cov_t[1:, 1:]
        cov[0, rows] = cov[rows, 0] = var_w2 * dtheta_dw2[1:]
        b = float(theta[1]) if self._linear else 0.0
        g = float(theta[-1])
        if not (math.isfinite(b) and math.isfinite(g) and np.all(np.isfinite(cov))):
            raise InputError(
                f"equation-error: the energy balance gave b = {b:.4g} 1/s, g = {g:.4g} per unit; "
                "expected finite damping (check the record and the rig file)",
                getattr(self, "file_", ""),
            )
        return b, g, cov

    def _noise_gradient(
        self, q: np.ndarray, qd: np.ndarray, dt: float, w2: float, idx: np.ndarray, X: np.ndarray, E: np.ndarray
    ) -> np.ndarray:
        """∂θ/∂y of the energy fit θ = (XᵀX)⁻¹XᵀE over the recorded samples y: (p, n).

        The sensor noise reaches θ through the energies E_k and through the regressors
        ∫q̇², ∫|q̇|³ (whose noise accumulates along the record, which the regression's s² does
        not see): dθ = (XᵀX)⁻¹ (dXᵀ r + Xᵀ (dE − dX θ)), r the residual. q and q̇ are the
        Savitzky–Golay filter's outputs, linear in y with the filter's coefficients, so each row
        is two convolutions; the covariance adds σ² G Gᵀ (σ the noise floor, white).
        """
        from scipy.signal import savgol_coeffs

        c0 = savgol_coeffs(self.window_, self.polyorder, 0, use="dot")
        c1 = savgol_coeffs(self.window_, self.polyorder, 1, delta=dt, use="dot")
        inv = np.linalg.inv(X.T @ X)
        theta = inv @ (X.T @ E)
        r = E - X @ theta
        # ∂C/∂q̇ per sample of each regressor column after the intercept: C1 = ∫q̇², C2 = ∫|q̇|³
        dC = ([2.0 * qd] if self._linear else []) + [3.0 * np.abs(qd) * qd]

        def weight(mass_k: np.ndarray) -> np.ndarray:
            """Σ_k m_k × (trapezoid weight of sample j in ∫₀^{t_k}): 1 inside, ½ at both ends."""
            inside = idx > 0  # (the first kept sample's integrals are zero)
            mass = np.zeros(q.size)
            np.add.at(mass, idx[inside], mass_k[inside])
            w = np.cumsum(mass[::-1])[::-1] - 0.5 * mass
            w[0] -= 0.5 * float(np.sum(mass_k[inside]))
            return w * dt

        rho = _rho(q[idx], self.constants_)
        w_r = weight(r)
        out = np.empty((X.shape[1], q.size + c0.size - 1))
        for j, row in enumerate(inv @ X.T):
            u0 = np.zeros(q.size)
            u1 = np.zeros(q.size)
            np.add.at(u0, idx, row * w2 * rho)  # ∂E_k/∂q_k
            np.add.at(u1, idx, row * qd[idx])  # ∂E_k/∂q̇_k
            w_row = weight(row)
            for i, d in enumerate(dC, start=1):
                # − dX θ (X's columns are −C) and dXᵀ r
                u1 += (theta[i] * w_row - inv[j, i] * w_r) * d
            out[j] = np.convolve(u0, c0) + np.convolve(u1, c1)
        return out

    def _check_energy(self, q: np.ndarray, qd: np.ndarray, dt: float, wave_cov: np.ndarray) -> None:
        """Keep the waveform's damping unless the energy balance contradicts it (class notes).

        A Hausman-type test: under the model both estimates of (b, g) are consistent and their
        difference d has a covariance at most the sum V of theirs, so χ² = dᵀ V⁻¹ d beyond its
        0.1 % point (2 degrees of freedom; 1 for Morison) says the waveform carries something
        the model does not; then the energy balance's (b, g) and covariance are reported and a
        warning names the gap in B_e at the launch amplitude.
        """
        from scipy.stats import chi2

        w2 = self.p_[0]
        energy = self._energy_damping(q, qd, dt, w2, float(wave_cov[0, 0]))
        if energy is None:
            return
        b, g, cov = energy
        free = [1, 2] if self._linear else [2]
        d = np.array([self.p_[1] - b, self.p_[2] - g])[np.array(free) - 1]
        V = wave_cov[np.ix_(free, free)] + cov[np.ix_(free, free)]
        stat = float(d @ np.linalg.solve(V, d))
        self.energy_check_ = {"chi2": stat, "dof": len(free), "p": float(chi2.sf(stat, len(free)))}
        if self.energy_check_["p"] >= ENERGY_CHECK_P:
            return
        k = 8.0 / (3.0 * math.pi) * math.sqrt(max(w2, 0.0)) * float(np.max(np.abs(q)))
        ref = b + k * g
        wave = self.p_[1] + k * self.p_[2]
        gap = f"{wave / ref - 1:+.0%}" if ref > 0 else f"{wave:.4g} against {ref:.4g} (per inertia, 1/s)"
        self.p_ = (w2, b, g)
        self.pcov_ = cov
        self.warnings_.append(
            f"equation-error: the in-cycle waveform's damping is {gap} off the energy balance at the launch "
            f"amplitude (χ² {stat:.3g} on {len(free)} dof): harmonics of the motion beyond the model; "
            "the energy balance's damping is reported"
        )


class MorisonEstimator(EquationErrorEstimator):
    """CELY2019 Morison variant: equation error with K_L = 0 (dimensionally corrected P1)."""

    method = "morison"
    _linear = False


class LogDecrementEstimator(_DecayEstimator):
    """Period and logarithmic decrement per cycle (CELY2019 graphical method, SPEC S2, S3).

    For each pair of successive peaks of the same sign: damped period T_d, decrement
    δ = ln(a_i/a_{i+1}), ζ = δ/√(4π² + δ²), ω_n = ω_d/√(1 − ζ²) (pendulum: corrected to small
    amplitude by the factor 1 + a²/16). ω_n gives the inertia (S2); the cycle ζ regressed on the
    cycle amplitude a, ζ = ζ_L + (4/(3π)) (c_Q/A) a (S3 generalised), gives linear and quadratic
    damping. ``cycles_`` lists per cycle the amplitude, ζ, peak Reynolds number and C_D with the
    fitted linear part taken as the structural ζ_s.
    """

    method = "log-decrement"

    def __init__(self, rig: Rig, min_amplitude_noise: float = 10.0):
        super().__init__(rig)
        self.min_amplitude_noise = min_amplitude_noise

    def _fit(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> None:
        offset = facts["offset"]
        z = y - offset
        peaks = _peaks(t, z, self.noise_ * self.min_amplitude_noise)
        if len(peaks) >= 3:
            # rest value from alternating extremes: geometric decay gives (p1 − c)(p3 − c) = (p2 − c)²
            cs = []
            for (_, p1), (_, p2), (_, p3) in zip(peaks, peaks[1:], peaks[2:]):
                den = p1 + p3 - 2 * p2
                if den != 0:
                    cs.append((p1 * p3 - p2 * p2) / den)
            if cs:
                shift = float(np.median(cs))
                offset += shift
                z = z - shift
                peaks = [(tp, a - shift) for tp, a in peaks]
        rows = []
        for sign in (1.0, -1.0):
            pk = [(tp, a) for tp, a in peaks if math.copysign(1.0, a) == sign]
            for (t1, a1), (t2, a2) in zip(pk[:-1], pk[1:]):
                a1, a2 = abs(a1), abs(a2)
                if a2 <= 0 or a2 >= a1:
                    continue
                delta = math.log(a1 / a2)
                zeta = delta / math.sqrt(4 * math.pi**2 + delta**2)
                wd = 2 * math.pi / (t2 - t1)
                wn = wd / math.sqrt(1 - zeta**2)
                a_mean = math.sqrt(a1 * a2)
                if self.constants_.sine:
                    wn *= 1.0 + a_mean**2 / 16.0  # large-amplitude pendulum period correction
                elif self.constants_.restoring is not None:
                    wn /= self.constants_.restoring.frequency_ratio(a_mean)  # nonlinear restoring
                rows.append((t1, a_mean, zeta, wn))
        if len(rows) < 2:
            raise InputError(
                "fewer than two cycles with peaks above the noise; expected at least two cycles of free decay"
            )
        rows.sort()
        arr = np.array(rows)
        a, zeta, wn = arr[:, 1], arr[:, 2], arr[:, 3]  # type: ignore[assignment]
        w = float(np.mean(wn))
        w2 = w * w
        H = np.column_stack([np.ones_like(a), a])
        if np.ptp(a) > 0.05 * np.max(a) and len(rows) >= 3:
            coef, *_ = np.linalg.lstsq(H, zeta, rcond=None)
            resid = zeta - H @ coef
            s2 = float(resid @ resid) / max(1, len(rows) - 2)
            cz = s2 * np.linalg.inv(H.T @ H)
        else:  # all cycles alike: no separation possible, all damping linear
            coef = np.array([float(np.mean(zeta)), 0.0])
            cz = np.diag([float(np.var(zeta)) / len(rows), 0.0])
            self.warnings_.append(
                "cycle amplitudes too alike to separate linear and quadratic damping; all taken as linear"
            )
        zl, kappa = float(coef[0]), float(coef[1])
        b = 2.0 * w * zl
        g = 3.0 * math.pi / 4.0 * kappa
        var_w = float(np.var(wn, ddof=1)) / wn.size  # type: ignore[attr-defined]  # (≥ 2 rows, checked above)
        # ω² = w², b = 2 w ζ_L, g = 3π/4 κ
        J = np.array([[2 * w, 0, 0], [2 * zl, 2 * w, 0], [0, 0, 3 * math.pi / 4]])
        cin = np.zeros((3, 3))
        cin[0, 0] = var_w
        cin[1:, 1:] = cz
        self.p_ = (w2, b, g)
        self.pcov_ = J @ cin @ J.T
        self.offset_ = offset
        self.q0_ = float(z[0])
        self.v0_ = 0.0
        c = self.constants_
        A = c.S / w2
        rig = self.rig
        self.cycles_ = []
        negative: list[tuple[int, float, float]] = []  # (cycle number, time s, C_D or K_Q)
        # peak interpolation resolves ζ of a noise-free record to about 1e-6 of itself: a cycle
        # counts as negative only below that floor (a purely linear decay is not flagged)
        floor = 1e-4 * float(np.mean(np.abs(zeta)))
        for k, (t1, am, ze, wni) in enumerate(rows, start=1):
            u = wni * am * c.speed_factor
            cq = (ze - zl) * 3.0 * math.pi * A / (4.0 * am)
            K_Q = cq / c.quadratic_factor
            cd = None if rig.rotational else 2.0 * K_Q / (rig.density * rig.reference_area)
            if ze < zl - floor:
                negative.append((k, t1, K_Q if cd is None else cd))
            self.cycles_.append(
                {
                    "time": t1,
                    "amplitude": am,
                    "damping_ratio": ze,
                    "natural_frequency": wni,
                    "reynolds": u * rig.reference_length / rig.kinematic_viscosity,
                    "drag_coefficient": cd,
                }
            )
        if negative and kappa != 0.0:  # (all-linear fallback: per-cycle C_D is meaningless, warned above)
            # a cycle that decays less than the fitted linear part alone: noise on the peaks or a
            # decrement that does not grow with amplitude; the per-cycle C_D of such cycles is not physical
            name = "K_Q" if rig.rotational else "C_D"
            k, t1, low = min(negative, key=lambda n: n[2])
            self.warnings_.append(
                f"log-decrement: {len(negative)} of {len(rows)} cycles give a negative per-cycle {name} "
                f"(lowest {low:.3g} at cycle {k}, t = {t1:.3g} s); those cycles decay less than the fitted "
                "linear damping alone (peak noise or a decrement not growing with amplitude)"
            )


def _peaks(t: np.ndarray, z: np.ndarray, min_abs: float) -> list[tuple[float, float]]:
    """One extreme per half-cycle (between hysteresis crossings), refined by a parabola."""
    band = max(min_abs, 1e-15)
    out: list[tuple[float, float]] = []
    state = 0
    start = 0
    # a half cycle is closed by the next crossing: the one cut off by the end of the record has no
    # true extreme and is left out
    for i in range(z.size):
        s = 1 if z[i] > band else (-1 if z[i] < -band else 0)
        if s != 0 and s != state:
            if state != 0:
                seg = z[start:i] * state
                k = start + int(np.argmax(seg))
                tp, ap = t[k], z[k]
                if k > 0:  # (k ≤ i − 1 ≤ z.size − 2: a closed half cycle always has a sample after it)
                    # vertex of the parabola through three samples (uniform spacing assumed)
                    y0, y1, y2 = z[k - 1], z[k], z[k + 1]
                    # y1 is the extreme of its half cycle and its neighbours lie inside it or
                    # beyond its crossings, so the vertex is within half a sample: |d| ≤ ½
                    den = y0 - 2 * y1 + y2
                    if den != 0:
                        d = 0.5 * (y0 - y2) / den
                        tp = t[k] + d * (t[k + 1] - t[k - 1]) / 2
                        ap = y1 - 0.25 * (y0 - y2) * d
                out.append((float(tp), float(ap)))
            state, start = s, i
    # the first half-cycle starts at the release: its peak is the release value
    return out


class OutputErrorEstimator(_DecayEstimator):
    """Output-error fit of the simulated rig to the recorded signal (SPEC §1.5).

    Parameters
    ----------
    rig : Rig
    substeps : int — RK4 steps per sample interval in the fit (default 4)
    restarts : int — extra starts tried when the first fit's RMS residual is above twice the
        noise floor (default 3)
    """

    method = "output-error"

    def __init__(
        self,
        rig: Rig,
        substeps: int = 4,
        restarts: int = 3,
        damping_model: str = "quadratic",
        restoring_terms: int = 1,
    ):
        super().__init__(rig)
        self.substeps = substeps
        self.restarts = restarts
        if damping_model not in DAMPING_MODELS:
            raise InputError(f"--damping-model {damping_model!r}: expected one of {', '.join(DAMPING_MODELS)}")
        if restoring_terms not in RESTORING_TERMS:
            raise InputError(f"--restoring-terms {restoring_terms!r}: expected 1, 3 or 5")
        if (damping_model, restoring_terms) != ("quadratic", 1) and rig.test == "pendulum":
            raise InputError(
                "--damping-model and --restoring-terms apply to the spring, torsion and floating rigs, "
                "not to the pendulum (its restoring is sin θ and its damping acts along the path)"
            )
        self.damping_model = damping_model
        self.restoring_terms = restoring_terms

    def _starts(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> list[np.ndarray]:
        starts = []
        for cls in (EquationErrorEstimator, LogDecrementEstimator):
            try:
                est = cls(self.rig)
                est.constants_ = self.constants_
                est.period_, est.noise_, est.warnings_, est.t0_ = self.period_, self.noise_, [], 0.0
                est._fit(t, y, facts)
                w2, b, g = est.p_
                if w2 > 0:
                    starts.append(
                        np.array([w2, max(b, 0.0), max(g, 0.0), y[0] - facts["offset"], 0.0, facts["offset"]])
                    )
            except (InputError, np.linalg.LinAlgError, ValueError):
                continue
        w = 2 * math.pi / facts["period"]
        starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))
        return starts

    def _fit(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> None:
        if (self.damping_model, self.restoring_terms) != ("quadratic", 1):
            self._fit_extended(t, y, facts)
            return
        from scipy.optimize import least_squares

        sine = self.constants_.sine
        shape = self.constants_.restoring
        sub = self.substeps

        def resid(x: np.ndarray) -> np.ndarray:
            q, _, _ = simulate_normalised(t, x[0], x[1], x[2], x[3], x[4], sine, sub, restoring=shape)
            return q + x[5] - y

        def jac(x: np.ndarray) -> np.ndarray:
            _, _, J = simulate_normalised(t, x[0], x[1], x[2], x[3], x[4], sine, sub, True, restoring=shape)
            return np.column_stack([J, np.ones(t.size)])

        noise = max(self.noise_, 1e-12)
        best = None
        starts = self._starts(t, y, facts)
        for x0 in starts[: 1 + self.restarts]:
            with quiet("scipy least_squares", fds=False):
                sol = least_squares(
                    resid, x0, jac=jac, method="lm", x_scale="jac", xtol=1e-12, ftol=1e-12, max_nfev=400
                )
            if best is None or sol.cost < best.cost:
                best = sol
            if math.sqrt(2 * best.cost / t.size) <= 2.0 * noise:  # noise ≥ 1e-12 (set above)
                break
        assert best is not None
        x = best.x
        rms = math.sqrt(2 * best.cost / t.size)
        self._warn_residual(rms, noise, y)
        J = best.jac
        dof = max(1, t.size - x.size)
        s2 = 2 * best.cost / dof
        try:
            cov = s2 * np.linalg.inv(J.T @ J)
            self.pcov_formal_ = cov[:3, :3]
            self.pcov_ = cycle_jackknife(J, best.fun, self._cycles(t), cov)[:3, :3]
        except np.linalg.LinAlgError:
            self.pcov_ = None
            self.warnings_.append("parameter covariance singular: coefficients not separately identifiable")
        self.p_ = (float(x[0]), float(x[1]), float(x[2]))
        self.q0_, self.v0_, self.offset_ = float(x[3]), float(x[4]), float(x[5])
        self.nfev_ = int(best.nfev)

    def _cycles(self, t: np.ndarray) -> np.ndarray:
        """Cycle number of every sample (one oscillation period each, from the release)."""
        return np.floor((t - t[0]) / self.period_).astype(int)

    def _warn_residual(self, rms: float, noise: float, y: np.ndarray) -> None:
        """Warn when the fit leaves much more than the sensor noise (model error, drift, bad trim)."""
        if rms > 3.0 * noise and rms > 1e-9 * max(1.0, float(np.max(np.abs(y)))):
            self.warnings_.append(
                f"RMS residual {rms:.3g} is {rms / noise:.1f}× the sensor noise floor: the rig model does not "
                "explain the record fully (unmodelled dynamics, sensor drift or a bad trim)"
            )

    def _fit_extended(self, t: np.ndarray, y: np.ndarray, facts: dict[str, float]) -> None:
        """Fit with the extended ODE: free (ω², b, [g], [d], [a3], [a5], q0, v0, offset)."""
        from scipy.optimize import least_squares

        shape = self.constants_.restoring
        sub = self.substeps
        # indices into the extended parameter vector (ω², b, g, d, a3, a5) that are fitted
        free = [0, 1]
        if self.damping_model != "linear":
            free.append(2)
        if self.damping_model == "cubic":
            free.append(3)
        if self.restoring_terms >= 3:
            free.append(4)
        if self.restoring_terms == 5:
            free.append(5)
        cols = free + [6, 7]
        k = len(free)

        def full(x: np.ndarray) -> np.ndarray:
            p = np.zeros(6)
            p[free] = x[:k]
            return p

        def resid(x: np.ndarray) -> np.ndarray:
            q, _, _ = simulate_extended(t, full(x), x[k], x[k + 1], shape, sub)
            return q + x[k + 2] - y

        def jac(x: np.ndarray) -> np.ndarray:
            _, _, J = simulate_extended(t, full(x), x[k], x[k + 1], shape, sub, True)
            return np.column_stack([J[:, cols], np.ones(t.size)])

        noise = max(self.noise_, 1e-12)
        best = None
        for x0 in self._starts(t, y, facts)[: 1 + self.restarts]:
            p0 = np.zeros(6)
            p0[:3] = x0[:3]
            start = np.concatenate([p0[free], x0[3:]])
            with quiet("scipy least_squares", fds=False):
                sol = least_squares(
                    resid, start, jac=jac, method="lm", x_scale="jac", xtol=1e-12, ftol=1e-12, max_nfev=600
                )
            if best is None or sol.cost < best.cost:
                best = sol
            if math.sqrt(2 * best.cost / t.size) <= 2.0 * noise:  # noise ≥ 1e-12 (set above)
                break
        assert best is not None
        x = best.x
        rms = math.sqrt(2 * best.cost / t.size)
        self._warn_residual(rms, noise, y)
        p = full(x)
        cov6 = np.zeros((6, 6))
        self._formal6_: np.ndarray | None = None
        try:
            J = best.jac
            cov = 2 * best.cost / max(1, t.size - x.size) * np.linalg.inv(J.T @ J)
            formal6 = np.zeros((6, 6))
            formal6[np.ix_(free, free)] = cov[:k, :k]
            self._formal6_ = formal6
            self.pcov_formal_ = formal6[:3, :3]
            self.pcov4_formal_ = formal6[:4, :4]
            cov = cycle_jackknife(J, best.fun, self._cycles(t), cov)
            cov6[np.ix_(free, free)] = cov[:k, :k]
            self.pcov_ = cov6[:3, :3]
            self.pcov4_ = cov6[:4, :4]
        except np.linalg.LinAlgError:
            cov6[:] = np.nan
            self.pcov_ = None
            self.warnings_.append("parameter covariance singular: coefficients not separately identifiable")
        self.p_ = (float(p[0]), float(p[1]), float(p[2]))
        self.ext_ = p
        self.q0_, self.v0_, self.offset_ = float(x[k]), float(x[k + 1]), float(x[k + 2])
        self.nfev_ = int(best.nfev)
        # reported units: B3 = d A with A = S/ω² (N·s³/m³ or N·m·s³/rad³), C3 = S a3, C5 = S a5
        S = self.constants_.S
        w2, d = p[0], p[3]
        grads = {
            "cubic_damping": (d * S / w2, {0: -d * S / w2**2, 3: S / w2}),
            "C3": (S * p[4], {4: S}),
            "C5": (S * p[5], {5: S}),
        }
        # standard errors by the delta method once fit() has chosen the covariance (formal or
        # cycle jackknife, as for m_a, K_L, K_Q): see _extended_errors
        self._derived_ = (grads, cov6, self._formal6_)


ESTIMATORS: dict[str, type[_DecayEstimator]] = {
    "output-error": OutputErrorEstimator,
    "equation-error": EquationErrorEstimator,
    "morison": MorisonEstimator,
    "log-decrement": LogDecrementEstimator,
}
assert tuple(ESTIMATORS) == METHODS


def make_estimator(method: str, rig: Rig, **settings: Any) -> _DecayEstimator:
    """The estimator for ``method`` (one of :data:`hydrokit.identify.types.METHODS`)."""
    try:
        cls = ESTIMATORS[method]
    except KeyError:
        raise InputError(f"method = {method!r}: expected one of {', '.join(METHODS)}") from None
    if method != "output-error":
        model, terms = settings.pop("damping_model", "quadratic"), settings.pop("restoring_terms", 1)
        if (model, terms) != ("quadratic", 1):
            raise InputError(
                f"--damping-model {model} / --restoring-terms {terms}: expected --method output-error "
                f"(the {method} method fits the quadratic model with the rig's restoring only)"
            )
    return cls(rig, **settings)


def identify_launch(
    rig: Rig,
    launch: Launch,
    method: str = "output-error",
    return_estimator: bool = False,
    **settings: Any,
) -> LaunchResult | tuple[LaunchResult, _DecayEstimator]:
    """Identify one trimmed launch: coefficients, diagnostics and warnings.

    Parameters
    ----------
    rig : Rig
    launch : Launch — trimmed (release at t = 0), t in s, y in m or rad
    method : str — estimator name (default output-error, the most accurate)
    return_estimator : bool — also return the fitted estimator (for plots)

    Returns
    -------
    LaunchResult (and the estimator). K_L, K_Q are net of the rig's tare damping.
    """
    est = make_estimator(method, rig, **settings).fit(launch.t, launch.y, file=launch.file)
    c = est.constants_
    K_L = est.linear_damping_ - rig.tare_linear_damping
    K_Q = est.quadratic_damping_ - rig.tare_quadratic_damping
    warnings = list(est.warnings_)
    if rig.tare_linear_damping or rig.tare_quadratic_damping:
        warnings.append(f"tare subtracted: K_L − {rig.tare_linear_damping:g}, K_Q − {rig.tare_quadratic_damping:g}")
    m_a = est.added_mass_
    t = np.asarray(launch.t, float)
    tf = np.linspace(t[0], t[-1], max(2000, 4 * t.size))
    u_max = float(np.max(np.abs(est.velocity(tf)))) * c.speed_factor
    re = u_max * rig.reference_length / rig.kinematic_viscosity
    kc = u_max * est.period_ / rig.reference_length
    gap = None
    if rig.wall_distance is not None:
        gap = rig.wall_distance / rig.reference_length
        if gap < GAP_RATIO_WARNING:
            warnings.append(
                f"gap ratio e/L = {gap:.2f} < {GAP_RATIO_WARNING:g}: the nearest wall is closer than one body "
                "size; added mass and damping are likely raised by wall proximity"
            )
    if c.sine and est.amplitude_ > math.radians(20):
        warnings.append(
            f"launch angle {math.degrees(est.amplitude_):.1f}° is large; the rod and body rotation matter more"
        )
    rv = rig.density * rig.volume
    result = LaunchResult(
        file=launch.file,
        method=est.method,
        added_mass=m_a,
        added_mass_coefficient=None if rig.rotational else m_a / rv,
        linear_damping=K_L,
        quadratic_damping=K_Q,
        drag_coefficient=None if rig.rotational else 2.0 * K_Q / (rig.density * rig.reference_area),
        natural_frequency=est.natural_frequency_,
        damping_ratio=est.damping_ratio_,
        reynolds_max=re,
        kc=kc,
        rms_residual=est.rms_residual_,
        std_error=dict(est.std_error_),
        warnings=warnings,
        amplitude=est.amplitude_,
        gap_ratio=gap,
        extra={
            "period": est.period_,
            "noise": est.noise_,
            "speed_max": u_max,
            "std_error_formal": dict(est.std_error_formal_),
            "covariance": None if est.covariance_ is None else np.asarray(est.covariance_).tolist(),
            "covariance_parameters": list(COEFFICIENTS),
            "adequacy": est.adequacy_,
            "uncertainty_method": getattr(est, "uncertainty_method_", "formal"),
        },
    )
    ext = getattr(est, "extended_", None)
    if ext is not None:
        # only the output-error estimator fits the extended model (and carries these settings)
        model, terms = est.damping_model, est.restoring_terms  # type: ignore[attr-defined]
        result.extra["damping_model"] = model
        result.extra["restoring_terms"] = terms
        if model == "linear":
            result.std_error["quadratic_damping"] = None  # not fitted (held at zero)
        if model == "cubic":
            result.extra["cubic_damping"] = ext["cubic_damping"][0]
            result.std_error["cubic_damping"] = ext["cubic_damping"][1]
        if terms > 1:
            names = ("C3", "C5") if terms == 5 else ("C3",)
            result.extra["restoring_correction"] = {n: ext[n][0] for n in names}
            result.extra["restoring_correction"]["std_error"] = {n: ext[n][1] for n in names}
    if rig.floating is not None and rig.floating[0] == "gz":
        last = float(rig.floating[1][-1][0])
        if math.degrees(est.amplitude_) > last:
            warnings.append(
                f"launch angle {math.degrees(est.amplitude_):.1f}° is beyond the GZ table's last angle {last:g}°; "
                "the righting arm is extrapolated straight from there"
            )
    if rig.test == "floating":
        # the closed form a naval architect checks: ω0 = √(C1 / (I + I_a)), C1 the linear restoring
        result.extra["restoring_stiffness"] = c.S
        result.extra["total_inertia"] = c.inertia(est.added_mass_)
    if method == "log-decrement":
        result.extra["cycles"] = est.cycles_
    return (result, est) if return_estimator else result


def with_notes(result: LaunchResult, notes: tuple[str, ...] | list[str]) -> LaunchResult:
    """A copy of ``result`` carrying the reader's/trimmer's notes in ``extra['notes']``."""
    extra = dict(result.extra)
    extra["notes"] = list(notes)
    return replace(result, extra=extra)
