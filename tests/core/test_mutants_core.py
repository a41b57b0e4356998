"""Core behaviour a mutation left unnoticed (issue #13; found by bench/mutation.py)."""

from __future__ import annotations

import dataclasses

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
