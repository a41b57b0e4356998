"""Waypoint guidance: LOS heading, depth and speed references, switching, path distance."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.model.guidance import Path, path_distance


def square() -> Path:
    pts = [[0, 0, 2], [20, 0, 2], [20, 20, 6], [20, 20, 10]]
    return Path(points=pts, speeds=[0.5, 0.4, 0.3], acceptance_radius=1.0, lookahead=4.0)


def test_los_heading_closed_form() -> None:
    path = square()
    s = path.initial_state()
    ref, s = path.update(s, [5.0, 2.0, 2.0])
    # leg along +x (alpha = 0); 2 m to starboard -> psi_d = atan(-2/4) (Fossen 2011 eq. 10.73)
    assert ref.heading == pytest.approx(math.atan(-2.0 / 4.0), rel=1e-12)
    assert ref.speed == pytest.approx(0.5)
    assert ref.depth == pytest.approx(2.0)
    assert s.leg == 1


def test_switching_depth_ramp_and_vertical_leg() -> None:
    path = square()
    s = path.initial_state()
    ref, s = path.update(s, [19.5, 0.0, 2.0])  # inside the 1 m acceptance radius of wp 1
    assert s.leg == 2
    # leg 2 runs along +y; x = 19.5 is 0.5 m to its starboard side
    assert ref.heading == pytest.approx(math.pi / 2 + math.atan(-0.5 / 4.0), rel=1e-12)
    # leg 2 descends 4 m over its 3-D length L; along-track fraction of the position plus
    # the lookahead scaled by the vertical share 4/L
    L = math.hypot(20.0, 4.0)
    s_ahead = (np.array([-0.5, 0.0, 0.0]) @ np.array([0, 20, 4]) / L + 4.0 * 4.0 / L) / L
    assert ref.depth == pytest.approx(2.0 + 4.0 * s_ahead, rel=1e-12)
    assert ref.speed == pytest.approx(0.4 * 20.0 / L, rel=1e-12)  # horizontal share
    ref, s = path.update(s, [20.0, 20.0, 6.0])  # at wp 2: vertical leg 3 starts
    assert s.leg == 3
    assert ref.speed == 0.0 and ref.heading == pytest.approx(math.pi / 2)
    assert ref.depth == pytest.approx(10.0)  # 4 m lookahead covers the 4 m leg
    ref, s = path.update(s, [20.0, 20.0, 9.5])
    assert s.leg == 4 and ref.speed == 0.0 and ref.depth == 10.0  # finished: hold the end


def test_passing_a_waypoint_outside_radius_still_switches() -> None:
    path = square()
    _, s = path.update(path.initial_state(), [21.0, -3.0, 2.0])  # beyond wp 1 along-track
    assert s.leg == 2


def test_path_distance_closed_form() -> None:
    pts = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0.0]])
    P = np.array([[5, 3, 0], [12, 5, 0], [-3, -4, 0], [10, 0, 2.0]])
    np.testing.assert_allclose(path_distance(P, pts), [3, 2, 5, 2], rtol=1e-12)


@pytest.mark.parametrize(
    ("pts", "speeds", "match"),
    [
        ([], [], "at least 2 points"),
        ([[0, 0, 0]], [], "at least 2 points"),
        ([[0, 0, 0], [0, 0, 0], [1, 0, 0]], [1, 1], "waypoint 1 repeats waypoint 0"),
        ([[0, 0, 0], [0.5, 0, 0], [0.5, 0, 0]], [1, 1], "waypoint 2 repeats waypoint 1"),  # after a short leg
        ([[0, 0, 0], [1, 0, 0]], [-1], "leg speeds"),
    ],
)
def test_bad_paths_rejected(pts, speeds, match) -> None:
    with pytest.raises(InputError, match=match):
        Path(points=np.array(pts, dtype=float).reshape(-1, 3) if pts else np.zeros((0, 3)), speeds=speeds)


@pytest.mark.parametrize("value", [0.0, -2.0, math.inf, math.nan])
@pytest.mark.parametrize("key", ["acceptance_radius", "lookahead"])
def test_bad_radius_or_lookahead_rejected(key: str, value: float) -> None:
    # both are distances in m: positive and finite (an infinite lookahead steers nowhere)
    with pytest.raises(InputError, match=rf"{key} = {value}: expected a positive distance in m"):
        Path(points=[[0, 0, 0], [1, 0, 0]], speeds=[1], **{key: value})


def test_speed_reduced_by_heading_error() -> None:
    path = square()
    ref, _ = path.update(path.initial_state(), [5.0, 0.0, 2.0], vehicle_heading=math.pi / 3)
    # on the line, psi_d = 0: speed x cos(60 deg) = 0.25 (closed form)
    assert ref.speed == pytest.approx(0.5 * 0.5, rel=1e-12)
    ref, _ = path.update(path.initial_state(), [5.0, 0.0, 2.0], vehicle_heading=math.pi)
    assert ref.speed == 0.0  # pointing backwards: no forward push


def test_default_guidance_state_is_the_start_of_the_path() -> None:
    # GuidanceState() (no arguments) is documented as leg 1 with heading 0: on a path whose first
    # leg is vertical (no course of its own) it is exactly what initial_state() gives, and it
    # steers to waypoint 1, not past it
    from hydrokit.model.guidance import GuidanceState

    path = Path(points=[[0, 0, 0], [0, 0, 5], [10, 0, 5]], speeds=[0.3, 0.5], acceptance_radius=0.5, lookahead=4.0)
    assert GuidanceState() == path.initial_state()
    ref, s = path.update(GuidanceState(), [0.0, 0.0, 1.0])
    assert s.leg == 1 and ref.depth > 1.0 and ref.heading == 0.0


def test_a_leg_speed_of_zero_is_allowed() -> None:
    # "leg speeds ≥ 0 m/s": a leg flown at 0 m/s (hold position while turning) is no error
    from hydrokit.model.guidance import Path

    p = Path(points=[[0, 0, 0], [1, 0, 0], [1, 1, 0]], speeds=[0.0, 0.5])
    np.testing.assert_array_equal(p.speeds, [0.0, 0.5])
