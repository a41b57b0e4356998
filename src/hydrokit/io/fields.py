"""Identified fields written back into a vehicle document (issue #48): a fit that frees
``control_surfaces.NAME.FIELD``, ``thrusters.NAME.FIELD`` or ``wind.FIELD``
(:mod:`hydrokit.model.uncertainty`) must write the fitted numbers where the vehicle file keeps
them, so that the written file loads back with them and its ``uncertainty:`` block is centred on
them.

Where each lands, in the file's own units (the values are those of
:func:`hydrokit.model.uncertainty.parameter_value`: degrees for a ``*_deg`` field):

- a surface's ``lift_slope``, ``area``, ``drag_coefficient``, ``stall_angle_deg``,
  ``neutral_deflection_deg``: the ``control_surfaces`` entry of that name; its race's
  ``diameter``, ``thrust_share`` and the MMG numbers (``epsilon``, ``kappa``, ``eta``,
  ``gamma_R_positive``, ``gamma_R_negative``, ``l_R``): the entry's ``slipstream`` mapping;
- a thruster's ``wake_fraction``, ``thrust_deduction``: the ``thrusters`` entry of that name;
- the wind model's ``frontal_area``, ``lateral_area``, ``s_L``: the ``wind`` block; Blendermann's
  ``CD_t``, ``CD_l_AF_bow``, ``CD_l_AF_stern``, ``delta``: ``wind.parameters`` (the 4 numbers;
  a ``vessel:`` name is replaced by its numbers, which are no longer that vessel's); a table row's
  ``coefficients.C_Y.<angle_deg>``: ``wind.coefficients.C_Y`` at the row whose ``angle_deg`` is
  that angle.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from hydrokit.errors import InputError
from hydrokit.model.uncertainty import SURFACE_PREFIX, THRUSTER_PREFIX, WIND_PREFIX
from hydrokit.model.wind import BLENDERMANN_1994, parse_wind_field

#: the surface fields kept in the entry's ``slipstream`` mapping (the rest at the entry's level)
SLIPSTREAM_FIELDS = (
    "diameter",
    "thrust_share",
    "epsilon",
    "kappa",
    "eta",
    "gamma_R_positive",
    "gamma_R_negative",
    "l_R",
)
#: Blendermann's four numbers in the order of ``wind.parameters``
BLENDERMANN_ORDER = ("CD_t", "CD_l_AF_bow", "CD_l_AF_stern", "delta")


def is_field(name: str) -> bool:
    """Whether ``name`` is a surface's, a thruster's or the wind model's field."""
    return name.startswith((SURFACE_PREFIX, THRUSTER_PREFIX, WIND_PREFIX))


def _entry(doc: dict[str, Any], block: str, name: str) -> dict[str, Any]:
    entries = doc.get(block)
    for entry in entries if isinstance(entries, list) else []:
        if isinstance(entry, dict) and entry.get("name") == name:
            return entry
    raise InputError(f"field '{block}': no entry named {name!r} to write the identified value into")


def write_fields(doc: dict[str, Any], values: Sequence[tuple[str, float]]) -> dict[str, Any]:
    """Write identified field values (module docstring) into the vehicle document ``doc``
    (changed in place and returned; its nested entries are copied before they change, so a
    document shared with the base file is left as it was).

    Parameters
    ----------
    doc : dict — a vehicle file's fields, as read
    values : (name, value) pairs — ``control_surfaces.NAME.FIELD``, ``thrusters.NAME.FIELD``,
        ``wind.FIELD``, each in its file unit (other names are ignored)

    Raises
    ------
    InputError
        A name whose surface, thruster, wind block or table row the document does not hold.
    """
    for name, raw in values:
        value = float(raw)
        if name.startswith(WIND_PREFIX):
            _write_wind(doc, name[len(WIND_PREFIX) :], value)
            continue
        for prefix, block in ((SURFACE_PREFIX, "control_surfaces"), (THRUSTER_PREFIX, "thrusters")):
            if not name.startswith(prefix):
                continue
            owner, _, field = name[len(prefix) :].rpartition(".")
            doc[block] = [dict(e) if isinstance(e, dict) else e for e in doc.get(block) or []]
            entry = _entry(doc, block, owner)
            if block == "control_surfaces" and field in SLIPSTREAM_FIELDS:
                slip = dict(entry.get("slipstream") or {})
                slip[field] = value
                entry["slipstream"] = slip
            else:
                entry[field] = value
    return doc


def _write_wind(doc: dict[str, Any], field_name: str, value: float) -> None:
    block = doc.get("wind")
    if not isinstance(block, dict):
        raise InputError(f"field 'wind': none to write the identified wind.{field_name} into")
    block = dict(block)
    doc["wind"] = block
    field, angle = parse_wind_field(field_name)
    if field in BLENDERMANN_ORDER:
        vessel = block.pop("vessel", None)
        pars = block.get("parameters")
        numbers = list(pars) if isinstance(pars, list) else list(BLENDERMANN_1994[str(vessel)])
        numbers[BLENDERMANN_ORDER.index(field)] = value
        block["parameters"] = [float(x) for x in numbers]
        return
    if angle is None:
        block[field] = value
        return
    table = dict(block.get("coefficients") or {})
    angles = [float(a) for a in table.get("angle_deg") or []]
    rows = [k for k, a in enumerate(angles) if math.isclose(a, angle, rel_tol=0.0, abs_tol=1e-6)]
    if not rows:
        raise InputError(f"field 'wind.coefficients.angle_deg': no row at {angle:g}° to write wind.{field_name} into")
    column = list(table[field])
    column[rows[0]] = value
    table[field] = column
    block["coefficients"] = table
