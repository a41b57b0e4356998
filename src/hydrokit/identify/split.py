"""Splitting a long recording into launches: one per release (issue #12, ``hydrokit ingest --split``).

A tank session is often recorded in one file: the body is held still at a displacement,
released, decays to rest, is lifted to the next displacement, held, released again, ….
:func:`split_launches` finds the still intervals (the signal's range over every ``min_hold``
window within 8 noise standard deviations) and keeps those followed by a large motion (holds,
and rests before a lift; the still turning points of a decay's tail are followed by small
ones). On the stretch from each to the next it runs the single-launch preprocessing of
:mod:`hydrokit.identify.preprocess`: the release detector finds the hold → free-decay
transition, the end detector the noise floor (the stretch is first cut at its last pass
through the rest value, before a lift into the next hold), and
:func:`~hydrokit.identify.preprocess.check_record` accepts the stretch only if it is a free
decay (at least two decaying cycles). A rest followed by a lift, or a hold broken by a twitch,
is not a decay and is skipped. Holds must last about ``min_hold`` (1 s): a shorter still
stretch cannot be told from the turning point of a slow oscillation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.preprocess import MIN_SAMPLES, _release_index, check_record, noise_floor, trim_launch
from hydrokit.identify.types import Launch

#: a window is still when its range is below this many noise standard deviations
STILL_SIGMAS = 8.0


@dataclass(frozen=True)
class Segment:
    """One launch inside a recording, as sample indices (inclusive).

    start : first sample to keep (the end of the hold before the release)
    release : last still sample before the release (the detector's index)
    end : last useful sample (where the decay sinks into the noise, or before the next hold)
    """

    start: int
    release: int
    end: int


def find_release(t: np.ndarray, y: np.ndarray) -> int:
    """Index of the last still sample before the release of a one-launch record (0 when the
    record starts in motion or holds no free decay at all, which
    :func:`hydrokit.identify.preprocess.check_record` then reports). The detector of
    :func:`hydrokit.identify.preprocess.trim_launch`."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    return _release_index(t, y, noise_floor(y))


def still_runs(t: np.ndarray, y: np.ndarray, min_hold: float = 1.0) -> list[tuple[int, int]]:
    """Intervals (first, last sample, inclusive) where the signal stays still for at least
    ``min_hold`` seconds: its range over every ``min_hold`` window is within 8 noise std."""
    from scipy.ndimage import maximum_filter1d, minimum_filter1d

    t = np.asarray(t, float)
    y = np.asarray(y, float)
    dt = float(np.median(np.diff(t)))
    w = max(5, int(round(min_hold / dt)))
    if y.size < w:
        return []
    sigma = noise_floor(y)
    span = float(np.max(y) - np.min(y))
    thr = max(STILL_SIGMAS * sigma, 1e-6 * span, 1e-300)
    # window [k, k + w) → still flag at k
    rng = maximum_filter1d(y, w, origin=-(w // 2)) - minimum_filter1d(y, w, origin=-(w // 2))
    flag = rng[: y.size - w + 1] <= thr
    edges = np.diff(np.concatenate([[0], flag.astype(np.int8), [0]]))
    starts, stops = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0]
    return [(int(a), int(b) - 1 + w - 1) for a, b in zip(starts, stops)]


def split_launches(
    t: np.ndarray, y: np.ndarray, *, min_hold: float = 1.0, keep_hold: float = 1.0, file: str = ""
) -> list[Segment]:
    """Every launch (hold → release → free decay) in a long recording.

    Parameters
    ----------
    t : s, strictly increasing; y : m or rad
    min_hold : float — shortest still interval taken for a hold, s (default 1)
    keep_hold : float — how much of the hold to keep before each release, s (default 1; so that
        ``hydrokit identify`` sees the hold and detects the release itself)
    file : str — name for messages

    Returns
    -------
    list of Segment, in time order; an empty list when no release is found.
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    runs = still_runs(t, y, min_hold)
    dt = float(np.median(np.diff(t)))
    sigma = noise_floor(y)
    big = max(20.0 * sigma, 0.02 * float(np.ptp(y)))
    # a hold (or a rest before a lift) is followed by a large motion; the still stretches of a
    # decay's tail are followed by small ones and belong to the launch before them
    cands = []
    for k, (a, b) in enumerate(runs):
        nxt = runs[k + 1][0] if k + 1 < len(runs) else y.size
        level = float(np.median(y[a : b + 1]))
        if nxt > b + 1 and float(np.max(np.abs(y[b + 1 : nxt] - level))) > big:
            cands.append((a, b))
    out: list[Segment] = []
    for k, (a, b) in enumerate(cands):
        # the stretch ends where the next candidate's still run begins, so launches never overlap:
        # each ends (at ``cut`` − 1 or before) ahead of the next one's hold
        stop = cands[k + 1][0] if k + 1 < len(cands) else y.size
        if stop - b < MIN_SAMPLES:
            continue
        motion = y[b + 1 : stop]
        centre = float(np.median(motion))
        band = max(4.0 * sigma, 0.02 * abs(float(np.median(y[a : b + 1])) - centre))
        near = np.nonzero(np.abs(motion - centre) <= band)[0]
        # cut before a lift into the next hold: the last pass near the rest value
        cut = b + 2 + int(near[-1]) if near.size else stop
        # the hold's last min_hold seconds: its level, free of the lift's settling
        a0 = max(a, b + 1 - max(5, int(round(min_hold / dt))))
        tt, yy = t[a0:cut], y[a0:cut]
        i0 = _release_index(tt, yy, sigma)
        try:
            trimmed = trim_launch(Launch(tt, yy, file), release=float(tt[i0]))
            check_record(trimmed)
        except InputError:
            continue  # a lift, a twitch or a rest: not a free decay
        release = a0 + i0
        end = release + trimmed.t.size - 1
        start = max(a, int(np.searchsorted(t, t[release] - keep_hold)))
        out.append(Segment(start, release, end))
    return out
