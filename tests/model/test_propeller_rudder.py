"""Propeller–rudder interaction as data (issue #48 item 2): constant terms, T(NAME) and n(NAME)
factors, wake fraction and thrust deduction, a surface's neutral deflection, and the MMG standard
method's rudder inflow."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from hydrokit.api import vehicle_from_dict
from hydrokit.errors import InputError
from hydrokit.model.dynamics import input_vector, pack, vehicle_dynamics
from hydrokit.model.surfaces import FIN_WIDTH, ControlSurface, Fin, SurfaceSet, fin_wrench
from hydrokit.model.terms import DELTA, RATE, THRUST, TermSet, input_layout, parse_term

RHO = 1000.0

#: a small planar ship with one propeller (a cubic K_T) and one rudder; SI
SHIP = {
    "name": "pond-ship",
    "fluid": {"density": RHO},
    "mass": 50.0,
    "volume": 0.05,
    "inertia": [2.0, 20.0, 20.0],
    "center_of_gravity": [0, 0, 0],
    "center_of_buoyancy": [0, 0, 0],
    "added_mass": [2.0, 20.0, 20.0, 0.5, 5.0, 5.0],
    "linear_damping": [5.0, 20.0, 20.0, 1.0, 5.0, 5.0],
    "quadratic_damping": [10.0, 40.0, 40.0, 1.0, 5.0, 5.0],
    "reference_length": 2.0,
    "reference_speed": 0.5,
    "thrusters": [
        {
            "name": "prop",
            "position": [-1.0, 0, 0],
            "direction": [1, 0, 0],
            "max_thrust": 50,
            "diameter": 0.08,
            "kt_forward": [0.0, -0.1385, -0.2753, 0.2931],
            "max_rpm": 1800,
        },
        {"name": "bow", "position": [0.8, 0, 0], "direction": [0, 1, 0], "max_thrust": 5},
    ],
    "control_surfaces": [{"name": "rudder", "position": [-1.05, 0, 0], "max_deflection_deg": 35}],
}


def ship(**changes: object) -> dict:
    doc = copy.deepcopy(SHIP)
    doc.update(changes)
    return doc


# ------------------------------------------------------------------ the grammar


def test_thrust_rate_and_constant_factors_parse_to_their_input_indices():
    surfaces, thrusters = ("rudder", "flap"), ("prop", "bow")
    first_t, first_n, size = input_layout(len(surfaces), len(thrusters))
    assert (first_t, first_n, size) == (2, 4, 6)
    t = parse_term("Y_T(bow)*delta(flap)", surfaces=surfaces, thrusters=thrusters)
    assert [(f.kind, f.indices) for f in t.factors] == [(THRUST, (first_t + 1,)), (DELTA, (1,))]
    n = parse_term("N_n(prop)^2*delta(rudder)", surfaces=surfaces, thrusters=thrusters)
    assert [(f.kind, f.indices) for f in n.factors] == [(RATE, (first_n,)), (RATE, (first_n,)), (DELTA, (0,))]
    c = parse_term("N_0")
    assert c.dof == 5 and c.factors == () and c.acceleration is None


@pytest.mark.parametrize(
    ("name", "match"),
    [
        (
            "Y_T(propeller)*delta(rudder)",
            r"^v\.yaml: term 'Y_T\(propeller\)\*delta\(rudder\)': T\(propeller\) names no "
            r"thruster of the vehicle \(thrusters: prop, bow\)$",
        ),
        ("N_n(bow)*delta(rudder)", r"n\(bow\): thruster 'bow' has no propeller curve"),
        ("Y_T()", r"a thruster's name in \(\)"),
    ],
)
def test_a_thrust_factor_naming_no_thruster_is_one_line(name, match):
    with pytest.raises(InputError, match=match) as err:
        parse_term(name, "v.yaml", ("rudder",), ("prop", "bow"), ("prop",))
    assert "\n" not in str(err.value)


def test_a_vehicle_file_term_naming_no_thruster_exits_2_with_one_line(run_cli, tmp_path):
    import yaml

    path = tmp_path / "ship.yaml"
    path.write_text(yaml.safe_dump(ship(terms={"Y_T(screw)*delta(rudder)": 0.3})))
    code, _, err = run_cli("simulate", path, "--duration", "1", "--dt", "0.1", "--out", tmp_path / "out.csv")
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "T(screw) names no thruster" in err, err
    assert not (tmp_path / "out.csv").exists()


def test_nondimensional_scaling_of_thrust_rate_and_constant_terms():
    rho, L, U = 1025.0, 2.0, 0.5
    # X_0: a force ½ρL²U² X'_0
    assert parse_term("X_0").dimensional(0.022, rho, L, U) == pytest.approx(0.5 * rho * L**2 * U**2 * 0.022)
    assert parse_term("N_0").dimensional(0.01, rho, L, U) == pytest.approx(0.5 * rho * L**3 * U**2 * 0.01)
    # Y' = c' T' δ with T' = T / (½ρL²U²) and Y = Y' ½ρL²U²: the SI coefficient is c' itself
    kw = {"surfaces": ("rudder",), "thrusters": ("prop",)}
    assert parse_term("Y_T(prop)*delta(rudder)", **kw).dimensional(0.3, rho, L, None) == pytest.approx(0.3)
    # N' = c' T' δ, N = N' ½ρL³U²: c = c' L (N·m per N)
    assert parse_term("N_T(prop)*delta(rudder)", **kw).dimensional(-0.15, rho, L, None) == pytest.approx(-0.15 * L)
    # N' = c' n'² δ with n' = n L / U: N = c' (nL/U)² δ ½ρL³U² = c' ½ρL⁵ n² δ
    c = parse_term("N_n(prop)^2*delta(rudder)", **kw).dimensional(-0.002, rho, L, U)
    n, d = 12.0, 0.1
    n_nd = n * L / U
    assert c * n**2 * d == pytest.approx(-0.002 * n_nd**2 * d * 0.5 * rho * L**3 * U**2)
    # Y' = c' u' n' (u' = u/U): Y = c' ½ρL³ u n
    c = parse_term("Y_u*n(prop)", **kw).dimensional(0.05, rho, L, U)
    assert c == pytest.approx(0.05 * 0.5 * rho * L**3)
    with pytest.raises(InputError, match="reference_speed"):
        parse_term("X_0").dimensional(0.022, rho, L, None)


def test_terms_read_the_thrust_and_rate_of_the_input_vector():
    kw = {"surfaces": ("rudder",), "thrusters": ("prop", "bow")}
    ts = TermSet.build(
        [
            (parse_term("Y_T(prop)*delta(rudder)", **kw), 0.3),
            (parse_term("N_n(prop)^2*delta(rudder)", **kw), -0.002),
            (parse_term("X_0"), -4.0),
            (parse_term("K_T(bow)", **kw), 0.01),
        ]
    )
    thrust, rate, delta = np.array([20.0, -3.0]), np.array([14.0, 0.0]), np.array([0.2])
    u = np.concatenate([delta, thrust, rate])
    f = ts.force(np.zeros(6), u)
    assert f[1] == pytest.approx(0.3 * 20.0 * 0.2)
    assert f[5] == pytest.approx(-0.002 * 14.0**2 * 0.2)
    assert f[0] == pytest.approx(-4.0)
    assert f[3] == pytest.approx(0.01 * -3.0)
    # given only the deflections, the thrusts and rates are 0
    f0 = ts.force(np.zeros(6), delta)
    assert f0[1] == 0.0 and f0[5] == 0.0 and f0[0] == -4.0


def test_python_and_compiled_dynamics_see_the_thrust_and_rate():
    from hydrokit.simulate.compiled import make_dynamics

    v = vehicle_from_dict(ship(terms={"Y_T(prop)*delta(rudder)": 0.3, "N_n(prop)^2*delta(rudder)": -0.002}), "s")
    assert v.thruster_names == ("prop", "bow") and v.n_inputs == 5
    x = np.zeros(12)
    x[6] = 0.8
    tau = np.array([10.0, 0, 0, 0, 0, 0])
    delta, thrust, rate = np.array([0.2]), np.array([20.0, 1.0]), np.array([14.0, 0.0])
    f_py, f_c = vehicle_dynamics(v), make_dynamics(v)
    with_inputs = f_py(0.0, x, tau, delta, thrust, rate)
    without = f_py(0.0, x, tau, delta)
    # the difference is M⁻¹ times the two terms' force, computed by hand
    extra = np.zeros(6)
    extra[1] = 0.3 * 20.0 * 0.2
    extra[5] = -0.002 * 14.0**2 * 0.2
    expected = pack(v).Minv @ extra
    np.testing.assert_allclose(with_inputs[6:] - without[6:], expected, rtol=1e-12, atol=1e-12)
    # the compiled right-hand side gives the same (same laws, compiled); rtol: rounding only
    np.testing.assert_allclose(f_c(0.0, x, tau, delta, thrust, rate), with_inputs, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(f_c(0.0, x, tau, input_vector(v, delta, thrust, rate)), with_inputs, rtol=1e-10)
    with pytest.raises(InputError, match="1 thrusts \\(N\\): expected 2"):
        input_vector(v, delta, [1.0])


# ------------------------------------------------------------------ thrusters


def test_thrust_deduction_takes_from_the_force_only():
    plain = vehicle_from_dict(ship(), "s").thrusters
    doc = ship()
    doc["thrusters"][0]["thrust_deduction"] = 0.22
    doc["thrusters"][0]["wake_fraction"] = 0.4
    ts = vehicle_from_dict(doc, "s").thrusters
    assert ts.thrusters[0].thrust_deduction == 0.22
    T0, T1 = plain.configuration_matrix(), ts.configuration_matrix()
    # X_P = (1 − t_P) T (MMG); the moment arm of the thrust is unchanged
    np.testing.assert_allclose(T1[:3, 0], 0.78 * T0[:3, 0], rtol=1e-15)
    np.testing.assert_allclose(T1[3:, 0], T0[3:, 0], rtol=0)
    np.testing.assert_allclose(T1[:, 1], T0[:, 1], rtol=0)
    with pytest.raises(InputError, match=r"thrust_deduction = 1\.2: expected 0 ≤ t < 1"):
        doc["thrusters"][0]["thrust_deduction"] = 1.2
        vehicle_from_dict(doc, "s")


def test_wake_fraction_sets_the_advance_ratio_of_k_t():
    doc = ship()
    doc["thrusters"][0]["wake_fraction"] = 0.4
    ts = vehicle_from_dict(doc, "s").thrusters
    u, n, D = 0.8, 15.0, 0.08
    va = ts.advance_speed([u, 0, 0, 0, 0, 0])
    assert va[0] == pytest.approx(0.6 * u)
    J = 0.6 * u / (n * D)
    kt = 0.2931 - 0.2753 * J - 0.1385 * J**2
    assert ts.thrust([n, 0.0], va)[0] == pytest.approx(kt * RHO * n**2 * D**4, rel=1e-12)
    # the rotation rate: a propeller's rotor state, or the one inversion of its curve
    f = ts.thrust([n, 0.0], va)
    np.testing.assert_allclose(ts.rotation_rate(f, va), [n, 0.0], rtol=1e-9)
    np.testing.assert_allclose(ts.rotation_rate(f, va, command=[n, 2.0]), [n, 0.0], rtol=0)


# ------------------------------------------------------------------ surfaces


def _fin_force(fin: Fin, position, nu, u_in, n_thrusters=1, thrust_x=0.0) -> np.ndarray:
    s = SurfaceSet((ControlSurface("rudder", position, math.radians(35), fin=fin),))
    row = s.pack_fins(RHO, n_thrusters)[0]
    f = np.zeros(6)
    fin_wrench(row, 0, np.asarray(nu, float), thrust_x, np.asarray(u_in, float), len(u_in), f)
    assert row.shape == (FIN_WIDTH,)
    return f


BASE_FIN = {"axis": (0.0, 0.0, 1.0), "chord": (1.0, 0.0, 0.0), "area": 0.0539, "lift_slope": 2.747, "stall_angle": 1.4}


def test_neutral_deflection_shifts_the_fin_law():
    d0 = math.radians(2.0)
    nu = [1.0, 0.05, 0, 0, 0, 0.03]
    shifted = Fin(**BASE_FIN, neutral_deflection=d0)
    plain = Fin(**BASE_FIN)
    for d in (-0.3, 0.0, 0.1):
        np.testing.assert_allclose(
            _fin_force(shifted, (-3.5, 0, 0), nu, [d]), _fin_force(plain, (-3.5, 0, 0), nu, [d - d0]), rtol=1e-14
        )
    # at δ = δ₀ in a straight inflow the fin has no lift (and no drag: C_D0 = 0)
    np.testing.assert_allclose(_fin_force(shifted, (-3.5, 0, 0), [1.0, 0, 0, 0, 0, 0], [d0]), 0.0, atol=1e-15)


def test_neutral_deflection_and_mmg_fields_are_read_from_the_file():
    doc = ship()
    doc["control_surfaces"][0].update(
        {
            "axis": [0, 0, 1],
            "area": 0.0539,
            "lift_slope": 2.747,
            "stall_angle_deg": 20,
            "neutral_deflection_deg": 1.5,
            "slipstream": {
                "thruster": "prop",
                "inflow": "mmg",
                "epsilon": 1.09,
                "kappa": 0.5,
                "rudder_height": 0.128,
                "gamma_R_positive": 0.640,
                "gamma_R_negative": 0.395,
                "l_R": -1.42,
            },
        }
    )
    doc["thrusters"][0]["wake_fraction"] = 0.4
    fin = vehicle_from_dict(doc, "s").surfaces.surfaces[0].fin
    assert fin is not None
    assert fin.neutral_deflection == pytest.approx(math.radians(1.5))
    assert (fin.inflow, fin.race_thruster, fin.wake_fraction) == ("mmg", 0, 0.4)
    assert fin.slipstream_diameter == 0.08 and fin.eta == pytest.approx(0.08 / 0.128)
    assert (fin.epsilon, fin.kappa, fin.gamma_positive, fin.gamma_negative, fin.l_R) == (1.09, 0.5, 0.64, 0.395, -1.42)
    bad = copy.deepcopy(doc)
    bad["control_surfaces"][0]["slipstream"]["thruster"] = "screw"
    with pytest.raises(InputError, match=r"slipstream\.thruster' = 'screw': names no thruster .*prop, bow"):
        vehicle_from_dict(bad, "s")
    bad = copy.deepcopy(doc)
    bad["control_surfaces"][0]["slipstream"]["inflow"] = "race"
    with pytest.raises(InputError, match="given without 'inflow: mmg'"):
        vehicle_from_dict(bad, "s")
    bad = copy.deepcopy(doc)
    del bad["control_surfaces"][0]["area"]
    with pytest.raises(InputError, match="neutral_deflection_deg.* given without 'area'"):
        vehicle_from_dict(bad, "s")


# KVLCC2 L7 model, Yasukawa & Yoshimura 2015 (J. Mar. Sci. Technol. 20:37–52): Table 1
# (L_pp = 7.00 m, D_P = 0.216 m, H_R = 0.345 m, A_R = 0.0539 m²) and Table 3 (w_P0 = 0.40,
# k_0 = 0.2931, k_1 = −0.2753, k_2 = −0.1385, ε = 1.09, κ = 0.50, γ_R = 0.395 for β_R < 0 and
# 0.640 for β_R > 0, l'_R = −0.710, f_α = 2.747, x'_R = −0.5).
L7 = {"L": 7.00, "D": 0.216, "H_R": 0.345, "A_R": 0.0539, "w": 0.40, "k": (0.2931, -0.2753, -0.1385)}
L7.update({"eps": 1.09, "kappa": 0.50, "g_neg": 0.395, "g_pos": 0.640, "l_R": -0.710, "f_alpha": 2.747})


@pytest.mark.parametrize(("v", "r"), [(-0.05, 0.02), (0.04, -0.03), (0.0, 0.0), (0.03, 0.01)])
def test_mmg_rudder_inflow_against_the_published_formula(v, r):
    c = L7
    u, n = 1.179, 10.4  # the paper's L7 approach speed (m/s), a propeller speed (rev/s)
    L, D = c["L"], c["D"]
    # hand calculation, MMG standard method eq. (38)–(44)
    J = u * (1 - c["w"]) / (n * D)
    K_T = c["k"][0] + c["k"][1] * J + c["k"][2] * J**2
    T = RHO * n**2 * D**4 * K_T
    eta = D / c["H_R"]
    u_R = (
        c["eps"]
        * u
        * (1 - c["w"])
        * math.sqrt(eta * (1 + c["kappa"] * (math.sqrt(1 + 8 * K_T / (math.pi * J**2)) - 1)) ** 2 + (1 - eta))
    )
    U = math.hypot(u, v)
    beta = math.atan(-v / u)
    r_nd = r * L / U
    beta_R = beta - c["l_R"] * r_nd
    gamma = c["g_pos"] if beta_R > 0 else c["g_neg"]
    v_R = U * gamma * beta_R
    # the fin (hinge +z, chord +x at δ = 0: normal +y) sees u_R along the chord and −v_R across
    # it; with the MMG lift slope f_α as C_Lα and no drag: F = qS C_L (sin α, −cos α)
    alpha = math.atan2(-v_R, u_R)
    qs = 0.5 * RHO * c["A_R"] * (u_R**2 + v_R**2)
    expected = qs * c["f_alpha"] * alpha * np.array([math.sin(alpha), -math.cos(alpha)])
    fin = Fin(
        axis=(0.0, 0.0, 1.0),
        chord=(1.0, 0.0, 0.0),
        area=c["A_R"],
        lift_slope=c["f_alpha"],
        stall_angle=1.4,
        slipstream_diameter=D,
        race_thruster=0,
        inflow="mmg",
        wake_fraction=c["w"],
        epsilon=c["eps"],
        kappa=c["kappa"],
        eta=eta,
        gamma_positive=c["g_pos"],
        gamma_negative=c["g_neg"],
        l_R=c["l_R"] * L,
    )
    # the rudder on the centreline (x'_R = −0.5): its own axial speed is u
    f = _fin_force(fin, (-0.5 * L, 0.0, 0.0), [u, v, 0, 0, 0, r], [0.0, T, n])
    # rtol: the same formula rearranged (the race written without K_T/J²), rounding only
    np.testing.assert_allclose(f[:2], expected, rtol=1e-12, atol=1e-15)
    assert f[5] == pytest.approx(-0.5 * L * f[1], rel=1e-12)


def test_mmg_inflow_with_unit_constants_is_the_fully_developed_race():
    D, T = 0.1, 15.0
    common = {"slipstream_diameter": D, "race_thruster": 0}
    race = Fin(**BASE_FIN, **common)
    mmg = Fin(**BASE_FIN, **common, inflow="mmg", l_R=-1.0)
    # small drift (γ_R = 1, l_R at the rudder: the geometric inflow to first order)
    nu = [1.2, 1e-5, 0, 0, 0, 1e-5]
    for d in (0.0, 0.15):
        a, b = _fin_force(race, (-1.0, 0, 0), nu, [d, T, 20.0]), _fin_force(mmg, (-1.0, 0, 0), nu, [d, T, 20.0])
        np.testing.assert_allclose(b, a, rtol=1e-6, atol=1e-9)


def test_the_race_reads_the_thrusters_thrust_when_given_else_the_share_of_tau_x():
    D = 0.1
    fin = Fin(**BASE_FIN, slipstream_diameter=D, race_thruster=0)
    nu = [0.5, 0, 0, 0, 0, 0]
    from_input = _fin_force(fin, (-1.0, 0, 0), nu, [0.2, 30.0, 12.0], thrust_x=5.0)
    from_tau = _fin_force(fin, (-1.0, 0, 0), nu, [0.2], thrust_x=30.0)
    np.testing.assert_allclose(from_input, from_tau, rtol=1e-14)
    # the race of 30 N: u_R² = u² + 8T/(ρπD²) (momentum theory), so the lift grows by u_R²/u²
    still = _fin_force(Fin(**BASE_FIN), (-1.0, 0, 0), nu, [0.2])
    ratio = (0.25 + 8 * 30.0 / (RHO * math.pi * D**2)) / 0.25
    assert from_input[1] == pytest.approx(ratio * still[1], rel=1e-12)
