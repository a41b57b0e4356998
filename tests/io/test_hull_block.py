"""The vehicle file's ``hull:`` block (:mod:`hydrokit.io.hull`): what it builds and what it refuses."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrokit.data import body_file
from hydrokit.errors import InputError
from hydrokit.estimate import hull
from hydrokit.io.hull import read_hull_block
from hydrokit.io.profile import read_profile

RHO = 1030.0


def test_strips_are_drag_elements_on_y_and_z(tmp_path: Path):
    """Default: 20 strips, named hull-strip-NN, quadratic only across the axis, summing to
    ½ρ·1.1·∫2r dx of the bundled myring profile (rtol 1e-12: the same integral)."""
    elements, terms = read_hull_block({"profile": "myring"}, str(tmp_path / "v.yaml"), RHO)
    assert terms == [] and len(elements) == hull.DEFAULT_STRIPS
    assert elements[0].name == "hull-strip-01"
    q = np.array([e.quadratic for e in elements])
    assert np.all(q[:, 0] == 0) and np.array_equal(q[:, 1], q[:, 2])
    x, r = read_profile(body_file("myring"))
    area = np.trapezoid(2 * r, x) if hasattr(np, "trapezoid") else np.trapz(2 * r, x)
    assert q[:, 1].sum() == pytest.approx(0.5 * RHO * 1.1 * area, rel=1e-12)
    # origin at the volume centroid: strips ahead of it have x > 0, behind it x < 0
    xs = np.array([e.position[0] for e in elements])
    assert xs[0] > 0 > xs[-1] and np.all(np.diff(xs) < 0)


def test_terms_mode_and_lift_defaults():
    """crossflow_drag: terms gives Prestero's eight integrals; lift: true adds Y_uv, Z_uw, N_uv,
    M_uw with Hoerner's slope and x_cp 0.70 l aft of the nose (for the REMUS profile and origin:
    x_cp = 0.611 − 0.70·1.3327 = −0.322 m, Prestero's −0.321 m; c = 1.2)."""
    block = {"profile": "remus100", "origin_from_nose": 0.611, "crossflow_drag": "terms", "lift": True}
    elements, terms = read_hull_block(block, "v.yaml", RHO)
    names = dict(terms)
    assert elements == []
    assert set(names) == {"Y_v|v|", "Z_w|w|", "M_w|w|", "N_v|v|", "Y_r|r|", "Z_q|q|", "M_q|q|", "N_r|r|"} | {
        "Y_uv",
        "Z_uw",
        "N_uv",
        "M_uw",
    }
    lift = 0.5 * RHO * 0.191**2 * 1.2
    assert names["Y_uv"] == pytest.approx(-lift, rel=5e-3)  # c from Hoerner: 1.1993 vs 1.2
    assert names["N_uv"] / names["Y_uv"] == pytest.approx(-0.322, abs=1e-3)  # N = x_cp Y


def test_explicit_lift_and_no_crossflow(tmp_path: Path):
    """A CSV next to the vehicle file, given lift values, cross-flow off."""
    (tmp_path / "body.csv").write_text("x,r\n0,0\n0.5,0.1\n1.5,0.1\n2,0\n")
    block = {"profile": "body.csv", "crossflow_drag": False, "lift": True, "lift_coefficient": 1.0, "lift_center": -0.5}
    elements, terms = read_hull_block(block, str(tmp_path / "v.yaml"), RHO)
    names = dict(terms)
    assert elements == [] and names["Y_uv"] == pytest.approx(-0.5 * RHO * 0.04)
    assert names["M_uw"] == pytest.approx(-0.5 * 0.5 * RHO * 0.04)


@pytest.mark.parametrize(
    ("block", "match"),
    [
        ("myring", "expected a mapping"),
        ({}, "missing 'profile'"),
        ({"profile": "myring", "strip": 3}, "hull.strip"),
        ({"profile": 3}, "bundled body name"),
        ({"profile": "no_such_body"}, "no such file or bundled body"),
        ({"profile": "missing.csv"}, "no such file"),
        ({"profile": "lingyun"}, "not an x,r profile"),
        ({"profile": "myring", "crossflow_drag": "yes"}, "strips, terms or false"),
        ({"profile": "myring", "strips": 0}, "whole number"),
        ({"profile": "myring", "strips": True}, "whole number"),
        ({"profile": "myring", "crossflow_drag_coefficient": -1}, "crossflow_drag_coefficient"),
        ({"profile": "myring", "lift": "yes"}, "hull.lift"),
        ({"profile": "myring", "lift_coefficient": 1.0}, "without 'lift: true'"),
        ({"profile": "myring", "origin_from_nose": "front"}, "origin_from_nose"),
    ],
)
def test_bad_blocks_are_refused(block, match):
    with pytest.raises(InputError, match=match):
        read_hull_block(block, "v.yaml", RHO)  # type: ignore[arg-type]


def test_a_profile_that_is_not_a_body_names_the_file(tmp_path: Path):
    (tmp_path / "flat.csv").write_text("x,r\n0,0\n1,0\n")
    with pytest.raises(InputError, match="flat.csv.*some radius"):
        read_hull_block({"profile": "flat.csv"}, str(tmp_path / "v.yaml"), RHO)
