"""``hydrokit allocate`` and ``hydrokit mission`` through the real entry point."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

# Lingyun poses (our choice for LI2021's symbolic r_hx, r_hy, r_vy, r_vz; docs/control.md)
LINGYUN_THRUSTERS = [
    {"name": "HT1", "position": [-0.6, -0.35, 0.0], "direction": [1, 0, 0], "max_thrust": 100, "min_thrust": -80},
    {"name": "HT2", "position": [-0.6, 0.35, 0.0], "direction": [1, 0, 0], "max_thrust": 100, "min_thrust": -80},
    {"name": "VT1", "position": [0.0, -0.30, -0.40], "direction": [0, 0, -1], "max_thrust": 100, "min_thrust": -80},
    {"name": "VT2", "position": [0.0, 0.30, -0.40], "direction": [0, 0, -1], "max_thrust": 100, "min_thrust": -80},
]


def write_vehicle(tmp_path: Path, thrusters: object, name: str = "veh.yaml", **extra) -> Path:
    doc = {"name": "test", "fluid": {"density": 1025.0}, "thrusters": thrusters}
    doc.update(extra)
    p = tmp_path / name
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def test_allocate_json_contract(run_cli, tmp_path: Path) -> None:
    veh = write_vehicle(tmp_path, LINGYUN_THRUSTERS)
    out = tmp_path / "alloc.json"
    code, stdout, err = run_cli("allocate", veh, "--tau", "60,0,-40,6,0,7", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    T = np.array(doc["configuration_matrix"])
    assert T.shape == (6, 4)
    f = np.array(doc["thrust"])
    # achieved_tau is T f by definition; all demands are reachable here, so it equals tau
    np.testing.assert_allclose(doc["achieved_tau"], T @ f, atol=1e-9)
    np.testing.assert_allclose(doc["achieved_tau"], [60, 0, -40, 6, 0, 7], atol=1e-6)
    # hand solution: f1+f2 = 60, 0.35(f1-f2) = 7 -> f1 = 40, f2 = 20; -(f3+f4) = -40,
    # 0.3(f3-f4) = 6 -> f3 = 30, f4 = 10
    np.testing.assert_allclose(f, [40, 20, 30, 10], atol=1e-6)
    assert doc["uncontrollable"] == ["sway", "pitch"]
    assert doc["saturated"] == []
    assert "Configuration matrix" in stdout


def test_allocate_out_of_reach_saturates(run_cli, tmp_path: Path) -> None:
    veh = write_vehicle(tmp_path, LINGYUN_THRUSTERS)
    out = tmp_path / "alloc.json"
    code, _, err = run_cli("allocate", veh, "--tau", "500,0,0,0,0,0", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    np.testing.assert_allclose(doc["thrust"], [100, 100, 0, 0], atol=1e-6)
    assert doc["saturated"] == ["HT1", "HT2"]
    assert doc["residual"] == pytest.approx(300.0, rel=1e-9)


def test_allocate_pinv_reports_overrun(run_cli, tmp_path: Path) -> None:
    veh = write_vehicle(tmp_path, LINGYUN_THRUSTERS)
    out = tmp_path / "alloc.json"
    code, _, err = run_cli("allocate", veh, "--tau", "500,0,0,0,0,0", "--method", "pinv", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    np.testing.assert_allclose(doc["thrust"], [250, 250, 0, 0], atol=1e-9)  # T+ tau, unclipped
    assert "exceeds the limits" in err


def test_allocate_uncontrollable_dof_warns_and_allocates_rest(run_cli, tmp_path: Path) -> None:
    veh = write_vehicle(tmp_path, LINGYUN_THRUSTERS)
    out = tmp_path / "alloc.json"
    code, _, err = run_cli("allocate", veh, "--tau", "20,15,0,0,0,0", "--json", out)
    assert code == 0
    assert "warning:" in err and "cannot actuate sway" in err
    doc = json.loads(out.read_text())
    np.testing.assert_allclose(doc["thrust"], [10, 10, 0, 0], atol=1e-8)


def test_allocate_propeller_speed_in_rpm(run_cli, tmp_path: Path) -> None:
    th = [{"name": "A", "position": [0, 0, 0], "direction": [1, 0, 0], "max_thrust": 500,
           "diameter": 0.22, "kt_forward": [0.5, -0.66, -0.25, 0.24],
           "kt_reverse": [0.025, -0.28, 0.17, 0.15],
           "thrust_loss": {"forward": 0.72, "reverse": 0.53}, "max_rpm": 1500}]
    veh = write_vehicle(tmp_path, th)
    out = tmp_path / "a.json"
    code, _, err = run_cli("allocate", veh, "--tau", "50,0,0,0,0,0", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    # closed form at J = 0: n = sqrt(f / (loss K_T(0) rho D^4)) rev/s, times 60 for rpm
    n = math.sqrt(50 / (0.72 * 0.24 * 1025 * 0.22**4))
    assert doc["command"][0] == pytest.approx(60 * n, rel=1e-12)
    assert doc["command_unit"] == ["rpm"]


@pytest.mark.parametrize(
    ("thrusters", "tau", "match"),
    [
        ([{**LINGYUN_THRUSTERS[0], "direction": [0, 0, 0]}], "1,0,0,0,0,0", "direction .* zero length"),
        ([LINGYUN_THRUSTERS[0], LINGYUN_THRUSTERS[0]], "1,0,0,0,0,0", "duplicate name 'HT1'"),
        ([], "1,0,0,0,0,0", "expected a non-empty list"),
        ([{**LINGYUN_THRUSTERS[0], "max_thrust": "big"}], "1,0,0,0,0,0", "max_thrust = 'big'"),
        ([{**LINGYUN_THRUSTERS[0], "colour": "red"}], "1,0,0,0,0,0", "unknown field 'colour'"),
        (LINGYUN_THRUSTERS, "1,2,3", "expected 6 comma-separated"),
        (LINGYUN_THRUSTERS, "1,2,3,x,5,6", "expected 6 comma-separated"),
    ],
)
def test_allocate_bad_input_one_line_exit_2(run_cli, tmp_path: Path, thrusters, tau, match) -> None:
    veh = write_vehicle(tmp_path, thrusters)
    out = tmp_path / "alloc.json"
    code, _, err = run_cli("allocate", veh, "--tau", tau, "--json", out)
    assert code == 2
    assert err.startswith("error: ") and len(err.strip().splitlines()) == 1
    assert __import__("re").search(match, err), err
    assert not out.exists()


def test_allocate_missing_vehicle(run_cli, tmp_path: Path) -> None:
    code, _, err = run_cli("allocate", tmp_path / "nope.yaml", "--tau", "1,0,0,0,0,0")
    assert code == 2 and "no such file or bundled vehicle" in err
