"""The HTML report of a standard manoeuvre (``hydrokit manoeuvre … --out DIR`` → ``DIR/report.html``).

Sections: the run (vehicle, surface, settings, approach speed); the metrics with units and the
definitions they follow (IMO MSC.137(76), ITTC 7.5-04-02-01); for surface craft the IMO criteria
with pass/fail; the track and time figures; warnings. A vehicle whose ``identification:`` block
says "does not fit", or whose approach misses its own runs' speed (the ``envelope:`` block: "the
model does not hold"), has its warning as a banner above everything; a prediction that leaves
the envelope is said under the run's description. User text is escaped.
"""

from __future__ import annotations

from typing import Any

from hydrokit.model.envelope import does_not_hold, is_envelope_line
from hydrokit.model.identification import is_unfit_warning
from hydrokit.report.html import esc, figure, fmt, page, table, warnings_block

DEFINITIONS = (
    "Every metric is measured from the execute point (the position and heading when the first order "
    "was given), after a straight approach at steady speed. Advance: distance along the original course "
    "to 90° of heading change; transfer: across it at 90°; tactical diameter: across it at 180° (IMO "
    "MSC.137(76) 4.2.3–4.2.4); steady turning diameter, speed, yaw rate and drift angle over the last 360° "
    "of a turn held to 540° (ITTC 7.5-04-02-01 2.2.1). Zigzag: initial turning time to the second execute, "
    "overshoots past ±B after the second and third executes (IMO 4.2.7–4.2.8), period between the second "
    "and fourth executes. Pull-out (ITTC 2.2.6): steady turns at +δ and −δ, each from a straight course, "
    "released to zero: the residual yaw rate, the time to half the turn's rate and the time to settle within "
    "5 %. Spiral (ITTC 2.2.5): each step held until the yaw rate's means over two windows of 5 L/U agree."
)


def _cell(v: Any) -> Any:
    if isinstance(v, bool) or v is None:
        return "–" if v is None else ("yes" if v else "no")
    if isinstance(v, (list, tuple)):
        return ", ".join(fmt(x) for x in v)
    return v if isinstance(v, (int, float, str)) else str(v)


def _unit(key: str, units: dict[str, str]) -> str:
    leaf = key.rsplit(".", 1)[-1]
    return units.get(leaf, "deg" if leaf.endswith("_deg") else "")


def render(result: Any, figures: dict[str, bytes] | None = None) -> str:
    """The whole report as one self-contained HTML string (``figures``: PNG bytes by name; None:
    rendered here)."""
    from hydrokit.manoeuvre.metrics import UNITS

    if figures is None:
        from hydrokit.plot._mpl import to_png
        from hydrokit.plot.manoeuvre import figures as make

        figures = {k: to_png(f) for k, f in make(result).items()}
    doc = result.to_dict()
    params = ", ".join(f"{k} = {fmt(v) if not isinstance(v, str) else v}" for k, v in doc["parameters"].items())
    # a vehicle whose fit said "does not fit" (issue #48): said before anything it predicts
    # and a model that misses its own runs' speed (issue #56 item 7)
    unfit = [w for w in result.warnings if is_unfit_warning(w) or does_not_hold(w)]
    outside = [w for w in result.warnings if is_envelope_line(w) and w not in unfit]
    parts = [] if not unfit else [warnings_block(unfit)]
    parts += [
        f"<p>Vehicle <b>{esc(result.vehicle)}</b>, steered by <b>{esc(result.surface)}</b>; {esc(params)}. "
        f"Approach speed {fmt(result.approach_speed)} m/s"
        + (f", reference length L = {fmt(result.reference_length)} m" if result.reference_length else "")
        + ".</p>",
        *(f"<p><b>{esc(w)}</b></p>" for w in outside),
        f'<p class="note">{esc(DEFINITIONS)}</p>',
    ]
    if result.problem:
        parts.append(warnings_block([result.problem]))
    rows = [
        [k, _cell(v), UNITS.get(k, "deg" if k.endswith("_deg") else "")]
        for k, v in result.metrics.items()
        if k not in ("points", "sides")
    ]
    parts.append("<h2>Metrics</h2>" + table(["metric", "value", "unit"], rows, left_cols=1))
    for key in ("points", "sides"):
        items = result.metrics.get(key)
        if items:
            head = list(items[0])
            parts.append(table(head, [[_cell(p[h]) for h in head] for p in items], left_cols=0))
    found = doc.get("intervals")
    if found:
        sampling = doc["sampling"]
        parts.append(
            f'<h2>95 % intervals</h2><p class="note">{sampling["samples"]} vehicles drawn from the vehicle file\'s '
            f"covariance ({esc(', '.join(sampling['parameters']))}; seed {sampling['seed']}), each flown through "
            "the same manoeuvre; median and the 2.5–97.5 % points of the draws that reached each metric.</p>"
        )
        parts.append(
            table(
                ["metric", "median", "low 95 %", "high 95 %", "samples", "unit"],
                [
                    [k, _cell(iv["median"]), _cell(iv["low95"]), _cell(iv["high95"]), iv["samples"], _unit(k, UNITS)]
                    for k, iv in found.items()
                ],
                left_cols=1,
            )
        )
    crit = doc.get("imo_criteria")
    if crit is not None:
        parts.append("<h2>IMO MSC.137(76) criteria (surface craft)</h2>")
        if crit:
            parts.append(
                table(
                    ["criterion", "value", "limit", "unit", "passed", "note"],
                    [[c["criterion"], c["value"], c["limit"], c["unit"], _cell(c["passed"]), c["note"]] for c in crit],
                )
            )
        else:
            parts.append(
                '<p class="note">No criterion applies to this run (they need the vehicle\'s '
                "reference_length and a turning circle, a 10°/10° or a 20°/20° zigzag).</p>"
            )
    parts.append("<h2>Figures</h2>")
    captions = {
        "track.png": "Track from the execute point (m), metrics drawn on it; triangles: later executes",
        "time.png": "Heading (or pitch and depth), rate and deflection against time from the execute",
        "spiral.png": "Steady yaw rate against deflection, in the order flown",
    }
    for name, png in figures.items():
        parts.append(figure(png, captions.get(name, name)))
    others = [w for w in result.warnings if w not in unfit and w not in outside]
    if others:
        parts.append("<h2>Warnings</h2>" + warnings_block(others))
    return page(f"hydrokit manoeuvre — {result.vehicle}: {result.kind.replace('_', ' ')}", parts)
