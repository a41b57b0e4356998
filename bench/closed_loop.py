"""Closed-loop benchmark: compiled vs Python loop speed, and PID vs S-plane tracking.

First the closed-loop speed (steps/s with guidance, autopilot, allocation, thruster curves
and rotor lag in the loop) of the compiled loop (numba, the default) and of the Python
reference loop, on the same 200 000-step mission (the bundled Lingyun mission flown for
10 000 s at dt = 0.05 s, both controllers). "Whole process minus start-up": the timed call is
the complete ``hydrokit.fly`` (packing, the loop, the metrics); start-up — imports and the
first call, which loads the compiled loop from numba's cache (or compiles it) — is timed
separately and excluded.

Then both controllers' tracking metrics side by side (LI2021 claims S-plane tracks a
pre-planned 3-D path better than PID; this reports what hydrokit measures).

Then fleets (``hydrokit.fly_batch``: N copies in one compiled call, numba prange over the
copies): vehicle-steps/s for N = 1, 100 and 10 000 (the last flown for the first 60 s of the mission),
copies with ±20 % surge and yaw damping. And gain tuning (``hydrokit tune``'s search,
:func:`hydrokit.simulate.tune.tune_gains`, with its defaults): the time, cost and
cross-track RMS before/after for both controllers on the bundled Lingyun mission and the
udrobot project mission, and which controller wins after tuning.

Then a mission steered by control surfaces (issue #45): a REMUS-100-like AUV with physical
fins, hull lift and cross-flow strips, one propeller, rudder on heading and stern plane on
pitch, flying a square — steps/s of both loops (the surface allocation and the fins' forces
in every step), to set beside the thruster-only figure above.

    .venv/bin/python bench/closed_loop.py [--steps N] [--python-steps N] [--no-fleet]
        [--no-tune] [--fins-steps N] [MISSION ...]
        (default: 200 000 steps for both loops; both bundled missions for the metrics)
"""

from __future__ import annotations

import math
import time


def closed_loop_speed(
    mission_name: str = "lingyun_path", kind: str = "pid", seconds: float = 60.0, loop: str = "compiled"
) -> float:
    """Steps per second of the closed loop (controller + allocation + thrusters + vehicle)."""
    from hydrokit import fly, load_mission, load_vehicle

    mis = load_mission(mission_name)
    vehicle = load_vehicle(mis.vehicle)
    fly(mis, kind, vehicle=vehicle, duration=1.0, loop=loop)  # warm-up: imports and any compilation
    t0 = time.perf_counter()
    fly(mis, kind, vehicle=vehicle, duration=seconds, loop=loop)
    elapsed = time.perf_counter() - t0
    return (seconds / mis.dt) / elapsed


def compiled_vs_python(
    mission_name: str = "lingyun_path", steps: int = 200_000, python_steps: int | None = None
) -> dict[str, dict[str, float]]:
    """Steps/s of both loops on ``steps`` steps of the mission (Python: ``python_steps``,
    default the same), each controller; prints and returns them."""
    t_start = time.perf_counter()
    from hydrokit import fly, load_mission, load_vehicle

    mis = load_mission(mission_name)
    vehicle = load_vehicle(mis.vehicle)
    fly(mis, "pid", vehicle=vehicle, duration=mis.dt, loop="compiled")  # start-up: cache load / compile
    startup = time.perf_counter() - t_start
    print(f"start-up (imports + loading the compiled loop): {startup:.2f} s")
    out: dict[str, dict[str, float]] = {}
    for kind in ("pid", "s-plane"):
        out[kind] = {}
        for loop, n in (("compiled", steps), ("python", python_steps or steps)):
            t0 = time.perf_counter()
            run = fly(mis, kind, vehicle=vehicle, duration=n * mis.dt, loop=loop)
            elapsed = time.perf_counter() - t0
            out[kind][loop] = n / elapsed
            print(
                f"{mis.name} {kind:8s} {loop:9s} {n:7d} steps in {elapsed:7.2f} s = {n / elapsed:10.0f} steps/s"
                f" (saturated {run.metrics['saturation_fraction']:.1%})"
            )
        print(f"{mis.name} {kind:8s} compiled / python = {out[kind]['compiled'] / out[kind]['python']:.0f}x")
    return out


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


