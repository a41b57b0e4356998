"""Thrust-curve objects (PropellerCurve, TableCurve, IdealCurve) and how Thruster,
ThrusterSet and the vehicle-file reader use them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.thrusters import parse_thrusters
from hydrokit.model.thrusters import IdealCurve, PropellerCurve, TableCurve, Thruster, ThrusterSet

# SPEC §8 Minerva propeller: K_T polynomials (highest power first), losses, D = 0.22 m
KT_F = (0.5, -0.66, -0.25, 0.24)
KT_R = (0.025, -0.28, 0.17, 0.15)


def minerva(**kw) -> PropellerCurve:
    args = dict(
        diameter=0.22,
        kt_forward=KT_F,
        kt_reverse=KT_R,
        max_speed=25.0,
        thrust_loss_forward=0.72,
        thrust_loss_reverse=0.53,
        density=1025.0,
    )
    args.update(kw)
    return PropellerCurve(**args)


def t200() -> TableCurve:
    # SPEC §8 BlueROV2 T200: F = -140.3V^9 + 389.9V^7 - 404.1V^5 + 176.0V^3 + 8.9V, N
    V = np.linspace(-1, 1, 21)
    F = -140.3 * V**9 + 389.9 * V**7 - 404.1 * V**5 + 176.0 * V**3 + 8.9 * V
    return TableCurve(tuple(V), tuple(F))


# ------------------------------------------------------------------------ propeller curve
def test_propeller_forward_reverse_asymmetry_by_hand() -> None:
    # f = loss K_T(0) ρ D⁴ |n| n at V_a = 0, n = ±12 rev/s:
    # ρ D⁴ n² = 1025 · 0.22⁴ · 144 = 1025 · 0.00234256 · 144 = 345.761856 N
    # forward: 0.72 · 0.24 · 345.761856 = 59.7476487168 N
    # reverse: −0.53 · 0.15 · 345.761856 = −27.488067552 N
    c = minerva()
    assert c.thrust(12.0) == pytest.approx(59.7476487168, rel=1e-12)
    assert c.thrust(-12.0) == pytest.approx(-27.488067552, rel=1e-12)
    # with inflow V_a = 0.5 m/s in reverse: J = 0.5 / (−12 · 0.22) = −0.189394,
    # K_T,r(J) = 0.025 J³ − 0.28 J² + 0.17 J + 0.15 = 0.1075896, f = −0.53 · K_T · 345.761856
    assert c.thrust(-12.0, 0.5) == pytest.approx(-19.716196334, rel=1e-9)


def test_propeller_density_scales_thrust() -> None:
    c = minerva()
    fresh = c.in_fluid(1000.0)
    assert fresh.density == 1000.0 and c.density == 1025.0  # a new curve; the old one is unchanged
    assert fresh.thrust(12.0) == pytest.approx(59.7476487168 * 1000.0 / 1025.0, rel=1e-12)
    assert c.in_fluid(1025.0) is c


@pytest.mark.parametrize("va", [0.0, 0.4, -0.3])
@pytest.mark.parametrize("n", [20.0, 7.5, 5.0, -5.0, -19.0])
def test_propeller_round_trip_command_of_thrust(n: float, va: float) -> None:
    c = minerva()
    # (slow rotation against strong inflow clamps K_T to 0: no thrust to invert there)
    assert abs(c.thrust(n, va)) > 1.0
    # the root search stops at 1e-12 relative thrust error; on this smooth, monotonic
    # curve that pins n to ~1e-10 relative
    assert c.command(c.thrust(n, va), va) == pytest.approx(n, rel=1e-9)


def test_propeller_limits_and_saturated_inverse() -> None:
    c = minerva(max_speed=10.0)
    lo, hi = c.limits()
    base = 1025.0 * 0.22**4 * 100.0  # ρ D⁴ n_max², N
    assert hi == pytest.approx(0.72 * 0.24 * base, rel=1e-12)
    assert lo == pytest.approx(-0.53 * 0.15 * base, rel=1e-12)
    assert c.command_limits() == (-10.0, 10.0)
    assert c.command(1e6) == 10.0 and c.command(-1e6) == -10.0  # held at the speed limit
    assert c.command(0.0) == 0.0 and c.thrust(0.0) == 0.0


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"diameter": -0.2}, r"propeller curve diameter = -0.2: expected a positive number in m"),
        ({"max_speed": 0}, r"propeller curve max_speed = 0.0: expected a positive number in rev/s"),
        ({"kt_forward": (0.1, -0.2)}, r"K_T\(0\) must be positive"),
        ({"kt_forward": "abc"}, r"kt_forward = 'abc': expected a list of finite numbers"),
        ({"thrust_loss_reverse": 0}, r"thrust_loss_reverse = 0.0: expected a positive number"),
        ({"advance_ratio_range": (0.1, 1.0)}, r"advance_ratio_range = \[0.1, 1.0\]: expected \[low ≤ 0"),
    ],
)
def test_propeller_curve_rejects_bad_parameters(kw: dict, match: str) -> None:
    with pytest.raises(InputError, match=match):
        minerva(**kw)


# ---------------------------------------------------------------------- table and ideal
def test_table_curve_interpolates_and_inverts() -> None:
    c = t200()
    # at V = 0.5 (a table point): F = -140.3/512 + 389.9/128 - 404.1/32 + 176/8 + 4.45
    f05 = -140.3 / 512 + 389.9 / 128 - 404.1 / 32 + 176.0 / 8 + 4.45
    assert c.thrust(0.5) == pytest.approx(f05, rel=1e-12)
    # midway between two points: the mean of their thrusts (linear interpolation)
    assert c.thrust(0.55) == pytest.approx(0.5 * (c.thrusts[15] + c.thrusts[16]), rel=1e-12)
    assert c.thrust(0.5, advance_speed=2.0) == c.thrust(0.5)  # a table ignores inflow
    for cmd in (-0.93, -0.2, 0.0, 0.37, 0.99):
        assert c.command(c.thrust(cmd)) == pytest.approx(cmd, rel=1e-12, abs=1e-15)
    assert c.limits() == (c.thrusts[0], c.thrusts[-1])
    assert c.limits()[0] < 0 < c.limits()[1]
    assert c.command_limits() == (-1.0, 1.0)


def test_table_curve_rejects_non_increasing_table() -> None:
    with pytest.raises(InputError, match=r"table curve thrust_table: command and thrust must both be strictly"):
        TableCurve((0.0, 1.0, 2.0), (0.0, 5.0, 4.0))
    # a flat stretch (two commands, one thrust) has no inverse: command(thrust) is ambiguous
    with pytest.raises(InputError, match=r"table curve thrust_table: command and thrust must both be strictly"):
        TableCurve((0.0, 1.0, 2.0), (0.0, 5.0, 5.0))
    with pytest.raises(InputError, match=r"table curve thrust_table: command and thrust must both be strictly"):
        TableCurve((0.0, 1.0, 1.0), (0.0, 5.0, 6.0))
    with pytest.raises(InputError, match="need the same length ≥ 2, got 2 and 3"):
        TableCurve((0.0, 1.0), (0.0, 5.0, 6.0))


def test_ideal_curve_is_identity() -> None:
    c = IdealCurve()
    assert c.thrust(-37.5) == -37.5 and c.command(12.25) == 12.25
    assert c.command(c.thrust(3.0)) == 3.0
    assert c.limits() == (-math.inf, math.inf)


# --------------------------------------------------------- Thruster and ThrusterSet with curves
def test_thruster_builds_its_curve_and_model_string() -> None:
    prop = Thruster("P", (0, 0, 0), (1, 0, 0), 100, diameter=0.22, kt_forward=KT_F, max_speed=20.0)
    assert isinstance(prop.curve, PropellerCurve) and prop.model == "propeller"
    assert prop.kt_reverse == KT_F  # reverse defaults to the forward polynomial, as before
    tab = Thruster("T", (0, 0, 0), (1, 0, 0), 40, table_command=(0, 1), table_thrust=(-5, 5))
    assert isinstance(tab.curve, TableCurve) and tab.model == "table"
    ideal = Thruster("I", (0, 0, 0), (1, 0, 0), 40)
    assert isinstance(ideal.curve, IdealCurve) and ideal.model == "ideal"


def test_thruster_given_a_curve_equals_the_field_form() -> None:
    fields = Thruster(
        "P",
        (0, 0, 0),
        (1, 0, 0),
        1e4,
        diameter=0.22,
        kt_forward=KT_F,
        kt_reverse=KT_R,
        thrust_loss_forward=0.72,
        thrust_loss_reverse=0.53,
        max_speed=25.0,
    )
    given = Thruster("P", (0, 0, 0), (1, 0, 0), 1e4, curve=minerva())
    assert given.diameter == 0.22  # taken from the curve (used for actuator-disk power)
    a, b = ThrusterSet((fields,), density=1025.0), ThrusterSet((given,), density=1025.0)
    for cmd, va in [(12.0, 0.0), (-12.0, 0.5), (30.0, 0.2)]:
        assert a.thrust([cmd], [va])[0] == b.thrust([cmd], [va])[0]
    np.testing.assert_array_equal(a.command_max, b.command_max)
    np.testing.assert_array_equal(a.f_min, b.f_min)
    with pytest.raises(InputError, match=r"thruster 'P': give either 'curve' or the kt_forward"):
        Thruster("P", (0, 0, 0), (1, 0, 0), 1e4, curve=t200(), kt_forward=KT_F, diameter=0.22, max_speed=25.0)
    with pytest.raises(InputError, match=r"thruster 'P' diameter = 0.3: its curve has diameter 0.22"):
        Thruster("P", (0, 0, 0), (1, 0, 0), 1e4, curve=minerva(), diameter=0.3)


def test_thruster_prefixes_curve_errors_with_its_name() -> None:
    with pytest.raises(InputError, match=r"^thruster 'T9' thrust_table: command and thrust must both"):
        Thruster("T9", (0, 0, 0), (1, 0, 0), 40, table_command=(0, 1), table_thrust=(5, -5))


def test_set_binds_its_density_into_the_curves() -> None:
    th = Thruster("P", (0, 0, 0), (1, 0, 0), 1e4, curve=minerva(density=1025.0))
    ts = ThrusterSet((th,), density=1000.0)
    assert ts.curves[0].density == 1000.0  # type: ignore[attr-defined]
    assert ts.thrust([12.0])[0] == pytest.approx(59.7476487168 * 1000.0 / 1025.0, rel=1e-12)


def test_set_limits_mix_curve_and_rated_limits() -> None:
    ts = ThrusterSet(
        (
            Thruster("P", (0, 0, 0), (1, 0, 0), 50.0, min_thrust=-10.0, curve=minerva(max_speed=12.0)),
            Thruster("T", (0, 0, 0), (1, 0, 0), 100.0, curve=t200()),
            Thruster("I", (0, 0, 0), (1, 0, 0), 60.0, min_thrust=-40.0),
        )
    )
    # P: rated 50 N is below the 59.75 N the curve gives at 12 rev/s; reverse the curve's
    # −27.49 N is beyond the rated −10 N. T: the table's own ends. I: rated only.
    np.testing.assert_allclose(ts.f_max, [50.0, t200().thrusts[-1], 60.0], rtol=1e-12)
    np.testing.assert_allclose(ts.f_min, [-10.0, t200().thrusts[0], -40.0], rtol=1e-12)
    np.testing.assert_array_equal(ts.command_max, [12.0, 1.0, 60.0])
    np.testing.assert_array_equal(ts.command_min, [-12.0, -1.0, -40.0])
    cmd = ts.command_for_thrust([30.0, 10.0, -25.0])
    np.testing.assert_allclose(ts.thrust(cmd), [30.0, 10.0, -25.0], rtol=1e-12)
    assert cmd[2] == -25.0  # ideal: the command is the thrust


# ------------------------------------------------------------------ the vehicle-file reader
DOC = {
    "fluid": {"density": 1025.0},
    "thrusters": [
        {
            "name": "A",
            "position": [0, 0, 0],
            "direction": [1, 0, 0],
            "max_thrust": 500,
            "diameter": 0.22,
            "kt_forward": list(KT_F),
            "kt_reverse": list(KT_R),
            "thrust_loss": {"forward": 0.72, "reverse": 0.53},
            "max_rpm": 1500,
            "advance_ratio_range": [-0.5, 1.0],
        },
        {
            "name": "B",
            "position": [0, 0.3, 0],
            "azimuth_deg": 90,
            "max_thrust": 40,
            "thrust_table": {"command": [-1, 0, 1], "thrust": [-30, 0, 35]},
        },
        {"name": "C", "position": [0, -0.3, 0], "direction": [0, 0, 1], "max_thrust": 60, "min_thrust": -40},
    ],
}


def test_reader_builds_the_same_curves() -> None:
    ts = parse_thrusters(DOC, "v.yaml")
    a, b, c = ts.thrusters
    assert a.curve == minerva(max_speed=1500 / 60.0)  # rpm → rev/s in the reader only
    assert b.curve == TableCurve((-1.0, 0.0, 1.0), (-30.0, 0.0, 35.0))
    assert c.curve == IdealCurve()
    assert [t.model for t in ts.thrusters] == ["propeller", "table", "ideal"]
    assert b.direction == pytest.approx((0.0, 1.0, 0.0), abs=1e-15)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"thrust_loss": {"forward": 0}}, r"field 'thrusters\[0\] \(A\).thrust_loss.forward' = 0: expected a positive"),
        ({"thrust_loss": "high"}, r"field 'thrusters\[0\] \(A\).thrust_loss' = 'high': expected a number"),
        ({"max_rpm": -100}, r"field 'thrusters\[0\] \(A\).max_rpm' = -100: expected a positive number"),
        (
            {"advance_ratio_range": [0, 1, 2]},
            r"thrusters\[0\] \(A\).advance_ratio_range' = \[0, 1, 2\]: expected a list of 2",
        ),
        ({"kt_forward": [0.1, -0.3]}, r"thrusters\[0\] \(A\): thruster 'A': K_T\(0\) must be positive"),
    ],
)
def test_reader_errors_are_one_line_naming_the_field(change: dict, match: str) -> None:
    doc = {"fluid": DOC["fluid"], "thrusters": [{**DOC["thrusters"][0], **change}]}
    with pytest.raises(InputError, match=match) as exc:
        parse_thrusters(doc, "v.yaml")
    assert str(exc.value).startswith("v.yaml: ") and "\n" not in str(exc.value)
