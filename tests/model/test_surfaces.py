"""Control surfaces (issue #45): the fin law against closed forms, its continuity through stall,
the servo, delta() terms, planar models and the vehicle-file fields."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.vehicle import parse_vehicle
from hydrokit.model.dynamics import pack, vehicle_dynamics
from hydrokit.model.surfaces import (
    FIN_WIDTH,
    ControlSurface,
    Fin,
    SurfaceSet,
    fin_wrench,
    helmbold_lift_slope,
    section_coefficients,
    servo_step,
)
from hydrokit.model.terms import DELTA, parse_term

RHO = 1025.0


def _fin(
    axis=(0.0, 0.0, 1.0), area=0.02, ar=2.0, stall_deg=15.0, cd0=0.008, e=0.9, slip=0.0, position=(-0.6, 0.0, 0.0)
):
    chord = np.array([1.0, 0.0, 0.0]) - axis[0] * np.asarray(axis)
    chord /= np.linalg.norm(chord)
    fin = Fin(
        axis=axis,
        chord=tuple(chord),
        area=area,
        lift_slope=helmbold_lift_slope(ar),
        stall_angle=math.radians(stall_deg),
        drag_coefficient=cd0,
        aspect_ratio=ar,
        oswald=e,
        slipstream_diameter=slip,
    )
    return SurfaceSet((ControlSurface("s", position, math.radians(30), fin=fin),))


def _wrench(surfaces, nu, delta, thrust_x=0.0):
    rows = surfaces.pack_fins(RHO)
    f = np.zeros(6)
    d = np.asarray(delta, float)
    for e in range(rows.shape[0]):
        fin_wrench(rows.ravel(), FIN_WIDTH * e, np.asarray(nu, float), thrust_x, d, d.size, f)
    return f


def test_helmbold_slope_tends_to_thin_airfoil_and_slender_body_limits():
    # AR → ∞: 2π (thin aerofoil); AR → 0: π AR / 2 (Jones' slender wing)
    assert helmbold_lift_slope(1e6) == pytest.approx(2 * math.pi, rel=1e-5)
    assert helmbold_lift_slope(1e-4) == pytest.approx(math.pi * 1e-4 / 2, rel=1e-3)


@pytest.mark.parametrize("delta_deg", [-12.0, -3.0, 2.0, 8.0, 14.0])
def test_rudder_below_stall_gives_the_lifting_line_force(delta_deg):
    # closed form: L = ½ρU²S C_Lα α, D = ½ρU²S (C_D0 + C_L²/(π e AR)), α = −δ (module docstring);
    # in body axes (U along x): X = −D, Y = L·sign … exactly: F = L ⊥ inflow, D ∥ inflow
    U, S, AR, e, cd0 = 1.5, 0.02, 2.0, 0.9, 0.008
    d = math.radians(delta_deg)
    f = _wrench(_fin(area=S, ar=AR, e=e, cd0=cd0), [U, 0, 0, 0, 0, 0], [d])
    cl = helmbold_lift_slope(AR) * d
    q = 0.5 * RHO * U**2 * S
    lift, drag = q * cl, q * (cd0 + cl**2 / (math.pi * e * AR))
    np.testing.assert_allclose(f[:3], [-drag, lift, 0.0], rtol=1e-12, atol=1e-12)
    # the moment is r × F about the origin (fin at x = −0.6 m)
    np.testing.assert_allclose(f[3:], np.cross([-0.6, 0, 0], f[:3]), rtol=1e-12, atol=1e-12)


def test_signs_are_prestero_s():
    # Prestero 2001: Y_uuδr > 0, N_uuδr < 0 (rudder aft); Z_uuδs < 0, M_uuδs < 0 (stern plane aft)
    rudder = _wrench(_fin(axis=(0.0, 0.0, 1.0)), [1.5, 0, 0, 0, 0, 0], [0.1])
    plane = _wrench(_fin(axis=(0.0, 1.0, 0.0)), [1.5, 0, 0, 0, 0, 0], [0.1])
    assert rudder[1] > 0 and rudder[5] < 0 and abs(rudder[2]) < 1e-12
    assert plane[2] < 0 and plane[4] < 0 and abs(plane[1]) < 1e-12


def test_angle_of_attack_comes_from_the_fins_own_inflow():
    # δ = 0 but the vehicle yaws at r: the fin at x = −0.6 m moves at v_f = (U, −0.6 r, 0) through
    # the water (ω × r), so it meets the flow at α = atan(0.6 r / U) and its lift, ⟂ v_f, pushes
    # against its sideways motion: a yaw-damping moment (the rudder's share of N_r)
    U, r, S, AR, e, cd0 = 1.5, 0.3, 0.02, 2.0, 0.9, 0.008
    f = _wrench(_fin(area=S, ar=AR, e=e, cd0=cd0), [U, 0, 0, 0, 0, r], [0.0])
    v = np.array([U, -0.6 * r, 0.0])
    speed = np.linalg.norm(v)
    alpha = math.atan2(0.6 * r, U)
    q = 0.5 * RHO * speed**2 * S
    cl = helmbold_lift_slope(AR) * alpha
    along, across = v / speed, np.array([-v[1], v[0], 0.0]) / speed  # across: ⟂ v_f, towards +y
    expect = -q * (cd0 + cl**2 / (math.pi * e * AR)) * along + q * cl * across
    np.testing.assert_allclose(f[:3], expect, rtol=1e-12)
    assert f[1] > 0 and f[5] < 0 < r  # pushed to starboard at the stern: N opposes r


def test_lift_is_continuous_through_stall_and_falls_to_the_flat_plate():
    slope, stall = helmbold_lift_slope(2.0), math.radians(15.0)
    a = np.linspace(0.0, math.radians(90.0), 9001)
    c = np.array([section_coefficients(x, slope, stall) for x in a])
    step = a[1] - a[0]
    # continuous: no jump larger than a steep slope times the step (C_Lα ≤ 2π; blend slope < 10)
    assert np.max(np.abs(np.diff(c[:, 0]))) < 10 * step
    assert np.max(np.abs(np.diff(c[:, 1]))) < 10 * step
    k = int(np.argmax(c[:, 0]))
    assert a[k] == pytest.approx(stall, abs=2 * step)  # lift peaks at the stall angle
    # beyond the blend: the flat plate's normal force, C_L = 1.2 sin α cos α, C_D = 1.2 sin² α
    for x in (math.radians(40.0), math.radians(60.0), math.radians(90.0)):
        cl, cd = section_coefficients(x, slope, stall)
        assert cl == pytest.approx(1.2 * math.sin(x) * math.cos(x), abs=1e-12)
        assert cd == pytest.approx(1.2 * math.sin(x) ** 2, abs=1e-12)
    assert section_coefficients(math.radians(30.0), slope, stall)[0] < slope * stall  # stalled


def test_section_is_odd_in_alpha_and_flow_from_behind_folds():
    slope, stall = 3.0, 0.25
    for x in (0.1, 0.3, 0.7, 1.2):
        assert section_coefficients(-x, slope, stall)[0] == pytest.approx(-section_coefficients(x, slope, stall)[0])
        assert section_coefficients(-x, slope, stall)[1] == pytest.approx(section_coefficients(x, slope, stall)[1])
    # a fin dragged backwards along its chord: drag only, no lift
    f = _wrench(_fin(), [-1.0, 0, 0, 0, 0, 0], [0.0])
    assert f[0] > 0 and abs(f[1]) < 1e-12


def test_propeller_race_raises_the_rudder_inflow_by_momentum_theory():
    # at rest with thrust T the rudder sees √(8T/(ρπD²)) (fully developed race)
    T, D, d = 40.0, 0.1, math.radians(10.0)
    f = _wrench(_fin(slip=D), [0, 0, 0, 0, 0, 0], [d], thrust_x=T)
    u_race = math.sqrt(8 * T / (RHO * math.pi * D**2))
    g = _wrench(_fin(slip=0.0), [u_race, 0, 0, 0, 0, 0], [d])
    np.testing.assert_allclose(f, g, rtol=1e-12)
    assert np.all(_wrench(_fin(slip=D), [0, 0, 0, 0, 0, 0], [d], thrust_x=-T) == 0)  # astern: no race, no inflow


def test_servo_rate_limit_lag_and_mechanical_limit():
    lim, n = np.array([0.5]), 1
    out = np.zeros(n)
    servo_step(np.zeros(n), np.array([0.3]), 0.1, lim, np.array([math.inf]), np.zeros(n), out)
    assert out[0] == 0.3  # no lag, no rate limit: the command at once
    servo_step(np.zeros(n), np.array([0.9]), 0.1, lim, np.array([math.inf]), np.zeros(n), out)
    assert out[0] == 0.5  # the mechanical limit
    d = np.zeros(n)
    for _ in range(10):
        servo_step(d, np.array([0.4]), 0.1, lim, np.array([0.2]), np.zeros(n), out)
        d = out.copy()
    assert d[0] == pytest.approx(0.2)  # 1 s at 0.2 rad/s
    d = np.zeros(n)
    for _ in range(100):
        servo_step(d, np.array([0.4]), 0.01, lim, np.array([math.inf]), np.array([0.5]), out)
        d = out.copy()
    assert d[0] == pytest.approx(0.4 * (1 - math.exp(-1.0 / 0.5)), rel=1e-12)  # exact first-order step


def test_delta_terms_parse_scale_and_evaluate():
    t = parse_term("Y_uu*delta(rudder)", surfaces=("sternplane", "rudder"))
    assert t.factors[-1].kind == DELTA and t.surfaces == (1,)
    assert t.scale_power() == parse_term("Y_uu").scale_power() and t.order() == 2
    assert parse_term("X_uu*delta(rudder)^2", surfaces=("rudder",)).factors[-1] == t.factors[-1].__class__(DELTA, (0,))
    with pytest.raises(InputError, match=r"delta\(rudde\) names no control surface.*rudder"):
        parse_term("Y_uu*delta(rudde)", surfaces=("rudder",))
    with pytest.raises(InputError, match=r"'\^' must follow a factor"):
        parse_term("Y_^2", surfaces=())


VEHICLE = {
    "name": "finned",
    "mass": 30.0,
    "volume": 30.0 / 1025.0,
    "fluid": {"density": 1025.0},
    "inertia": [0.2, 3.4, 3.4],
    "center_of_gravity": [0, 0, 0],
    "center_of_buoyancy": [0, 0, 0],
    "added_mass": [1.0, 35.0, 35.0, 0.1, 4.9, 4.9],
    "linear_damping": [1, 5, 5, 0.5, 2, 2],
    "quadratic_damping": [1.6, 130, 130, 0.13, 90, 90],
    "control_surfaces": [
        {"name": "rudder", "position": [-0.6, 0, 0], "max_deflection_deg": 15},
        {
            "name": "fin",
            "position": [-0.6, 0, 0.1],
            "max_deflection_deg": 20,
            "axis": [0, 0, 1],
            "area": 0.02,
            "aspect_ratio": 2,
            "stall_angle_deg": 15,
        },
    ],
    "terms": {"Y_uu*delta(rudder)": 9.64, "N_uu*delta(rudder)": -6.15, "X_uu*delta(rudder)^2": -2.0},
}


def test_delta_terms_give_coefficient_times_product():
    v = parse_vehicle(dict(VEHICLE), "v.yaml")
    u, d = 1.3, 0.12
    f = v.terms.force(np.array([u, 0, 0, 0, 0, 0]), np.array([d, 0.0]))
    np.testing.assert_allclose(f, [-2.0 * u * u * d * d, 9.64 * u * u * d, 0, 0, 0, -6.15 * u * u * d], rtol=1e-14)


def test_compiled_and_numpy_right_hand_sides_agree_with_fins_and_delta_terms():
    from hydrokit.simulate.compiled import make_dynamics

    v = parse_vehicle(dict(VEHICLE), "v.yaml")
    rng = np.random.default_rng(3)
    f_np, f_c = vehicle_dynamics(v), make_dynamics(v)
    for _ in range(20):
        x = np.concatenate([rng.normal(size=3), rng.normal(scale=0.3, size=3), rng.normal(size=6)])
        tau, d = rng.normal(size=6) * 10, rng.uniform(-0.3, 0.3, size=2)
        np.testing.assert_allclose(f_c(0.0, x, tau, d), f_np(0.0, x, tau, d), rtol=1e-10, atol=1e-10)


def test_fin_force_enters_the_model():
    # the fin's wrench, at a state, is exactly the difference the deflection makes to M ν̇
    v = parse_vehicle(dict(VEHICLE), "v.yaml")
    f = vehicle_dynamics(v)
    x = np.zeros(12)
    x[6] = 1.5
    a0, a1 = f(0.0, x, np.zeros(6), np.array([0.0, 0.0])), f(0.0, x, np.zeros(6), np.array([0.0, 0.2]))
    wrench = v.M @ (a1[6:] - a0[6:])
    fins = SurfaceSet(v.surfaces.surfaces[1:])
    expect = _wrench(fins, x[6:], [0.2]) - _wrench(fins, x[6:], [0.0])
    np.testing.assert_allclose(wrench, expect, rtol=1e-9, atol=1e-12)


def test_planar_model_solves_its_reduced_equations():
    data = dict(VEHICLE, dofs=["surge", "sway", "yaw"])
    data["added_mass"] = [
        [1, 0, 0, 0, 0, 0],
        [0, 35, 0, 2, 0, 1.9],
        [0, 0, 35, 0, -1.9, 0],
        [0, 2, 0, 0.1, 0, 0],
        [0, 0, -1.9, 0, 4.9, 0],
        [0, 1.9, 0, 0, 0, 4.9],
    ]
    v = parse_vehicle(data, "v.yaml")
    assert v.dofs == (0, 1, 5)
    x = np.zeros(12)
    x[6], x[7], x[11] = 1.2, 0.1, 0.2
    tau = np.array([5.0, 1.0, 3.0, 4.0, 2.0, 0.5])
    xd = vehicle_dynamics(v)(0.0, x, tau, np.array([0.1, 0.05]))
    assert np.all(xd[[2, 3, 4, 8, 9, 10]] == 0)  # heave, roll, pitch held
    # kept accelerations from M_kk ν̇_k = f_k: f from the full model's M ν̇ at the same state
    full = parse_vehicle({k: w for k, w in data.items() if k != "dofs"}, "v.yaml")
    fd = vehicle_dynamics(full)(0.0, x, tau, np.array([0.1, 0.05]))
    force = full.M @ fd[6:]
    k = [0, 1, 5]
    np.testing.assert_allclose(xd[6:][k], np.linalg.solve(v.M[np.ix_(k, k)], force[k]), rtol=1e-10)
    assert not np.allclose(xd[6:][k], fd[6:][k])  # the 6-DOF rows differ: the coupling to roll is dropped


def test_planar_and_six_dof_agree_on_a_symmetric_vehicle():
    # a vehicle symmetric about its xy plane with r_G = r_B: a rudder turn never leaves the plane,
    # so the 3-DOF and the 6-DOF trajectories must coincide (two integrations of one physics)
    from hydrokit.simulate.driver import simulate

    surfaces = [VEHICLE["control_surfaces"][0], dict(VEHICLE["control_surfaces"][1], position=[-0.6, 0, 0])]
    six = parse_vehicle(dict(VEHICLE, control_surfaces=surfaces), "v.yaml")
    three = parse_vehicle(dict(VEHICLE, control_surfaces=surfaces, dofs=["surge", "sway", "yaw"]), "v.yaml")
    args = dict(tau=(4.0, 0, 0, 0, 0, 0), nu0=(1.5, 0, 0, 0, 0, 0), deflection=[0.15, 0.05])
    a = simulate(six, 20.0, 0.02, **args)
    b = simulate(three, 20.0, 0.02, **args)
    assert abs(a.eta[-1, 5]) > 0.5  # it turned
    np.testing.assert_allclose(a.eta, b.eta, atol=1e-9)


def test_deflection_table_and_constant_agree_and_limits_are_enforced():
    from hydrokit.simulate.driver import simulate

    v = parse_vehicle(dict(VEHICLE), "v.yaml")
    a = simulate(v, 5.0, 0.01, tau=(4, 0, 0, 0, 0, 0), deflection=[0.1, 0.0])
    b = simulate(v, 5.0, 0.01, tau=(4, 0, 0, 0, 0, 0), deflection=[[0, 0.1, 0.0], [3, 0.1, 0.0]])
    np.testing.assert_allclose(a.eta, b.eta, rtol=0, atol=1e-12)
    with pytest.raises(InputError, match=r"rudder = 20°: expected at most 15°"):
        simulate(v, 1.0, 0.01, deflection=[math.radians(20), 0])
    with pytest.raises(InputError, match=r"expected 2 values"):
        simulate(v, 1.0, 0.01, deflection=[0.1])


BAD = [
    ({"terms": {"Y_uu*delta(aileron)": 1.0}}, r"delta\(aileron\) names no control surface"),
    (
        {"control_surfaces": [dict(VEHICLE["control_surfaces"][1], stall_angle_deg=0)]},
        r"stall_angle_deg' = 0: expected an angle in \(0, 90\)",
    ),
    (
        {"control_surfaces": [dict(VEHICLE["control_surfaces"][1], axis=[0, 0, 0])]},
        r"axis' = \[0.0, 0.0, 0.0\]: expected a vector of non-zero length",
    ),
    ({"dofs": ["surge", "sway", "yawn"]}, r"dofs\[2\]' = 'yawn': expected one of surge"),
    ({"dofs": ["surge", "yaw", "yaw"]}, r"dofs\[2\]' = 'yaw': repeated"),
    (
        {"control_surfaces": [{"name": "r", "position": [0, 0, 0], "max_deflection_deg": 10, "lift_slope": 3}]},
        r"lift_slope given without 'area'",
    ),
    ({"control_surfaces": [{"name": "r", "position": [0, 0, 0]}]}, r"missing 'max_deflection_deg'"),
    ({"control_surfaces": [VEHICLE["control_surfaces"][0]] * 2}, r"expected a unique name"),
]


@pytest.mark.parametrize(("change", "message"), BAD)
def test_bad_surface_fields_are_one_line_errors(change, message):
    data = dict(VEHICLE)
    if "terms" not in change:
        data["terms"] = {}
    data.update(change)
    with pytest.raises(InputError, match=message) as err:
        parse_vehicle(data, "bad.yaml")
    assert "\n" not in str(err.value) and "bad.yaml" in str(err.value)


def test_pack_holds_mask_and_fins():
    v = parse_vehicle(dict(VEHICLE, dofs=["surge", "sway", "yaw"]), "v.yaml")
    p = pack(v)
    assert p.scal[9:15].tolist() == [1, 1, 0, 0, 0, 1] and p.scal[15] == 1
    np.testing.assert_array_equal(p.scal[16 : 16 + FIN_WIDTH], v.surfaces.pack_fins(v.density)[0])
    assert np.all(p.Minv[[2, 3, 4]] == 0) and np.all(p.Minv[:, [2, 3, 4]] == 0)


def test_batch_and_samples_fly_the_same_deflections():
    # the compiled batch (fleets, --samples) carries the deflection columns like the single run
    from hydrokit.simulate.batch import simulate_batch
    from hydrokit.simulate.driver import simulate

    v = parse_vehicle(dict(VEHICLE), "v.yaml")
    one = simulate(v, 4.0, 0.01, tau=(4, 0, 0, 0, 0, 0), nu0=(1.5, 0, 0, 0, 0, 0), deflection=[0.1, -0.05])
    both = simulate_batch([v, v], 4.0, 0.01, (4, 0, 0, 0, 0, 0), nu0=(1.5, 0, 0, 0, 0, 0), deflection=[0.1, -0.05])
    np.testing.assert_allclose(
        both.states[:, -1, :], np.stack([np.concatenate([one.eta[-1], one.nu[-1]])] * 2), atol=1e-12
    )
    assert abs(one.eta[-1, 5]) > 0.01  # the deflection did something
    with pytest.raises(InputError, match=r"one constant deflection per control surface"):
        simulate_batch([v], 1.0, 0.01, deflection=[[0, 0.1, 0], [1, 0.2, 0]])
