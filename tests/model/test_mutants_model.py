"""Closed forms that catch one-line mutations of the vehicle dynamics (issue #13, item 1).

Each test here was written because a deliberate mutation of ``src/`` passed the whole suite:
dropping the added-mass Coriolis matrix C_A (kinetic energy is conserved with or without it,
so the energy test cannot see it) and flipping the sign of the quaternion-normalisation term.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.vehicle import parse_vehicle
from hydrokit.model.dynamics import kinetic_energy, vehicle_dynamics
from hydrokit.simulate.compiled import make_dynamics

MASS = 10.0
INERTIA = (1.0, 1.2, 1.4)
# positive convention: a11 = −X_udot, a22 = −Y_vdot, a33 = −Z_wdot, …
ADDED = (2.0, 8.0, 9.0, 0.5, 0.6, 0.7)
DYNAMICS = {"numpy": vehicle_dynamics, "compiled": make_dynamics}


def neutral_vehicle(**changes):
    """Neutrally buoyant, r_B = r_G = 0, no damping: only the Coriolis terms act."""
    doc = {
        "name": "munk",
        "gravity": 9.81,
        "fluid": {"density": 1000.0},
        "mass": MASS,
        "volume": 0.01,  # = MASS / ρ: neutrally buoyant
        "inertia": list(INERTIA),
        "center_of_gravity": [0, 0, 0],
        "center_of_buoyancy": [0, 0, 0],
        "added_mass": list(ADDED),
        "linear_damping": [0] * 6,
        "quadratic_damping": [0] * 6,
    }
    doc.update(changes)
    return parse_vehicle(doc, "munk")


@pytest.mark.parametrize("path", ["numpy", "compiled"])
def test_munk_moment_of_a_body_translating_at_an_angle(path):
    # Newman, Marine Hydrodynamics (1977) §4.13; Fossen 2011 §6.3: a body with unequal added
    # masses translating steadily (ω = 0) feels no force but the Munk moment
    #   N = (Y_vdot − X_udot) u v (yaw),  M = (X_udot − Z_wdot) u w (pitch),  K = (Z_wdot − Y_vdot) v w
    # (roll; together the moment (M_A v) × v), destabilising: it turns the nose away from the velocity. The rigid-body Coriolis term
    # vanishes here (r_G = 0), so the whole moment comes from C_A.
    X_udot, Y_vdot, Z_wdot = -ADDED[0], -ADDED[1], -ADDED[2]
    u, v, w = 1.5, 0.4, -0.3
    f = DYNAMICS[path](neutral_vehicle(), attitude="euler")
    xdot = f(0.0, np.array([0, 0, 0, 0, 0, 0, u, v, w, 0, 0, 0], float), np.zeros(6))
    nu_dot = xdot[6:]
    N = (Y_vdot - X_udot) * u * v
    M = (X_udot - Z_wdot) * u * w
    K = (Z_wdot - Y_vdot) * v * w
    expected = [0, 0, 0, K / (INERTIA[0] + ADDED[3]), M / (INERTIA[1] + ADDED[4]), N / (INERTIA[2] + ADDED[5])]
    # one evaluation of the right-hand side: only round-off separates it from the closed form
    np.testing.assert_allclose(nu_dot, expected, rtol=1e-12, atol=1e-12)
    # nose away from the velocity: u v > 0 turns to port (ṙ < 0), u w < 0 pitches down
    assert nu_dot[5] < 0 and nu_dot[4] < 0


@pytest.mark.parametrize("path", ["numpy", "compiled"])
def test_derivative_sets_with_munk_terms_drop_c_a(path):
    # added_mass_coriolis: false (LI2021 Table 4 holds the Munk terms among its cross
    # derivatives): the same motion then has no moment at all
    f = DYNAMICS[path](neutral_vehicle(added_mass_coriolis=False), attitude="euler")
    xdot = f(0.0, np.array([0, 0, 0, 0, 0, 0, 1.5, 0.4, -0.3, 0, 0, 0], float), np.zeros(6))
    np.testing.assert_allclose(xdot[6:], 0.0, atol=1e-12)


def rk4(f, x0, dt, n):
    x = np.array(x0, float)
    out = [x.copy()]
    tau = np.zeros(6)
    for k in range(n):
        t = k * dt
        k1 = f(t, x, tau)
        k2 = f(t + dt / 2, x + dt / 2 * k1, tau)
        k3 = f(t + dt / 2, x + dt / 2 * k2, tau)
        k4 = f(t + dt, x + dt * k3, tau)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(x.copy())
    return np.array(out)


@pytest.mark.parametrize("path", ["numpy", "compiled"])
@pytest.mark.parametrize("s0", [0.9, 1.1])
def test_quaternion_norm_relaxes_to_one_as_the_logistic_closed_form(path, s0):
    # q̇ = ½ T(q) ω + ½ (1 − |q|²) q with T(q) ω ⟂ q, so s = |q|² obeys ds/dt = s (1 − s)
    # whatever the rotation: s(t) = 1 / (1 + (1/s0 − 1) e^{−t}). A wrong sign of the
    # stabilising term gives ds/dt = −s (1 − s) and s runs away from 1.
    q = np.array([0.8, 0.2, -0.4, 0.4])
    q *= math.sqrt(s0) / np.linalg.norm(q)
    x0 = np.concatenate([[0, 0, 0], q, [0.2, -0.1, 0.05, 0.3, -0.5, 0.8]])
    dt, n = 0.01, 400
    xs = rk4(DYNAMICS[path](neutral_vehicle(), attitude="quaternion"), x0, dt, n)
    t = dt * np.arange(n + 1)
    s = np.sum(xs[:, 3:7] ** 2, axis=1)
    exact = 1.0 / (1.0 + (1.0 / s0 - 1.0) * np.exp(-t))
    # RK4 at 10 ms on a logistic with unit rate: global error ~1e-10
    np.testing.assert_allclose(s, exact, rtol=1e-8)
    assert abs(s[-1] - 1.0) < 0.5 * abs(s0 - 1.0)


def test_kinetic_energy_is_half_nu_m_nu():
    # diagonal M: T = ½ Σ (M_RB + M_A)_ii ν_i², here surge and yaw only
    u, r = 1.2, 0.5
    T = kinetic_energy(neutral_vehicle(), np.array([u, 0, 0, 0, 0, r]))
    assert T == pytest.approx(0.5 * (MASS + ADDED[0]) * u * u + 0.5 * (INERTIA[2] + ADDED[5]) * r * r, rel=1e-12)


def test_zero_mass_is_refused():
    # make_vehicle itself (not only the file reader) refuses m = 0: M_A alone would still make
    # M_RB + M_A positive definite and the vehicle would build
    from hydrokit.model.vehicle import make_vehicle

    z6 = np.zeros(6)
    with pytest.raises(InputError, match="field 'mass' = 0.0: expected a positive number"):
        make_vehicle(
            "m0",
            0.0,
            0.01,
            9.81,
            1000.0,
            np.diag(INERTIA),
            np.zeros(3),
            np.zeros(3),
            np.diag(ADDED),
            np.zeros((6, 6)),
            z6,
        )


@pytest.mark.parametrize("north,east", [(0.3, 0.3), (-40.0, 10.0)])
def test_leg_course_is_the_horizontal_bearing(north, east):
    # the course of a leg is atan2(ΔE, ΔN), whatever it climbs or dives, for legs of any
    # horizontal length above the 1 µm "vertical leg" threshold (here 0.42 m and 41 m)
    from hydrokit.model.guidance import Path

    path = Path(np.array([[0.0, 0.0, 0.0], [north, east, 5.0]]), np.array([0.5]))
    assert path.initial_state(heading=1.0).heading == pytest.approx(math.atan2(east, north), abs=1e-12)
    # a purely vertical leg has no bearing: the given heading is kept
    vertical = Path(np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 5.0]]), np.array([0.5]))
    assert vertical.initial_state(heading=1.0).heading == 1.0


def test_propeller_thruster_without_loss_gives_the_open_water_thrust():
    # no thrust-loss factor given: T = K_T(0) ρ n² D⁴ at V_a = 0 (the definition of the thrust
    # coefficient K_T), with ρ = 1025 kg/m³ until a ThrusterSet binds its density
    from hydrokit.model.thrusters import Thruster

    t = Thruster("T1", (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 60.0, diameter=0.1, kt_forward=(0.4,), max_speed=40.0)
    n = 20.0
    expected = 0.4 * 1025.0 * n * n * 0.1**4
    assert t.curve.thrust(n, 0.0) == pytest.approx(expected, rel=1e-12)
    # and the inverse: the command that gives that thrust is n again
    assert t.curve.command(expected, 0.0) == pytest.approx(n, rel=1e-9)