FIN = {"area": 0.0133, "aspect_ratio": 2.21, "lift_slope": 3.12, "stall_angle_deg": 15, "max_deflection_deg": 15}
FINNED_AUV = {
    "name": "finned-auv",
    "gravity": 9.81,
    "fluid": {"density": 1030.0},
    "mass": 30.48,
    "volume": 30.48 / 1030.0,
    "inertia": [0.177, 3.45, 3.45],
    "center_of_gravity": [0.0, 0.0, 0.0196],
    "center_of_buoyancy": [0.0, 0.0, 0.0],
    "added_mass": [0.93, 35.5, 35.5, 0.0141, 4.88, 4.88],
    "linear_damping": [0, 0, 0, 0, 0, 0],
    "quadratic_damping": [0, 0, 0, 0, 0, 0],
    "hull": {"profile": "remus100", "origin_from_nose": 0.611, "lift": True},
    "terms": {"X_u|u|": -1.62, "K_p|p|": -0.0013},
    "control_surfaces": [
        {"name": "rudder", "position": [-0.638, 0, 0], "axis": [0, 0, 1], "rate_limit_deg_s": 20, **FIN},
        {"name": "sternplane", "position": [-0.638, 0, 0], "axis": [0, 1, 0], "rate_limit_deg_s": 20, **FIN},
    ],
    "thrusters": [
        {"name": "prop", "position": [-0.7, 0, 0], "direction": [1, 0, 0], "model": "ideal", "max_thrust": 10},
    ],
}
FINNED_MISSION = {
    "name": "fin-square",
    "dt": 0.05,
    "duration": 400,
    "controller": "pid",
    "controllers": {
        "pid": {
            "speed": {"kp": 20, "ki": 2, "kd": 0, "limit": 10},
            "depth": {"kp": 0, "ki": 0, "kd": 0, "limit": 1},
            "heading": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
            "pitch": {"kp": 10, "ki": 0, "kd": 10, "limit": 5},
        }
    },
    "guidance": {
        "acceptance_radius": 3,
        "lookahead": 5,
        "speed": 1.5,
        "waypoints": [[0, 0, 0], [60, 0, 0], [60, 60, 0], [0, 60, 0], [0, 0, 0]],
    },
}


def fins_speed(steps: int = 100_000, python_steps: int = 20_000) -> dict[str, float]:
    """Steps/s of the closed loop steered by fins (compiled and Python) and the square's
    tracking; prints and returns the speeds."""
    import tempfile
    from pathlib import Path

    import yaml

    from hydrokit import fly, load_mission, load_vehicle

    with tempfile.TemporaryDirectory() as tmp:
        vpath = Path(tmp) / "finned-auv.yaml"
        vpath.write_text(yaml.safe_dump(FINNED_AUV))
        mpath = Path(tmp) / "fin-square.yaml"
        mpath.write_text(yaml.safe_dump(dict(FINNED_MISSION, vehicle=str(vpath))))
        mis = load_mission(mpath)
        vehicle = load_vehicle(vpath)
        out = {}
        for loop, n in (("compiled", steps), ("python", python_steps)):
            fly(mis, "pid", vehicle=vehicle, duration=mis.dt, loop=loop)  # start-up excluded
            t0 = time.perf_counter()
            fly(mis, "pid", vehicle=vehicle, duration=n * mis.dt, loop=loop)
            out[loop] = n / (time.perf_counter() - t0)
            print(f"fins, {loop:8s}: {n} steps, {out[loop]:,.0f} steps/s")
        print(f"fins: compiled / Python = {out['compiled'] / out['python']:.0f}×")
        square = fly(mis, "pid", vehicle=vehicle)
        m = square.metrics
        rud = abs(square.run.deflection[:, 0]).max()
        print(
            f"fin square ({mis.duration:.0f} s): completed {m['completed']}, cross-track RMS {m['cross_track_rms']:.2f} m, "
            f"heading error RMS {math.degrees(m['heading_error_rms']):.1f}°, largest rudder {math.degrees(rud):.1f}°"
        )
    return out


