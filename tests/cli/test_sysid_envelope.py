"""Predictions inside the identification's envelope (issue #56 item 7).

On the Esso Osaka pond runs a fit whose surge resistance sat at a bound flew its turning circles at
two to three times the speed its own runs ran at those revolutions, with one easily-missed warning.
Here a planar ship (:mod:`tests.simulate.test_sysid_surfaces`'s 3 m model) runs straight ahead with a small rudder at two propeller speeds, each run starting at its
steady speed; ``hydrokit sysid`` fits its surge resistance and writes the runs' envelope into
vehicle.yaml. The envelope's speed at each propeller speed must be the runs' own, computed here from
the run files; the reader round-trips the block and refuses bad ones in one line. The fitted vehicle
flown by ``manoeuvre`` and ``simulate`` at a propeller speed its runs held keeps their speed; the
same file with its resistance halved does not — it says so in words, in manoeuvre.json and the
report, and ``--strict`` refuses it; a propeller speed beyond the runs' is said to extrapolate.
"""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from tests.simulate.test_sysid_surfaces import SHIP

from hydrokit.errors import InputError

#: run file → (propeller speed rev/s, seed); each run 60 s, rudder within ±2°
RUNS = {"fast1": (20.0, 3), "fast2": (20.0, 4), "slow": (15.0, 5)}
DURATION = 60.0
#: the truth's surge resistance (N s²/m²) and where the fit starts
D_SURGE, START = 40.0, 28.0
NOT_HOLD = "envelope: the model does not hold at its own runs' speed"
EXTRAPOLATES = "envelope: the prediction extrapolates beyond the identification"


def _truth() -> dict[str, Any]:
    return copy.deepcopy(SHIP)


def _steady(vehicle: Any, n: float) -> float:
    """The truth's straight-line speed at n rev/s (m/s): thrust = D u² (no other surge force)."""
    from scipy.optimize import brentq

    th = vehicle.thrusters

    def excess(u: float) -> float:
        nu = np.array([u, 0, 0, 0, 0, 0.0])
        return float((th.configuration_matrix() @ th.thrust([n], th.advance_speed(nu)))[0]) - D_SURGE * u * u

    return float(brentq(excess, 0.01, 5.0))


