"""Run files from vehicle logs (issue #44): DataFlash, tlog and ROS 2 bags generated here from a
known motion and known thruster commands, read back and compared with that truth."""

from __future__ import annotations

import csv
import math
import os
import struct
from pathlib import Path

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.errors import InputError
from hydrokit.io.runfile import log_to_run, pwm_to_level, read_channels
from hydrokit.io.vehicle import resolve_vehicle

RHO, G, P0 = 1000.0, 9.82, 101_325.0  # the bundled BlueROV2's water and gravity; sea-level air
# ArduSub vectored-6DOF (Heavy): motors 1-8 on outputs 1-8; the hydrokit layout's direction is the
# opposite of the frame's for FR, FL and the four vertical thrusters (docs/ingest.md)
MAPPING = {"FR": (1, True), "FL": (2, True), "RR": (3, False), "RL": (4, False)}
MAPPING |= {"VFR": (5, True), "VFL": (6, True), "VRR": (7, True), "VRL": (8, True)}
MOT_DIRECTION = {1: -1.0, 2: -1.0, 3: 1.0, 4: -1.0, 5: -1.0, 6: 1.0, 7: 1.0, 8: 1.0}  # as BlueROV2s ship


def mapped_vehicle(tmp_path: Path, drop: str | None = None, key: str = "channel") -> Path:
    doc = yaml.safe_load(resolve_vehicle("bluerov2-heavy").read_text())
    for th in doc["thrusters"]:
        for k in ("channel", "motor", "reversed"):  # the bundled file maps its thrusters; start bare
            th.pop(k, None)
        out, rev = MAPPING[th["name"]]
        if th["name"] != drop:
            th[key] = out
        th["reversed"] = rev
    path = tmp_path / f"rov-{key}-{drop}.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def truth(t: np.ndarray) -> dict[str, np.ndarray]:
    """A smooth dive: attitude (rad), rates (rad/s), depth (m), body velocity (m/s)."""
    return {
        "phi": 0.1 * np.sin(0.7 * t),
        "theta": -0.05 + 0.08 * np.cos(0.4 * t),
        "psi": np.angle(np.exp(1j * (3.0 + 0.3 * t))),  # crosses ±π during the run
        "p": 0.2 * np.sin(1.1 * t),
        "q": -0.1 * np.cos(0.9 * t),
        "r": 0.05 + 0.0 * t,
        "z": 1.0 + 0.5 * np.sin(0.3 * t),
        "u": 0.4 * np.sin(0.2 * t),
        "v": -0.1 + 0.0 * t,
        "w": 0.05 * np.cos(0.5 * t),
    }


def commands(t: np.ndarray) -> np.ndarray:
    """(n, 8) autopilot actuator levels −1…1 of motors 1-8 along the frame's directions."""
    k = np.arange(1, 9)
    return np.clip(0.6 * np.sin(0.5 * t[:, None] + k), -1, 1)


def pwm_of(level: np.ndarray) -> np.ndarray:
    """What ArduSub writes: 1500 + MOT_n_DIRECTION · level · 400 µs, whole µs."""
    d = np.array([MOT_DIRECTION[k] for k in range(1, 9)])
    return np.round(1500 + 400 * d * level).astype(int)


# --- a DataFlash writer (the binary format DFReader reads: 0xA3 0x95 type payload, FMT first) ----
FMT_TYPE = 128


def _fmt(mtype: int, name: str, fmt: str, cols: str) -> bytes:
    length = 3 + struct.calcsize("<" + fmt.replace("N", "16s").replace("Q", "Q"))
    return bytes([0xA3, 0x95, FMT_TYPE]) + struct.pack(
        "<BB4s16s64s", mtype, length, name.encode(), fmt.encode(), cols.encode()
    )


def _rec(mtype: int, fmt: str, *vals: object) -> bytes:
    return bytes([0xA3, 0x95, mtype]) + struct.pack("<" + fmt.replace("N", "16s"), *vals)


