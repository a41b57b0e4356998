"""Vehicle simulation figures: 3-D path and the twelve states against time (LI2021 Figs. 12–14)."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.plot._mpl import pyplot

LABELS = (("x (m)", "y (m)", "z (m)", "φ (°)", "θ (°)", "ψ (°)"),
          ("u (m/s)", "v (m/s)", "w (m/s)", "p (°/s)", "q (°/s)", "r (°/s)"))


def states_figure(traj: Any, title: str = "") -> Any:
    """Twelve panels: position and attitude (top two rows), velocities (bottom two rows)."""
    plt = pyplot()
    fig, axes = plt.subplots(4, 3, figsize=(10, 8.5), sharex=True)
    t = traj.time
    for k in range(6):
        ax = axes.flat[k]
        y = traj.eta[:, k] * (180 / np.pi if k >= 3 else 1.0)
        ax.plot(t, y, lw=1.0)
        ax.set_ylabel(LABELS[0][k])
        ax.grid(alpha=0.3)
        ax2 = axes.flat[6 + k]
        y2 = traj.nu[:, k] * (180 / np.pi if k >= 3 else 1.0)
        ax2.plot(t, y2, lw=1.0, color="C1")
        ax2.set_ylabel(LABELS[1][k])
        ax2.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def path_figure(traj: Any, title: str = "") -> Any:
    """3-D path in NED (z drawn downwards)."""
    plt = pyplot()
    fig = plt.figure(figsize=(6.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    x, y, z = traj.eta[:, 0], traj.eta[:, 1], traj.eta[:, 2]
    ax.plot(y, x, z, lw=1.2)
    ax.scatter([y[0]], [x[0]], [z[0]], color="C2", label="start")
    ax.scatter([y[-1]], [x[-1]], [z[-1]], color="C3", label="end")
    ax.set_xlabel("east y (m)")
    ax.set_ylabel("north x (m)")
    ax.set_zlabel("down z (m)")
    ax.invert_zaxis()
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    return fig
