"""Self-contained HTML report of identification runs (issue #2, item 7).

A *run* is one rig (one axis) identified with one or more methods. The report shows, per run,
coefficients per method with their uncertainty, full-scale values when the rig has a scale,
the pairwise rank-sum table between amplitude groups, a per-launch table, the model-adequacy
verdict of each launch beside its adequacy figure, fit figures and the warnings; at the end
coefficients against Reynolds number for all runs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from hydrokit.report.html import esc, figure, fmt, page, table, warnings_block

COEFS = (
    ("added_mass", "m_a"),
    ("added_mass_coefficient", "C_m"),
    ("linear_damping", "K_L"),
    ("quadratic_damping", "K_Q"),
    ("drag_coefficient", "C_D"),
    ("natural_frequency", "ω_n (rad/s)"),
    ("damping_ratio", "ζ"),
)


@dataclass
class Run:
    """One rig identified by one or more methods.

    title : str — e.g. "spring rig, surge"
    rig : Rig
    documents : dict method → JSON result document (hydrokit.io.results.results_document)
    figures : list of (png bytes, caption)
    adequacy_figures : dict ``<launch stem>_adequacy.png`` → (png bytes, caption), from
        :func:`hydrokit.plot.adequacy.adequacy_figures` (of the first method's launches); each is
        shown next to its launch's verdict
    """

    title: str
    rig: Any
    documents: dict[str, dict[str, Any]]
    figures: list[tuple[bytes, str]] = field(default_factory=list)
    adequacy_figures: dict[str, tuple[bytes, str]] = field(default_factory=dict)


def _pm(s: dict[str, Any]) -> str:
    if s.get("mean") is None:
        return "–"
    ci = s.get("ci") or [None, None]
    ci_txt = f" [{fmt(ci[0])}, {fmt(ci[1])}]" if ci[0] is not None else ""
    return f"{fmt(s['mean'])} ± {fmt(s['std'])}{ci_txt}"


def rejection_note(method: str, summary: dict[str, Any]) -> str | None:
    """The warning line for launches the outlier rule rejected, with each affected coefficient's
    statistics over every launch (``without_rejection``), or None when nothing was rejected."""
    rej = {f for k, _ in COEFS for f in summary[k]["rejected"]}
    if not rej:
        return None
    every = "; ".join(f"{lab} {_pm(summary[k]['without_rejection'])}" for k, lab in COEFS if summary[k]["rejected"])
    return (
        f"{method}: outliers rejected ({summary['outlier_rule']}): {', '.join(sorted(rej))}; over every launch: {every}"
    )


def _units(rig: Any) -> dict[str, str]:
    if rig.rotational:
        return {"added_mass": "kg·m²", "linear_damping": "N·m·s/rad", "quadratic_damping": "N·m·s²/rad²"}
    return {"added_mass": "kg", "linear_damping": "N·s/m", "quadratic_damping": "N·s²/m²"}


def _record_table(launches: list[dict[str, Any]], rig: Any) -> str:
    """Release, detrend, amplitude window and equivalent damping per launch (issue #16), when given."""
    if not any("release_time" in L for L in launches):
        return ""
    deg = not rig.translational_signal
    unit = "°" if deg else "m"
    damp = "N·m·s/rad" if deg else "N·s/m"

    def amp(a: float) -> str:
        return fmt(math.degrees(a) if deg else a, 3)

    rows = []
    for L in launches:
        w = L.get("amplitude_window")
        win = (
            f"{amp(w['high'])}–{amp(w['low'])} {unit}: {fmt(w['start_time'])}–{fmt(w['end_time'])} s, {fmt(w['cycles'], 3)} cycles"
            if w
            else "whole decay"
        )
        eq = "; ".join(
            f"{amp(e['amplitude'])} {unit}: {fmt(e['value'])} ± {fmt(e['std_error'], 2)}"
            for e in L.get("equivalent_damping") or []
        )
        det = L.get("detrend") or {}
        rows.append(
            [
                L["file"].split("/")[-1],
                f"{fmt(L.get('release_time'))} ({L.get('release', '')})",
                det.get("method", ""),
                win,
                eq or "–",
            ]
        )
    return "<h3>Records: release, drift and amplitude window</h3>" + table(
        ["file", "release (s, file time)", "detrend", "amplitude window", f"B_e at amplitude ({damp}, ± formal SE)"],
        rows,
        left_cols=1,
    )


def _adequacy_section(method: str, launches: list[dict[str, Any]], figures: dict[str, tuple[bytes, str]]) -> str:
    """Each launch's adequacy numbers and verdict; where a figure was made, the verdict beside it."""
    from hydrokit.plot.adequacy import adequacy_png_name

    found = [(L["file"], (L.get("extra") or {}).get("adequacy")) for L in launches]
    rows = [(f, a) for f, a in found if a]
    if not rows:
        return ""
    bad = sum(1 for _, a in rows if not str(a["verdict"]).startswith("adequate"))
    parts = [
        f"<h3>Model adequacy ({esc(method)}): {bad} of {len(rows)} launches not explained down to the noise</h3>",
        '<p class="note">residual / noise: RMS residual over the sensor noise floor (≤ 2 is noise); '
        "ρ(one period): the residual's autocorrelation one oscillation period apart (ρ ≥ 0.3: the same "
        "model error repeats every cycle). The figures show ρ against lag with the white-noise band "
        "±1.96/√N, and the residual against time with the noise floor.</p>",
        table(
            ["file", "residual / noise", "ρ(one period)", "verdict"],
            [
                [f.split("/")[-1], fmt(a["residual_to_noise"], 3), fmt(a["acf_at_period"], 2), a["verdict"]]
                for f, a in rows
            ],
        ),
    ]
    for f, a in rows:
        fig = figures.get(adequacy_png_name(f))
        if fig is not None:
            parts.append(
                f'<div class="adequacy"><p><b>{esc(f.split("/")[-1])}</b>: {esc(a["verdict"])}</p>'
                f"{figure(fig[0], fig[1])}</div>"
            )
    return "\n".join(parts)


def run_section(run: Run) -> str:
    """HTML of one run."""
    units = _units(run.rig)
    parts = [f"<h2>{esc(run.title)}</h2>"]
    parts.append(
        f"<p>rig file: <code>{esc(run.rig.source)}</code>; test {esc(run.rig.test)}, axis {esc(run.rig.axis)}; "
        "values are mean ± standard deviation over launches [95 % confidence interval of the mean].</p>"
    )
    header = ["method", "n"] + [f"{lab} ({units[k]})" if k in units else lab for k, lab in COEFS]
    rows = []
    warn: list[str] = []
    for method, doc in run.documents.items():
        s = doc["summary"]
        rows.append([method, s["added_mass"]["n"]] + [_pm(s[k]) for k, _ in COEFS])
        for L in doc["launches"]:
            warn.extend(f"{method}: {L['file']}: {w}" for w in L["warnings"])
        if note := rejection_note(method, s):
            warn.append(note)
    parts.append(table(header, rows, left_cols=1))
    scaled = {m: d["full_scale"] for m, d in run.documents.items() if d.get("full_scale")}
    if scaled:
        # the values come from the result (CampaignResult.full_scale): the report only shows them
        lam = next(iter(scaled.values()))["lambda"]
        keys = ("added_mass", "linear_damping", "quadratic_damping")
        srows = [[method] + [fmt(full.get(k)) for k in keys] for method, full in scaled.items()]
        parts.append(f"<h3>Full scale (λ = {fmt(lam)}; equal C_D at equal speed, not Reynolds similarity)</h3>")
        header = ["method"] + [f"{lab} ({units[k]})" for lab, k in zip(("m_a", "K_L", "K_Q"), keys)]
        parts.append(table(header, srows))
    first = next(iter(run.documents.values()))
    pw = first.get("pairwise", {}).get("added_mass", [])
    if pw:
        parts.append(
            f"<h3>Amplitude groups compared (added mass, {esc(next(iter(run.documents)))}; two-sided rank-sum, normal approximation)</h3>"
        )
        parts.append(
            table(
                ["groups", "U", "z (continuity-corrected)", "p (normal, as CELY2019)", "p (exact)"],
                [
                    [" vs ".join(p["pair"]), fmt(p["u"]), fmt(p["z"], 3), fmt(p["p"], 3), fmt(p.get("p_exact"), 3)]
                    for p in pw
                ],
            )
        )
    launches = first["launches"]
    parts.append(
        "<details><summary>Per-launch results ("
        + esc(next(iter(run.documents)))
        + f", {len(launches)} launches)</summary>"
    )
    parts.append(
        table(
            ["file", "amplitude", "m_a", "K_L", "K_Q", "C_D", "Re_max", "KC", "RMS residual"],
            [
                [
                    L["file"].split("/")[-1],
                    fmt(L["amplitude"]),
                    fmt(L["added_mass"]),
                    fmt(L["linear_damping"]),
                    fmt(L["quadratic_damping"]),
                    fmt(L["drag_coefficient"]),
                    fmt(L["reynolds_max"], 3),
                    fmt(L["kc"], 3),
                    fmt(L["rms_residual"], 3),
                ]
                for L in launches
            ],
        )
    )
    parts.append("</details>")
    parts.append(_record_table(launches, run.rig))
    parts.append(_adequacy_section(next(iter(run.documents)), launches, run.adequacy_figures))
    for png, cap in run.figures:
        parts.append(figure(png, cap))
    if warn:
        parts.append("<h3>Warnings</h3>")
        parts.append(warnings_block(warn[:40]))
        if len(warn) > 40:
            parts.append(f"<p>… and {len(warn) - 40} more (see the JSON results).</p>")
    return "\n".join(parts)


def identify_report(
    title: str, runs: Sequence[Run], intro: str = "", closing_figures: Sequence[tuple[bytes, str]] = ()
) -> str:
    """The whole HTML document."""
    parts = []
    if intro:
        parts.append(f"<p>{esc(intro)}</p>")
    for run in runs:
        parts.append(run_section(run))
    if closing_figures:
        parts.append("<h2>Coefficients against Reynolds number</h2>")
        parts.extend(figure(png, cap) for png, cap in closing_figures)
    return page(title, parts)
