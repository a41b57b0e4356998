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
    # p is angular too (velocity index 3, the first of p, q, r)
    assert parse_term("K_pdot").scale_power() == 5
    assert parse_term("Y_pdot").scale_power() == 4


def test_a_term_takes_at_most_five_factors():
    # MAX_FACTORS = 5 (the compiled evaluator's fixed width): room for Abkowitz's u²·δ² style terms
    assert parse_term("N_uvvr").order() == 4
    assert parse_term("N_uvvrr").order() == 5
    for name in ("X_uuuuuu", "N_uvvrrr", "X_u^2*v^4"):
        with pytest.raises(InputError, match=r"term '.*': more than 5 factors"):
            parse_term(name)


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
    "bad",
    [
        "Q_uu",
        "X_uz",
        "X_u|u",
        "X_",
        "X_udotv",
        "X_(u/|v|)",
        "X_sqrt(u^2)",
        "__import__('os')",
        "X_|",  # a velocity expected where the name ends
        "X_u*",  # '*' only between two factors
        "X_*u",
        "X_u**v",
        "Z_sqrt(u^2+v^2+w^2+p^2)",  # a norm of at most three velocities
    ],
)
def test_bad_names_are_one_line_errors(bad):
    with pytest.raises(InputError, match="term") as err:
        parse_term(bad, "veh.yaml")
    assert "\n" not in str(err.value) and str(err.value).startswith("veh.yaml: ")


@pytest.mark.parametrize(("bad", "at"), [("X_u**v", 4), ("X_u*", 4), ("X_*u", 3), ("N_vr*", 5)])
def test_a_misplaced_star_is_named_at_its_own_position(bad, at):
    # the position is 1-based and points at the first offending '*' (in '**' the first one)
    with pytest.raises(InputError, match=rf"'\*' must stand between two factors at position {at};"):
        parse_term(bad)


def test_a_star_before_a_last_one_letter_factor_is_fine():
    # the '*' rule looks one character ahead: Y_v*r (r the last character) is Y_vr
    assert parse_term("Y_v*r").factors == parse_term("Y_vr").factors


def test_the_largest_norm_and_an_empty_or_missing_name():
    assert parse_term("Z_w*sqrt(u^2+v^2+w^2)").factors[1].indices == (0, 1, 2)
    for name in ("  ", None, 3):
        with pytest.raises(InputError, match=r"term name .*: expected text like X_uu"):
            parse_term(name)  # type: ignore[arg-type]


def test_terms_in_array_form_are_immutable():
    import dataclasses

    ts = TermSet.build([(parse_term("Y_v|v|"), -3.0)])
    with pytest.raises(dataclasses.FrozenInstanceError):
        ts.coef = np.zeros(1)  # type: ignore[misc]


def test_order_one_nondimensional_needs_reference_speed():
    with pytest.raises(InputError, match="reference_speed"):
        parse_term("Z_|w|").dimensional(-6.6, 1025.9, 1.25, None)
    # with U: ½ρL²U c'
    assert parse_term("Z_|w|").dimensional(-1.0, 1000.0, 2.0, 1.5) == pytest.approx(-0.5 * 1000 * 4 * 1.5)
    # a reference speed of zero is no speed either (0^(2−n) would be 0 or infinite)
    for name in ("Z_|w|", "Y_vvv"):
        with pytest.raises(InputError, match="reference_speed"):
            parse_term(name).dimensional(-1.0, 1000.0, 2.0, 0.0)


def test_a_speed_norm_over_surge_includes_the_surge_velocity():
    # X_u*sqrt(u^2+v^2): X = c·u·√(u² + v²). Surge is velocity index 0, the first one a norm can
    # name; at ν = (3, 4, 0, 0, 0, 0) the norm is 5, so X = 2·3·5 = 30 (and 2·3·4 = 24 without u)
    ts = TermSet.build([(parse_term("X_u*sqrt(u^2+v^2)"), 2.0)])
    out = ts.force(np.array([3.0, 4.0, 0.0, 0.0, 0.0, 0.0]))
    np.testing.assert_allclose(out, [30.0, 0, 0, 0, 0, 0], rtol=1e-12)
