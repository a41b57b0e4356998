"""Rig files (YAML): one rig and the tested body. Format frozen by issue #2 (docs/identify.md).

```yaml
test: pendulum          # spring | pendulum | torsion | floating
axis: surge             # surge | sway | heave | roll | pitch | yaw (floating: heave | roll | pitch)
gravity: 9.81           # m/s^2 (default 9.81)
fluid: {density: 998.2, kinematic_viscosity: 1.0e-6}   # kg/m^3, m^2/s
body: {mass: 0.146, volume: 1.07597e-4, reference_area: 0.004, reference_length: 0.087, inertia: 0.0}
pendulum: {length: 0.39}     # m          (pendulum only)
spring:   {stiffness: 63.6}  # N/m        (spring only)
torsion:  {stiffness: 0.5}   # N m/rad    (torsion only)
floating: {gm: 0.05}         # exactly one of gm (m, roll/pitch), waterplane_area (m², heave),
                             # restoring [C1, C3, C5] (SI) or gz [[deg, m], ...] (roll/pitch)
```

Optional extras: ``pendulum.rod_mass`` (kg), ``pendulum.rod_volume`` (m³), ``tare.linear_damping``
and ``tare.quadratic_damping`` (reported units), ``wall_distance`` (m), ``scale`` (model/full
length ratio), ``sensor`` (free-form description: sample_rate Hz, noise, resolution).
"""

from __future__ import annotations

import math
import os
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from hydrokit.core.constants import GRAVITY
from hydrokit.core.validate import body_quantity
from hydrokit.errors import InputError
from hydrokit.identify.types import AXES, FLOATING_AXES, TESTS, Rig, rig_document
from hydrokit.io.yamlfile import pydantic_error_line, read_yaml


def _finite(v: float) -> float:
    if not math.isfinite(v):
        raise ValueError("expected a finite number")
    return v


class _Fluid(BaseModel):
    model_config = ConfigDict(extra="forbid")
    density: float = Field(gt=0, description="kg/m^3")
    kinematic_viscosity: float = Field(1.0e-6, gt=0, description="m^2/s")
    _f = field_validator("density", "kinematic_viscosity")(_finite)


class _Body(BaseModel):
    model_config = ConfigDict(extra="forbid")
    mass: float = Field(gt=0, description="kg")
    volume: float = Field(gt=0, description="m^3")
    reference_area: float = Field(gt=0, description="m^2")
    reference_length: float = Field(gt=0, description="m")
    inertia: float = Field(0.0, ge=0, description="kg m^2")
    _f = field_validator("mass", "volume", "reference_area", "reference_length", "inertia")(_finite)


class _Pendulum(BaseModel):
    model_config = ConfigDict(extra="forbid")
    length: float = Field(gt=0, description="m")
    rod_mass: float = Field(0.0, ge=0, description="kg")
    rod_volume: float = Field(0.0, ge=0, description="m^3")


class _Stiffness(BaseModel):
    model_config = ConfigDict(extra="forbid")
    stiffness: float = Field(gt=0)
    _f = field_validator("stiffness")(_finite)


class _Floating(BaseModel):
    """The floating body's restoring: exactly one field (checked in :func:`_floating`)."""

    model_config = ConfigDict(extra="forbid")
    gm: float | None = Field(None, description="m, metacentric height (roll/pitch)")
    waterplane_area: float | None = Field(None, description="m^2 (heave)")
    restoring: list[float] | None = Field(None, min_length=1, max_length=3, description="[C1, C3, C5], SI")
    gz: list[tuple[float, float]] | None = Field(None, description="[[deg, m], ...] righting-arm curve")

    @field_validator("gm", "waterplane_area")
    @classmethod
    def _fin(cls, v: float | None) -> float | None:
        return None if v is None else _finite(v)

    @field_validator("restoring")
    @classmethod
    def _fin_list(cls, v: list[float] | None) -> list[float] | None:
        if v is not None:
            for x in v:
                _finite(x)
        return v

    @field_validator("gz")
    @classmethod
    def _fin_table(cls, v: list[tuple[float, float]] | None) -> list[tuple[float, float]] | None:
        if v is not None:
            for a, b in v:
                _finite(a)
                _finite(b)
        return v


