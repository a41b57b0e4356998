"""Figures of a CFD sweep: resistance against speed, loads against angle and rate, convergence."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure

_STRAIGHT = ("drift_deg", "attack_deg", "yaw_rate", "pitch_rate")


def _bars(row: dict[str, Any], k: str) -> float:
    gci = row.get(f"{k}_gci")
    sd = row.get(f"{k}_std") or 0.0
    return float(max(sd, gci if gci is not None and math.isfinite(gci) else 0.0))


def resistance_axes(result: Any, ax: Any = None, axis: str = "x") -> Any:
    """Resistance (N, positive) against speed (m/s) along one body axis, error bars = max(σ, GCI),
    with the Chin and Morison fits; returns the axes."""
    ax = axes_or_new(ax)
    k = "XYZ"["xyz".index(axis)]
    rows = [
        r for r in result.rows if r["axis"] == axis and r["status"] != "failed" and not any(r[c] for c in _STRAIGHT)
    ]
    if rows:
        U = np.array([r["speed"] for r in rows])
        F = np.array([-r[k] for r in rows])
        ax.errorbar(U, F, yerr=[_bars(r, k) for r in rows], fmt="o", ms=4, color="0.2", capsize=3, label="CFD (±σ/GCI)")
        fit = result.fits.get(axis)
        if fit is not None:
            u = np.linspace(0.0, U.max() * 1.05, 200)
            ax.plot(
                u,
                fit.chin(u),
                "-",
                label=f"Chin: K_L = {fit.K_L:.4g} ± {fit.K_L_se:.2g}, K_Q = {fit.K_Q:.4g} ± {fit.K_Q_se:.2g}",
            )
            ax.plot(u, fit.morison(u), "--", label=f"Morison: C_D = {fit.C_D:.4g}")
    ax.set_xlabel(f"speed along {axis} (m/s)")
    ax.set_ylabel("resistance (N)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def resistance_figure(result: Any) -> Any:
    """One panel per body axis with a speed sweep."""
    axes_list = sorted({r["axis"] for r in result.rows})
    fig = new_figure((6.0 * len(axes_list), 4.2))
    for i, axis in enumerate(axes_list):
        resistance_axes(result, fig.add_subplot(1, len(axes_list), i + 1), axis)
    fig.tight_layout()
    return fig


def sweep_figure(result: Any) -> Any | None:
    """Loads against drift and attack angle (deg) and against yaw and pitch rate (rad/s), with
    the fitted derivatives' curves; None when the sweep has no angles or rates."""
    panels = [
        ("drift_deg", ("Y", "N"), "drift angle β (deg)"),
        ("attack_deg", ("Z", "M"), "angle of attack α (deg)"),
        ("yaw_rate", ("Y", "N"), "yaw rate r (rad/s)"),
        ("pitch_rate", ("Z", "M"), "pitch rate q (rad/s)"),
    ]
    U = result.reference_speed
    used = [p for p in panels if any(r[p[0]] for r in result.rows)]
    if not used:
        return None
    fig = new_figure((5.5 * len(used), 4.2))
    for i, (col, loads, label) in enumerate(used):
        ax = fig.add_subplot(1, len(used), i + 1)
        others = [c for c in _STRAIGHT if c != col]
        rows = [
            r
            for r in result.rows
            if r["status"] != "failed"
            and r["axis"] == "x"
            and math.isclose(r["speed"], U)
            and not any(r[c] for c in others)
        ]
        rows.sort(key=lambda r: r[col])
        x = np.array([r[col] for r in rows])
        for k, style in zip(loads, ("o", "s"), strict=True):
            y = np.array([r[k] for r in rows])
            ax.errorbar(
                x,
                y,
                yerr=[_bars(r, k) for r in rows],
                fmt=style,
                ms=4,
                capsize=3,
                label=f"{k} ({'N' if k in 'XYZ' else 'N·m'})",
            )
        ax.axhline(0, color="0.6", lw=0.8)
        ax.set_xlabel(label)
        ax.set_ylabel(f"load ({', '.join(loads[:1])}: N; {', '.join(loads[1:])}: N·m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def convergence_figure(result: Any, limit: int = 12) -> Any:
    """Force history of each case (X, and |Y|, |Z| when not negligible), normalised by its final
    value: the evidence behind "converged" or "averaged"."""
    fig = new_figure((7.5, 4.2))
    ax = fig.add_subplot(1, 1, 1)
    shown = 0
    for o in result.outcomes:
        h = o.get("history")
        if not h or shown >= limit:
            continue
        it = np.asarray(h["iteration"])
        X = np.asarray(h["X"])
        ref = abs(X[-1]) or 1.0
        ax.plot(it, X / ref, lw=1, label=f"{o['label']} ({o['status']})")
        shown += 1
    ax.set_xlabel("iteration (count)")
    ax.set_ylabel("X / |X final| (–)")
    ax.set_ylim(-2.5, 0.5) if shown else None
    ax.grid(alpha=0.3)
    if shown:
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def slice_figure(outcome: dict[str, Any]) -> Any | None:
    """|U|/U∞ on the body's x–y plane (z = 0) around the body, from a case's outcome; None
    without a slice. Points are the cut faces' centres (no interpolation across the body)."""
    sl = outcome.get("slice")
    if not sl or not sl.get("x"):
        return None
    fig = new_figure((8.0, 3.6))
    ax = fig.add_subplot(1, 1, 1)
    x, y, c = (np.asarray(sl[k]) for k in ("x", "y", "speed"))
    pts = ax.scatter(x, y, c=c, s=3, cmap="viridis", vmin=0.0, vmax=max(1.3, float(np.nanmax(c))), linewidths=0)
    fig.colorbar(pts, ax=ax, label="|U| / U∞")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, body axes)")
    ax.set_ylabel("y (m)" if outcome.get("path") != "wedge" else "r (m)")
    ax.set_title(f"{outcome.get('label', '')}: velocity magnitude on z = 0", fontsize=9)
    fig.tight_layout()
    return fig
