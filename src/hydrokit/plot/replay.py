"""Figures of a trial replay (``hydrokit manoeuvre --replay``): the measured and the predicted
track overlaid (east across, north up, metres from the measured execute point, equal scales),
and both headings with the logged deflections against time (degrees at this edge)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure


def tracks_axes(res: Any, ax: Any = None) -> Any:
    """The measured (solid) and predicted (dashed) tracks with the execute point and the later
    executes marked on each; with ``--samples`` the drawn vehicles' predicted tracks thin and grey
    beneath; returns the axes."""
    ax = axes_or_new(ax)
    tracks = getattr(res.predicted, "sample_tracks", None) or []
    for k, tr in enumerate(tracks):
        label = f"{len(tracks)} drawn vehicles" if k == 0 else None
        ax.plot(tr[:, 2], tr[:, 1], lw=0.6, color="0.45", alpha=0.3, zorder=1, label=label)
    for r, style, label in ((res.measured, "-", "measured"), (res.predicted, "--", "predicted")):
        x, y = r.eta[:, 0], r.eta[:, 1]
        (line,) = ax.plot(y, x, style, lw=1.4, label=label)
        for t in r.executes[1:]:
            k = min(int(np.searchsorted(r.time, t)), r.time.size - 1)
            ax.plot(y[k], x[k], "v", color=line.get_color(), ms=5)
    ax.plot([0], [0], "ko", ms=5, label="execute")
    ax.set_xlabel("east y from the execute point [m]")
    ax.set_ylabel("north x from the execute point [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"{res.vehicle} replaying {res.trial}: {res.kind.replace('_', ' ')}")
    return ax


def time_figure(res: Any) -> Any:
    """Heading change (measured, predicted; the check angles ±B dashed), yaw rate and the logged
    deflections against time from the execute, s."""
    fig = new_figure((9.0, 7.5))
    axes = fig.subplots(3, 1, sharex=True)
    m = res.measured
    k0 = min(int(np.searchsorted(m.time, 0.0)), m.time.size - 1)
    for r, style, label in ((res.measured, "-", "measured"), (res.predicted, "--", "predicted")):
        psi = np.unwrap(r.eta[:, 5])
        axes[0].plot(r.time, np.degrees(psi - psi[k0]), style, lw=1.3, label=label)
        axes[1].plot(r.time, r.nu[:, 5], style, lw=1.3, label=label)
    b = m.manoeuvre.check_angle
    if b:
        for s in (1, -1):
            axes[0].axhline(s * math.degrees(b), color="0.5", ls="--", lw=0.8)
    axes[0].set_ylabel("heading change [deg]")
    axes[0].legend(fontsize=8)
    axes[1].set_ylabel("yaw rate r [rad/s]")
    for j, name in enumerate(m.surface_names):
        axes[2].plot(m.time, np.degrees(m.deflection[:, j]), lw=1.2, label=name)
    axes[2].set_ylabel("logged deflection [deg]")
    axes[2].legend(fontsize=8)
    axes[-1].set_xlabel("time from the execute [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        for t in m.executes:
            ax.axvline(t, color="C1", lw=0.6, alpha=0.6)
    fig.suptitle(f"{res.vehicle} replaying {res.trial}: {res.kind.replace('_', ' ')} (executes marked)")
    fig.tight_layout()
    return fig


def figures(res: Any) -> dict[str, Any]:
    """The replay's figures by file name: track.png (both tracks) and time.png."""
    fig = new_figure((7.5, 7.0))
    tracks_axes(res, fig.add_subplot(1, 1, 1))
    fig.tight_layout()
    return {"track.png": fig, "time.png": time_figure(res)}
