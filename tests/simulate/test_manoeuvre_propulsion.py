"""Manoeuvres propelled by the vehicle's thrusters at held commands (``run_manoeuvre(commands=…)``)
against a constant force, closed forms of the propeller's open-water curve and the rotor lag.

The boat: planar, surge resistance 20 u|u| N (quadratic_damping), a rudder by delta() terms, a
propeller astern (D = 0.2 m, K_T(J) = 0.4 − 0.4 J, wake fraction 0.1, rotor lag 0.3 s) and an
ideal (force-commanded) thruster on the centreline.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.manoeuvre import run as M

RHO, D, W, DRAG = 1025.0, 0.2, 0.1, 20.0  # kg/m³, m, –, N·s²/m²
KT0, KT1 = 0.4, 0.4  # K_T(J) = KT0 − KT1 J

BOAT = f"""
name: boat
mass: 100.0
volume: 0.09756
inertia: [10, 50, 50]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [10, 80, 80, 1, 20, 20]
linear_damping: [0, 40, 0, 0, 0, 30]
quadratic_damping: [{DRAG}, 0, 0, 0, 0, 0]
reference_length: 2.0
fluid: {{density: {RHO}}}
dofs: [surge, sway, yaw]
control_surfaces:
  - {{name: rudder, position: [-1.0, 0, 0], max_deflection_deg: 35}}
terms:
  Y_uu*delta(rudder): 20.0
  N_uu*delta(rudder): -20.0
thrusters:
  - {{name: prop, position: [-1.0, 0, 0], direction: [1, 0, 0], max_thrust: 500, diameter: {D},
     kt_forward: [{-KT1}, {KT0}], max_rpm: 1800, wake_fraction: {W}, time_constant: 0.3}}
  - {{name: main, position: [-0.5, 0, 0], direction: [1, 0, 0], max_thrust: 100}}
"""


def boat(text=BOAT):
    from hydrokit.api import vehicle_from_dict

    return vehicle_from_dict(yaml.safe_load(text), "inline")


def steady_speed(n):
    """u where the propeller's thrust K_T(J) ρ D⁴ n² with J = (1 − w) u / (n D) equals DRAG u²: the
    positive root of DRAG u² + KT1 ρ D³ n (1 − w) u − KT0 ρ D⁴ n² = 0."""
    b = KT1 * RHO * D**3 * n * (1 - W)
    c = KT0 * RHO * D**4 * n**2
    return (-b + math.sqrt(b * b + 4 * DRAG * c)) / (2 * DRAG)


def test_ideal_thruster_command_is_the_same_constant_force():
    """An ideal thruster on the centreline pushing 40 N ahead, without lag, is the force (40, 0, …):
    τ = T f = [40, 0, 0, 0, 0, 0] exactly (its moment arm r × e is zero), so the track is the same
    to the last bit; and --force adds to the thrusters' force (30 N + 10 N)."""
    v = boat()
    zz = M.turning_circle(math.radians(35))
    kw = {"dt": 0.1, "duration": 30.0}  # past 180°: every metric but the steady ones
    ref = M.run_manoeuvre(v, zz, tau=(40, 0, 0, 0, 0, 0), **kw)
    cmd = M.run_manoeuvre(v, zz, commands={"main": 40.0}, **kw)
    both = M.run_manoeuvre(v, zz, tau=(10, 0, 0, 0, 0, 0), commands={"main": 30.0}, **kw)
    assert ref.metrics["tactical_diameter"] is not None
    np.testing.assert_array_equal(cmd.array(), ref.array())
    np.testing.assert_array_equal(both.array(), ref.array())
    assert cmd.metrics == ref.metrics
    assert cmd.propulsion is not None and ref.propulsion is None
    assert cmd.propulsion["thrust_at_execute"] == {"prop": 0.0, "main": 40.0}
    assert cmd.propulsion["command_units"] == {"prop": "rev/s", "main": "N"}
    assert cmd.to_dict()["propulsion"]["commands"] == {"prop": 0.0, "main": 40.0}


def test_propeller_steady_straight_speed_from_the_open_water_curve():
    """At 20 rev/s the approach settles where K_T(J) ρ D⁴ n² = 20 u² (closed form, checked by brentq
    on the drag balance). The approach ends when u varies by ≤ 1e-4 of itself over 2 s; the surge
    mode decays at λ = (2·20 u + KT1 ρ D³ n (1−w)) / 110 kg ≈ 1.4 /s, so what is left is
    ≤ 1e-4 e^(−2λ)/(1 − e^(−2λ)) ≈ 7e-6 of u: rtol 2e-5."""
    from scipy.optimize import brentq

    n = 20.0
    u_ref = steady_speed(n)
    u_root = brentq(lambda u: (KT0 - KT1 * (1 - W) * u / (n * D)) * RHO * D**4 * n**2 - DRAG * u * u, 0.1, 10.0)
    assert u_root == pytest.approx(u_ref, rel=1e-12)  # the two references agree
    res = M.run_manoeuvre(boat(), M.turning_circle(math.radians(35)), commands={"prop": n}, dt=0.1, duration=5.0)
    assert res.approach_speed == pytest.approx(u_ref, rel=2e-5)
    # the thrust reported at the execute balances the drag there (the same tolerance, doubled: u²)
    assert res.propulsion["thrust_at_execute"]["prop"] == pytest.approx(DRAG * u_ref**2, rel=4e-5)
    assert res.propulsion["thrust_at_execute"]["main"] == 0.0


