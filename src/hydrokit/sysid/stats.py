"""Statistics of system identification: the covariance with coloured residuals, whiteness,
correlations and the plain-words identifiability messages (issue #44).

**Coloured residuals.** Least squares on residuals r = J δθ + ε gives δθ̂ = A⁻¹ Jᵀ ε with
A = JᵀJ, so Cov θ̂ = Gᵀ E[εεᵀ] G with G = J A⁻¹. White residuals of unit variance give the
Fisher bound A⁻¹; output-error residuals are coloured (unmodelled dynamics, disturbances), and
then A⁻¹ is too small. Here E[εεᵀ] is estimated within each residual series (one channel of
one run; series are independent) by its autocovariance R(k), Bartlett-tapered up to a lag L
three times the first insignificant lag (Morelli & Klein 1997, J. Aircraft 34(5), "Accounting
for coloured residuals"; Newey & West 1987). The Toeplitz product is a convolution (FFT), so
the cost is that of a few passes over G.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np


def autocorrelation(x: np.ndarray, lags: int) -> np.ndarray:
    """Biased autocovariance R(0..lags) of ``x`` (mean removed) via FFT."""
    x = np.asarray(x, float) - np.mean(x)
    n = x.size
    size = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(x, size)
    r = np.fft.irfft(f * np.conj(f), size)[: lags + 1] / n
    return r


def _lag(r: np.ndarray, n: int) -> int:
    """First lag whose autocorrelation is insignificant (|ρ| < 2/√n)."""
    rho = r / r[0] if r[0] > 0 else np.zeros_like(r)
    small = np.nonzero(np.abs(rho[1:]) < 2.0 / np.sqrt(n))[0]
    return int(small[0] + 1) if small.size else int(r.size - 1)


def sandwich(A: np.ndarray, r: np.ndarray, blocks: Sequence[tuple[int, int]], first: int | None = None) -> np.ndarray:
    """Cov θ̂ = Gᵀ R G (module docstring) for weighted Jacobian ``A`` (N, p) and residuals ``r``.

    ``blocks`` are the (start, stop) index ranges of the independent residual series; only the
    ``first`` parameters' covariance is returned (the others, e.g. initial states, are
    nuisance parameters: their uncertainty is accounted for, their covariance not kept).
    """
    from scipy.signal import fftconvolve

    info = A.T @ A
    inv = np.linalg.pinv(info)
    p = A.shape[1] if first is None else first
    G = A @ inv[:, :p]
    cov = np.zeros((p, p))
    for a, b in blocks:
        n = b - a
        if n < 2:
            continue
        r_b = r[a:b]
        full = autocorrelation(r_b, min(n - 1, max(1, n // 4)))
        L = min(3 * _lag(full, n), full.size - 1)
        w = 1.0 - np.arange(L + 1) / (L + 1)
        h = full[: L + 1] * w
        kernel = np.concatenate([h[:0:-1], h])  # lags −L … L
        g = G[a:b]
        H = fftconvolve(g, kernel[:, None], mode="same", axes=0) if L > 0 else g * h[0]
        cov += g.T @ H
    return 0.5 * (cov + cov.T)


def whiteness(x: np.ndarray, lags: int = 20) -> dict[str, float]:
    """Lag-1 autocorrelation of ``x`` and the fraction of lags 1..``lags`` outside ±1.96/√n
    (about 0.05 for white noise)."""
    n = x.size
    if n < lags + 2:
        return {"lag1": float("nan"), "outside": float("nan")}
    r = autocorrelation(x, lags)
    rho = r[1:] / r[0] if r[0] > 0 else np.zeros(lags)
    return {"lag1": float(rho[0]), "outside": float(np.mean(np.abs(rho) > 1.96 / np.sqrt(n)))}


def correlation(cov: np.ndarray) -> np.ndarray:
    """Correlation matrix of a covariance (0 where a σ is 0)."""
    s = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = cov / np.outer(s, s)
    c = np.where(np.isfinite(c), c, 0.0)
    np.fill_diagonal(c, 1.0)
    return np.clip(c, -1.0, 1.0)


def condition_number(info: np.ndarray) -> float:
    """Condition number of the Fisher information scaled to unit diagonal (unit-free)."""
    d = np.sqrt(np.clip(np.diag(info), 1e-300, None))
    s = info / np.outer(d, d)
    ev = np.linalg.eigvalsh(0.5 * (s + s.T))
    return float(ev[-1] / ev[0]) if ev[0] > 0 else float("inf")


# ------------------------------------------------------------------------------ the verdict
#: held-out NRMSE above which a moving channel is said not predicted (RMS error above half the
#: channel's own spread: the prediction is closer to a flat line than to the measurement)
NRMSE_LIMIT = 0.5
#: a channel moves when its standard deviation exceeds this many sensor-noise σ (below, its
#: NRMSE is mostly noise: σ/std ≥ 1/3)
MOVING = 3.0
#: residual RMS above this many sensor-noise σ …
EXCESS = 2.0
#: … with a lag-1 autocorrelation above this (slow, structured: not noise) …
COLOURED = 0.8
#: … and a systematic part √(RMS² − σ²) above this fraction of the channel's standard
#: deviation is an error of the model, not of the sensors
SYSTEMATIC = 0.1
#: a channel whose sensor noise (the smoother's residual) is below this fraction of its standard
#: deviation is smoother than a sensor: pre-filtered or derived in the log (a real gyro, DVL or
#: compass has 1e-3–1e-2 of the motion), so its ratio to that noise says little; the reasons say so
PREFILTERED = 1e-4
#: what to check when the model does not describe the runs: the base vehicle, where heave, roll or
#: pitch is modelled and spoiled (a buoyancy, centre or inertia error shows there first)
ADVICE = (
    "the model does not describe these runs — check the base vehicle (mass, inertia, centres of gravity and "
    "buoyancy) and which coefficients are free"
)
#: … a speed channel: what sets the speed at given revolutions
ADVICE_SPEED = (
    "the speed is not modelled — check the surge resistance (X_u|u|, quadratic_damping.surge), the propeller "
    "curve K_T(J), the wake fraction and the thrust deduction (free them, or measure them)"
)
#: … sway and yaw: the hull's manoeuvring terms and the rudder
ADVICE_TURN = (
    "the sway and yaw are not modelled — check the hull's sway and yaw terms (Y_uv, Y_ur, N_uv, N_ur and their "
    "modulus terms), the rudder's force and its neutral angle"
)
#: … only the track: it integrates the speed and the heading
ADVICE_TRACK = "the track drifts — it integrates the speed and heading: check the surge, sway and yaw terms"
#: the channels whose error each piece of advice answers (positions last: they integrate the others)
ADVICE_OF = {
    "u": ADVICE_SPEED,
    "v": ADVICE_TURN,
    "r": ADVICE_TURN,
    "psi": ADVICE_TURN,
    "w": ADVICE,
    "p": ADVICE,
    "q": ADVICE,
    "phi": ADVICE,
    "theta": ADVICE,
    "z": ADVICE,
}
_SYMBOL = {"phi": "φ", "theta": "θ", "psi": "ψ"}


def symbol(channel: str) -> str:
    """The printed symbol of a channel (φ θ ψ for the Euler angles)."""
    return _SYMBOL.get(channel, channel)


def channel_checks(measured: np.ndarray, residual: np.ndarray, noise: float) -> dict[str, float]:
    """What the verdict reads of one channel of one run.

    Parameters
    ----------
    measured : (n,) — the measured samples, SI
    residual : (n,) — measured − simulated, SI
    noise : float — the sensor's noise σ from the smoother (independent of the model), SI

    Returns
    -------
    dict — ``nrmse`` = RMS(residual)/std(measured) (NaN for a channel that does not vary),
    ``noise_sigma`` (SI), ``noise_ratio`` = RMS(residual)/σ, ``systematic`` = √(RMS² − σ²)/std
    (the part of the residual the sensor noise does not explain, relative to the motion),
    ``moving`` (std > :data:`MOVING` σ)
    """
    rms = float(np.sqrt(np.mean(residual**2)))
    sd = float(np.std(measured))
    sigma = float(noise) if np.isfinite(noise) and noise > 0 else 0.0
    excess = math.sqrt(max(rms * rms - sigma * sigma, 0.0))
    return {
        "nrmse": rms / sd if sd > 0 else float("nan"),
        "noise_sigma": sigma,
        "noise_ratio": rms / sigma if sigma > 0 else float("inf"),
        "systematic": excess / sd if sd > 0 else float("nan"),
        "moving": bool(sd > MOVING * sigma),
    }


def _fails(entry: dict[str, Any], holdout: bool) -> tuple[bool, bool]:
    """(held-out NRMSE fails, systematic residual fails) of one channel entry of a run row."""
    nrmse = entry.get("nrmse", float("nan"))
    bad_nrmse = holdout and bool(entry.get("moving")) and nrmse > NRMSE_LIMIT
    lag1 = entry["whiteness"]["lag1"]
    bad_resid = bool(
        entry.get("noise_ratio", 0.0) > EXCESS and lag1 > COLOURED and entry.get("systematic", 0.0) > SYSTEMATIC
    )
    return bad_nrmse, bad_resid


def _list(values: Sequence[str]) -> str:
    return ", ".join(values)


def _lag1(entry: dict[str, Any]) -> str:
    return f"{entry['whiteness']['lag1']:.2f}"


def _noise_share(entry: dict[str, Any]) -> float:
    """The sensor noise σ over the channel's standard deviation (NRMSE / noise ratio), –."""
    ratio, nrmse = entry.get("noise_ratio", float("nan")), entry.get("nrmse", float("nan"))
    return nrmse / ratio if ratio > 0 and np.isfinite(ratio) and np.isfinite(nrmse) else float("inf")


