"""Core behaviour a mutation left unnoticed (issue #13; found by bench/mutation.py)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hydrokit.core.drag import DragElement


def test_drag_element_is_immutable():
    # a vehicle shares its elements between runs (STYLE: no mutable shared state)
    e = DragElement("fin", (0.1, 0.0, 0.0), (1.0, 1.0, 1.0), (2.0, 2.0, 2.0))
    with pytest.raises(dataclasses.FrozenInstanceError):
        e.position = (0.0, 0.0, 0.0)
    assert e.position == (0.1, 0.0, 0.0)


def test_default_sea_water_reproduces_rehman_table_1_sphere():
    # REHMAN Table 1 prints the 0.5 m payload sphere's added mass as 33.5 kg: ½ ρ V with the
    # sources' sea water, 1025 kg/m³ (33.54; 1026 would print 33.6). A geometry that names no
    # fluid gets that density
    from pathlib import Path

    import hydrokit.core.constants as constants
    from hydrokit.io.geometry import parse_geometry

    geo = parse_geometry({"parts": [{"shape": "sphere", "diameter": 0.5, "mass": 130.0}]}, Path("payload.yaml"))
    assert geo.density == constants.SEAWATER_DENSITY
    assert round(float(geo.parts[0].part.added_mass[0, 0]), 1) == 33.5
    assert geo.gravity == constants.GRAVITY == 9.81  # the sources' rig files (ENG2009, CELY2019)


def test_coriolis_matrix_symmetrises_an_estimated_mass_matrix_by_default():
    # Theorem 3.2 holds for M = Mᵀ: an M_A off by round-off (or a fit) is used through its
    # symmetric part unless the caller says it is already exact; C(ν) is then skew-symmetric
    import numpy as np

    from hydrokit.core.coriolis import coriolis_matrix

    rng = np.random.default_rng(3)
    A = rng.normal(size=(6, 6))
    M = A @ A.T + 6 * np.eye(6)
    M[0, 4] += 0.3  # not symmetric
    nu = rng.normal(size=6)
    C = coriolis_matrix(M, nu)
    np.testing.assert_allclose(C, coriolis_matrix(0.5 * (M + M.T), nu, symmetric=True), rtol=0, atol=1e-12)
    np.testing.assert_allclose(C, -C.T, atol=1e-12)


def test_a_single_drag_element_is_the_closed_form_point_drag():
    # one element at r = (0, 0.5, 0) with linear and quadratic drag in surge only, the body
    # surging at u = 2 m/s and yawing at r = 0.4 rad/s: the point moves at u − r·0.5 = 1.8 m/s,
    # so F_x = −(K_L 1.8 + K_Q 1.8²) and the yaw moment is −0.5 · F_x (N = x F_y − y F_x)
    import numpy as np

    from hydrokit.core.drag import DragElement, drag_wrench, pack_elements

    el = DragElement("fin", (0.0, 0.5, 0.0), linear=(3.0, 0.0, 0.0), quadratic=(7.0, 0.0, 0.0))
    w = drag_wrench(pack_elements([el]), [2.0, 0.0, 0.0, 0.0, 0.0, 0.4])
    fx = -(3.0 * 1.8 + 7.0 * 1.8**2)
    np.testing.assert_allclose(w, [fx, 0, 0, 0, 0, -0.5 * fx], atol=1e-12)
    # an element given only a position drags nothing
    assert DragElement("tag", (1.0, 0.0, 0.0)).row().tolist() == [1.0, 0, 0, 0, 0, 0, 0, 0, 0]


@pytest.mark.parametrize(("yaw", "pitch"), [(0.8217701239287258, -math.pi / 2), (-2.7541588563828316, math.pi / 2)])
def test_euler_angles_at_gimbal_lock_survive_rounding_past_one(yaw, pitch):
    # pitch ±90° with these yaw angles: R[2, 0] = −sin θ rounds to ±1.0000000000000002, outside
    # asin's domain; the clamp keeps θ = ∓asin(±1) = ±π/2 instead of a domain error
    from hydrokit.core.kinematics import quaternion_to_euler, quaternion_to_rotation

    c, s = math.cos(pitch / 2), math.sin(pitch / 2)
    q = np.array([math.cos(yaw / 2) * c, -math.sin(yaw / 2) * s, math.cos(yaw / 2) * s, math.sin(yaw / 2) * c])
    assert abs(quaternion_to_rotation(q / np.linalg.norm(q))[2, 0]) > 1.0  # the rounding at issue
    assert quaternion_to_euler(q)[1] == pytest.approx(pitch, abs=1e-12)
