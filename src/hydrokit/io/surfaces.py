"""The ``control_surfaces:`` and ``dofs:`` blocks of a vehicle file (issue #45; frozen fields).

```yaml
dofs: [surge, sway, yaw]          # optional: a planar model; the others held at zero
control_surfaces:
  - name: rudder
    position: [-0.6, 0, 0]         # m, body axes
    max_deflection_deg: 30         # mechanical limit
    rate_limit_deg_s: 10           # optional servo rate limit
    time_constant: 0.1             # optional first-order servo lag, s
    # a physical fin (optional; without `area` the surface is a deflection variable only):
    axis: [0, 0, 1]                # hinge; positive deflection right-handed about it
    area: 0.0106                   # m^2
    aspect_ratio: 1.5              # and/or lift_slope (1/rad); slope by Helmbold when only AR
    stall_angle_deg: 15
    stall_width_deg: 10            # blend to the flat plate above stall (default 10)
    drag_coefficient: 0.01         # C_D0 (default 0)
    oswald: 0.9                    # e of the induced drag C_L²/(π e AR) (default 0.9)
    normal_force_coefficient: 1.2  # flat-plate C_N beyond stall (default 1.2)
    slipstream: {diameter: 0.1, thrust_share: 1.0}   # a rudder in a propeller race
```

Degrees are converted here, at the edge; the model holds radians
(:mod:`hydrokit.model.surfaces`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.core.validate import cut, cut_repr, mapping, number, vector
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import check_keys
from hydrokit.model.surfaces import (
    DEFAULT_STALL_WIDTH,
    FLAT_PLATE_NORMAL_FORCE,
    MAX_SURFACES,
    ControlSurface,
    Fin,
    SurfaceSet,
    helmbold_lift_slope,
)

SURFACE_KEYS = ("name", "position", "max_deflection_deg", "rate_limit_deg_s", "time_constant")
FIN_KEYS = (
    "axis",
    "area",
    "aspect_ratio",
    "lift_slope",
    "stall_angle_deg",
    "stall_width_deg",
    "drag_coefficient",
    "oswald",
    "normal_force_coefficient",
    "slipstream",
)
EXTRA_KEYS = ("description", "note", "source", "chord")
SLIPSTREAM_KEYS = ("diameter", "thrust_share")


def read_dofs(value: Any, source: str) -> tuple[int, ...] | None:
    """``dofs:`` as kept DOF indices (None when absent): names from surge … yaw, none repeated."""
    if value is None:
        return None
    if not isinstance(value, list) or not value:
        raise InputError(
            f"field 'dofs' = {cut_repr(value)}: expected a list of DOF names ({', '.join(DOF_NAMES)})", source
        )
    out: list[int] = []
    for k, name in enumerate(value):
        if name not in DOF_NAMES:
            raise InputError(f"field 'dofs[{k}]' = {cut_repr(name)}: expected one of {', '.join(DOF_NAMES)}", source)
        idx = DOF_NAMES.index(name)
        if idx in out:
            raise InputError(f"field 'dofs[{k}]' = {name!r}: repeated; expected each DOF once", source)
        out.append(idx)
    if 0 not in out:
        raise InputError(f"field 'dofs' = {value}: expected surge among the kept DOF", source)
    return tuple(sorted(out))


def _unit(value: Any, n: int, where: str, source: str) -> tuple[float, float, float]:
    a = vector(value, n, where, source)
    norm = float(np.linalg.norm(a))
    if not norm > 1e-9:
        raise InputError(f"field '{where}' = {a.tolist()}: expected a vector of non-zero length", source)
    u = a / norm
    return float(u[0]), float(u[1]), float(u[2])


def _fin(entry: dict[str, Any], where: str, source: str) -> Fin | None:
    """The physical model of a surface entry, or None when it has no ``area``."""
    if "area" not in entry:
        given = [k for k in FIN_KEYS if k in entry]
        if given:
            raise InputError(
                f"field '{where}': {', '.join(given)} given without 'area' (m^2); expected 'area' for a physical fin "
                "or none of the fin fields for a deflection variable",
                source,
            )
        return None
    area = number(entry["area"], f"{where}.area", source, positive=True)
    axis = _unit(entry.get("axis"), 3, f"{where}.axis", source) if "axis" in entry else None
    if axis is None:
        raise InputError(f"field '{where}': missing 'axis' (the hinge, a unit vector in body axes)", source)
    # zero-deflection chord: the body x axis with its hinge component removed
    x = np.array([1.0, 0.0, 0.0]) - axis[0] * np.asarray(axis)
    if np.linalg.norm(x) < 1e-6:
        raise InputError(
            f"field '{where}.axis' = {list(axis)}: a hinge along the body x axis leaves no chord; expected an axis "
            "across the flow",
            source,
        )
    chord = x / np.linalg.norm(x)
    ar = (
        number(entry["aspect_ratio"], f"{where}.aspect_ratio", source, positive=True)
        if "aspect_ratio" in entry
        else 0.0
    )
    if "lift_slope" in entry:
        slope = number(entry["lift_slope"], f"{where}.lift_slope", source, positive=True)
    elif ar > 0:
        slope = helmbold_lift_slope(ar)
    else:
        raise InputError(f"field '{where}': expected 'aspect_ratio' or 'lift_slope' (1/rad) for a physical fin", source)
    if "stall_angle_deg" not in entry:
        raise InputError(f"field '{where}': missing 'stall_angle_deg' (deg, > 0)", source)
    stall_deg = number(entry["stall_angle_deg"], f"{where}.stall_angle_deg", source)
    if not 0 < stall_deg < 90:
        raise InputError(
            f"field '{where}.stall_angle_deg' = {stall_deg:g}: expected an angle in (0, 90) degrees", source
        )
    width = (
        math.radians(number(entry["stall_width_deg"], f"{where}.stall_width_deg", source, positive=True))
        if "stall_width_deg" in entry
        else DEFAULT_STALL_WIDTH
    )
    cd0 = number(entry.get("drag_coefficient", 0.0), f"{where}.drag_coefficient", source, nonneg=True)
    e = number(entry.get("oswald", 0.9), f"{where}.oswald", source, positive=True)
    cn = number(
        entry.get("normal_force_coefficient", FLAT_PLATE_NORMAL_FORCE),
        f"{where}.normal_force_coefficient",
        source,
        positive=True,
    )
    d_s, share = 0.0, 1.0
    if "slipstream" in entry:
        slip = mapping(entry["slipstream"], f"{where}.slipstream", source)
        check_keys(slip, SLIPSTREAM_KEYS, f"{where}.slipstream", source)
        if "diameter" not in slip:
            raise InputError(f"field '{where}.slipstream': missing 'diameter' (m, the propeller's)", source)
        d_s = number(slip["diameter"], f"{where}.slipstream.diameter", source, positive=True)
        share = number(slip.get("thrust_share", 1.0), f"{where}.slipstream.thrust_share", source, nonneg=True)
    return Fin(
        axis=axis,
        chord=(float(chord[0]), float(chord[1]), float(chord[2])),
        area=area,
        lift_slope=slope,
        stall_angle=math.radians(stall_deg),
        stall_width=width,
        drag_coefficient=cd0,
        aspect_ratio=ar,
        oswald=e,
        normal_force_coefficient=cn,
        slipstream_diameter=d_s,
        thrust_share=share,
    )


def read_control_surfaces(value: Any, source: str) -> SurfaceSet:
    """``control_surfaces:`` as a :class:`~hydrokit.model.surfaces.SurfaceSet` (empty when absent)."""
    if value is None:
        return SurfaceSet()
    if not isinstance(value, list):
        raise InputError(
            f"field 'control_surfaces' = {cut_repr(value)}: expected a list of {{name, position, max_deflection_deg …}}",
            source,
        )
    if len(value) > MAX_SURFACES:
        raise InputError(f"field 'control_surfaces': {len(value)} surfaces; expected at most {MAX_SURFACES}", source)
    out: list[ControlSurface] = []
    seen: dict[str, int] = {}
    for k, entry in enumerate(value):
        where = f"control_surfaces[{k}]"
        mapping(entry, where, source)
        check_keys(entry, (*SURFACE_KEYS, *FIN_KEYS, *EXTRA_KEYS), where, source)
        for key in ("name", "position", "max_deflection_deg"):
            if key not in entry:
                raise InputError(f"field '{where}': missing '{key}'", source)
        name = entry["name"]
        if not isinstance(name, str) or not name.strip() or not all(c.isalnum() or c in "_-." for c in name):
            raise InputError(
                f"field '{where}.name' = {cut_repr(name)}: expected a name of letters, digits, '_', '-' or '.'", source
            )
        if name in seen:
            raise InputError(
                f"field '{where}.name' = {name!r}: expected a unique name (control_surfaces[{seen[name]}] has it)",
                source,
            )
        seen[name] = k
        pos = vector(entry["position"], 3, f"{where}.position", source)
        max_deg = number(entry["max_deflection_deg"], f"{where}.max_deflection_deg", source, positive=True)
        if max_deg > 90:
            raise InputError(f"field '{where}.max_deflection_deg' = {max_deg:g}: expected at most 90 degrees", source)
        rate = (
            math.radians(number(entry["rate_limit_deg_s"], f"{where}.rate_limit_deg_s", source, positive=True))
            if "rate_limit_deg_s" in entry
            else math.inf
        )
        lag = number(entry.get("time_constant", 0.0), f"{where}.time_constant", source, nonneg=True)
        out.append(
            ControlSurface(
                name=cut(name),
                position=(float(pos[0]), float(pos[1]), float(pos[2])),
                max_deflection=math.radians(max_deg),
                rate_limit=rate,
                time_constant=lag,
                fin=_fin(entry, where, source),
            )
        )
    return SurfaceSet(tuple(out))
