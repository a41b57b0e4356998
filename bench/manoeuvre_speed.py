"""Speed of the manoeuvre loop (issue #50 item 2): steps/s and a Mariner spiral's wall time.

1. Steps/s of the compiled manoeuvre loop (:mod:`hydrokit.manoeuvre.compiled`: logic,
   depth hold, servo and RK4 compiled) on ``remus100`` and ``remus100-fins``: a straight approach
   of half the time, then a turning circle at 15° with the stern planes holding depth, dt =
   0.02 s; beside it the open-loop RK4 of the same right-hand side (``compiled.rk4_run``, no
   logic at all: the ceiling the loop can reach) and the Python loop (the same laws called as
   Python around the compiled right-hand side, ``run_manoeuvre(compiled_loop=False)``).
2. The planar ship ``mariner``'s direct spiral (15 kn, dt = 0.1 s, the default budget: every step
   until steady), wall time of ``run_manoeuvre`` — the first call in the process (numba's cache
   loaded) and the next one; ``--python`` flies it in the Python loop too (about two minutes).
3. Steps/s of a REMUS 100 turning circle flown on its propeller (``--command propeller=11.567``,
   the rotor lag and K_T(J) at the advance speed: ``ThrusterDrive``), compiled loop (since issue
   #50's thruster laws) against the Python loop it flew in before.

    .venv/bin/python bench/manoeuvre_speed.py [--python] [--seconds S] [--command-only]

Prints the date and the commit; docs/validation/manoeuvre.md records its output.
"""

from __future__ import annotations

import datetime
import math
import subprocess
import sys
import time
from typing import Any

APPROACH = (1.5, 0, 0, 0, 0, 0)
PROPULSION = (3.86, 0.0, 0.0, -0.543, 0.0, 0.0)  # Prestero (2001): N, N·m
COMMAND = {"propeller": 11.567}  # rev/s: the bundled REMUS 100's propeller at 694 rpm
ROLL_TORQUE = (0.0, 0.0, 0.0, -0.543, 0.0, 0.0)  # the propeller's torque K, N·m (Prestero 2001)
MARINER = {"tau": (727_000.0, 0, 0, 0, 0, 0), "nu0": (7.7, 0, 0, 0, 0, 0), "dt": 0.1}


def _commit() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _turn(v: Any, seconds: float, dt: float, compiled: bool) -> tuple[int, float]:
    """(steps, wall s) of an approach of seconds/2 and a 15° turn of seconds/2."""
    import numpy as np

    from hydrokit.manoeuvre.compiled import Engine
    from hydrokit.manoeuvre.run import fly_manoeuvre, holding_surfaces, turning_circle
    from hydrokit.simulate.compiled import make_dynamics

    s = v.surfaces
    f = make_dynamics(v)
    hold = holding_surfaces(f, v.dofs, len(s), "turning_circle", 0)
    x0 = np.zeros(12)
    x0[6:] = APPROACH
    kw = {"tau": PROPULSION, "x0": x0, "dt": dt, "length": v.reference_length, "hold": hold}
    servo = (s.max_deflection, s.rate_limit, s.time_constant)
    m = turning_circle(math.radians(15))
    engine = (lambda: Engine(v, PROPULSION)) if compiled else (lambda: None)
    fly_manoeuvre(f, m, 0, servo, approach=0.5, duration=0.5, engine=engine(), **kw)  # warm-up
    t0 = time.perf_counter()
    t, *_ = fly_manoeuvre(
        f, m, 0, servo, approach=seconds / 2, duration=seconds / 2, keep_approach=seconds, engine=engine(), **kw
    )
    return t.size - 1, time.perf_counter() - t0


def _open_loop(v: Any, n: int, dt: float) -> float:
    """Steps/s of ``compiled.rk4_run`` on the same vehicle with a constant force (no logic)."""
    import numpy as np

    from hydrokit.model.dynamics import current_table, pack
    from hydrokit.simulate.compiled import no_drive, rk4_run

    p = pack(v)
    tau = np.zeros((1, 7 + v.n_inputs))
    tau[0, 1:7] = PROPULSION
    x0 = np.zeros(12)
    x0[6:] = APPROACH
    out = np.empty((2, 12))
    args = (p.V, no_drive(), out)
    rk4_run(x0, 0.0, dt, 10, 10, False, tau, current_table(None), *args)
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        rk4_run(x0, 0.0, dt, n, n, False, tau, current_table(None), *args)
        best = min(best, time.perf_counter() - t0)
    return n / best


def loop_speed(seconds: float = 2000.0, python_seconds: float = 20.0, dt: float = 0.02) -> dict[str, float]:
    """Steps/s of the compiled and the Python manoeuvre loop and of the open-loop RK4."""
    from hydrokit.io.vehicle import load_vehicle

    out: dict[str, float] = {}
    print(f"== manoeuvre loop: approach, then a turning circle at 15°, stern planes holding depth, dt = {dt} s ==")
    for name in ("remus100", "remus100-fins"):
        v = load_vehicle(name)
        best = 0.0
        for _ in range(3):  # best of three: the machine is shared
            steps, wall = _turn(v, seconds, dt, True)
            best = max(best, steps / wall)
        out[f"{name} compiled"] = best
        print(f"{name:14s} compiled loop  {steps:8d} steps: {best:11,.0f} steps/s (best of 3)")
        ceiling = _open_loop(v, steps, dt)
        out[f"{name} open-loop rk4"] = ceiling
        print(f"{name:14s} open-loop RK4  {steps:8d} steps: {ceiling:11,.0f} steps/s (the right-hand side alone)")
        steps, wall = _turn(v, python_seconds, dt, False)
        out[f"{name} python"] = steps / wall
        print(f"{name:14s} python loop    {steps:8d} steps: {steps / wall:11,.0f} steps/s")
    return out


