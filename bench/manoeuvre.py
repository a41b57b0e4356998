"""Manoeuvre benchmark: the bundled REMUS-100-like AUVs' turning circles and zigzags beside the
peers' REMUS 100 models, and the speed of the manoeuvre loop.

1. ``remus100`` (Prestero 2001 derivative terms with delta() factors) and ``remus100-fins``
   (physical fins, hull lift and cross-flow; skipped with its error when it does not load):
   turning circles at 5°, 10° and 15° (the files' fin limit) and zigzags 10°/10° and 15°/15°,
   at Prestero's steady propulsion (3.86 N thrust, −0.543 N·m propeller torque: about 1.5 m/s),
   with the stern planes holding depth and pitch (the default) — and one turn without the hold.
2. The facts of PythonVehicleSimulator's and MSS's REMUS 100 (read from their source files;
   no code copied): they are printed beside ours, with what differs in the model.
3. The planar surface ship ``mariner``'s IMO trials (turning circle at 35°, zigzags 10°/10° and
   20°/20°) with the IMO MSC.137(76) criteria.
4. Speed: calls/s of the compiled right-hand side with delta() terms, with physical fins and
   with no surfaces at all; the manoeuvre loop's steps/s, compiled vs python; and today's
   thruster-only compiled closed loop (bench/closed_loop.py's figure) for reference.

    .venv/bin/python bench/manoeuvre.py [--no-speed] [--no-manoeuvres]
"""

from __future__ import annotations

import math
import sys
import time
from typing import Any

PROPULSION = (3.86, 0.0, 0.0, -0.543, 0.0, 0.0)  # Prestero (2001): N, N·m
APPROACH = (1.5, 0, 0, 0, 0, 0)

#: the peers' REMUS 100 models, as their source files state them (no code copied)
PEERS = [
    (
        "PythonVehicleSimulator remus100.py (cybergalactic/PythonVehicleSimulator, "
        "src/python_vehicle_simulator/vehicles/remus100.py)",
        [
            "L 1.6 m, D 0.19 m, mass 31.9 kg (a spheroid's), B = W (neutral)",
            "fin limit 30°, first-order fin servo T = 1 s",
            "rudder: one fin, area 0.10 × 0.05 = 0.005 m², C_Lδ 0.5, at x = −L/2; stern planes 2 × 0.005 m², C_Lδ 0.7",
            "lift from δ alone (no inflow angle from the vehicle's own motion), no stall",
            "Munk moments in pitch and yaw set to zero (C_A entries zeroed)",
            "cross-flow drag by strips, hull lift/drag from the angle of attack (Fossen 2021 §8.4.2)",
            "no published turning-circle or zigzag figures for it were found",
        ],
    ),
    (
        "MSS remus100.m (cybergalactic/MSS, VESSELS/remus100.m)",
        [
            "L 1.6 m, D 0.19 m, mass 31.9 kg, B = W (neutral); max speed 2.5 m/s at 1525 rpm",
            "fin limit 20° (no servo in the model)",
            "rudder area 2 × S_fin = 2 × 0.00665 = 0.0133 m² (Prestero's fin), C_Lδr 0.5, C_Lδs 0.7, at x = −L/2",
            "Munk moments in pitch and yaw set to zero ('can destabilize the model')",
            "propeller roll moment scaled by 1/10 'to match experimental results'",
            "MSS ExZigZag includes the REMUS 100 (revision 16 Nov 2023); no published numbers for it were found",
        ],
    ),
]


def _fmt(v: Any) -> str:
    if v is None:
        return "–"
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def _load(name: str) -> Any:
    from hydrokit.errors import InputError
    from hydrokit.io.vehicle import load_vehicle

    try:
        return load_vehicle(name)
    except InputError as e:
        print(f"{name}: not loadable here ({e})")
        return None


