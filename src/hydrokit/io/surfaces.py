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
    neutral_deflection_deg: 0.5    # optional: the fin's zero-lift deflection (default 0)
    slipstream: {diameter: 0.1, thrust_share: 1.0}   # a rudder in a propeller race
    # or the race of a named thruster, with the MMG standard method's rudder inflow:
    # slipstream: {thruster: prop, inflow: mmg, epsilon: 1.09, kappa: 0.5, rudder_height: 0.25,
    #              gamma_R_positive: 0.640, gamma_R_negative: 0.395, l_R: -0.71}
```

``slipstream`` keys: ``diameter`` (m; default the named thruster's ``diameter``),
``thrust_share`` (the share of the commanded surge force that is the propeller's thrust when the
run gives no thruster's thrust; default 1), ``thruster`` (a name of the ``thrusters:`` block:
its thrust at each instant and its ``wake_fraction``), ``inflow`` (``race``: the fully developed
race of momentum theory, default; ``mmg``: Yasukawa & Yoshimura 2015), and for ``mmg``
``epsilon`` ε, ``kappa`` κ, ``eta`` η = D/H_R or ``rudder_height`` H_R (m), ``gamma_R_positive``
and ``gamma_R_negative`` (flow straightening for β_R > 0 and < 0), ``l_R`` (m, l_R' × L);
each defaults to 1 (l_R: the rudder's x position, the geometric value).

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
    INFLOW_LAWS,
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
    "neutral_deflection_deg",
)
EXTRA_KEYS = ("description", "note", "source", "chord")
#: the MMG inflow's numbers in ``slipstream`` (each defaults to 1; l_R to the rudder's x, m)
MMG_KEYS = ("epsilon", "kappa", "eta", "rudder_height", "gamma_R_positive", "gamma_R_negative", "l_R")
SLIPSTREAM_KEYS = ("diameter", "thrust_share", "thruster", "inflow", *MMG_KEYS)


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


def _slipstream(
    slip: Any, where: str, source: str, position: np.ndarray, axis: tuple[float, float, float], thrusters: Any
) -> dict[str, Any]:
    """The :class:`Fin` fields of a ``slipstream`` block (module docstring). ``thrusters`` maps each
    thruster's name to its raw entry (file order)."""
    at = f"{where}.slipstream"
    slip = mapping(slip, at, source)
    check_keys(slip, SLIPSTREAM_KEYS, at, source)
    out: dict[str, Any] = {}
    entry: dict[str, Any] = {}
    if "thruster" in slip:
        name = slip["thruster"]
        names = list(thrusters)
        if not isinstance(name, str) or name not in names:
            raise InputError(
                f"field '{at}.thruster' = {cut_repr(name)}: names no thruster of the vehicle "
                f"(thrusters: {', '.join(names) or 'none'})",
                source,
            )
        out["race_thruster"] = names.index(name)
        entry = thrusters[name]
        w = number(entry.get("wake_fraction", 0.0), f"thrusters ({name}).wake_fraction", source)
        out["wake_fraction"] = w if 0 <= w < 1 else 0.0  # a bad one is said by the thrusters' reader
    if "diameter" in slip:
        out["slipstream_diameter"] = number(slip["diameter"], f"{at}.diameter", source, positive=True)
    elif "diameter" in entry:
        out["slipstream_diameter"] = number(entry["diameter"], f"{at}.thruster's diameter", source, positive=True)
    else:
        raise InputError(f"field '{at}': missing 'diameter' (m, the propeller's)", source)
    out["thrust_share"] = number(slip.get("thrust_share", 1.0), f"{at}.thrust_share", source, nonneg=True)
    inflow = slip.get("inflow", "race")
    if inflow not in INFLOW_LAWS:
        raise InputError(f"field '{at}.inflow' = {cut_repr(inflow)}: expected one of {', '.join(INFLOW_LAWS)}", source)
    out["inflow"] = inflow
    given = [k for k in MMG_KEYS if k in slip]
    if inflow != "mmg":
        if given:
            raise InputError(f"field '{at}': {', '.join(given)} given without 'inflow: mmg'", source)
        return out
    if abs(axis[2]) < 0.99:
        raise InputError(
            f"field '{where}.axis' = {list(axis)}: the MMG rudder inflow is for a rudder; expected a hinge along "
            "body z ([0, 0, 1])",
            source,
        )
    for key, field in (("epsilon", "epsilon"), ("kappa", "kappa")):
        out[field] = number(slip.get(key, 1.0), f"{at}.{key}", source, positive=True)
    if "eta" in slip and "rudder_height" in slip:
        raise InputError(f"field '{at}': give 'eta' or 'rudder_height' (m), not both", source)
    if "rudder_height" in slip:
        h = number(slip["rudder_height"], f"{at}.rudder_height", source, positive=True)
        out["eta"] = out["slipstream_diameter"] / h
    else:
        out["eta"] = number(slip.get("eta", 1.0), f"{at}.eta", source, positive=True)
    if out["eta"] > 1.0:
        raise InputError(
            f"field '{at}': eta = D/H_R = {out['eta']:.4g}: expected at most 1 (a propeller no taller than the rudder)",
            source,
        )
    out["gamma_positive"] = number(slip.get("gamma_R_positive", 1.0), f"{at}.gamma_R_positive", source, nonneg=True)
    out["gamma_negative"] = number(slip.get("gamma_R_negative", 1.0), f"{at}.gamma_R_negative", source, nonneg=True)
    out["l_R"] = number(slip["l_R"], f"{at}.l_R", source) if "l_R" in slip else float(position[0])
    return out


def _fin(
    entry: dict[str, Any], where: str, source: str, position: np.ndarray | None = None, thrusters: Any = None
) -> Fin | None:
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
    race: dict[str, Any] = {}
    if "slipstream" in entry:
        pos = np.zeros(3) if position is None else position
        race = _slipstream(entry["slipstream"], where, source, pos, axis, thrusters or {})
    neutral = 0.0
    if "neutral_deflection_deg" in entry:
        nd = number(entry["neutral_deflection_deg"], f"{where}.neutral_deflection_deg", source)
        if abs(nd) > stall_deg:
            raise InputError(
                f"field '{where}.neutral_deflection_deg' = {nd:g}: expected at most the stall angle ({stall_deg:g}°)",
                source,
            )
        neutral = math.radians(nd)
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
        neutral_deflection=neutral,
        **race,
    )


def read_control_surfaces(value: Any, source: str, thrusters: tuple[str, ...] = (), entries: Any = None) -> SurfaceSet:
    """``control_surfaces:`` as a :class:`~hydrokit.model.surfaces.SurfaceSet` (empty when absent).

    ``thrusters`` : the names of the ``thrusters:`` block in file order, and ``entries`` its raw
    entries (a race's ``thruster`` takes its diameter and wake fraction from them).
    """
    raw = entries if isinstance(entries, list) else []
    named = {n: (e if isinstance(e, dict) else {}) for n, e in zip(thrusters, raw + [{}] * len(thrusters))}
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
                fin=_fin(entry, where, source, pos, named),
            )
        )
    return SurfaceSet(tuple(out))
