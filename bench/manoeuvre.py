"""Manoeuvre benchmark: the bundled REMUS 100 models beside the published simulators' REMUS 100,
flown by the same code, and the speed of the manoeuvre loop.

1. Four REMUS 100 models side by side, each on its own propeller at fixed rpm (no propeller roll
   torque, so that roll trim does not colour the comparison), the stern planes holding depth (the
   default): turning circles at 5°, 10°, 15°, 20° and the fin limit, zigzags 10°/10°, 15°/15° and
   20°/20°, a pull-out from ±10°. The models:

   * ``remus100`` — Prestero (2001) derivative model, lift terms from his fin and hull data;
   * ``remus100-fins`` — physical fins, hull lift and cross-flow strips from his profile;
     both on their propeller at 11.567 rev/s (Prestero's 3.86 N at 1.54 m/s);
   * ``pvs`` — PythonVehicleSimulator's ``remus100`` class and ``mss`` — the MSS toolbox's
     ``remus100.m`` (both by T. I. Fossen), rebuilt here as hydrokit vehicle dicts from the numbers
     their source files publish (no code copied; :func:`peer_vehicle` lists each number and what
     had to be approximated to write it as hydrokit terms), on their propeller at 1525 rpm (about
     2.5 m/s). Under their own propulsion and rudder the rebuilds turn as the simulators are
     quoted to: PVS 36.8 m at its 30° limit (quoted ≈ 37 m), MSS 19.1 m at its 20° limit (≈ 20 m)
     once its Reynolds-dependent cross-flow drag is taken at the turn's own cross-flow.

2. The planar surface ship ``mariner``'s IMO trials (turning circle at 35°, zigzags 10°/10° and
   20°/20°) with the IMO MSC.137(76) criteria.
3. Speed: calls/s of the compiled right-hand side with delta() terms, with physical fins and
   with no surfaces at all; the manoeuvre loop's steps/s, compiled vs python; and today's
   thruster-only compiled closed loop (bench/closed_loop.py's figure) for reference.

    .venv/bin/python bench/manoeuvre.py [--no-speed] [--no-manoeuvres] [--no-ship]
"""

from __future__ import annotations

import math
import sys
import time
from typing import Any

PRESTERO_SPEED = math.sqrt(3.86 / 1.62)  # m/s: his 3.86 N against X_u|u| = -1.62 kg/m
APPROACH = (1.5, 0, 0, 0, 0, 0)
PROPULSION = (3.86, 0.0, 0.0, -0.543, 0.0, 0.0)  # Prestero (2001): N, N·m (the speed section)
ANGLES = (5.0, 10.0, 15.0, 20.0)  # deg
ZIGZAGS = (10.0, 15.0, 20.0)  # deg


def _fmt(v: Any) -> str:
    if v is None:
        return "–"
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def _load(name: str) -> Any:
    from hydrokit.api import load_vehicle
    from hydrokit.errors import InputError

    try:
        return load_vehicle(name)
    except InputError as e:
        print(f"{name}: not loadable here ({e})")
        return None


#: the peers' propeller (both files): D 0.14 m, K_T(J) = K_T0 + (K_Tmax − K_T0) J / J_max with
#: K_T0 = 0.4566, K_Tmax = 0.1798 at J_max = 0.6632 (Wageningen B3-71.8), V_a = 0.944 U, t = 0.1,
#: 1525 rpm at most (their step input and autopilot runs use it: about 2.5 m/s)
PEER_RPM = 1525.0
PEER_KT = ((0.1798 - 0.4566) / 0.6632, 0.4566)


#: the circular cylinder's 2-D drag coefficient against Re (DNV-RP-C205's curve, as MSS's
#: cylinderDrag tabulates it; rounded, subcritical plateau to the drag crisis and back), and its
#: finite-length factor κ at L/D = 8.42 (subcritical, Re < 2·10⁵; supercritical)
CYLINDER_CD = (
    (1e4, 1.21), (2.15e5, 1.21), (2.72e5, 1.17), (3.25e5, 1.01), (3.62e5, 0.89), (4.1e5, 0.71),
    (4.75e5, 0.53), (5.25e5, 0.41), (5.79e5, 0.33), (6.38e5, 0.28), (7.44e5, 0.30), (1.07e6, 0.39),
    (1.39e6, 0.47), (1.83e6, 0.54), (2.9e6, 0.63), (4.94e6, 0.68),
)  # fmt: skip
CYLINDER_KAPPA = (0.66, 0.81)