def test_rotor_lag_from_rest_and_the_advance_speed_in_a_current():
    """The rotor follows n(1 − e^(−t/τ)) from rest; a stage h s into a step reads the rotor at
    that instant (closed form of the first-order lag, to round-off), and the rotation rate the
    ``n()`` factors read is that rotor state; the advance speed is the velocity through the
    water: u = 2 m/s heading north in a 0.5 m/s current from the south (flowing north) gives
    V_a = (1 − w)(2 − 0.5) m/s."""
    v = boat()
    n, tau_r, dt = 20.0, 0.3, 0.05
    drive = M.ThrusterDrive(v.thrusters, [n, 0.0], current_ned=[0.5, 0.0, 0.0])
    x = np.zeros(12)
    x[6] = 2.0
    for k in range(1, 8):
        drive.begin_step((k - 1) * dt, dt)
        assert drive.c[0] == pytest.approx(n * (1 - math.exp(-k * dt / tau_r)), rel=1e-13)
        for h in (0.0, 0.5 * dt, dt):
            rotor = n * (1 - math.exp(-((k - 1) * dt + h) / tau_r))
            J = (1 - W) * 1.5 / (rotor * D) if rotor > 0 else math.inf
            thrust = (KT0 - KT1 * J) * RHO * D**4 * rotor**2 if J < 1 else 0.0  # K_T clamped at ≥ 0
            tau, f, rate = drive.inputs((k - 1) * dt + h, x, h)
            assert f[0] == pytest.approx(thrust, rel=1e-12, abs=1e-12)
            assert rate[0] == pytest.approx(rotor, rel=1e-13)
            np.testing.assert_allclose(tau, [thrust, 0, 0, 0, 0, 0], rtol=1e-12, atol=1e-12)
        # between steps: the rotor state now, the step's end
        J = (1 - W) * 1.5 / (drive.c[0] * D)
        thrust = (KT0 - KT1 * J) * RHO * D**4 * drive.c[0] ** 2 if J < 1 else 0.0
        assert drive.thrust(x)[0] == pytest.approx(thrust, rel=1e-12, abs=1e-12)
        np.testing.assert_allclose(drive(x), [thrust, 0, 0, 0, 0, 0], rtol=1e-12, atol=1e-12)


def test_a_propeller_loses_less_speed_in_a_turn_than_a_constant_force():
    """The same boat and approach speed, propelled once by the propeller at 20 rev/s and once by the
    constant force the propeller gives on the approach: in the turn the boat slows, J falls and the
    propeller's K_T(J) rises, so its thrust grows while the force stays — the propeller keeps
    more speed. The thrust at the end is K_T(J) ρ D⁴ n² at the final surge speed (closed form)."""
    v = boat()
    n = 20.0
    tc = M.turning_circle(math.radians(35))
    kw = {"dt": 0.1, "duration": 300.0}
    prop = M.run_manoeuvre(v, tc, commands={"prop": n}, **kw)
    f0 = prop.propulsion["thrust_at_execute"]["prop"]
    const = M.run_manoeuvre(v, tc, tau=(f0, 0, 0, 0, 0, 0), **kw)
    assert prop.problem is None and const.problem is None
    # the same approach: the force is the propeller's thrust there (the approach settles to 1e-5)
    assert prop.approach_speed == pytest.approx(const.approach_speed, rel=2e-5)
    up, uc = prop.metrics["steady_speed"], const.metrics["steady_speed"]
    assert up > 1.2 * uc  # measured 1.25 against 0.91 m/s: well apart
    assert prop.propulsion["thrust_at_end"]["prop"] > 1.5 * f0
    u_end = float(prop.nu[-1, 0])
    J = (1 - W) * u_end / (n * D)
    assert prop.propulsion["thrust_at_end"]["prop"] == pytest.approx((KT0 - KT1 * J) * RHO * D**4 * n**2, rel=1e-12)


RACE = ", slipstream: {diameter: 0.2, thrust_share: 1.0}"


