"""Figures of a standard manoeuvre: the track with its metrics drawn on it, and the heading
(or pitch, depth) and the deflection against time. Positions are from the execute point
(east across, north up, metres, equal scales); angles in degrees at this edge."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure


def track_axes(res: Any, ax: Any = None) -> Any:
    """The horizontal track (east y across, north x up, m) with the execute point, and for a
    turning circle the advance, transfer and tactical diameter drawn as dimension lines and the
    steady circle dashed; with ``--samples`` the drawn vehicles' tracks thin and grey beneath,
    and the 95 % intervals of the drawn metrics in their labels; returns the axes."""
    ax = axes_or_new(ax)
    x, y = res.eta[:, 0], res.eta[:, 1]
    tracks = getattr(res, "sample_tracks", None) or []
    for k, tr in enumerate(tracks):
        label = f"{len(tracks)} drawn vehicles" if k == 0 else None
        ax.plot(tr[:, 2], tr[:, 1], lw=0.6, color="0.45", alpha=0.3, zorder=1, label=label)
    ax.plot(y, x, lw=1.4, label="track", zorder=3)
    ax.plot([0], [0], "ko", ms=5, label="execute")
    m = res.metrics
    if res.kind == "turning_circle" and m.get("advance") is not None:
        psi0 = float(res.eta[np.searchsorted(res.time, 0.0), 5])
        c, s = math.cos(psi0), math.sin(psi0)
        side = 1.0 if m["direction"] == "starboard" else -1.0

        def pt(a: float, b: float) -> tuple[float, float]:  # along, across → (east, north)
            return s * a + c * side * b, c * a - s * side * b

        adv, tr = m["advance"], m["transfer"]
        for (a0, b0), (a1, b1), label in (
            ((0, 0), (adv, 0), f"advance {adv:.3g} m{_interval(res, 'advance')}"),
            ((adv, 0), (adv, tr), f"transfer {tr:.3g} m{_interval(res, 'transfer')}"),
        ):
            (e0, n0), (e1, n1) = pt(a0, b0), pt(a1, b1)
            ax.annotate("", (e1, n1), (e0, n0), arrowprops={"arrowstyle": "<->", "color": "0.3"})
            ax.text(0.5 * (e0 + e1), 0.5 * (n0 + n1), label, fontsize=8, color="0.2")
        if m.get("tactical_diameter") is not None:
            td = m["tactical_diameter"]
            (e0, n0), (e1, n1) = pt(-0.1 * td, 0), pt(-0.1 * td, td)
            ax.annotate("", (e1, n1), (e0, n0), arrowprops={"arrowstyle": "<->", "color": "C3"})
            ax.text(
                0.5 * (e0 + e1),
                0.5 * (n0 + n1),
                f"tactical diameter {td:.3g} m{_interval(res, 'tactical_diameter')}",
                fontsize=8,
                color="C3",
            )
        if m.get("steady_turning_diameter") is not None:
            from hydrokit.manoeuvre.metrics import fit_circle

            tail = res.time >= (res.time[-1] - 0.5 * (res.time[-1] - m["time_to_180_deg"]))
            cx, cy, r = fit_circle(x[tail], y[tail])
            th = np.linspace(0, 2 * np.pi, 200)
            ax.plot(
                cy + r * np.sin(th),
                cx + r * np.cos(th),
                "k--",
                lw=0.8,
                label=f"steady circle ⌀ {m['steady_turning_diameter']:.3g} m",
            )
    for t in res.executes[1:]:
        k = int(np.searchsorted(res.time, t))
        ax.plot(y[k], x[k], "v", color="C1", ms=5)
    ax.set_xlabel("east y from the execute point [m]")
    ax.set_ylabel("north x from the execute point [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"{res.vehicle}: {res.kind.replace('_', ' ')}")
    return ax


def _interval(res: Any, key: str) -> str:
    """`` (95 %: a–b)`` of a metric drawn from the covariance (empty without ``--samples``)."""
    iv = (getattr(res, "intervals", None) or {}).get(key)
    if not iv or iv["low95"] is None:
        return ""
    return f" (95 %: {iv['low95']:.3g}–{iv['high95']:.3g})"


def track_figure(res: Any) -> Any:
    """A figure holding :func:`track_axes`."""
    fig = new_figure((7.5, 7.0))
    track_axes(res, fig.add_subplot(1, 1, 1))
    fig.tight_layout()
    return fig


def time_figure(res: Any) -> Any:
    """Heading change (or pitch and depth change for the vertical manoeuvres), yaw rate and every
    surface's deflection against time from the execute (s), and for a 6-DOF vehicle's horizontal
    manoeuvre the depth change; the check angles ±B dashed."""
    vertical = res.kind in ("depth_change", "vertical_zigzag")
    depth = not vertical and not res.planar  # a 6-DOF vehicle's turn: the depth it held (or lost)
    fig = new_figure((9.0, 9.5 if depth else 7.5))
    axes = fig.subplots(4 if depth else 3, 1, sharex=True)
    k0 = int(np.searchsorted(res.time, 0.0))
    ang = 4 if vertical else 5
    change = np.degrees(np.unwrap(res.eta[:, ang]) - res.eta[k0, ang])
    axes[0].plot(res.time, change, lw=1.3)
    axes[0].set_ylabel(("pitch" if vertical else "heading") + " change [deg]")
    b = res.manoeuvre.check_angle
    if b:
        for s in (1, -1):
            axes[0].axhline(s * math.degrees(b), color="0.5", ls="--", lw=0.8)
    if vertical:
        for tr in getattr(res, "sample_tracks", None) or []:
            j0 = int(np.searchsorted(tr[:, 0], 0.0))
            axes[1].plot(tr[:, 0], tr[:, 3] - tr[j0, 3], lw=0.6, color="0.45", alpha=0.3)
        axes[1].plot(res.time, res.eta[:, 2] - res.eta[k0, 2], lw=1.3)
        axes[1].set_ylabel("depth change [m]")
        axes[1].invert_yaxis()
    else:
        axes[1].plot(res.time, res.nu[:, 5], lw=1.3)
        axes[1].set_ylabel("yaw rate r [rad/s]")
    for j, name in enumerate(res.surface_names):
        axes[2].plot(res.time, np.degrees(res.deflection[:, j]), lw=1.2, label=name)
    axes[2].set_ylabel("deflection [deg]")
    axes[2].legend(fontsize=8)
    if depth:
        axes[3].plot(res.time, res.eta[:, 2] - res.eta[k0, 2], lw=1.3)
        axes[3].set_ylabel("depth change [m]")
        axes[3].invert_yaxis()
    axes[-1].set_xlabel("time from the execute [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        for t in res.executes:
            ax.axvline(t, color="C1", lw=0.6, alpha=0.6)
    fig.suptitle(f"{res.vehicle}: {res.kind.replace('_', ' ')} (executes marked)")
    fig.tight_layout()
    return fig


def spiral_figure(res: Any) -> Any:
    """Steady yaw rate (rad/s) against deflection (deg), in the order flown: a course-unstable
    vehicle shows a loop (direct spiral) or an S (reverse)."""
    ax = axes_or_new(None, (7.0, 5.0))
    pts = res.metrics.get("points") or []
    d = [p["deflection_deg"] for p in pts]
    r = [p["yaw_rate"] for p in pts]
    ax.plot(d, r, "o-", lw=1.0, ms=4)
    ax.axhline(0, color="0.5", lw=0.6)
    ax.axvline(0, color="0.5", lw=0.6)
    ax.set_xlabel(f"{res.surface} deflection [deg]")
    ax.set_ylabel("steady yaw rate r [rad/s]")
    ax.grid(alpha=0.3)
    ax.set_title(f"{res.vehicle}: {res.metrics.get('mode', '')} spiral")
    return ax.figure


def figures(res: Any) -> dict[str, Any]:
    """The manoeuvre's figures by file name (track.png, time.png, and spiral.png for a spiral)."""
    out = {"track.png": track_figure(res), "time.png": time_figure(res)}
    if res.kind == "spiral":
        out["spiral.png"] = spiral_figure(res)
    return out