def _command_turn(v: Any, seconds: float, dt: float, compiled: bool) -> tuple[int, float]:
    """(steps, wall s) of an approach of seconds/2 and a 15° turn of seconds/2 on the propeller."""
    import numpy as np

    from hydrokit.manoeuvre.compiled import Engine
    from hydrokit.manoeuvre.run import (
        ThrusterDrive,
        fly_manoeuvre,
        holding_surfaces,
        thruster_commands,
        turning_circle,
    )
    from hydrokit.simulate.compiled import make_dynamics

    s = v.surfaces
    f = make_dynamics(v)
    hold = holding_surfaces(f, v.dofs, len(s), "turning_circle", 0)
    x0 = np.zeros(12)
    x0[6:] = APPROACH
    servo = (s.max_deflection, s.rate_limit, s.time_constant)
    m = turning_circle(math.radians(15))
    command = thruster_commands(v, COMMAND)

    def run(approach: float, duration: float, keep: float) -> int:
        drive = ThrusterDrive(v.thrusters, command, ROLL_TORQUE)
        engine = Engine(v, ROLL_TORQUE, drive=drive) if compiled else None
        t, *_ = fly_manoeuvre(
            f, m, 0, servo, tau=drive, x0=x0, dt=dt, length=v.reference_length, hold=hold,
            approach=approach, duration=duration, keep_approach=keep, engine=engine,
        )  # fmt: skip
        return int(t.size - 1)

    run(0.5, 0.5, 10.0)  # warm-up
    t0 = time.perf_counter()
    steps = run(seconds / 2, seconds / 2, seconds)
    return steps, time.perf_counter() - t0


def command_speed(seconds: float = 2000.0, python_seconds: float = 20.0, dt: float = 0.02) -> dict[str, float]:
    """Steps/s of the manoeuvre loop flying thruster commands: compiled and Python."""
    from hydrokit.api import load_vehicle  # the bundled vehicle with its thrusters

    out: dict[str, float] = {}
    print(f"== --command propeller=11.567: approach, then a turning circle at 15°, depth held, dt = {dt} s ==")
    v = load_vehicle("remus100")
    best = 0.0
    for _ in range(3):  # best of three: the machine is shared
        steps, wall = _command_turn(v, seconds, dt, True)
        best = max(best, steps / wall)
    out["remus100 --command compiled"] = best
    print(f"{'remus100':14s} compiled loop  {steps:8d} steps: {best:11,.0f} steps/s (best of 3)")
    steps, wall = _command_turn(v, python_seconds, dt, False)
    out["remus100 --command python"] = steps / wall
    print(f"{'remus100':14s} python loop    {steps:8d} steps: {steps / wall:11,.0f} steps/s (before: every --command)")
    return out


def mariner_spiral(python: bool = False) -> dict[str, float]:
    """Wall time (s) of the Mariner's direct spiral: first call, second call, and the Python loop."""
    from hydrokit.io.vehicle import load_vehicle
    from hydrokit.manoeuvre.run import run_manoeuvre, spiral

    v = load_vehicle("mariner")
    out: dict[str, float] = {}
    print("\n== mariner direct spiral, 15 kn, dt = 0.1 s, default budget ==")
    runs = [("compiled, first call (numba cache loaded)", True), ("compiled, second call", True)]
    if python:
        runs.append(("python loop", False))
    for label, compiled in runs:
        t0 = time.perf_counter()
        r = run_manoeuvre(v, spiral("direct"), compiled_loop=compiled, **MARINER)
        wall = time.perf_counter() - t0
        n = r.time.size
        out[label] = wall
        settled = sum(bool(p.get("settled")) for p in r.metrics.get("points", []))
        print(f"{label:42s} {wall:7.2f} s, {n} steps ({n / wall:,.0f} steps/s), {settled} steps settled")
    return out


def main(argv: list[str]) -> None:
    seconds = float(argv[argv.index("--seconds") + 1]) if "--seconds" in argv else 2000.0
    print(f"bench/manoeuvre_speed.py, {datetime.date.today().isoformat()}, commit {_commit()}\n")
    t0 = time.perf_counter()
    if "--command-only" in argv:
        command_speed(seconds)
        print(f"\nbench/manoeuvre_speed.py done in {time.perf_counter() - t0:.1f} s")
        return
    mariner_spiral("--python" in argv)  # first: its first call loads numba's cache
    print()
    loop_speed(seconds)
    print()
    command_speed(seconds)
    print(f"\nbench/manoeuvre_speed.py done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
