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
