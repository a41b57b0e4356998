"""``hydrokit demo`` writes a report that renders in a real browser: headless Chromium loads it
without console errors, shows the title and every figure, and the figures decode."""

from __future__ import annotations

import html
import re
import subprocess
import sys
from pathlib import Path


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
    assert page.text("h1") == [html.unescape(title[1]).strip()]
    assert "rov2" in page.text("h1")[0]
    assert len(page.images) == n_img
    assert figures_ok(page) == []
    assert page.screenshot.stat().st_size > 0
