"""Outputs of ``hydrokit sysid`` (issue #44): the identified vehicle file, sysid.json,
predictions.csv and a self-contained HTML report, built in memory so the caller writes them
all or none."""

from __future__ import annotations

import io
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.model.uncertainty import COEFFICIENTS
from hydrokit.report.html import esc, figure, page, table, warnings_block
from hydrokit.simulate.sysid import SysidResult


def vehicle_document(result: SysidResult, base_data: Mapping[str, Any]) -> dict[str, Any]:
    """The base vehicle file's fields with the identified values and an ``uncertainty:`` block.

    Diagonal coefficients are written into ``added_mass`` / ``linear_damping`` /
    ``quadratic_damping`` (6 numbers or a 6×6 matrix, as the base has them); ``terms.<term>``
    into ``terms`` as dimensional values (:func:`hydrokit.pipeline.sysid.write_terms`). The
    ``uncertainty`` block holds the σ of the diagonal coefficients and the full covariance
    (SI²) over every free parameter, ``terms.*`` included, which ``simulate --samples`` and
    ``mission --samples`` read.
    """
    from hydrokit.pipeline.sysid import write_terms

    doc = {k: v for k, v in base_data.items() if k != "uncertainty"}
    names = list(result.parameters)
    for coef in COEFFICIENTS:
        values = doc.get(coef)
        matrix = isinstance(values, list) and bool(values) and all(isinstance(r, list) for r in values)
        vals: Any = [list(map(float, r)) for r in values] if matrix else [float(x) for x in values]  # type: ignore[union-attr]
        for i, dof in enumerate(DOF_NAMES):
            name = f"{coef}.{dof}"
            if name in names:
                v = float(result.values[names.index(name)])
                if matrix:
                    vals[i][i] = v
                else:
                    vals[i] = v
        doc[coef] = vals
    write_terms(doc, [(n, float(v)) for n, v in zip(names, result.values) if n.startswith("terms.")])
    cov = np.asarray(result.covariance, float)
    se = {c: [0.0] * 6 for c in COEFFICIENTS}
    for k, name in enumerate(names):
        coef, _, dof = name.partition(".")
        if coef in COEFFICIENTS:
            se[coef][DOF_NAMES.index(dof)] = math.sqrt(max(float(cov[k, k]), 0.0))
    doc["uncertainty"] = {
        "description": f"hydrokit sysid ({result.method}): standard errors (SI) and covariance (SI²) of the "
        "identified parameters, inflated for coloured residuals",
        **se,
        "parameters": names,
        "covariance": (0.5 * (cov + cov.T)).tolist(),
    }
    runs = ", ".join(r["name"] for r in result.runs if not r["holdout"])
    sources = [str(s) for s in (doc.get("sources") or [])] if isinstance(doc.get("sources"), list) else []
    doc["sources"] = sources + [f"hydrokit sysid ({result.method}) from runs {runs}; free: {', '.join(names)}"]
    doc["name"] = f"{base_data.get('name', 'vehicle')}-sysid"
    return doc


def predictions_csv(result: SysidResult) -> str:
    """Long table run,holdout,channel,time,measured,simulated,low95,high95 (s, SI)."""
    out = io.StringIO()
    out.write("run,holdout,channel,time,measured,simulated,low95,high95\n")
    for p in result.predictions:
        for c, d in p["channels"].items():
            for row in zip(d["time"], d["measured"], d["simulated"], d["low"], d["high"]):
                out.write(f"{p['name']},{int(p['holdout'])},{c}," + ",".join(f"{float(x):.9g}" for x in row) + "\n")
    return out.getvalue()


def identifiability_note(verdict: Mapping[str, Any]) -> str:
    """The line shown when no identifiability message is raised: good news only when the model
    fits (σ are meaningful only then)."""
    if verdict.get("fits", True):
        return "No pair with |ρ| > 0.95; every σ below its value."
    return (
        "No pair with |ρ| > 0.95 and every σ below its value — but the model does not describe the runs "
        "(verdict above), so these σ understate the error."
    )


