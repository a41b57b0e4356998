"""``hydrokit ingest LOG --vehicle V.yaml --run-out RUN.csv`` (issue #44): a run file from a tlog or
a ROS 2 bag generated here; bad input is one line, exit 2, nothing written."""

from __future__ import annotations

import csv
import json
import struct
from pathlib import Path

import numpy as np
import pytest
import yaml

RHO, G = 1000.0, 9.81


def vehicle(tmp_path: Path, **extra: dict) -> Path:
    """Two ideal thrusters on servo outputs 1 and 2 (``extra`` overrides their entries)."""
    ths = [
        {"name": "port", "position": [0, -0.2, 0], "direction": [1, 0, 0], "max_thrust": 40, "channel": 1},
        {"name": "stbd", "position": [0, 0.2, 0], "direction": [1, 0, 0], "max_thrust": 40, "channel": 2},
    ]
    for th in ths:
        th.update(extra.get(th["name"], {}))
        th.update({k: v for k, v in extra.items() if k not in ("port", "stbd")})
    doc = {
        "mass": 10.0,
        "volume": 0.01,
        "inertia": [0.2, 0.3, 0.3],
        "center_of_gravity": [0, 0, 0],
        "center_of_buoyancy": [0, 0, -0.01],
        "added_mass": [1, 2, 3, 0.1, 0.1, 0.1],
        "linear_damping": [1, 2, 3, 0.1, 0.1, 0.1],
        "quadratic_damping": [1, 2, 3, 0.1, 0.1, 0.1],
        "gravity": G,
        "fluid": {"density": RHO},
        "thrusters": ths,
    }
    path = tmp_path / "v.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def tlog(path: Path, attitude: bool = True) -> Path:
    """10 s: ATTITUDE 10 Hz, SCALED_PRESSURE2 5 Hz descending 0 → 2 m, SERVO_OUTPUT_RAW 5 Hz
    (output 1 at 1700 µs, output 2 stepping 1500 → 1300 µs at 5 s)."""
    mavutil = pytest.importorskip("pymavlink.mavutil")
    path.touch()
    conn = mavutil.mavlink_connection(str(path), write=True)
    for k in range(100):
        tk = 20.0 + 0.1 * k
        conn.write(struct.pack(">Q", int((1.7e9 + tk) * 1e6)))
        if attitude:
            conn.mav.attitude_send(int(tk * 1000), 0.01 * k, 0.0, 0.5, 0.0, 0.0, 0.0)
        else:
            conn.mav.heartbeat_send(12, 3, 0, 0, 4)
        if k % 2 == 0:
            z = 2.0 * k / 100
            conn.write(struct.pack(">Q", int((1.7e9 + tk) * 1e6)))
            conn.mav.scaled_pressure2_send(int(tk * 1000) + 5, (101_000.0 + RHO * G * z) / 100, 0.0, 1500)
            conn.write(struct.pack(">Q", int((1.7e9 + tk) * 1e6)))
            conn.mav.servo_output_raw_send(
                int(tk * 1e6) + 7000, 0, 1700, 1500 if k < 50 else 1300, 1500, 1500, 0, 0, 0, 0
            )
    conn.close()
    return path


def _bad(run_cli, tmp_path: Path, *args: object) -> str:
    out = tmp_path / "never" / "run.csv"
    code, _, err = run_cli("ingest", *args, "--run-out", out)
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert not out.parent.exists()
    return err


def test_tlog_to_run_file(tmp_path: Path, run_cli) -> None:
    log = tlog(tmp_path / "dive.tlog")
    out = tmp_path / "runs" / "dive.csv"
    code, _, err = run_cli(
        "ingest", log, "--vehicle", vehicle(tmp_path), "--run-out", out, "--surface-pressure", 101000
    )
    assert code == 0, err
    assert "phi 10 Hz" in err and "z 5 Hz" in err and "wrote" in err
    rows = list(csv.reader(out.read_text().splitlines()))
    assert rows[0] == ["time", "z", "phi", "theta", "psi", "p", "q", "r", "port", "stbd"]
    data = np.array([[float(c) if c else np.nan for c in r] for r in rows[1:]])
    t, z, port, stbd = data[:, 0], data[:, 1], data[:, 8], data[:, 9]
    assert np.all(np.diff(t) > 0)
    m = ~np.isnan(z)
    # z = (P − P_surface)/(ρ g) returns the depth the log was written from (hPa float32: 1e-4 m)
    assert np.allclose(z[m], 2.0 * (t[m] - 0.005 - 20.0) / 10.0, atol=1e-4)
    # ideal thrusters: F = level × max_thrust; 1700 µs → 0.5 → 20 N; 1300 µs → −0.5 → −20 N
    assert np.allclose(port, 20.0)
    assert set(np.round(stbd, 9)) == {0.0, -20.0}
    doc = json.loads(out.with_suffix(".json").read_text())
    assert doc["surface_pressure"] == 101000 and doc["thrusters"]["stbd"]["min"] == -20.0
    assert doc["channels"]["z"]["max"] == pytest.approx(1.96, abs=1e-3)
    # --start/--end on the log's clock
    cut = tmp_path / "cut.csv"
    code, _, err = run_cli("ingest", log, "--vehicle", vehicle(tmp_path), "--run-out", cut, "--start", 22, "--end", 25)
    assert code == 0, err
    tc = np.array([float(r.split(",")[0]) for r in cut.read_text().splitlines()[1:]])
    assert tc[0] >= 22.0 and tc[-1] <= 25.0


