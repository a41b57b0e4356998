"""A vehicle whose fit said "does not fit" (issue #48): ``simulate`` and ``manoeuvre`` fly it with one
loud warning (stderr, manoeuvre.json, the report's banner), ``--strict`` refuses it writing nothing;
a vehicle that fits, or whose file has no ``identification:`` block, flies without a word."""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

import pytest
import yaml
from tests.cli.test_manoeuvre_cli import BOAT

from hydrokit.io.vehicle import resolve_vehicle

REASON = "pond3 (held out): held-out NRMSE of v 0.57 > 0.5 and residuals lag-1 ρ 0.98: <see the report> & fix it."
UNFIT = 'its identification says "does not fit"'


def _vehicle(tmp_path: Path, text: str, verdict: str | None) -> Path:
    """``text`` (a vehicle file) with an identification block saying ``verdict`` (None: no block)."""
    doc = yaml.safe_load(text)
    if verdict is not None:
        doc["identification"] = {"verdict": verdict, "reasons": [REASON], "runs": ["pond1"], "holdout": ["pond3"]}
    path = tmp_path / "vehicle.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return path


def _warning(path: Path) -> str:
    return f"{path}: {UNFIT} ({REASON.rstrip('.')}): the predictions below are not trustworthy"


def _simulate(run_cli: Any, tmp_path: Path, verdict: str | None, *extra: str) -> tuple[Path, int, str, str]:
    path = _vehicle(tmp_path, resolve_vehicle("bluerov2-heavy").read_text(), verdict)
    out = tmp_path / "t.csv"
    code, stdout, err = run_cli("simulate", path, "--duration", "1", "--force", "20,0,0,0,0,0", "--out", out, *extra)
    return out, code, stdout, err


def test_simulate_warns_once_of_a_vehicle_that_does_not_fit(run_cli: Any, tmp_path: Path) -> None:
    out, code, _, err = _simulate(run_cli, tmp_path, "does not fit")
    assert code == 0, err
    assert err.count(UNFIT) == 1
    assert f"warning: {_warning(tmp_path / 'vehicle.yaml')}" in err.splitlines()
    assert out.is_file()


@pytest.mark.parametrize("verdict", ["fits", None])
def test_simulate_says_nothing_of_a_vehicle_that_fits_or_makes_no_claim(
    run_cli: Any, tmp_path: Path, verdict: str | None
) -> None:
    out, code, _, err = _simulate(run_cli, tmp_path, verdict, "--strict")
    assert code == 0, err
    assert "identification" not in err and out.is_file()


def test_simulate_strict_refuses_it_writing_nothing(run_cli: Any, tmp_path: Path) -> None:
    plots = tmp_path / "plots"
    out, code, stdout, err = _simulate(run_cli, tmp_path, "does not fit", "--strict", "--plots", str(plots))
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err and stdout == ""
    assert f"{tmp_path / 'vehicle.yaml'}: {UNFIT} (pond3 (held out)" in err and "refused under --strict" in err
    assert not out.exists() and not plots.exists()


def _manoeuvre(run_cli: Any, tmp_path: Path, verdict: str | None, *extra: str) -> tuple[Path, int, str, str]:
    path = _vehicle(tmp_path, BOAT, verdict)
    out = tmp_path / "tc"
    args = ("--turning-circle", "35", "--dt", "0.1", "--force", "20,0,0,0,0,0", "--out", out, *extra)
    code, stdout, err = run_cli("manoeuvre", path, *args)
    return out, code, stdout, err


def test_manoeuvre_warns_in_stderr_json_and_report(run_cli: Any, tmp_path: Path) -> None:
    out, code, stdout, err = _manoeuvre(run_cli, tmp_path, "does not fit")
    assert code == 0, err
    warning = _warning(tmp_path / "vehicle.yaml")
    assert err.count(UNFIT) == 1 and f"warning: {warning}" in err.splitlines()
    assert "tactical diameter" in stdout  # still flown: the user may want to look
    doc = json.loads((out / "manoeuvre.json").read_text())
    assert doc["warnings"][0] == warning and sum(UNFIT in w for w in doc["warnings"]) == 1
    assert "tactical_diameter" in doc["turning_circle"]  # the frozen keys stay
    page = (out / "report.html").read_text()
    banner = f'<p class="warn">{html.escape(warning)}</p>'
    # a banner above everything the report predicts, the reason's user text escaped
    assert page.count(banner) == 1 and page.index(banner) < page.index("<h2>Metrics</h2>")
    assert "<see the report>" not in page and "&lt;see the report&gt; &amp; fix it" in page


@pytest.mark.parametrize("verdict", ["fits", None])
def test_manoeuvre_says_nothing_of_a_vehicle_that_fits_or_makes_no_claim(
    run_cli: Any, tmp_path: Path, verdict: str | None
) -> None:
    out, code, _, err = _manoeuvre(run_cli, tmp_path, verdict, "--strict", "--no-plots")
    assert code == 0, err
    assert "identification" not in err
    assert not any("identification" in w for w in json.loads((out / "manoeuvre.json").read_text())["warnings"])


def test_manoeuvre_strict_refuses_it_writing_nothing(run_cli: Any, tmp_path: Path) -> None:
    out, code, stdout, err = _manoeuvre(run_cli, tmp_path, "does not fit", "--strict")
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err and stdout == ""
    assert UNFIT in err and "refused under --strict" in err
    assert not out.exists() or not any(out.iterdir())


def test_sysid_writes_the_verdict_it_printed(run_cli: Any, tmp_path: Path) -> None:
    """End to end through ``hydrokit sysid`` (the fast recipe of tests/cli/test_sysid_cli.py): the
    written vehicle's block holds sysid.json's verdict, and simulate says it when it does not fit."""
    import hydrokit
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.data import generate_runs, hidden_vehicle

    base = hydrokit.load_vehicle("bluerov2-sysid")
    for d in generate_runs(hidden_vehicle(base, 4), 2, 1.5, seed=4, dt=0.01):
        rows = {c: v for c, v in d.rows().items() if c in ("psi", "r", "u")}
        (tmp_path / f"{d.name}.csv").write_text(run_csv(d.time, rows, d.commands))
    out = tmp_path / "fit"
    code, _, err = run_cli(
        "sysid", tmp_path / "dive1.csv", "--holdout", tmp_path / "dive2.csv", "--vehicle", "bluerov2-sysid",
        "--free", "added_mass.yaw,quadratic_damping.yaw", "--out", out, "--samples", 0, "--workers", 1, "--dt", 0.02,
    )  # fmt: skip
    assert code == 0, err
    verdict = json.loads((out / "sysid.json").read_text())["verdict"]
    block = yaml.safe_load((out / "vehicle.yaml").read_text())["identification"]
    assert block["verdict"] == ("fits" if verdict["fits"] else "does not fit")
    assert block["reasons"] == verdict["reasons"]
    assert block["runs"] == ["dive1"] and block["holdout"] == ["dive2"] and set(block["holdout_nrmse"]) <= {"dive2"}
    code, _, err = run_cli("simulate", out / "vehicle.yaml", "--duration", "0.5", "--out", tmp_path / "t.csv")
    assert code == 0, err
    assert (UNFIT in err) is (not verdict["fits"])
