"""Ingest figure: the whole recording with each launch's span and detected release."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hydrokit.plot._mpl import new_figure


def recording_overview(
    t: np.ndarray, y: np.ndarray, launches: Sequence[dict[str, Any]], unit: str, title: str = ""
) -> Any:
    """The recorded signal (mm or degrees) with the written launches shaded and their releases
    marked. ``launches`` are the ``ingest.json`` entries (start/end/release times in s)."""
    scale, label = (1e3, "position (mm)") if unit == "m" else (180 / np.pi, "angle (°)")
    fig = new_figure((9, 3.6))
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(t, np.asarray(y) * scale, "-", lw=0.7, color="0.3")
    for k, d in enumerate(launches):
        ax.axvspan(d["start_time"], d["end_time"], color=f"C{k % 10}", alpha=0.15)
        ax.axvline(d["release_time"], color=f"C{k % 10}", lw=1.0, ls="--")
        ax.text(d["release_time"], 1.0, f" {k + 1}", transform=ax.get_xaxis_transform(), va="top", fontsize=8)
    ax.set_xlabel("time (s, source time base)")
    ax.set_ylabel(label)
    ax.set_title(title or f"{len(launches)} launch(es): shaded = written, dashed = release", fontsize=9)
    fig.tight_layout()
    return fig


def video_tracking(frame: np.ndarray, tracking: dict[str, Any]) -> Any:
    """The first video frame with the tracked marker positions, the fitted circle and the pivot.
    ``tracking`` is the ``ingest.json`` ``tracking`` entry (pixels)."""
    pv, r = tracking["pivot"], tracking["radius_px"]
    pf = tracking["per_frame"]
    h, w = frame.shape[:2]
    fig = new_figure((7, 7 * h / w + 0.4))
    ax = fig.add_subplot(1, 1, 1)
    ax.imshow(frame, cmap="gray", vmin=0, vmax=255)
    a = np.linspace(0, 2 * np.pi, 721)
    ax.plot(pv["x"] + r * np.sin(a), pv["y"] + r * np.cos(a), "-", color="C1", lw=0.8, label=f"circle r = {r:.1f} px")
    ax.plot([pv["x"]], [pv["y"]], "+", color="C1", ms=12, mew=2, label=f"pivot ({pv['x']:.1f}, {pv['y']:.1f})")
    ax.plot([pv["x"], pv["x"]], [pv["y"], pv["y"] + r], ":", color="C1", lw=0.8)
    if pf.get("x_px"):
        lost = np.asarray(pf["lost"], bool)
        xs, ys = (np.array([np.nan if v is None else v for v in pf[k]]) for k in ("x_px", "y_px"))
        ax.plot(xs[~lost], ys[~lost], ".", color="C0", ms=2, label="marker")
        if lost.any():
            ax.plot(xs[lost], ys[lost], "x", color="C3", ms=4, label=f"lost ({int(lost.sum())})")
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(
        f"θ = 0 along the dotted vertical, + to the right; circle RMS {tracking['circle_rms_px']:.3f} px", fontsize=9
    )
    fig.tight_layout()
    return fig