DF = {
    "ATT": (129, "Qffffff", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw"),
    "IMU": (130, "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ"),
    "BARO": (131, "QBff", "TimeUS,I,Alt,Press"),
    "RCOU": (132, "QHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10"),
    "VISO": (133, "Qffffffff", "TimeUS,dt,AngDX,AngDY,AngDZ,PosDX,PosDY,PosDZ,conf"),
    "PARM": (134, "QNf", "TimeUS,Name,Value"),
}


def write_dataflash(
    path: Path, *, att: bool = True, dvl: bool = True, t_end: float = 6.0, params: dict | None = None
) -> dict[str, np.ndarray]:
    """A DataFlash log: ATT 10 Hz (deg), IMU 25 Hz (two instances), BARO 10 Hz (internal + depth
    sensor), RCOU 10 Hz, VISO 5 Hz, PARM; returns the sample times used."""
    out = bytearray()
    for name, (mt, fmt, cols) in DF.items():
        out += _fmt(mt, name, fmt, cols)
    t0 = 100.0  # the autopilot's clock at the start of logging
    for k, v in MOT_DIRECTION.items():
        out += _rec(134, "QNf", int(t0 * 1e6), f"MOT_{k}_DIRECTION".encode(), v)
    out += _rec(134, "QNf", int(t0 * 1e6), b"BARO_PRIMARY", 1.0)
    for k, v in (params or {}).items():
        out += _rec(134, "QNf", int(t0 * 1e6), k.encode(), float(v))
    times = {
        "ATT": t0 + 0.013 + np.arange(0, t_end, 0.1),
        "IMU": t0 + 0.004 + np.arange(0, t_end, 0.04),
        "BARO": t0 + 0.021 + np.arange(0, t_end, 0.1),
        "RCOU": t0 + 0.017 + np.arange(0, t_end, 0.1),
        "VISO": t0 + 0.05 + np.arange(0.2, t_end, 0.2),
    }
    times = {k: np.round(v, 6) for k, v in times.items()}  # whole µs, as TimeUS holds them
    events = []
    for tk in times["ATT"]:
        s = truth(np.array([tk]))
        deg = [math.degrees(s[c][0]) for c in ("phi", "theta", "psi")]
        if att:
            events.append(
                (tk, _rec(129, "Qffffff", int(round(tk * 1e6)), deg[0], deg[0], deg[1], deg[1], deg[2], deg[2]))
            )
    for tk in times["IMU"]:
        s = truth(np.array([tk]))
        for inst, scale in ((0, 1.0), (1, 5.0)):  # instance 1 is not the one read
            gyr = [scale * s[c][0] for c in ("p", "q", "r")]
            events.append((tk, _rec(130, "QBffffff", int(round(tk * 1e6)), inst, *gyr, 0.0, 0.0, -9.8)))
    for tk in times["BARO"]:
        z = truth(np.array([tk]))["z"][0]
        events.append((tk, _rec(131, "QBff", int(round(tk * 1e6)), 0, 0.0, 99_000.0)))  # inside the enclosure
        events.append((tk, _rec(131, "QBff", int(round(tk * 1e6)), 1, -z, P0 + RHO * G * z)))
    pwm = pwm_of(commands(times["RCOU"]))
    for tk, row in zip(times["RCOU"], pwm):
        events.append((tk, _rec(132, "QHHHHHHHHHH", int(round(tk * 1e6)), *row.tolist(), 1100, 0)))
    if dvl:
        for tk in times["VISO"]:
            s = truth(np.array([tk]))
            dt = 0.2
            vals = (dt, 0.0, 0.0, 0.0, s["u"][0] * dt, s["v"][0] * dt, s["w"][0] * dt, 90.0)
            events.append((tk, _rec(133, "Qffffffff", int(round(tk * 1e6)), *vals)))
    events.sort(key=lambda e: e[0])
    for _, b in events:
        out += b
    path.write_bytes(bytes(out))
    return times


@pytest.fixture
def vehicle(tmp_path: Path) -> hydrokit.Vehicle:
    return hydrokit.load_vehicle(mapped_vehicle(tmp_path))


def _read_csv(text: str) -> tuple[list[str], np.ndarray]:
    rows = list(csv.reader(text.splitlines()))
    head = rows[0]
    data = np.array([[float(c) if c else np.nan for c in r] for r in rows[1:]])
    return head, data


def test_dataflash_run_matches_the_truth(tmp_path: Path, vehicle) -> None:
    pytest.importorskip("pymavlink")
    log = tmp_path / "dive.BIN"
    times = write_dataflash(log)
    ch = read_channels(log)
    run = log_to_run(ch, vehicle.thrusters, density=vehicle.density, gravity=vehicle.gravity, surface_pressure=P0)
    head, data = _read_csv(run.csv)
    names = [th.name for th in vehicle.thrusters.thrusters]
    assert head == ["time", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r", *names]
    t = data[:, 0]
    assert np.all(np.diff(t) > 0)
    col = {h: data[:, i] for i, h in enumerate(head)}
    s = truth(t)
    # every measured cell equals the generating motion at its row time; float32 in the log:
    # |x| ≤ 200° in degrees → ulp 1.5e-5 deg = 2.7e-7 rad; pressure 1e5 Pa float32 → 0.008 Pa = 1e-6 m
    for c, tol in (("phi", 1e-6), ("theta", 1e-6), ("psi", 1e-6), ("p", 1e-6), ("q", 1e-6), ("r", 1e-6)):
        m = ~np.isnan(col[c])
        assert np.allclose(col[c][m], s[c][m], atol=tol), c
    m = ~np.isnan(col["z"])
    assert np.allclose(col["z"][m], s["z"][m], atol=2e-6)  # z = (P − P0)/(ρ g) inverts the log's P
    for c in ("u", "v", "w"):
        m = ~np.isnan(col[c])
        assert np.allclose(col[c][m], s[c][m], atol=1e-6), c
    # each channel at its own rate: as many filled cells as samples written in the span
    span = (t[0] <= times["ATT"]) & (times["ATT"] <= t[-1])
    assert int(np.sum(~np.isnan(col["phi"]))) == int(span.sum())
    assert int(np.sum(~np.isnan(col["p"]))) == int(np.sum((t[0] <= times["IMU"]) & (times["IMU"] <= t[-1])))
    assert 4.0 < np.sum(~np.isnan(col["u"])) / (t[-1] - t[0]) < 6.0  # 5 Hz DVL
    # commands: zero-order hold of the last RCOU sample, mapped back through MOT_n_DIRECTION and
    # the thruster's 'reversed': the frame's level ±, quantised by 1 µs in 400 (tol 1/800)
    idx = np.searchsorted(times["RCOU"], t, side="right") - 1
    level = commands(times["RCOU"])[idx]
    for k, name in enumerate(["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]):
        sign = -1.0 if MAPPING[name][1] else 1.0
        assert np.allclose(col[name], sign * level[:, k], atol=1 / 800 + 1e-12), name
        assert not np.any(np.isnan(col[name]))  # on every row
    d = run.to_dict()
    assert d["channels"]["phi"]["rate"] == pytest.approx(10.0, rel=1e-3)
    assert d["channels"]["p"]["rate"] == pytest.approx(25.0, rel=1e-3)
    assert any("BARO instance 1" in n for n in d["notes"])
    files = run.files(tmp_path / "r.csv")
    assert set(files) == {tmp_path / "r.csv", tmp_path / "r.json"}


def test_the_run_reader_takes_what_ingest_writes(tmp_path: Path, vehicle) -> None:
    """The contract's own reader (hydrokit.io.runlog) reads the file back unchanged."""
    pytest.importorskip("pymavlink")
    from hydrokit.io.runlog import read_run

    log = tmp_path / "dive.bin"
    times = write_dataflash(log, dvl=False)
    run = log_to_run(read_channels(log), vehicle.thrusters, density=RHO, gravity=G, start=101.0, end=104.0)
    path = tmp_path / "run.csv"
    path.write_text(run.csv)
    back = read_run(path, [th.name for th in vehicle.thrusters.thrusters])
    assert back.time[0] >= 101.0 and back.time[-1] <= 104.0
    assert set(back.channels) == {"z", "phi", "theta", "psi", "p", "q", "r"}
    tt, zz = back.channels["z"]
    first = times["BARO"][times["BARO"] <= times["BARO"][0] + 1.0]  # the surface: the first second
    expected = truth(tt)["z"] - float(np.mean(truth(first)["z"]))
    assert np.allclose(zz, expected, atol=2e-6)  # float32 pressure: 1e-6 m
    head = run.csv.splitlines()[0].split(",")
    assert np.allclose(back.commands["RR"], [float(r.split(",")[head.index("RR")]) for r in run.csv.splitlines()[1:]])


def test_surface_pressure_from_the_first_second(tmp_path: Path, vehicle) -> None:
    pytest.importorskip("pymavlink")
    log = tmp_path / "d.bin"
    times = write_dataflash(log, dvl=False)
    run = log_to_run(read_channels(log), vehicle.thrusters, density=RHO, gravity=G)
    first = times["BARO"][times["BARO"] <= times["BARO"][0] + 1.0]
    p_surf = P0 + RHO * G * float(np.mean(truth(first)["z"]))
    assert run.to_dict()["surface_pressure"] == pytest.approx(p_surf, abs=0.05)  # float32 Pa
    assert any("first 1 s" in n for n in run.to_dict()["notes"])


def test_motor_numbers_and_pwm_levels(tmp_path: Path) -> None:
    pytest.importorskip("pymavlink")
    # ArduSub calc_thrust_to_pwm: 1500 + a·400; asymmetric ranges scale each side by its own span
    assert np.allclose(pwm_to_level(np.array([1100, 1300, 1500, 1700, 1900])), [-1, -0.5, 0, 0.5, 1])
    assert np.allclose(pwm_to_level(np.array([1200, 1800]), 1200, 1700), [-1, 1])
    log = tmp_path / "d.bin"
    write_dataflash(log, dvl=False)
    v = hydrokit.load_vehicle(mapped_vehicle(tmp_path, key="motor"))
    by_motor = log_to_run(read_channels(log), v.thrusters, density=RHO, gravity=G).csv
    v2 = hydrokit.load_vehicle(mapped_vehicle(tmp_path))
    by_channel = log_to_run(read_channels(log), v2.thrusters, density=RHO, gravity=G)
    assert by_motor.splitlines()[1:] == by_channel.csv.splitlines()[1:]


def test_bad_logs_name_what_is_missing(tmp_path: Path, vehicle) -> None:
    pytest.importorskip("pymavlink")
    log = tmp_path / "noatt.bin"
    write_dataflash(log, att=False)
    with pytest.raises(InputError, match=r"no ATT messages in the log: a run needs the attitude"):
        read_channels(log)
    ok = tmp_path / "ok.bin"
    write_dataflash(ok)
    ch = read_channels(ok)
    unmapped = hydrokit.load_vehicle(mapped_vehicle(tmp_path, drop="RL"))
    with pytest.raises(InputError, match=r"thruster 'RL' has no 'channel'"):
        log_to_run(ch, unmapped.thrusters, density=RHO, gravity=G)
    doc = yaml.safe_load(mapped_vehicle(tmp_path).read_text())
    doc["thrusters"][0]["channel"] = 12
    far = tmp_path / "far.yaml"
    far.write_text(yaml.safe_dump(doc))
    with pytest.raises(InputError, match=r"thruster 'FR': output 12 is not in the log \(RCOU: 1, 2, .*10\)"):
        log_to_run(ch, hydrokit.load_vehicle(far).thrusters, density=RHO, gravity=G)
    with pytest.raises(InputError, match=r"no samples between 200.000 and"):
        log_to_run(ch, vehicle.thrusters, density=RHO, gravity=G, start=200.0)
    with pytest.raises(InputError, match=r"--end 101 s is not after --start 102 s"):
        log_to_run(ch, vehicle.thrusters, density=RHO, gravity=G, start=102.0, end=101.0)
    with pytest.raises(InputError, match=r"--baro 3: no BARO instance 3 in the log \(have: 0, 1\)"):
        read_channels(ok, baro=3)
    doc["thrusters"][0]["channel"] = 0
    far.write_text(yaml.safe_dump(doc))
    with pytest.raises(
        InputError, match=r"thrusters\[0\] \(FR\): thruster 'FR' channel = 0: expected an output number"
    ):
        hydrokit.load_vehicle(far)
    doc["thrusters"][0].update(channel=1, reversed="yes")
    far.write_text(yaml.safe_dump(doc))
    with pytest.raises(InputError, match=r"thruster 'FR' reversed = 'yes': expected true or false"):
        hydrokit.load_vehicle(far)


def test_the_mapping_fields_are_metadata_only(tmp_path: Path) -> None:
    plain = hydrokit.load_vehicle("bluerov2-heavy")
    mapped = hydrokit.load_vehicle(mapped_vehicle(tmp_path))
    assert mapped.thrusters == plain.thrusters  # the model does not see them
    assert [th.channel for th in mapped.thrusters.thrusters] == [
        MAPPING[th.name][0] for th in plain.thrusters.thrusters
    ]
    assert [th.reversed for th in mapped.thrusters.thrusters][:3] == [True, True, False]
    assert not any("unknown field" in n for n in mapped.thrusters.notes)


def test_table_units_propeller_and_ideal_thrusters(tmp_path: Path) -> None:
    """Commands in each curve's unit: a PWM table keeps µs, a propeller n = level·max_rpm/60,
    an ideal thruster F = level·max_thrust (|min_thrust| below zero)."""
    pytest.importorskip("pymavlink")
    log = tmp_path / "d.bin"
    times = write_dataflash(log, dvl=False)
    doc = {
        "fluid": {"density": RHO},
        "thrusters": [
            {
                "name": "A",
                "position": [0, 0, 0],
                "direction": [1, 0, 0],
                "max_thrust": 50,
                "channel": 3,
                "thrust_table": {"command": [1100, 1500, 1900], "thrust": [-40, 0, 50]},
            },
            {
                "name": "B",
                "position": [0, 0, 0],
                "direction": [1, 0, 0],
                "max_thrust": 50,
                "min_thrust": -20,
                "channel": 3,
            },
            {
                "name": "C",
                "position": [0, 0, 0],
                "direction": [1, 0, 0],
                "max_thrust": 50,
                "channel": 3,
                "diameter": 0.1,
                "kt_forward": [0.4],
                "max_rpm": 3000,
            },
            {
                "name": "D",
                "position": [0, 0, 0],
                "direction": [1, 0, 0],
                "max_thrust": 50,
                "channel": 3,
                "thrust_table": {"command": [0, 10], "thrust": [0, 50]},
            },
        ],
    }
    from hydrokit.io.thrusters import parse_thrusters

    ths = parse_thrusters(doc, "t.yaml")
    keep = parse_thrusters({**doc, "thrusters": doc["thrusters"][:3]}, "t.yaml")
    run = log_to_run(read_channels(log), keep, density=RHO, gravity=G)
    head, data = _read_csv(run.csv)
    col = {h: data[:, i] for i, h in enumerate(head)}
    idx = np.searchsorted(times["RCOU"], col["time"], side="right") - 1
    level = commands(times["RCOU"])[idx][:, 2]  # motor 3, MOT_3_DIRECTION = +1
    assert np.allclose(col["A"], np.round(1500 + 400 * level), atol=1e-9)
    assert np.allclose(col["B"], np.where(level >= 0, 50 * level, 20 * level), atol=50 / 800)
    assert np.allclose(col["C"], level * 3000 / 60, atol=50 / 800)
    assert run.to_dict()["thrusters"]["C"]["unit"] == "rev/s"
    with pytest.raises(InputError, match=r"thruster 'D': its thrust_table command runs 0…10"):
        log_to_run(read_channels(log), ths, density=RHO, gravity=G)


# --- MAVLink tlog ---------------------------------------------------------------------------------


def write_tlog(path: Path, *, t_end: float = 5.0, garbage: bool = True, dvl: bool = False) -> dict[str, np.ndarray]:
    """A tlog: ATTITUDE 20 Hz, RAW_IMU 10 Hz (mrad/s), SCALED_PRESSURE2 5 Hz (hPa), SERVO_OUTPUT_RAW
    10 Hz, PARAM_VALUE, a ground station's heartbeat and (optionally) one corrupt packet."""
    mavutil = pytest.importorskip("pymavlink.mavutil")
    saved = os.environ.get("MAVLINK20")
    os.environ["MAVLINK20"] = "1"  # MAVLink 2, as ArduSub sends (VISION_POSITION_DELTA is id 11011)
    mavutil.set_dialect("ardupilotmega")
    path.touch()
    conn = mavutil.mavlink_connection(str(path), write=True, source_system=1)
    if saved is None:
        del os.environ["MAVLINK20"]
    t0, epoch = 50.0, 1.7e9
    times = {
        "ATTITUDE": t0 + np.arange(0, t_end, 0.05),
        "RAW_IMU": t0 + 0.01 + np.arange(0, t_end, 0.1),
        "SP2": t0 + 0.02 + np.arange(0, t_end, 0.2),
        "SERVO": t0 + 0.03 + np.arange(0, t_end, 0.1),
    }
    times = {k: np.round(v, 3) if k in ("ATTITUDE", "SP2") else np.round(v, 6) for k, v in times.items()}
    ev = []
    for tk in times["ATTITUDE"]:
        s = truth(np.array([tk]))
        ev.append((tk, "att", s))
    for key in ("RAW_IMU", "SP2", "SERVO"):
        ev += [(tk, key, truth(np.array([tk]))) for tk in times[key]]
    ev.sort(key=lambda e: e[0])

    def send(tk: float, fn: object, *args: object) -> None:
        conn.write(struct.pack(">Q", int((epoch + tk + 0.01) * 1e6)))  # the ground station's receive stamp
        fn(*args)  # type: ignore[operator]

    for k, v in MOT_DIRECTION.items():
        send(t0, conn.mav.param_value_send, f"MOT_{k}_DIRECTION".encode(), v, 9, 200, k)
    gcs = mavutil.mavlink.MAVLink(conn, srcSystem=255)
    send(t0, gcs.attitude_send, 0, 1.0, 1.0, 1.0, 0, 0, 0)  # another system's ATTITUDE: ignored
    for tk, kind, s in ev:
        ms = int(round(tk * 1000))
        if kind == "att":
            send(tk, conn.mav.attitude_send, ms, s["phi"][0], s["theta"][0], s["psi"][0], 9.0, 9.0, 9.0)
        elif kind == "RAW_IMU":
            g = [int(round(1000 * s[c][0])) for c in ("p", "q", "r")]
            send(tk, conn.mav.raw_imu_send, int(round(tk * 1e6)), 0, 0, -980, *g, 0, 0, 0)
        elif kind == "SP2":
            send(tk, conn.mav.scaled_pressure2_send, ms, (P0 + RHO * G * s["z"][0]) / 100.0, 0.0, 1500)
        else:
            pwm = pwm_of(commands(np.array([tk])))[0]
            send(tk, conn.mav.servo_output_raw_send, int(round(tk * 1e6)), 0, *pwm.tolist())
        if dvl and kind == "SP2":  # the DVL through the autopilot's link: 0.2 s of body-frame travel
            d = [0.2 * s[c][0] for c in ("u", "v", "w")]
            send(tk, conn.mav.vision_position_delta_send, 0, 200_000, [0.0, 0.0, 0.0], d, 90.0)
        if garbage and kind == "SP2" and tk > t0 + 2.0:
            bad = bytes([0xFD, 9, 0, 0, 7, 1, 1, 30, 0, 0]) + bytes(range(1, 12))  # a MAVLink 2 packet, bad CRC
            send(tk, conn.write, bad)
            garbage = False
    conn.close()
    return times


def test_tlog_run_matches_the_truth(tmp_path: Path, vehicle) -> None:
    log = tmp_path / "dive.tlog"
    times = write_tlog(log)
    ch = read_channels(log)
    run = log_to_run(ch, vehicle.thrusters, density=vehicle.density, gravity=vehicle.gravity, surface_pressure=P0)
    head, data = _read_csv(run.csv)
    col = {h: data[:, i] for i, h in enumerate(head)}
    s = truth(col["time"])
    for c in ("phi", "theta", "psi"):
        m = ~np.isnan(col[c])
        assert np.allclose(col[c][m], s[c][m], atol=1e-6), c  # MAVLink float32
    for c in ("p", "q", "r"):  # RAW_IMU in whole mrad/s: ±0.5e-3 rad/s
        m = ~np.isnan(col[c])
        assert m.sum() == pytest.approx(10 * (col["time"][-1] - col["time"][0]), abs=2)
        assert np.allclose(col[c][m], s[c][m], atol=0.5e-3 + 1e-9), c
    m = ~np.isnan(col["z"])
    assert np.allclose(col["z"][m], s["z"][m], atol=1e-4)  # hPa float32 at 1013: ulp 6e-5 hPa = 6e-4 mm
    idx = np.searchsorted(times["SERVO"], col["time"], side="right") - 1
    level = commands(times["SERVO"])[idx]
    for k, name in enumerate(["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]):
        sign = -1.0 if MAPPING[name][1] else 1.0
        assert np.allclose(col[name], sign * level[:, k], atol=1 / 800 + 1e-12), name
    d = run.to_dict()
    assert d["corrupt_packets"] == 1
    assert any("corrupt" in w for w in d["warnings"])
    assert any("RAW_IMU" in n for n in d["notes"]) and any("system 1" in n for n in d["notes"])


# --- ROS 2 bag ------------------------------------------------------------------------------------


def _enu_quaternion(phi: np.ndarray, theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """(w, x, y, z) of the ENU/FLU attitude of a NED/FRD one: roll φ, pitch −θ, yaw π/2 − ψ."""
    from hydrokit.core.kinematics import euler_to_quaternion

    return np.array([euler_to_quaternion(a, -b, math.pi / 2 - c) for a, b, c in zip(phi, theta, psi)])


def write_bag(
    path: Path, *, t_end: float = 4.0, per_thruster: bool = False, odom: bool = False
) -> dict[str, np.ndarray]:
    pytest.importorskip("rosbags")
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.LATEST)
    T = ts.types
    epoch = 1.7e9
    times = {
        "imu": np.arange(0, t_end, 0.02),
        "p": 0.005 + np.arange(0, t_end, 0.1),
        "dvl": 0.01 + np.arange(0, t_end, 0.2),
    }
    times["cmd"] = 0.003 + np.arange(0, t_end, 0.05)

    def header(tk: float) -> object:
        sec = int(epoch + tk)
        return T["std_msgs/msg/Header"](
            stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=int(round((epoch + tk - sec) * 1e9))),
            frame_id="base_link",
        )

    V3, cov = T["geometry_msgs/msg/Vector3"], np.zeros(9)
    names = ["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]
    with Writer(path, version=9) as w:
        c_imu = w.add_connection("/imu", "sensor_msgs/msg/Imu", typestore=ts)
        c_p = w.add_connection("/pressure", "sensor_msgs/msg/FluidPressure", typestore=ts)
        c_dvl = w.add_connection("/dvl/twist", "geometry_msgs/msg/TwistStamped", typestore=ts)
        c_odom = w.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=ts) if odom else None
        if per_thruster:
            c_th = {n: w.add_connection(f"/thrusters/{n}/input", "std_msgs/msg/Float64", typestore=ts) for n in names}
        else:
            c_cmd = w.add_connection("/commands", "std_msgs/msg/Float64MultiArray", typestore=ts)
        ev = []
        s = truth(times["imu"])
        q = _enu_quaternion(s["phi"], s["theta"], s["psi"])
        for k, tk in enumerate(times["imu"]):
            quat = T["geometry_msgs/msg/Quaternion"](x=q[k, 1], y=q[k, 2], z=q[k, 3], w=q[k, 0])
            wv = V3(x=s["p"][k], y=-s["q"][k], z=-s["r"][k])  # FLU
            msg = T["sensor_msgs/msg/Imu"](header(tk), quat, cov, wv, cov, V3(x=0.0, y=0.0, z=9.8), cov)
            ev.append((tk, c_imu, ts.serialize_cdr(msg, "sensor_msgs/msg/Imu")))
        sp = truth(times["p"])
        for k, tk in enumerate(times["p"]):
            msg = T["sensor_msgs/msg/FluidPressure"](header(tk), P0 + RHO * G * sp["z"][k], 0.0)
            ev.append((tk, c_p, ts.serialize_cdr(msg, "sensor_msgs/msg/FluidPressure")))
        sd = truth(times["dvl"])
        for k, tk in enumerate(times["dvl"]):
            tw = T["geometry_msgs/msg/Twist"](
                linear=V3(x=sd["u"][k], y=-sd["v"][k], z=-sd["w"][k]), angular=V3(x=0.0, y=0.0, z=0.0)
            )
            msg = T["geometry_msgs/msg/TwistStamped"](header(tk), tw)
            ev.append((tk, c_dvl, ts.serialize_cdr(msg, "geometry_msgs/msg/TwistStamped")))
            if c_odom is not None:  # ENU position: z up = −depth; FLU twist
                pos = T["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=-sd["z"][k])
                ori = T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
                pose = T["geometry_msgs/msg/PoseWithCovariance"](T["geometry_msgs/msg/Pose"](pos, ori), np.zeros(36))
                twc = T["geometry_msgs/msg/TwistWithCovariance"](tw, np.zeros(36))
                od = T["nav_msgs/msg/Odometry"](header(tk), "base_link", pose, twc)
                ev.append((tk, c_odom, ts.serialize_cdr(od, "nav_msgs/msg/Odometry")))
        lv = commands(times["cmd"])
        for k, tk in enumerate(times["cmd"]):
            if per_thruster:
                for j, n in enumerate(names):
                    if n == "RL" and k < 3:  # this thruster's topic starts late: the run starts with it
                        continue
                    ev.append(
                        (
                            tk,
                            c_th[n],
                            ts.serialize_cdr(T["std_msgs/msg/Float64"](data=float(lv[k, j])), "std_msgs/msg/Float64"),
                        )
                    )
            else:
                layout = T["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
                msg = T["std_msgs/msg/Float64MultiArray"](layout=layout, data=lv[k].astype(float))
                ev.append((tk, c_cmd, ts.serialize_cdr(msg, "std_msgs/msg/Float64MultiArray")))
        ev.sort(key=lambda e: e[0])
        for tk, c, raw in ev:
            w.write(c, int((epoch + tk + 0.002) * 1e9), raw)  # recorded 2 ms after the stamp
    return {k: np.round(v + epoch, 6) for k, v in times.items()}


@pytest.mark.parametrize("per_thruster", [False, True])
def test_ros2_bag_run_matches_the_truth(tmp_path: Path, per_thruster: bool) -> None:
    bag = tmp_path / "bag"
    times = write_bag(bag, per_thruster=per_thruster)
    # commands in the bag are the thrusters' own (normalised) inputs along the hydrokit layout
    v = hydrokit.load_vehicle(mapped_vehicle(tmp_path))
    cmd = "/thrusters/{name}/input" if per_thruster else "/commands"
    ch = read_channels(bag, topics={"dvl": "/dvl/twist", "command": cmd})
    run = log_to_run(ch, v.thrusters, density=RHO, gravity=G, surface_pressure=P0)
    head, data = _read_csv(run.csv)
    col = {h: data[:, i] for i, h in enumerate(head)}
    t = col["time"]
    s = truth(t - 1.7e9)
    # ROS time near 1.7e9 s in float64: 2.4e-7 s resolution; the signals move < 1 rad/s → ≤ 1e-6
    for c in ("phi", "theta", "psi", "p", "q", "r", "u", "v", "w"):
        m = ~np.isnan(col[c])
        assert m.sum() > 0
        assert np.allclose(col[c][m], s[c][m], atol=1e-6), c
    m = ~np.isnan(col["z"])
    assert np.allclose(col["z"][m], s["z"][m], atol=1e-6)
    assert t[0] >= times["cmd"][3 if per_thruster else 0]  # every command known from the first row
    idx = np.searchsorted(times["cmd"], t, side="right") - 1
    level = commands(times["cmd"] - 1.7e9)[idx]
    for k, name in enumerate(["FR", "FL", "RR", "RL", "VFR", "VFL", "VRR", "VRL"]):
        sign = -1.0 if MAPPING[name][1] else 1.0  # 'reversed' applies to a bag's commands too
        # Float64 commands; the truth re-evaluated at epoch-shifted times (float64 at 1.7e9 s: ±2.4e-7 s)
        assert np.allclose(col[name], sign * level[:, k], atol=1e-6), name


def test_bad_bag_topics(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    write_bag(bag, t_end=1.0)
    with pytest.raises(InputError, match=r"--dvl-topic '/nope' is not in the bag \(topics: /commands"):
        read_channels(bag, topics={"dvl": "/nope", "command": "/commands"})
    with pytest.raises(InputError, match=r"--dvl-topic /imu: a sensor_msgs/msg/Imu, expected"):
        read_channels(bag, topics={"dvl": "/imu", "command": "/commands"})
    with pytest.raises(InputError, match=r"give --command-topic"):
        read_channels(bag, topics={})
    with pytest.raises(InputError, match=r"--command-topic '/x/\{name\}': no Float64/Float32 topic matches"):
        read_channels(bag, topics={"command": "/x/{name}"})
    with pytest.raises(InputError, match=r"--ros-frame 'nwu': expected enu or ned"):
        read_channels(bag, topics={"command": "/commands"}, ros_frame="nwu")
    with pytest.raises(InputError, match=r"--baro is for an ArduPilot log"):
        read_channels(bag, baro=1)


def test_servo_functions_decide_the_motor_outputs(tmp_path: Path) -> None:
    """SERVOn_FUNCTION decides which output drives motor n (here motors 1 and 2 swap outputs)."""
    pytest.importorskip("pymavlink")
    log = tmp_path / "d.bin"
    swap = {"SERVO1_FUNCTION": 34, "SERVO2_FUNCTION": 33, **{f"SERVO{k}_FUNCTION": 32 + k for k in range(3, 9)}}
    write_dataflash(log, params=swap)
    ch = read_channels(log)
    v = hydrokit.load_vehicle(mapped_vehicle(tmp_path, key="motor"))
    d = log_to_run(ch, v.thrusters, density=RHO, gravity=G).to_dict()
    assert d["thrusters"]["FR"]["output"] == 2 and d["thrusters"]["FL"]["output"] == 1
    assert d["thrusters"]["FR"]["motor"] == 1
    v2 = hydrokit.load_vehicle(mapped_vehicle(tmp_path))  # by channel: output 1 drives motor 2
    assert log_to_run(ch, v2.thrusters, density=RHO, gravity=G).to_dict()["thrusters"]["FR"]["motor"] == 2
    assert d["thrusters"]["FL"]["direction_param"] == MOT_DIRECTION[2]
    assert not any("default SERVOn_FUNCTION" in n for n in d["notes"])
    bad = tmp_path / "b.bin"
    write_dataflash(bad, params={"MOT_PWM_MIN": 1600})
    with pytest.raises(InputError, match=r"MOT_PWM_MIN 1600 / MOT_PWM_MAX 1900 µs do not bracket 1500 µs"):
        log_to_run(read_channels(bad), v.thrusters, density=RHO, gravity=G)


def test_tlog_dvl_on_the_autopilot_clock(tmp_path: Path, vehicle) -> None:
    log = tmp_path / "dvl.tlog"
    write_tlog(log, garbage=False, dvl=True)
    run = log_to_run(read_channels(log), vehicle.thrusters, density=RHO, gravity=G)
    head, data = _read_csv(run.csv)
    s = truth(data[:, 0])
    for c in ("u", "v", "w"):
        m = ~np.isnan(data[:, head.index(c)])
        assert 20 <= m.sum() <= 26  # 5 Hz for 5 s
        assert np.allclose(data[m, head.index(c)], s[c][m], atol=1e-6), c  # float32 deltas / 0.2 s
    assert run.to_dict()["corrupt_packets"] == 0


def test_bag_depth_and_dvl_from_odometry(tmp_path: Path) -> None:
    bag = tmp_path / "odom"
    write_bag(bag, odom=True)
    v = hydrokit.load_vehicle(mapped_vehicle(tmp_path))
    ch = read_channels(bag, topics={"depth": "/odom", "dvl": "/odom", "command": "/commands"})
    assert ch.pressure is None  # an explicit depth topic: the pressure topic is not read
    run = log_to_run(ch, v.thrusters, density=RHO, gravity=G)
    head, data = _read_csv(run.csv)
    s = truth(data[:, 0] - 1.7e9)
    for c in ("z", "u", "v", "w"):
        m = ~np.isnan(data[:, head.index(c)])
        assert m.sum() >= 15 and np.allclose(data[m, head.index(c)], s[c][m], atol=1e-6), c
    ned = read_channels(bag, topics={"depth": "/odom", "command": "/commands"}, ros_frame="ned")
    assert np.allclose(ned.motion["z"].y, -ch.motion["z"].y)  # NED: the position's z is the depth
    assert np.allclose(ned.motion["q"].y, -ch.motion["q"].y)  # no FLU → FRD flip


def test_more_bad_logs(tmp_path: Path, vehicle) -> None:
    pytest.importorskip("pymavlink")
    from hydrokit.io.runfile import LogChannels

    # the autopilot rebooted inside the log: its clock goes back
    out = bytearray(_fmt(129, "ATT", *DF["ATT"][1:]))
    for tk in (100.0, 100.1, 100.2, 3.0, 3.1):
        out += _rec(129, "Qffffff", int(tk * 1e6), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    (tmp_path / "reboot.bin").write_bytes(bytes(out))
    with pytest.raises(InputError, match=r"ATT: the autopilot's clock goes back from 100.200 to 3.000 s"):
        read_channels(tmp_path / "reboot.bin")
    # attitude but no servo outputs
    (tmp_path / "noout.bin").write_bytes(bytes(out[: len(out) - 2 * len(_rec(129, "Qffffff", 0, *[0.0] * 6))]))
    with pytest.raises(InputError, match=r"no servo outputs \(RCOU\) in the log: a run needs the thruster commands"):
        read_channels(tmp_path / "noout.bin")
    src = tmp_path / "table.csv"
    src.write_text("time,angle\n0,0\n")
    with pytest.raises(InputError, match=r"--run-out reads an ArduPilot log or a ROS bag, not a csv source"):
        read_channels(src)
    empty = LogChannels("x.bin", {}, None, {})
    with pytest.raises(InputError, match=r"no attitude in the log"):
        log_to_run(empty, vehicle.thrusters, density=RHO, gravity=G)


def test_an_output_without_pulses_is_a_zero_command(tmp_path: Path) -> None:
    """RCOU C10 is 0 µs throughout (an output the frame does not drive): command 0, and said."""
    pytest.importorskip("pymavlink")
    log = tmp_path / "d.bin"
    write_dataflash(log, dvl=False)
    doc = yaml.safe_load(mapped_vehicle(tmp_path).read_text())
    doc["thrusters"][7]["channel"] = 10
    path = tmp_path / "ten.yaml"
    path.write_text(yaml.safe_dump(doc))
    run = log_to_run(read_channels(log), hydrokit.load_vehicle(path).thrusters, density=RHO, gravity=G)
    head, data = _read_csv(run.csv)
    assert np.all(data[:, head.index("VRL")] == 0.0)
    assert any("thruster 'VRL': output 10 is 0 µs throughout" in w for w in run.to_dict()["warnings"])


def test_bag_float_depth_and_wrong_types(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    times = write_bag(bag, t_end=1.0, per_thruster=True)
    cmd = "/thrusters/{name}/input"
    ch = read_channels(bag, topics={"depth": "/thrusters/FR/input", "command": cmd})
    assert np.allclose(ch.motion["z"].y, commands(times["cmd"] - 1.7e9)[:, 0], atol=1e-6)  # data as depth, m
    with pytest.raises(
        InputError, match=r"--imu-topic /pressure: a sensor_msgs/msg/FluidPressure, expected sensor_msgs/msg/Imu"
    ):
        read_channels(bag, topics={"imu": "/pressure", "command": cmd})
    with pytest.raises(InputError, match=r"--command-topic '/nope' is not in the bag"):
        read_channels(bag, topics={"command": "/nope"})
    with pytest.raises(InputError, match=r"--command-topic /imu: a sensor_msgs/msg/Imu, expected std_msgs"):
        read_channels(bag, topics={"command": "/imu"})


def test_bag_without_attitude(tmp_path: Path) -> None:
    pytest.importorskip("rosbags")
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.LATEST)
    bag = tmp_path / "b"
    with Writer(bag, version=9) as w:
        w.add_connection("/imu", "sensor_msgs/msg/Imu", typestore=ts)  # declared, never published
        c = w.add_connection("/x", "std_msgs/msg/Float64", typestore=ts)
        for k in range(3):
            w.write(c, k * 10**8, ts.serialize_cdr(ts.types["std_msgs/msg/Float64"](data=1.0), "std_msgs/msg/Float64"))
    with pytest.raises(InputError, match=r"topic '/imu' has no messages"):
        read_channels(bag, topics={"command": "/x"})
    bare = tmp_path / "bare"
    with Writer(bare, version=9) as w:
        c = w.add_connection("/x", "std_msgs/msg/Float64", typestore=ts)
        w.write(c, 0, ts.serialize_cdr(ts.types["std_msgs/msg/Float64"](data=1.0), "std_msgs/msg/Float64"))
    with pytest.raises(
        InputError, match=r"no attitude: give --imu-topic \(a sensor_msgs/Imu topic; topics: /x \(Float64\)\)"
    ):
        read_channels(bare, topics={"command": "/x"})