def verdict_lines(result: SysidResult) -> list[str]:
    """What ``hydrokit sysid`` prints first (stdout): the verdict, its reasons, and per run the
    NRMSE and residual lag-1 ρ of every channel (``NRMSE/ρ``; held-out runs are predicted open
    loop, fitted ones are the fit's residuals)."""
    from hydrokit.simulate.sysid_stats import symbol

    v = result.verdict
    out = [f"verdict: {'fits' if v['fits'] else 'DOES NOT FIT'}"] + [f"  {r}" for r in v["reasons"]]
    out.append("per run, channel NRMSE/lag-1 ρ of the residuals:")
    width = max((len(r["name"]) for r in result.runs), default=4) + 12
    for r in result.runs:
        head = f"{r['name']} ({'held out' if r['holdout'] else 'fitted'})"
        cells = [f"{symbol(c)} {d['nrmse']:.2f}/{d['whiteness']['lag1']:.2f}" for c, d in r["channels"].items()]
        out.append(f"  {head:<{width}} " + "  ".join(cells))
    return out


def verdict_html(verdict: Mapping[str, Any], runs: Sequence[Mapping[str, Any]], level: int = 2) -> list[str]:
    """The verdict as the head of a report: a heading that says it, the reasons, and a table of
    per run and channel NRMSE, lag-1 ρ and residual RMS / sensor noise."""
    from hydrokit.simulate.sysid_stats import symbol

    fits = bool(verdict["fits"])
    head = "the model describes these runs" if fits else "the model does NOT describe these runs"
    said = "".join(f"<p>{esc(r)}</p>" for r in verdict["reasons"]) if fits else warnings_block(verdict["reasons"])
    parts = [f"<h{level}>Verdict: {esc(head)}</h{level}>", said]
    rows = []
    for r in runs:
        for c, d in r["channels"].items():
            rows.append(
                [
                    r["name"],
                    "held out" if r["holdout"] else "fitted",
                    symbol(c),
                    d.get("nrmse"),
                    d["whiteness"]["lag1"],
                    d.get("noise_ratio"),
                    "yes" if d.get("moving") else "no",
                ]
            )
    parts.append(
        table(["run", "use", "channel", "NRMSE", "lag-1 ρ", "residual / noise σ", "moving"], rows, left_cols=3)
    )
    return parts


def _pm(v: float, s: float) -> str:
    return f"{v:.4g} ± {s:.2g}" if math.isfinite(s) else f"{v:.4g}"


def report_html(result: SysidResult, title: str = "System identification") -> str:
    """A self-contained HTML report (figures embedded; user text escaped)."""
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.sysid import correlation_figure, residual_figure, run_figure

    parts = verdict_html(result.verdict, result.runs)
    parts += [
        f"<p>Method: {esc(result.method)}; {result.iterations} iteration(s); condition number of the "
        f"scaled Fisher information {result.condition:.3g}; halving the integration step moves the estimates "
        f"by at most {result.step_check:.3g} σ. Wall time {result.timing.get('total', float('nan')):.1f} s, of which "
        f"simulation {result.timing.get('simulation', float('nan')):.1f} s.</p>"
    ]
    parts.append("<h2>Identifiability</h2>")
    parts.append(
        warnings_block(result.messages) if result.messages else f"<p>{esc(identifiability_note(result.verdict))}</p>"
    )
    if result.warnings:
        parts.append("<h2>Warnings</h2>" + warnings_block(result.warnings))
    parts.append("<h2>Parameters</h2>")
    ee = result.equation_error
    rows = [
        [n, u, _pm(float(v), float(s)), _pm(float(ev), float(es)), float(st), float(b)]
        for n, u, v, s, ev, es, st, b in zip(
            result.parameters,
            result.units,
            result.values,
            result.sigma,
            ee["values"],
            ee["sigma"],
            result.start,
            result.base,
        )
    ]
    parts.append(
        table(["parameter", "unit", "identified ± σ", "equation error ± σ", "start", "base file"], rows, left_cols=4)
    )
    parts.append(figure(to_png(correlation_figure(result.parameters, result.correlation)), "Parameter correlation"))
    parts.append("<h2>Runs</h2>")
    run_rows = []
    for r in result.runs:
        for c, d in r["channels"].items():
            run_rows.append(
                [
                    r["name"],
                    "held out" if r["holdout"] else "training",
                    c,
                    d["samples"],
                    d["residual_rms"],
                    d["whiteness"]["lag1"],
                    d.get("nrmse"),
                ]
            )
    parts.append(
        table(["run", "use", "channel", "samples", "residual RMS (SI)", "lag-1 ρ", "NRMSE"], run_rows, left_cols=3)
    )
    for p in result.predictions:
        cap = f"{p['name']}{' (held out: open-loop prediction)' if p['holdout'] else ''}: measured (dots), simulated (line), 95 % band from the covariance"
        parts.append(figure(to_png(run_figure(p), dpi=80), cap))
    parts.append(figure(to_png(residual_figure(result.predictions), dpi=80), "Residuals, measured − simulated (SI)"))
    return page(title, parts)


