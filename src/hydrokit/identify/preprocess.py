"""Launch preprocessing: release detection, useful-end detection and record checks.

A real record starts with the body held still at the launch displacement and ends in sensor
noise around the equilibrium. :func:`trim_launch` keeps the decay between the release and the
point where the oscillation sinks into the noise floor; :func:`check_record` rejects records
no estimator can use (fewer than two cycles, growing, not oscillating).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Launch

MIN_SAMPLES = 20


def noise_floor(y: np.ndarray) -> float:
    """Robust standard deviation of the sample-to-sample noise (MAD of second differences).

    Second differences of a smooth, well-sampled oscillation are small; of white noise σ they
    have standard deviation √6 σ.
    """
    y = np.asarray(y, float)
    if y.size < 5:
        return 0.0
    d2 = np.diff(y, 2)
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    sigma = 1.4826 * mad / math.sqrt(6.0)
    d1 = np.abs(np.diff(y))
    if np.mean(d1 == 0) > 0.2 and np.any(d1 > 0):
        # a quantised sensor (encoder): many repeated values; its noise is step/√12
        step = float(np.min(d1[d1 > 0]))
        sigma = max(sigma, step / math.sqrt(12.0))
    return sigma


def equilibrium(y: np.ndarray) -> float:
    """The rest value: median of the last fifth of the record (m or rad)."""
    y = np.asarray(y, float)
    return float(np.median(y[-max(5, y.size // 5) :]))


def zero_crossings(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Times (s) where y changes sign, by linear interpolation."""
    s = np.signbit(y)
    idx = np.nonzero(s[1:] != s[:-1])[0]
    y0, y1 = y[idx], y[idx + 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(y1 != y0, y0 / (y0 - y1), 0.5)
    return t[idx] + frac * (t[idx + 1] - t[idx])


def _release_index(t: np.ndarray, y: np.ndarray, sigma: float) -> int:
    """Index of the last still sample before the release.

    Just after the release the body departs as d = c (t − t_r)² (it starts from rest), so
    √d is linear in t: two departure samples (above 1× and 4× the detection threshold)
    extrapolate back to the release time t_r.
    """
    start = float(np.median(y[: min(5, y.size)]))
    span = float(np.max(y) - np.min(y))
    thr = max(6.0 * sigma, 0.01 * span)
    d = np.abs(y - start)
    moved = np.nonzero(d > thr)[0]
    if moved.size == 0 or moved[0] <= 1:
        return 0
    i1 = int(moved[0])
    far = np.nonzero(d[i1:] > 4.0 * thr)[0]
    if far.size:
        i2 = i1 + int(far[0])
        s1, s2 = math.sqrt(d[i1]), math.sqrt(d[i2])
        if s2 > s1:
            tr = t[i1] - (t[i2] - t[i1]) * s1 / (s2 - s1)
            return int(np.clip(np.searchsorted(t, tr, side="right") - 1, 0, i1 - 1))
    return i1 - 1


def trim_launch(launch: Launch, release: float | None = None, end: float | None = None) -> Launch:
    """Keep the free decay: from the release to where the motion sinks into the noise.

    Parameters
    ----------
    launch : Launch — as read (time in s, signal in m or rad)
    release : float, optional — release time, s (default: detected as the first sample that
        leaves the still hold by more than 6 noise standard deviations or 1 % of the range)
    end : float, optional — last useful time, s (default: the last sample whose distance from
        the equilibrium exceeds 4 noise standard deviations, plus a quarter of a period)

    Returns
    -------
    Launch — time shifted so the release is t = 0, notes saying what was trimmed.
    """
    t = np.asarray(launch.t, float)
    y = np.asarray(launch.y, float)
    notes = list(launch.notes)
    if t.size < MIN_SAMPLES:
        raise InputError(f"only {t.size} samples; expected at least {MIN_SAMPLES}", launch.file)
    sigma = noise_floor(y)
    if release is None:
        i0 = _release_index(t, y, sigma)
        how = "detected"
    else:
        if not (t[0] <= release < t[-1]):
            raise InputError(
                f"release = {release} s: expected a time within the record [{t[0]:g}, {t[-1]:g}] s", launch.file
            )
        i0 = int(np.searchsorted(t, release, side="left"))
        how = "given"
    eq = equilibrium(y[i0:])
    if end is None:
        floor = max(4.0 * sigma, 1e-12)
        big = np.nonzero(np.abs(y[i0:] - eq) > floor)[0]
        i1 = i0 + int(big[-1]) if big.size else t.size - 1
        zc = zero_crossings(t[i0 : i1 + 1], y[i0 : i1 + 1] - eq)
        quarter = 0.5 * float(np.median(np.diff(zc))) if zc.size >= 3 else 0.0
        i1 = min(t.size - 1, int(np.searchsorted(t, t[i1] + quarter)))
        how_end = "detected"
    else:
        if not (t[i0] < end <= t[-1] + 1e-12):
            raise InputError(
                f"end = {end} s: expected a time after the release ({t[i0]:g} s) and within the record", launch.file
            )
        i1 = int(np.searchsorted(t, end, side="right")) - 1
        how_end = "given"
    if i0 > 0:
        notes.append(f"release {how} at t = {t[i0]:.3f} s: {i0} still samples dropped")
    if i1 < t.size - 1:
        notes.append(f"end {how_end} at t = {t[i1]:.3f} s: {t.size - 1 - i1} samples of noise dropped")
    tt = t[i0 : i1 + 1] - t[i0]
    return replace(launch, t=tt, y=y[i0 : i1 + 1].copy(), notes=tuple(notes))


def check_record(launch: Launch) -> dict[str, float]:
    """Reject records no estimator can use; return basic facts about the oscillation.

    Returns
    -------
    dict with ``period`` (s, mean damped period from zero crossings), ``cycles`` (number of
    full cycles), ``offset`` (equilibrium, m or rad) and ``noise`` (noise std, m or rad).

    Raises
    ------
    InputError
        Too few samples, no oscillation, fewer than two cycles, or a growing record.
    """
    t = np.asarray(launch.t, float)
    y = np.asarray(launch.y, float)
    if t.size < MIN_SAMPLES:
        raise InputError(f"only {t.size} samples after trimming; expected at least {MIN_SAMPLES}", launch.file)
    eq = equilibrium(y)
    sigma = noise_floor(y)
    z = y - eq
    # ignore crossings produced by noise near the rest value: hysteresis of 3 σ
    band = 3.0 * sigma
    state = 0
    crossings = []
    for i, v in enumerate(z):
        s = 1 if v > band else (-1 if v < -band else 0)
        if s != 0 and s != state:
            if state != 0:
                crossings.append(i)
            state = s
    n3 = max(1, y.size // 3)
    first, last = np.max(np.abs(z[:n3])), np.max(np.abs(z[-n3:]))
    if last > 1.2 * first + band:
        raise InputError(
            f"the oscillation grows (peak {first:.4g} in the first third, {last:.4g} in the last); "
            "expected a decaying record",
            launch.file,
        )
    n_cross = len(crossings)
    if n_cross < 2:
        raise InputError(
            f"the record does not oscillate ({n_cross} crossing(s) of the rest value {eq:.4g}); expected a free decay",
            launch.file,
        )
    cycles = n_cross / 2.0
    if cycles < 2.0:
        raise InputError(f"only {cycles:g} cycles; expected at least two cycles of free decay", launch.file)
    # refine the rest value: mean over whole cycles of the second half (the median of the
    # tail is biased when the tail holds a fraction of a cycle)
    same = [c for c in crossings[::2] if c >= y.size // 2] if len(crossings) >= 3 else []
    if len(same) >= 2:
        eq = float(np.mean(y[same[0] : same[-1]]))
    tc = t[np.asarray(crossings)]
    # full periods between crossings of the same direction: the hysteresis offsets cancel
    period = float(np.median(tc[2:] - tc[:-2])) if tc.size >= 3 else 2.0 * float(tc[1] - tc[0])
    return {"period": period, "cycles": cycles, "offset": eq, "noise": sigma}