def manoeuvres(names: tuple[str, ...] = ("remus100", "remus100-fins")) -> dict[str, Any]:
    """Fly and print the turning circles and zigzags of the bundled REMUS-like vehicles."""
    from hydrokit.simulate.manoeuvre import run_manoeuvre, turning_circle, zigzag

    out: dict[str, Any] = {}
    rad = math.radians
    for name in names:
        v = _load(name)
        if v is None:
            continue
        L = v.reference_length
        print(f"\n== {name}: L = {L} m, propulsion {PROPULSION} (N, N·m), approach from u = 1.5 m/s ==")
        print(
            f"{'turn':>10s} {'hold':>5s} {'U0 m/s':>7s} {'advance':>8s} {'transfer':>8s} {'tactical':>8s} "
            f"{'D_steady':>8s} {'D/L':>5s} {'U/U0':>5s} {'drift°':>6s} {'t90 s':>6s} {'dz max m':>8s} {'turns':>5s}"
        )
        for deg, hold in ((5.0, None), (10.0, None), (15.0, None), (15.0, False)):
            r = run_manoeuvre(v, turning_circle(rad(deg)), tau=PROPULSION, nu0=APPROACH, hold=hold, duration=600)
            m = r.metrics
            d = m["steady_turning_diameter"]
            print(
                f"{deg:9.0f}° {'on' if r.hold else 'off':>5s} {r.approach_speed:7.3f} {_fmt(m['advance']):>8s} "
                f"{_fmt(m['transfer']):>8s} {_fmt(m['tactical_diameter']):>8s} {_fmt(d):>8s} "
                f"{_fmt(d / L if d else None):>5s} {_fmt(m['speed_ratio']):>5s} {_fmt(m['drift_angle_deg']):>6s} "
                f"{_fmt(m['time_to_90_deg']):>6s} {_fmt(m.get('max_depth_change')):>8s} "
                f"{m['heading_change_deg'] / 360:5.1f}"
            )
            for w in r.warnings:
                print(f"{'':17s}warning: {w}")
            if r.problem:
                print(f"{'':17s}problem: {r.problem}")
            out[f"{name} turn {deg:g} hold={bool(r.hold)}"] = m
        print(
            f"{'zigzag':>10s} {'1st os°':>8s} {'2nd os°':>8s} {'t_a s':>6s} {'t_check s':>9s} {'period s':>8s} "
            f"{'dz max m':>8s}"
        )
        for a in (10.0, 15.0):
            r = run_manoeuvre(v, zigzag(rad(a), rad(a)), tau=PROPULSION, nu0=APPROACH, duration=300)
            m = r.metrics
            print(
                f"{a:6.0f}/{a:<3.0f} {_fmt(m['first_overshoot_deg']):>8s} {_fmt(m['second_overshoot_deg']):>8s} "
                f"{_fmt(m['initial_turning_time']):>6s} {_fmt(m['time_to_check_yaw']):>9s} {_fmt(m['period']):>8s} "
                f"{_fmt(m.get('max_depth_change')):>8s}"
            )
            if r.problem:
                print(f"{'':11s}problem: {r.problem}")
            out[f"{name} zigzag {a:g}"] = m
    print("\n== the peers' REMUS 100 (facts from their source files) ==")
    for title, facts in PEERS:
        print(title)
        for fact in facts:
            print(f"  - {fact}")
    return out


def ship(name: str = "mariner", force: float = 727_000.0, speed: float = 7.7) -> dict[str, Any]:
    """The planar surface ship's IMO MSC.137(76) trials: turning circle at 35°, zigzags 10°/10°
    and 20°/20°, each with its criteria (``--force 727000,0,0,0,0,0`` holds 15 kn)."""
    from hydrokit.simulate.manoeuvre import run_manoeuvre, turning_circle, zigzag

    v = _load(name)
    out: dict[str, Any] = {}
    if v is None:
        return out
    rad = math.radians
    print(f"\n== {name}: planar {v.dofs}, L = {v.reference_length} m, force {force:g} N, from {speed} m/s ==")
    for m in (turning_circle(rad(35)), zigzag(rad(10), rad(10)), zigzag(rad(20), rad(20))):
        r = run_manoeuvre(v, m, tau=(force, 0, 0, 0, 0, 0), nu0=(speed, 0, 0, 0, 0, 0), dt=0.1, duration=3000)
        shown = {k: x for k, x in r.metrics.items() if isinstance(x, float) and k != "approach_speed"}
        label = m.kind + (
            ""
            if m.kind == "turning_circle"
            else f" {math.degrees(m.deflection or 0):g}/{math.degrees(m.check_angle):g}"
        )
        print(f"{label}: " + ", ".join(f"{k} {_fmt(x)}" for k, x in shown.items()))
        for c in r.imo():
            verdict = "–" if c["passed"] is None else "pass" if c["passed"] else "FAIL"
            note = f" ({c['note']})" if c["note"] else ""
            print(f"   IMO {c['criterion']}: {_fmt(c['value'])} {c['unit']} vs {_fmt(c['limit'])}: {verdict}{note}")
        out[label] = r.metrics
    return out


