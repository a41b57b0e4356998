"""The compiled (numba) copies in simulate/compiled.py against their one numpy source.

Each formula exists once in numpy (core/ and model/dynamics.py); compiled.deriv and
compiled.rk4_run repeat it in scalar form for speed. These tests pin every repeated block to
its numpy source at random states, so a sign or index slip in either copy fails here:

- rotation R(Θ) and R(q)         ↔ core.kinematics.rotation_zyx / quaternion_to_rotation
- Euler and quaternion rates     ↔ core.kinematics.euler_rate_matrix / quaternion_rate
- Coriolis–centripetal C(ν) ν    ↔ core.coriolis.coriolis_force
- point drag elements            ↔ core.drag.add_drag_wrench (one law, compiled and called as Python)
- the whole right-hand side      ↔ model.dynamics.vehicle_dynamics (terms, current table)
- one RK4 step                   ↔ simulate.integrators.rk4_step
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.core.coriolis import coriolis_force
from hydrokit.core.kinematics import euler_rate_matrix, quaternion_rate, quaternion_to_rotation, rotation_zyx
from hydrokit.io.vehicle import load_vehicle, parse_vehicle
from hydrokit.model.dynamics import current_table, pack, vehicle_dynamics
from hydrokit.simulate.compiled import make_dynamics, no_drive, rk4_run
from hydrokit.simulate.integrators import rk4_step

# a current that changes over time (rows t s, v_N, v_E, v_D m/s): exercises the table slope
CURRENT = [[0.0, 0.1, -0.2, 0.05], [10.0, 0.3, 0.1, -0.05], [20.0, -0.1, 0.2, 0.0]]


def coupled_vehicle(**changes):
    """Full added mass with off-diagonals, CG and CB apart, W ≠ B, linear + quadratic damping."""
    MA = np.diag([5.0, 6, 7, 0.5, 0.6, 0.7])
    MA[0, 4] = MA[4, 0] = 0.3
    MA[1, 5] = MA[5, 1] = -0.2
    MA[2, 3] = MA[3, 2] = 0.15
    doc = {
        "name": "t",
        "gravity": 9.81,
        "fluid": {"density": 1000.0},
        "mass": 10.0,
        "volume": 0.0102,
        "inertia": [1.0, 1.2, 1.4],
        "center_of_gravity": [0.01, -0.02, 0.05],
        "center_of_buoyancy": [0.0, 0.01, -0.03],
        "added_mass": MA.tolist(),
        "linear_damping": [3, 4, 5, 0.5, 0.6, 0.7],
        "quadratic_damping": [20, 30, 40, 1, 2, 3],
    }
    doc.update(changes)
    return parse_vehicle(doc, "t")


# three point drag elements off the origin, with linear and quadratic parts on every axis
DRAG_ELEMENTS = [
    {"name": "arm", "position": [0.1, 0.75, -0.05], "linear": [2.0, 1.0, 0.5], "quadratic": [83.28, 10.0, 20.0]},
    {"name": "skid", "position": [-0.4, -0.3, 0.25], "quadratic": [15.0, 60.0, 35.0]},
    {"name": "mast", "position": [0.0, 0.0, -0.6], "linear": [4.0, 4.0, 0.0]},
]


def random_state(rng: np.random.Generator, quat: bool) -> np.ndarray:
    pos = rng.normal(size=3) * 5
    nu = rng.normal(size=6) * np.array([1.0, 0.5, 0.5, 0.4, 0.4, 0.4])
    if quat:
        q = rng.normal(size=4)
        q *= rng.uniform(0.9, 1.1) / np.linalg.norm(q)  # slightly off unit: the correction term acts
        return np.concatenate([pos, q, nu])
    att = rng.uniform(-math.pi, math.pi, 3)
    att[1] = rng.uniform(-1.4, 1.4)  # away from the θ = ±90° singularity
    return np.concatenate([pos, att, nu])


@pytest.mark.parametrize("attitude", ["euler", "quaternion"])
@pytest.mark.parametrize("vehicle", ["lingyun", "coupled", "drag-elements"])
def test_compiled_rhs_equals_numpy_at_random_states(vehicle: str, attitude: str) -> None:
    if vehicle == "lingyun":
        v = load_vehicle("lingyun")
        assert len(v.terms.names) > 0  # the general derivative terms are part of the comparison
    elif vehicle == "drag-elements":
        v = coupled_vehicle(drag_elements=DRAG_ELEMENTS)
        assert len(v.drag_elements) == 3 and pack(v).scal[8] == 3
    else:
        v = coupled_vehicle()
    f_np = vehicle_dynamics(v, CURRENT, attitude)
    f_nb = make_dynamics(v, CURRENT, attitude)
    rng = np.random.default_rng(20240611)
    for _ in range(40):
        x = random_state(rng, attitude == "quaternion")
        t = rng.uniform(-1.0, 25.0)  # before, inside and after the current table
        tau = rng.normal(size=6) * np.array([50, 50, 50, 10, 10, 10])
        a, b = f_nb(t, x, tau), f_np(t, x, tau)
        # same arithmetic in another order: agreement to round-off of the largest term
        np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-11 * (1 + np.max(np.abs(b))))
    if vehicle == "drag-elements":  # the elements are not a negligible part of what was compared
        bare = vehicle_dynamics(coupled_vehicle(), CURRENT, attitude)(t, x, tau)
        assert np.max(np.abs(b - bare)) > 0.1


@pytest.mark.parametrize("attitude", ["euler", "quaternion"])
def test_compiled_rotation_and_attitude_rates_equal_core(attitude: str) -> None:
    # no current: the position rates are R ν1 and the attitude rates T(Θ) ω or ½Ω(ω)q + the
    # norm correction ½(1 − |q|²) q, exactly as core.kinematics defines them
    v = coupled_vehicle()
    f = make_dynamics(v, None, attitude)
    rng = np.random.default_rng(7)
    for _ in range(40):
        x = random_state(rng, attitude == "quaternion")
        xd = f(0.0, x, np.zeros(6))
        if attitude == "euler":
            R = rotation_zyx(x[3], x[4], x[5])
            att_rate = euler_rate_matrix(x[3], x[4]) @ x[9:12]
            np.testing.assert_allclose(xd[0:3], R @ x[6:9], rtol=1e-12, atol=1e-13)
            np.testing.assert_allclose(xd[3:6], att_rate, rtol=1e-12, atol=1e-13)
        else:
            q = x[3:7]
            R = quaternion_to_rotation(q / np.linalg.norm(q))
            q_rate = quaternion_rate(q, x[10:13]) + 0.5 * (1.0 - q @ q) * q
            np.testing.assert_allclose(xd[0:3], R @ x[7:10], rtol=1e-12, atol=1e-13)
            np.testing.assert_allclose(xd[3:7], q_rate, rtol=1e-12, atol=1e-13)


def test_compiled_coriolis_equals_core_coriolis_force() -> None:
    # no damping, no terms, no current and W = B at one point (g = 0): what is left is
    # M ν̇ = τ − C(ν) ν with C from M_RB + M_A (Fossen 2011 Theorem 3.2)
    v = coupled_vehicle(
        linear_damping=[0] * 6, quadratic_damping=[0] * 6, volume=0.01, center_of_buoyancy=[0.01, -0.02, 0.05]
    )
    assert v.weight == pytest.approx(v.buoyancy, rel=1e-12)
    f = make_dynamics(v)
    rng = np.random.default_rng(3)
    for _ in range(40):
        x = random_state(rng, False)
        tau = rng.normal(size=6) * 5
        expected = np.linalg.solve(v.M, tau - coriolis_force(v.M_coriolis, x[6:]))
        np.testing.assert_allclose(f(0.0, x, tau)[6:], expected, rtol=1e-10, atol=1e-12)
    # C(ν) ν is not zero here: the comparison above is not trivially 0 = 0
    assert np.max(np.abs(coriolis_force(v.M_coriolis, x[6:]))) > 1e-2


def test_numpy_model_uses_core_coriolis() -> None:
    # the same isolation for the numpy model: a wrong sign in either would break one side
    v = coupled_vehicle(
        linear_damping=[0] * 6, quadratic_damping=[0] * 6, volume=0.01, center_of_buoyancy=[0.01, -0.02, 0.05]
    )
    f = vehicle_dynamics(v)
    x = np.zeros(12)
    x[6:] = [0.4, -0.3, 0.2, 0.3, -0.2, 0.5]
    expected = -np.linalg.solve(v.M, coriolis_force(v.M_coriolis, x[6:]))
    np.testing.assert_allclose(f(0.0, x, np.zeros(6))[6:], expected, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("attitude", ["euler", "quaternion"])
def test_compiled_rk4_step_equals_numpy_rk4_step(attitude: str) -> None:
    v = load_vehicle("lingyun")
    quat = attitude == "quaternion"
    p = pack(v)
    ctab = current_table(CURRENT)
    rng = np.random.default_rng(11)
    f = vehicle_dynamics(v, CURRENT, attitude)
    for _ in range(10):
        x0 = random_state(rng, quat)
        t0, dt = rng.uniform(0, 15), 0.05
        tau = rng.normal(size=6) * 20
        out = np.empty((2, x0.size))
        taken = rk4_run(
            x0,
            t0,
            dt,
            1,
            1,
            quat,
            np.concatenate([[0.0], tau])[None, :],
            ctab,
            p.V,
            no_drive(),
            out,
        )
        assert taken == 1
        expected = rk4_step(f, t0, x0, dt, u=tau)
        np.testing.assert_allclose(out[1], expected, rtol=1e-11, atol=1e-12)
        assert not np.allclose(out[1], x0)  # the step moved the state


def test_rk4_step_with_input_is_classical_rk4() -> None:
    # ẋ = λx + u, u held: one RK4 step multiplies by R(z) = 1 + z + z²/2 + z³/6 + z⁴/24 (z = λh)
    # and adds (R(z) − 1) u / λ; any wrong stage weight or half-step breaks this.
    lam, u, h, x0 = -0.7, 2.5, 0.3, 1.2
    z = lam * h
    R = 1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24
    exact_rk4 = R * x0 + (R - 1) * u / lam
    got = rk4_step(lambda t, x, uu: lam * x + uu, 0.0, np.array([x0]), h, u=np.array([u]))
    assert got[0] == pytest.approx(exact_rk4, rel=1e-14)
    # and the same step without an input is the f(t, x) form
    got0 = rk4_step(lambda t, x: lam * x, 0.0, np.array([x0]), h)
    assert got0[0] == pytest.approx(R * x0, rel=1e-14)


def test_closed_loop_uses_the_one_rk4_step_and_rotation() -> None:
    from hydrokit.core import kinematics
    from hydrokit.simulate import closed_loop as cl
    from hydrokit.simulate import integrators as integ

    assert cl.rk4_step is integ.rk4_step
    assert cl.rotation_zyx is kinematics.rotation_zyx
    assert not hasattr(cl, "_rotation_zyx")
