"""Thrust allocation: thrust per thruster against its limits."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new


def allocation_axes(names: list[str], thrust: np.ndarray, f_min: Any, f_max: Any, ax: Any = None) -> Any:
    """Bars of the allocated thrust (N) per thruster with its limits as whiskers; returns the axes."""
    ax = axes_or_new(ax)
    x = np.arange(len(names))
    limited = f_min is not None and f_max is not None
    ax.bar(
        x,
        thrust,
        color=["C3" if (f <= lo + 1e-9 or f >= hi - 1e-9) else "C0" for f, lo, hi in zip(thrust, f_min, f_max)]
        if limited
        else "C0",
    )
    if limited:
        ax.plot(x, f_min, "_", ms=14, color="0.3", label="limits")
        ax.plot(x, f_max, "_", ms=14, color="0.3")
        ax.legend(fontsize=8)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xticks(x, names, rotation=30, fontsize=8)
    ax.set_ylabel("thrust (N)")
    ax.grid(alpha=0.3, axis="y")
    return ax