def mss_crossflow_cd(v_cross: float, length: float = 1.6) -> float:
    """MSS's cross-flow C_d of the REMUS hull (its 'cylinder' model): C_d(Re) κ with Re = |v_c| L / 10⁻⁶
    (their Reynolds number: the cross-flow speed √(v² + w²), m/s, and the hull length L, m)."""
    import numpy as np

    re = abs(v_cross) * length * 1e6
    xs, ys = zip(*CYLINDER_CD, strict=True)
    cd = float(np.interp(re, xs, ys))
    return cd * (CYLINDER_KAPPA[0] if re < 2e5 else CYLINDER_KAPPA[1])


def peer_vehicle(kind: str, crossflow_cd: float | None = None) -> tuple[Any, float]:
    """The REMUS 100 of PythonVehicleSimulator (``kind="pvs"``: src/python_vehicle_simulator/
    vehicles/remus100.py) or of the MSS toolbox (``kind="mss"``: CRAFT/AUV/models/remus100.m, the
    revision with the cylinder cross-flow and one water density), as a hydrokit vehicle with their
    propeller as a ``thrusters:`` entry, and its steady speed (m/s) at :data:`PEER_RPM`.

    Their published numbers (both: Fossen 2021 §8.4.2, Allen et al. 2000):

    * a prolate spheroid of L 1.6 m, D 0.19 m in water of 1026 kg/m³: m = 4/3 π ρ a b², I_x = 2/5
      m b², I_y = I_z = 1/5 m (a² + b²) about G; MSS scales a and b by 1.0096 (m = 31.9 kg), PVS
      does not (31.03 kg); r_G = (0, 0, 0.02) m, r_B = 0, B = W;
    * added mass of the spheroid from Lamb's k-factors, roll A_44 = 0.3 I_x;
    * added-mass Coriolis C_A with entries zeroed, each as its file does: PVS (M,u), (M,p), (N,u),
      (N,v); MSS (M,w), (Z,q), (M,u), (X,q), (N,u), (X,r), (N,v), (Y,r). Written here as explicit
      terms (added_mass_coriolis off);
    * linear damping diag(M11/T1, M22/T2, M33/T2, 2ζ4 ω4 M44, 2ζ5 ω5 M55, M66/T6), ω = √(W z_G/M):
      T1 = T2 = 20 s, ζ4 = 0.3, ζ5 = 0.8; PVS T6 = 5 s with D11, D22, D66 scaled by e^{−3U}; MSS
      T6 = 1 s with only D11 scaled. hydrokit's linear damping is constant, so the factor is taken
      at the steady speed of the propeller (a turn that slows would have slightly more);
    * hull drag and lift in the vertical plane (forceLiftDrag): S = 0.7 L D, C_D0 = 0.42 π b² / S,
      C_Lα = π AR / (1 + √(1 + (AR/2)²)), AR = D²/S, Oswald e = 0.7; written as X_u U, Z_w U and
      X_ww terms (small-angle forms of their flow-axis formulas);
    * cross-flow drag (crossFlowDrag), ½ ρ D C_d per metre of strip: PVS 21 strips of width L/20
      from −L/2 to L/2, sway and yaw only, Hoerner's C_d at B/2T = 0.5 (1.198); MSS 20 strips at
      their midpoints in sway and heave, in water of 1025 kg/m³ as that function has it, with the
      C_d of a finite circular cylinder at Re = √(v² + w²) L / 10⁻⁶ (:func:`mss_crossflow_cd`):
      0.80 on a straight course, 0.3–0.5 in a turn at 2.5 m/s (past the drag crisis). A hydrokit
      term cannot change its coefficient with the state, so ``crossflow_cd`` is given (default: the
      straight course's) and :func:`manoeuvres` iterates it to the steady turn's own cross-flow;
    * fins (rudder force −½ρ U_h² A C_Lδ δ at x = −L/2, yaw moment x_r Y_r; stern plane likewise):
      PVS rudder one fin 0.10 × 0.05 m², C_Lδ 0.5, stern planes 2 × 0.005 m², C_Lδ 0.7, limit
      30°, first-order servo T = 1 s; MSS rudder and stern planes 2 × 0.00665 m² each, C_Lδ 0.5
      and 0.7, limit 20°, no servo. Their fin drag −½ρU²A C_Lδ δ² is kept (delta()² terms). The
      fins' lift depends on δ only: no inflow angle from the vehicle's own motion;
    * propeller :data:`PEER_KT` as a hydrokit propeller (its J uses (1 − w) u at the propeller
      where theirs uses 0.944 U: the same on a straight course, 0.944 U cos β in a turn).
      Its roll torque is left out, as for every model in the bench.
    """
    from hydrokit.api import vehicle_from_dict

    if kind not in ("pvs", "mss"):
        raise ValueError(f"peer {kind!r}: expected 'pvs' or 'mss'")
    rho, g, length, diam = 1026.0, 9.81, 1.6, 0.19
    scale = 1.0096 if kind == "mss" else 1.0
    a, b = scale * length / 2, scale * diam / 2
    m = 4 / 3 * math.pi * rho * a * b * b
    ix, iy = 0.4 * m * b * b, 0.2 * m * (a * a + b * b)
    e = math.sqrt(1 - (b / a) ** 2)
    log = math.log((1 + e) / (1 - e))
    alpha0 = 2 * (1 - e * e) / e**3 * (0.5 * log - e)
    beta0 = 1 / e**2 - (1 - e * e) / (2 * e**3) * log
    k1, k2 = alpha0 / (2 - alpha0), beta0 / (2 - beta0)
    kp = e**4 * (beta0 - alpha0) / ((2 - e * e) * (2 * e * e - (2 - e * e) * (beta0 - alpha0)))
    added = [m * k1, m * k2, m * k2, 0.3 * ix, kp * iy, kp * iy]
    a1, a2, a3, a4, a5, a6 = added
    z_g, weight = 0.02, m * g
    big = [m + added[0], m + added[1], m + added[2], ix + added[3], iy + added[4], iy + added[5]]
    # forceLiftDrag (vertical plane), small-angle forms; S and D are the unscaled L, D in both
    s_ref = 0.7 * length * diam
    cd0 = 0.42 * math.pi * b * b / s_ref
    ar = diam**2 / s_ref
    cla = math.pi * ar / (1 + math.sqrt(1 + (ar / 2) ** 2))
    q = 0.5 * rho * s_ref
    # the propeller's steady speed: (1 − t) ρ D⁴ n² K_T(0.944 U / (n D)) = q C_D0 U² + D11(U) U
    n, d_p = PEER_RPM / 60, 0.14
    t_yaw = 5.0 if kind == "pvs" else 1.0
    speed = 2.0
    for _ in range(200):  # fixed point: the right side grows faster than the thrust falls
        thrust = 0.9 * rho * d_p**4 * n * n * (PEER_KT[1] + PEER_KT[0] * 0.944 * speed / (n * d_p))
        drag_coef = q * cd0 + big[0] / 20 * math.exp(-3 * speed) / speed
        speed = 0.5 * speed + 0.5 * math.sqrt(max(thrust, 0.0) / drag_coef)
    fade = math.exp(-3 * speed)  # their e^{-3U} at the steady speed
    damping = [
        big[0] / 20 * fade,
        big[1] / 20 * (fade if kind == "pvs" else 1.0),
        big[2] / 20,
        2 * 0.3 * math.sqrt(weight * z_g / big[3]) * big[3],
        2 * 0.8 * math.sqrt(weight * z_g / big[4]) * big[4],
        big[5] / t_yaw * (fade if kind == "pvs" else 1.0),
    ]
    # added-mass Coriolis, −C_A(ν)ν of a diagonal M_A (Fossen 2011 eq. 6.43) less what each zeroes
    if kind == "pvs":
        coriolis = {"X_wq": -a3, "X_vr": a2, "Y_ur": -a1, "Y_wp": a3, "Z_vp": -a2, "Z_uq": a1}
        coriolis |= {"M_uw": -a1, "M_pr": -a4, "N_pq": a4 - a5}
    else:
        coriolis = {"Y_wp": a3, "Z_vp": -a2, "M_pr": a6 - a4, "N_pq": a4 - a5}
    hull = {
        "X_u*sqrt(u^2+v^2+w^2)": -q * cd0,
        "Z_w*sqrt(u^2+v^2+w^2)": -q * (cd0 + cla),
        "X_ww": q * (cla - cla * cla / (math.pi * 0.7 * ar)),
    }
    if kind == "pvs":  # Hoerner's C_d at B/(2T) = 0.5 (interpolated in his table: 1.198), 21 strips
        cd_2d = 1.2108 + (0.5 - 0.4933) / (0.5585 - 0.4933) * (1.0836 - 1.2108)
        dx = length / 20
        xs = [-length / 2 + i * dx for i in range(21)]
        per = [0.0, 0.5 * rho * diam * cd_2d * dx, 0.0]
    else:  # a finite cylinder's C_d, 20 strips at their midpoints, sway and heave, ρ 1025
        dx = length / 20
        xs = [-length / 2 + (i + 0.5) * dx for i in range(20)]
        cd_2d = mss_crossflow_cd(0.0) if crossflow_cd is None else crossflow_cd
        per = [0.0, 0.5 * 1025.0 * diam * cd_2d * dx, 0.5 * 1025.0 * diam * cd_2d * dx]
    strips = [{"name": f"cf-{i:02d}", "position": [x, 0.0, 0.0], "quadratic": per} for i, x in enumerate(xs)]
    if kind == "pvs":
        rudder_area, plane_area, limit, servo = 0.10 * 0.05, 2 * 0.10 * 0.05, 30, 1.0
    else:
        rudder_area, plane_area, limit, servo = 2 * 0.00665, 2 * 0.00665, 20, None
    yr, zs = -0.5 * rho * rudder_area * 0.5, -0.5 * rho * plane_area * 0.7
    x_fin = -a
    m_sign = 1.0 if kind == "pvs" else -1.0
    fins = {
        "Y_uu*delta(rudder)": yr,
        "Y_vv*delta(rudder)": yr,
        "N_uu*delta(rudder)": x_fin * yr,
        "N_vv*delta(rudder)": x_fin * yr,
        "X_uu*delta(rudder)^2": yr,
        "X_vv*delta(rudder)^2": yr,
        "Z_uu*delta(sternplane)": zs,
        "Z_ww*delta(sternplane)": zs,
        "M_uu*delta(sternplane)": m_sign * x_fin * zs,  # PVS M = x_s Z_s; MSS corrected: −x_s Z_s
        "M_ww*delta(sternplane)": m_sign * x_fin * zs,
        "X_uu*delta(sternplane)^2": zs,
        "X_ww*delta(sternplane)^2": zs,
    }
    surfaces = []
    for name in ("rudder", "sternplane"):
        entry: dict[str, Any] = {"name": name, "position": [x_fin, 0.0, 0.0], "max_deflection_deg": limit}
        if servo is not None:
            entry["time_constant"] = servo
        surfaces.append(entry)
    propeller = {
        "name": "propeller",
        "position": [x_fin, 0.0, 0.0],
        "direction": [1, 0, 0],
        "diameter": d_p,
        "kt_forward": list(PEER_KT),
        "max_rpm": PEER_RPM,
        "advance_ratio_range": [-0.5, 1.094],
        "wake_fraction": 0.056,
        "thrust_deduction": 0.1,
        "max_thrust": round(rho * d_p**4 * n * n * PEER_KT[1], 1),
    }
    data = {
        "name": f"{kind}-remus100",
        "gravity": g,
        "fluid": {"density": rho},
        "mass": m,
        "volume": m / rho,
        "inertia": [ix, iy, iy],
        "center_of_gravity": [0.0, 0.0, z_g],
        "center_of_buoyancy": [0.0, 0.0, 0.0],
        "added_mass": added,
        "added_mass_coriolis": False,
        "linear_damping": damping,
        "quadratic_damping": [0, 0, 0, 0, 0, 0],
        "reference_length": length,
        "drag_elements": strips,
        "thrusters": [propeller],
        "control_surfaces": surfaces,
        "terms": coriolis | hull | fins,
    }
    return vehicle_from_dict(data, f"bench {kind} REMUS 100"), speed


