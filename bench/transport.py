"""Transport benchmark (issue #11): speed of the three models, REHMAN's runs, and the closed
loop that goes beyond them.

1. Steps/s of ``rigid`` (compiled RK4 of the composite, joint loads every step),
   ``multibody`` (every part a body, stiff joints, sub-steps) and ``independent``, on the
   bundled ``rehman_transport`` with four vertical and four axial thrusters running. Timed
   calls exclude the first one (numba loads or compiles its kernels then). Target: rigid
   ≥ 200 000 steps/s.
2. REHMAN Fig. 3 (four vertical thrusters at 1000 rpm: rise in 30 s, drift, tilt, vehicle
   distance) with REHMAN's thrust and with the public Minerva thrust; Fig. 4 (axial
   thrusters at 1000 rpm, opposite senses on the two vehicles: rigid motion, independent
   separation), with the joint loads.
3. Beyond REHMAN: the constrained-allocation carry controller takes the payload 20 m along
   the line at 0.3 m/s, without and with an unknown 60 N side force and 40 N·m yaw moment;
   cross-track, final error and the loads the manipulators hold.
4. The damping models of the composite (elements, rehman d·r³, shifted Hᵀ D H) on a turning
   run: how far apart their paths end.

    .venv/bin/python bench/transport.py [--steps N]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import hydrokit as hk
from hydrokit.simulate.transport import carry


def _rpm(kind: str) -> dict[str, float]:
    if kind == "vertical":
        return {f"minerva-{k}.V{j}": 1000.0 for k in (1, 2) for j in (1, 2)}
    return {"minerva-1.A1": 1000.0, "minerva-1.A2": 1000.0, "minerva-2.A1": -1000.0, "minerva-2.A2": -1000.0}


def speed(asm: hk.Assembly, steps: int) -> None:
    rpm = {**_rpm("vertical"), **_rpm("axial")}
    print(f"1. speed ({steps} steps of 0.01 s, loads every step)")
    for model in ("rigid", "multibody", "independent"):
        n = steps if model != "multibody" else max(steps // 20, 1000)
        hk.transport(asm, 0.1, 0.01, model, rpm=rpm)  # load/compile the kernels
        t0 = time.perf_counter()
        r = hk.transport(asm, n * 0.01, 0.01, model, rpm=rpm)
        dt = time.perf_counter() - t0
        extra = f", {r.substeps} sub-steps per step" if model == "multibody" else ""
        print(f"   {model:12s} {n / dt:12,.0f} steps/s ({n} steps in {dt:.2f} s{extra})")


def rehman(asm: hk.Assembly, public: hk.Assembly) -> None:
    print("2. REHMAN Fig. 3: four vertical thrusters at 1000 rpm, 30 s (REHMAN: ~10 m, straight up)")
    for label, a in (("REHMAN thrust (294 N)", asm), ("public Minerva thrust", public)):
        r = hk.transport(a, 30.0, 0.01, "rigid", rpm=_rpm("vertical"), output_every=10)
        drift = np.abs(r.assembly[:, 0:2]).max()
        tilt = np.degrees(np.abs(r.assembly[:, 3:6]).max())
        print(
            f"   {label:24s} rise {-r.assembly[-1, 2]:6.2f} m, horizontal drift {drift:.1e} m, tilt {tilt:.1e} deg, "
            f"thrust per vertical thruster {r.thrust[0, 1]:.1f} N at rest, {r.thrust[-1, 1]:.1f} N climbing"
        )
    m = hk.transport(asm, 30.0, 0.01, "multibody", rpm=_rpm("vertical"), output_every=10)
    d = np.linalg.norm(m.parts["minerva-1"][:, :3] - m.parts["payload"][:, :3], axis=1)
    print(f"   multibody: vehicle-payload distance {d.min():.4f}–{d.max():.4f} m (REHMAN: keeps 1.97 m)")
    print("   REHMAN Fig. 4: axial thrusters at 1000 rpm, vehicle 1 forward, vehicle 2 reverse, 30 s")
    for model in ("rigid", "multibody", "independent"):
        r = hk.transport(asm, 30.0, 0.01, model, rpm=_rpm("axial"), output_every=10)
        s = r.summary()
        disp = np.round(s["displacement_m"], 2).tolist()
        att = np.round(s["end"]["attitude_deg"], 2).tolist()
        sep = max(j["max_separation_m"] for j in s["joints"].values())
        loads = ", ".join(f"{k} {j['max_force_N']:.0f} N/{j['max_moment_Nm']:.0f} N·m" for k, j in s["joints"].items())
        print(f"   {model:12s} moved {disp} m, attitude {att} deg, largest separation {sep:.3g} m")
        print(f"   {'':12s} largest joint loads: {loads}")


def beyond(asm: hk.Assembly) -> None:
    print("3. beyond REHMAN: carry 20 m along the line at 0.3 m/s (constrained allocation, 90 s)")
    for label, forces in (
        ("calm", None),
        ("60 N side force + 40 N·m yaw", {"payload": [60, 0, 0, 0, 0, 0], "minerva-1": [0, 0, 0, 0, 0, 40]}),
    ):
        t0 = time.perf_counter()
        _, f = carry(asm, [0, 20, 0], 90.0, forces=forces)
        dt = time.perf_counter() - t0
        loads = ", ".join(f"{k} {j['max_force_N']:.0f} N/{j['max_moment_Nm']:.0f} N·m" for k, j in f["joints"].items())
        print(
            f"   {label:30s} cross-track RMS {f['cross_track_rms_m']:.3g} m, max {f['cross_track_max_m']:.3g} m, "
            f"final error {f['final_error_m']:.2g} m, heading error max {f['heading_error_max_deg']:.2f} deg, "
            f"saturated {100 * f['saturated_fraction']:.0f} % ({dt:.1f} s)"
        )
        print(f"   {'':30s} loads the manipulators hold: {loads}")


def damping_models() -> None:
    print("4. composite quadratic drag: a turning run (axial pair of vehicle 1 + transverse thrusters), 60 s")
    rpm = {"minerva-1.A1": 1000.0, "minerva-1.TT": 1000.0, "minerva-2.TT": -1000.0}
    ends = {}
    for dm in ("elements", "rehman", "shifted"):
        a = hk.load_assembly("rehman_transport", damping_model=dm)
        r = hk.transport(a, 60.0, 0.01, "rigid", rpm=rpm, output_every=100)
        ends[dm] = r.assembly[-1]
        print(
            f"   {dm:9s} end x, y = {r.assembly[-1, 0]:7.2f}, {r.assembly[-1, 1]:7.2f} m, heading "
            f"{np.degrees(r.assembly[-1, 5]):8.1f} deg, yaw rate {np.degrees(r.assembly[-1, 11]):6.2f} deg/s"
        )
    for dm in ("rehman", "shifted"):
        print(
            f"   {dm} vs elements: end position {np.linalg.norm(ends[dm][:3] - ends['elements'][:3]):.2f} m apart, "
            f"yaw rate ratio {ends[dm][11] / ends['elements'][11]:.3f}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200_000, help="steps timed for rigid and independent (count)")
    args = ap.parse_args()
    asm = hk.load_assembly("rehman_transport")
    public = hk.load_assembly("rehman_transport_public")
    speed(asm, args.steps)
    rehman(asm, public)
    beyond(asm)
    damping_models()


if __name__ == "__main__":
    main()