#: which floating restoring suits which axis
_FLOATING_AXES = {
    "gm": ("roll", "pitch"),
    "waterplane_area": ("heave",),
    "restoring": FLOATING_AXES,
    "gz": ("roll", "pitch"),
}


def _floating(f: RigFile, source: str) -> tuple[tuple[str, Any], float]:
    """The floating rig's restoring (kind, value) and its linear stiffness C1 (SI)."""
    if f.axis not in FLOATING_AXES:
        raise InputError(f"field 'axis' = {f.axis!r}: a floating rig oscillates in {', '.join(FLOATING_AXES)}", source)
    fl = f.floating
    given = [k for k in _FLOATING_AXES if fl is not None and getattr(fl, k) is not None]
    if not given:
        raise InputError(
            "field 'floating' is missing: a floating rig needs one of floating.gm (m), "
            "floating.waterplane_area (m²), floating.restoring [C1, C3, C5] or floating.gz [[deg, m], ...]",
            source,
        )
    if len(given) > 1:
        raise InputError(
            f"field 'floating' gives {' and '.join(given)}: expected exactly one restoring "
            "(gm, waterplane_area, restoring or gz)",
            source,
        )
    assert fl is not None
    kind = given[0]
    if f.axis not in _FLOATING_AXES[kind]:
        raise InputError(
            f"field 'floating.{kind}' does not suit axis {f.axis!r}: expected axis {' or '.join(_FLOATING_AXES[kind])}",
            source,
        )
    if f.axis != "heave" and f.body.inertia <= 0:
        raise InputError(
            f"field 'body.inertia' = {f.body.inertia}: a floating rig in {f.axis} needs the body's dry "
            "inertia about the axis (kg·m², > 0)",
            source,
        )
    rho_g = f.fluid.density * f.gravity
    if kind == "gm":
        gm = float(fl.gm)  # type: ignore[arg-type]
        if gm <= 0:
            raise InputError(
                f"field 'floating.gm' = {gm}: expected a positive metacentric height (m); GM ≤ 0 is unstable", source
            )
        return ("gm", gm), rho_g * f.body.volume * gm
    if kind == "waterplane_area":
        awp = float(fl.waterplane_area)  # type: ignore[arg-type]
        if awp <= 0:
            raise InputError(f"field 'floating.waterplane_area' = {awp}: expected a positive area (m²)", source)
        return ("waterplane_area", awp), rho_g * awp
    if kind == "restoring":
        coef = [float(x) for x in fl.restoring or []] + [0.0] * (3 - len(fl.restoring or []))
        if coef[0] <= 0:
            raise InputError(
                f"field 'floating.restoring' = {fl.restoring}: expected C1 > 0 (the linear restoring, "
                f"{'N/m' if f.axis == 'heave' else 'N·m/rad'}) in [C1, C3, C5]",
                source,
            )
        return ("restoring", (coef[0], coef[1], coef[2])), coef[0]
    table = [(float(a), float(b)) for a, b in fl.gz or []]
    if len(table) < 2:
        raise InputError(f"field 'floating.gz' has {len(table)} row(s): expected at least two [deg, m] rows", source)
    if table[0] != (0.0, 0.0):
        raise InputError(
            f"field 'floating.gz' starts at {list(table[0])}: expected the first row [0, 0] (zero angle, zero arm)",
            source,
        )
    for (a0, _), (a1, _) in zip(table, table[1:]):
        if a1 <= a0:
            raise InputError(
                f"field 'floating.gz': angle {a1:g}° follows {a0:g}°: expected strictly increasing angles (deg)",
                source,
            )
    if table[-1][0] >= 180.0:
        raise InputError(f"field 'floating.gz': angle {table[-1][0]:g}°: expected angles below 180°", source)
    if table[1][1] <= 0:
        raise InputError(
            f"field 'floating.gz': arm {table[1][1]:g} m at {table[1][0]:g}°: expected a positive righting arm "
            "next to zero (a stable body)",
            source,
        )
    gm0 = table[1][1] / math.radians(table[1][0])
    return ("gz", tuple(table)), rho_g * f.body.volume * gm0