def _percent(entry: dict[str, Any]) -> str:
    return f"{100 * entry['systematic']:.0f} %"


#: a window row's name: RUN@START s (:func:`hydrokit.sysid.window` names them so)
_WINDOW = re.compile(r"(.+)@[-+0-9.eE]+s")


def _run_name(name: str) -> str:
    """The run a window row belongs to (``RUN@12.5s`` → ``RUN``; a whole run's row is its own)."""
    m = _WINDOW.fullmatch(name)
    return m.group(1) if m else name


def _advice(channels: Sequence[str]) -> str:
    """The advice for the failing ``channels`` (worst first): that of the worst channel that has
    one (a velocity or attitude), else the track's."""
    for c in channels:
        if c in ADVICE_OF:
            return ADVICE_OF[c]
    return ADVICE_TRACK


def verdict(runs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Does the identified model describe the runs? ``{"fits": bool, "reasons": [sentences],
    "details": [sentences]}``.

    ``runs`` are the result's run rows (name, holdout, channels → residual_rms, whiteness,
    :func:`channel_checks`; a window's row is named ``RUN@START s``). A channel fails when

    - held out, moving, and its NRMSE exceeds :data:`NRMSE_LIMIT` (not predicted), or
    - its residual exceeds :data:`EXCESS` × the sensor noise, is coloured (lag-1 ρ above
      :data:`COLOURED`) and its systematic part exceeds :data:`SYSTEMATIC` of the channel's
      spread — a structured error the sensors cannot make (coloured residuals alone are
      expected at 50 Hz: a tiny systematic error is coloured, and so is a disturbance).

    A correct model leaves residuals at the sensor noise (ratio ≈ 1, lag-1 ρ ≈ 0); a wrong base
    vehicle leaves several times the noise, coloured (ratio 2–150, lag-1 ρ 0.8–1.0).
    ``reasons`` is what a user reads (issue #56 item 6): the one verdict first, then at most one
    line per run (its windows taken together): its worst channels with their systematic share,
    the held-out NRMSE, and advice that fits the channel — a speed channel points at the
    resistance, the propeller curve, wake and thrust deduction; sway and yaw at the hull's
    manoeuvring terms and the rudder; only heave, roll and pitch (which only a vehicle that
    models them has) at the base vehicle's mass, inertia and centres. ``details`` keeps one
    sentence per failing row (window), for sysid.json.
    """
    details: list[str] = []
    worst_nrmse: tuple[float, str] = (0.0, "")
    worst_ratio: tuple[float, str] = (0.0, "")
    # per run: rows, failing rows, the worst systematic share and the worst held-out NRMSE per channel
    per_run: dict[str, dict[str, Any]] = {}
    for row in runs:
        hold = bool(row["holdout"])
        run = per_run.setdefault(
            _run_name(str(row["name"])), {"rows": 0, "bad": 0, "hold": hold, "sys": {}, "nrmse": {}, "smooth": {}}
        )
        run["rows"] += 1
        bad_n, bad_r = [], []
        for c, e in row["channels"].items():
            fn, fr = _fails(e, hold)
            if fn:
                bad_n.append((e["nrmse"], c, e))
            if hold and e.get("moving") and np.isfinite(e.get("nrmse", np.nan)):
                run["nrmse"][c] = max(run["nrmse"].get(c, 0.0), float(e["nrmse"]))
            if fr:
                bad_r.append((e["noise_ratio"], c, e))
                run["sys"][c] = max(run["sys"].get(c, 0.0), float(e["systematic"]))
                if _noise_share(e) < PREFILTERED:
                    run["smooth"][c] = _noise_share(e)
            if hold and e.get("moving") and np.isfinite(e.get("nrmse", np.nan)) and e["nrmse"] > worst_nrmse[0]:
                worst_nrmse = (float(e["nrmse"]), c)
            if np.isfinite(e.get("noise_ratio", np.nan)) and e["noise_ratio"] > worst_ratio[0]:
                worst_ratio = (float(e["noise_ratio"]), c)
        if not (bad_n or bad_r):
            continue
        run["bad"] += 1
        parts = []
        if bad_n:
            top = sorted(bad_n, key=lambda x: -x[0])[:3]
            parts.append(
                f"held-out NRMSE of {_list([f'{symbol(c)} {v:.2f}' for v, c, _ in top])} > {NRMSE_LIMIT:g}"
                + f" and residuals lag-1 ρ {_list([_lag1(e) for *_, e in top])}"
            )
        if bad_r:
            top = sorted(bad_r, key=lambda x: -x[0])[:3]
            parts.append(
                f"residuals of {_list([symbol(c) for _, c, _ in top])} at "
                f"{_list([f'{v:.3g}' for v, _, _ in top])} × the sensor noise with lag-1 ρ "
                f"{_list([_lag1(e) for *_, e in top])} (a systematic error of "
                f"{_list([_percent(e) for *_, e in top])} of the motion)"
            )
            smooth = [(c, e) for _, c, e in top if _noise_share(e) < PREFILTERED]
            if smooth:
                names = _list([symbol(c) for c, _ in smooth])
                shares = _list([f"{_noise_share(e):.1g}" for _, e in smooth])
                one = len(smooth) == 1
                parts[-1] += (
                    f" — {names} {'is' if one else 'are'} smoother than a sensor (noise {shares} of "
                    f"{'its' if one else 'their'} motion: pre-filtered in the log?), so a ratio to that noise "
                    "says little; the systematic error does"
                )
        use = "held out" if hold else "fitted"
        worst = [c for c, _ in sorted(_order(bad_r, bad_n).items(), key=lambda x: -x[1])]
        details.append(f"{row['name']} ({use}): {'; '.join(parts)}: {_advice(worst)}.")
    fits = not details
    if fits:
        held = [r for r in runs if r["holdout"]]
        said = (
            f"every moving channel of the held-out run(s) predicted with NRMSE ≤ {NRMSE_LIMIT:g} "
            f"(largest {symbol(worst_nrmse[1])} {worst_nrmse[0]:.2f})"
            if held and worst_nrmse[1]
            else "no held-out run (give --holdout to test the prediction): judged on the fitted runs"
        )
        reasons = [
            f"The model describes these runs: {said}; no residual is a systematic error above the sensor noise "
            f"(largest RMS {worst_ratio[0]:.2g} × the noise, in {symbol(worst_ratio[1]) or '–'})."
        ]
        return {"fits": True, "reasons": reasons, "details": []}
    failing = {name: r for name, r in per_run.items() if r["bad"]}
    reasons = [
        f"The model does not describe these runs: {len(failing)} of {len(per_run)} run(s) show errors the sensors "
        "cannot make (below, one line per run; sysid.json's verdict.details has every window). The stated σ hold "
        "only for a model that describes the runs: here they understate the error."
    ]
    for name, r in failing.items():
        reasons.append(_run_line(name, r))
    return {"fits": False, "reasons": reasons, "details": details}


def _order(
    bad_r: Sequence[tuple[float, str, dict[str, Any]]], bad_n: Sequence[tuple[float, str, dict[str, Any]]]
) -> dict[str, float]:
    """The failing channels of a row and how bad each is (systematic share, else NRMSE), –."""
    out = {c: float(e["systematic"]) for _, c, e in bad_r}
    for v, c, _ in bad_n:
        out.setdefault(c, float(v))
    return out


def _run_line(name: str, r: dict[str, Any]) -> str:
    """One line for a failing run: its windows, worst channels, held-out NRMSE and advice."""
    use = "held out" if r["hold"] else "fitted"
    windows = f", {r['bad']} of {r['rows']} windows" if r["rows"] > 1 else ""
    parts = []
    sys_top = sorted(r["sys"].items(), key=lambda x: -x[1])[:3]
    if sys_top:
        parts.append(
            "systematic error of " + _list([f"{symbol(c)} {100 * v:.0f} %" for c, v in sys_top]) + " of the motion"
        )
    n_top = sorted(r["nrmse"].items(), key=lambda x: -x[1])[:3]
    if n_top:
        parts.append("held-out NRMSE " + _list([f"{symbol(c)} {v:.2f}" for c, v in n_top]))
    if r["smooth"]:
        names = _list([symbol(c) for c in r["smooth"]])
        parts.append(f"{names} smoother than a sensor (pre-filtered in the log?): read the systematic share")
    order = [c for c, _ in sys_top] + [c for c, v in n_top if c not in r["sys"] and v > NRMSE_LIMIT]
    return f"{name} ({use}{windows}): {'; '.join(parts)} — {_advice(order)}."
