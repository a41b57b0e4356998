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
    # HT1 and HT2 (250 N each) are over their 100 N limit; VT1, VT2 (0 N) are not
    assert err.splitlines()[0] == "warning: pseudo-inverse thrust exceeds the limits of HT1, HT2"


def test_allocate_uncontrollable_dof_warns_and_allocates_rest(run_cli, tmp_path: Path) -> None:
    veh = write_vehicle(tmp_path, LINGYUN_THRUSTERS)
    out = tmp_path / "alloc.json"
    code, _, err = run_cli("allocate", veh, "--tau", "20,15,0,0,0,0", "--json", out)
    assert code == 0
    assert err.splitlines()[0] == (
        "warning: tau asks for sway=15 but the thruster layout cannot actuate sway; "
        "those components are ignored and the rest allocated"
    )
    doc = json.loads(out.read_text())
    np.testing.assert_allclose(doc["thrust"], [10, 10, 0, 0], atol=1e-8)


def test_allocate_propeller_speed_in_rpm(run_cli, tmp_path: Path) -> None:
    th = [
        {
            "name": "A",
            "position": [0, 0, 0],
            "direction": [1, 0, 0],
            "max_thrust": 500,
            "diameter": 0.22,
            "kt_forward": [0.5, -0.66, -0.25, 0.24],
            "kt_reverse": [0.025, -0.28, 0.17, 0.15],
            "thrust_loss": {"forward": 0.72, "reverse": 0.53},
            "max_rpm": 1500,
        }
    ]
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


def test_allocate_missing_vehicle(run_cli, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # a relative path: a long temporary folder (xdist workers nest one level deeper) would be shortened in the message
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli("allocate", "nope.yaml", "--tau", "1,0,0,0,0,0")
    assert code == 2
    from hydrokit.io.vehicle import bundled_vehicles

    names = bundled_vehicles()
    assert {"bluerov2-heavy", "lingyun", "minerva", "remus100", "mariner", "udrobot"} <= set(names)
    assert err.splitlines() == [f"error: no such file or bundled vehicle 'nope.yaml' (bundled: {', '.join(names)})"]


# --------------------------------------------------------------------------- mission
from hydrokit.io.mission import MISSIONS_DIR  # noqa: E402

CSV_HEAD = "time,x,y,z,phi,theta,psi,u,v,w,p,q,r"


def test_mission_short_run_writes_everything(run_cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, stdout, err = run_cli("mission", "lingyun_path", "--out", out, "--duration", 10)
    assert code == 0, err
    names = {"trajectory.csv", "metrics.json", "path.png", "tracking.png", "thrusters.png"}
    assert names <= {p.name for p in out.iterdir()}
    for png in ("path.png", "tracking.png", "thrusters.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = (out / "trajectory.csv").read_text().splitlines()
    assert lines[0].startswith(CSV_HEAD + ",cmd_demand_HT1")
    assert "thrust_VT2" in lines[0]
    # dt 0.05 s, output_every 2 -> rows every 0.1 s from 0 to 10 s inclusive
    assert len(lines) == 1 + 101
    doc = json.loads((out / "metrics.json").read_text())
    m = doc["controllers"]["PID"]
    # the metrics against the written trajectory (101 rows, 0.1 s apart). In 10 s at 0.5 m/s the
    # vehicle stays on the first leg, (0, 0, 5) -> (25, 0, 5): cross-track = hypot(y, z - 5), and
    # the first waypoint (25 m away) is not reached
    header = lines[0].split(",")
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    col = {h: i for i, h in enumerate(header)}
    assert np.all(rows[:, col["leg"]] == 1) and rows[:, col["x"]].max() < 24.0
    d = np.hypot(rows[:, col["y"]], rows[:, col["z"]] - 5.0)
    assert m["cross_track_rms"] == pytest.approx(math.sqrt(np.mean(d**2)), rel=1e-6)
    assert m["cross_track_max"] == pytest.approx(d.max(), rel=1e-6)
    assert m["waypoint_times"] == [None] * 4 and m["completed"] is False and m["final_time"] == 10.0
    thrust = rows[:, [col[f"thrust_{n}"] for n in ("HT1", "HT2", "VT1", "VT2")]]
    assert m["thrust_impulse"] == pytest.approx(np.abs(thrust).sum() * 0.1, rel=1e-6)
    # ideal actuator disk (Rankine-Froude) at zero advance: P = |f|^1.5 / sqrt(2 rho A), with the
    # vehicle file's 0.134 m propellers in 1025.9 kg/m³ water
    disk = math.pi * 0.134**2 / 4
    assert m["thruster_energy"] == pytest.approx(
        np.sum(np.abs(thrust) ** 1.5) / math.sqrt(2 * 1025.9 * disk) * 0.1, rel=1e-6
    )
    saturated = int(np.count_nonzero(rows[:, col["saturated"]]))
    assert saturated > 0 and m["saturation_time"] == pytest.approx(saturated * 0.1, rel=1e-9)
    assert m["saturation_fraction"] == pytest.approx(saturated / 101, rel=1e-9)
    assert "Mission metrics" in stdout


@pytest.mark.parametrize("controller", ["pid", "s-plane"])
def test_bundled_lingyun_mission_completes(run_cli, tmp_path: Path, controller: str) -> None:
    out = tmp_path / controller
    code, _, err = run_cli("mission", "lingyun_path", "--out", out, "--controller", controller, "--no-plots")
    assert code == 0, err
    m = json.loads((out / "metrics.json").read_text())["controllers"]
    (metrics,) = m.values()
    assert metrics["completed"], metrics["waypoint_times"]
    times = metrics["waypoint_times"]
    assert all(b > a for a, b in zip(times, times[1:]))
    # path legs 25, 15.3, 25, 15.1 m at 0.5 m/s: at least 161 s of pure travel, and the
    # vehicle stays within a couple of metres of the planned path in the 90-degree turns
    assert times[-1] > 161.0
    assert metrics["cross_track_max"] < 2.5
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    header = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    thrust = rows[:, [i for i, h in enumerate(header) if h.startswith("thrust_HT") or h.startswith("thrust_VT")]]
    assert np.all(thrust <= 60 + 1e-9) and np.all(thrust >= -45 - 1e-9)  # lingyun limits


def _mission_doc() -> dict:
    return yaml.safe_load((MISSIONS_DIR / "lingyun_path.yaml").read_text())


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda d: d["controllers"]["pid"]["speed"].update(kp="fast"), "controllers.pid.speed.kp' = 'fast'"),
        (lambda d: d["guidance"].update(waypoints=[]), "0 given; expected a list of at least 2"),
        (
            lambda d: d["guidance"].update(
                waypoints=[{"x": 0, "y": 0, "z": 1, "time": 9}, {"x": 9, "y": 0, "z": 1, "time": 3}]
            ),
            "waypoints out of order",
        ),
        (lambda d: d.update(vehicle="no-such-vehicle"), "no such file or bundled vehicle"),
    ],
)
def test_mission_bad_input_exit_2_nothing_written(run_cli, tmp_path: Path, edit, match) -> None:
    doc = _mission_doc()
    doc["vehicle"] = str(MISSIONS_DIR / doc["vehicle"])
    edit(doc)
    p = tmp_path / "m.yaml"
    p.write_text(yaml.safe_dump(doc))
    out = tmp_path / "out"
    code, _, err = run_cli("mission", p, "--out", out, "--duration", 1)
    assert code == 2
    assert err.startswith("error: ") and len(err.strip().splitlines()) == 1
    assert __import__("re").search(match, err), err
    assert not out.exists()  # not even an empty folder


