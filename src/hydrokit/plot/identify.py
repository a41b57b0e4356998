"""Identification figures: fit and residual per launch; coefficients against Reynolds number
(what CELY2019 Figs. 8, 11–13 and 17–19 show)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hydrokit.plot._mpl import pyplot


def launch_fit(t: np.ndarray, y: np.ndarray, fitted: np.ndarray, title: str, unit: str, ax: Any = None) -> Any:
    """Measured vs fitted signal (top) and residual (bottom). Returns the figure.

    Parameters
    ----------
    t : s; y, fitted : signal in ``unit`` (m or rad — shown in mm or degrees)
    """
    plt = pyplot()
    scale, label = (1e3, "position (mm)") if unit == "m" else (180 / np.pi, "angle (°)")
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 4.2), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    a1.plot(t, y * scale, ".", ms=2.5, color="0.35", label="measured")
    a1.plot(t, fitted * scale, "-", lw=1.2, color="C0", label="fitted")
    a1.set_ylabel(label)
    a1.set_title(title, fontsize=9)
    a1.legend(loc="upper right", fontsize=8)
    a2.plot(t, (y - fitted) * scale, "-", lw=0.7, color="C3")
    a2.axhline(0, color="0.5", lw=0.5)
    a2.set_ylabel("residual")
    a2.set_xlabel("time after release (s)")
    fig.tight_layout()
    return fig


def coefficients_vs_reynolds(groups: dict[str, Sequence[Any]], title: str = "") -> Any:
    """C_m, C_D, K_L and K_Q per launch against the peak Reynolds number, one colour per group
    (axis or method). ``groups`` maps a label to LaunchResults."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(8, 5.5))
    panels = (("added_mass_coefficient", "C_m = m_a/(ρV)"), ("drag_coefficient", "C_D"),
              ("linear_damping", "K_L"), ("quadratic_damping", "K_Q"))
    for ax, (field, label) in zip(axes.flat, panels):
        for i, (name, results) in enumerate(groups.items()):
            re = [r.reynolds_max for r in results if getattr(r, field) is not None]
            v = [getattr(r, field) for r in results if getattr(r, field) is not None]
            if v:
                ax.plot(re, v, "o", ms=4, color=f"C{i}", label=name)
        ax.set_xscale("log")
        ax.set_ylabel(label)
        ax.set_xlabel("peak Reynolds number")
        ax.grid(alpha=0.3)
    axes.flat[0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def drag_per_cycle(cycles: Sequence[dict[str, Any]], title: str = "") -> Any:
    """C_D of each cycle against the cycle's Reynolds number (log-decrement; CELY2019 Fig. 18)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    re = [c["reynolds"] for c in cycles if c.get("drag_coefficient") is not None]
    cd = [c["drag_coefficient"] for c in cycles if c.get("drag_coefficient") is not None]
    ax.plot(re, cd, "o", ms=4)
    ax.set_xscale("log")
    ax.set_xlabel("cycle peak Reynolds number")
    ax.set_ylabel("C_D per cycle")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