class _Tare(BaseModel):
    model_config = ConfigDict(extra="forbid")
    linear_damping: float = 0.0
    quadratic_damping: float = 0.0


class RigFile(BaseModel):
    """The rig file schema (see module docstring)."""

    model_config = ConfigDict(extra="forbid")
    test: Literal["spring", "pendulum", "torsion", "floating"]
    axis: Literal["surge", "sway", "heave", "roll", "pitch", "yaw"]
    gravity: float = Field(GRAVITY, gt=0, description="m/s^2")
    fluid: _Fluid
    body: _Body
    pendulum: _Pendulum | None = None
    spring: _Stiffness | None = None
    torsion: _Stiffness | None = None
    floating: _Floating | None = None
    tare: _Tare | None = None
    wall_distance: float | None = Field(None, gt=0, description="m")
    scale: float | None = Field(None, gt=0, description="model/full-size length ratio")
    sensor: dict[str, Any] | None = None
    name: str | None = None
    description: str | None = None


def parse_rig(data: dict[str, Any], source: str) -> Rig:
    """Validate a rig mapping and return the :class:`Rig` (errors name the file and field)."""
    if "test" in data and data["test"] not in TESTS:
        raise InputError(f"field 'test' = {data['test']!r}: expected spring, pendulum, torsion or floating", source)
    if "axis" in data and data["axis"] not in AXES:
        raise InputError(f"field 'axis' = {data['axis']!r}: expected one of {', '.join(AXES)}", source)
    try:
        f = RigFile.model_validate(data)
    except ValidationError as exc:
        raise pydantic_error_line(exc, source, RigFile) from None
    for name, kind in (
        ("mass", "mass"),
        ("volume", "volume"),
        ("reference_area", "area"),
        ("reference_length", "size"),
    ):
        body_quantity(getattr(f.body, name), kind, f"body.{name}", source)
    stiffness = None
    if f.test == "pendulum" and f.pendulum is None:
        raise InputError("field 'pendulum.length' is missing: a pendulum rig needs its length (m)", source)
    if f.test == "spring":
        if f.spring is None:
            raise InputError("field 'spring.stiffness' is missing: a spring rig needs its stiffness (N/m)", source)
        stiffness = f.spring.stiffness
    if f.test == "torsion":
        if f.torsion is None:
            raise InputError(
                "field 'torsion.stiffness' is missing: a torsion rig needs its stiffness (N·m/rad)", source
            )
        stiffness = f.torsion.stiffness
        if f.body.inertia <= 0:
            raise InputError(
                f"field 'body.inertia' = {f.body.inertia}: a torsion rig needs the body's inertia about the axis (kg·m², > 0)",
                source,
            )
    floating = None
    if f.test == "floating":
        floating, stiffness = _floating(f, source)
    elif f.floating is not None:
        raise InputError(f"field 'floating' is given for a {f.test} rig: expected it only with test: floating", source)
    pend = f.pendulum if f.test == "pendulum" else None
    tare = f.tare or _Tare()
    rig = Rig(
        test=f.test,
        axis=f.axis,
        gravity=f.gravity,
        density=f.fluid.density,
        kinematic_viscosity=f.fluid.kinematic_viscosity,
        mass=f.body.mass,
        volume=f.body.volume,
        reference_area=f.body.reference_area,
        reference_length=f.body.reference_length,
        inertia=f.body.inertia,
        pendulum_length=pend.length if pend else None,
        stiffness=stiffness,
        rod_mass=pend.rod_mass if pend else 0.0,
        rod_volume=pend.rod_volume if pend else 0.0,
        tare_linear_damping=tare.linear_damping,
        tare_quadratic_damping=tare.quadratic_damping,
        wall_distance=f.wall_distance,
        scale=f.scale,
        source=source,
        floating=floating,
    )
    if rig.test == "pendulum":
        from hydrokit.identify.rig_model import rig_constants

        rig_constants(rig)  # B == W: no restoring force
    return rig


def load_rig(path: str | os.PathLike[str]) -> Rig:
    """Read and validate a rig file."""
    return parse_rig(read_yaml(path), str(path))


#: the rig in the rig-file layout (kept under its old name)
rig_to_dict = rig_document
