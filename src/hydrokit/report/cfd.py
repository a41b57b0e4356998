"""The HTML report of a CFD sweep (``hydrokit cfd … --out DIR`` → ``DIR/report.html``).

Sections: the body and fluid; every case (status, cells, mesh checks, iterations, y⁺, σ, wall
time); resistance against speed with the Chin/Morison fits and error bars; loads against angle
and rate; the derivatives with standard errors, dimensional and non-dimensional; convergence
histories; warnings. User text (body name, labels, reasons) is escaped.
"""

from __future__ import annotations

from typing import Any

from hydrokit.report.html import esc, figure, fmt, page, table, warnings_block


def _case_rows(result: Any) -> list[list[Any]]:
    rows = []
    for o in result.outcomes:
        mesh = o.get("mesh") or {}
        yp = o.get("y_plus") or [None, None, None]
        rows.append(
            [
                o.get("label", ""),
                o.get("status", ""),
                o.get("model", ""),
                o.get("reynolds"),
                mesh.get("cells"),
                mesh.get("failed_checks"),
                mesh.get("max_non_orthogonality"),
                o.get("iterations"),
                yp[0],
                yp[1],
                o.get("wall_time"),
                "yes" if o.get("cached") else "no",
            ]
        )
    return rows


def render(result: Any) -> str:
    """The whole report as one self-contained HTML string."""
    from hydrokit.plot import cfd as plots
    from hydrokit.plot._mpl import to_png

    parts = [
        f"<p>Body <b>{esc(result.body)}</b>: reference length L = {fmt(result.length)} m, reference area "
        f"A = {fmt(result.area)} m²; fluid ρ = {fmt(result.density)} kg/m³, ν = {fmt(result.viscosity)} m²/s. "
        f"Angle and rate cases at U = {fmt(result.reference_speed)} m/s. Ran on: {esc(result.executor)}, "
        f"{fmt(result.wall_time, 3)} s.</p>",
        '<p class="note">Loads are the hydrodynamic force and moment on the body about its origin in body axes '
        "(x forward, y starboard, z down; SNAME signs: resistance is negative X). σ is the iterative or "
        "unsteadiness standard deviation from the force history; GCI (three grids) is Roache's grid "
        "convergence index of the finest grid's value.</p>",
    ]
    if result.warnings:
        parts.append("<h2>Warnings</h2>" + warnings_block(result.warnings))
    parts.append("<h2>Cases</h2>")
    parts.append(
        table(
            [
                "case",
                "status",
                "model",
                "Re_L",
                "cells",
                "failed checks",
                "max non-ortho (°)",
                "iterations",
                "y⁺ min",
                "y⁺ max",
                "wall time (s)",
                "cached",
            ],
            _case_rows(result),
            left_cols=3,
        )
    )
    header, rows = result.table()
    parts.append("<h2>Loads</h2>")
    parts.append('<div style="overflow-x:auto">' + table(header, rows, left_cols=1) + "</div>")
    if result.fits:
        parts.append("<h2>Force against speed (CELY2019 §4.1, Chin fit)</h2>")
        parts.append(
            table(
                ["axis", "K_L (N·s/m)", "σ", "K_Q (N·s²/m²)", "σ", "R² Chin", "K_D (N·s²/m²)", "C_D", "R² Morison"],
                [
                    [a, f.K_L, f.K_L_se, f.K_Q, f.K_Q_se, f.r2_chin, f.K_D, f.C_D, f.r2_morison]
                    for a, f in result.fits.items()
                ],
            )
        )
        parts.append(
            figure(
                to_png(plots.resistance_figure(result)),
                "Resistance against speed: CFD points with max(σ, GCI) bars and the fits",
            )
        )
    sweep = plots.sweep_figure(result)
    if sweep is not None:
        parts.append("<h2>Virtual tow tank and rotating arm</h2>")
        parts.append(
            figure(to_png(sweep), "Loads against drift/attack angle and yaw/pitch rate at the reference speed")
        )
    if result.derivatives:
        parts.append("<h2>Derivatives (LI2021 form)</h2>")
        parts.append(
            table(
                ["term", "SI value", "σ", "non-dimensional (÷ ½ρL^k)", "σ", "k", "points"],
                [
                    [d.name, d.value, d.se, d.nondimensional, d.nondimensional_se, d.k, d.points]
                    for d in result.derivatives
                ],
            )
        )
    shown = [o for o in result.outcomes if o.get("slice")][:2]
    if shown:
        parts.append("<h2>Flow</h2>")
        for o in shown:
            fig = plots.slice_figure(o)
            if fig is not None:
                parts.append(figure(to_png(fig), f"{o['label']}: |U|/U∞ on the body's x–y plane"))
    parts.append("<h2>Convergence</h2>")
    parts.append(
        figure(
            to_png(plots.convergence_figure(result)), "Axial force history of each case, normalised by its last value"
        )
    )
    n_fail = sum(1 for o in result.outcomes if o.get("status") == "failed")
    if n_fail:
        parts.append(
            f'<p class="warn">{n_fail} case(s) failed; their rows are empty (see cfd.json for the reasons).</p>'
        )
    title = f"hydrokit cfd — {result.body}"
    return page(title, parts)
