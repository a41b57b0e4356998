"""A mesh part as a uniform solid: centroid and inertia of the enclosed polyhedron against the
closed forms of a box (m(b² + c²)/12 about each axis), moved and turned."""

from __future__ import annotations

import numpy as np
import pytest

from hydrokit.estimate.composite import combine, rotation_from_degrees
from hydrokit.estimate.geometry import mesh_part
from hydrokit.estimate.mesh import SurfaceMesh, check_mesh

# the 8 corners of the unit cube and its 12 outward triangles
CORNERS = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
TRIANGLES = np.array(
    [
        [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5],  # x = 0, x = 1
        [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],  # y = 0, y = 1
        [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],  # z = 0, z = 1
    ]
)  # fmt: skip


def box(a: float, b: float, c: float, shift: np.ndarray, R: np.ndarray) -> SurfaceMesh:
    """An a × b × c box centred at ``shift``, its axes turned by R."""
    v = (CORNERS - 0.5) * [a, b, c]
    return SurfaceMesh(v @ R.T + shift, TRIANGLES, "box.stl")


def box_inertia(m: float, a: float, b: float, c: float) -> np.ndarray:
    return m / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


@pytest.mark.parametrize("angles", [(0.0, 0.0, 0.0), (20.0, -35.0, 50.0)])
def test_box_mesh_is_the_closed_form_box_moved_and_turned(angles):
    a, b, c, m = 0.6, 0.25, 0.1, 7.0
    shift = np.array([0.3, -1.2, 0.45])
    R = rotation_from_degrees(*angles)
    mesh = box(a, b, c, shift, R)
    check_mesh(mesh)
    centroid, inertia = mesh.solid_inertia(m)
    np.testing.assert_allclose(centroid, shift, atol=1e-12)
    np.testing.assert_allclose(inertia, R @ box_inertia(m, a, b, c) @ R.T, atol=1e-12 * m)


def test_mesh_part_defaults_to_the_uniform_solid_and_keeps_given_values():
    # CB is always the volume centroid; CG and inertia default to the uniform solid's. The
    # composite of the part alone then has its CG and CB there and the box's inertia about it
    a, b, c, m = 0.6, 0.25, 0.1, 7.0
    shift = np.array([0.3, -0.2, 0.05])
    mesh = box(a, b, c, shift, np.eye(3))
    part = mesh_part("hull", mesh, m, np.zeros(3), np.eye(3), density=1000.0, gravity=9.81).part
    comp = combine([part])
    np.testing.assert_allclose(comp.r_g, shift, atol=1e-12)
    np.testing.assert_allclose(comp.r_b, shift, atol=1e-12)
    np.testing.assert_allclose(comp.inertia_cg, box_inertia(m, a, b, c), atol=1e-12)
    assert comp.volume == pytest.approx(a * b * c, rel=1e-12)
    # a shell: given CG (the keel weight 0.04 m below the centroid) and inertia
    given = np.diag([0.05, 0.2, 0.22])
    cog = shift + [0.0, 0.0, 0.04]
    shell = mesh_part(
        "hull", mesh, m, np.zeros(3), np.eye(3), density=1000.0, gravity=9.81, inertia=given, center_of_gravity=cog
    )
    comp = combine([shell.part])
    np.testing.assert_allclose(comp.r_g, cog, atol=1e-12)
    np.testing.assert_allclose(comp.r_b, shift, atol=1e-12)
    np.testing.assert_allclose(comp.inertia_cg, given, atol=1e-12)
    assert shell.sources["inertia"] == "given"


def test_sphere_mesh_tends_to_two_fifths_m_r_squared():
    # the inscribed polyhedron's inertia approaches 2/5 m r² from below as the panels refine
    from hydrokit.estimate.bem import shape_mesh

    errors = []
    for n in (16, 48):
        _, inertia = shape_mesh("sphere", n, diameter=2.0).solid_inertia(3.0)
        errors.append(abs(np.diag(inertia) - 0.4 * 3.0).max() / 1.2)
    assert errors[1] < 0.01 and errors[1] < errors[0] / 4
