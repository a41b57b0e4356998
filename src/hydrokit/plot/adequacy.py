"""The model-adequacy figure of one launch (issue #16): does the fitted model explain the record?

Two panels make the ``adequacy`` verdict of :func:`hydrokit.identify.estimators.adequacy`
visible. Top: the residual's autocorrelation ρ(k) against the lag in oscillation periods, with
the white-noise band ±1.96/√N, the verdict's threshold |ρ| = 0.3 and the value one period apart
marked (near 0 for noise; near 1 when the same model error repeats every cycle). Bottom: the
residual against time with ±1 and ±2 noise floors (σ of the sensor noise) and ±RMS residual.

The autocorrelation is computed here a second way (FFT of the zero-padded, mean-free residual),
so the marked value at one period checks the number in the JSON rather than repeating it.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.plot._mpl import new_figure

#: |ρ(one period)| at or above which the verdict calls the residual cycle-periodic (the
#: threshold of :func:`hydrokit.identify.estimators.adequacy`)
ACF_THRESHOLD = 0.3
#: RMS residual / noise floor at or below which the residual counts as noise (same source)
NOISE_RATIO_THRESHOLD = 2.0


def residual_acf(residual: Any, max_lag: int) -> np.ndarray:
    """Autocorrelation of a residual at lags 0 … ``max_lag`` samples (ρ(0) = 1).

    ρ(k) = Σ_i r_i r_{i+k} / Σ_i r_i² of the mean-free residual r (the biased estimator, as
    in the ``adequacy`` numbers), computed by FFT of r padded to at least twice its length so
    that the circular correlation equals the linear one.

    Parameters
    ----------
    residual : (n,) array — measured minus fitted signal, m or rad (any unit: ρ has none)
    max_lag : int — largest lag, samples (clipped to n − 1)

    Returns
    -------
    (max_lag + 1,) array — ρ(k), dimensionless; all NaN after ρ(0) when the residual is constant
    """
    r = np.asarray(residual, float)
    r = r - float(np.mean(r))
    n = r.size
    max_lag = max(0, min(int(max_lag), n - 1))
    size = 1 << int(2 * n - 1).bit_length()
    spec = np.fft.rfft(r, size)
    acov = np.fft.irfft(spec * np.conj(spec), size)[: max_lag + 1]
    if acov[0] <= 0:
        out = np.full(max_lag + 1, np.nan)
        out[0] = 1.0
        return out
    return np.asarray(acov / acov[0], dtype=float)


def period_lag(t: Any, period: float) -> int:
    """One oscillation period as a whole number of samples (the lag the ``adequacy`` number uses).

    Parameters
    ----------
    t : (n,) array — sample times, s
    period : float — oscillation period, s
    """
    t = np.asarray(t, float)
    dt = float(np.mean(np.diff(t))) if t.size > 1 else 1.0
    if not (dt > 0 and math.isfinite(period)):
        return 0
    return int(round(period / dt))


def adequacy_figure(
    t: Any,
    residual: Any,
    period: float,
    noise: float,
    unit: str = "rad",
    verdict: str = "",
    title: str = "",
    periods: float = 3.0,
    fig: Any = None,
) -> Any:
    """Residual autocorrelation against lag and residual against time, with the noise floor.

    Parameters
    ----------
    t : (n,) array — sample times, s
    residual : (n,) array — measured minus fitted signal, m or rad (``unit``)
    period : float — oscillation period, s (the lag axis is in periods)
    noise : float — sensor noise floor (standard deviation), m or rad
    unit : str — "m" (shown in mm) or "rad" (shown in degrees)
    verdict : str — the launch's plain-words verdict, printed under the title
    title : str — figure title
    periods : float — lags shown, in periods (default 3: a repeating error peaks at 1, 2, 3)
    fig : matplotlib Figure or SubFigure, optional — drawn into (two axes added); default a new one

    Returns
    -------
    The figure. ``fig.axes[0]`` is the autocorrelation panel; its line labelled "one period"
    holds the single point (lag in periods, ρ) the verdict reads.
    """
    t = np.asarray(t, float)
    r = np.asarray(residual, float)
    if t.shape != r.shape or t.ndim != 1 or t.size < 2:
        raise ValueError(f"t and residual must be 1-D of equal length ≥ 2, got {t.shape} and {r.shape}")
    scale, label = (1e3, "residual (mm)") if unit == "m" else (180 / math.pi, "residual (°)")
    fig = fig if fig is not None else new_figure((9, 5.2))
    a1, a2 = fig.subplots(2, 1, gridspec_kw={"height_ratios": [1.25, 1]})
    lag = period_lag(t, period)
    dt = float(np.mean(np.diff(t)))
    n = r.size
    if lag > 0:
        max_lag = min(n - 1, int(math.ceil(periods * lag)))
        acf = residual_acf(r, max_lag)
        x = np.arange(acf.size) * dt / period
        band = 1.96 / math.sqrt(n)
        a1.fill_between(
            [0, x[-1]], -band, band, color="C2", alpha=0.25, lw=0, label=f"white noise ±1.96/√N ({band:.2g})"
        )
        a1.plot(x, acf, "-", lw=1.0, color="C0", label="residual autocorrelation ρ")
        for s in (1, -1):
            a1.axhline(
                s * ACF_THRESHOLD, color="C3", lw=0.8, ls=":", label="verdict threshold |ρ| = 0.3" if s > 0 else None
            )
        if lag < acf.size:
            value = float(acf[lag])
            a1.axvline(lag * dt / period, color="0.4", lw=0.8, ls="--")
            a1.plot([lag * dt / period], [value], "o", ms=7, color="C3", label="one period")
            a1.annotate(
                f"ρ(one period) = {value:.2f}",
                (lag * dt / period, value),
                (8, 6),
                textcoords="offset points",
                fontsize=8,
            )
        a1.set_xlim(0, x[-1])
    else:
        a1.text(0.5, 0.5, "no oscillation period: autocorrelation not computed", ha="center", transform=a1.transAxes)
    a1.set_ylim(-1.05, 1.05)
    a1.axhline(0, color="0.5", lw=0.5)
    a1.set_xlabel("lag (oscillation periods)")
    a1.set_ylabel("autocorrelation ρ (–)")
    a1.grid(alpha=0.3)
    a1.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    a2.plot(t, r * scale, "-", lw=0.6, color="C3", label="residual (measured − fitted)")
    if noise > 0:
        a2.axhspan(-noise * scale, noise * scale, color="C2", alpha=0.3, lw=0, label="±1 noise floor σ")
        a2.axhspan(
            -NOISE_RATIO_THRESHOLD * noise * scale,
            NOISE_RATIO_THRESHOLD * noise * scale,
            color="C2",
            alpha=0.12,
            lw=0,
            label="±2 σ (adequate if RMS inside)",
        )
    rms = float(np.sqrt(np.mean((r - np.mean(r)) ** 2)))
    ratio = f", {rms / noise:.1f}× the noise" if noise > 0 else ""
    for s in (1, -1):
        a2.axhline(s * rms * scale, color="0.2", lw=0.8, ls="--", label=f"±RMS residual{ratio}" if s > 0 else None)
    a2.set_xlabel("time after release (s)")
    a2.set_ylabel(label)
    a2.grid(alpha=0.3)
    a2.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    heading = "\n".join(x for x in (title, textwrap.fill(verdict, 110)) if x)
    if heading:
        a1.set_title(heading, fontsize=8, loc="left")
    if hasattr(fig, "tight_layout"):
        fig.tight_layout()
    return fig


def adequacy_png_name(file: str) -> str:
    """File name of a launch's adequacy figure in ``--plots`` (``<launch stem>_adequacy.png``)."""
    return f"{Path(file).stem}_adequacy.png"


