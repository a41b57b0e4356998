from __future__ import annotations

import pytest

from hydrokit.identify.types import Rig


@pytest.fixture
def pendulum_rig() -> Rig:
    """CELY2019 pendulum model (m = 0.146 kg, V = 107 597 mm³, g = 9.79) on a 0.39 m rod."""
    return Rig(
        test="pendulum",
        axis="surge",
        gravity=9.79,
        density=998.2,
        kinematic_viscosity=1e-6,
        mass=0.146,
        volume=107597e-9,
        reference_area=0.004,
        reference_length=0.087,
        pendulum_length=0.39,
    )


@pytest.fixture
def spring_rig() -> Rig:
    """CELY2019 spring rig (m = 0.97 kg, V = 344 868 mm³, k = 63.6 N/m)."""
    return Rig(
        test="spring",
        axis="surge",
        gravity=9.79,
        density=998.2,
        kinematic_viscosity=1e-6,
        mass=0.97,
        volume=344868e-9,
        reference_area=0.008,
        reference_length=0.09,
        stiffness=63.6,
    )


@pytest.fixture
def torsion_rig() -> Rig:
    """A yaw torsion rig: body inertia 0.02 kg m², K = 0.5 N m/rad."""
    return Rig(
        test="torsion",
        axis="yaw",
        gravity=9.81,
        density=998.2,
        kinematic_viscosity=1e-6,
        mass=1.0,
        volume=1e-3,
        reference_area=0.01,
        reference_length=0.2,
        inertia=0.02,
        stiffness=0.5,
    )
