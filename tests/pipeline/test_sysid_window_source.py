"""The estimator of ``hydrokit run``'s sysid step is ``hydrokit sysid fit``'s: the project's
``sysid.window`` (a length in s, ``auto`` — the default, as ``--window`` — or ``none``) and
``sysid.window_continuity`` (dimensionless, default 0) reach the fit, the step's document says
which estimator fitted the runs and why, and bad values are one line naming ``sysid.window``.

The fits are real but small (one 6 s bundled dive, one free parameter: about a second each
compiled, so they skip under NUMBA_DISABLE_JIT).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.project import PROJECTS_DIR, load_project

BUNDLED = PROJECTS_DIR / "bluerov2_sysid"
VEHICLE = DATA_DIR / "vehicles" / "bluerov2-sysid.yaml"
FREE = ["linear_damping.heave"]


def make_project(tmp_path: Path, **sysid: Any) -> Path:
    """A project with one bundled 6 s dive and one free parameter; ``sysid`` adds fields."""
    shutil.copy(BUNDLED / "dive1.csv", tmp_path / "dive1.csv")
    doc = {
        "name": "w",
        "vehicle": str(VEHICLE),
        "sysid": {"runs": ["dive1.csv"], "free": list(FREE)} | sysid,
        "choose": {"default": "sysid"},
        "uncertainty": {"samples": 0, "seed": 1},
    }
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.fixture
def no_figures(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("hydrokit.pipeline.sysid._figures", lambda result: [])


def run(path: Path, out: Path) -> Any:
    from hydrokit.pipeline import run_project

    return run_project(path, out, workers=1)


@pytest.mark.needs_jit(reason="a real fit of one dive on the compiled batch RK4 (~1 s each, minutes interpreted)")
def test_the_default_is_auto_and_none_fits_whole_runs_as_asked(tmp_path, no_figures):
    path = make_project(tmp_path)
    spec = load_project(path).sysid
    assert spec is not None and spec.window == "auto" and spec.window_continuity == 0.0
    out = tmp_path / "out"
    auto = run(path, out).document["sysid"]
    assert auto["window"] == "auto" and auto["window_continuity"] == 0.0
    # a 6 s dive is too short to cut into 30 s windows: auto fits it whole, and says why
    assert auto["estimator"]["method"] == "output error, whole runs"
    assert auto["estimator"]["why"].startswith("window auto: ")
    assert auto["estimator"] == auto["result"]["estimator"]  # sysid.json's block

    path = make_project(tmp_path, window="none")
    res = run(path, out)
    none = res.document["sysid"]
    assert not next(t for t in res.timings if t["step"] == "sysid")["cached"]  # the window is in the key
    assert none["window"] == "none"
    assert none["estimator"] == {
        "method": "output error, whole runs",
        "window_s": None,
        "jacobian_step_s": None,
        "why": "as asked (window none)",
    }


@pytest.mark.needs_jit(reason="a real fit of one dive on the compiled batch RK4 (~1 s each, minutes interpreted)")
def test_a_window_length_and_continuity_reach_the_fit(tmp_path, no_figures):
    from hydrokit.report.run import run_report

    res = run(make_project(tmp_path, window="3s", window_continuity=2), tmp_path / "out")
    step = res.document["sysid"]
    assert step["window"] == 3.0 and step["window_continuity"] == 2.0
    assert step["estimator"]["method"] == "output error in windows" and step["estimator"]["window_s"] == 3.0
    assert step["result"]["windows"]["count"] == 2 and step["result"]["windows"]["continuity"] == 2.0
    # the report's sysid section says which estimator and why, its text escaped
    html = run_report(res)
    assert "Estimator: output error in windows of about 3 s" in html and "Asked: window 3 s, continuity 2" in html
    step["estimator"]["why"] = "as <asked> & more"
    assert "as &lt;asked&gt; &amp; more" in run_report(res) and "<asked>" not in run_report(res)


@pytest.mark.needs_jit(reason="a real fit of one dive on the compiled batch RK4 (~1 s each, minutes interpreted)")
def test_the_main_job_fits_as_hydrokit_sysid_fit_by_default(tmp_path, no_figures):
    """Same runs, free parameter and base vehicle, no window option on either side: the same
    estimator, and the same estimate to 1e-9 (one code path: only the threads' summation order
    could differ)."""
    from click.testing import CliRunner

    from hydrokit.cli.main import cli

    step = run(make_project(tmp_path), tmp_path / "out").document["sysid"]
    args = ["sysid", "fit", str(tmp_path / "dive1.csv"), "--vehicle", str(VEHICLE), "--free", FREE[0]]
    result = CliRunner().invoke(cli, [*args, "--out", str(tmp_path / "cli"), "--samples", "0", "--workers", "1"])
    assert result.exit_code == 0, result.output
    cli = json.loads((tmp_path / "cli" / "sysid.json").read_text())
    assert cli["estimator"] == step["estimator"]
    np.testing.assert_allclose(
        [p["value"] for p in cli["parameters"]], [step["parameters"][FREE[0]]["value"]], rtol=1e-9
    )


@pytest.mark.parametrize(
    ("fields", "says"),
    [
        ({"window": -3}, r"field 'sysid\.window' = -3: expected a length > 0 s, 'auto' or 'none'$"),
        ({"window": "banana"}, r"field 'sysid\.window' = 'banana': expected a length in seconds \(e\.g\. 30\), 'auto'"),
        ({"window": 0}, r"field 'sysid\.window' = 0: expected a length > 0 s"),
        ({"window": False}, r"field 'sysid\.window' = False: expected a length in seconds .*true/false"),
        ({"window": 7}, r"field 'sysid\.window' = 7 s is longer than run dive1 \(6 s\); expected a window ≤ 6 s"),
        ({"window_continuity": -1}, r"field 'sysid\.window_continuity' = -1: Input should be greater than or equal"),
    ],
)
def test_a_bad_window_is_one_line_naming_the_field(tmp_path, fields, says):
    from hydrokit.pipeline import run_project

    path = make_project(tmp_path, **fields)
    with pytest.raises(InputError, match=says) as info:
        run_project(path, tmp_path / "out", workers=1)
    assert "\n" not in str(info.value) and str(info.value).startswith(f"{path}: ")
    assert not (tmp_path / "out" / ".cache").exists()  # refused before any step
