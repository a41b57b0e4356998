"""What ``hydrokit manoeuvre`` prints (kept apart so the command module stays short): the warnings
and the envelope's lines on stderr, the propulsion, what was held, then the metrics, intervals and
IMO criteria on stdout."""

from __future__ import annotations

from typing import Any

import click


def print_warnings(warnings: list[str]) -> None:
    """Each warning as ``warning: …`` on stderr, the envelope's lines (issue #56 item 7) as they are
    (``envelope: the model does not hold …``) after them."""
    from hydrokit.model.envelope import is_envelope_line

    for w in warnings:
        if not is_envelope_line(w):
            click.echo(f"warning: {w}", err=True)
    for w in warnings:
        if is_envelope_line(w):
            click.echo(w, err=True)


def print_result(res: Any, samples: int, seed: int) -> None:
    """The propulsion's thrusts and what was held (stderr), then the manoeuvre's metrics, its
    intervals and the IMO criteria (stdout)."""
    from hydrokit.manoeuvre.metrics import describe
    from hydrokit.manoeuvre.samples import interval_lines

    if res.propulsion:
        a, b = res.propulsion["thrust_at_execute"], res.propulsion["thrust_at_end"]
        click.echo(
            "thrust: " + ", ".join(f"{k} {a[k]:.4g} N at the execute, {b[k]:.4g} N at the end" for k in a), err=True
        )
    trim = ", ".join(f"{k} {v * 57.29577951308232:+.2f}°" for k, v in res.approach_deflection.items() if abs(v) > 1e-3)
    if res.hold and (res.hold != {"heading": f"{res.surface} (approach)"} or trim):  # more than a straight approach
        trim = f"; approach trim {trim}" if trim else ""
        click.echo("held: " + ", ".join(f"{k} by {n}" for k, n in res.hold.items()) + trim, err=True)
    kind = res.kind
    click.echo(f"{'pull-out' if kind == 'pull_out' else kind.replace('_', ' ')}{_setting(res)}, {res.surface}:")
    for line in describe(kind, res.metrics):
        click.echo("  " + line)
    if res.intervals is not None:
        click.echo(f"95 % intervals of {samples} vehicles from the file's covariance (seed {seed}):")
        for line in interval_lines(res.intervals):
            click.echo("  " + line)
    for c in res.imo():
        verdict = "–" if c["passed"] is None else "pass" if c["passed"] else "FAIL"
        click.echo(f"IMO {c['criterion']}: {verdict}")


def _setting(res: Any) -> str:
    """The manoeuvre's settings as a person reads them: " at 35°", " 10°/10°", " +5 m at 15°",
    " (direct)"."""
    p = res.manoeuvre.parameters()
    a = p.get("deflection_deg")
    if "check_angle_deg" in p:
        return f" {a:.4g}°/{p['check_angle_deg']:.4g}°"
    if "depth_change" in p:
        how = f" at {abs(a):.4g}° (open loop)" if p["loop"] == "open" else f", pitch within ±{p['max_pitch_deg']:.4g}°"
        return f" {p['depth_change']:+.4g} m{how}"
    if "mode" in p:
        return f" ({p['mode']}" + ("" if a is None else f", up to {a:.4g}°") + ")"
    return f" at ±{abs(a):.4g}°" if res.kind == "pull_out" else f" at {a:.4g}°"
