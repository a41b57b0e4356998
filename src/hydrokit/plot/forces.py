"""Force–speed data with the Chin and Morison fits (CELY2019 Fig. 16)."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure


def force_fit_figure(U: np.ndarray, F: np.ndarray, fit: Any, title: str = "") -> Any:
    """Data points and both fitted curves; ``fit`` is an estimate.forces.ForceFit."""
    fig = new_figure((6, 4))
    ax = force_fit_axes(U, F, fit, fig.subplots())
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    return fig


def force_fit_axes(U: np.ndarray, F: np.ndarray, fit: Any, ax: Any = None) -> Any:
    """Data (speed m/s, force N) and both fitted curves on ``ax`` (or new axes); returns it."""
    ax = axes_or_new(ax)
    ax.plot(U, F, "o", ms=4, color="0.3", label="data")
    u = np.linspace(min(0.0, U.min()), U.max(), 200)
    ax.plot(u, fit.chin(u), "-", label=f"Chin: K_L = {fit.K_L:.4g}, K_Q = {fit.K_Q:.4g} (R² = {fit.r2_chin:.4f})")
    ax.plot(
        u, fit.morison(u), "--", label=f"Morison: K_D = {fit.K_D:.4g}, C_D = {fit.C_D:.4g} (R² = {fit.r2_morison:.4f})"
    )
    ax.set_xlabel("speed (m/s)")
    ax.set_ylabel("force (N)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return ax
