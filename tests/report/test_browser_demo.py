"""``hydrokit demo`` writes a report that renders in a real browser: headless Chromium loads it
without console errors, shows the title and every figure, and the figures decode."""

from __future__ import annotations

import html
import json
import re
import subprocess
import sys
from pathlib import Path

# the coefficient columns of the report's summary table, in order (m_a, C_m, K_L, K_Q, C_D, ω_n, ζ)
COLUMNS = ("added_mass", "added_mass_coefficient", "linear_damping", "quadratic_damping")
COLUMNS += ("drag_coefficient", "natural_frequency", "damping_ratio")


def test_demo_report_renders_in_chromium(tmp_path: Path, open_in_chromium, figures_ok) -> None:
    out = tmp_path / "demo"
    done = subprocess.run(
        [sys.executable, "-m", "hydrokit", "demo", "--out", str(out), "--campaign", "rov2"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    report = out / "report.html"
    source = report.read_text(encoding="utf-8")
    title = re.search(r"<h1>(.*?)</h1>", source, re.DOTALL)
    assert title, "the report has no <h1> title"
    n_img = source.count("<img")
    assert n_img >= 1

    page = open_in_chromium(report, tmp_path / "report.png")

    assert page.errors == [], f"console errors: {page.console}"
    assert page.text("h1") == [html.unescape(title[1]).strip()] == ["hydrokit identification: rov2 campaign"]
    # the browser shows the numbers of results.json: the summary row of each method, as
    # "method n mean ± std [CI]" per coefficient with 4 significant digits
    run = json.loads((out / "results.json").read_text())["pendulum rig, surge"]
    cells = page.text("td")
    for method, result in run.items():
        s = result["summary"]
        row = [method, str(s["added_mass"]["n"])]
        row += [f"{s[k]['mean']:.4g} ± {s[k]['std']:.4g} [{s[k]['ci'][0]:.4g}, {s[k]['ci'][1]:.4g}]" for k in COLUMNS]
        assert any(cells[i : i + len(row)] == row for i in range(len(cells))), (method, row)
    assert len(page.images) == n_img
    assert figures_ok(page) == []
    assert page.screenshot.stat().st_size > 0
