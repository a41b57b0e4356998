"""Coefficients from geometry: added-mass diagonal, full transform vs diagonal-only (REHMAN)."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.plot._mpl import axes_or_new


def added_mass_axes(full: np.ndarray, diagonal_only: np.ndarray, ax: Any = None, title: str = "") -> Any:
    """Paired bars of the added-mass diagonal (kg for surge–heave, kg·m² for roll–yaw, log
    scale) with the full 6×6 transform and REHMAN's diagonal-only sum; returns the axes."""
    ax = axes_or_new(ax)
    x = np.arange(6)
    ax.bar(x - 0.2, full, 0.4, label="full 6×6 transform")
    ax.bar(x + 0.2, diagonal_only, 0.4, label="diagonal only (REHMAN)")
    ax.set_xticks(x, list(DOF_NAMES))
    ax.set_ylabel("added mass (kg, kg·m²)")
    if np.all(np.concatenate([full, diagonal_only]) > 0):
        ax.set_yscale("log")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    if title:
        ax.set_title(title, fontsize=9)
    return ax
