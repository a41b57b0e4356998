"""``hydrokit sysid`` (issue #44): generate virtual dives, identify, write outputs whole or not at all."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml
from tests.simulate.test_sysid_surfaces import SHIP


@pytest.fixture()
def run_sysid(run_cli: Any) -> Any:
    """``run_cli`` (``sysid`` is registered in hydrokit.cli.main)."""
    return run_cli


@pytest.mark.needs_jit(reason="integrates 2 × 4 s of dives at a 2.5 ms step")
def test_generate_writes_dives_and_truth(run_sysid: Any, tmp_path: Path) -> None:
    code, _, err = run_sysid("sysid", "generate", "--out", tmp_path, "--runs", 2, "--duration", 4, "--seed", 3)
    assert code == 0, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dive1.csv", "dive2.csv", "truth.json"]
    assert len(json.loads((tmp_path / "truth.json").read_text())["hidden"]) == 12


def test_identify_writes_all_outputs(run_sysid: Any, tmp_path: Path) -> None:
    import hydrokit
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.data import generate_runs, hidden_vehicle

    # two 1.5 s dives integrated at 10 ms with yaw, yaw rate and surge speed (cheap without the
    # JIT), written as run files
    base = hydrokit.load_vehicle("bluerov2-sysid")
    for d in generate_runs(hidden_vehicle(base, 4), 2, 1.5, seed=4, dt=0.01):
        rows = {c: v for c, v in d.rows().items() if c in ("psi", "r", "u")}
        (tmp_path / f"{d.name}.csv").write_text(run_csv(d.time, rows, d.commands))
    out = tmp_path / "fit"
    code, out_text, err = run_sysid(
        "sysid", tmp_path / "dive1.csv", "--holdout", tmp_path / "dive2.csv", "--vehicle", "bluerov2-sysid",
        "--free", "added_mass.yaw,quadratic_damping.yaw", "--out", out, "--samples", 2, "--workers", 1, "--dt", 0.02,
    )  # fmt: skip
    assert code == 0, err
    assert "training  dive1: 1.5 s" in err and "held out  dive2" in err  # the start lists the runs
    assert sorted(p.name for p in out.iterdir()) == ["predictions.csv", "report.html", "sysid.json", "vehicle.yaml"]
    assert "quadratic_damping.yaw = " in out_text
    # the verdict leads stdout and sysid.json: per run the NRMSE/lag-1 ρ of every channel
    assert out_text.startswith("verdict: ") and "dive2 (held out)" in out_text
    assert out_text.index("verdict: ") < out_text.index("quadratic_damping.yaw = ")
    # the identified file is a vehicle that simulate --samples reads, with the fitted values
    doc = json.loads((out / "sysid.json").read_text())
    assert (
        list(doc)[0] == "verdict"
        and set(doc["verdict"]) == {"fits", "reasons", "details"}
        and doc["verdict"]["reasons"]
    )
    v = hydrokit.load_vehicle(out / "vehicle.yaml")
    assert v.uncertainty.parameters == ("added_mass.yaw", "quadratic_damping.yaw")
    assert v.M_A[5, 5] == doc["parameters"][0]["value"] and v.D_Q[5] == doc["parameters"][1]["value"]


@pytest.mark.slow
def test_cli_recovers_the_twelve_hidden_coefficients(run_sysid: Any, tmp_path: Path) -> None:
    logs, out = tmp_path / "logs", tmp_path / "fit"
    assert run_sysid("sysid", "generate", "--out", logs, "--runs", 3, "--duration", 8, "--seed", 3)[0] == 0
    truth = json.loads((logs / "truth.json").read_text())["hidden"]
    code, _, err = run_sysid(
        "sysid", logs / "dive1.csv", logs / "dive2.csv", "--holdout", logs / "dive3.csv",
        "--vehicle", "bluerov2-sysid", "--free", ",".join(truth), "--out", out, "--samples", 0,
    )  # fmt: skip
    assert code == 0, err
    for p in json.loads((out / "sysid.json").read_text())["parameters"]:
        # the generating truth within 4 σ (12 parameters: a chance failure has p < 1e-3)
        assert abs(p["value"] - truth[p["name"]]) < 4 * p["sigma"], p


def test_bad_inputs_exit_2_and_write_nothing(run_sysid: Any, tmp_path: Path) -> None:
    run = tmp_path / "run.csv"
    names = ["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]
    rows = "\n".join(f"{0.1 * k:.1f},0.0," + ",".join("0" for _ in names) for k in range(30))
    run.write_text("time,r," + ",".join(names) + "\n" + rows + "\n")
    out = tmp_path / "out"
    code, _, err = run_sysid("sysid", run, "--vehicle", "bluerov2-sysid", "--free", "added_mass.swirl", "--out", out)
    assert code == 2 and "free parameter 'added_mass.swirl' does not exist" in err
    assert not out.exists() or not any(out.iterdir())
    bad = tmp_path / "bad.csv"
    bad.write_text("time,r,FR\n0,0,0\n0.1,0,0\n0.2,0,0\n")
    code, _, err = run_sysid(
        "sysid", "fit", bad, "--vehicle", "bluerov2-sysid", "--free", "added_mass.yaw", "--out", out
    )
    assert code == 2 and "no column for thruster 'FL'" in err and str(bad) in err
    code, out_text, _ = run_sysid("sysid", "--help")
    assert code == 0 and "generate" in out_text


def test_a_bad_free_name_is_one_line_with_the_nearest_names_before_any_run_is_read(
    run_cli: Any, tmp_path: Path
) -> None:
    run = tmp_path / "run.csv"
    names = ["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]
    rows = "\n".join(f"{0.1 * k:.1f},0.0," + ",".join("0" for _ in names) for k in range(30))
    run.write_text("time,r," + ",".join(names) + "\n" + rows + "\n")
    missing = tmp_path / "missing.csv"  # never read: the free names are checked first
    out = tmp_path / "out"
    code, text, err = run_cli(
        "sysid", run, "--holdout", missing, "--vehicle", "bluerov2-sysid", "--free", "added_mass.yaw,lineer_damping.yaw",
        "--out", out,
    )  # fmt: skip
    assert code == 2 and text == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err  # no run listing before it
    assert "free parameter 'lineer_damping.yaw' does not exist (nearest: linear_damping.yaw" in lines[0]
    assert not out.exists() or not any(out.iterdir())
    # a delta() term naming no surface of the vehicle: before the fit, with the vehicle's terms near it
    ship = tmp_path / "ship.yaml"
    ship.write_text(yaml.safe_dump(SHIP))
    code, _, err = run_cli("sysid", run, "--vehicle", ship, "--free", "terms.N_uu*delta(ruder)", "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "delta(ruder) names no control surface" in err and "nearest: terms.N_uu*delta(rudder)" in err
    # a misspelt term: the nearest of the vehicle's own terms
    code, _, err = run_cli("sysid", run, "--vehicle", ship, "--free", "terms.N_uu*delta(rudder", "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "(nearest: terms.N_uu*delta(rudder)" in err