def test_bad_run_inputs(tmp_path: Path, run_cli) -> None:
    log = tlog(tmp_path / "dive.tlog")
    v = vehicle(tmp_path)
    assert "--run-out needs --vehicle" in _bad(run_cli, tmp_path, log)
    assert "--rig is for launches" in _bad(run_cli, tmp_path, log, "--vehicle", v, "--rig", v)
    assert "--split is for launches" in _bad(run_cli, tmp_path, log, "--vehicle", v, "--split")
    err = _bad(run_cli, tmp_path, log, "--vehicle", vehicle(tmp_path, stbd={"channel": None}))
    assert "thruster 'stbd' has no 'channel'" in err
    # MAVLink 2 carries servo9_raw…servo16_raw (0 when unused): output 17 is beyond what it holds
    err = _bad(run_cli, tmp_path, log, "--vehicle", vehicle(tmp_path, stbd={"channel": 17}))
    assert "thruster 'stbd': output 17 is not in the log (SERVO_OUTPUT_RAW: 1, 2, 3," in err
    flat = tlog(tmp_path / "flat.tlog", attitude=False)
    assert "no ATTITUDE messages in the log: a run needs the attitude" in _bad(run_cli, tmp_path, flat, "--vehicle", v)
    assert "--surface-pressure '-3'" in _bad(run_cli, tmp_path, log, "--vehicle", v, "--surface-pressure", -3)
    assert "--baro 2: no SCALED_PRESSURE3" in _bad(run_cli, tmp_path, log, "--vehicle", v, "--baro", 2)
    assert "topics are for a ROS bag" in _bad(run_cli, tmp_path, log, "--vehicle", v, "--imu-topic", "/imu")
    code, _, err = run_cli("ingest", log)
    assert code == 2 and "give --rig RIG.yaml and --out DIR" in err


def test_bag_topics_named_on_the_command_line(tmp_path: Path, run_cli) -> None:
    pytest.importorskip("rosbags")
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.LATEST)
    T = ts.types
    bag = tmp_path / "bag"
    V3, cov = T["geometry_msgs/msg/Vector3"], np.zeros(9)
    with Writer(bag, version=9) as w:
        c_imu = w.add_connection("/imu", "sensor_msgs/msg/Imu", typestore=ts)
        c_cmd = w.add_connection("/cmd", "std_msgs/msg/Float64MultiArray", typestore=ts)
        for k in range(20):
            ns = 1_000_000_000 + k * 50_000_000
            hdr = T["std_msgs/msg/Header"](
                stamp=T["builtin_interfaces/msg/Time"](sec=1, nanosec=k * 50_000_000), frame_id="b"
            )
            q = T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)  # ENU level, facing east
            imu = T["sensor_msgs/msg/Imu"](hdr, q, cov, V3(x=0.0, y=0.0, z=0.1), cov, V3(x=0.0, y=0.0, z=9.8), cov)
            w.write(c_imu, ns, ts.serialize_cdr(imu, "sensor_msgs/msg/Imu"))
            lay = T["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
            msg = T["std_msgs/msg/Float64MultiArray"](layout=lay, data=np.array([5.0, -5.0]))
            w.write(c_cmd, ns + 1000, ts.serialize_cdr(msg, "std_msgs/msg/Float64MultiArray"))
    v = vehicle(tmp_path)
    out = tmp_path / "bag.csv"
    code, _, err = run_cli("ingest", bag, "--vehicle", v, "--run-out", out, "--command-topic", "/cmd")
    assert code == 0, err
    rows = list(csv.reader(out.read_text().splitlines()))
    assert rows[0] == ["time", "phi", "theta", "psi", "p", "q", "r", "port", "stbd"]
    first = rows[1]
    # ENU yaw 0 (east) is NED psi = π/2; an ENU yaw rate +0.1 rad/s (left) is r = −0.1 rad/s
    # the file keeps 9 significant digits: ±5e-9 rad
    assert float(first[3]) == pytest.approx(np.pi / 2, abs=5e-9) and float(first[6]) == pytest.approx(-0.1)
    assert {float(r[7]) for r in rows[1:]} == {5.0} and {float(r[8]) for r in rows[1:]} == {-5.0}
    assert "--dvl-topic '/dvl' is not in the bag" in _bad(
        run_cli, tmp_path, bag, "--vehicle", v, "--command-topic", "/cmd", "--dvl-topic", "/dvl"
    )
    assert "give --command-topic" in _bad(run_cli, tmp_path, bag, "--vehicle", v)
    assert "--baro is for an ArduPilot log" in _bad(run_cli, tmp_path, bag, "--vehicle", v, "--baro", 1)


def test_warnings_and_a_vehicle_without_thrusters(tmp_path: Path, run_cli) -> None:
    log = tlog(tmp_path / "dive.tlog")
    out = tmp_path / "w.csv"
    code, _, err = run_cli("ingest", log, "--vehicle", vehicle(tmp_path, stbd={"channel": 5}), "--run-out", out)
    assert code == 0 and "warning: thruster 'stbd': output 5 is 0 µs throughout" in err
    doc = yaml.safe_load(vehicle(tmp_path).read_text())
    del doc["thrusters"]
    bare = tmp_path / "bare.yaml"
    bare.write_text(yaml.safe_dump(doc))
    assert "the vehicle has no 'thrusters' list" in _bad(run_cli, tmp_path, log, "--vehicle", bare)
