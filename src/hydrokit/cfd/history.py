"""Force histories: reading OpenFOAM's ``forces`` output and judging convergence on it.

A steady solver's residuals say little about the quantity wanted (a wedge case's out-of-plane
residual never falls; a bluff body's wake keeps shedding). hydrokit judges the **force and
moment history** instead:

* **converged** — at least ``min_iterations`` done and, over the last ``window`` iterations,
  every one of the six components stays within ``tolerance`` of the load scale (|F| for forces,
  |F|·L for moments; a relative test, not an absolute one) — and so do the force's pressure and
  viscous parts, each against the same |F|: on a streamlined body the friction can still climb
  while the pressure drag falls, and their sum then looks settled long before either is (the
  Myring wedge at Re_L 1e7, finest grid: the total's window spanned 0.03 N while the friction
  still rose 0.04 N per 100 iterations and the pressure fell). The value is the window's mean and
  its iterative uncertainty U_I = ½ (max − min) over the window (ITTC 7.5-03-01-01's estimate
  from the last oscillation) — or, where the history still creeps one way, the change still to
  come, whichever is larger: the means of the last three windows that step the same way by
  significant, shrinking amounts (ratio r) are extrapolated geometrically, Δ r / (1 − r) with r
  capped at 0.95. A slow monotone approach passes the window test long before it has arrived (a
  wedge case at Re_L 1e7 was still 0.15 N from its end when its window spanned 0.03 N).
* **averaged** — the run ended (iteration limit) without settling, but the last half of the
  history is stationary: a straight line through it changes by less than the tolerance or
  than 3 σ of that change (the residuals' autocorrelation counted), the parts' lines too. The value is the mean
  of that half; its σ is the standard error of a correlated series, s √(τ/n) with τ the
  integrated autocorrelation time (Sokal's self-consistent window, c = 5), so a slowly
  oscillating force is not credited with n independent samples.
* **not converged** — neither: the mean of the last half is reported with σ no smaller than half
  the trend across it, and the case is marked so.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf", re.IGNORECASE)


def read_dat(path: Path) -> np.ndarray:
    """Rows of numbers from an OpenFOAM function-object ``.dat`` file (parentheses ignored).

    Returns (n, m): the time (iteration) and the first m − 1 values of each complete line; an
    incomplete last line (a file still being written) is dropped.
    """
    try:
        text = path.read_text(errors="replace")
    except FileNotFoundError:
        return np.zeros((0, 0))
    rows = []
    for line in text.splitlines():
        if not line or line.startswith("#"):
            continue
        rows.append([float(x) for x in _NUMBER.findall(line)])
    if not rows:
        return np.zeros((0, 0))
    width = max(len(r) for r in rows[:-1]) if len(rows) > 1 else len(rows[0])
    rows = [r for r in rows if len(r) == width]
    return np.array(rows, dtype=float)


def _force_rows(post: Path) -> tuple[np.ndarray, np.ndarray]:
    """The newest start-time folder's ``force.dat`` and ``moment.dat`` rows, cut to the rows
    present in both (empty arrays when either is missing or has fewer than 4 columns)."""
    folders = sorted((p for p in post.glob("*") if p.is_dir()), key=lambda p: _time(p.name))
    if not folders:
        return np.zeros((0, 0)), np.zeros((0, 0))
    f = read_dat(folders[-1] / "force.dat")
    m = read_dat(folders[-1] / "moment.dat")
    n = min(len(f), len(m))
    if n == 0 or f.shape[1] < 4 or m.shape[1] < 4:
        return np.zeros((0, 0)), np.zeros((0, 0))
    return f[:n], m[:n]


def read_forces(post: Path) -> tuple[np.ndarray, np.ndarray]:
    """Iterations (n,) and total force and moment (n, 6), N and N·m, from ``postProcessing/forces``.

    Reads the newest start-time folder's ``force.dat`` and ``moment.dat`` (OpenFOAM v1912 layout:
    time, (total), (pressure), (viscous)); rows present in both files only.
    """
    it, loads, _, _ = read_all(post)
    return it, loads


def read_force_parts(post: Path) -> tuple[np.ndarray, np.ndarray]:
    """Pressure and viscous force (n, 3) each, N, from ``postProcessing/forces``, on the rows
    :func:`read_forces` returns (their sum is its total force).

    Friction and pressure drag move differently with the mesh (a wall function's friction with
    the first cell, pressure drag with the surface's facets), so a grid study reads them apart.
    """
    return read_all(post)[2:]


def read_all(post: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`read_forces` and :func:`read_force_parts` from one reading of the files, so that a
    file still being written gives all four on the same rows: iterations (n,), loads (n, 6),
    pressure and viscous force (n, 3) each (parts (0, 3) when OpenFOAM wrote none)."""
    f, m = _force_rows(post)
    if len(f) == 0:
        return np.zeros(0), np.zeros((0, 6)), np.zeros((0, 3)), np.zeros((0, 3))
    loads = np.column_stack([f[:, 1:4], m[:, 1:4]])
    if f.shape[1] < 10:
        return f[:, 0], loads, np.zeros((0, 3)), np.zeros((0, 3))
    return f[:, 0], loads, f[:, 4:7], f[:, 7:10]


def _time(name: str) -> float:
    try:
        return float(name)
    except ValueError:
        return -math.inf


@dataclass(frozen=True)
class Judgement:
    """Outcome of a force history.

    status : str — ``converged``, ``averaged`` or ``not converged``
    mean : (6,) — X, Y, Z (N) and K, M, N (N·m)
    std : (6,) — their σ (iterative or unsteadiness), same units
    iterations : int — iterations in the history
    samples : int — iterations the value is taken from
    tau : float — integrated autocorrelation time of the averaged series, iterations (1 if converged)
    """

    status: str
    mean: np.ndarray
    std: np.ndarray
    iterations: int
    samples: int
    tau: float = 1.0


def _scales(values: np.ndarray, length: float) -> np.ndarray:
    force = float(np.linalg.norm(values[:, :3].mean(axis=0)))
    force = max(force, float(np.abs(values[:, :3]).max()) * 1e-3, 1e-300)
    return np.array([force] * 3 + [force * length] * 3)


def converged(
    values: np.ndarray,
    *,
    window: int,
    min_iterations: int,
    tolerance: float,
    length: float,
    parts: np.ndarray | None = None,
) -> bool:
    """True when the last ``window`` rows of (n, 6) loads all stay within ``tolerance`` of the load
    scale, and so do the same rows of ``parts`` (n, k): forces, N, such as the pressure and viscous
    parts of the total force, each judged against the total's scale |F|."""
    n = len(values)
    if n < max(min_iterations, window):
        return False
    last = values[-window:]
    scales = _scales(last, length)
    spread = last.max(axis=0) - last.min(axis=0)
    if not np.all(spread <= tolerance * scales):
        return False
    if parts is None or np.size(parts) == 0:
        return True
    p = np.asarray(parts, float)
    if len(p) != n:
        raise ValueError(f"parts has {len(p)} rows: expected one per load row ({n})")
    tail = p[-window:]
    return bool(np.all(tail.max(axis=0) - tail.min(axis=0) <= tolerance * scales[0]))


#: largest window-to-window ratio a geometric extrapolation of a creeping history assumes
CREEP_RATIO = 0.95


def remaining_change(values: np.ndarray, window: int) -> np.ndarray:
    """Per column of (n, m) ``values``, the change still to come if the history keeps converging
    geometrically, from the means of its last three windows (units of ``values``).

    With window means m₀, m₁, m₂ and steps d₁ = m₁ − m₀, d₂ = m₂ − m₁ of one sign, |d₂| < |d₁| and
    both above three standard errors of a difference of window means (the series' autocorrelation
    counted), r = d₂/d₁ (≤ CREEP_RATIO) and the rest of the series Σ d₂ rᵏ = |d₂| r / (1 − r).
    Otherwise 0: an oscillating or settled history, which the window's range describes.
    """
    values = np.asarray(values, float)
    n = len(values)
    out = np.zeros(values.shape[1])
    if window < 4 or n < 3 * window:
        return out
    blocks = [values[n - (k + 1) * window : n - k * window] for k in (2, 1, 0)]
    m0, m1, m2 = (b.mean(axis=0) for b in blocks)
    d1, d2 = m1 - m0, m2 - m1
    last = blocks[2]
    for j in range(values.shape[1]):
        col = last[:, j]
        resid = col - np.polyval(np.polyfit(np.arange(window), col, 1), np.arange(window))
        se = float(np.std(resid, ddof=2)) * math.sqrt(autocorrelation_time(resid) * 2.0 / window)
        if d1[j] * d2[j] > 0 and abs(d2[j]) < abs(d1[j]) and abs(d2[j]) > 3.0 * se:
            r = min(float(d2[j] / d1[j]), CREEP_RATIO)
            out[j] = abs(float(d2[j])) * r / (1.0 - r)
    return out


def autocorrelation_time(x: np.ndarray, c: float = 5.0) -> float:
    """Integrated autocorrelation time τ = 1 + 2 Σ ρ_k, summed to the first k ≥ c τ (Sokal 1997).

    1 for an uncorrelated series, ≈ (1 + φ)/(1 − φ) for AR(1) with coefficient φ; a constant
    series gives 1.
    """
    x = np.asarray(x, float) - np.mean(x)
    n = len(x)
    var = float(x @ x)
    if n < 4 or var <= 0:
        return 1.0
    size = 1 << (2 * n - 1).bit_length()
    f = np.fft.rfft(x, size)
    acf = np.fft.irfft(f * np.conj(f), size)[:n] / var
    tau = 1.0
    for k in range(1, n):
        tau += 2.0 * float(acf[k])
        if k >= c * tau:
            break
    return float(min(max(tau, 1.0), n))


def judge(
    values: np.ndarray,
    *,
    window: int,
    min_iterations: int,
    tolerance: float,
    length: float,
    parts: np.ndarray | None = None,
) -> Judgement:
    """Judge a finished run's (n, 6) load history (see the module docstring); ``parts`` (n, k),
    N: the force's parts that must settle too (pressure and viscous), as in :func:`converged`."""
    values = np.asarray(values, float)
    n = len(values)
    if n == 0:
        nan = np.full(6, math.nan)
        return Judgement("not converged", nan, nan, 0, 0, math.nan)
    if converged(values, window=window, min_iterations=min_iterations, tolerance=tolerance, length=length, parts=parts):
        last = values[-window:]
        spread = 0.5 * (last.max(axis=0) - last.min(axis=0))
        return Judgement(
            "converged", last.mean(axis=0), np.maximum(spread, remaining_change(values, window)), n, window
        )
    half = values[n // 2 :]
    m = len(half)
    taus = np.array([autocorrelation_time(half[:, j]) for j in range(6)])
    sd = half.std(axis=0, ddof=1) if m > 1 else np.zeros(6)
    sigma = sd * np.sqrt(taus / max(m, 1))
    drift, drift_sd = _trend(half)
    # a trend across the last half larger than the tolerance and than 3 σ of its own estimate
    # (residuals' autocorrelation counted): the history still moves
    scales = _scales(half, length)
    moving = (np.abs(drift) > 3.0 * drift_sd) & (np.abs(drift) > tolerance * scales)
    if parts is not None and np.size(parts):
        p_drift, p_sd = _trend(np.asarray(parts, float)[n // 2 :])
        moving = np.r_[moving, (np.abs(p_drift) > 3.0 * p_sd) & (np.abs(p_drift) > tolerance * scales[0])]
    status = "not converged" if bool(np.any(moving)) else "averaged"
    if status == "not converged":
        sigma = np.maximum(sigma, 0.5 * np.abs(drift))
    return Judgement(status, half.mean(axis=0), sigma, n, m, float(taus.max()))


def _trend(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Change of a straight-line fit across the series, per column, and its standard error
    (residual variance inflated by the residuals' autocorrelation time)."""
    m = len(values)
    t = np.arange(m, dtype=float) - (m - 1) / 2.0
    stt = float(t @ t)
    if m < 4 or stt == 0:
        return np.zeros(values.shape[1]), np.full(values.shape[1], np.inf)
    slope = t @ (values - values.mean(axis=0)) / stt
    res = values - values.mean(axis=0) - np.outer(t, slope)
    tau = np.array([autocorrelation_time(res[:, j]) for j in range(values.shape[1])])
    s2 = (res**2).sum(axis=0) / (m - 2)
    return slope * m, np.sqrt(s2 * tau / stt) * m
