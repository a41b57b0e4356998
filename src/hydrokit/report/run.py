"""The report of the whole chain (``hydrokit run``) and the run folder's files.

First screen: the full-scale coefficients with their 95 % CI next to geometry, BEM, CFD, the
vehicle's own dives (sysid, value ± σ) and published values, the chosen values with their source, the mission with its uncertainty
envelope and the de-duplicated warnings. Then the details: per campaign, the launches' fits and
residuals (collapsible), per-launch standard errors with units, C_D against Re with rejected
launches marked, and the amplitude-group tests; the system identification (parameters, identifiability,
residuals and held-out NRMSE, measured against simulated). Self-contained (inline CSS, base64 PNG).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from hydrokit.pipeline.result import RunResult
from hydrokit.plot.sysid import LABELS, channel_order
from hydrokit.report.html import esc, fmt, page, table, warnings_block
from hydrokit.report.sysid import identifiability_note, verdict_html

SYMBOL = {"added_mass": "added mass", "linear_damping": "K_L", "quadratic_damping": "K_Q"}
UNIT = {
    False: {"added_mass": "kg", "linear_damping": "N·s/m", "quadratic_damping": "N·s²/m²"},
    True: {"added_mass": "kg·m²", "linear_damping": "N·m·s/rad", "quadratic_damping": "N·m·s²/rad²"},
}
ROTATIONAL = {"roll", "pitch", "yaw"}
#: SI unit of each sysid channel ("x (m)" → "m")
CHANNEL_UNIT = {c: label[label.index("(") + 1 : -1] for c, label in LABELS.items()}
EXTRA_CSS = """
.banner{background:#fdecea;border-left:5px solid #c0392b;padding:.5rem .9rem;font-weight:600}
details{margin:.4rem 0} summary{cursor:pointer;color:#0b5394}
td{white-space:nowrap}
.grid{display:flex;flex-wrap:wrap;gap:.4rem} .grid figure{width:32%;margin:0}
"""


def _img(fig: dict[str, str], cls: str = "") -> str:
    cap = esc(fig.get("caption", ""))
    return (
        f'<figure{cls}><img alt="{cap}" src="data:image/png;base64,{fig["png"]}">'
        f"<figcaption>{cap}</figcaption></figure>"
    )


def _rel(value: float | None) -> str:
    return "" if value is None else f" ({value:+.1f} %)"


def _ci(ci: list[Any] | None) -> str:
    if not ci or ci[0] is None:
        return ""
    return f" [{fmt(ci[0])}, {fmt(ci[1])}]"


def _without_rejection(e: dict[str, Any]) -> str:
    """Mean [CI] over every launch when the outlier rule rejected any, else "same"."""
    alt = e.get("without_rejection")
    if not e.get("rejected") or not alt:
        return "same"
    return fmt(alt["mean"]) + _ci(alt["ci"])


def first_screen(doc: dict[str, Any], figures: dict[str, list[dict[str, str]]]) -> list[str]:
    """Coefficients vs other sources, the choice, the mission envelope, warnings."""
    parts = data_statement(doc)
    proj = doc["project"]
    if proj.get("description"):
        parts.append(f"<p>{esc(proj['description'])}</p>")
    has_tank = bool(doc["campaigns"])
    sysid = doc.get("sysid")
    parts.append(
        "<h2>Full-scale coefficients: tank against the other sources</h2>"
        if has_tank
        else "<h2>Coefficients: the vehicle's own dives (sysid) against the other sources</h2>"
    )
    rules = sorted(set(proj["choose"].values()))
    parts.append(
        f"<p>Choice rule: <b>{esc(', '.join(f'{d}: {r}' for d, r in proj['choose'].items()))}</b>"
        if len(rules) > 1
        else f"<p>Choice rule: <b>{esc(rules[0])}</b> for every DOF"
    )
    said = (
        "; a coefficient the preferred source lacks falls back along tank → sysid → CFD → BEM → geometry → "
        "base vehicle. "
    )
    if has_tank:
        said += (
            "Tank values: mean over launches scaled with λ, [95 % interval of the stated uncertainty: launch "
            "scatter, amplitude-group spread and the air tare's error]. "
        )
    if sysid:
        said += (
            f"sysid: value ± σ identified from the vehicle's own runs ({len(sysid['runs'])} fitted, "
            f"{len(sysid['holdout'])} held out; σ from the Fisher information, widened for coloured residuals) "
            "[95 % interval]. "
        )
    said += f"In parentheses: difference from the {'tank' if has_tank else 'sysid'} value.</p>"
    parts.append(said)
    ref = "relative_to_tank_percent" if has_tank else "relative_to_sysid_percent"
    has_truth = any(r.get("truth") is not None for r in doc["comparison"])
    header = ["DOF", "coefficient", "unit"] + (["tank [95 % CI]"] if has_tank else [])
    header += (["true"] if has_truth else []) + ["geometry", "BEM", "CFD"]
    header += (["sysid ± σ [95 %]"] if sysid else []) + ["published", "chosen", "source"]
    rows = []
    for r in doc["comparison"]:
        rel = r.get(ref) or {}
        row = [r["dof"], SYMBOL[r["coefficient"]], UNIT[r["dof"] in ROTATIONAL][r["coefficient"]]]
        if has_tank:
            row.append(fmt(r["tank"]) + _ci(r["tank_ci"]))
        if has_truth:
            row.append(fmt(r["truth"]) + _rel(rel.get("truth")))
        for k in ("geometry", "bem", "cfd"):
            row.append(fmt(r[k]) + _rel(rel.get(k)) if r[k] is not None else "–")
        if sysid:
            row.append(_sysid_cell(r, rel.get("sysid") if has_tank else None))
        row.append(fmt(r["published"]) + _rel(rel.get("published")) if r["published"] is not None else "–")
        row += [fmt(r["chosen"]), r["chosen_source"]]
        rows.append(row)
    parts.append(table(header, rows, left_cols=3))
    pubs = {r["published_source"] for r in doc["comparison"] if r.get("published_source")}
    if pubs:
        parts.append(f'<p class="note">Published values: {esc("; ".join(sorted(pubs)))}.</p>')
    parts += _mission_summary(doc, figures)
    if doc["warnings"]:
        parts.append(f"<h2>Warnings ({len(doc['warnings'])})</h2>")
        parts.append(warnings_block(doc["warnings"][:15]))
        if len(doc["warnings"]) > 15:
            parts.append(
                "<details><summary>all warnings</summary>" + warnings_block(doc["warnings"][15:]) + "</details>"
            )
    return parts


def data_statement(doc: dict[str, Any]) -> list[str]:
    """What the data are, per source: tank launches simulated by the virtual rig or measured;
    dives (sysid runs) written by hydrokit's generator or logged. Simulated or generated data
    get the red banner, measured data a plain line."""
    virtual = bool(doc["project"].get("virtual_data"))
    made, measured = [], []
    camps = doc.get("campaigns") or {}
    if camps:
        n = sum(len(c["campaign"]["launches"]) for c in camps.values())
        where = f"{n} tank launches ({', '.join(camps)})"
        if virtual or all(c.get("truth") for c in camps.values()):
            made.append(f"The {where} are virtual: simulated by hydrokit's virtual rig, not measured.")
        else:
            measured.append(f"The {where} are measured.")
    sysid = doc.get("sysid")
    if sysid:
        runs = [*sysid["runs"], *sysid["holdout"]]
        where = f"{len(runs)} dives (sysid runs: {', '.join(runs)})"
        if virtual or sysid.get("truth_file"):
            made.append(
                f"The {where} are generated: simulated by hydrokit from a vehicle with hidden coefficients "
                "(hydrokit sysid generate), not logged in the water."
            )
        else:
            measured.append(f"The {where} are logs of the vehicle.")
    truth = any(r.get("truth") is not None for r in doc.get("comparison") or []) or (
        sysid and any(p.get("truth") is not None for p in sysid["parameters"].values())
    )
    out = []
    if made:
        said = " ".join(made) + (
            " Where the truth is known the report shows identified against true values." if truth else ""
        )
        out.append(f'<p class="banner">{esc(said)}</p>')
    if measured:
        out.append(f"<p>{esc(' '.join(measured))}</p>")
    return out


def _sysid_cell(r: dict[str, Any], relative: float | None) -> str:
    v, s = r.get("sysid"), r.get("sysid_sigma")
    if v is None:
        return "–"
    return f"{fmt(v)} ± {fmt(s, 2)}" + _ci(r.get("sysid_ci")) + _rel(relative)


def _estimator_html(s: dict[str, Any]) -> list[str]:
    """Which estimator fitted the runs and why (sysid.json's ``estimator``), beside the window
    (s, ``auto`` or ``none``) and continuity weight (–) the project asked for; nothing for a
    step that does not say."""
    est = s.get("estimator") or s["result"].get("estimator") or {}
    if not est.get("method"):
        return []
    window = s.get("window", "auto")
    asked = f"{fmt(window)} s" if isinstance(window, (int, float)) else esc(window)
    length = f" of about {fmt(est['window_s'])} s" if est.get("window_s") else ""
    step = f"; Jacobian columns every {fmt(est['jacobian_step_s'])} s" if est.get("jacobian_step_s") else ""
    return [
        f"<p>Estimator: {esc(est['method'])}{length}{step}: {esc(est.get('why') or '')}. Asked: window {asked}, "
        f"continuity {fmt(s.get('window_continuity', 0.0))}.</p>"
    ]


def sysid_section(s: dict[str, Any], figures: dict[str, list[dict[str, str]]]) -> list[str]:
    """The system identification's details: runs, parameters with σ (beside start, base,
    equation error and truth), identifiability, residuals and held-out NRMSE, figures."""
    res = s["result"]
    parts = [f"<h2>System identification from the vehicle's own runs ({esc(s['method'])})</h2>"]
    if s.get("verdict"):  # first: does the model describe the runs (hydrokit.sysid.stats.verdict)
        parts += verdict_html(s["verdict"], res["runs"], level=3)
    held = f"; held out for validation: <code>{esc(', '.join(s['holdout']))}</code>" if s["holdout"] else ""
    tank = s["start_vehicle"]["from_tank"]
    start = (
        f"the base vehicle with the tank's {', '.join(sorted(tank))} written in"
        if tank
        else "the base vehicle (no tank value to write in)"
    )
    parts.append(
        f"<p>Runs <code>{esc(', '.join(s['runs']))}</code>{held}. Start: {esc(start)}; every coefficient not free "
        f"keeps that value. Integration step {fmt(s['dt'])} s; {res['iterations']} iteration(s); condition number "
        f"of the scaled Fisher information {fmt(res['condition_number'], 3)}; halving the step moves the estimates "
        f"by at most {fmt(res['step_check_sigma'], 2)} σ.</p>"
    )
    parts += _estimator_html(s)
    has_truth = any(p.get("truth") is not None for p in s["parameters"].values())
    rows = []
    for name, p in s["parameters"].items():
        ee = p["equation_error"]
        row = [
            name,
            p["unit"],
            f"{fmt(p['value'])} ± {fmt(p['sigma'], 2)}",
            f"{fmt(ee['value'])} ± {fmt(ee['sigma'], 2)}",
            fmt(p["start"]),
            fmt(p["base"]),
        ]
        if has_truth:
            t = p.get("truth")
            z = (p["value"] - t) / p["sigma"] if t is not None and p["sigma"] else None
            row.append(fmt(t) + (f" ({z:+.1f} σ)" if z is not None else ""))
        row.append("yes" if p["identifiable"] else "no: σ ≥ |value|")
        rows.append(row)
    header = ["parameter", "unit (SI)", "identified ± σ", "equation error ± σ", "start", "start vehicle"]
    header += (["true (generated)"] if has_truth else []) + ["identifiable"]
    parts.append(table(header, rows, left_cols=2))
    terms = s.get("terms") or []
    if terms:
        parts.append(
            "<p>Free terms: "
            + esc(
                "; ".join(
                    f"{t['name']} {t['value']:.4g} ± {t['sigma']:.2g} "
                    + (
                        "(written into the vehicle)"
                        if t["written"]
                        else f"(not written: {t['dof']} does not choose sysid)"
                    )
                    for t in terms
                )
            )
            + ".</p>"
        )
    msgs = res.get("messages") or []
    parts.append(
        "<h3>Identifiability</h3>"
        + (warnings_block(msgs) if msgs else f"<p>{esc(identifiability_note(s.get('verdict') or {}))}</p>")
    )
    run_rows = []
    for r in res["runs"]:
        for c in channel_order(r["channels"]):
            d = r["channels"][c]
            run_rows.append(
                [
                    r["name"],
                    "held out" if r["holdout"] else "fitted",
                    c,
                    CHANNEL_UNIT.get(c, "SI"),
                    d["samples"],
                    fmt(d["residual_rms"], 3),
                    fmt(d["whiteness"]["lag1"], 2),
                    fmt(d.get("nrmse"), 3),
                ]
            )
    parts.append(
        "<details><summary>Residuals per run and channel (RMS in the channel's SI unit; NRMSE of held-out "
        "runs)</summary>"
        + table(
            ["run", "use", "channel", "unit", "samples (count)", "residual RMS (unit)", "lag-1 ρ (–)", "NRMSE (–)"],
            run_rows,
            left_cols=4,
        )
        + "</details>"
    )
    figs = figures.get("sysid", [])
    if figs:
        parts.append(f"<details><summary>Measured against simulated ({len(figs)} figures)</summary>")
        parts.append("".join(_img(f) for f in figs) + "</details>")
    return parts


def _mission_summary(doc: dict[str, Any], figures: dict[str, list[dict[str, str]]]) -> list[str]:
    missions, mc = doc.get("missions"), doc.get("monte_carlo")
    if not missions:
        return ["<h2>Mission</h2><p>No mission in the project.</p>"]
    parts = [f"<h2>Mission {esc(missions['mission'])} on the identified vehicle</h2>"]
    header = ["controller", "cross-track RMS (m)", "cross-track max (m)", "depth error RMS (m)", "completed (yes/no)"]
    if mc:
        header += [
            f"MC cross-track RMS, median [5–95 %] (m), n = {mc['samples']}",
            "MC completed (% of samples)",
            "truth inside envelope (% of times)",
        ]
    rows = []
    for c, f in missions["controllers"].items():
        m = f["metrics"]
        row = [c, m["cross_track_rms"], m["cross_track_max"], m["depth_error_rms"], "yes" if m["completed"] else "no"]
        if mc:
            s = mc["controllers"][c]
            x = s["metrics"]["cross_track_rms"]
            row.append(f"{fmt(x['median'], 3)} [{fmt(x['p5'], 3)}, {fmt(x['p95'], 3)}]")
            row.append(f"{100 * s['completed_fraction']:.0f} %")
            inside = s.get("truth_inside")
            row.append(f"{100 * inside['min_max']:.0f} % of times (min–max)" if inside else "–")
        rows.append(row)
    parts.append(table(header, rows))
    for fig in figures.get("monte_carlo", []):
        parts.append(_img(fig))
    return parts


def campaign_section(dof: str, c: dict[str, Any], figures: dict[str, list[dict[str, str]]]) -> list[str]:
    """One campaign's details."""
    camp = c["campaign"]
    units = c["units"]
    parts = [f"<h2>Campaign {esc(dof)}: {esc(camp['rig']['test'])} rig, {esc(c['method'])}</h2>"]
    parts.append(
        f"<p>rig file <code>{esc(c['rig_file'])}</code>, launches <code>{esc(c['launches_pattern'])}</code> "
        f"({len(camp['launches'])}); scale ratio {fmt(c['scale_ratio'])} (λ = {fmt(c['lambda'])}: "
        "equal C_D at equal speed, not Reynolds similarity).</p>"
    )
    tare = c.get("tare")
    if tare:
        se = tare["std_error"]
        parts.append(
            f"<p>Air tare (ENG2009 §IV.A) from {len(tare['files'])} in-air launches: effective length "
            f"{fmt(tare['effective_length'], 5)} m (rig file {fmt(tare['rig_length'], 5)} m); pivot friction "
            f"K_L {fmt(tare['linear_damping'], 3)} ± {fmt(se['linear_damping'], 2)}, "
            f"K_Q {fmt(tare['quadratic_damping'], 3)} ± {fmt(se['quadratic_damping'], 2)} (model units) subtracted from "
            "every launch; its standard error is part of the uncertainty.</p>"
        )
    s = camp["summary"]
    rows = []
    for k in ("added_mass", "linear_damping", "quadratic_damping", "drag_coefficient", "added_mass_coefficient"):
        e = s.get(k)
        if not e:
            continue
        full = c["full_scale"].get(k)
        truth = (c.get("truth") or {}).get(k)
        rows.append(
            [
                k,
                units.get(k, "–"),
                fmt(e["mean"]) + _ci(e["ci"]),
                fmt(e["std"]),
                e["n"],
                len(e["rejected"] or []),
                _without_rejection(e),
                fmt(truth["model"]) if truth else "–",
                (fmt(full["mean"]) + _ci(full["ci"])) if full else "–",
            ]
        )
    parts.append(
        table(
            [
                "coefficient",
                "unit (model)",
                "model mean [95 % CI] (unit)",
                "std (unit)",
                "n (launches)",
                "rejected (launches)",
                "all launches mean [95 % CI] (unit)",
                "true (model, unit)",
                "full scale [95 % CI] (SI, full-scale unit)",
            ],
            rows,
            left_cols=2,
        )
    )
    parts.append('<div class="grid">' + "".join(_img(f) for f in figures.get(f"summary:{dof}", [])) + "</div>")
    pw = camp.get("pairwise", {})
    test_rows = [
        [k, " vs ".join(p["pair"]), fmt(p["u"]), fmt(p["z"], 3), fmt(p["p"], 3), fmt(p.get("p_exact"), 3)]
        for k in ("added_mass", "linear_damping", "quadratic_damping")
        for p in pw.get(k, [])
    ]
    cons = s.get("consistency") or {}
    cons_rows = [
        [k, label, g["n"], fmt(g["chi2"], 3), g["dof"], fmt(g["p"], 3), fmt(g["birge_ratio"], 3)]
        for k in ("added_mass", "linear_damping", "quadratic_damping")
        for label, g in (cons.get(k) or {}).items()
        if g.get("chi2") is not None
    ]
    if cons_rows:
        low = sum(1 for r in cons_rows if r[5] != "–" and float(r[5]) < 0.01)
        parts.append(
            f"<details><summary>Repeats against their stated errors (χ² per amplitude group; {low} of "
            f"{len(cons_rows)} with p &lt; 0.01: repeats differ by more than their standard errors say)</summary>"
        )
        parts.append(
            table(
                ["coefficient", "group", "n (launches)", "χ² (–)", "dof (count)", "p (–)", "Birge ratio (–)"],
                cons_rows,
                2,
            )
        )
        parts.append("</details>")
    if test_rows:
        parts.append("<details><summary>Amplitude-group tests (two-sided rank-sum)</summary>")
        parts.append(
            table(
                ["coefficient", "groups", "U (–)", "z, continuity (–)", "p, normal (–)", "p, exact (–)"],
                test_rows,
                2,
            )
        )
        parts.append("</details>")
    se_u = {k: units.get(k, "") for k in ("added_mass", "linear_damping", "quadratic_damping")}
    launch_rows = []
    for L in camp["launches"]:
        se = L.get("std_error") or {}
        launch_rows.append(
            [
                L["file"],
                fmt(L["amplitude"]),
                fmt(L["added_mass"]),
                fmt(se.get("added_mass"), 2),
                fmt(L["linear_damping"]),
                fmt(se.get("linear_damping"), 2),
                fmt(L["quadratic_damping"]),
                fmt(se.get("quadratic_damping"), 2),
                fmt(L["drag_coefficient"]),
                fmt(L["reynolds_max"], 3),
                fmt(L["rms_residual"], 3),
            ]
        )
    parts.append(f"<details><summary>Per-launch results and standard errors ({len(launch_rows)} launches)</summary>")
    parts.append(
        table(
            [
                "file",
                f"amplitude ({units.get('amplitude', '')})",
                f"m_a ({se_u['added_mass']})",
                f"SE ({se_u['added_mass']})",
                f"K_L ({se_u['linear_damping']})",
                f"SE ({se_u['linear_damping']})",
                f"K_Q ({se_u['quadratic_damping']})",
                f"SE ({se_u['quadratic_damping']})",
                "C_D (–)",
                "Re_max (–)",
                f"RMS residual ({units.get('rms_residual', '')})",
            ],
            launch_rows,
        )
    )
    parts.append("</details>")
    ade: list[tuple[str, dict[str, Any]]] = []
    for L in camp["launches"]:
        found = (L.get("extra") or {}).get("adequacy")
        if found:
            ade.append((L["file"], found))
    if ade:
        bad = sum(1 for _, a in ade if str(a["verdict"]).startswith("model error"))
        parts.append(
            f"<details><summary>Model adequacy: {bad} of {len(ade)} launches show model error (residual repeating "
            "each cycle)</summary>"
        )
        parts.append(
            table(
                ["file", "residual / noise (–)", "autocorrelation one period apart (–)", "verdict"],
                [[f, fmt(a["residual_to_noise"], 3), fmt(a["acf_at_period"], 2), a["verdict"]] for f, a in ade],
            )
        )
        parts.append("</details>")
    launches = figures.get(f"launches:{dof}", [])
    parts.append(f"<details><summary>Every launch's fit and residual ({len(launches)} figures)</summary>")
    parts.append('<div class="grid">' + "".join(_img(f) for f in launches) + "</div></details>")
    return parts


def run_report(result: RunResult) -> str:
    """The whole self-contained HTML document of a run."""
    doc, figures = result.document, result.figures
    parts = first_screen(doc, figures)
    parts.append("<h2>Details</h2>")
    for dof, c in doc["campaigns"].items():
        parts += campaign_section(dof, c, figures)
    if doc.get("sysid"):
        parts += sysid_section(doc["sysid"], figures)
    if figures.get("missions"):
        parts.append("<h2>Mission details</h2>")
        parts += [_img(f) for f in figures["missions"]]
    unc = doc["vehicle"].get("uncertainty", {})
    parts.append("<h2>Vehicle written (vehicle.yaml)</h2>")
    unit = {k: f"{UNIT[False][k]}; {UNIT[True][k]}" for k in SYMBOL}
    parts.append(
        table(
            ["coefficient", "unit (surge–heave; roll–yaw)", "surge", "sway", "heave", "roll", "pitch", "yaw"],
            [
                [f"{k}", unit[k], *doc["vehicle"][k]]
                if not isinstance(doc["vehicle"][k][0], list)
                else [k, unit[k], *[doc["vehicle"][k][i][i] for i in range(6)]]
                for k in SYMBOL
            ]
            + [[f"{k} standard error", unit[k], *unc.get(k, [None] * 6)] for k in SYMBOL],
            left_cols=2,
        )
    )
    parts.append("<details><summary>Steps, timings and inputs</summary>")
    parts.append(
        table(
            ["step", "time (s)", "cached (yes/no)"],
            [[t["step"], fmt(t["seconds"], 3), "yes" if t["cached"] else "no"] for t in result.timings],
        )
    )
    parts.append(f"<p>Engine: {esc(doc.get('engine', ''))}.</p>")
    parts.append(table(["input file", "SHA-256"], [[k, v[:16] + "…"] for k, v in doc["project"]["inputs"].items()]))
    parts.append("</details>")
    html = page(f"hydrokit run: {doc['project']['name']}", parts)
    return html.replace("</style>", EXTRA_CSS + "</style>", 1)


def write_run(result: RunResult, out_dir: str | os.PathLike[str]) -> list[Path]:
    """Write report.html, results.json, vehicle.yaml and mission/ (each file whole or not at all).

    Everything is rendered in memory first, so a failure leaves the previous run's files as they were.
    """
    from hydrokit._atomic import write_bytes

    out = Path(out_dir)
    written = []
    for name, data in run_files(result).items():
        write_bytes(out / name, data)
        written.append(out / name)
    return written


def run_files(result: RunResult) -> dict[str, bytes]:
    """The run folder's files (relative path → bytes), rendered in memory."""
    files: dict[str, str] = {
        "report.html": run_report(result),
        "results.json": json.dumps(result.to_dict(), indent=1, allow_nan=False, ensure_ascii=False) + "\n",
        **result.files,
    }
    return {name: text.encode("utf-8") for name, text in files.items()}


def write_run_folder(result: RunResult, out_dir: str | os.PathLike[str], force: bool = False) -> list[Path]:
    """Write the run folder's files as one set (:func:`hydrokit._atomic.staged_dir`), unless
    they are already there from a run with the same key (:func:`hydrokit.pipeline.cache.run_key`)
    and unchanged since: then nothing is rendered or written and the list is empty.

    Parameters
    ----------
    result : RunResult of :func:`hydrokit.pipeline.run_project`
    out_dir : the run folder (directory)
    force : bool — render and write even when the files are current

    Returns
    -------
    list of Path — the files written
    """
    from hydrokit._atomic import staged_dir
    from hydrokit.pipeline.cache import outputs_current, record_outputs

    out = Path(out_dir)
    if result.key is not None and not force and outputs_current(out, result.key):
        return []
    files = run_files(result)
    with staged_dir(out) as stage:  # the folder's files replace the old ones as one set
        for name, data in files.items():
            (stage / name).parent.mkdir(parents=True, exist_ok=True)
            (stage / name).write_bytes(data)
    if result.key is not None:
        record_outputs(out, result.key, list(files))
    return [out / name for name in files]
