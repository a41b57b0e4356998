"""Wind from the command line and from run files (issue #48 item 4): simulate --wind / --wind-csv
against the closed-form beam-wind drift, and wind columns without a wind model refused in one line
(exit 2, nothing written)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.runlog import read_run

SHIP = """name: windship
gravity: 9.81
fluid: {density: 1000.0}
dofs: [surge, sway, yaw]
mass: 100.0
volume: 0.1
inertia: [10, 60, 60]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [5, 50, 0, 0, 0, 30]
linear_damping: [20, 40, 0, 0, 0, 15]
quadratic_damping: [10, 80, 0, 0, 0, 5]
"""
WIND = """wind:
  frontal_area: 0.135
  lateral_area: 0.52
  length: 3.0
  model: blendermann1994
  vessel: tanker_loaded
"""


def _drift(V: float) -> float:
    """Steady sway (m/s) under a beam wind V from starboard: −d v + d₂ v² = CD_t ½ρ_a A_L (V + v)²
    (tanker_loaded CD_t = 0.70, Blendermann 1994; d = 40, d₂ = 80 as in SHIP)."""
    k = 0.70 * 0.5 * 1.225 * 0.52
    r = np.roots([80.0 - k, -(40.0 + 2 * k * V), -k * V * V])
    return float(r[(r < 0) & (r > -V)][0])


def test_simulate_wind_reaches_the_closed_form_drift(run_cli: Any, tmp_path: Path) -> None:
    ship = tmp_path / "ship.yaml"
    ship.write_text(SHIP + WIND)
    out = tmp_path / "traj.csv"
    code, _, err = run_cli("simulate", ship, "--duration", 150, "--dt", 0.05, "--wind", "2,90", "--out", out)
    assert code == 0, err
    final = np.loadtxt(out, delimiter=",", skiprows=1)[-1]
    # rtol 1e-6: 150 s is ~40 sway time constants
    assert final[8] == pytest.approx(_drift(2.0), rel=1e-6)
    # the same wind over time from a CSV (rad): speed ramping to 2 m/s by 10 s, then held
    csv = tmp_path / "wind.csv"
    csv.write_text(f"time,wind_speed,wind_direction\n0,0,{math.pi / 2}\n10,2,{math.pi / 2}\n")
    out2 = tmp_path / "traj2.csv"
    code, _, err = run_cli("simulate", ship, "--duration", 150, "--dt", 0.05, "--wind-csv", csv, "--out", out2)
    assert code == 0, err
    rows = np.loadtxt(out2, delimiter=",", skiprows=1)
    assert rows[-1, 8] == pytest.approx(_drift(2.0), rel=1e-6)
    assert abs(rows[20, 8]) < abs(final[8])  # 1 s in: the wind has barely risen


def test_simulate_wind_without_a_wind_model_is_refused(run_cli: Any, tmp_path: Path) -> None:
    ship = tmp_path / "plain.yaml"
    ship.write_text(SHIP)
    out = tmp_path / "traj.csv"
    code, text, err = run_cli("simulate", ship, "--duration", 10, "--wind", "2,90", "--out", out)
    assert code == 2 and "no wind model" in err and "wind:" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def _run_file(path: Path) -> Path:
    cmd = ",".join(["0"] * 8)
    rows = [
        "time,psi,u,v,r,FR,FL,RR,RL,VFR,VFL,VRR,VRL,wind_speed,wind_direction",
        f"0,0,0.3,0,0,{cmd},1.5,6.2",
        f"0.5,0,0.3,0.01,0,{cmd},,",
        f"1.0,0,0.3,0.02,0,{cmd},1.7,0.1",
        f"1.5,0,0.3,0.02,0,{cmd},1.4,0.2",
    ]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_run_file_wind_columns_without_a_wind_model(run_cli: Any, tmp_path: Path) -> None:
    run = _run_file(tmp_path / "run1.csv")
    out = tmp_path / "fit"
    code, text, err = run_cli(
        "sysid", run, "--vehicle", "bluerov2-heavy", "--free", "linear_damping.surge", "--out", out
    )
    assert code == 2, err
    assert "wind_speed" in err and "no wind model" in err and "run1.csv" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_run_file_wind_is_read_and_filled(tmp_path: Path) -> None:
    run = _run_file(tmp_path / "run1.csv")
    names = ("FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL")
    log = read_run(run, names)
    # the empty cell at 0.5 s filled linearly; the direction unwrapped through 2π (6.2 → 0.1 rad)
    assert log.environment["wind_speed"][1] == pytest.approx(1.6, rel=1e-12)
    assert log.environment["wind_direction"][2] == pytest.approx(0.1 + 2 * math.pi, rel=1e-12)
    table = log.environment_table()
    assert table is not None and table.shape == (4, 6)
    # the wind from 6.2 rad blows towards 6.2 − π: velocity −V (cos β, sin β)
    np.testing.assert_allclose(table[0, 4:], [-1.5 * math.cos(6.2), -1.5 * math.sin(6.2)], rtol=1e-12)
    with pytest.raises(InputError, match="wind_speed.*no wind model"):
        read_run(run, names, wind_model=False)
    lone = tmp_path / "lone.csv"
    lone.write_text(run.read_text().replace("wind_direction", "other"))
    with pytest.raises(InputError, match="'wind_speed' without 'wind_direction'"):
        read_run(lone, names)
