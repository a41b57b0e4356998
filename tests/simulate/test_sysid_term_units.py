"""The unit sysid gives a free term's coefficient: its force's (N or N·m) over the product of its
factors' units — what a user needs to read ``Y_uv = −300 ± 2`` (it said "N per product of
velocities (SI)" for every term)."""

from __future__ import annotations

import pytest

from hydrokit.model.terms import parse_term
from hydrokit.sysid.model import _term_unit


@pytest.mark.parametrize(
    ("name", "unit"),
    [
        ("Y_uv", "N/(m/s)²"),  # N = [Y_uv] · (m/s)(m/s)
        ("N_ur", "N·m/((m/s)·(rad/s))"),
        ("N_r|r|", "N·m/(rad/s)²"),
        ("X_uu", "N/(m/s)²"),
        ("N_rrr", "N·m/(rad/s)³"),
        ("Y_uu*delta(rudder)", "N/((m/s)²·rad)"),
        ("Y_T(prop)*delta(rudder)", "N/(N·rad)"),
        ("N_n(prop)^2*delta(rudder)", "N·m/((rev/s)²·rad)"),
        ("N_0", "N·m"),
        ("X_udot", "N·s²/m"),
        ("N_rdot", "N·m·s²/rad"),
    ],
)
def test_the_unit_of_a_term_is_its_force_over_its_factors(name: str, unit: str) -> None:
    assert _term_unit(parse_term(name, surfaces=["rudder"], thrusters=["prop"])) == unit
