"""Identify a planar manoeuvring model of the Esso Osaka (3 m free-running model) from its pond
zigzags, and predict held-out zigzags and random-input runs (issues #44, #45).

    python bench/esso_osaka.py PATH/TO/esso-osaka [--train 3] [--free LIST] [--dt 0.05]

PATH holds ``zigzag/*.csv`` and ``random/*.csv`` of the FRT-DS-ESSO data set (Wakita et al. 2022,
J. Mar. Sci. Technol. 27:772; Miyauchi et al. 2022, 27:1065; CC BY-NC 4.0 — read from the path
given, never copied). Columns used: t, x/y of midship (m, pond frame), u, v at midship (m/s),
heading ψ (rad), r (rad/s), propeller speed n (rev/s), rudder angle (rad). The runs are
converted into hydrokit run files and a planar (surge, sway, yaw) vehicle file in a temporary
folder; ``hydrokit.sysid`` fits the chosen derivatives on the first ``--train`` zigzags; the
other zigzags and the random runs are predicted open loop. Prints the NRMSE per channel and the
identified values with σ, the correlations above 0.9 and the identifiability messages.

The start model: the KVLCC2 MMG hull derivatives of Yasukawa & Yoshimura (2015, J. Mar. Sci.
Technol. 20:37, Table 2 — a VLCC of the Esso Osaka's fullness, C_b 0.81 vs 0.83) made
dimensional with ½ρLd (forces) and ½ρL²d (moments) for L = 3 m, d = 0.201 m; the rudder force
of the MMG model, F_N = ½ρ A_R f_α U_R² δ with f_α = 6.13 Λ/(Λ + 2.25) (Fujii), Λ = 1.83,
U_R ≈ 1.3 u, Y = (1 + a_H) F_N, N = (x_R + a_H x_H) F_N, a_H = 0.31, x_H = −0.464 L,
x_R = −0.5 L; the surge resistance from the runs' steady speed (thrust = drag); a propeller of
D = 0.084 m with a B-series-like K_T(J) = 0.30 − 0.27 J − 0.08 J² (our assumption: the model
propeller's open-water curve is not in the data set), wake fraction 0.4, thrust deduction 0.2.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

RHO, L, D_DRAFT, MASS, XG = 1000.0, 3.0, 0.201, 244.6, 0.094
PROP_D, A_R = 0.084, 0.0106
KT = [-0.08, -0.27, 0.30]
WAKE, THRUST_LOSS = 0.4, 0.8
FREE = (
    "quadratic_damping.surge,terms.Y_uv,terms.Y_ur,terms.N_uv,terms.N_ur,"
    "terms.Y_uu*delta(rudder),terms.N_uu*delta(rudder)"
)


def read_esso(path: Path) -> list[tuple[str, np.ndarray]]:
    """Rows [t, x, u, y, v, psi, r, n, delta, wind…] of a file, split at NaN rows into pieces
    of at least 30 s (one file holds NaN rows, the time column too)."""
    d = np.genfromtxt(path, delimiter=",", skip_header=1)
    bad = np.isnan(d[:, :9]).any(axis=1)
    pieces, start = [], 0
    for k in [*np.nonzero(bad)[0], d.shape[0]]:
        seg = d[start:k]
        if seg.shape[0] and seg[-1, 0] - seg[0, 0] >= 30.0:
            pieces.append(seg)
        start = k + 1
    return [(f"{path.stem}" + (f"_{i}" if len(pieces) > 1 else ""), p) for i, p in enumerate(pieces)]


def segments(items: list[tuple[str, np.ndarray]], length: float, limit: int) -> list[tuple[str, np.ndarray]]:
    """Consecutive windows of ``length`` s with the propeller ahead (n > 1 rev/s) and the ship
    under way (u > 0.1 m/s) throughout — at most ``limit`` per piece. An open-loop simulation of
    a course-unstable hull over minutes drifts away whatever its coefficients; short windows,
    each with its own fitted initial state, are the multiple shooting of the issue."""
    out = []
    for name, rows in items:
        k, n = 0, 0
        t = rows[:, 0]
        while k < rows.shape[0] and n < limit:
            j = int(np.searchsorted(t, t[k] + length))
            if j >= rows.shape[0]:
                break
            w = rows[k : j + 1]
            if np.all(w[:, 2] > 0.1) and np.all(w[:, 7] > 1.0):
                out.append((f"{name}@{t[k] - t[0]:.0f}s", w))
                n += 1
                k = j
            else:
                k += 10
    return out


def rudder_sign(rows: list[np.ndarray]) -> float:
    """−1 if a positive logged rudder angle turns the ship to starboard (r > 0): hydrokit's
    positive deflection (right-handed about +z, behind the centre) turns it to port."""
    c = np.corrcoef(np.concatenate([r[:, 8] for r in rows]), np.concatenate([r[:, 6] for r in rows]))[0, 1]
    return -1.0 if c > 0 else 1.0


def write_run(rows: np.ndarray, name: str, out: Path, sign: float) -> Path:
    from hydrokit.io.runlog import run_csv

    t = rows[:, 0] - rows[0, 0]
    chans = {"x": rows[:, 1], "y": rows[:, 3], "psi": rows[:, 5], "u": rows[:, 2], "v": rows[:, 4], "r": rows[:, 6]}
    text = run_csv(
        t,
        chans,
        {"prop": rows[:, 7]},
        comment="Esso Osaka free-running model test (FRT-DS-ESSO, CC BY-NC 4.0), converted",
        deflections={"rudder": sign * rows[:, 8]},
    )
    p = out / f"{name}.csv"
    p.write_text(text)
    return p


def vehicle_doc(x_uu: float) -> dict:
    half = 0.5 * RHO
    f, m2, m3 = half * L * D_DRAFT, half * L**2 * D_DRAFT, half * L**3 * D_DRAFT
    m_x, m_y, j_z = 0.022 * m2, 0.223 * m2, 0.011 * half * L**4 * D_DRAFT
    lam = 1.83
    f_alpha = 6.13 * lam / (lam + 2.25)
    fn = half * A_R * f_alpha * 1.3**2
    return {
        "name": "esso-osaka-model",
        "description": "Esso Osaka 3 m free-running model, planar MMG-like start (bench/esso_osaka.py)",
        "gravity": 9.81,
        "fluid": {"density": RHO},
        "dofs": ["surge", "sway", "yaw"],
        "mass": MASS,
        "volume": MASS / RHO,
        "inertia": [MASS * (0.35 * 0.489) ** 2, MASS * (0.25 * L) ** 2, MASS * (0.25 * L) ** 2],
        "center_of_gravity": [XG, 0, 0],
        "center_of_buoyancy": [XG, 0, 0],
        "added_mass": [m_x, m_y, 0, 0, 0, j_z],
        "linear_damping": [0] * 6,
        "quadratic_damping": [x_uu, 0, 0, 0, 0, 0],
        # the captive-test derivatives hold the Munk moment; MMG writes (m + m_x) u r on the left
        "added_mass_coriolis": False,
        "control_surfaces": [{"name": "rudder", "position": [-0.5 * L, 0, 0], "max_deflection_deg": 36}],
        "thrusters": [
            {
                "name": "prop",
                "position": [-0.48 * L, 0, 0],
                "direction": [1, 0, 0],
                "diameter": PROP_D,
                "kt_forward": KT,
                "wake_fraction": WAKE,
                "thrust_loss": {"forward": THRUST_LOSS, "reverse": THRUST_LOSS},
                "max_rpm": 1200,
                "max_thrust": 30,
                "min_thrust": -30,
            }
        ],
        "terms": {
            "Y_uv": -0.315 * f,
            "Y_ur": 0.083 * m2 - m_x,
            "N_uv": -0.137 * m2,
            "N_ur": -0.049 * m3,
            "Y_uu*delta(rudder)": (1 + 0.31) * fn,
            "N_uu*delta(rudder)": -(0.5 * L + 0.31 * 0.464 * L) * fn,
        },
    }


def steady_resistance(rows: list[np.ndarray]) -> float:
    """X_u|u| coefficient (N·s²/m²) balancing the propeller thrust at the runs' steady speeds."""
    from hydrokit.model.thrusters import PropellerCurve

    cv = PropellerCurve(PROP_D, tuple(KT), 20.0, density=RHO)
    vals = []
    for r in rows:
        half = r[r.shape[0] // 2 :]
        u, n = np.median(half[:, 2]), np.median(half[:, 7])
        if u > 0.1 and n > 1:
            vals.append(THRUST_LOSS * cv.thrust(n, (1 - WAKE) * u) / u**2)
    return float(np.median(vals)) if vals else 30.0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", help="esso-osaka folder with zigzag/ and random/")
    ap.add_argument("--train", type=int, default=3, help="zigzags used for the fit (count)")
    ap.add_argument("--free", default=FREE, help="free parameters (comma-separated)")
    ap.add_argument("--dt", type=float, default=0.05, help="integration step, s")
    ap.add_argument("--random", type=int, default=3, help="random-input runs predicted (count)")
    ap.add_argument("--segment", type=float, default=20.0, help="length of the fitted and predicted windows, s")
    ap.add_argument("--per-run", type=int, default=6, help="windows taken from each run (count)")
    a = ap.parse_args()
    import hydrokit
    from hydrokit.io.runlog import read_run

    root = Path(a.folder)
    zig = [p for f in sorted((root / "zigzag").glob("*.csv")) for p in read_esso(f)]
    rnd = [p for f in sorted((root / "random").glob("*.csv"))[: a.random] for p in read_esso(f)]
    sign = rudder_sign([r for _, r in zig])
    print(f"rudder: logged δ > 0 turns to {'starboard' if sign < 0 else 'port'}; hydrokit δ = {sign:+.0f} × logged")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        x_uu = steady_resistance([r for _, r in zig[: a.train]])
        doc = vehicle_doc(x_uu)
        vpath = out / "esso.yaml"
        vpath.write_text(yaml.safe_dump(doc, sort_keys=False))
        base = hydrokit.load_vehicle(str(vpath))
        names, surf = base.thrusters.names, base.surfaces.names
        lim = base.surfaces.max_deflection

        def load(items: list[tuple[str, np.ndarray]]) -> list:
            return [read_run(write_run(rows, n, out, sign), names, surf, lim) for n, rows in items]

        cut = lambda items: segments(items, a.segment, a.per_run)  # noqa: E731
        train, held_zig, held_rnd = load(cut(zig[: a.train])), load(cut(zig[a.train :])), load(cut(rnd))
        print(f"{len(train)} training windows, {len(held_zig)} held-out zigzag and {len(held_rnd)} random windows")
        free = [s.strip() for s in a.free.split(",")]
        t0 = time.perf_counter()
        res = hydrokit.sysid(train, base, free, holdout=held_zig + held_rnd, dt=a.dt, samples=0)
        print(f"\nfit: {time.perf_counter() - t0:.1f} s, {res.iterations} iterations, condition {res.condition:.3g}")
        print(f"{'parameter':32s} {'start':>10s} {'value':>10s} {'σ':>9s} {'σ/|v|':>7s} {'eq.-error':>10s}")
        for n, st, v, s, e in zip(res.parameters, res.start, res.values, res.sigma, res.equation_error["values"]):
            print(f"{n:32s} {st:10.4g} {v:10.4g} {s:9.3g} {s / abs(v):7.2f} {e:10.4g}")
        c = res.correlation
        pairs = [
            (abs(c[i, j]), res.parameters[i], res.parameters[j], c[i, j])
            for i in range(c.shape[0])
            for j in range(i + 1, c.shape[0])
            if abs(c[i, j]) > 0.9
        ]
        for _, pa, pb, rho in sorted(pairs, reverse=True):
            print(f"  ρ({pa}, {pb}) = {rho:+.3f}")
        print(f"\nnoise σ used: {', '.join(f'{k} {v:.3g}' for k, v in res.noise.items())}")
        chans = ("x", "y", "psi", "u", "v", "r")
        print(f"\n{'run':40s} " + " ".join(f"{ch:>7s}" for ch in chans) + "   (NRMSE; fit runs: residual lag-1 ρ)")
        groups: dict[str, list[list[float]]] = {
            "fit windows (residual lag-1 ρ, median)": [],
            "held-out zigzag windows (NRMSE, median)": [],
        }
        groups["random-input windows (NRMSE, median)"] = []
        keys = list(groups)
        for row in res.runs:
            ch = row["channels"]
            if row["holdout"]:
                vals = [ch[k].get("nrmse", math.nan) if k in ch else math.nan for k in chans]
                groups[keys[2 if row["name"].startswith("random") else 1]].append(vals)
            else:
                groups[keys[0]].append([ch[k]["whiteness"]["lag1"] if k in ch else math.nan for k in chans])
        for g, rows in groups.items():
            if rows:
                med = np.nanmedian(np.array(rows, float), axis=0)
                print(f"{g[:40]:40s} " + " ".join(f"{v:7.3f}" for v in med))
        for m in res.messages:
            print("note:", m)
        for w in res.warnings:
            print("warning:", w)
    return 0


if __name__ == "__main__":
    sys.exit(main())
