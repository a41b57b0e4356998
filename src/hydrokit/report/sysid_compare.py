"""Outputs of ``hydrokit sysid compare`` (issue #48 item 5): compare.json, each candidate's
identified vehicle.yaml and sysid.json in a folder of its name, and a self-contained HTML report
with the candidates side by side — built in memory so the caller writes them all or none."""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hydrokit.io.vehicle import identified_vehicle_document, vehicle_text
from hydrokit.report.html import esc, figure, page, table, warnings_block
from hydrokit.sysid.compare import EQUIVALENT, Comparison

_SYMBOL = {"phi": "φ", "theta": "θ", "psi": "ψ"}


def report_html(comparison: Comparison, title: str = "Model structures compared") -> str:
    """The candidates side by side: the recommendation, a ranking table (k, held-out NRMSE, AIC,
    BIC, ΔBIC, verdict), held-out NRMSE per channel (table and bars), each candidate's free
    parameters with their values and σ, and each verdict's reasons (user text escaped)."""
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.sysid import channel_order
    from hydrokit.plot.sysid_compare import heldout_figure

    cands = comparison.candidates
    best_bic = min(c.bic for c in cands)
    parts = [f"<h2>Keep {esc(comparison.keep)}</h2>", f"<p>{esc(comparison.recommendation)}</p>"]
    rows = []
    for i, name in enumerate(comparison.ranking, 1):
        c = comparison.by_name(name)
        rows.append(
            [
                i,
                c.name,
                c.source,
                c.k,
                c.heldout,
                f"{c.aic:.1f}",
                f"{c.bic:.1f}",
                f"{c.bic - best_bic:.1f}",
                "fits" if c.verdict["fits"] else "does NOT fit",
            ]
        )
    parts.append(
        table(
            ["rank", "candidate", "vehicle", "k", "held-out NRMSE (mean)", "AIC", "BIC", "ΔBIC", "verdict"],
            rows,
            left_cols=3,
        )
    )
    parts.append(
        "<p class='note'>Held-out NRMSE: RMS error of the open-loop prediction of the held-out runs over the "
        "standard deviation of the measured channel, averaged over the channels that move. AIC and BIC from the "
        "Gaussian output-error likelihood of the training residuals with the effective sample count for their "
        "autocorrelation; k = free parameters. Candidates within "
        f"{100 * EQUIVALENT:.0f} % of the lowest held-out error predict equally; of those the lowest BIC is kept. Effective samples (N_eff/N per channel, from "
        f"{esc(comparison.reference)}'s residuals): "
        + esc(", ".join(f"{_SYMBOL.get(c, c)} {100 * f:.0f} %" for c, f in comparison.effective.items()))
        + ".</p>"
    )
    if comparison.notes:
        parts.append(warnings_block(comparison.notes))
    parts.append("<h2>Held-out error per channel</h2>")
    channels = channel_order([ch for c in cands for ch in c.heldout_nrmse])
    parts.append(
        table(
            ["candidate", *[_SYMBOL.get(ch, ch) for ch in channels]],
            [[c.name, *[c.heldout_nrmse.get(ch) for ch in channels]] for c in cands],
        )
    )
    png = to_png(heldout_figure([c.name for c in cands], [c.heldout_nrmse for c in cands]), dpi=80)
    parts.append(figure(png, "Held-out NRMSE per channel and candidate (lower is better)"))
    parts.append("<h2>Identified parameters</h2>")
    names = list(dict.fromkeys(n for c in cands for n in c.result.parameters))
    prow = []
    for n in names:
        cells: list[Any] = [n]
        for c in cands:
            r = c.result
            if n in r.parameters:
                k = r.parameters.index(n)
                cells.append(f"{float(r.values[k]):.4g} ± {float(r.sigma[k]):.2g} {r.units[k]}")
            else:
                cells.append("fixed")
        prow.append(cells)
    parts.append(table(["parameter", *[c.name for c in cands]], prow, left_cols=len(cands) + 1))
    parts.append("<h2>Verdicts</h2>")
    for c in cands:
        v = c.verdict
        head = "describes the runs" if v["fits"] else "does NOT describe the runs"
        said = "".join(f"<p>{esc(r)}</p>" for r in v["reasons"]) if v["fits"] else warnings_block(v["reasons"])
        parts.append(f"<h3>{esc(c.name)}: {esc(head)}</h3>{said}")
        if c.result.messages:
            parts.append(warnings_block(c.result.messages))
    return page(title, parts)


def output_files(comparison: Comparison, base_data: Mapping[str, Mapping[str, Any]], out_dir: str) -> dict[str, str]:
    """DIR/compare.json, DIR/report.html and, per candidate, DIR/NAME/vehicle.yaml and
    DIR/NAME/sysid.json, as texts.

    Parameters
    ----------
    comparison : the ranked candidates
    base_data : candidate name → its base vehicle file's fields (for vehicle.yaml)
    out_dir : the output folder
    """
    d = Path(out_dir)
    files = {
        str(d / "compare.json"): json.dumps(comparison.to_dict(), indent=2, allow_nan=False, ensure_ascii=False) + "\n",
        str(d / "report.html"): report_html(comparison),
    }
    head = "# identified by hydrokit sysid compare; uncertainty: σ and covariance of the free coefficients (SI)\n"
    for c in comparison.candidates:
        files[str(d / c.name / "vehicle.yaml")] = vehicle_text(
            identified_vehicle_document(c.result, base_data[c.name]), head
        )
        files[str(d / c.name / "sysid.json")] = (
            json.dumps(c.result.to_dict(), indent=2, allow_nan=False, ensure_ascii=False) + "\n"
        )
    return files


__all__ = ["output_files", "report_html"]
