"""Launch preprocessing: release detection, useful-end detection and record checks.

A real record starts with the body at rest or held at the launch displacement — often after a
heel applied by hand, held with a wobble or moving slowly — and ends in sensor noise around the
equilibrium. :func:`detect_release` finds where the free decay starts (the one detector of
``hydrokit identify`` and ``hydrokit ingest --split``); :func:`trim_launch` keeps the decay from
there to where the oscillation sinks into the noise floor, removes the rest value (constant or
drifting, :func:`rest_line`) and applies an amplitude window; :func:`check_record` rejects
records no estimator can use (fewer than two cycles, growing, not oscillating).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from hydrokit.core.validate import record
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


def half_cycle_extremes(t: np.ndarray, z: np.ndarray, band: float) -> list[tuple[int, int, int]]:
    """One extreme per half cycle: (index of the extreme, first, last sample of the half cycle).

    Half cycles are the stretches between crossings of ±``band`` about zero (hysteresis); the
    stretch cut off by the end of the record is left out (it has no true extreme).
    """
    out: list[tuple[int, int, int]] = []
    state = 0
    start = 0
    for i in range(z.size):
        s = 1 if z[i] > band else (-1 if z[i] < -band else 0)
        if s != 0 and s != state:
            if state != 0:
                k = start + int(np.argmax(z[start:i] * state))
                out.append((k, start, i - 1))
            state, start = s, i
    return out


def _free_start(t: np.ndarray, z: np.ndarray, ext: list[tuple[int, int, int]], band: float, sigma: float) -> int | None:
    """Position in ``ext`` of the first extreme after which the motion is a free decay.

    From there on: no same-sign extreme of the next three cycles exceeds the one a cycle before
    it by more than 3 noise σ (a hand building the heel up fails); the amplitudes of up to 20
    extremes fall, by a least-squares slope at least three standard errors below zero (with an
    alternating term for an offset rest value; a steady forced swing fails), or, with only a few
    extremes, by more than twice the hysteresis band; and the periods agree within 15 %.
    """
    amps = np.array([abs(z[k]) for k, _, _ in ext])
    times = np.array([t[k] for k, _, _ in ext])
    tol = 3.0 * sigma
    for j in range(len(ext) - 3):
        m = min(len(ext), j + 7)
        a = amps[j:m]
        if np.any(a[2:] > a[:-2] + tol):
            continue
        n = min(len(ext), j + 20)  # up to 20 extremes
        if n - j >= 6:
            tt, aa = times[j:n] - times[j], amps[j:n]
            H = np.column_stack([np.ones_like(tt), tt, (-1.0) ** np.arange(tt.size)])
            coef, *_ = np.linalg.lstsq(H, aa, rcond=None)
            r = aa - H @ coef
            s2 = float(r @ r) / max(1, tt.size - 3)
            se = math.sqrt(max(s2 * float(np.linalg.inv(H.T @ H)[1, 1]), 0.0))
            if not coef[1] < -3.0 * se:
                continue
        elif a[0] - a[-2 if a.size % 2 == 0 else -1] <= 2.0 * band:
            continue
        if m - j >= 5:
            per = times[j + 3 : m] - times[j + 1 : m - 2]  # full periods after the release extreme
            if per.size and np.max(np.abs(per / np.median(per) - 1.0)) > 0.15:
                continue
        return j
    return None


def detect_release(t: np.ndarray, y: np.ndarray, sigma: float | None = None, file: str = "") -> float:
    """Release time (s, in the record's time base): where the free decay starts.

    Works for a body held still and let go, and for forced motion before the release (a hand
    heel or pull, held with a wobble or moving slowly): the first extreme after which the
    same-sign extremes shrink at a steady period marks the half cycle holding the release;
    there the record is fitted by a quadratic before the release (the hand) joined, with the same
    position and rate, to the free damped oscillation after it (period and decrement from the
    following cycles), and the join time that fits best is the release. A half cycle counts
    where the motion leaves a band of 4 noise σ (or 1 % of the peak) about the rest value, and
    two cycles of them are needed.

    Raises
    ------
    InputError
        No free decay in the record (still, or forced throughout).
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if not y.size:
        raise InputError("the record holds no samples: no free decay found", file)
    if sigma is None:
        sigma = noise_floor(y)
    z = y - equilibrium(y)
    peak = float(np.max(np.abs(z)))
    band = max(4.0 * sigma, 0.01 * peak, 1e-300)
    ext = half_cycle_extremes(t, z, band)
    if not ext:
        raise InputError(
            "the record does not oscillate (still, or moved without swinging back): no free decay found", file
        )
    if len(ext) < 4:
        raise InputError(
            f"only {len(ext) / 2:g} cycles (half cycles with an extreme: {len(ext)}); "
            "expected at least two cycles of free decay",
            file,
        )
    j = _free_start(t, z, ext, band, sigma)
    if j is None:
        raise InputError(
            "no free decay found (the record is still, or forced throughout: expected extremes that shrink "
            "at a steady period after the release)",
            file,
        )
    k0, s0, s1 = ext[j]
    ks = [k for k, _, _ in ext[j + 1 : j + 7]]
    tk = t[ks]
    # _free_start returns j ≤ len(ext) − 4: at least three extremes follow, one full period
    period = float(np.median(tk[2:] - tk[:-2]))
    # every extreme lies beyond the band (> 0), and at least one pair a cycle apart follows
    delta = float(np.median([math.log(abs(z[a]) / abs(z[b])) for a, b in zip(ks[:-2], ks[2:])]))
    zeta = delta / math.sqrt(4 * math.pi**2 + delta**2)
    wd = 2 * math.pi / period
    wn = wd / math.sqrt(1 - zeta**2)
    # the crossing that ends the release half cycle
    c0 = float(t[s1 + 1])  # (a closed half cycle: s1 + 1 is its crossing sample, inside the record)
    if c0 - t[0] < 0.3 * period:
        return float(t[0])  # the record starts in free motion
    lo = max(float(t[0]), c0 - 0.55 * period)
    hi = c0 - 0.1 * period
    sel = np.nonzero((t >= lo) & (t <= hi))[0]
    tw, yw = t[sel], y[sel]
    cands = sel[(t[sel] > lo + 0.05 * period) & (t[sel] < c0 - 0.15 * period)]
    if cands.size == 0 or tw.size < 8:
        # too few samples to fit the hand (under ~18 a period). A hold at the extreme — three or
        # more samples of the release half cycle within 2 % of its extreme (a free swing sampled
        # this coarsely has at most two: its samples are 20° or more of phase apart) — ends at its
        # last such sample; otherwise the release is the sample before the half cycle. (The noise
        # floor is no yardstick here: at this sampling the signal's own curvature inflates it.)
        still = np.nonzero(np.abs(z[s0 : s1 + 1] - z[k0]) <= 0.02 * abs(float(z[k0])))[0]
        if still.size >= 3:
            return float(t[s0 + int(still[-1])])
        return float(t[max(0, s0 - 1)])

    def fit(tr: float) -> tuple[float, np.ndarray]:
        s = tw - tr
        post = s >= 0
        sp = np.where(post, s, 0.0)
        e = np.exp(-zeta * wn * sp)
        c, sn = np.cos(wd * sp), np.sin(wd * sp)
        qa = e * (c + zeta * wn / wd * sn)  # free response to a unit displacement
        qb = e * sn / wd  # to a unit rate
        pre = ~post
        cols = [
            np.where(pre, 1.0, qa),
            np.where(pre, s, qb),
            np.where(pre, s * s, 0.0),
            np.where(pre, 0.0, 1.0 - qa),  # the rest value the free motion decays to
        ]
        H = np.column_stack(cols)
        coef, *_ = np.linalg.lstsq(H, yw, rcond=None)
        r = yw - H @ coef
        return float(r @ r), coef

    costs = np.array([fit(float(t[i]))[0] for i in cands])
    b = int(np.argmin(costs))
    tr = float(t[cands[b]])
    if 0 < b < costs.size - 1:
        # refine between samples: the minimum of a parabola through the three costs
        c_m, c_0, c_p = costs[b - 1], costs[b], costs[b + 1]
        den = c_m - 2 * c_0 + c_p
        if den > 0:  # c_0 is the least of the three, so the vertex is within half a step: |d| ≤ ½
            d = 0.5 * (c_m - c_p) / den
            tr += d * 0.5 * float(t[cands[b + 1]] - t[cands[b - 1]])
    # a hand may let go while the body still moves outwards: the free motion then starts at
    # the extreme that follows, where the rate of the fitted free response is zero
    coef = fit(tr)[1]
    q0, v0 = coef[0] - coef[3], coef[1]
    if q0 * v0 > 0:
        tr += math.atan(v0 * wd / (wn * wn * q0 + zeta * wn * v0)) / wd
    return tr


def _release_index(t: np.ndarray, y: np.ndarray, sigma: float) -> int:
    """Index of the sample nearest the release (:func:`detect_release`); 0 when the record starts
    in free motion or holds no free decay (the caller's :func:`check_record` then decides)."""
    try:
        tr = detect_release(t, y, sigma)
    except InputError:
        return 0
    return _nearest(t, tr)


def _nearest(t: np.ndarray, time: float) -> int:
    i = int(np.clip(np.searchsorted(t, time), 0, t.size - 1))
    return i - 1 if i > 0 and time - t[i - 1] < t[i] - time else i


#: ``--detrend``: keep the record as is, remove a constant rest value, or remove a straight drift
DETRENDS = ("none", "mean", "linear")


def rest_line(t: np.ndarray, y: np.ndarray, sigma: float) -> tuple[float, float]:
    """Rest value of a free decay as a straight line c0 + c1 t (m or rad, per s).

    From every three successive extremes p1, p2, p3: c = (p1 p3 − p2²)/(p1 + p3 − 2 p2), exact
    for a geometric decay about c and unbiased by the oscillation (a plain mean is not); a line
    through these values (at the middle extremes' times) by least squares. Falls back to the
    median of the record's tail when there are fewer than three extremes.
    """
    z0 = equilibrium(y)
    z = y - z0
    band = max(4.0 * sigma, 0.01 * float(np.max(np.abs(z))), 1e-300)
    ext = [k for k, _, _ in half_cycle_extremes(t, z, band)]
    tc, cs = [], []
    for k1, k2, k3 in zip(ext, ext[1:], ext[2:]):
        p1, p2, p3 = z[k1], z[k2], z[k3]
        den = p1 + p3 - 2 * p2
        if den != 0:
            tc.append(t[k2])
            cs.append((p1 * p3 - p2 * p2) / den)
    if len(cs) < 2:
        return z0, 0.0
    # two or more middle extremes at distinct times (t increases strictly): a line is defined
    c1, c0 = np.polyfit(np.asarray(tc), np.asarray(cs), 1)
    return z0 + float(c0), float(c1)


def parse_amplitude(text: str, translational: bool, name: str) -> float:
    """An amplitude from the command line: ``5deg`` (angles only) or a number in SI (m or rad)."""
    s = text.strip().lower()
    degrees = s.endswith("deg") or s.endswith("°")
    if degrees and translational:
        raise InputError(f"{name} {text!r}: degrees given for a translational signal; expected metres")
    try:
        value = math.radians(float(s.rstrip("°").removesuffix("deg"))) if degrees else float(s)
    except ValueError:
        raise InputError(f"{name} {text!r}: expected a number in SI (m or rad) or degrees such as 5deg") from None
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"{name} {text!r}: expected a positive amplitude")
    return value


