"""Ingest benchmark: samples/s read from a rosbag2 (sqlite3 and mcap, sensor_msgs/msg/Imu →
roll), a MAVLink tlog (ATTITUDE.roll) and a CSV, each written on the fly with the format's own
library (``hydrokit[ros]``, ``hydrokit[ardupilot]``), and of ``--split`` on a long recording.

    .venv/bin/python bench/ingest.py [SAMPLES]   (default 50 000)
"""

from __future__ import annotations

import math
import struct
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

RIG = Path(__file__).resolve().parents[1] / "src" / "hydrokit" / "data" / "campaigns" / "udrobot" / "pendulum_x.yaml"


def _signal(n: int) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(n) * 0.01
    return t, math.radians(10.0) * np.exp(-0.05 * t) * np.cos(2.5 * t)


def _bag(path: Path, t: np.ndarray, roll: np.ndarray, mcap: bool) -> None:
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.LATEST)
    T = ts.types
    v, cov = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0), np.zeros(9)
    plugin = StoragePlugin.MCAP if mcap else StoragePlugin.SQLITE3
    with Writer(path, version=9, storage_plugin=plugin) as w:
        c = w.add_connection("/imu", "sensor_msgs/msg/Imu", typestore=ts)
        for tk, r in zip(t, roll):
            hdr = T["std_msgs/msg/Header"](
                stamp=T["builtin_interfaces/msg/Time"](sec=int(tk), nanosec=int(tk % 1 * 1e9)), frame_id=""
            )
            q = T["geometry_msgs/msg/Quaternion"](x=math.sin(r / 2), y=0.0, z=0.0, w=math.cos(r / 2))
            msg = T["sensor_msgs/msg/Imu"](hdr, q, cov, v, cov, v, cov)
            w.write(c, int(tk * 1e9) + 1, ts.serialize_cdr(msg, "sensor_msgs/msg/Imu"))


def _tlog(path: Path, t: np.ndarray, roll: np.ndarray) -> None:
    from pymavlink import mavutil

    path.touch()
    conn = mavutil.mavlink_connection(str(path), write=True)
    for tk, r in zip(t, roll):
        conn.write(struct.pack(">Q", int((1.7e9 + tk) * 1e6)))
        conn.mav.attitude_send(int(1000 * tk), float(r), 0.0, 0.0, 0.0, 0.0, 0.0)
    conn.close()


def _rate(n: int, fn) -> float:  # noqa: ANN001
    t0 = time.perf_counter()
    fn()
    return n / (time.perf_counter() - t0)


def main(n: int = 50_000) -> None:
    import hydrokit
    from hydrokit.identify.split import split_launches
    from hydrokit.io.ingest import read_recording

    rig = hydrokit.load_rig(RIG)
    t, y = _signal(n)
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        csv = tmp / "r.csv"
        csv.write_text("t,angle\n" + "\n".join(f"{a:.2f},{b:.7f}" for a, b in zip(t, y)) + "\n")
        print(f"CSV           {_rate(n, lambda: read_recording(csv, rig)):>12,.0f} samples/s")
        for name, mcap in (("rosbag2 sqlite3", False), ("rosbag2 mcap", True)):
            try:
                _bag(tmp / name.replace(" ", "_"), t, y, mcap)
            except ImportError:
                print(f"{name:<15} skipped: pip install 'hydrokit[ros]'")
                continue
            bag = tmp / name.replace(" ", "_")
            r = _rate(n, lambda bag=bag: read_recording(bag, rig, topic="/imu", signal="roll"))
            print(f"{name:<15} {r:>10,.0f} samples/s (Imu → roll)")
        try:
            _tlog(tmp / "r.tlog", t, y)
            r = _rate(n, lambda: read_recording(tmp / "r.tlog", rig, signal="ATTITUDE.roll"))
            print(f"tlog          {r:>12,.0f} samples/s (ATTITUDE.roll)")
        except ImportError:
            print("tlog          skipped: pip install 'hydrokit[ardupilot]'")
    print(f"--split       {_rate(n, lambda: split_launches(t, y)):>12,.0f} samples/s")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 50_000)