def launch_adequacy(item: Any, unit: str, title: str = "", fig: Any = None) -> Any:
    """The adequacy figure of one identified launch (an ``IdentifiedLaunch``).

    The residual is recomputed as the record minus the fitted signal at the launch's own
    samples (:func:`hydrokit.identify.fitted.predict`), which is the residual the ``adequacy``
    numbers were computed from; period (s) and noise floor (m or rad) come from the result.
    """
    from hydrokit.identify.fitted import predict

    t = np.asarray(item.launch.t, float)
    residual = np.asarray(item.launch.y, float) - predict(item)
    extra = item.result.extra
    verdict = (extra.get("adequacy") or {}).get("verdict", "")
    return adequacy_figure(t, residual, float(extra["period"]), float(extra["noise"]), unit, verdict, title, fig=fig)


def adequacy_figures(campaign: Any, per_launch: bool = True) -> dict[str, tuple[bytes, str]]:
    """PNG adequacy figures of a CampaignResult: ``<launch stem>_adequacy.png`` → (png, caption).

    Every launch when ``per_launch``; otherwise those whose verdict is not "adequate" and at
    most four in all (a report of a large campaign stays small), in launch order.
    """
    from hydrokit.plot._mpl import to_png

    unit = "m" if campaign.rig.translational_signal else "rad"
    items = list(campaign.launches)
    if not per_launch:
        flagged = [
            i
            for i, it in enumerate(items)
            if not str((it.result.extra.get("adequacy") or {}).get("verdict", "")).startswith("adequate")
        ]
        spread = list(range(0, len(items), max(1, len(items) // 4)))
        keep = sorted(list(dict.fromkeys(flagged + spread))[:4])
        items = [items[i] for i in keep]
    out: dict[str, tuple[bytes, str]] = {}
    for it in items:
        stem = Path(it.result.file).stem
        fig = launch_adequacy(it, unit, f"{stem}: model adequacy ({campaign.method})")
        out[adequacy_png_name(it.result.file)] = (
            to_png(fig),
            f"{stem}: residual autocorrelation against lag (one period marked, white-noise band) "
            "and residual against time with the noise floor",
        )
    return out
