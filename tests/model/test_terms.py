from __future__ import annotations

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.model.terms import ABS, NORM, SIGN, VEL, TermSet, parse_term


@pytest.mark.parametrize(
    "name,dof,kinds",
    [
        ("X_uu", 0, [VEL, VEL]),
        ("Y_v|v|", 1, [VEL, ABS]),
        ("Y_vq", 1, [VEL, VEL]),
        ("Z_|w|", 2, [ABS]),
        ("N_p|p|", 5, [VEL, ABS]),
        ("Z_w*sqrt(v^2+w^2)", 2, [VEL, NORM]),
        ("N_(v/|v|)*sqrt(v^2+w^2)*|r|", 5, [SIGN, NORM, ABS]),
    ],
)
def test_grammar(name, dof, kinds):
    t = parse_term(name)
    assert t.dof == dof and [f.kind for f in t.factors] == kinds


def test_acceleration_term():
    t = parse_term("X_udot")
    assert t.acceleration == 0 and t.factors == ()
    assert parse_term("M_qdot").scale_power() == 5  # moment / angular
    assert parse_term("X_udot").scale_power() == 3  # force / linear
    assert parse_term("Z_qdot").scale_power() == 4  # mixed


def test_scaling_rule_of_spec_section_3():
    # forces: 2 for two linear velocities, 3 linear × angular, 4 two angular; moments one more
    assert parse_term("X_uu").scale_power() == 2
    assert parse_term("Y_vq").scale_power() == 3
    assert parse_term("Y_pq").scale_power() == 4
    assert parse_term("K_p|p|").scale_power() == 5
    assert parse_term("N_vw").scale_power() == 3
    # X_uu = −1.35758e-1 (LI2021 Table 4), ρ = 1025.9, L = 1.25: ½ρL²X'_uu = −108.81 N s²/m²
    assert parse_term("X_uu").dimensional(-1.35758e-1, 1025.9, 1.25, None) == pytest.approx(-108.81, abs=0.01)


def test_sign_factor_and_values():
    ts = TermSet.build([(parse_term("N_(v/|v|)*sqrt(v^2+w^2)*|r|"), 2.0), (parse_term("Y_v|v|"), -3.0)])
    nu = np.array([0.0, -0.3, 0.4, 0, 0, -0.5])
    f = ts.force(nu)
    assert f[5] == pytest.approx(2.0 * -1 * 0.5 * 0.5)
    assert f[1] == pytest.approx(-3.0 * -0.3 * 0.3)
    assert ts.force(np.zeros(6))[5] == 0.0  # sign of zero is zero


@pytest.mark.parametrize(
    "bad", ["Q_uu", "X_uz", "X_u|u", "X_", "X_udotv", "X_(u/|v|)", "X_sqrt(u^2)", "__import__('os')"]
)
def test_bad_names_are_one_line_errors(bad):
    with pytest.raises(InputError, match="term"):
        parse_term(bad, "veh.yaml")


def test_order_one_nondimensional_needs_reference_speed():
    with pytest.raises(InputError, match="reference_speed"):
        parse_term("Z_|w|").dimensional(-6.6, 1025.9, 1.25, None)
    # with U: ½ρL²U c'
    assert parse_term("Z_|w|").dimensional(-1.0, 1000.0, 2.0, 1.5) == pytest.approx(-0.5 * 1000 * 4 * 1.5)


def test_a_speed_norm_over_surge_includes_the_surge_velocity():
    # X_u*sqrt(u^2+v^2): X = c·u·√(u² + v²). Surge is velocity index 0, the first one a norm can
    # name; at ν = (3, 4, 0, 0, 0, 0) the norm is 5, so X = 2·3·5 = 30 (and 2·3·4 = 24 without u)
    ts = TermSet.build([(parse_term("X_u*sqrt(u^2+v^2)"), 2.0)])
    out = ts.force(np.array([3.0, 4.0, 0.0, 0.0, 0.0, 0.0]))
    np.testing.assert_allclose(out, [30.0, 0, 0, 0, 0, 0], rtol=1e-12)
