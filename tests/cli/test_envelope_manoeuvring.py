"""Runs that never go straight still bound the straight speed (issue #56 item 7).

The Esso Osaka pond trials hold a propeller speed only while zigzagging or under a random rudder,
so their envelope had no straight level, and a fit that flew its approach at two to three times
the runs' speed at those revolutions was only said to "extrapolate". The envelope now keeps each
run's steady speed while manoeuvring at its held commands with its turning r' = rms(r) L / mean U,
and a straight speed is checked against it from both sides: a ship is not slower straight than
turning, and turning that gently costs at most 1 − 1 / (1 + 4 r') of the straight speed
(:func:`hydrokit.model.envelope.largest_speed_loss`).

Here the 3 m planar ship of :mod:`tests.simulate.test_sysid_surfaces` runs 120 s under a random
rudder (±25°) at 20 rev/s: its level must carry the runs' own mean speed and r', computed here
from the run files; the truth flown by ``hydrokit manoeuvre`` at 20 rev/s holds; the same file
with its surge resistance cut to a twentieth (a fit whose resistance sat at its bound: far too
fast) and made 30 times larger (slower straight than the runs turning) does not, in words, in
manoeuvre.json, and ``--strict`` refuses it.
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

from hydrokit.model.envelope import (
    LOSS_PER_TURNING,
    Envelope,
    SpeedLevel,
    compare,
    largest_speed_loss,
)

#: propeller speed, rev/s; run length, s; seeds of the two runs
SPEED, DURATION, SEEDS = 20.0, 120.0, (11, 12)
NOT_HOLD = "envelope: the model does not hold at its own runs' speed"


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two random-rudder runs as files and the truth with their envelope (``truth.yaml``)."""
    from hydrokit.api import load_vehicle, vehicle_from_dict
    from hydrokit.io.runlog import read_runs, run_csv
    from hydrokit.sysid.envelope import run_envelope
    from hydrokit.sysid.ship import ship_runs

    root = tmp_path_factory.mktemp("manoeuvring")
    truth = vehicle_from_dict(copy.deepcopy(SHIP), "truth")
    for k, seed in enumerate(SEEDS):
        (run,) = ship_runs(truth, 1, DURATION, seed, speed=SPEED, rudder=math.radians(25.0))
        chans = {c: y for c, (_, y) in run.channels.items()}
        text = run_csv(run.time, chans, run.commands, deflections=run.deflections)
        (root / f"run{k}.csv").write_text(text)
    (root / "plain.yaml").write_text(yaml.safe_dump(copy.deepcopy(SHIP)))
    base = load_vehicle(str(root / "plain.yaml"))
    env = run_envelope(read_runs([str(root / f"run{k}.csv") for k in range(len(SEEDS))], base), base)
    doc = copy.deepcopy(SHIP)
    doc["envelope"] = env.to_dict()
    (root / "truth.yaml").write_text(yaml.safe_dump(doc))
    return root


def _by_hand(path: Path, length: float) -> tuple[float, float]:
    """Mean speed (m/s) and r' = rms(r) L / mean U over the second half of a run file."""
    rows = np.genfromtxt(path, delimiter=",", names=True, comments="#")
    late = rows["time"] >= 0.5 * rows["time"][-1]
    U = np.hypot(rows["u"][late], rows["v"][late])
    return float(np.mean(U)), float(np.sqrt(np.mean(rows["r"][late] ** 2)) * length / np.mean(U))


def test_each_runs_manoeuvring_level_is_its_own_speed_and_turning(runs: Path) -> None:
    """One level per run at 20 rev/s, no straight level; its speed and r' within 0.5 % of the run
    file's own second half (the hold is the whole run)."""
    env = yaml.safe_load((runs / "truth.yaml").read_text())["envelope"]
    assert env["speed_per_command"] == []
    levels = env["speed_manoeuvring"]
    assert len(levels) == len(SEEDS)
    for k, lv in enumerate(levels):
        speed, turning = _by_hand(runs / f"run{k}.csv", env["length"])
        assert lv["command"] == {"prop": SPEED}
        assert lv["speed"] == pytest.approx(speed, rel=5e-3)
        assert lv["turning"] == pytest.approx(turning, rel=5e-3)
        assert turning > 0.1  # never straight: |r| L / U above the straight limit