def output_files(result: SysidResult, base_data: Mapping[str, Any], out_dir: str, title: str = "") -> dict[str, str]:
    """DIR/vehicle.yaml, DIR/sysid.json, DIR/predictions.csv, DIR/report.html as texts."""
    import json
    from pathlib import Path

    import yaml

    d = Path(out_dir)
    vdoc = vehicle_document(result, base_data)
    head = "# identified by hydrokit sysid; uncertainty: σ and covariance of the free coefficients (SI)\n"
    return {
        str(d / "vehicle.yaml"): head
        + yaml.safe_dump(vdoc, sort_keys=False, allow_unicode=True, width=120, default_flow_style=None),
        str(d / "sysid.json"): json.dumps(result.to_dict(), indent=2, allow_nan=False, ensure_ascii=False) + "\n",
        str(d / "predictions.csv"): predictions_csv(result),
        str(d / "report.html"): report_html(
            result, title or f"System identification of {base_data.get('name', 'vehicle')}"
        ),
    }


def describe_runs(runs: Sequence[Any], holdout: Sequence[Any]) -> list[str]:
    """One line per run: name, duration, rows, channels and sample counts."""
    return [("held out  " if k >= len(runs) else "training  ") + r.describe() for k, r in enumerate([*runs, *holdout])]


def dive_files(
    base: Any, out_dir: str, n_runs: int, duration: float, seed: int, spread: float, amplitude: float, noise: float
) -> dict[str, str]:
    """Virtual dives of ``base`` with hidden coefficients (:mod:`hydrokit.simulate.sysid_data`)
    as DIR/diveN.csv run files and DIR/truth.json (the hidden values, SI)."""
    import json
    from pathlib import Path

    from hydrokit.io.runlog import run_csv
    from hydrokit.simulate.sysid_data import HIDDEN, generate_runs, hidden_vehicle
    from hydrokit.simulate.sysid_model import free_parameters, values_of

    truth = hidden_vehicle(base, seed, spread)
    dives = generate_runs(truth, n_runs, duration, seed, amplitude, noise)
    _, params = free_parameters(truth, HIDDEN)
    note = f"virtual dive of {base.name} with hidden coefficients (seed {seed})"
    files = {str(Path(out_dir) / f"{d.name}.csv"): run_csv(d.time, d.rows(), d.commands, comment=note) for d in dives}
    hidden = {p.name: float(v) for p, v in zip(params, values_of(truth, params))}
    doc = {"vehicle": base.name, "seed": seed, "spread": spread, "hidden": hidden}
    files[str(Path(out_dir) / "truth.json")] = json.dumps(doc, indent=2) + "\n"
    return files
