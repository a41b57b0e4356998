"""Figures of ``hydrokit sysid compare`` (issue #48 item 5): the held-out error of each candidate
model structure, channel by channel."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new
from hydrokit.plot.sysid import LABEL_PT, LEGEND_PT, TICK_PT, channel_order

_SYMBOL = {"phi": "φ", "theta": "θ", "psi": "ψ"}


def heldout_axes(names: Sequence[str], nrmse: Sequence[Mapping[str, float]], ax: Any = None) -> Any:
    """Grouped bars: per channel (x), one bar per candidate of its held-out NRMSE (unit-free:
    RMS error / standard deviation of the measured channel); a channel a candidate has no value
    for is left empty. Returns the axes.

    Parameters
    ----------
    names : candidate names (legend)
    nrmse : per candidate, channel → held-out NRMSE (unit-free)
    ax : matplotlib axes or None (a new figure)
    """
    channels = channel_order([c for d in nrmse for c in d])
    ax = axes_or_new(ax, figsize=(max(6.4, 0.7 * len(channels) * max(len(names), 2) / 2 + 2), 4.0))
    x = np.arange(len(channels))
    width = 0.8 / max(len(names), 1)
    for i, (n, d) in enumerate(zip(names, nrmse)):
        vals = [d.get(c, np.nan) for c in channels]
        ax.bar(x + (i - (len(names) - 1) / 2) * width, vals, width, label=n)
    ax.set_xticks(x, [_SYMBOL.get(c, c) for c in channels])
    ax.set_xlabel("channel")
    ax.set_ylabel("held-out NRMSE (–)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=LEGEND_PT, title="candidate", title_fontsize=LEGEND_PT)
    ax.xaxis.label.set_fontsize(LABEL_PT)
    ax.yaxis.label.set_fontsize(LABEL_PT)
    ax.tick_params(labelsize=TICK_PT)
    return ax


def heldout_figure(names: Sequence[str], nrmse: Sequence[Mapping[str, float]]) -> Any:
    """The figure of :func:`heldout_axes` (for the report)."""
    return heldout_axes(names, nrmse).figure


__all__ = ["heldout_axes", "heldout_figure"]