def _flown(
    runs: Path, tmp_path: Path, run_cli: Any, factor: float, *extra: str
) -> tuple[tuple[int, str], dict[str, Any]]:
    """The truth with its surge resistance times ``factor`` flown by ``hydrokit manoeuvre`` at 20
    rev/s: (exit code, stdout + stderr) and manoeuvre.json."""
    doc = yaml.safe_load((runs / "truth.yaml").read_text())
    doc["quadratic_damping"][0] *= factor
    path = tmp_path / f"x{factor:g}.yaml"
    path.write_text(yaml.safe_dump(doc))
    out = tmp_path / f"out{factor:g}"
    code, stdout, stderr = run_cli(
        "manoeuvre", str(path), "--turning-circle", "20", "--command", f"prop={SPEED}", "--out", str(out), *extra
    )
    report = json.loads((out / "manoeuvre.json").read_text()) if (out / "manoeuvre.json").exists() else {}
    return (code, stdout + stderr), report


def test_the_truth_holds_at_its_own_runs(runs: Path, tmp_path: Path, run_cli: Any) -> None:
    """The generating model's straight speed lies inside every run's bound: no line, holds."""
    (code, output), report = _flown(runs, tmp_path, run_cli, 1.0)
    assert code == 0, output
    assert NOT_HOLD not in output
    check = report["envelope"]["speed_check"]
    assert report["envelope"]["holds"] is True
    assert check["runs_speed"] < check["speed"] < check["bound"]


@pytest.mark.parametrize(
    ("factor", "words"),
    [(0.05, "turning that gently costs a ship at most"), (30.0, "a ship is not slower straight than turning")],
)
def test_a_model_off_its_runs_speed_is_said_not_to_hold(
    runs: Path, tmp_path: Path, run_cli: Any, factor: float, words: str
) -> None:
    """Resistance cut to 1/20 (too fast) or made 30 × (slower straight than the runs turning): the
    line in words, manoeuvre.json's holds False; ``--strict`` refuses in one line, exit 2."""
    (code, output), report = _flown(runs, tmp_path, run_cli, factor)
    assert code == 0, output
    line = next(x for x in output.splitlines() if x.startswith(NOT_HOLD))
    assert words in line and "prop=20" in line
    assert report["envelope"]["holds"] is False
    (tmp_path / "strict").mkdir()
    (code, output), _ = _flown(runs, tmp_path / "strict", run_cli, factor, "--strict")
    assert code == 2
    assert "Traceback" not in output


def test_the_bound_is_its_closed_form() -> None:
    """compare() against one manoeuvring level: the bound is speed / (1 − loss) + tolerance with
    loss = 4 r' / (1 + 4 r'), the tolerance max(3 × scatter, 10 % of the speed); below the level's
    speed it does not hold unless the speed is still rising."""
    lv = SpeedLevel((("prop", 10.0),), speed=0.3, scatter=0.02, runs=1, samples=500, turning=0.25)
    env = Envelope(speed_manoeuvring=(lv,), command_range=(("prop", 0.0, 10.0),))
    loss = LOSS_PER_TURNING * 0.25 / (1 + LOSS_PER_TURNING * 0.25)
    assert largest_speed_loss(0.25) == pytest.approx(loss, rel=1e-12)
    top = 0.3 / (1 - loss) + 0.06
    for flown, rising, holds in [
        (top * 0.999, False, True),
        (top * 1.001, False, False),
        (top * 1.001, True, False),
        (0.3 - 0.06 * 1.01, False, False),
        (0.3 - 0.06 * 1.01, True, True),
        (0.3 - 0.06 * 0.99, False, True),
    ]:
        found, check = compare(env, steady=({"prop": 10.0}, flown), rising=rising)
        assert check is not None and check["holds"] is holds, (flown, rising)
        assert bool(found) is not holds
        assert check["bound"] == pytest.approx(top, rel=1e-12)


def test_the_reader_round_trips_and_refuses_a_negative_turning(runs: Path, tmp_path: Path) -> None:
    """The block read back equals the written one; ``turning: -1`` is one line naming the field."""
    from hydrokit.api import load_vehicle
    from hydrokit.errors import InputError

    v = load_vehicle(str(runs / "truth.yaml"))
    assert v.envelope is not None
    written = yaml.safe_load((runs / "truth.yaml").read_text())["envelope"]
    assert v.envelope.to_dict() == written
    doc = yaml.safe_load((runs / "truth.yaml").read_text())
    doc["envelope"]["speed_manoeuvring"][0]["turning"] = -1
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(doc))
    with pytest.raises(InputError, match=r"envelope\.speed_manoeuvring\[0\]\.turning") as err:
        load_vehicle(str(bad))
    assert "\n" not in str(err.value)
