"""Rig files (YAML): one rig and the tested body. Format frozen by issue #2 (docs/identify.md).

```yaml
test: pendulum          # spring | pendulum | torsion
axis: surge             # surge | sway | heave | roll | pitch | yaw
gravity: 9.81           # m/s^2 (default 9.81)
fluid: {density: 998.2, kinematic_viscosity: 1.0e-6}   # kg/m^3, m^2/s
body: {mass: 0.146, volume: 1.07597e-4, reference_area: 0.004, reference_length: 0.087, inertia: 0.0}
pendulum: {length: 0.39}     # m          (pendulum only)
spring:   {stiffness: 63.6}  # N/m        (spring only)
torsion:  {stiffness: 0.5}   # N m/rad    (torsion only)
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

from hydrokit.errors import InputError
from hydrokit.identify.types import AXES, Rig, rig_document
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


class _Tare(BaseModel):
    model_config = ConfigDict(extra="forbid")
    linear_damping: float = 0.0
    quadratic_damping: float = 0.0


class RigFile(BaseModel):
    """The rig file schema (see module docstring)."""

    model_config = ConfigDict(extra="forbid")
    test: Literal["spring", "pendulum", "torsion"]
    axis: Literal["surge", "sway", "heave", "roll", "pitch", "yaw"]
    gravity: float = Field(9.81, gt=0, description="m/s^2")
    fluid: _Fluid
    body: _Body
    pendulum: _Pendulum | None = None
    spring: _Stiffness | None = None
    torsion: _Stiffness | None = None
    tare: _Tare | None = None
    wall_distance: float | None = Field(None, gt=0, description="m")
    scale: float | None = Field(None, gt=0, description="model/full-size length ratio")
    sensor: dict[str, Any] | None = None
    name: str | None = None
    description: str | None = None


def parse_rig(data: dict[str, Any], source: str) -> Rig:
    """Validate a rig mapping and return the :class:`Rig` (errors name the file and field)."""
    if "test" in data and data["test"] not in ("spring", "pendulum", "torsion"):
        raise InputError(f"field 'test' = {data['test']!r}: expected spring, pendulum or torsion", source)
    if "axis" in data and data["axis"] not in AXES:
        raise InputError(f"field 'axis' = {data['axis']!r}: expected one of {', '.join(AXES)}", source)
    try:
        f = RigFile.model_validate(data)
    except ValidationError as exc:
        raise pydantic_error_line(exc, source) from None
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
