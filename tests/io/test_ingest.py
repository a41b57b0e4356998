"""``hydrokit ingest`` (issue #12): real files written with the field's own libraries (rosbags,
pymavlink, csv), ingested, split and identified; every bad input is one line, exit 2, nothing
written."""

from __future__ import annotations

import json
import math
import struct
import sys
from pathlib import Path

import numpy as np
import pytest

import hydrokit
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

RIG = Path(hydrokit.__file__).parent / "data" / "campaigns" / "udrobot" / "pendulum_x.yaml"
TRUE = {"added_mass": 0.06, "linear_damping": 0.05, "quadratic_damping": 1.0}
EPOCH = 1_700_000_000.0  # header stamps in ROS time


@pytest.fixture(scope="module")
def rig():
    return hydrokit.load_rig(RIG)


def _launch(rig, amp_deg: float, seed: int, hold: float = 2.0, rate: float = 100.0):
    sensor = SensorModel(rate, math.radians(0.05), 0.0, hold, "test IMU")
    return simulate_launch(rig, *TRUE.values(), math.radians(amp_deg), 12.0, sensor, seed)


def _recording(rig, amps=(10.0, -15.0, 20.0, 12.0, -8.0, 25.0)):
    """Rest → lift → 2 s hold → release → 12 s decay, once per amplitude; true release times."""
    rng = np.random.default_rng(7)
    ys, releases, holds = [], [], []
    n0 = 0
    for k, a in enumerate(amps):
        launch = _launch(rig, a, 100 + k)
        lift = 0.5 * (1 - np.cos(np.linspace(0, np.pi, 150))) * math.radians(a)
        noise = rng.normal(0, math.radians(0.05), 250)
        seg = np.concatenate([noise[:100], lift + noise[100:], launch.y])
        holds.append(((n0 + 250) * 0.01, (n0 + 449) * 0.01))
        releases.append((n0 + 449) * 0.01)  # the last still sample
        ys.append(seg)
        n0 += seg.size
    y = np.concatenate(ys)
    return np.arange(y.size) * 0.01, y, releases, holds


def _identified(rig, files) -> float:
    res = hydrokit.identify_campaign(rig, sorted(str(f) for f in files))
    return res.mean("added_mass")


def _doc(out: Path) -> dict:
    return json.loads((out / "ingest.json").read_text())


# --- CSV / TSV -----------------------------------------------------------------------------------


def test_tsv_in_ms_and_degrees_is_ingested_and_identified(tmp_path, rig, run_cli) -> None:
    launches = [_launch(rig, a, s) for s, a in enumerate((12.0, -18.0, 24.0))]
    files = []
    for k, la in enumerate(launches):
        src = tmp_path / f"tank_{k}.tsv"
        rows = [f"{1000 * (5.0 + t):.1f}\t{math.degrees(v):.5f}" for t, v in zip(la.t, la.y)]
        src.write_text("# logger v2\nstamp_ms\tpitch_deg\n" + "\n".join(rows) + "\n")
        out = tmp_path / f"out_{k}"
        code, _, err = run_cli(
            "ingest", src, "--rig", RIG, "--out", out, "--time-unit", "ms", "--signal-unit", "deg", "--plots"
        )
        assert code == 0, err
        doc = _doc(out)
        (d,) = doc["launches"]
        assert d["samples"] == la.t.size and d["rate"] == pytest.approx(100.0)
        assert d["start_time"] == pytest.approx(5.0)  # the file's time base is kept
        assert d["release_time"] == pytest.approx(5.0 + 1.99, abs=0.03)
        assert any("time base" in n for n in d["notes"]) and not doc["warnings"]
        assert (out / "ingest.png").stat().st_size > 1000
        files.append(out / "launch_001.csv")
    assert _identified(rig, files) == pytest.approx(TRUE["added_mass"], rel=0.01)


