"""Every axis of the figures in the main job's report says its unit ("(–)" when dimensionless)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hydrokit.plot.identify import campaign_axes, coefficients_vs_reynolds, drag_vs_reynolds, launch_fit


def _launch(k: int) -> SimpleNamespace:
    return SimpleNamespace(
        file=f"launch{k}.csv",
        amplitude=0.1 + 0.02 * k,
        added_mass=2.0 + 0.01 * k,
        added_mass_coefficient=0.8,
        linear_damping=1.0,
        quadratic_damping=5.0 + 0.1 * k,
        drag_coefficient=1.1,
        reynolds_max=1e5 * (1 + k),
        std_error={"quadratic_damping": 0.1},
    )


def _labels(fig) -> list[str]:
    return [lab for ax in fig.axes for lab in (ax.get_xlabel(), ax.get_ylabel()) if lab]


def _has_unit(label: str) -> bool:
    return label.rstrip().endswith(")") and "(" in label


@pytest.mark.parametrize(
    "make",
    [
        lambda: launch_fit(np.linspace(0, 5, 50), np.zeros(50), np.zeros(50), "t", "m"),
        lambda: launch_fit(np.linspace(0, 5, 50), np.zeros(50), np.zeros(50), "t", "rad"),
        lambda: campaign_axes([_launch(k) for k in range(5)], "added_mass", {"mean": 2.0}, "kg").figure,
        lambda: coefficients_vs_reynolds({"surge": [_launch(k) for k in range(5)]}),
        lambda: drag_vs_reynolds([_launch(k) for k in range(5)], {"mean": 1.1}).figure,
    ],
    ids=["launch-m", "launch-rad", "campaign", "vs-re", "drag"],
)
def test_every_axis_label_has_a_unit(make):
    labels = _labels(make())
    assert labels and all(_has_unit(lab) for lab in labels), labels


def test_the_launch_amplitude_axis_names_the_rigs_unit():
    ax = campaign_axes([_launch(k) for k in range(5)], "added_mass", {"mean": 2.0}, "kg m^2", amplitude_unit="rad")
    assert ax.get_xlabel() == "launch amplitude (rad)"
