"""The ``hull:`` block of a vehicle file (issue #45 item 3): cross-flow drag and viscous lift of
a body of revolution from its profile, for vehicles without a coefficient table.

```yaml
hull:
  profile: remus100            # a bundled body (remus100, myring) or an x,r CSV, relative to the
                               # vehicle file's folder (the format of hydrokit cfd)
  origin_from_nose: 0.611      # m: the body origin's distance aft of the nose along the axis
                               # (default: the profile's volume centroid, as hydrokit cfd takes it)
  crossflow_drag: true         # true or strips (default) | terms | false
  crossflow_drag_coefficient: 1.1   # C_dc of a circular cylinder (default 1.1, Hoerner 1965)
  strips: 20                   # number of strip elements (default 20)
  lift: true                   # viscous hull lift terms Y_uv, Z_uw, N_uv, M_uw (default false)
  lift_coefficient: 1.2        # body-lift slope c_ydβ, 1/rad (default Hoerner's 0.003 l/d per degree)
  lift_center: -0.321          # m, body x of the lift's centre of pressure (default 0.70 l aft of the nose)
```

The laws and their sources are in :mod:`hydrokit.estimate.hull`. Strips become point drag
elements named ``hull-strip-NN`` (:mod:`hydrokit.core.drag`); ``terms`` and ``lift`` become
derivative terms (SI, SNAME signs) that add to any the file's ``terms:`` gives for the same name.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hydrokit.core.drag import DragElement
from hydrokit.core.validate import cut, cut_repr, mapping, number
from hydrokit.data import DATA_DIR, body_file
from hydrokit.errors import InputError
from hydrokit.estimate import hull as hull_forces
from hydrokit.io.profile import read_profile
from hydrokit.io.yamlfile import check_keys

#: the keys of the ``hull`` block
HULL_KEYS = (
    "profile",
    "origin_from_nose",
    "crossflow_drag",
    "crossflow_drag_coefficient",
    "strips",
    "lift",
    "lift_coefficient",
    "lift_center",
    "description",
    "note",
    "source",
)
#: the values of ``crossflow_drag`` (true is strips)
CROSSFLOW_MODES = ("strips", "terms")
#: most strips a hull may be cut into (each is a drag element evaluated every step)
MAX_STRIPS = 200


def _profile_path(value: Any, source: str) -> Path:
    """The profile CSV: a path relative to the vehicle file's folder, or a bundled body name."""
    if not isinstance(value, str) or not value.strip():
        raise InputError(
            f"field 'hull.profile' = {cut_repr(value)}: expected a bundled body name or an x,r CSV path", source
        )
    folder = Path(source).parent if source else Path(".")
    candidate = folder / value
    if candidate.is_file():
        return candidate
    if "/" not in value and "\\" not in value and not value.endswith(".csv"):
        path = body_file(value)  # InputError naming the bundled bodies
        if path.suffix != ".csv":
            raise InputError(
                f"field 'hull.profile' = {value!r}: bundled body {path.name} is not an x,r profile", source
            )
        return path
    raise InputError(f"field 'hull.profile' = {cut(value)!r}: no such file (relative to {folder})", source)


def _flag(value: Any, key: str, source: str) -> bool:
    if not isinstance(value, bool):
        raise InputError(f"field 'hull.{key}' = {cut_repr(value)}: expected true or false", source)
    return value


def read_hull_block(
    value: dict[str, Any], source: str, density: float
) -> tuple[list[DragElement], list[tuple[str, float]]]:
    """Drag elements and derivative terms of a vehicle file's ``hull:`` block.

    Parameters
    ----------
    value : dict — the block as read from YAML (see the module docstring)
    source : str — the vehicle file's path (a relative profile path is taken from its folder)
    density : float — the vehicle's fluid density ρ, kg/m³

    Returns
    -------
    elements : list of DragElement — the cross-flow strips (positions m, quadratic N·s²/m² on y
        and z); empty unless ``crossflow_drag`` is true or ``strips``
    terms : list of (str, float) — term name and SI coefficient (SNAME signs): Prestero's
        cross-flow derivatives when ``crossflow_drag: terms``, the hull-lift terms when ``lift``

    Raises
    ------
    InputError
        One line naming the field (``hull.strips``), the bad value and what was expected.
    """
    mapping(value, "hull", source)
    check_keys(value, HULL_KEYS, "hull", source)
    if "profile" not in value:
        raise InputError("field 'hull': missing 'profile' (a bundled body or an x,r CSV)", source)
    path = _profile_path(value["profile"], source)
    where = f"{source}: hull.profile {path.name if path.is_relative_to(DATA_DIR) else path}"
    x, r = hull_forces.check_hull_profile(*read_profile(path), where)
    if "origin_from_nose" in value:
        origin = number(value["origin_from_nose"], "hull.origin_from_nose", source)
    else:
        origin = hull_forces.profile_centroid(x, r)
    mode = value.get("crossflow_drag", True)
    if mode is True:
        mode = "strips"
    if mode is not False and mode not in CROSSFLOW_MODES:
        raise InputError(
            f"field 'hull.crossflow_drag' = {cut_repr(mode)}: expected true (strips), strips, terms or false", source
        )
    c_dc = number(
        value.get("crossflow_drag_coefficient", hull_forces.CYLINDER_CROSSFLOW_DRAG),
        "hull.crossflow_drag_coefficient",
        source,
        nonneg=True,
    )
    strips = value.get("strips", hull_forces.DEFAULT_STRIPS)
    if isinstance(strips, bool) or not isinstance(strips, int) or not 1 <= strips <= MAX_STRIPS:
        raise InputError(f"field 'hull.strips' = {cut_repr(strips)}: expected a whole number 1–{MAX_STRIPS}", source)
    elements: list[DragElement] = []
    terms: list[tuple[str, float]] = []
    if mode == "strips":
        positions, quadratic = hull_forces.crossflow_strips(x, r, origin, density, c_dc, strips)
        elements = [
            DragElement(f"hull-strip-{k + 1:02d}", (float(p), 0.0, 0.0), quadratic=(0.0, float(q), float(q)))
            for k, (p, q) in enumerate(zip(positions, quadratic, strict=True))
        ]
    elif mode == "terms":
        terms += list(hull_forces.crossflow_derivatives(x, r, origin, density, c_dc).items())
    if _flag(value.get("lift", False), "lift", source):
        length, diameter = float(x[-1] - x[0]), 2.0 * float(r.max())
        slope = value.get("lift_coefficient")
        slope = (
            hull_forces.hoerner_body_lift_slope(length, diameter)
            if slope is None
            else number(slope, "hull.lift_coefficient", source, nonneg=True)
        )
        center = value.get("lift_center")
        center = (
            origin - (x[0] + hull_forces.LIFT_CENTER_FRACTION * length)
            if center is None
            else number(center, "hull.lift_center", source)
        )
        terms += list(hull_forces.hull_lift_derivatives(diameter, density, slope, float(center)).items())
    elif "lift_coefficient" in value or "lift_center" in value:
        raise InputError("field 'hull': lift_coefficient or lift_center given without 'lift: true'", source)
    return elements, terms
