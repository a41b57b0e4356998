"""Ingest benchmark: samples/s read from a rosbag2 (sqlite3 and mcap, sensor_msgs/msg/Imu →
roll), a MAVLink tlog (ATTITUDE.roll) and a CSV, each written on the fly with the format's own
library (``hydrokit[ros]``, ``hydrokit[ardupilot]``), of ``--split`` on a long recording, and
frames/s of video marker tracking at 640×480 (MJPG .avi rendered with ``hydrokit[video]``;
issue #12 acceptance: ≥ 200 frames/s on 2 cores).

    .venv/bin/python bench/ingest.py [SAMPLES [FRAMES]]   (default 50 000 and 1 200)
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


def _video(path: Path, frames: int, fps: float = 30.0) -> None:
    """A 640×480 MJPG video of a dark 9 px disc swinging 383 px below a pivot, blurred and noisy."""
    import cv2

    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, (640, 480))
    noise = np.empty((480, 640), np.float32)
    for k in range(frames):
        th = math.radians(20.0) * math.exp(-0.1 * k / fps) * math.cos(5.6 * k / fps)
        img = np.full((480, 640), 165.0, np.float32)
        cv2.circle(img, (round(318 + 383 * math.sin(th)), round(37 + 383 * math.cos(th))), 9, 55.0, -1, cv2.LINE_AA)
        cv2.randn(noise, 0.0, 3.0)
        frame = np.clip(cv2.GaussianBlur(img, (0, 0), 1.2) + noise, 0, 255).astype(np.uint8)
        writer.write(cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR))
    writer.release()


def _rate(n: int, fn) -> float:  # noqa: ANN001
    t0 = time.perf_counter()
    fn()
    return n / (time.perf_counter() - t0)


def main(n: int = 50_000, frames: int = 1200) -> None:
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
        try:
            _video(tmp / "swing.avi", frames)
            r = _rate(frames, lambda: read_recording(tmp / "swing.avi", rig))
            print(f"video         {r:>12,.0f} frames/s (640×480 MJPG, dark marker; acceptance ≥ 200)")
        except ImportError:
            print("video         skipped: pip install 'hydrokit[video]'")
    print(f"--split       {_rate(n, lambda: split_launches(t, y)):>12,.0f} samples/s")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
