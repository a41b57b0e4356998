"""Geometry-file part keys: CG and inertia overrides are used (not accepted and dropped), and a
vehicle part refuses the body keys it would ignore."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.estimate.composite import combine
from hydrokit.io.geometry import parse_geometry


def parts(*entries: dict) -> dict:
    return {"name": "g", "fluid": {"density": 1000.0}, "parts": list(entries)}


def test_shape_part_cg_and_inertia_overrides_reach_the_composite(tmp_path: Path):
    # a 0.5 m sphere of 30 kg: uniform solid 2/5 m r² = 0.75 kg·m² about its centre; the ballasted
    # one has its CG 0.05 m below the centre and the inertia the file gives
    sphere = {"shape": "sphere", "diameter": 0.5, "mass": 30.0}
    plain = combine([gp.part for gp in parse_geometry(parts(sphere), tmp_path / "g.yaml").parts])
    np.testing.assert_allclose(plain.inertia_cg, 0.4 * 30.0 * 0.25**2 * np.eye(3), rtol=1e-12)
    np.testing.assert_allclose(plain.r_g, 0.0, atol=1e-15)
    given = {**sphere, "center_of_gravity": [0.0, 0.0, 0.05], "inertia": [[0.6, 0.01, 0], [0.01, 0.7, 0], [0, 0, 0.5]]}
    geo = parse_geometry(parts(given), tmp_path / "g.yaml")
    comp = combine([gp.part for gp in geo.parts])
    np.testing.assert_allclose(comp.r_g, [0.0, 0.0, 0.05], atol=1e-15)
    np.testing.assert_allclose(comp.r_b, 0.0, atol=1e-15)
    np.testing.assert_allclose(comp.inertia_cg, [[0.6, 0.01, 0], [0.01, 0.7, 0], [0, 0, 0.5]], atol=1e-15)
    assert geo.parts[0].sources["inertia"] == "given"


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("inertia", "abc", r"parts\[0\]\.inertia' = 'abc': expected a list of 3 numbers or an 3x3 matrix"),
        ("inertia", [1.0, float("nan"), 1.0], r"parts\[0\]\.inertia\[1\]' = nan"),
        ("inertia", [[1, 0], [0, 1]], r"parts\[0\]\.inertia': expected an 3x3 matrix, got 2 rows"),
        ("center_of_gravity", [0, 0], r"parts\[0\]\.center_of_gravity' = \[0, 0\]: expected a list of 3"),
        (
            "resolution",
            "abc",
            r"parts\[0\]\.resolution' = 'abc': expected a whole number of panels around from 6 to 200",
        ),
        ("resolution", 201, r"parts\[0\]\.resolution' = 201: expected a whole number"),
        ("resolution", 5, r"parts\[0\]\.resolution' = 5: expected a whole number"),
        ("resolution", 48.5, r"parts\[0\]\.resolution' = 48\.5: expected a whole number"),
        ("inertia", [[1, 0.2, 0], [0, 1, 0], [0, 0, 1]], r"parts\[0\]\.inertia' = .*: expected a symmetric tensor"),
        ("inertia", [1.0, 1.0, 2.5], r"parts\[0\]\.inertia': principal moments \[1\.0, 1\.0, 2\.5\] kg·m²; expected"),
        ("inertia", [0.0, 1.0, 1.0], r"parts\[0\]\.inertia': principal moments \[0\.0, 1\.0, 1\.0\]"),
        ("bem", "no", r"parts\[0\]\.bem' = 'no': expected true or false"),
    ],
)
def test_bad_overrides_name_the_field(tmp_path: Path, key, value, message):
    bad = {"shape": "sphere", "diameter": 0.5, "mass": 30.0, key: value}
    with pytest.raises(InputError, match=message):
        parse_geometry(parts(bad), tmp_path / "g.yaml")


@pytest.mark.parametrize("key", ["mass", "inertia", "center_of_gravity", "diameter", "buoyancy"])
def test_a_vehicle_part_refuses_body_keys_it_would_ignore(tmp_path: Path, key):
    entry = {"name": "m", "vehicle": "minerva", key: 1.0}
    with pytest.raises(InputError, match=rf"field 'parts\[0\]\.{key}': a vehicle part takes its body from the vehicle"):
        parse_geometry(parts(entry), tmp_path / "g.yaml")
    ok = parse_geometry(parts({"name": "m", "vehicle": "minerva", "position": [0, 1, 0]}), tmp_path / "g.yaml")
    assert ok.parts[0].part.mass > 0


@pytest.mark.parametrize(("key", "value"), [("bem", False), ("bem", True), ("resolution", 24)])
def test_a_mesh_part_refuses_the_bem_keys_it_would_ignore(tmp_path: Path, key, value):
    # a mesh part's added mass comes from BEM on its own panels: a BEM switch or a panel count
    # would be ignored, so they are refused (like a vehicle part's body keys)
    (tmp_path / "tet.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    entry = {"name": "hull", "mesh": "tet.obj", "mass": 1.0, key: value}
    with pytest.raises(InputError, match=rf"field 'parts\[0\]\.{key}' = {value}: a mesh part always takes"):
        parse_geometry(parts(entry), tmp_path / "g.yaml")
    ok = parse_geometry(parts({"name": "hull", "mesh": "tet.obj", "mass": 1.0}), tmp_path / "g.yaml")
    assert ok.parts[0].mesh is not None and ok.parts[0].bem


@pytest.mark.parametrize("resolution", [6, 200])
def test_resolution_bounds_are_inclusive(tmp_path: Path, resolution):
    geo = parse_geometry(
        parts({"shape": "sphere", "diameter": 0.5, "mass": 30.0, "resolution": resolution}), tmp_path / "g.yaml"
    )
    assert geo.parts[0].resolution == resolution


def test_a_part_without_resolution_takes_the_documented_default(tmp_path: Path):
    # docs/estimate.md, "Geometry file": "resolution panels around (6 to 200, default 48)"
    geo = parse_geometry(parts({"shape": "cylinder", "length": 1.0, "diameter": 0.2, "mass": 3.0}), tmp_path / "g.yaml")
    assert geo.parts[0].resolution == 48


def test_a_mesh_too_big_for_the_direct_solver_is_refused_before_solving(monkeypatch):
    # two dense complex N×N matrices, 32 N² bytes, may use half the memory: with 1 GiB of
    # "physical memory" the limit is √(2³⁰ / 64) = 4096 panels
    import os

    from hydrokit.estimate.bem import panel_memory_check

    pages = {"SC_PHYS_PAGES": 2**18, "SC_PAGE_SIZE": 2**12}
    monkeypatch.setattr(os, "sysconf", lambda name: pages[name])
    panel_memory_check(4096, "hull.stl")
    with pytest.raises(InputError, match=r"hull.stl: mesh has 4097 panels: .* expected at most 4096 panels"):
        panel_memory_check(4097, "hull.stl")


def test_a_thin_plates_moments_are_a_rigid_bodys():
    # a lamina in the x–y plane has I_z = I_x + I_y exactly: the limit of the triangle inequality
    geo = parse_geometry(
        parts({"shape": "sphere", "diameter": 0.5, "mass": 30.0, "inertia": [0.4, 0.6, 1.0]}), Path("g.yaml")
    )
    np.testing.assert_array_equal(geo.parts[0].part.inertia, np.diag([0.4, 0.6, 1.0]))


def test_a_flat_plate_without_thickness_displaces_nothing(tmp_path: Path):
    # a plate is thin unless the file gives its thickness: volume L·W·t, zero when t is left out
    plate = {"shape": "flat_plate", "length": 0.8, "width": 0.5, "mass": 2.0}
    thin = combine([gp.part for gp in parse_geometry(parts(plate), tmp_path / "g.yaml").parts])
    thick = combine([gp.part for gp in parse_geometry(parts({**plate, "thickness": 0.02}), tmp_path / "g.yaml").parts])
    assert thin.volume == 0.0
    assert thick.volume == pytest.approx(0.8 * 0.5 * 0.02, rel=1e-12)
