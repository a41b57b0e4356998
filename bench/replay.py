"""Trial replay (``hydrokit manoeuvre --replay``, issue #48): how closely a model replays a trial
flown by itself, how long a replay takes, and — given the Esso Osaka pond data — what a start model
predicts for real zigzags.

    python bench/replay.py [PATH/TO/esso-osaka] [--dt 0.05]

1. The bundled Mariner flies a 20°/20° zigzag and a 35° turning circle with the manoeuvre code
   (dt = 0.25 s); each is written as a run file, read back and replayed by the same Mariner. Prints
   the largest relative difference between the replay's predicted metrics and the trial's own
   (the run file's 9 significant digits are all that separate them) and the replay's wall time.
2. With PATH (the FRT-DS-ESSO data set, read from where it is, never copied; see
   bench/esso_osaka.py for the columns and the start model): every zigzag is converted to a run
   file and replayed with the planar MMG-like start model of bench/esso_osaka.py (not identified:
   ``bench/esso_osaka.py`` fits it). Prints the detected A/B, the executes and the measured and
   predicted overshoots.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

FORCE = (727000.0, 0, 0, 0, 0, 0)  # N: the Mariner at 15 kn


def _mariner(out: Path) -> None:
    import hydrokit
    from hydrokit.io.runlog import read_run, run_csv
    from hydrokit.manoeuvre import run as M
    from hydrokit.manoeuvre.replay import replay

    v = hydrokit.load_vehicle("mariner")
    dt = 0.25
    for m in (M.zigzag(math.radians(20), math.radians(20)), M.turning_circle(math.radians(35))):
        res = M.run_manoeuvre(v, m, tau=FORCE, nu0=(7.7, 0, 0, 0, 0, 0), dt=dt)
        states = np.column_stack([res.eta, res.nu])
        chans = {
            c: states[:, j] for j, c in enumerate(("x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r"))
        }
        chans = {c: chans[c] for c in ("x", "y", "psi", "u", "v", "r")}
        path = out / f"mariner_{m.kind}.csv"
        path.write_text(run_csv(res.time, chans, {}, deflections={"rudder": res.deflection[:, 0]}))
        run = read_run(path, (), ("rudder",), v.surfaces.max_deflection)
        t0 = time.perf_counter()
        rp = replay(v, run, tau=FORCE, dt=dt)
        wall = time.perf_counter() - t0
        worst = max(
            abs(rp.predicted.metrics[k] - x) / max(abs(x), 1e-12)
            for k, x in res.metrics.items()
            if isinstance(x, float) and rp.predicted.metrics.get(k) is not None
        )
        n = rp.predicted.time.size
        print(
            f"mariner {m.kind}: detected {rp.kind}, executes {len(rp.detected.executes)}; largest relative "
            f"difference of the predicted metrics from the trial's own {worst:.2g}; replay {wall:.2f} s "
            f"for {n} steps ({n / wall:.0f} steps/s)"
        )


def _esso(root: Path, out: Path, dt: float) -> None:
    sys.path.insert(0, str(Path(__file__).parent))
    import yaml

    import esso_osaka as E
    import hydrokit
    from hydrokit.io.runlog import read_run
    from hydrokit.manoeuvre.replay import replay

    zig = [p for f in sorted((root / "zigzag").glob("*.csv")) for p in E.read_esso(f)]
    sign = E.rudder_sign([r for _, r in zig])
    doc = E.vehicle_doc(E.steady_resistance([r for _, r in zig[:3]]))
    (out / "esso.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    v = hydrokit.load_vehicle(str(out / "esso.yaml"))
    for name, rows in zig:
        run = read_run(
            E.write_run(rows, name, out, sign), v.thrusters.names, v.surfaces.names, v.surfaces.max_deflection
        )
        try:
            rp = replay(v, run, dt=dt)
        except hydrokit.HydrokitError as exc:
            print(f"{name}: {exc}")
            continue
        m, p = rp.measured.metrics, rp.predicted.metrics
        par = rp.predicted.manoeuvre.parameters()

        def f(x: float | None) -> str:
            return "–" if x is None else f"{x:.3g}"

        print(
            f"{name}: {par['kind']} {abs(par.get('deflection_deg', 0)):.3g}°/{par.get('check_angle_deg', 0):.3g}°, "
            f"{len(rp.detected.executes)} executes, execute at {rp.detected.executes[0]:.1f} s, U {f(m['approach_speed'])} "
            f"m/s; overshoots measured {f(m.get('first_overshoot_deg'))}°, {f(m.get('second_overshoot_deg'))}°, "
            f"predicted {f(p.get('first_overshoot_deg'))}°, {f(p.get('second_overshoot_deg'))}°"
        )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("esso", nargs="?", help="esso-osaka folder with zigzag/ (optional)")
    ap.add_argument("--dt", type=float, default=0.05, help="integration step of the Esso Osaka replays, s")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        _mariner(Path(tmp))
        if a.esso:
            _esso(Path(a.esso), Path(tmp), a.dt)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
