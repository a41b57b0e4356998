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
