"""The rudder's inflow behind a propeller: the fully developed race against the MMG standard
method (issue #48 item 2).

Prints u_R²/u² — the factor on a rudder's force from the propeller's race — for the KVLCC2 L7
model of Yasukawa & Yoshimura 2015 (J. Mar. Sci. Technol. 20:37–52; Table 1 particulars, Table 3
coefficients) at its self-propulsion point (u = 1.179 m/s, R'_0 = 0.022, t_P = 0.220) and at
heavier loadings, for the two inflow laws of ``hydrokit.model.surfaces.fin_wrench``: ``race``
(momentum theory, no wake, κ = η = ε = 1) and ``mmg`` (w_P = 0.40, ε = 1.09, κ = 0.50,
η = D_P/H_R). The inflow is read back from the fin law itself (a drag-free fin at a small
deflection in a straight run: |F| = ½ρS u_R² C_Lα δ).

    .venv/bin/python bench/rudder_inflow.py
"""

from __future__ import annotations

import math

import numpy as np

from hydrokit.model.surfaces import ControlSurface, Fin, SurfaceSet, fin_wrench
from hydrokit.model.thrusters import Thruster, ThrusterSet

RHO = 1000.0
L, D_P, H_R, A_R, DRAFT = 7.00, 0.216, 0.345, 0.0539, 0.46
W_P, T_P, R0 = 0.40, 0.220, 0.022
U = 1.179


def inflow_ratio(fin: Fin, u: float, thrust: float) -> float:
    """u_R²/u² from the fin law: a 1 mrad deflection, no drag, straight run."""
    s = SurfaceSet((ControlSurface("rudder", (-0.5 * L, 0.0, 0.0), math.radians(35), fin=fin),))
    row = s.pack_fins(RHO, 1)[0]
    f = np.zeros(6)
    d = 1e-3
    fin_wrench(row, 0, np.array([u, 0, 0, 0, 0, 0.0]), 0.0, np.array([d, thrust, 0.0]), 3, f)
    q = math.hypot(f[0], f[1]) / (A_R * fin.lift_slope * d)  # ½ρ u_R²
    return 2.0 * q / RHO / (u * u)


def main() -> None:
    base = {"axis": (0.0, 0.0, 1.0), "chord": (1.0, 0.0, 0.0), "area": A_R, "lift_slope": 2.747}
    base.update({"stall_angle": 0.5, "slipstream_diameter": D_P, "race_thruster": 0})
    race = Fin(**base)
    mmg = Fin(**base, inflow="mmg", wake_fraction=W_P, epsilon=1.09, kappa=0.50, eta=D_P / H_R, l_R=-0.710 * L)
    prop = Thruster(
        "prop",
        (-0.5 * L, 0, 0),
        (1, 0, 0),
        500.0,
        diameter=D_P,
        kt_forward=(-0.1385, -0.2753, 0.2931),
        max_speed=40.0,
        wake_fraction=W_P,
        thrust_deduction=T_P,
    )
    ts = ThrusterSet((prop,), density=RHO)
    resistance = 0.5 * RHO * L * DRAFT * U * U * R0
    print("KVLCC2 L7 (Yasukawa & Yoshimura 2015), u = 1.179 m/s")
    print(f"{'loading':>22} {'T (N)':>8} {'n (rev/s)':>10} {'race u_R²/u²':>13} {'MMG u_R²/u²':>12}")
    for label, factor in (("self-propulsion", 1.0), ("2 × resistance", 2.0), ("4 × resistance", 4.0)):
        thrust = factor * resistance / (1.0 - T_P)
        n = float(ts.rotation_rate([thrust], ts.advance_speed([U, 0, 0, 0, 0, 0]))[0])
        print(
            f"{label:>22} {thrust:8.2f} {n:10.2f} {inflow_ratio(race, U, thrust):13.2f} "
            f"{inflow_ratio(mmg, U, thrust):12.2f}"
        )


if __name__ == "__main__":
    main()