@pytest.fixture(scope="module")
def fit(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The runs as files (``runs/NAME.csv``) and ``fit/`` written by ``hydrokit sysid``."""
    from hydrokit.api import vehicle_from_dict
    from hydrokit.cli.main import main
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.ship import ship_runs

    root = tmp_path_factory.mktemp("envelope")
    truth = vehicle_from_dict(_truth(), "truth")
    (root / "runs").mkdir()
    for name, (n, seed) in RUNS.items():
        (run,) = ship_runs(truth, 1, DURATION, seed, speed=n, rudder=math.radians(2), u0=_steady(truth, n))
        chans = {c: y for c, (_, y) in run.channels.items()}
        (root / "runs" / f"{name}.csv").write_text(run_csv(run.time, chans, run.commands, deflections=run.deflections))
    base = _truth()
    base["quadratic_damping"][0] = START
    (root / "base.yaml").write_text(yaml.safe_dump(base))
    files = [root / "runs" / f"{n}.csv" for n in RUNS]
    args = [*files, "--vehicle", root / "base.yaml", "--free", "quadratic_damping.surge", "--out", root / "fit"]
    assert main([str(a) for a in ["sysid", *args, "--dt", 0.05, "--samples", 0, "--window", "none"]]) == 0
    return root


def _spoiled(fit: Path, out: Path, keep_envelope: bool = True) -> Path:
    """vehicle.yaml with its fitted surge resistance halved (and, if asked, no envelope)."""
    doc = yaml.safe_load((fit / "fit" / "vehicle.yaml").read_text())
    doc["quadratic_damping"][0] *= 0.5
    if not keep_envelope:
        del doc["envelope"]
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def _columns(path: Path) -> dict[str, np.ndarray]:
    with path.open() as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    head = lines[0].strip().split(",")
    data = np.loadtxt(lines[1:], delimiter=",")
    return {h: data[:, k] for k, h in enumerate(head)}


@pytest.mark.needs_jit(reason="a CLI output-error fit of three 60 s runs")
def test_the_envelope_holds_the_runs_speed_at_each_propeller_speed(fit: Path) -> None:
    written = yaml.safe_load((fit / "fit" / "vehicle.yaml").read_text())["envelope"]
    assert json.loads((fit / "fit" / "sysid.json").read_text())["envelope"] == written
    runs = {n: _columns(fit / "runs" / f"{n}.csv") for n in RUNS}
    speed = {n: np.hypot(c["u"], c["v"]) for n, c in runs.items()}
    levels = {lv["command"]["prop"]: lv for lv in written["speed_per_command"]}
    assert sorted(levels) == [15.0, 20.0]
    # independently: each run started at its steady speed and ran straight, so every sample is
    # steady; the envelope used the second half of each. abs 1.5e-3 m/s: 5 × the noise of a mean of
    # 300 samples against one of 600 (σ_u = 0.005 m/s, SHIP_NOISE)
    means = [float(np.mean(speed[n])) for n in ("fast1", "fast2")]
    assert levels[20.0]["speed"] == pytest.approx(np.mean(means), abs=1.5e-3)
    assert levels[20.0]["runs"] == 2 and levels[20.0]["scatter"] < 2e-3  # two means of one steady speed
    assert levels[15.0]["speed"] == pytest.approx(np.mean(speed["slow"]), abs=1.5e-3)
    # one run: the scatter is its samples' standard deviation (the sensor noise): rel 0.3
    assert levels[15.0]["runs"] == 1
    assert levels[15.0]["scatter"] == pytest.approx(np.std(speed["slow"], ddof=1), rel=0.3)
    # the ranges, to the 6 significant digits written (rel 1e-5)
    assert written["command_range"] == {"prop": [15.0, 20.0]}
    rudder = max(float(np.max(np.abs(c["rudder"]))) for c in runs.values())
    assert written["deflection_deg"]["rudder"] == pytest.approx(math.degrees(rudder), rel=1e-5)
    assert written["yaw_rate"] == pytest.approx(max(float(np.max(np.abs(c["r"]))) for c in runs.values()), rel=1e-5)
    assert written["speed"][1] == pytest.approx(max(float(np.max(s)) for s in speed.values()), rel=1e-5)
    assert written["runs"] == list(RUNS)


@pytest.mark.needs_jit(reason="reads the fit's vehicle")
def test_the_reader_round_trips_the_block_and_refuses_bad_ones_in_one_line(fit: Path, tmp_path: Path) -> None:
    from hydrokit.api import load_vehicle

    path = fit / "fit" / "vehicle.yaml"
    doc = yaml.safe_load(path.read_text())
    env = load_vehicle(path).envelope
    assert env is not None and env.to_dict() == doc["envelope"]
    bad = {
        "speeds": ("envelope", {"speeds": [0, 1]}, r"envelope\.speeds"),
        "negative speed": ("speed_per_command", [{"command": {"prop": 20}, "speed": -1, "scatter": 0}], r"speed_per_command\[0\]\.speed"),
        "unknown thruster": ("command_range", {"stern": [0, 1]}, r"command_range\.stern': the vehicle has thrusters prop"),
        "reversed": ("speed", [0.5, 0.1], r"envelope\.speed' = \[0\.5, 0\.1\]: expected the least first"),
        "unknown surface": ("deflection_deg", {"flap": 10}, r"deflection_deg\.flap': the vehicle has control surfaces rudder"),
        "drift": ("drift_deg", 200, r"drift_deg' = 200: expected an angle from 0 to 180"),
        "text": ("yaw_rate", "fast", r"envelope\.yaw_rate"),
        "no scatter": ("speed_per_command", [{"command": {"prop": 20}, "speed": 0.3}], r"has no 'scatter'"),
    }  # fmt: skip
    for what, (key, value, match) in bad.items():
        broken = copy.deepcopy(doc)
        if key == "envelope":
            broken["envelope"].update(value)
        else:
            broken["envelope"][key] = value
        f = tmp_path / f"{what.replace(' ', '-')}.yaml"
        f.write_text(yaml.safe_dump(broken))
        with pytest.raises(InputError, match=match) as caught:
            load_vehicle(f)
        assert "\n" not in str(caught.value), what


@pytest.mark.needs_jit(reason="turning circles and runs of the fitted ship")
def test_a_model_off_its_runs_speed_is_said_not_to_hold(fit: Path, tmp_path: Path, run_cli: Any) -> None:
    level = {lv["command"]["prop"]: lv for lv in yaml.safe_load((fit / "fit" / "vehicle.yaml").read_text())["envelope"]["speed_per_command"]}[20.0]  # fmt: skip
    turn = ("--turning-circle", 35, "--dt", 0.2, "--no-plots")
    # the fit: its approach at 20 rev/s keeps the runs' speed; only the 35° rudder is new
    code, _, err = run_cli(
        "manoeuvre", fit / "fit" / "vehicle.yaml", *turn, "--command", "prop=20", "--out", tmp_path / "ok"
    )
    assert code == 0, err
    assert NOT_HOLD not in err and EXTRAPOLATES in err and "rudder 35°" in err, err
    doc = json.loads((tmp_path / "ok" / "manoeuvre.json").read_text())["envelope"]
    assert doc["holds"] is True and doc["speed_check"]["runs_speed"] == level["speed"]
    assert abs(doc["speed_check"]["speed"] - level["speed"]) < 0.02 * level["speed"]  # the fit: within 2 %
    # halved resistance: the approach runs ~30 % faster than its runs did at the same revolutions
    spoiled = _spoiled(fit, tmp_path / "spoiled.yaml")
    code, _, err = run_cli("manoeuvre", spoiled, *turn, "--command", "prop=20", "--out", tmp_path / "bad")
    assert code == 0, err
    line = next(ln for ln in err.splitlines() if ln.startswith(NOT_HOLD))
    assert "at prop=20 rev/s, its runs ran" in line and line.endswith("its manoeuvres are not predictions"), line
    doc = json.loads((tmp_path / "bad" / "manoeuvre.json").read_text())
    assert doc["envelope"]["holds"] is False and doc["envelope"]["findings"][0]["kind"] == "does not hold"
    assert doc["envelope"]["speed_check"]["speed"] > 1.2 * level["speed"]
    assert any(w.startswith(NOT_HOLD) for w in doc["warnings"])
    # --strict refuses it: one line, exit 2, nothing written
    code, _, err = run_cli(
        "manoeuvre", spoiled, *turn, "--command", "prop=20", "--out", tmp_path / "strict", "--strict"
    )
    assert code == 2 and "refused under --strict" in err and NOT_HOLD in err, err
    assert not (tmp_path / "strict" / "manoeuvre.json").exists()
    # a propeller speed beyond the runs': no speed to compare, an extrapolation named with its limit
    code, _, err = run_cli(
        "manoeuvre", fit / "fit" / "vehicle.yaml", *turn, "--command", "prop=25", "--out", tmp_path / "far"
    )
    assert code == 0, err
    assert NOT_HOLD not in err and "command prop=25 rev/s (its runs' commands spanned 15 to 20)" in err, err
    far = json.loads((tmp_path / "far" / "manoeuvre.json").read_text())["envelope"]
    assert far["speed_check"] is None and far["holds"] is None  # nothing compared


@pytest.mark.needs_jit(reason="simulations of the fitted ship")
def test_simulate_compares_a_run_that_ends_steady(fit: Path, tmp_path: Path, run_cli: Any) -> None:
    run = ("--command", "prop=20", "--duration", 120, "--dt", 0.05)
    code, _, err = run_cli("simulate", fit / "fit" / "vehicle.yaml", *run, "--out", tmp_path / "ok.csv")
    assert code == 0 and "envelope:" not in err, err  # inside: its own speed, no rudder
    spoiled = _spoiled(fit, tmp_path / "spoiled.yaml")
    code, _, err = run_cli("simulate", spoiled, *run, "--deflection", "rudder=10", "--out", tmp_path / "bad.csv")
    assert code == 0, err
    assert f"{NOT_HOLD}: steady speed at the end" not in err  # turning at 10°: not straight, not compared
    assert f"{EXTRAPOLATES}: rudder 10°" in err, err
    code, _, err = run_cli("simulate", spoiled, *run, "--out", tmp_path / "bad.csv")
    assert code == 0 and f"{NOT_HOLD}: steady speed at the end" in err, err
    code, _, err = run_cli("simulate", spoiled, *run, "--out", tmp_path / "strict.csv", "--strict")
    assert code == 2 and "refused under --strict" in err and not (tmp_path / "strict.csv").exists(), err
    # a vehicle without the block: nothing said
    bare = _spoiled(fit, tmp_path / "bare.yaml", keep_envelope=False)
    code, _, err = run_cli("simulate", bare, *run, "--out", tmp_path / "bare.csv")
    assert code == 0 and "envelope" not in err, err


@pytest.mark.needs_jit(reason="a turning circle of the fitted ship")
def test_the_api_and_the_report_say_it(fit: Path, tmp_path: Path) -> None:
    import hydrokit
    from hydrokit.manoeuvre.run import turning_circle
    from hydrokit.report.manoeuvre import render

    spoiled = _spoiled(fit, tmp_path / "spoiled.yaml")
    res = hydrokit.manoeuvre(str(spoiled), turning_circle(math.radians(35)), commands={"prop": 20.0}, dt=0.2)
    assert res.envelope is not None and res.envelope["holds"] is False
    html = render(res, {})
    banner = html.index("the model does not hold at its own runs&#x27;")
    assert banner < html.index("Metrics")  # above what it predicts