#: our REMUS propeller's speed (rev/s) that gives Prestero's 3.86 N at 1.54 m/s (remus100.yaml)
REMUS_PROPELLER = 11.567


def _models() -> list[tuple[str, Any, dict[str, Any]]]:
    """(label, vehicle, run options) of every REMUS model flown side by side: each on its own
    propeller at fixed rpm (ours at :data:`REMUS_PROPELLER`, the peers' at :data:`PEER_RPM`)."""
    out = []
    for name in ("remus100", "remus100-fins"):
        v = _load(name)
        if v is not None:
            opts = {"commands": {"propeller": REMUS_PROPELLER}, "nu0": APPROACH}
            out.append((name, v, opts))
    for kind in ("pvs", "mss"):
        v, speed = peer_vehicle(kind)
        opts = {"commands": {"propeller": PEER_RPM / 60}, "nu0": (round(speed, 2), 0, 0, 0, 0, 0)}
        out.append((f"{kind} remus100", v, opts))
    return out


def manoeuvres() -> dict[str, Any]:
    """Fly and print the REMUS models' turning circles, zigzags and pull-outs side by side."""
    from hydrokit.manoeuvre.run import pull_out, run_manoeuvre, turning_circle, zigzag

    out: dict[str, Any] = {}
    rad = math.radians
    models = _models()
    print("\n== REMUS 100 models, each on its own propeller at fixed rpm, no roll torque, depth held ==")
    for label, v, opts in models:
        limit = max(math.degrees(x) for x in v.surfaces.max_deflection)
        print(
            f"{label:16s} L {v.reference_length:.4g} m, mass {v.mass:.2f} kg, B − W {v.buoyancy - v.weight:.2f} N, "
            f"propeller {opts['commands']['propeller'] * 60:.0f} rpm, fin limit {limit:.0f}°"
        )
    print(
        f"\n{'turning circle':16s} {'rudder':>6s} {'U0 m/s':>7s} {'advance':>8s} {'tactical':>8s} {'D_steady':>8s} "
        f"{'D/L':>5s} {'U/U0':>5s} {'drift°':>6s} {'dz max m':>8s}  note"
    )
    for label, v, opts in models:
        limit = max(math.degrees(x) for x in v.surfaces.max_deflection)
        for deg in sorted({*ANGLES, limit}):
            if deg > limit:
                continue
            r = run_manoeuvre(v, turning_circle(rad(deg)), dt=0.05, duration=900, **opts)
            cd_note = ""
            if label.startswith("mss"):  # their C_d at the steady turn's own cross-flow (fixed point)
                for _ in range(4):
                    m = r.metrics
                    if m["steady_speed"] is None:
                        break
                    cd = mss_crossflow_cd(m["steady_speed"] * math.sin(math.radians(m["drift_angle_deg"])))
                    veh, _ = peer_vehicle("mss", cd)
                    r = run_manoeuvre(veh, turning_circle(rad(deg)), dt=0.05, duration=900, **opts)
                cd_note = f"cross-flow C_d {cd:.3g}"
            m = r.metrics
            d = m["steady_turning_diameter"]
            note = (r.problem or "; ".join(r.warnings) or cd_note)[:60]
            print(
                f"{label:16s} {deg:5.0f}° {r.approach_speed:7.3f} {_fmt(m['advance']):>8s} "
                f"{_fmt(m['tactical_diameter']):>8s} {_fmt(d):>8s} {_fmt(d / v.reference_length if d else None):>5s} "
                f"{_fmt(m['speed_ratio']):>5s} {_fmt(m['drift_angle_deg']):>6s} {_fmt(m.get('max_depth_change')):>8s}  {note}"
            )
            out[f"{label} turn {deg:g}"] = m
    print(f"\n{'zigzag':16s} {'A/B':>6s} {'1st os°':>8s} {'2nd os°':>8s} {'3rd os°':>8s} {'period s':>8s}  note")
    for label, v, opts in models:
        for a in ZIGZAGS:
            r = run_manoeuvre(v, zigzag(rad(a), rad(a)), dt=0.05, duration=300, **opts)
            m = r.metrics
            print(
                f"{label:16s} {a:3.0f}/{a:<2.0f} {_fmt(m['first_overshoot_deg']):>8s} {_fmt(m['second_overshoot_deg']):>8s} "
                f"{_fmt(m.get('third_overshoot_deg')):>8s} {_fmt(m['period']):>8s}  {(r.problem or '')[:60]}"
            )
            out[f"{label} zigzag {a:g}"] = m
    print(f"\n{'pull-out ±10°':16s} {'r before rad/s':>15s} {'residual rad/s':>15s} {'t½ s':>6s}")
    for label, v, opts in models:
        r = run_manoeuvre(v, pull_out(rad(10)), dt=0.05, duration=900, **opts)
        for side in r.metrics.get("sides") or []:
            print(
                f"{label:16s} {_fmt(side.get('yaw_rate_before')):>15s} {_fmt(side.get('residual_yaw_rate')):>15s} "
                f"{_fmt(side.get('time_to_half')):>6s}"
            )
        if r.problem:
            print(f"{label:16s} problem: {r.problem[:100]}")
        out[f"{label} pull-out 10"] = r.metrics
    return out


def ship(name: str = "mariner", force: float = 727_000.0, speed: float = 7.7) -> dict[str, Any]:
    """The planar surface ship's IMO MSC.137(76) trials: turning circle at 35°, zigzags 10°/10°
    and 20°/20°, each with its criteria (``--force 727000,0,0,0,0,0`` holds 15 kn)."""
    from hydrokit.manoeuvre.run import run_manoeuvre, turning_circle, zigzag

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

    from hydrokit.manoeuvre.run import fly_manoeuvre, holding_surfaces, turning_circle
    from hydrokit.model.dynamics import vehicle_dynamics
    from hydrokit.simulate.compiled import make_dynamics

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
    if "--no-ship" not in argv:
        ship()
    if "--no-speed" not in argv:
        rhs_speed()
        loop_speed()
    print(f"\nbench/manoeuvre.py done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