def _no_surfaces(name: str) -> Any:
    """The bundled vehicle ``name`` without its control surfaces and delta() terms."""
    from hydrokit.io.vehicle import parse_vehicle, resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml

    data = dict(read_yaml(resolve_vehicle(name)))
    data.pop("control_surfaces", None)
    data["terms"] = {k: c for k, c in (data.get("terms") or {}).items() if "delta(" not in k}
    return parse_vehicle(data, f"{name} without surfaces")


def rhs_speed(n: int = 200_000) -> dict[str, float]:
    """Calls/s of the compiled right-hand side ``make_dynamics(vehicle)(t, x, τ, δ)``."""
    import numpy as np

    from hydrokit.simulate.compiled import make_dynamics

    cases = [("remus100 (delta() terms)", _load("remus100"))]
    fins = _load("remus100-fins")
    if fins is not None:
        cases.append(("remus100-fins (physical fins)", fins))
    try:
        cases.append(("remus100 without surfaces", _no_surfaces("remus100")))
    except Exception as e:  # noqa: BLE001 - a bench reports and goes on
        print(f"remus100 without surfaces: {e}")
    out: dict[str, float] = {}
    print("\n== compiled right-hand side, one call per (t, x, τ, δ) from Python ==")
    for label, v in cases:
        if v is None:
            continue
        f = make_dynamics(v)
        x = np.zeros(12)
        x[6] = 1.5
        tau = np.array(PROPULSION)
        d = np.full(len(v.surfaces), 0.1)
        f(0.0, x, tau, d)  # warm-up (cache load / compile)
        best = math.inf
        for _ in range(3):  # best of three: the machine is shared
            t0 = time.perf_counter()
            for _ in range(n):
                f(0.0, x, tau, d)
            best = min(best, time.perf_counter() - t0)
        rate = n / best
        out[label] = rate
        print(f"{label:32s} {rate:12,.0f} calls/s ({1e6 / rate:.2f} µs/call)")
    return out


def loop_speed(seconds: float = 120.0, python_seconds: float = 20.0, dt: float = 0.02) -> dict[str, float]:
    """Steps/s of the manoeuvre loop (RK4 in Python around the right-hand side, the servo law and
    the depth hold): a straight approach of half the time, then a 15° turn."""
    import numpy as np

    from hydrokit.model.dynamics import vehicle_dynamics
    from hydrokit.simulate.compiled import make_dynamics
    from hydrokit.simulate.manoeuvre import fly_manoeuvre, holding_surfaces, turning_circle

    out: dict[str, float] = {}
    print(f"\n== manoeuvre loop (approach, then a turning circle at 15°; stern planes holding depth), dt = {dt} s ==")
    for name in ("remus100", "remus100-fins"):
        v = _load(name)
        if v is None:
            continue
        s = v.surfaces
        servo = (s.max_deflection, s.rate_limit, s.time_constant)
        for loop, sim in (("compiled", seconds), ("python", python_seconds)):
            f = make_dynamics(v) if loop == "compiled" else vehicle_dynamics(v)
            hold = holding_surfaces(f, v.dofs, len(s), "turning_circle", 0)
            x0 = np.zeros(12)
            x0[6:] = APPROACH
            kw = {"tau": PROPULSION, "x0": x0, "dt": dt, "length": v.reference_length, "hold": hold}
            fly_manoeuvre(f, turning_circle(math.radians(15)), 0, servo, approach=0.5, duration=0.5, **kw)
            t0 = time.perf_counter()
            t, *_ = fly_manoeuvre(
                f,
                turning_circle(math.radians(15)),
                0,
                servo,
                approach=sim / 2,
                duration=sim / 2,
                keep_approach=sim,
                **kw,
            )
            el = time.perf_counter() - t0
            steps = t.size - 1
            out[f"{name} {loop}"] = steps / el
            print(f"{name:14s} {loop:9s} {steps:8d} steps in {el:6.2f} s = {steps / el:9,.0f} steps/s")
    try:
        sys.path.insert(0, "bench")
        from closed_loop import closed_loop_speed

        rate = closed_loop_speed("lingyun_path", "pid", 60.0, "compiled")
        out["thruster-only closed loop"] = rate
        print(
            f"today's thruster-only compiled closed loop (bench/closed_loop.py, lingyun_path, PID): {rate:,.0f} steps/s"
        )
    except Exception as e:  # noqa: BLE001 - a bench reports and goes on
        print(f"thruster-only closed loop: not run ({e})")
    return out


def main(argv: list[str]) -> None:
    t0 = time.perf_counter()
    if "--no-manoeuvres" not in argv:
        manoeuvres()
        ship()
    if "--no-speed" not in argv:
        rhs_speed()
        loop_speed()
    print(f"\nbench/manoeuvre.py done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