def fin_boat(race):
    """The boat with a physical rudder (a fin of 0.02 m², AR 1.5, on the centreline) instead of the delta() terms, in
    the propeller's race when ``race`` is :data:`RACE` (else "")."""
    fin = (
        "  - {name: rudder, position: [-1.1, 0, 0], max_deflection_deg: 35, axis: [0, 0, 1], area: 0.02, "
        f"aspect_ratio: 1.5, stall_angle_deg: 20{race}}}"
    )
    text = BOAT.replace("  - {name: rudder, position: [-1.0, 0, 0], max_deflection_deg: 35}", fin)
    return boat(text.replace("  Y_uu*delta(rudder): 20.0\n  N_uu*delta(rudder): -20.0\n", "  X_u: 0.0\n"))


def test_a_rudder_in_the_race_sees_the_propellers_thrust():
    """A physical rudder in the propeller race sees the axial speed V² = u² + 8T/(ρπD²) (momentum
    theory), T the commanded propeller's thrust. At the execute (straight and steady: v = r = 0, so
    the angle of attack is δ with or without the race) the fin force, and with it the initial yaw
    acceleration, scales with V²: with the race / without = 1 + 8T/(ρπD²u²) = 1 + 8·20/(ρπD²), as
    T = 20 u² on the straight approach (the fin has no drag at zero lift: C_D0 = 0). Were the
    thrusters' force not passed as τ_X the ratio would be 1.

    ṙ(0) from the record by ṙ(0) ≈ (4 r(dt) − r(2dt)) / (2 dt), error O(dt²): the yaw and sway
    rates change on a time scale ≳ 0.3 s, so ≲ (0.01 s / 0.3 s)² ≈ 1e-3 (measured: 8e-5) → rtol 1e-3.
    The approach starts at the closed-form speed, so it settles soon (the rotors spin up from rest)."""
    dt = 0.01
    tc = M.turning_circle(math.radians(10))
    kw = {"commands": {"prop": 20.0}, "dt": dt, "duration": 2 * dt, "nu0": (steady_speed(20.0), 0, 0, 0, 0, 0)}

    def rdot0(v):
        res = M.run_manoeuvre(v, tc, **kw)
        k = int(np.searchsorted(res.time, 0.0))
        assert res.nu[k, 5] == 0.0 and res.nu[k, 1] == 0.0  # the straight approach
        return (4 * res.nu[k + 1, 5] - res.nu[k + 2, 5]) / (2 * dt)

    ratio = rdot0(fin_boat(RACE)) / rdot0(fin_boat(""))
    assert ratio == pytest.approx(1 + 8 * DRAG / (RHO * math.pi * D**2), rel=1e-3)


def test_bad_commands():
    v = boat()
    tc = M.turning_circle(0.3)
    with pytest.raises(InputError, match=r"command 'bow': the vehicle has thrusters prop, main; expected one of them"):
        M.run_manoeuvre(v, tc, commands={"bow": 1.0})
    with pytest.raises(
        InputError, match=r"command prop=40 rev/s: expected within thruster 'prop'.s command limits \[-30, 30\] rev/s"
    ):
        M.run_manoeuvre(v, tc, commands={"prop": 40.0})
    with pytest.raises(InputError, match=r"command main=-120 N: expected within .*\[-100, 100\] N"):
        M.run_manoeuvre(v, tc, commands={"main": -120})
    with pytest.raises(InputError, match=r"command prop=nan: expected a finite number \(rev/s\)"):
        M.run_manoeuvre(v, tc, commands={"prop": "nan"})
    with pytest.raises(InputError, match=r"command main=None: expected a finite number \(N\)"):
        M.run_manoeuvre(v, tc, commands={"main": None})
    with pytest.raises(InputError, match="expected a mapping of thruster name to command"):
        M.run_manoeuvre(v, tc, commands=[1.0, 2.0])
    with pytest.raises(InputError, match=r"with commands: expected 6 finite numbers"):
        M.run_manoeuvre(v, tc, commands={"prop": 1.0}, tau=lambda x: np.zeros(6))
    bare = boat(BOAT.split("thrusters:")[0])
    with pytest.raises(
        InputError, match=r"vehicle 'boat' has no thrusters; expected a vehicle file with a 'thrusters:'"
    ):
        M.run_manoeuvre(bare, tc, commands={"prop": 1.0})


def test_commands_from_text():
    assert M.commands_from_text("prop=20, main=-5.5") == {"prop": 20.0, "main": -5.5}
    for text, match in [
        ("prop", r"--command 'prop': expected NAME=VALUE"),
        ("prop=fast", r"--command 'prop=fast': expected NAME=VALUE with a finite VALUE"),
        ("=3", r"--command '=3': expected NAME=VALUE"),
        ("prop=inf", "expected NAME=VALUE with a finite VALUE"),
        ("prop=1,prop=2", r"--command: thruster 'prop' named twice"),
    ]:
        with pytest.raises(InputError, match=match):
            M.commands_from_text(text)
