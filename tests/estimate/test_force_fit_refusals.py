"""Issue #32 class 5: a force–speed fit with nothing to fit is refused in one line instead of
printing R² = nan (all-zero forces, or forces that do not change with speed)."""

from __future__ import annotations

import pytest

import hydrokit
from hydrokit.errors import InputError

SPEEDS = [0.5, 1.0, 1.5, 2.0]


@pytest.mark.parametrize(
    ("force", "says"),
    [([0.0, 0.0, 0.0, 0.0], r"all 4 forces are 0 N"), ([7.5, 7.5, 7.5, 7.5], r"all 4 forces are 7\.5 N")],
    ids=["all-zero", "constant"],
)
def test_forces_that_do_not_change_with_speed_are_refused(force, says):
    with pytest.raises(InputError, match=rf"^force: {says}: nothing to fit; expected .*change with speed"):
        hydrokit.fit_forces(SPEEDS, force, area=0.1, density=1000.0)


def test_a_curve_with_one_zero_force_is_still_fitted():
    fit = hydrokit.fit_forces(SPEEDS, [0.0, 10.0, 22.5, 40.0], area=0.1, density=1000.0)
    assert 0.9 < fit.r2_morison <= 1.0 and 0.9 < fit.r2_chin <= 1.0
