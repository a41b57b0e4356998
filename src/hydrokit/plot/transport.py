"""Transport runs: 3-D path of the assembly and its parts, joint separations, joint loads."""

from __future__ import annotations

from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure, to_png


def path_axes(res: Any, ax: Any = None) -> Any:
    """3-D path (east across, north into the page as on a chart, height −z up) of the
    assembly origin and every part's origin, start and end marked; returns the axes."""
    ax = axes_or_new(ax, figsize=(6.4, 5.2), projection="3d")
    for name, S in res.parts.items():
        ax.plot(S[:, 1], S[:, 0], -S[:, 2], lw=1.0, label=name)
        ax.scatter([S[-1, 1]], [S[-1, 0]], [-S[-1, 2]], s=10)
    A = res.assembly
    ax.plot(A[:, 1], A[:, 0], -A[:, 2], "k--", lw=1.2, label="assembly origin")
    ax.scatter([A[0, 1]], [A[0, 0]], [-A[0, 2]], c="k", marker="o", s=20)
    ax.set_xlabel("east y (m)")
    ax.set_ylabel("north x (m)")
    ax.set_zlabel("height −z (m)")
    ax.set_title(f"Transport, {res.model} model", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    return ax


def separation_axes(res: Any, ax: Any = None) -> Any:
    """Separation at every joint over time (m); returns the axes."""
    ax = axes_or_new(ax)
    for k, name in enumerate(res.joint_names):
        ax.plot(res.time, res.separation[:, k], label=f"joint {name}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("separation (m)")
    ax.set_title(
        {
            "rigid": "Rigid: joints cannot separate",
            "multibody": "Joined bodies: joint-point mismatch",
            "independent": "Separate bodies: how far the groups pull apart",
        }.get(res.model, res.model),
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    if res.joint_names:
        ax.legend(fontsize=7)
    return ax


def loads_figure(res: Any) -> Any:
    """Joint force (N) and moment (N·m) magnitudes and components over time, one row per joint."""
    n = max(1, len(res.joint_names))
    fig = new_figure((9.0, 2.2 * n + 0.6))
    for k, name in enumerate(res.joint_names):
        L = res.loads[:, k]
        for col, (sl, unit, lab) in enumerate(((slice(0, 3), "N", "f"), (slice(3, 6), "N·m", "m"))):
            ax = fig.add_subplot(n, 2, 2 * k + col + 1)
            for a, axis in zip(range(sl.start, sl.stop), "xyz"):
                ax.plot(res.time, L[:, a], lw=0.9, label=f"{lab}{axis}")
            ax.plot(res.time, np.linalg.norm(L[:, sl], axis=1), "k--", lw=1.0, label="|·|")
            ax.set_ylabel(f"{name} ({unit})", fontsize=8)
            ax.grid(alpha=0.3)
            if k == 0:
                ax.set_title("force on the child subtree" if col == 0 else "moment about the joint point", fontsize=9)
                ax.legend(fontsize=7, ncol=4)
            if k == n - 1:
                ax.set_xlabel("time (s)")
    fig.tight_layout()
    return fig


def figure_bytes(res: Any) -> dict[str, bytes]:
    """PNG files of a run: ``path.png``, ``separation.png``, ``loads.png``."""
    out = {"path.png": to_png(path_axes(res).figure), "separation.png": to_png(separation_axes(res).figure)}
    out["loads.png"] = to_png(loads_figure(res))
    return out
