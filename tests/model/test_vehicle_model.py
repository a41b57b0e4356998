"""Vehicle model and simulator against closed forms (issue #3 acceptance)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError, SimulationError
from hydrokit.io.vehicle import load_vehicle, parse_vehicle
from hydrokit.model.dynamics import kinetic_energy
from hydrokit.simulate.driver import simulate


def base(**changes):
    doc = {
        "name": "t",
        "gravity": 9.81,
        "fluid": {"density": 1000.0},
        "mass": 10.0,
        "volume": 0.01,
        "inertia": [1.0, 1.2, 1.4],
        "center_of_gravity": [0, 0, 0],
        "center_of_buoyancy": [0, 0, 0],
        "added_mass": [5, 6, 7, 0.5, 0.6, 0.7],
        "linear_damping": [0] * 6,
        "quadratic_damping": [0] * 6,
    }
    doc.update(changes)
    return doc


def test_pure_surge_quadratic_drag_closed_form():
    # u(t) = u0 / (1 + d u0 t / (m + m_a))
    v = parse_vehicle(base(quadratic_damping=[20, 0, 0, 0, 0, 0]), "t")
    tr = simulate(v, 10.0, 0.001, nu0=[2, 0, 0, 0, 0, 0])
    exact = 2.0 / (1 + 20 * 2.0 * tr.time / 15.0)
    # RK4 at 1 ms: error ~1e-12; keep 1e-9 for rounding over 10 000 steps
    np.testing.assert_allclose(tr.nu[:, 0], exact, rtol=1e-9)
    np.testing.assert_allclose(tr.nu[:, 1:], 0, atol=1e-12)


def test_steady_speed_under_constant_thrust():
    # d_L u + d_Q u² = X  ->  u = (−d_L + √(d_L² + 4 d_Q X)) / (2 d_Q)
    # BlueROV2 Heavy surge damping on a neutral body with r_B = r_G (no pitch coupling)
    v = parse_vehicle(
        base(linear_damping=[13.7, 0, 33, 0, 0.8, 0], quadratic_damping=[141, 217, 190, 1.19, 0.47, 1.5]), "t"
    )
    tr = simulate(v, 60.0, 0.01, tau=[30, 0, 0, 0, 0, 0])
    u = (-13.7 + math.sqrt(13.7**2 + 4 * 141 * 30)) / (2 * 141)
    assert tr.nu[-1, 0] == pytest.approx(u, rel=1e-6)


@pytest.mark.parametrize("integrator", ["rk4", "rk4-numpy"])
def test_kinetic_energy_conserved_without_damping(integrator):
    # full 6x6 added mass with off-diagonals, off-centre CG, no damping, no restoring (B = W at
    # the same point): ½νᵀMν is invariant because C(ν) is skew-symmetric
    MA = np.diag([5.0, 6, 7, 0.5, 0.6, 0.7])
    MA[0, 4] = MA[4, 0] = 0.3
    MA[1, 5] = MA[5, 1] = -0.2
    doc = base(
        added_mass=MA.tolist(),
        center_of_gravity=[0.01, 0.0, 0.02],
        center_of_buoyancy=[0.01, 0.0, 0.02],
        volume=10.0 / 1000.0,
    )
    v = parse_vehicle(doc, "t")
    nu0 = [0.5, -0.2, 0.3, 0.4, -0.3, 0.6]
    tr = simulate(v, 10.0, 0.001, nu0=nu0, integrator=integrator, output_every=100)
    e0 = kinetic_energy(v, np.array(nu0))
    drift = max(abs(kinetic_energy(v, n) - e0) for n in tr.nu) / e0
    assert drift < 1e-8


def test_small_angle_roll_period_from_metacentric_moment():
    # B = W, r_B 0.05 m above r_G: restoring K = −W·BG·φ; T = 2π √((I_x + A_44)/(W·BG))
    doc = base(center_of_buoyancy=[0, 0, -0.05], volume=0.01)
    v = parse_vehicle(doc, "t")
    tr = simulate(v, 20.0, 0.001, eta0=[0, 0, 0, 0.01, 0, 0], output_every=10)
    phi = tr.eta[:, 3]
    ups = [tr.time[i] for i in range(1, phi.size) if phi[i - 1] < 0 <= phi[i]]
    period = np.mean(np.diff(ups))
    expected = 2 * math.pi * math.sqrt((1.0 + 0.5) / (10 * 9.81 * 0.05))
    assert period == pytest.approx(expected, rel=1e-3)


def test_compiled_equals_numpy_with_terms_and_current():
    v = load_vehicle("lingyun")
    kw = dict(tau=[30, 5, 3, 1, 2, 3], nu0=[0.2, 0.1, 0.05, 0.02, 0.01, 0.03], current_ned=[0.2, -0.1, 0.0])
    a = simulate(v, 20.0, 0.05, integrator="rk4", **kw)
    b = simulate(v, 20.0, 0.05, integrator="rk4-numpy", **kw)
    np.testing.assert_allclose(a.nu, b.nu, atol=1e-12)
    np.testing.assert_allclose(a.eta, b.eta, atol=1e-12)


def test_quaternion_and_euler_paths_agree_and_pass_90_degrees():
    v = load_vehicle("bluerov2-heavy")
    a = simulate(v, 5.0, 0.01, tau=[10, 0, 0, 0, 0.5, 0.3])
    b = simulate(v, 5.0, 0.01, tau=[10, 0, 0, 0, 0.5, 0.3], attitude="quaternion")
    np.testing.assert_allclose(a.nu, b.nu, atol=1e-7)
    # pitch through 90°: the quaternion path stays finite and near unit norm
    v2 = parse_vehicle(base(), "t")
    c = simulate(v2, 3.0, 0.001, nu0=[0, 0, 0, 0, 1.0, 0], attitude="quaternion")
    assert np.all(np.isfinite(c.eta)) and np.max(c.eta[:, 4]) > 1.5
    d = simulate(v2, 1.52, 0.001, nu0=[0, 0, 0, 0, 1.0, 0])
    assert any("singularity" in w for w in d.warnings)


@pytest.mark.parametrize("pitch_deg, warns", [(84.9, False), (85.3, True)])
def test_euler_pitch_warning_starts_at_the_documented_85_degrees(pitch_deg, warns):
    # docs/model.md: "warning when |θ| > 85°"; a held pose over two steps stays within 0.01°
    v = load_vehicle("bluerov2-heavy")
    tr = simulate(v, 0.002, 0.001, eta0=[0, 0, 0, 0, -math.radians(pitch_deg), 0])
    assert np.max(np.abs(np.degrees(tr.eta[:, 4]) + pitch_deg)) < 0.01
    assert any("singularity" in w for w in tr.warnings) is warns


def test_current_gives_relative_velocity():
    # in a uniform current a drag-only vehicle drifts to the current's speed (no thrust)
    v = load_vehicle("bluerov2-heavy")
    tr = simulate(v, 120.0, 0.01, current_ned=[0.3, 0.0, 0.0])
    assert tr.nu[-1, 0] == pytest.approx(0.3, abs=1e-3)


def test_li2021_open_loop_settles():
    # LI2021 open-loop check: τ = [30 0 3 0 0 3] with RK4; velocities settle (docs/model.md)
    v = load_vehicle("lingyun")
    tr = simulate(v, 300.0, 0.05, tau=[30, 0, 3, 0, 0, 3])
    last = tr.nu[tr.time > 250]
    assert np.max(np.ptp(last, axis=0)) < 1e-3
    assert last[-1, 0] == pytest.approx(0.474, abs=0.002)  # value stated in docs/model.md
    assert last[-1, 5] == pytest.approx(0.0768, abs=0.0005)


def test_blow_up_stops_with_time():
    doc = base(quadratic_damping=[-50, 0, 0, 0, 0, 0])  # energy fed in: u runs away
    v = parse_vehicle(doc | {"allow_negative_damping": True}, "t")  # refused unless intended
    with pytest.raises(SimulationError, match=r"non-finite at t = "):
        simulate(v, 100.0, 0.01, nu0=[1, 0, 0, 0, 0, 0])


def test_batch_equals_single():
    from hydrokit.simulate.batch import simulate_batch

    vs = [parse_vehicle(base(quadratic_damping=[10 + k, 20, 30, 1, 1, 1]), "t") for k in range(4)]
    res = simulate_batch(vs, 5.0, 0.01, tau=[5, 1, 2, 0.1, 0.1, 0.2])
    for k, v in enumerate(vs):
        single = simulate(v, 5.0, 0.01, tau=[5, 1, 2, 0.1, 0.1, 0.2])
        np.testing.assert_allclose(res["states"][k, -1, 6:], single.nu[-1], atol=1e-13)
    assert np.all(res["steps"] == 500)


@pytest.mark.parametrize(
    "change,match",
    [
        (
            {
                "added_mass": [
                    [5, 0, 0, 0, 0, 0],
                    [0, 6, 0, 0, 0, 0],
                    [0, 0, 7, 0, 0, 0],
                    [0, 0, 0, 0.5, 0, 0],
                    [0, 0, 0, 0, 0.6, 0],
                    [3, 0, 0, 0, 0, 0.7],
                ]
            },
            "not symmetric",
        ),
        ({"added_mass": [-50, 6, 7, 0.5, 0.6, 0.7]}, "not positive definite"),
        ({"added_mass": [5, 6, 7]}, "'added_mass' has 3 values; expected 6"),
        ({"mass": float("nan")}, "'mass'"),
        ({"terms": {"X_ux": -1.0}}, "term 'X_ux'"),
        ({"inertia": [1, 2]}, "'inertia' has 2 values"),
        ({"inertia": [0.2, 0.3, 0.0]}, r"'inertia' = .*: expected a positive definite tensor"),  # a zero moment
    ],
)
def test_bad_vehicle_input(change, match):
    with pytest.raises(InputError, match=match):
        parse_vehicle(base(**change), "veh.yaml")


def test_missing_field():
    doc = base()
    del doc["volume"]
    with pytest.raises(InputError, match="missing field 'volume'"):
        parse_vehicle(doc, "veh.yaml")


def test_tiny_asymmetry_is_symmetrised_with_warning():
    # like the public RexROV matrix's 10.774 vs 10.775
    MA = np.diag([5.0, 6, 7, 0.5, 0.6, 0.7])
    MA[0, 4], MA[4, 0] = 10.774e-3, 10.775e-3
    v = parse_vehicle(base(added_mass=MA.tolist()), "t")
    assert any("symmetrised" in w for w in v.warnings)
    np.testing.assert_allclose(v.M_A, v.M_A.T)


def test_li2021_table4_loads_as_data(lingyun_reference):
    v = load_vehicle("lingyun")
    # X_udot = −5.8589e-2 (LI2021 Table 4) scaled by ½ρL³ → added mass 58.70 kg
    assert v.M_A[0, 0] == pytest.approx(5.8589e-2 * 0.5 * 1025.9 * 1.25**3, rel=1e-9)
    assert v.mass == lingyun_reference["properties"]["mass"]
    assert len(v.terms.names) >= 30
