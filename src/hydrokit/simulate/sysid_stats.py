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

from collections.abc import Sequence

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
