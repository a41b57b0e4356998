"""The bundled free-running vehicles (issue #45 item 7): REMUS 100 from Prestero's (2001, MIT/WHOI
MS thesis) derivative table (``remus100``) and with physical fins, hull lift and cross-flow from
its profile (``remus100-fins``)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hydrokit.core.coriolis import coriolis_matrix
from hydrokit.io.vehicle import bundled_vehicles, load_vehicle
from hydrokit.simulate.driver import simulate

THRUST = 3.86  # N, Prestero's steady run at about 1.5 m/s
X_UU = -1.62  # kg/m, Prestero's axial drag
U_STEADY = math.sqrt(THRUST / -X_UU)  # 1.5436 m/s


@pytest.mark.parametrize("name", ["remus100", "remus100-fins"])
def test_bundled_remus_loads_with_its_surfaces(name):
    assert name in bundled_vehicles()
    v = load_vehicle(name)
    assert v.surfaces.names == ("rudder", "sternplane")
    # 20°: the MSS REMUS 100 limit (no hardware limit was found in a public source)
    assert np.allclose(np.degrees(v.surfaces.max_deflection), 20.0)
    assert v.buoyancy - v.weight == pytest.approx(306.0 - 299.0, abs=0.1)  # Prestero: B 306 N, W 299 N


@pytest.mark.parametrize(("name", "dofs"), [("remus100", (0, 1, 5)), ("remus100-fins", None)])
def test_steady_speed_under_prestero_thrust(name, dofs):
    """Under Prestero's 3.86 N: u → √(T/−X_u|u|) = 1.5436 m/s. Neutrally buoyant (B = W) so that
    nothing excites the vertical plane from a straight start (r_G straight below r_B). Prestero's
    printed set is unstable in its vertical plane (see below), where even the round-off of B − W
    grows into a dive within a minute: it is flown planar (surge, sway, yaw). The surge time
    constant is (m − X_u̇)/(2·1.62·u) ≈ 6.3 s; from 1.5 m/s the error after 30 s is
    0.044·e^{-4.8} ≈ 4e-4 m/s: rtol 1e-3. The strips and fins add no axial drag (cross-flow only;
    fins with C_D0 = 0 at zero lift)."""
    v = load_vehicle(name)
    v = dataclasses.replace(v, volume=v.mass / v.density, dofs=dofs or v.dofs)
    tr = simulate(v, 30.0, 0.05, tau=(THRUST, 0, 0, 0, 0, 0), nu0=(1.5, 0, 0, 0, 0, 0))
    assert tr.nu[-1, 0] == pytest.approx(U_STEADY, rel=1e-3)
    assert np.abs(tr.nu[:, [1, 3, 5]]).max() == 0.0  # nothing acts across the vertical plane
    # the surge acceleration pitches the body a little through M_RB's m z_G coupling; decayed
    # to ~1e-5 by 30 s
    assert np.abs(tr.nu[-1, [2, 4]]).max() < 1e-4


@pytest.mark.parametrize("name", ["remus100", "remus100-fins"])
def test_stern_planes_give_no_sway(name):
    """Symmetric stern planes act in the vertical plane only: sway, roll and yaw stay zero, and
    positive stern plane pitches the nose down when moving ahead (−Z, −M: Prestero's signs)."""
    v = load_vehicle(name)
    tr = simulate(v, 5.0, 0.02, tau=(THRUST, 0, 0, 0, 0, 0), nu0=(U_STEADY, 0, 0, 0, 0, 0), deflection=[0.0, 0.1])
    assert np.abs(tr.nu[:, [1, 3, 5]]).max() < 1e-12
    assert tr.nu[5, 4] < 0  # q < 0 within 0.1 s: nose down


@pytest.mark.parametrize("name", ["remus100", "remus100-fins"])
def test_rudder_turns_to_port(name):
    """Positive rudder (Y_uuδr > 0, N_uuδr < 0) turns the vehicle to port: r < 0."""
    v = load_vehicle(name)
    tr = simulate(v, 3.0, 0.02, tau=(THRUST, 0, 0, 0, 0, 0), nu0=(U_STEADY, 0, 0, 0, 0, 0), deflection=[0.1, 0.0])
    assert tr.nu[-1, 5] < 0 and tr.eta[-1, 5] < 0


def test_prestero_cross_terms_are_the_added_mass_coriolis():
    """remus100 switches the model's C_A(ν) off because Prestero's table holds it: his added-mass
    cross terms plus the added-mass parts of his combined terms (Y_ura = X_u̇, Z_uqa = −X_u̇,
    M_uwa = −(Z_ẇ − X_u̇), N_uva = −(X_u̇ − Y_v̇), M_uqa = −Z_q̇, N_ura = Y_ṙ) must equal
    −C_A(ν)ν of the file's added mass (Fossen 2011 eq. 6.43). Printed to 3 digits: rtol 1 % of
    the largest component."""
    v = load_vehicle("remus100")
    M_A = v.M_A
    Xu, Yv, Zw, Zq, Yr = -M_A[0, 0], -M_A[1, 1], -M_A[2, 2], -M_A[2, 4], -M_A[1, 5]
    munk = {"Y_ur": Xu, "Z_uq": -Xu, "M_uw": -(Zw - Xu), "N_uv": -(Xu - Yv), "M_uq": -Zq, "N_ur": Yr}
    terms = dict(zip(v.terms.names, v.terms.coef))
    rng = np.random.default_rng(45)
    for _ in range(5):
        nu = rng.normal(size=6)
        u, vv, w, p, q, r = nu
        products = {
            "X_wq": w * q, "X_qq": q * q, "X_vr": vv * r, "X_rr": r * r, "Y_wp": w * p, "Y_pq": p * q,
            "Z_vp": vv * p, "Z_rp": r * p, "M_vp": vv * p, "M_rp": r * p, "N_wp": w * p, "N_pq": p * q,
        }  # fmt: skip
        mine = np.zeros(6)
        for name, x in products.items():
            mine["XYZKMN".index(name[0])] += terms[name] * x
        for name, c in munk.items():
            a, b = name[2], name[3]
            mine["XYZKMN".index(name[0])] += c * nu["uvwpqr".index(a)] * nu["uvwpqr".index(b)]
        expected = -coriolis_matrix(M_A, nu) @ nu
        assert np.allclose(mine, expected, atol=0.01 * np.abs(expected).max())


def test_open_loop_stability_of_the_two_remus_models():
    """Clarke's straight-line stability index C = Y_v N_r − N_v (Y_r − m) (per unit speed) of the
    horizontal plane: Prestero's printed set (fins at 9.64, N_uv −24.0, N_ur −2.0, Y_ur 5.22) is
    unstable (C < 0); the bundled remus100 (lift terms from his fin and hull data) and the physical
    fins (ρ c_Lα S = 21.4 per pair, with the hull lift and the model's Munk moment) are stable.
    An independent check: the eigenvalues of the linearised v–r dynamics at 1.54 m/s."""
    from hydrokit.simulate.compiled import make_dynamics

    growth = {}
    for name in ("remus100", "remus100-fins"):
        v = load_vehicle(name)
        f = make_dynamics(v)
        x0 = np.zeros(12)
        x0[6] = U_STEADY
        tau = np.array([THRUST, 0, 0, 0, 0, 0])
        J = np.zeros((2, 2))
        for j, i in enumerate((7, 11)):
            e = np.zeros(12)
            e[i] = 1e-6
            J[:, j] = (np.asarray(f(0.0, x0 + e, tau)) - np.asarray(f(0.0, x0 - e, tau)))[[7, 11]] / 2e-6
        growth[name] = np.linalg.eigvals(J).real.max()
    assert -28.6 * -2.0 - -24.0 * (5.22 - 30.48) < 0  # Prestero's printed terms
    terms = dict(zip(load_vehicle("remus100").terms.names, load_vehicle("remus100").terms.coef))
    clarke = terms["Y_uv"] * terms["N_ur"] - terms["N_uv"] * (terms["Y_ur"] - 30.48)
    assert clarke > 0 and growth["remus100"] < 0
    assert growth["remus100-fins"] < 0


def test_mariner_is_planar_and_holds_its_speed():
    """The Mariner ship (Chislett & Strøm-Tejsen 1965): planar, and its resistance X_u|u| =
    X'_u/2·½ρL² with T = −X_u|u| U0² holds U0 = 7.7175 m/s (15 kn) exactly: started there, it
    stays within round-off (rtol 1e-9); a positive rudder turns it to port (N'_δ < 0)."""
    v = load_vehicle("mariner")
    assert v.dofs == (0, 1, 5) and v.surfaces.names == ("rudder",)
    u0 = 7.7175
    x_uu = dict(zip(v.terms.names, v.terms.coef))["X_u|u|"]
    assert x_uu == pytest.approx(-92.0e-5 * 0.5 * 1025.0 * 160.93**2, rel=1e-12)
    thrust = -x_uu * u0 * u0
    tr = simulate(v, 20.0, 0.5, tau=(thrust, 0, 0, 0, 0, 0), nu0=(u0, 0, 0, 0, 0, 0))
    assert tr.nu[-1, 0] == pytest.approx(u0, rel=1e-9)
    tr = simulate(v, 20.0, 0.5, tau=(thrust, 0, 0, 0, 0, 0), nu0=(u0, 0, 0, 0, 0, 0), deflection=[0.1])
    assert tr.nu[-1, 5] < 0
