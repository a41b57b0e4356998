"""Identification figures: fit and residual per launch; coefficients against Reynolds number
(what CELY2019 Figs. 8, 11–13 and 17–19 show)."""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from typing import Any

import numpy as np

from hydrokit.plot._mpl import axes_or_new, new_figure


def launch_fit(
    t: np.ndarray, y: np.ndarray, fitted: np.ndarray, title: str, unit: str, ax: Any = None, compact: bool = False
) -> Any:
    """Measured vs fitted signal (top) and residual (bottom). Returns the figure.

    Parameters
    ----------
    t : s; y, fitted : signal in ``unit`` (m or rad — shown in mm or degrees)
    compact : bool — a small figure with a fixed layout (for grids of many launches; renders
        about twice as fast as the automatic layout)
    """
    scale, label = (1e3, "position (mm)") if unit == "m" else (180 / np.pi, "angle (°)")
    fig = new_figure((4.6, 3.0) if compact else (7, 4.2))
    (a1, a2) = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    a1.plot(t, y * scale, ".", ms=2.5, color="0.35", label="measured")
    a1.plot(t, fitted * scale, "-", lw=1.2, color="C0", label="fitted")
    a1.set_ylabel(label)
    a1.set_title(title, fontsize=9)
    a1.legend(loc="upper right", fontsize=8)
    a2.plot(t, (y - fitted) * scale, "-", lw=0.7, color="C3")
    a2.axhline(0, color="0.5", lw=0.5)
    a2.set_ylabel("residual (mm)" if unit == "m" else "residual (°)")
    a2.set_xlabel("time after release (s)")
    if compact:
        fig.subplots_adjust(left=0.16, right=0.97, top=0.91, bottom=0.15, hspace=0.08)
    else:
        fig.tight_layout()
    return fig


#: legend entry of launches the outlier rule rejected (hollow red markers in every figure)
REJECTED_LABEL = "rejected (outlier rule)"
_REJECTED_STYLE = {"marker": "o", "ls": "none", "mfc": "none", "color": "C3"}