def test_mission_missing_controller_gains(run_cli, tmp_path: Path) -> None:
    doc = _mission_doc()
    doc["vehicle"] = str(MISSIONS_DIR / doc["vehicle"])
    del doc["controllers"]["s-plane"]
    p = tmp_path / "m.yaml"
    p.write_text(yaml.safe_dump(doc))
    code, _, err = run_cli("mission", p, "--out", tmp_path / "o", "--controller", "s-plane")
    assert code == 2
    assert err.splitlines() == [
        f"error: {p}: controllers.s-plane: no gains for the 's-plane' controller (file has: pid)"
    ]
    assert not (tmp_path / "o").exists()


def test_allocate_minerva_block_reproduces_published_matrix(run_cli, tmp_path: Path, published) -> None:
    # The same thruster block as appended to the bundled minerva.yaml (azimuths in degrees,
    # converted by the reader); the matrix must match SPEC §8 to its printed 3 decimals.
    kt = {"kt_forward": [0.5, -0.66, -0.25, 0.24], "kt_reverse": [0.025, -0.28, 0.17, 0.15], "max_rpm": 1500}
    th = [
        {
            "name": "TT",
            "position": [0.166, 0, 0],
            "direction": [0, 1, 0],
            "diameter": 0.19,
            "thrust_loss": 1.04,
            "max_thrust": 208,
            "min_thrust": -130,
            **kt,
        },
        {
            "name": "V1",
            "position": [0, 0.2, 0],
            "direction": [0, 0, 1],
            "diameter": 0.22,
            "thrust_loss": 0.58,
            "max_thrust": 208,
            "min_thrust": -130,
            **kt,
        },
        {
            "name": "V2",
            "position": [0, -0.2, 0],
            "direction": [0, 0, 1],
            "diameter": 0.22,
            "thrust_loss": 0.58,
            "max_thrust": 208,
            "min_thrust": -130,
            **kt,
        },
        {
            "name": "A1",
            "position": [-0.2, -0.305, 0],
            "azimuth_deg": -10,
            "diameter": 0.22,
            "thrust_loss": {"forward": 0.72, "reverse": 0.53},
            "max_thrust": 259,
            "min_thrust": -119,
            **kt,
        },
        {
            "name": "A2",
            "position": [-0.2, 0.305, 0],
            "azimuth_deg": 10,
            "diameter": 0.22,
            "thrust_loss": {"forward": 0.72, "reverse": 0.53},
            "max_thrust": 259,
            "min_thrust": -119,
            **kt,
        },
    ]
    veh = write_vehicle(tmp_path, th)
    out = tmp_path / "m.json"
    code, _, err = run_cli("allocate", veh, "--tau", "300,0,0,0,0,0", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    printed = np.array(published["minerva_mo2015"]["configuration_matrix"], dtype=float)
    np.testing.assert_allclose(doc["configuration_matrix"], printed, atol=5e-4)
    assert doc["uncontrollable"] == ["pitch"]
    # Surge 300 N: axial pair only (toe-out cancels in sway); A1 = A2 = 300 / (2 cos 10°),
    # within the reverse/forward limits -> reachable, so achieved = demanded
    f = np.array(doc["thrust"])
    np.testing.assert_allclose(f[3:], 300 / (2 * math.cos(math.radians(10))), rtol=1e-6)
    np.testing.assert_allclose(doc["achieved_tau"], [300, 0, 0, 0, 0, 0], atol=1e-6)
    # speeds from the forward curve at J = 0 (rpm), SPEC §8 coefficients by hand
    n = math.sqrt(f[3] / (0.72 * 0.24 * 1025 * 0.22**4)) * 60
    assert doc["command"][3] == pytest.approx(n, rel=1e-9)


@pytest.mark.parametrize(
    ("name", "n", "unactuated"),
    [("minerva", 5, ["pitch"]), ("lingyun", 4, ["sway", "pitch"]), ("bluerov2-heavy", 8, [])],
)
def test_allocate_bundled_names(run_cli, tmp_path: Path, published, name, n, unactuated) -> None:
    out = tmp_path / "a.json"
    code, _, err = run_cli("allocate", name, "--tau", "20,0,-10,0,0,2", "--json", out)
    assert code == 0, err
    doc = json.loads(out.read_text())
    T = np.array(doc["configuration_matrix"])
    assert T.shape == (6, n)
    assert doc["uncontrollable"] == unactuated
    np.testing.assert_allclose(doc["achieved_tau"], T @ np.array(doc["thrust"]), atol=1e-9)
    np.testing.assert_allclose(doc["achieved_tau"], [20, 0, -10, 0, 0, 2], atol=1e-6)
    if name == "minerva":  # SPEC §8 matrix, 3 printed decimals
        printed = np.array(published["minerva_mo2015"]["configuration_matrix"], dtype=float)
        np.testing.assert_allclose(T, printed, atol=5e-4)


def test_minerva_mission_propeller_commands(run_cli, tmp_path: Path) -> None:
    # Propeller thrusters in the loop: commands are rev/s within +-1500 rpm, thrust within the
    # asymmetric forward/reverse limits of SPEC §8 at that speed (axial: +259 / -119 N).
    out = tmp_path / "m"
    code, _, err = run_cli("mission", "minerva_square", "--out", out, "--duration", 40, "--no-plots")
    assert code == 0, err
    doc = json.loads((out / "metrics.json").read_text())
    assert doc["command_units"] == ["rev/s"] * 5
    header = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    col = {h: i for i, h in enumerate(header)}
    for name in ("TT", "V1", "V2", "A1", "A2"):
        assert np.all(np.abs(rows[:, col[f"cmd_{name}"]]) <= 25.0 + 1e-9)
    a1 = rows[:, col["thrust_A1"]]
    assert a1.max() <= 259 + 1e-6 and a1.min() >= -119 - 1e-6
    assert a1.max() > 100  # the axial thrusters do drive the vehicle
    assert doc["controllers"]["PID"]["waypoint_times"][0] is not None  # first 12 m leg done


def test_allocate_unknown_thruster_field_is_a_warning(run_cli, tmp_path: Path) -> None:
    th = [{**LINGYUN_THRUSTERS[0], "colour": "red"}, *LINGYUN_THRUSTERS[1:]]
    veh = write_vehicle(tmp_path, th)
    out = tmp_path / "a.json"
    code, _, err = run_cli("allocate", veh, "--tau", "10,0,0,0,0,0", "--json", out)
    assert code == 0
    assert "warning:" in err and "'colour' ignored" in err
    doc = json.loads(out.read_text())
    assert any("colour" in w for w in doc["warnings"])
    np.testing.assert_allclose(doc["thrust"], [5, 5, 0, 0], atol=1e-9)