def fleet_speed(mission_name: str = "lingyun_path", sizes: tuple[int, ...] = (1, 100, 10_000)) -> dict[int, float]:
    """Vehicle-steps/s of fleets of N copies (damping ±20 %); prints and returns them."""
    import numpy as np

    from hydrokit import fly_batch, load_mission, load_vehicle

    mis = load_mission(mission_name)
    veh = load_vehicle(mis.vehicle)
    fly_batch(mis, veh, n=2, duration=mis.dt)  # start-up: load (or compile) the fleet kernel
    out = {}
    rng = np.random.default_rng(0)
    for n in sizes:
        duration = mis.duration if n <= 100 else 60.0
        var = {
            "linear_damping.surge": veh.D_L[0, 0] * rng.uniform(0.8, 1.2, n),
            "linear_damping.yaw": veh.D_L[5, 5] * rng.uniform(0.8, 1.2, n),
        }
        t0 = time.perf_counter()
        fleet = fly_batch(mis, var, "pid", vehicle=veh, duration=duration)
        total = time.perf_counter() - t0
        out[n] = n * fleet.steps / fleet.elapsed
        print(
            f"fleet N = {n:6d} x {fleet.steps:5d} steps: {out[n]:10.0f} vehicle-steps/s in the compiled call "
            f"({fleet.elapsed:.2f} s; {n * fleet.steps / total:10.0f} with packing, {total:.2f} s)"
        )
    best = max(out.values())
    verdict = "meets" if best >= 1_000_000 else "misses"
    print(f"fleet throughput: best {best:,.0f} vehicle-steps/s on {_cores()} cores ({verdict} the 1 000 000 target)")
    return out


def _cores() -> int:
    import numba

    return int(numba.get_num_threads())


def tuning(missions: tuple[str, ...] = ("lingyun_path", "src/hydrokit/data/projects/udrobot/mission.yaml")) -> None:
    """Tune both controllers of each mission with the CLI defaults; print time, cost and
    cross-track RMS before/after (the full mission flown with the hand-picked and tuned gains)."""
    from hydrokit import fly, load_mission, load_vehicle
    from hydrokit.simulate.tune import tune_gains

    for name in missions:
        mis = load_mission(name)
        veh = load_vehicle(mis.vehicle)
        fly(mis, "pid", vehicle=veh, duration=mis.dt)  # start-up
        rms = {}
        for kind in ("pid", "s-plane"):
            res = tune_gains(mis, veh, kind)
            before = fly(mis, kind, vehicle=veh).metrics["cross_track_rms"]
            after = fly(res.mission, kind, vehicle=veh).metrics["cross_track_rms"]
            rms[kind] = (before, after)
            print(
                f"tune {mis.name} {kind:8s}: {res.elapsed:6.1f} s, {res.evaluations} runs, cost "
                f"{res.cost_before:.4f} -> {res.cost_after:.4f}; cross-track RMS {before:.4f} -> {after:.4f} m"
            )
        for when, i in (("hand-picked", 0), ("tuned", 1)):
            p, s_ = rms["pid"][i], rms["s-plane"][i]
            win = "PID" if p < s_ else "S-plane"
            print(
                f"  {when:11s}: {win} wins, cross-track RMS {min(p, s_):.4f} vs {max(p, s_):.4f} m "
                f"({(max(p, s_) - min(p, s_)) / max(p, s_):.0%} lower)"
            )


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200_000, help="steps of the speed run (compiled)")
    ap.add_argument("--python-steps", type=int, default=None, help="steps for the Python loop (default: --steps)")
    ap.add_argument("--no-fleet", action="store_true", help="skip the fleet speeds")
    ap.add_argument("--no-tune", action="store_true", help="skip the gain tuning")
    ap.add_argument("--fins-steps", type=int, default=100_000, help="steps of the fin-steered speed run (compiled)")
    ap.add_argument("missions", nargs="*", default=["lingyun_path", "minerva_square"])
    args = ap.parse_args()
    compiled_vs_python("lingyun_path", args.steps, args.python_steps)
    print()
    fins_speed(args.fins_steps, max(1, args.fins_steps // 5))
    print()
    for name in args.missions:
        main(name)
        print()
    if not args.no_fleet:
        fleet_speed()
        print()
    if not args.no_tune:
        tuning()
