"""Mesh options of ``hydrokit cfd`` (counts and dimensionless targets; the unit in each help text)."""

from __future__ import annotations

from typing import Any

import click

from hydrokit.cli._types import Count, Number

# (flags, click keyword arguments) in the order --help shows them, after the flow options
MESH_OPTIONS: list[tuple[tuple[str, ...], dict[str, Any]]] = [
    (
        ("--grids",),
        {
            "type": click.Choice(["1", "3"]),
            "default": "1",
            "help": "1 grid, or 3 (a refinement triplet, ratio √2) for Richardson extrapolation and GCI.",
        },
    ),
    (
        ("--cells-per-length",),
        {"type": Count(2, 200), "default": 2, "help": "Background cells per body length at grid level 1 (count)."},
    ),
    (
        ("--surface-level",),
        {
            "type": Count(0, 8),
            "default": 4,
            "help": "Refinement levels at the body (count; each halves the cell size).",
        },
    ),
    (
        ("--y-plus",),
        {
            "type": Number("dimensionless", at_least=0, at_most=1000),
            "default": 0.0,
            "help": "Target y⁺ of the first cell at the body (dimensionless); 0: each path's own (wedge y⁺ ≈ 1, "
            "3-D prism layers relative to the surface cells); 30–100 lays both paths for wall functions.",
        },
    ),
    (
        ("--end-level",),
        {
            "type": Count(0, 3),
            "default": 0,
            "help": "3-D path: refinement levels added at the body's fore and aft tenth of its length (count), "
            "where stagnation and pressure recovery set a streamlined hull's pressure drag; 1: about a third more cells.",
        },
    ),
]
