"""Pendulum video as a recording (ENG2009 eq. 11), through ``opencv-python-headless``.

A dark (or bright) marker on the rod is found in every frame: a coarse search on the
4×-downsampled frame (or ``--roi``), then the intensity-weighted centroid of the blob above half
its contrast in a window about it (sub-pixel). The pivot is the centre of the circle fitted to
the marker's arc (algebraic Kåsa fit, then Gauss–Newton on the geometric distances) unless
``--pivot`` gives it. θ = atan2(x − x_p, y − y_p): the angle from the downward image vertical
(image y points down), positive when the marker is to the image right (+x) of the pivot.
Frame times: the container's (``CAP_PROP_POS_MSEC``), or frame index / ``--fps``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.errors import InputError, MissingExtraError
from hydrokit.io.recording import Recording

MAX_LOST = 0.2  # fraction of frames the marker may be lost in


def parse_ints(text: str | tuple[float, ...] | None, n: int, option: str) -> tuple[float, ...] | None:
    """``"x,y"`` / ``"x,y,w,h"`` (pixels) → a tuple of ``n`` numbers."""
    if text is None or isinstance(text, tuple):
        return text
    try:
        vals = tuple(float(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != n or not np.all(np.isfinite(vals)):
        raise InputError(f"{option} {text!r}: expected {n} numbers in pixels separated by commas")
    return vals


def blob_centroid(win: np.ndarray, dark: bool) -> tuple[float, float, float, float, float]:
    """Sub-pixel centroid of the marker in an image window (float array).
    The marker signal s = background − I (dark) or I − background (bright), background = the
    window's median; pixels above half the peak weigh s − peak/2 (intensity-weighted moments).
    Returns (x, y, area px², contrast, noise σ) in window pixels and grey levels."""
    bg = float(np.median(win))
    s = bg - win if dark else win - bg
    peak = float(s.max())
    noise = 1.4826 * float(np.median(np.abs(s)))
    w = np.maximum(s - 0.5 * peak, 0.0)
    m = float(w.sum())
    if m <= 0.0:
        return math.nan, math.nan, 0.0, peak, noise
    ys, xs = np.indices(w.shape)
    return float((w * xs).sum() / m), float((w * ys).sum() / m), float(np.count_nonzero(w)), peak, noise


def fit_circle(x: np.ndarray, y: np.ndarray, steps: int = 5) -> tuple[float, float, float]:
    """Circle through the points (x, y): Kåsa's algebraic fit, then Gauss–Newton on the
    geometric distances. Returns (x_c, y_c, R)."""
    mx, my = float(np.mean(x)), float(np.mean(y))
    u, v = x - mx, y - my  # centred for conditioning
    a, b, c = np.linalg.lstsq(np.column_stack([u, v, np.ones_like(u)]), -(u * u + v * v), rcond=None)[0]
    p = np.array([-a / 2, -b / 2, math.sqrt(max(a * a / 4 + b * b / 4 - c, 0.0))])
    for _ in range(steps):
        du, dv = u - p[0], v - p[1]
        d = np.hypot(du, dv)
        jac = np.column_stack([-du / d, -dv / d, -np.ones_like(d)])
        p = p - np.linalg.lstsq(jac, d - p[2], rcond=None)[0]
    return float(p[0] + mx), float(p[1] + my), float(abs(p[2]))


def _json(a: np.ndarray) -> list[float | None]:
    return [round(float(v), 6) if math.isfinite(v) else None for v in a]


def _open(path: Path) -> Any:
    try:
        import cv2
    except ImportError:
        raise MissingExtraError("opencv-python-headless", "video") from None
    if not path.is_file():
        raise InputError("no such video file", str(path))
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")  # FFmpeg's own messages would break the one-line error
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise InputError("OpenCV cannot open this video (codec or container not supported)", str(path))
    return cv2, cap


def _check_roi(roi: tuple[float, ...], shape: tuple[int, ...], src: str) -> None:
    x, y, w, h = roi
    if not (w >= 8 and h >= 8 and x >= 0 and y >= 0 and x + w <= shape[1] and y + h <= shape[0]):
        raise InputError(f"--roi {x:g},{y:g},{w:g},{h:g}: not inside the {shape[1]}×{shape[0]} frame", src)


def track_video(
    path: str | os.PathLike[str], dark: bool = True, roi: tuple[float, ...] | None = None
) -> dict[str, Any]:
    """Per-frame marker centroids (pixels, full-frame coordinates), times (s), area, contrast,
    noise, and the first frame (grey) for plots."""
    cv2, cap = _open(p := Path(path))
    rows: list[tuple[float, ...]] = []
    first, half, best = None, 0, -1.0
    x0, y0 = (int(roi[0]), int(roi[1])) if roi else (0, 0)
    while (got := cap.read())[0]:
        frame = got[1]
        gray = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY) if frame.ndim == 3 else frame
        if first is None:
            first = gray.copy()
            if roi:
                _check_roi(roi, gray.shape, str(p))
        area = gray[y0 : y0 + int(roi[3]), x0 : x0 + int(roi[2])] if roi else gray
        small = cv2.resize(area, None, fx=0.25, fy=0.25, interpolation=cv2.INTER_AREA)
        lo, hi, lo_at, hi_at = cv2.minMaxLoc(small)
        at = lo_at if dark else hi_at
        if len(rows) < 30:  # window size from the blob of highest contrast in the first frames
            s = (float(np.median(small)) - small.astype(np.float32)) * (1.0 if dark else -1.0)
            if s.max() > best:
                best, r = float(s.max()), math.sqrt(16.0 * np.count_nonzero(s > 0.5 * s.max()) / math.pi)
                half = int(np.clip(2.0 * r + 8.0, 12, 160))
        cx, cy = 4 * at[0] + 2, 4 * at[1] + 2
        xa, ya = max(cx - half, 0), max(cy - half, 0)
        win = area[ya : cy + half + 1, xa : cx + half + 1].astype(np.float32)
        bx, by, a, c, n = blob_centroid(win, dark)
        rows.append((cap.get(cv2.CAP_PROP_POS_MSEC) / 1e3, bx + xa + x0, by + ya + y0, a, c, n))
    fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
    cap.release()
    if len(rows) < 2:
        raise InputError(f"{len(rows)} frame(s) decoded; expected a video", str(p))
    cols = dict(zip(("t", "x", "y", "area", "contrast", "noise"), np.array(rows).T))
    return {**cols, "frame": first, "fps": fps}


def read_video(
    path: str | os.PathLike[str],
    *,
    marker: str = "dark",
    roi: str | tuple[float, ...] | None = None,
    pivot: str | tuple[float, ...] | None = None,
    fps: float | None = None,
) -> Recording:
    """The rod angle (rad) of a pendulum video; tracking quality in ``Recording.details``."""
    src = str(path)
    if marker not in ("dark", "bright"):
        raise InputError(f"--marker {marker!r}: expected dark or bright")
    if fps is not None and not (math.isfinite(fps) and fps > 0):
        raise InputError(f"--fps {fps}: expected a positive frame rate")
    roi_px, piv = parse_ints(roi, 4, "--roi"), parse_ints(pivot, 2, "--pivot")
    tr = track_video(path, marker == "dark", roi_px)
    n = tr["t"].size
    if fps:
        t, tsrc = np.arange(n) / fps, f"frame index / --fps {fps:g}"
    elif np.all(tr["t"][1:] > tr["t"][:-1]):
        t, tsrc = tr["t"], "container time stamps (CAP_PROP_POS_MSEC)"
    elif tr["fps"] > 0:
        t, tsrc = np.arange(n) / tr["fps"], f"frame index / container rate {tr['fps']:g} fps (no usable stamps)"
    else:
        raise InputError("the container gives neither frame times nor a frame rate; give --fps", src)
    area, con = tr["area"], tr["contrast"]
    ok = np.isfinite(tr["x"]) & (con > 6.0 * tr["noise"]) & (con > 0.5 * np.median(con))
    ref = float(np.median(area[ok])) if ok.any() else 0.0
    ok &= (area > 0.3 * ref) & (area < 3.0 * ref)
    for k in range(3):  # fit, drop the frames far off the circle, fit again
        lost = int(n - ok.sum())
        if lost > MAX_LOST * n:
            msg = f"marker lost in {lost} of {n} frames (> {MAX_LOST:.0%}): check --marker, --roi and the lighting"
            raise InputError(msg, src)
        if k == 2:
            break
        xc, yc, r = piv + (math.nan,) if piv else fit_circle(tr["x"][ok], tr["y"][ok])
        dist = np.hypot(tr["x"] - xc, tr["y"] - yc)
        r = float(np.median(dist[ok])) if piv else r
        dist -= r
        ok &= np.abs(dist) <= max(1.0, 8.0 * 1.4826 * float(np.median(np.abs(dist[ok]))))
    theta = np.arctan2(tr["x"] - xc, tr["y"] - yc)
    if not piv and (span := math.degrees(float(np.ptp(theta[ok])))) < 10.0:
        raise InputError(f"the marker's arc spans only {span:.3g}°: too short for a circle fit; give --pivot x,y", src)
    dropped = int(np.sum(np.maximum(np.round(np.diff(t) / np.median(np.diff(t))) - 1, 0)))
    details = {
        "marker": marker,
        "roi": list(roi_px) if roi_px else None,
        "pivot": {"x": xc, "y": yc, "from": "--pivot" if piv else "circle fit of the marker's arc"},
        "radius_px": r,
        "circle_rms_px": float(np.sqrt(np.mean(dist[ok] ** 2))),
        "frames": n,
        "lost_frames": lost,
        "dropped_frames": dropped,
        "times": tsrc,
        "sign": "θ from the downward image vertical, positive with the marker to the image right (+x)",
    }
    pf = {"time": t, "x_px": tr["x"], "y_px": tr["y"], "area_px": area, "contrast": con, "circle_distance_px": dist}
    details["per_frame"] = {k: _json(v) for k, v in pf.items()} | {"lost": (~ok).tolist()}
    notes = (
        f"frame times from {tsrc}",
        f"θ about the pivot ({xc:.2f}, {yc:.2f}) px, radius {r:.2f} px: {details['sign']}",
    )
    warns = [f"marker lost in {lost} of {n} frames: those frames are left out"] if lost else []
    if dropped:
        warns.append(f"{dropped} dropped frame(s) (gaps in the frame times)")
    return Recording(t[ok], theta[ok], src, f"{marker} marker angle (rad)", notes, tuple(warns), details, tr["frame"])
