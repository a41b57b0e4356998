"""Closed-loop benchmark: the bundled Lingyun mission flown with PID and with S-plane control.

Prints both controllers' tracking metrics side by side (LI2021 claims S-plane tracks a
pre-planned 3-D path better than PID; this reports what hydrokit measures) and the
closed-loop simulation speed (steps/s with guidance, autopilot, allocation, thruster curves
and rotor lag in the loop).

    .venv/bin/python bench/closed_loop.py [MISSION ...]   (default: both bundled missions)
"""

from __future__ import annotations

import math
import sys
import time


def closed_loop_speed(mission_name: str = "lingyun_path", kind: str = "pid", seconds: float = 60.0) -> float:
    """Steps per second of the closed loop (controller + allocation + thrusters + vehicle)."""
    from hydrokit import fly, load_mission, load_vehicle

    mis = load_mission(mission_name)
    vehicle = load_vehicle(mis.vehicle)
    fly(mis, kind, vehicle=vehicle, duration=1.0)  # warm-up: imports and any compilation
    t0 = time.perf_counter()
    fly(mis, kind, vehicle=vehicle, duration=seconds)
    elapsed = time.perf_counter() - t0
    return (seconds / mis.dt) / elapsed


def main(mission_name: str = "lingyun_path") -> None:
    from hydrokit import fly, load_mission, load_vehicle

    mis = load_mission(mission_name)
    vehicle = load_vehicle(mis.vehicle)
    runs = {}
    for kind in ("pid", "s-plane"):
        t0 = time.perf_counter()
        run = fly(mis, kind, vehicle=vehicle)
        elapsed = time.perf_counter() - t0
        runs[kind] = (run.metrics, elapsed)
    rows = [
        ("cross-track RMS [m]", "cross_track_rms", 1.0),
        ("cross-track max [m]", "cross_track_max", 1.0),
        ("depth error RMS [m]", "depth_error_rms", 1.0),
        ("heading error RMS [deg]", "heading_error_rms", 180 / math.pi),
        ("thrust impulse [N s]", "thrust_impulse", 1.0),
        ("thruster energy [J]", "thruster_energy", 1.0),
        ("saturation time [s]", "saturation_time", 1.0),
    ]
    print(f"mission {mis.name} ({mis.source}), dt = {mis.dt} s, duration {mis.duration} s")
    print(f"{'metric':28s}{'PID':>14s}{'S-plane':>14s}")
    for title, key, scale in rows:
        vals = [runs[k][0][key] for k in ("pid", "s-plane")]
        cells = ["–" if v is None else f"{v * scale:.4g}" for v in vals]
        print(f"{title:28s}{cells[0]:>14s}{cells[1]:>14s}")
    n_wp = len(runs["pid"][0]["waypoint_times"])
    for i in range(n_wp):
        cells = []
        for k in ("pid", "s-plane"):
            t = runs[k][0]["waypoint_times"][i]
            cells.append("–" if t is None else f"{t:.1f}")
        print(f"{'time to waypoint ' + str(i + 1) + ' [s]':28s}{cells[0]:>14s}{cells[1]:>14s}")
    steps = mis.duration / mis.dt
    for k in ("pid", "s-plane"):
        print(f"{k}: {steps:.0f} steps in {runs[k][1]:.2f} s = {steps / runs[k][1]:.0f} steps/s (closed loop)")
    better = min(("pid", "s-plane"), key=lambda k: runs[k][0]["cross_track_rms"])
    print(f"lower cross-track RMS: {'PID' if better == 'pid' else 'S-plane'}")


if __name__ == "__main__":
    for name in sys.argv[1:] or ["lingyun_path", "minerva_square"]:
        main(name)
        print()