def _amplitude_window(
    t: np.ndarray, z: np.ndarray, sigma: float, window: tuple[float, float], file: str
) -> tuple[int, int, dict[str, float]]:
    """First and last sample of the stretch whose amplitude is inside (LO, HI]: from the first
    extreme ≤ HI to the first extreme below LO (or the record's end)."""
    hi, lo = window
    label = f"amplitude window {hi:.4g}, {lo:.4g} (HI, LO)"
    if not (hi > lo > 0):
        raise InputError(f"{label}: expected HI > LO > 0")
    band = max(4.0 * sigma, 0.01 * float(np.max(np.abs(z))), 1e-300)
    ext = [k for k, _, _ in half_cycle_extremes(t, z, band)]
    amps = [abs(float(z[k])) for k in ext]
    first = next((j for j, a in enumerate(amps) if a <= hi), None)
    if first is None:
        raise InputError(f"{label}: no extreme of the decay at or below HI; expected a decay through the window", file)
    last = next((j for j in range(first + 1, len(amps)) if amps[j] < lo), None)
    i0 = ext[first]
    i1 = ext[last] if last is not None else z.size - 1
    n_half = (last if last is not None else len(amps)) - first
    cycles = n_half / 2.0
    if cycles < 2.0:
        raise InputError(
            f"{label}: only {cycles:g} cycles inside the window ({amps[first]:.4g} down to {lo:.4g}); "
            "expected at least two cycles",
            file,
        )
    info = {
        "start_amplitude": amps[first],
        "end_amplitude": amps[last] if last is not None else amps[-1],
        "cycles": cycles,
    }
    return i0, i1, info