def coefficients_vs_reynolds(
    groups: Mapping[str, Sequence[Any]], title: str = "", rejected: Mapping[str, Collection[str]] | None = None
) -> Any:
    """C_m, C_D, K_L and K_Q per launch against the peak Reynolds number, one colour per group
    (axis or method). ``groups`` maps a label to LaunchResults; ``rejected`` maps a coefficient
    name (e.g. "quadratic_damping") to the files the outlier rule rejected for it, drawn hollow
    in red (a campaign summary's ``rejected`` lists)."""
    fig = new_figure((8, 5.5))
    axes = fig.subplots(2, 2)
    panels = (
        ("added_mass_coefficient", "C_m = m_a/(ρV) (–)"),
        ("drag_coefficient", "C_D (–)"),
        ("linear_damping", "K_L (N·s/m or N·m·s/rad)"),
        ("quadratic_damping", "K_Q (N·s²/m² or N·m·s²/rad²)"),
    )
    rejected = rejected or {}
    for ax, (field, label) in zip(axes.flat, panels):
        out = set(rejected.get(field) or ())
        shown = [r for results in groups.values() for r in results if getattr(r, field) is not None]
        for i, (name, results) in enumerate(groups.items()):
            kept = [r for r in results if getattr(r, field) is not None and r.file not in out]
            if kept:
                ax.plot(
                    [r.reynolds_max for r in kept],
                    [getattr(r, field) for r in kept],
                    "o",
                    ms=4,
                    color=f"C{i}",
                    label=name,
                )
        bad = [r for r in shown if r.file in out]
        if bad:
            ax.plot(
                [r.reynolds_max for r in bad],
                [getattr(r, field) for r in bad],
                ms=6,
                label=REJECTED_LABEL,
                **_REJECTED_STYLE,
            )
            ax.legend(fontsize=7)
        ax.set_xscale("log")
        ax.set_ylabel(label)
        ax.set_xlabel("peak Reynolds number (–)")
        ax.grid(alpha=0.3)
    if axes.flat[0].get_legend_handles_labels()[0]:
        axes.flat[0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def drag_per_cycle(cycles: Sequence[dict[str, Any]], title: str = "") -> Any:
    """C_D of each cycle against the cycle's Reynolds number (log-decrement; CELY2019 Fig. 18)."""
    fig = new_figure((5.5, 3.6))
    ax = fig.subplots()
    re = [c["reynolds"] for c in cycles if c.get("drag_coefficient") is not None]
    cd = [c["drag_coefficient"] for c in cycles if c.get("drag_coefficient") is not None]
    ax.plot(re, cd, "o", ms=4)
    ax.set_xscale("log")
    ax.set_xlabel("cycle peak Reynolds number (–)")
    ax.set_ylabel("C_D per cycle (–)")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def drag_vs_reynolds(results: Sequence[Any], summary: dict[str, Any], title: str = "", ax: Any = None) -> Any:
    """C_D per launch against its peak Reynolds number with ±1.96 standard-error bars; launches
    the outlier rule rejected drawn hollow in red. Returns the figure.

    Parameters
    ----------
    results : LaunchResults (``drag_coefficient`` –, ``reynolds_max`` –, ``quadratic_damping``
        and its ``std_error`` in N·s²/m² or the rotational unit)
    summary : the campaign summary entry of ``drag_coefficient`` (``rejected`` files, ``mean``)
    """
    ax = axes_or_new(ax, (6, 3.8))
    rejected = set(summary.get("rejected") or [])
    for keep in (True, False):
        pts = [r for r in results if r.drag_coefficient is not None and (r.file not in rejected) == keep]
        if not pts:
            continue
        re = [r.reynolds_max for r in pts]
        cd = [r.drag_coefficient for r in pts]
        err = []
        for r in pts:
            se = (r.std_error or {}).get("quadratic_damping")
            kq = r.quadratic_damping
            err.append(1.96 * se * abs(r.drag_coefficient / kq) if se is not None and kq else 0.0)
        style = {"fmt": "o", "ms": 4, "color": "C0", "label": "launch (±1.96 SE)"}
        if not keep:
            style = {"fmt": "o", "ms": 6, "mfc": "none", "color": "C3", "label": REJECTED_LABEL}
        ax.errorbar(re, cd, yerr=err, capsize=2, lw=0.8, **style)
    if summary.get("mean") is not None:
        ax.axhline(summary["mean"], color="C1", lw=1, label="campaign mean")
    ax.set_xscale("log")
    ax.set_xlabel("peak Reynolds number (–)")
    ax.set_ylabel("C_D (–)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    if title:
        ax.set_title(title, fontsize=9)
    ax.figure.tight_layout()
    return ax.figure


def campaign_axes(
    results: Sequence[Any],
    coefficient: str,
    summary: dict[str, Any],
    unit: str,
    ax: Any = None,
    title: str = "",
    amplitude_unit: str = "m or rad",
) -> Any:
    """One coefficient per launch against the launch amplitude, with the campaign mean and its
    confidence interval as a band; rejected launches (outliers) drawn hollow in red, and then the
    mean over every launch dashed. Returns the axes.

    Parameters
    ----------
    results : LaunchResults (``amplitude`` in m or rad, ``file``, the coefficient)
    coefficient : field name, e.g. "added_mass"
    summary : the campaign summary entry of that coefficient (``mean``, ``ci``, ``rejected``,
        ``without_rejection``)
    unit : the coefficient's unit, for the axis label
    amplitude_unit : the launches' amplitude unit ("m" or "rad"), for the axis label
    """
    ax = axes_or_new(ax)
    rejected = set(summary.get("rejected") or [])
    keep = [
        (r.amplitude, getattr(r, coefficient))
        for r in results
        if getattr(r, coefficient) is not None and r.file not in rejected
    ]
    out = [
        (r.amplitude, getattr(r, coefficient))
        for r in results
        if getattr(r, coefficient) is not None and r.file in rejected
    ]
    if keep:
        ax.plot(*zip(*keep), "o", ms=4, color="C0", label="launch")
    if out:
        ax.plot(*zip(*out), ms=5, label=REJECTED_LABEL, **_REJECTED_STYLE)
    mean, ci = summary.get("mean"), summary.get("ci") or [None, None]
    if mean is not None:
        ax.axhline(mean, color="C1", lw=1.2, label="mean")
        if ci[0] is not None:
            ax.axhspan(ci[0], ci[1], color="C1", alpha=0.15, label="95 % CI of the mean")
    every = summary.get("without_rejection") or {}
    if out and every.get("mean") is not None:
        ax.axhline(every["mean"], color="0.4", lw=1.0, ls="--", label="mean without rejection")
    ax.set_xlabel(f"launch amplitude ({amplitude_unit})")
    ax.set_ylabel(f"{coefficient} ({unit})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    if title:
        ax.set_title(title, fontsize=9)
    return ax


def damping_curve(result: Any, unit: str, title: str = "", ax: Any = None) -> Any:
    """Model-free equivalent damping of each half cycle against its mean amplitude, with the
    fitted model's B_e(a) = B1 + 8/(3π)·ω0·a·B2 (+ 3/4·ω0²·a²·B3) and the ``equivalent_damping``
    points (±1.96 standard error). Returns the figure.

    Parameters
    ----------
    result : LaunchResult with ``extra['damping_curve']`` (amplitude m or rad, value in reported
        damping units), ``linear_damping``, ``quadratic_damping``, ``natural_frequency``
    unit : "m" or "rad" (amplitude shown in mm or degrees)
    """
    from hydrokit.identify.damping import model_curve

    scale, label = (1e3, "amplitude (mm)") if unit == "m" else (180 / np.pi, "amplitude (°)")
    ax = axes_or_new(ax, (6, 3.8))
    pts = result.extra.get("damping_curve") or []
    if pts:
        a = np.array([p["amplitude"] for p in pts])
        v = np.array([p["value"] for p in pts])
        ax.plot(a * scale, v, "o", ms=3.5, color="0.35", label="half cycles (energy decrement)")
        grid = np.linspace(0.0, float(np.max(a)) * 1.05, 200)
        b3 = result.extra.get("cubic_damping") or 0.0
        model = model_curve(grid, result.linear_damping, result.quadratic_damping, b3, result.natural_frequency)
        ax.plot(grid * scale, model, "-", lw=1.4, color="C0", label="fitted model B_e(a)")
    eq = result.extra.get("equivalent_damping") or []
    if eq:
        ax.errorbar(
            [e["amplitude"] * scale for e in eq],
            [e["value"] for e in eq],
            yerr=[1.96 * (e["std_error"] or 0.0) for e in eq],
            fmt="s",
            ms=5,
            color="C3",
            capsize=3,
            label="B_e at stated amplitude (±1.96 SE)",
        )
    ax.set_xlabel(label)
    ax.set_ylabel("equivalent linear damping B_e (" + ("N·s/m" if unit == "m" else "N·m·s/rad") + ")")
    ax.set_xlim(left=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    if title:
        ax.set_title(title, fontsize=9)
    ax.figure.tight_layout()
    return ax.figure


def campaign_figures(campaign: Any, per_launch: bool = True) -> dict[str, tuple[bytes, str]]:
    """PNG figures of a CampaignResult: name → (png bytes, caption).

    One fit/residual figure per launch (or four spread over the campaign when ``per_launch`` is
    false), coefficients against Reynolds number, and C_D per cycle when the method gives it.
    """
    from pathlib import Path

    from hydrokit.identify.fitted import predict
    from hydrokit.plot._mpl import to_png

    rig, method, items = campaign.rig, campaign.method, campaign.launches
    unit = "m" if rig.translational_signal else "rad"
    out: dict[str, tuple[bytes, str]] = {}
    chosen = items if per_launch else items[:: max(1, len(items) // 4)][:4]
    for it in chosen:
        stem = Path(it.result.file).stem
        fig = launch_fit(np.asarray(it.launch.t), np.asarray(it.launch.y), predict(it), f"{stem} ({method})", unit)
        out[f"{stem}_fit.png"] = (to_png(fig), f"{stem}: measured and fitted signal, residual")
        if per_launch and it.result.extra.get("damping_curve"):
            fig = damping_curve(it.result, unit, f"{stem}: damping curve ({method})")
            out[f"{stem}_damping.png"] = (
                to_png(fig),
                f"{stem}: equivalent damping per half cycle against amplitude, with the fitted model's curve",
            )
    rejected = {
        k: v.get("rejected") or [] for k, v in campaign.summary.items() if isinstance(v, dict) and "rejected" in v
    }
    fig = coefficients_vs_reynolds({f"{rig.axis} ({method})": campaign.results}, rejected=rejected)
    out["coefficients_vs_reynolds.png"] = (to_png(fig), "coefficients against peak Reynolds number")
    cycles = [c for r in campaign.results for c in r.extra.get("cycles", [])]
    if cycles:
        fig = drag_per_cycle(cycles, f"{rig.axis}: C_D per cycle")
        out["drag_per_cycle.png"] = (to_png(fig), "C_D per cycle against the cycle's Reynolds number")
    return out
