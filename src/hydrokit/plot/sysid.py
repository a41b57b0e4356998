"""Figures of system identification (issue #44): measured vs simulated channels with the Monte
Carlo band, residuals, and the parameter correlation heat map."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
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


#: the order a reader expects the channels in: position, attitude, linear and angular velocity
CHANNEL_ORDER = ("x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r")
#: channels that are angles: drawn wrapped to (−π, π]
ANGLES = frozenset({"phi", "theta", "psi"})

#: font sizes (pt) chosen for the report's figures, embedded at 70 dpi: 11 pt is 10.7 px there,
#: 10.5 pt is 10.2 px (matplotlib's 7 pt legends were 6.8 px, 5 pt cell numbers 4.9 px)
LABEL_PT = 11.0
TICK_PT = 10.5
LEGEND_PT = 10.5

#: most points drawn per line (a 90 s channel at 50 Hz has 4500: drawing them all is slow and
#: shows nothing more at report size)
MAX_POINTS = 600


def channel_order(names: Iterable[str]) -> list[str]:
    """``names`` in the natural order x y z φ θ ψ u v w p q r; any other channel after them in
    the order given."""
    names = list(dict.fromkeys(names))
    known = [c for c in CHANNEL_ORDER if c in names]
    return known + [c for c in names if c not in CHANNEL_ORDER]


def wrap_pi(a: Any) -> np.ndarray:
    """Angles (rad, any value) wrapped to (−π, π] (rad)."""
    return np.pi - np.mod(np.pi - np.asarray(a, float), 2 * np.pi)


def pieces(values: np.ndarray) -> list[slice]:
    """Slices of ``values`` (a wrapped angle, rad) between its jumps across ±π, so that a line
    drawn piece by piece has no vertical stroke where the angle wraps."""
    jumps = np.flatnonzero(np.abs(np.diff(values)) > np.pi) + 1
    edges = [0, *jumps.tolist(), len(values)]
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def _thin(*arrays: Any) -> list[np.ndarray]:
    n = len(arrays[0])
    step = max(1, -(-n // MAX_POINTS))
    return [np.asarray(a, float)[::step] for a in arrays]


def _style(ax: Any) -> None:
    ax.xaxis.label.set_fontsize(LABEL_PT)
    ax.yaxis.label.set_fontsize(LABEL_PT)
    ax.tick_params(labelsize=TICK_PT)


def prediction_axes(prediction: Mapping[str, Any], ax: Any = None, channel: str | None = None) -> Any:
    """One channel of one run (default: the first in :data:`CHANNEL_ORDER`): measured points,
    simulation, 95 % band. Angles (φ, θ, ψ) are wrapped to (−π, π] rad; the simulation and its
    band are drawn piece by piece between wraps."""
    ax = axes_or_new(ax)
    chans = prediction["channels"]
    c = channel or channel_order(chans)[0]
    d = chans[c]
    t, y, sim, lo, hi = _thin(d["time"], d["measured"], d["simulated"], d["low"], d["high"])
    if c in ANGLES:
        wrapped = wrap_pi(sim)
        shift = wrapped - sim  # a whole number of turns: the band moves with its line
        sim, lo, hi, y = wrapped, lo + shift, hi + shift, wrap_pi(y)
        if np.ptp(sim) > np.pi:  # it goes round: show the whole circle
            ax.set_ylim(-1.05 * np.pi, 1.05 * np.pi)
    for k, s in enumerate(pieces(sim) if c in ANGLES else [slice(None)]):
        first = k == 0
        ax.fill_between(t[s], lo[s], hi[s], color="C1", alpha=0.3, lw=0, label="95 % (covariance)" if first else None)
        ax.plot(t[s], sim[s], "-", lw=1.2, color="C1", label="simulated" if first else None)
    ax.plot(t, y, ".", ms=2.5, color="C0", label="measured")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(LABELS.get(c, f"{c} (SI)"))
    held = " (held out)" if prediction.get("holdout") else ""
    ax.set_title(f"{prediction['name']}{held}", fontsize=LABEL_PT)
    ax.legend(loc="best", fontsize=LEGEND_PT)
    _style(ax)
    return ax


def run_figure(prediction: Mapping[str, Any]) -> Any:
    """Every channel of a run in the order x y z φ θ ψ u v w p q r, measured vs simulated
    (angles wrapped to (−π, π] rad)."""
    chans = channel_order(prediction["channels"])
    n = len(chans)
    cols = 2
    rows = (n + cols - 1) // cols
    fig = new_figure((11, 2.7 * rows))
    for k, c in enumerate(chans):
        ax = fig.add_subplot(rows, cols, k + 1)
        prediction_axes(prediction, ax, c)
        if k:
            ax.set_title("")
            leg = ax.get_legend()
            if leg is not None:
                leg.remove()
    fig.subplots_adjust(hspace=0.7, wspace=0.3)
    return fig


def residual_figure(predictions: Sequence[Mapping[str, Any]]) -> Any:
    """Residuals (measured − simulated, SI; angles wrapped to (−π, π] rad) of every run and
    channel, one panel per channel in the order x y z φ θ ψ u v w p q r."""
    chans = channel_order(c for p in predictions for c in p["channels"])
    fig = new_figure((11, 2.0 * max(len(chans), 1)))
    for k, c in enumerate(chans):
        ax = fig.add_subplot(len(chans), 1, k + 1)
        for j, p in enumerate(predictions):
            if c in p["channels"]:
                d = p["channels"][c]
                t, y, sim = _thin(d["time"], d["measured"], d["simulated"])
                r = wrap_pi(y - sim) if c in ANGLES else y - sim
                for i, s in enumerate(pieces(r) if c in ANGLES else [slice(None)]):
                    ax.plot(t[s], r[s], lw=0.8, color=f"C{j % 10}", label=p["name"] if i == 0 else None)
        ax.set_ylabel(LABELS.get(c, f"{c} (SI)"))
        _style(ax)
    if fig.axes:
        fig.axes[0].legend(loc="upper right", fontsize=LEGEND_PT, ncol=4)
        fig.axes[-1].set_xlabel("time (s)", fontsize=LABEL_PT)
    fig.subplots_adjust(hspace=0.7, wspace=0.25)
    return fig


def cell_text_colour(rgba: Sequence[float]) -> str:
    """ "black" or "white", whichever contrasts more with a cell of colour ``rgba`` (WCAG 2.1
    contrast ratio of relative luminances)."""
    lum = relative_luminance(rgba)
    return "black" if (lum + 0.05) / 0.05 >= 1.05 / (lum + 0.05) else "white"


def relative_luminance(rgba: Sequence[float]) -> float:
    """Relative luminance (0 black … 1 white) of an sRGB colour with channels in 0…1
    (WCAG 2.1, after IEC 61966-2-1 linearisation)."""
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgba[:3]]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def correlation_figure(names: Sequence[str], corr: np.ndarray) -> Any:
    """Heat map of the parameter correlation matrix (−1 … 1, dimensionless); each cell's number
    in black or white, whichever reads better on the cell's colour."""
    n = len(names)
    corr = np.asarray(corr, float)
    side = 2.4 + 0.62 * n
    ax = axes_or_new(None, figsize=(side + 1.2, side))
    im = ax.imshow(corr, vmin=-1, vmax=1, cmap="RdBu_r")
    ax.set_xticks(range(n))
    ax.set_yticks(range(n))
    ax.set_xticklabels(names, rotation=90, fontsize=TICK_PT)
    ax.set_yticklabels(names, fontsize=TICK_PT)
    for i in range(n):
        for j in range(n):
            colour = cell_text_colour(im.cmap(im.norm(corr[i, j])))
            text = f"{corr[i, j]:.2f}".replace("-0.00", "0.00")  # no signed zero
            ax.text(j, i, text, ha="center", va="center", fontsize=TICK_PT, color=colour)
    bar = ax.figure.colorbar(im, ax=ax, shrink=0.8)
    bar.set_label("correlation ρ (–)", fontsize=LABEL_PT)
    bar.ax.tick_params(labelsize=TICK_PT)
    ax.set_title("parameter correlation (–)", fontsize=LABEL_PT)
    return ax.figure