def trim_launch(
    launch: Launch,
    release: float | None = None,
    end: float | None = None,
    detrend: str = "mean",
    amplitude_window: tuple[float, float] | None = None,
) -> Launch:
    """Keep the free decay: from the release to where the motion sinks into the noise.

    Parameters
    ----------
    launch : Launch — as read (time in s, signal in m or rad)
    release : float, optional — release time, s in the file's time base (default: detected by
        :func:`detect_release`, after any forced motion)
    end : float, optional — last useful time, s (default: the last sample whose distance from
        the equilibrium exceeds 4 noise standard deviations, plus a quarter of a period)
    detrend : str — "none" (as recorded), "mean" (remove the constant rest value; default) or
        "linear" (remove a straight drift of the rest value, see :func:`rest_line`)
    amplitude_window : (HI, LO), optional — m or rad: keep only from the first extreme ≤ HI to
        the first extreme below LO

    Returns
    -------
    Launch — time shifted so the release is t = 0, notes saying what was trimmed, ``info`` with
    ``release_time`` (s, file time base), ``release`` ("detected"/"given"), ``detrend`` and
    ``amplitude_window``.

    Raises
    ------
    InputError
        Too few samples, no free decay, a release or end outside the record, an unknown detrend,
        an amplitude window with fewer than two cycles.
    """
    t = np.asarray(launch.t, float)
    y = np.asarray(launch.y, float)
    notes = list(launch.notes)
    if detrend not in DETRENDS:
        raise InputError(f"--detrend {detrend!r}: expected one of {', '.join(DETRENDS)}", launch.file)
    t, y = record(t, y, "signal", "m or rad", launch.file)
    if t.size < MIN_SAMPLES:
        raise InputError(f"only {t.size} samples; expected at least {MIN_SAMPLES}", launch.file)
    sigma = noise_floor(y)
    if release is None:
        try:
            t_rel = detect_release(t, y, sigma, launch.file)
        except InputError:
            check_record(launch)  # a growing or non-oscillating record: say so in its own words
            raise
        i0 = _nearest(t, t_rel)
        how = "detected"
    else:
        if not (t[0] <= release < t[-1]):
            raise InputError(
                f"release = {release} s: expected a time within the record [{t[0]:g}, {t[-1]:g}] s", launch.file
            )
        i0 = int(np.searchsorted(t, release, side="left"))
        t_rel = float(release)
        how = "given"
    eq = equilibrium(y[i0:])
    if end is None:
        floor = max(4.0 * sigma, 1e-12)
        big = np.nonzero(np.abs(y[i0:] - eq) > floor)[0]
        if big.size:
            # from the release to the last sample above the noise, then on to the sample nearest
            # a quarter period later (the swing's next zero crossing): half the median spacing of
            # the extremes above the noise (plain zero crossings multiply in the noisy tail and
            # shorten it), none added when fewer than two extremes measure it
            seg = slice(i0, i0 + int(big[-1]) + 1)
            tk = t[seg][[k for k, _, _ in half_cycle_extremes(t[seg], y[seg] - eq, floor)]]
            quarter = 0.5 * float(np.median(np.diff(tk))) if tk.size >= 2 else 0.0
            i1 = _nearest(t, t[seg.stop - 1] + quarter)
        else:
            i1 = t.size - 1  # nothing above the noise: refused below (first as too short, if it is)
        how_end = "detected"
    else:
        if not (t[i0] < end <= t[-1] + 1e-12):
            raise InputError(
                f"end = {end} s: expected a time after the release ({t[i0]:g} s) and within the record", launch.file
            )
        i1 = int(np.searchsorted(t, end, side="right")) - 1
        how_end = "given"
    if i0 > 0:
        notes.append(f"release {how} at t = {t_rel:.3f} s: {i0} samples before it dropped")
    if i1 < t.size - 1:
        notes.append(f"end {how_end} at t = {t[i1]:.3f} s: {t.size - 1 - i1} samples of noise dropped")
    if i1 + 1 - i0 < MIN_SAMPLES:
        raise InputError(
            f"the launch from the release ({how}, t = {t_rel:g} s) to the end ({how_end}, t = {t[i1]:g} s) holds "
            f"{i1 + 1 - i0} sample{'s' if i1 - i0 else ''}; expected at least {MIN_SAMPLES}",
            launch.file,
        )
    if end is None and not big.size:
        raise InputError(
            f"after the release (t = {t_rel:g} s) the record stays within 4 noise floors ({floor:.3g}) of its "
            "rest value: expected a free decay above the noise",
            launch.file,
        )
    tt = t[i0 : i1 + 1] - t[i0]
    yy = y[i0 : i1 + 1].copy()
    info: dict[str, Any] = {"release_time": t_rel, "release": how}
    c0, c1 = rest_line(tt, yy, noise_floor(yy))
    if detrend == "linear":
        yy = yy - (c0 + c1 * tt)
        notes.append(f"drift removed: rest value {c0:.4g} + {c1:.4g}·t")
        info["detrend"] = {"method": detrend, "offset": c0, "slope": c1}
    elif detrend == "mean":
        yy = yy - c0
        info["detrend"] = {"method": detrend, "offset": c0, "slope": 0.0}
    else:
        info["detrend"] = {"method": detrend, "offset": 0.0, "slope": 0.0}
    if amplitude_window is not None:
        z = yy - (0.0 if detrend != "none" else c0)
        w0, w1, facts = _amplitude_window(tt, z, noise_floor(yy), amplitude_window, launch.file)
        info["amplitude_window"] = {
            "high": float(amplitude_window[0]),
            "low": float(amplitude_window[1]),
            "start_time": float(t[i0 + w0]),
            "end_time": float(t[i0 + w1]),
            **facts,
        }
        notes.append(
            f"amplitude window: t = {t[i0 + w0]:.3f} to {t[i0 + w1]:.3f} s ({facts['cycles']:g} cycles, "
            f"amplitude {facts['start_amplitude']:.4g} down to {facts['end_amplitude']:.4g})"
        )
        tt, yy = tt[w0 : w1 + 1], yy[w0 : w1 + 1]
    return replace(launch, t=tt, y=yy, notes=tuple(notes), info=info)


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
    same = [c for c in crossings[::2] if c >= y.size // 2]  # (two cycles: at least 4 crossings)
    if len(same) >= 2:
        eq = float(np.mean(y[same[0] : same[-1]]))
    tc = t[np.asarray(crossings)]
    # full periods between crossings of the same direction: the hysteresis offsets cancel
    period = float(np.median(tc[2:] - tc[:-2]))
    return {"period": period, "cycles": cycles, "offset": eq, "noise": sigma}
