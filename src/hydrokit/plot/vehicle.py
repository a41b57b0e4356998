"""Vehicle simulation figures: 3-D path and the twelve states against time (LI2021 Figs. 12–14)."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure

LABELS = (
    ("x (m)", "y (m)", "z (m)", "φ (°)", "θ (°)", "ψ (°)"),
    ("u (m/s)", "v (m/s)", "w (m/s)", "p (°/s)", "q (°/s)", "r (°/s)"),
)


def states_figure(traj: Any, title: str = "") -> Any:
    """Twelve panels: position and attitude (top two rows), velocities (bottom two rows)."""
    fig = new_figure((10, 8.5))
    axes = fig.subplots(4, 3, sharex=True)
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
    fig = new_figure((6.5, 5.5))
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


def path_axes(traj: Any, ax: Any = None, label: str | None = None) -> Any:
    """Horizontal path (east y across, north x up) of a trajectory on ``ax`` (or new axes).

    ``traj`` has ``eta`` (n, 6) in m and rad. Returns the axes.
    """
    ax = axes_or_new(ax)
    x, y = traj.eta[:, 0], traj.eta[:, 1]
    line = ax.plot(y, x, lw=1.2, label=label)[0]
    ax.plot([y[0]], [x[0]], "o", ms=4, color=line.get_color())
    ax.set_xlabel("east y (m)")
    ax.set_ylabel("north x (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    return ax


def batch_axes(time: np.ndarray, states: np.ndarray, ax: Any = None) -> Any:
    """Horizontal paths of a batch (states (n_vehicles, n_out, ≥ 2): x, y in m) on ``ax``."""
    ax = axes_or_new(ax)
    for k in range(states.shape[0]):
        ax.plot(states[k, :, 1], states[k, :, 0], lw=0.8, alpha=0.6)
    ax.set_xlabel("east y (m)")
    ax.set_ylabel("north x (m)")
    ax.set_title(f"{states.shape[0]} vehicles, {time[-1]:.4g} s", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def envelope_figure(time: np.ndarray, env: dict[str, np.ndarray], nominal: Any = None, title: str = "") -> Any:
    """Six panels, u v w (m/s) and p q r (°/s) against time (s): the 5–95 % band and min–max of
    sampled runs (``env`` band → (t, 12) states, SI) and the nominal run's velocity when given."""
    fig = new_figure((10, 5.5))
    axes = fig.subplots(2, 3, sharex=True)
    for k in range(6):
        ax = axes.flat[k]
        f = 180 / np.pi if k >= 3 else 1.0
        j = 6 + k
        ax.fill_between(time, env["min"][:, j] * f, env["max"][:, j] * f, color="C0", alpha=0.15, label="min–max")
        ax.fill_between(time, env["p5"][:, j] * f, env["p95"][:, j] * f, color="C0", alpha=0.35, label="5–95 %")
        ax.plot(time, env["p50"][:, j] * f, color="C0", lw=0.8, label="median")
        if nominal is not None:
            ax.plot(nominal.time, nominal.nu[:, k] * f, color="C3", lw=1.0, ls="--", label="nominal")
        ax.set_ylabel(LABELS[1][k])
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes.flat[0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