def test_any_delimiter_named_columns_and_the_degree_warning(tmp_path, rig, run_cli) -> None:
    la = _launch(rig, 15.0, 3)
    src = tmp_path / "log.csv"
    lines = [f"{i};{t:.3f};{v:.6f};{math.degrees(v):.4f}" for i, (t, v) in enumerate(zip(la.t, la.y))]
    src.write_text("idx;Time;theta_rad;Theta_Deg\n" + "\n".join(lines) + "\n")
    out = tmp_path / "a"
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out, "--time", "time", "--signal", "THETA_RAD")
    assert code == 0, err
    y = np.loadtxt(out / "launch_001.csv", delimiter=",", skiprows=3)[:, 1]
    assert np.allclose(y, la.y, atol=2e-6)
    # the degree column read as rad: a warning in ingest.json and on stderr (the value check also fires)
    out2 = tmp_path / "b"
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out2, "--time", "2", "--signal", "4")
    assert code == 0
    assert "looks like degrees" in err
    assert any("looks like degrees" in w for w in _doc(out2)["warnings"])


# --- ROS bags ------------------------------------------------------------------------------------


def _quat_roll(roll: np.ndarray, pitch: float = 0.05, yaw: float = 0.7) -> np.ndarray:
    """q = qz(yaw) qy(pitch) qx(roll) as (w, x, y, z) rows (ZYX Euler)."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    w = cy * cp * cr + sy * sp * sr
    x = cy * cp * sr - sy * sp * cr
    y = cy * sp * cr + sy * cp * sr
    z = sy * cp * cr - cy * sp * sr
    return np.stack([w, x, y, z], axis=1)


def _write_bag(path: Path, t: np.ndarray, angle: np.ndarray, kind: str) -> None:
    pytest.importorskip("rosbags")
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.LATEST)
    T = ts.types
    imu_t, f64_t = "sensor_msgs/msg/Imu", "std_msgs/msg/Float64"
    ser = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    if ros1:
        from rosbags.rosbag1 import Writer

        writer = Writer(path)
    else:
        from rosbags.rosbag2 import StoragePlugin, Writer

        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        writer = Writer(path, version=9, storage_plugin=plugin)
    zero3, cov = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=9.8), np.zeros(9)
    with writer as w:
        c_imu = w.add_connection("/imu/data", imu_t, typestore=ts)
        c_f64 = w.add_connection("/rig/angle", f64_t, typestore=ts)
        for tk, q, a in zip(t, _quat_roll(angle), angle):
            sec = int(EPOCH + tk)
            nsec = int(round((EPOCH + tk - sec) * 1e9))
            stamp = T["builtin_interfaces/msg/Time"](sec=sec, nanosec=nsec)
            hdr = T["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="imu") if ros1 else None
            hdr = hdr or T["std_msgs/msg/Header"](stamp=stamp, frame_id="imu")
            quat = T["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0])
            msg = T[imu_t](hdr, quat, cov, zero3, cov, zero3, cov)
            rec_ns = int((EPOCH + tk + 0.003) * 1e9)  # recorded 3 ms after the stamp
            w.write(c_imu, rec_ns, ser(msg, imu_t))
            w.write(c_f64, rec_ns, ser(T[f64_t](data=float(a)), f64_t))


@pytest.mark.parametrize("kind", ["sqlite3", "mcap", "ros1"])
def test_ros_bag_imu_roll_is_ingested_and_identified(tmp_path, rig, run_cli, kind) -> None:
    la = _launch(rig, 20.0, 11)
    bag = tmp_path / ("session.bag" if kind == "ros1" else "session")
    _write_bag(bag, la.t, la.y, kind)
    out = tmp_path / "imu"
    code, _, err = run_cli("ingest", bag, "--rig", RIG, "--out", out, "--topic", "/imu/data", "--signal", "roll")
    assert code == 0, err
    (d,) = _doc(out)["launches"]
    assert d["start_time"] == pytest.approx(EPOCH, abs=1e-6)  # header stamp, not the record time
    assert any("Euler" in n for n in d["notes"])
    y = np.loadtxt(out / "launch_001.csv", delimiter=",", skiprows=3)[:, 1]
    assert np.allclose(y, la.y, atol=2e-6)
    assert _identified(rig, [out / "launch_001.csv"]) == pytest.approx(TRUE["added_mass"], rel=0.01)
    # Float64 has no header: the record time is used
    out2 = tmp_path / "f64"
    code, _, err = run_cli("ingest", bag, "--rig", RIG, "--out", out2, "--topic", "/rig/angle", "--signal", "data")
    assert code == 0, err
    (d2,) = _doc(out2)["launches"]
    assert d2["start_time"] == pytest.approx(EPOCH + 0.003, abs=1e-6)
    assert any("record time" in n for n in d2["notes"])


# --- ArduPilot tlog ------------------------------------------------------------------------------


def _write_tlog(path: Path, t: np.ndarray, roll: np.ndarray) -> None:
    mavutil = pytest.importorskip("pymavlink.mavutil")
    path.touch()  # mavlink_connection opens an existing path as a log file
    conn = mavutil.mavlink_connection(str(path), write=True)
    jitter = np.random.default_rng(0).uniform(0, 0.02, t.size)
    for tk, r, j in zip(t, roll, jitter):
        conn.write(struct.pack(">Q", int((EPOCH + tk + j) * 1e6)))  # the ground station's receive stamp
        conn.mav.attitude_send(int(round(1000 * (60.0 + tk))), float(r), 0.01, 1.2, 0.0, 0.0, 0.0)
    conn.close()


def test_tlog_attitude_roll_is_ingested_and_identified(tmp_path, rig, run_cli) -> None:
    la = _launch(rig, -22.0, 5)
    log = tmp_path / "dive.tlog"
    _write_tlog(log, la.t, la.y)
    out = tmp_path / "o"
    code, _, err = run_cli("ingest", log, "--rig", RIG, "--out", out, "--signal", "ATTITUDE.roll")
    assert code == 0, err
    (d,) = _doc(out)["launches"]
    assert d["start_time"] == pytest.approx(60.0)  # time_boot_ms: the autopilot's clock
    assert any("filtered estimate" in n and "tens of ms" in n for n in d["notes"])
    y = np.loadtxt(out / "launch_001.csv", delimiter=",", skiprows=3)[:, 1]
    assert np.allclose(y, la.y, atol=1e-6)  # MAVLink floats are float32
    assert _identified(rig, [out / "launch_001.csv"]) == pytest.approx(TRUE["added_mass"], rel=0.01)


# --- splitting -----------------------------------------------------------------------------------


def test_split_finds_every_release_and_none_in_the_holds(tmp_path, rig, run_cli) -> None:
    t, y, releases, holds = _recording(rig)
    src = tmp_path / "session.csv"
    src.write_text("t,angle\n" + "\n".join(f"{a:.2f},{b:.7f}" for a, b in zip(t, y)) + "\n")
    out = tmp_path / "split"
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out, "--split", "--plots")
    assert code == 0, err
    found = [d["release_time"] for d in _doc(out)["launches"]]
    assert len(found) == 6
    assert np.allclose(found, releases, atol=0.05)
    # none inside a hold (the last 50 ms of a hold is where the release is)
    assert not [r for r in found for h0, h1 in holds if h0 <= r < h1 - 0.05]
    assert all(d["start_time"] < d["release_time"] < d["end_time"] for d in _doc(out)["launches"])
    files = sorted(out.glob("launch_*.csv"))
    assert len(files) == 6
    assert _identified(rig, files) == pytest.approx(TRUE["added_mass"], rel=0.01)


def test_split_function_on_its_own(rig) -> None:
    from hydrokit.identify.split import split_launches

    t, y, releases, _ = _recording(rig, amps=(15.0, -12.0))
    segs = split_launches(t, y)
    assert [round(t[s.release], 1) for s in segs] == [round(r, 1) for r in releases]
    assert all(s.start < s.release < s.end for s in segs)
    assert split_launches(t[:300], y[:300]) == []  # rest and lift only: no release


# --- bad input: one line, exit 2, nothing written ------------------------------------------------


@pytest.fixture
def bag(tmp_path, rig) -> Path:
    la = _launch(rig, 10.0, 1)
    path = tmp_path / "b"
    _write_bag(path, la.t, la.y, "sqlite3")
    return path


def _bad(run_cli, tmp_path, *args) -> str:
    out = tmp_path / "never"
    code, _, err = run_cli("ingest", *args, "--rig", RIG, "--out", out)
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert not out.exists()
    return err


def test_bad_bag_inputs(tmp_path, bag, run_cli) -> None:
    err = _bad(run_cli, tmp_path, bag, "--topic", "/nope", "--signal", "roll")
    assert "/nope" in err and "/imu/data" in err and "/rig/angle" in err
    err = _bad(run_cli, tmp_path, bag, "--topic", "/imu/data", "--signal", "orientation")
    assert "not a number" in err
    err = _bad(run_cli, tmp_path, bag, "--topic", "/imu/data", "--signal", "angular_velocity.w")
    assert "'w'" in err and "x, y, z" in err
    assert "give --topic" in _bad(run_cli, tmp_path, bag, "--signal", "data")


def test_bad_table_inputs(tmp_path, rig, run_cli) -> None:
    la = _launch(rig, 10.0, 2)
    src = tmp_path / "x.csv"
    src.write_text("time,pitch\n" + "\n".join(f"{t:.3f},{v:.6f}" for t, v in zip(la.t, la.y)) + "\n")
    err = _bad(run_cli, tmp_path, src, "--signal", "roll")
    assert "'roll'" in err and "time, pitch" in err
    back = tmp_path / "back.csv"
    rows = [f"{t:.3f},{v:.6f}" for t, v in zip(la.t, la.y)]
    rows[50], rows[51] = rows[51], rows[50]
    back.write_text("time,pitch\n" + "\n".join(rows) + "\n")
    assert "non-monotonic" in _bad(run_cli, tmp_path, back)
    still = tmp_path / "still.csv"
    still.write_text("time,pitch\n" + "\n".join(f"{0.01 * k:.2f},{0.1 + 1e-4 * (k % 3)}" for k in range(900)) + "\n")
    assert "no release found" in _bad(run_cli, tmp_path, still, "--split")
    odd = tmp_path / "x.dat"
    odd.write_text(src.read_text())
    assert "extension" in _bad(run_cli, tmp_path, odd)
    assert "--signal-unit" in _bad(run_cli, tmp_path, odd, "--format", "csv", "--signal-unit", "mm")


def test_missing_extras_name_the_install(tmp_path, bag, monkeypatch, run_cli) -> None:
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)
    err = _bad(run_cli, tmp_path, bag, "--topic", "/imu/data", "--signal", "roll")
    assert "pip install 'hydrokit[ros]'" in err
    log = tmp_path / "a.tlog"
    log.write_bytes(b"")
    monkeypatch.setitem(sys.modules, "pymavlink", None)
    assert "pip install 'hydrokit[ardupilot]'" in _bad(run_cli, tmp_path, log, "--signal", "ATTITUDE.roll")


def test_encoder_counts_on_a_spring_rig(tmp_path, run_cli) -> None:
    spring = RIG.with_name("spring_x.yaml")
    srig = hydrokit.load_rig(spring)
    la = simulate_launch(srig, 0.29, 1.0, 5.0, 0.05, 10.0, SensorModel.encoder(hold_time=1.0), 4)
    counts = np.round(la.y * 2450.0).astype(int)  # 2.45 counts/mm
    src = tmp_path / "enc.txt"
    src.write_text("us counts\n" + "\n".join(f"{int(t * 1e6)} {c}" for t, c in zip(la.t, counts)) + "\n")
    out = tmp_path / "o"
    code, _, err = run_cli(
        "ingest", src, "--rig", spring, "--out", out, "--time-unit", "us", "--signal-unit", f"counts:{1 / 2450.0}"
    )
    assert code == 0, err
    head = (out / "launch_001.csv").read_text().splitlines()
    assert head[2] == "time,position"
    y = np.loadtxt(out / "launch_001.csv", delimiter=",", skiprows=3)[:, 1]
    assert np.allclose(y, counts / 2450.0, atol=1e-9)
    # an angle unit on a spring rig is refused
    code, _, err = run_cli("ingest", src, "--rig", spring, "--out", tmp_path / "n", "--signal-unit", "deg")
    assert code == 2 and not (tmp_path / "n").exists()
    assert err.splitlines() == ["error: --signal-unit deg: a spring rig records a length"]
