"""Thruster models: propeller curves (REHMAN/Minerva), tables, rotor lag, saturation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.model.thrusters import Thruster, ThrusterSet

RHO = 1025.0  # SPEC §8 (Minerva, sea water)
# SPEC §8 Minerva: K_T = c3 J^3 + c2 J^2 + c1 J + c0, forward and reverse
KT_F = (0.5, -0.66, -0.25, 0.24)
KT_R = (0.025, -0.28, 0.17, 0.15)


def axial(**kw) -> Thruster:
    args = dict(
        name="A1",
        position=(-0.2, -0.305, 0.0),
        direction=(1.0, 0.0, 0.0),
        max_thrust=1e4,
        min_thrust=-1e4,
        diameter=0.22,
        kt_forward=KT_F,
        kt_reverse=KT_R,
        thrust_loss_forward=0.72,
        thrust_loss_reverse=0.53,
        max_speed=25.0,
    )
    args.update(kw)
    return Thruster(**args)


def test_forward_reverse_asymmetry_at_bollard_pull() -> None:
    # SPEC §8: at J = 0, K_T = 0.24 forward, 0.15 reverse; losses 0.72 / 0.53 (axial).
    ts = ThrusterSet((axial(),), density=RHO)
    n = 15.0  # rev/s
    f_fwd = ts.thrust([n])[0]
    f_rev = ts.thrust([-n])[0]
    base = RHO * 0.22**4 * n * n
    # closed form; rtol 1e-12 is round-off only
    assert f_fwd == pytest.approx(0.72 * 0.24 * base, rel=1e-12)
    assert f_rev == pytest.approx(-0.53 * 0.15 * base, rel=1e-12)
    assert abs(f_fwd) / abs(f_rev) == pytest.approx((0.72 * 0.24) / (0.53 * 0.15), rel=1e-12)


def test_advance_ratio_reduces_forward_thrust() -> None:
    ts = ThrusterSet((axial(),), density=RHO)
    n, va = 10.0, 0.5
    J = va / (n * 0.22)
    kt = np.polyval(KT_F, J)
    expected = 0.72 * kt * RHO * 0.22**4 * n * n  # REHMAN eq. 1.12 by hand
    assert ts.thrust([n], [va])[0] == pytest.approx(expected, rel=1e-12)
    assert ts.thrust([n], [va])[0] < ts.thrust([n])[0]


def test_advance_speed_includes_rotation_and_wake() -> None:
    th = axial(position=(0.0, 0.5, 0.0), wake_fraction=0.2)
    ts = ThrusterSet((th,), density=RHO)
    # yaw rate r = 1 rad/s at y = 0.5 m: ω × r = (0,0,1) × (0,0.5,0) = (-0.5, 0, 0)
    va = ts.advance_speed([1.0, 0.0, 0.0, 0.0, 0.0, 1.0])[0]
    assert va == pytest.approx(0.8 * (1.0 - 0.5), rel=1e-12)


@pytest.mark.parametrize("va", [0.0, 0.3, -0.2])
@pytest.mark.parametrize("f", [50.0, -30.0, 5.0])
def test_inversion_round_trip(f: float, va: float) -> None:
    ts = ThrusterSet((axial(),), density=RHO)
    n = ts.command_for_thrust([f], [va])
    # bisection to 2^-48 of the range: thrust matches to ~1e-9 relative
    assert ts.thrust(n, [va])[0] == pytest.approx(f, rel=1e-8)
    assert np.sign(n[0]) == np.sign(f)


def test_speed_saturation_limits_thrust() -> None:
    ts = ThrusterSet((axial(max_speed=10.0),), density=RHO)
    f_max = 0.72 * 0.24 * RHO * 0.22**4 * 100.0
    assert ts.f_max[0] == pytest.approx(f_max, rel=1e-12)
    assert ts.thrust([50.0])[0] == pytest.approx(f_max, rel=1e-12)
    assert ts.command_for_thrust([1e6])[0] == pytest.approx(10.0)


def test_rated_thrust_saturation() -> None:
    th = Thruster("T", (0, 0, 0), (1, 0, 0), max_thrust=60, min_thrust=-40)
    ts = ThrusterSet((th,))
    assert ts.thrust([100.0])[0] == 60.0
    assert ts.thrust([-100.0])[0] == -40.0


def test_first_order_rotor_matches_closed_form() -> None:
    tau = 0.4  # s
    ts = ThrusterSet((axial(time_constant=tau),), density=RHO)
    n_c, dt = 12.0, 0.01
    n = np.zeros(1)
    t = 0.0
    for _ in range(150):
        n = ts.rotor_step(n, [n_c], dt)
        t += dt
    # exact ZOH update: only round-off separates it from n_c (1 - e^(-t/tau))
    assert n[0] == pytest.approx(n_c * (1 - math.exp(-t / tau)), rel=1e-12)


def test_table_thruster_interpolates_t200() -> None:
    # SPEC §8 BlueROV2 T200: F = -140.3V^9 + 389.9V^7 - 404.1V^5 + 176.0V^3 + 8.9V
    V = np.linspace(-1, 1, 21)
    F = -140.3 * V**9 + 389.9 * V**7 - 404.1 * V**5 + 176.0 * V**3 + 8.9 * V
    th = Thruster(
        "T", (0, 0, 0), (1, 0, 0), max_thrust=40, min_thrust=-40, table_command=tuple(V), table_thrust=tuple(F)
    )
    ts = ThrusterSet((th,))
    assert ts.thrust([0.5])[0] == pytest.approx(F[15], rel=1e-12)
    v = 0.55
    exact = -140.3 * v**9 + 389.9 * v**7 - 404.1 * v**5 + 176.0 * v**3 + 8.9 * v
    # linear interpolation of a 0.1-spaced table: within 3 % of the polynomial here
    assert ts.thrust([v])[0] == pytest.approx(exact, rel=0.03)
    assert ts.thrust(ts.command_for_thrust([10.0]))[0] == pytest.approx(10.0, rel=1e-12)
    assert ts.f_max[0] == pytest.approx(F[-1])


def test_zero_direction_rejected() -> None:
    with pytest.raises(InputError, match="thruster 'T1' direction .* zero length"):
        Thruster("T1", (0, 0, 0), (0, 0, 0), max_thrust=10)


def test_duplicate_names_rejected() -> None:
    a = Thruster("T1", (0, 0, 0), (1, 0, 0), max_thrust=10)
    with pytest.raises(InputError, match="duplicate name 'T1'"):
        ThrusterSet((a, a))


def test_direction_is_normalised() -> None:
    th = Thruster("T1", (0, 0, 0), (3, 4, 0), max_thrust=10)
    assert th.direction == pytest.approx((0.6, 0.8, 0.0), rel=1e-15)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"max_thrust": -5}, "max_thrust = -5.0: expected a positive"),
        ({"max_thrust": "lots"}, "max_thrust = 'lots': expected a number"),
        ({"min_thrust": 3}, "min_thrust = 3.0: expected a reverse thrust"),
        ({"time_constant": -1}, "time_constant = -1.0"),
    ],
)
def test_bad_fields_rejected(kw: dict, match: str) -> None:
    args = dict(name="T1", position=(0, 0, 0), direction=(1, 0, 0), max_thrust=10)
    args.update(kw)
    with pytest.raises(InputError, match=match):
        Thruster(**args)


def test_propeller_needs_speed_limit() -> None:
    with pytest.raises(InputError, match="needs max_rpm"):
        axial(max_speed=None)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@given(st.floats(-100, 200), st.floats(-1.0, 2.0))
@settings(max_examples=200, deadline=None)
def test_inversion_round_trip_property(f: float, va: float) -> None:
    ts = ThrusterSet((axial(),), density=RHO)
    n = ts.command_for_thrust([f], [va])[0]
    assert abs(n) <= 25.0
    got = ts.thrust([n], [va])[0]
    if abs(n) < 25.0 * (1 - 1e-9):  # not at the speed limit: the demand is met (1e-9 rel)
        assert got == pytest.approx(f, rel=1e-9, abs=1e-9)
    else:  # at the limit: the best the curve gives, never more than asked
        assert abs(got) <= abs(f) + 1e-9


def test_wrong_length_commands_and_thrusts_are_one_line_errors():
    # a command vector of the wrong length used to reach numpy's broadcast error in the clip
    from hydrokit.api import load_vehicle

    ts = load_vehicle("lingyun-diagonal").thrusters
    for call, what in ((ts.thrust, "commands"), (ts.command_for_thrust, "thrusts")):
        with pytest.raises(InputError, match=rf"expected {len(ts)} {what} \(one per thruster\), got shape \(3,\)"):
            call(np.zeros(3))
