"""``hydrokit sysid --window`` and ``--window-continuity`` (issue #48 items 3 and 9): a bad or
too-long window, or a bad continuity weight, is refused in one line with exit 2 and nothing
written."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from tests.simulate.test_sysid_surfaces import SHIP, _ship


def _files(tmp_path: Path) -> tuple[Path, Path]:
    """One 20 s generated run of the ship as a run file, and the ship's vehicle file."""
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.ship import ship_runs

    run = ship_runs(_ship(), 1, 20.0, seed=1, dt=0.01)[0]
    p = tmp_path / "run1.csv"
    rows = {c: y for c, (_, y) in run.channels.items()}
    p.write_text(run_csv(run.time, rows, run.commands, comment="generated", deflections=run.deflections))
    v = tmp_path / "ship.yaml"
    v.write_text(yaml.safe_dump(SHIP))
    return p, v


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [
        ("--window", "30", "--window: window 30 s is longer than run run1 (20 s); expected a window ≤ 20 s, or 'none'"),
        ("--window", "abc", "--window: window 'abc': expected a length in seconds (e.g. 30), 'auto' or 'none'"),
        ("--window", "-5", "--window: window -5.0: expected a length > 0 s, 'auto' or 'none'"),
        ("--window-continuity", "-1", "--window-continuity '-1': expected a finite number ≥ 0"),
        ("--window-continuity", "abc", "--window-continuity 'abc': expected a finite number ≥ 0"),
        ("--window-continuity", "nan", "--window-continuity 'nan': expected a finite number ≥ 0"),
    ],
)
def test_a_bad_window_is_one_line_exit_2_and_nothing_written(
    run_cli: Any, tmp_path: Path, option: str, value: str, message: str
) -> None:
    run, vehicle = _files(tmp_path)
    out = tmp_path / "fit"
    code, text, err = run_cli("sysid", run, "--vehicle", vehicle, "--free", "terms.N_uv", "--out", out, option, value)
    assert code == 2
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and message in lines[0], err
    assert "Traceback" not in err and text == ""
    assert not out.exists()
