"""Figures of system identification (issue #44): measured vs simulated channels with the Monte
Carlo band, residuals, and the parameter correlation heat map."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure

#: axis label of each channel (SI)
LABELS = {
    "x": "x (m)",
    "y": "y (m)",
    "z": "z (m)",
    "phi": "φ (rad)",
    "theta": "θ (rad)",
    "psi": "ψ (rad)",
    "u": "u (m/s)",
    "v": "v (m/s)",
    "w": "w (m/s)",
    "p": "p (rad/s)",
    "q": "q (rad/s)",
    "r": "r (rad/s)",
}


#: most points drawn per line (a 90 s channel at 50 Hz has 4500: drawing them all is slow and
#: shows nothing more at report size)
MAX_POINTS = 600


def _thin(*arrays: Any) -> list[np.ndarray]:
    n = len(arrays[0])
    step = max(1, -(-n // MAX_POINTS))
    return [np.asarray(a)[::step] for a in arrays]


def prediction_axes(prediction: Mapping[str, Any], ax: Any = None, channel: str | None = None) -> Any:
    """One channel of one run (default: its first): measured points, simulation, 95 % band."""
    ax = axes_or_new(ax)
    chans = prediction["channels"]
    c = channel or next(iter(chans))
    d = chans[c]
    t, y, sim, lo, hi = _thin(d["time"], d["measured"], d["simulated"], d["low"], d["high"])
    ax.fill_between(t, lo, hi, color="C1", alpha=0.3, lw=0, label="95 % (covariance)")
    ax.plot(t, y, ".", ms=2, color="C0", label="measured")
    ax.plot(t, sim, "-", lw=1, color="C1", label="simulated")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(LABELS.get(c, c))
    held = " (held out)" if prediction.get("holdout") else ""
    ax.set_title(f"{prediction['name']}{held}")
    ax.legend(loc="best", fontsize=7)
    return ax


def run_figure(prediction: Mapping[str, Any]) -> Any:
    """Every channel of a run, measured vs simulated, with the residual below each."""
    chans = list(prediction["channels"])
    n = len(chans)
    cols = 2
    rows = (n + cols - 1) // cols
    fig = new_figure((11, 2.4 * rows))
    for k, c in enumerate(chans):
        ax = fig.add_subplot(rows, cols, k + 1)
        prediction_axes(prediction, ax, c)
        if k:
            ax.set_title("")
            leg = ax.get_legend()
            if leg is not None:
                leg.remove()
    fig.subplots_adjust(hspace=0.6, wspace=0.25)
    return fig


def residual_figure(predictions: Sequence[Mapping[str, Any]]) -> Any:
    """Residuals (measured − simulated) of every run and channel, normalised by their RMS."""
    chans = sorted({c for p in predictions for c in p["channels"]})
    fig = new_figure((11, 1.6 * max(len(chans), 1)))
    for k, c in enumerate(chans):
        ax = fig.add_subplot(len(chans), 1, k + 1)
        for j, p in enumerate(predictions):
            if c in p["channels"]:
                d = p["channels"][c]
                t, y, sim = _thin(d["time"], d["measured"], d["simulated"])
                ax.plot(t, y - sim, lw=0.6, color=f"C{j % 10}", label=p["name"])
        ax.set_ylabel(LABELS.get(c, c), fontsize=7)
    fig.axes[0].legend(loc="upper right", fontsize=6, ncol=4) if fig.axes else None
    if fig.axes:
        fig.axes[-1].set_xlabel("time (s)")
    fig.subplots_adjust(hspace=0.6, wspace=0.25)
    return fig


def correlation_figure(names: Sequence[str], corr: np.ndarray) -> Any:
    """Heat map of the parameter correlation matrix (−1 … 1)."""
    n = len(names)
    ax = axes_or_new(None, figsize=(1.2 + 0.5 * n, 1.0 + 0.45 * n))
    im = ax.imshow(np.asarray(corr), vmin=-1, vmax=1, cmap="RdBu_r")
    ax.set_xticks(range(n))
    ax.set_yticks(range(n))
    ax.set_xticklabels(names, rotation=90, fontsize=7)
    ax.set_yticklabels(names, fontsize=7)
    for i in range(n):
        for j in range(n):
            ax.text(j, i, f"{corr[i][j]:.2f}", ha="center", va="center", fontsize=5)
    ax.figure.colorbar(im, ax=ax, shrink=0.8, label="ρ")
    ax.set_title("parameter correlation")
    return ax.figure
