"""Figures of a closed-loop mission: path in 3-D and projections, tracking error, thrusters.

Each function returns a matplotlib Figure (Agg); the caller
renders it to PNG bytes with :func:`hydrokit.plot._mpl.to_png`.
Plan views are drawn as charts: east (NED y) across, north (NED x) up, equal scales; depth is
drawn positive downwards (NED z), as in LI2021 Figs. 16–17.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from hydrokit.model.control import wrap_angle
from hydrokit.model.guidance import path_distance
from hydrokit.plot._mpl import axes_or_new, new_figure
from hydrokit.simulate.closed_loop import ClosedLoopResult

#: axis labels of every mission figure: plan views as charts (east across, north up), depth down
EAST = "east y (m)"
NORTH = "north x (m)"
DEPTH = "depth z (m)"


def path_figure(runs: Mapping[str, ClosedLoopResult], title: str = "") -> Any:
    """3-D path and its plan (east across, north up, as a chart), north–depth and east–depth
    views; planned path dashed, one line per run (m).

    ``runs`` maps a label (e.g. "PID", "S-plane") to a result; all share the planned path.
    """
    first = next(iter(runs.values()))
    wp = first.path.points
    fig = new_figure((11, 8.5))
    ax3 = fig.add_subplot(2, 2, 1, projection="3d")
    ax3.plot(wp[:, 1], wp[:, 0], wp[:, 2], "k--", lw=1.2, label="planned")
    ax3.scatter(wp[:, 1], wp[:, 0], wp[:, 2], c="k", s=14)
    for label, res in runs.items():
        ax3.plot(res.eta[:, 1], res.eta[:, 0], res.eta[:, 2], lw=1.3, label=label)
    ax3.set_xlabel(EAST)
    ax3.set_ylabel(NORTH)
    ax3.set_zlabel(DEPTH)
    ax3.invert_zaxis()
    ax3.legend(fontsize=8)
    # (horizontal, vertical) NED indices of each view: the plan as a chart, then side views
    panels = [
        ((1, 0), EAST, NORTH, False),
        ((0, 2), NORTH, DEPTH, True),
        ((1, 2), EAST, DEPTH, True),
    ]
    for k, ((i, j), xl, yl, invert) in enumerate(panels, start=2):
        ax = fig.add_subplot(2, 2, k)
        ax.plot(wp[:, i], wp[:, j], "k--", lw=1.2, label="planned")
        ax.plot(wp[:, i], wp[:, j], "ko", ms=3)
        for label, res in runs.items():
            ax.plot(res.eta[:, i], res.eta[:, j], lw=1.3, label=label)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        if invert:
            ax.invert_yaxis()
        ax.grid(alpha=0.3)
        if (i, j) == (1, 0):
            ax.set_aspect("equal", adjustable="datalim")
    fig.suptitle(title or "Path following")
    fig.tight_layout()
    return fig


def tracking_figure(runs: Mapping[str, ClosedLoopResult], title: str = "") -> Any:
    """Distance to the path (m), depth error (m) and heading error (deg) against time (s)."""
    fig = new_figure((10, 7.5))
    axes = fig.subplots(3, 1, sharex=True)
    for label, res in runs.items():
        d = path_distance(res.eta[:, :3], res.path.points)
        axes[0].plot(res.time, d, label=label)
        axes[1].plot(res.time, res.eta[:, 2] - res.reference[:, 1], label=label)
        dpsi = np.degrees([wrap_angle(a - b) for a, b in zip(res.eta[:, 5], res.reference[:, 2])])
        axes[2].plot(res.time, dpsi, label=label)
    axes[0].set_ylabel("distance to path [m]")
    axes[1].set_ylabel("depth error z − z_d [m]")
    axes[2].set_ylabel("heading error ψ − ψ_d [deg]")
    axes[2].set_xlabel("time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title or "Tracking error")
    fig.tight_layout()
    return fig


def thruster_figure(res: ClosedLoopResult, f_min: Any, f_max: Any, title: str = "") -> Any:
    """Actual (solid) and allocated (dotted) thrust of each thruster (N) with its limits."""
    m = len(res.thruster_names)
    fig = new_figure((10, 1.9 * m + 1))
    axes = fig.subplots(m, 1, sharex=True, squeeze=False)
    for i, name in enumerate(res.thruster_names):
        ax = axes[i, 0]
        ax.plot(res.time, res.thrust[:, i], lw=1.2, label="actual")
        ax.plot(res.time, res.thrust_demand[:, i], ":", lw=1.0, label="allocated")
        ax.axhline(float(f_max[i]), color="r", lw=0.8, ls="--")
        ax.axhline(float(f_min[i]), color="r", lw=0.8, ls="--")
        ax.set_ylabel(f"{name} [N]")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(title or "Thruster usage (limits dashed)")
    fig.tight_layout()
    return fig


def mission_axes(res: ClosedLoopResult, ax: Any = None, label: str = "flown") -> Any:
    """Planned (dashed, waypoints marked) and flown horizontal path on ``ax``; returns it."""
    ax = axes_or_new(ax)
    wp = res.path.points
    ax.plot(wp[:, 1], wp[:, 0], "k--", lw=1.0, label="planned")
    ax.plot(wp[:, 1], wp[:, 0], "ko", ms=3)
    ax.plot(res.eta[:, 1], res.eta[:, 0], lw=1.3, label=label)
    ax.set_xlabel(EAST)
    ax.set_ylabel(NORTH)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return ax


#: colours of the Monte Carlo figure: bands drawn under the lines in the hue of the identified
#: vehicle's line, which is darker so that it reads on top of them
BAND = "C0"
LINE = "#08306b"
TRUE = "C3"
#: NED axes in the spread panels: names and one hue each
AXIS_NAMES = ("north", "east", "depth")
AXIS_COLOURS = ("C2", "C1", "C4")


def envelope_figure(
    waypoints: np.ndarray,
    grid: np.ndarray,
    envelopes: Mapping[str, Mapping[str, Any]],
    nominal: Mapping[str, np.ndarray],
    truth: Mapping[str, np.ndarray] | None = None,
    title: str = "",
) -> Any:
    """Monte Carlo of a mission, one column per controller: the plan view (east across, north
    up) with sample paths under the identified vehicle's path and the truth's (when known);
    then the samples' 5–95 % and min–max bands about the identified vehicle's path against
    time (s): north and east, then depth (m), each at its own scale — a spread of centimetres
    along a path of metres vanishes in the plan view.

    Parameters
    ----------
    waypoints : (k, 3) — NED, m
    grid : (t,) — s
    envelopes : controller label → {"p5", "p95": (t, 3); optional "min", "max": (t, 3);
        "sample_paths": (n, t, 3)}, m
    nominal : controller label → (t, 3) path of the identified vehicle on ``grid``, m
    truth : controller label → (t, 3) path of the true vehicle on ``grid``, m (virtual data)
    """
    labels = list(envelopes)
    grid = np.asarray(grid, float)
    fig = new_figure((5.4 * len(labels), 11.5))
    axes = fig.subplots(3, len(labels), squeeze=False, gridspec_kw={"height_ratios": [3, 1.5, 1.3]})
    for j, label in enumerate(labels):
        env = envelopes[label]
        nom = np.asarray(nominal[label], float)
        true = np.asarray(truth[label], float) if truth is not None and label in truth else None
        paths = np.asarray(env["sample_paths"], float)
        ax = axes[0, j]
        for k, p in enumerate(paths):
            ax.plot(p[:, 1], p[:, 0], color=BAND, lw=1.0, alpha=0.35, zorder=1, label="samples" if k == 0 else None)
        ax.plot(waypoints[:, 1], waypoints[:, 0], "k--", lw=1.0, zorder=2, label="planned")
        ax.plot(waypoints[:, 1], waypoints[:, 0], "ko", ms=3, zorder=2)
        ax.plot(nom[:, 1], nom[:, 0], color=LINE, lw=0.9, zorder=3, label="identified vehicle")
        if true is not None:
            ax.plot(true[:, 1], true[:, 0], color=TRUE, lw=1.1, ls=":", zorder=4, label="true vehicle")
        ax.set_xlabel(EAST)
        ax.set_ylabel(NORTH)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        width = np.asarray(env["p95"], float)[:, :2] - np.asarray(env["p5"], float)[:, :2]
        spread = float(np.nanmax(width)) if np.isfinite(width).any() else float("nan")
        ax.set_title(f"{label}: {len(paths)} sample paths; 5–95 % spread ≤ {spread:.2g} m", fontsize=10)
        for row, ks in ((1, (0, 1)), (2, (2,))):
            ax = axes[row, j]
            for k in ks:
                name, colour = AXIS_NAMES[k], AXIS_COLOURS[k]
                _bands(ax, grid, env, k, nom[:, k], colour, (f"{name}: min–max", f"{name}: 5–95 %"))
                if true is not None:
                    ax.plot(grid, true[:, k] - nom[:, k], color=colour, lw=1.1, ls=":", zorder=4, label=f"{name}: true")
            ax.axhline(0.0, color=LINE, lw=0.9, zorder=3, label="identified")
            ax.set_ylabel(f"{' and '.join(AXIS_NAMES[k] for k in ks)} from identified (m)", fontsize=9)
            ax.set_xlabel("time (s)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, ncol=3 if len(ks) > 1 else 2)
        axes[1, j].set_title("the samples about the identified vehicle's path", fontsize=9)
    fig.suptitle(title or "Mission under coefficient uncertainty (Monte Carlo)")
    fig.tight_layout()
    return fig


def _bands(
    ax: Any, grid: np.ndarray, env: Mapping[str, Any], k: int, about: Any, colour: str, labels: tuple[Any, Any]
) -> None:
    """The min–max (light) and 5–95 % (darker) bands of NED axis ``k`` minus ``about`` (m),
    under every line of ``ax``; ``labels`` their legend entries (None: none)."""
    if "min" in env and "max" in env:
        lo, hi = np.asarray(env["min"], float)[:, k] - about, np.asarray(env["max"], float)[:, k] - about
        ax.fill_between(grid, lo, hi, color=colour, alpha=0.2, lw=0, zorder=1, label=labels[0])
    lo, hi = np.asarray(env["p5"], float)[:, k] - about, np.asarray(env["p95"], float)[:, k] - about
    ax.fill_between(grid, lo, hi, color=colour, alpha=0.45, lw=0, zorder=1.5, label=labels[1])


def fleet_axes(waypoints: np.ndarray, paths: np.ndarray | None, cross_track_rms: np.ndarray, ax: Any = None) -> Any:
    """A fleet on ``ax`` (or new axes): the kept paths (N, k, 6; plan view, m) over the
    planned path, or without paths the histogram of the copies' cross-track RMS (m)."""
    ax = axes_or_new(ax)
    if paths is None:
        v = np.asarray(cross_track_rms, float)
        ax.hist(v[np.isfinite(v)], bins=min(30, max(5, v.size // 5)), color="C0", alpha=0.8)
        ax.set_xlabel("cross-track RMS (m)")
        ax.set_ylabel("copies")
        ax.grid(alpha=0.3)
        return ax
    for k, p in enumerate(paths[:200]):
        ax.plot(p[:, 1], p[:, 0], color="C0", lw=0.6, alpha=0.5, label="copies" if k == 0 else None)
    ax.plot(waypoints[:, 1], waypoints[:, 0], "k--", lw=1.0, label="planned")
    ax.plot(waypoints[:, 1], waypoints[:, 0], "ko", ms=3)
    ax.set_xlabel(EAST)
    ax.set_ylabel(NORTH)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def convergence_figure(best: Any, before: float, title: str = "") -> Any:
    """Gain tuning: the best cost after each generation (sequence of floats, m-equivalent) and
    the hand-picked gains' cost."""
    fig = new_figure((6.4, 4.0))
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(np.arange(len(best)), best, "o-", ms=3, label="best so far")
    ax.axhline(before, color="k", ls="--", lw=1.0, label="hand-picked gains")
    ax.set_xlabel("generation (0: the initial population)")
    ax.set_ylabel("cost (m-equivalent)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
