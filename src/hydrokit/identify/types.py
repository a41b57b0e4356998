"""Data types shared by the identification engine, the file readers and the reports.

These are the contract between ``identify/`` (estimators), ``io/`` (rig and launch files) and
``report``/``cli``. Units: SI. For the pendulum the generalised coordinate is the angle θ
(rad) and the hydrodynamic force acts along the path, ẋ = r θ̇; coefficients are reported in
translational units (kg, N·s/m, N·s²/m²). For the torsion rig they are rotational
(kg·m², N·m·s/rad, N·m·s²/rad²). For the spring rig the coordinate is the position (m).
The floating-body rig (issue #16) is rotational in roll and pitch (rad) and translational in
heave (m), with a restoring that may be nonlinear (polynomial or a righting-arm curve).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

from hydrokit._result import jsonable

TestKind = Literal["spring", "pendulum", "torsion", "floating"]
TESTS = ("spring", "pendulum", "torsion", "floating")
#: axes a floating body can be released in
FLOATING_AXES = ("heave", "roll", "pitch")
AXES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
METHODS = ("output-error", "equation-error", "morison", "log-decrement")


@dataclass(frozen=True)
class Rig:
    """One rig and the tested body (the parsed rig file; see docs/identify.md).

    Parameters
    ----------
    test : {"spring", "pendulum", "torsion", "floating"}
    axis : str — one of surge, sway, heave, roll, pitch, yaw
    gravity : float — m/s²
    density : float — fluid density ρ, kg/m³
    kinematic_viscosity : float — ν, m²/s
    mass : float — dry mass of the tested body, kg
    volume : float — displaced volume V, m³
    reference_area : float — projected area normal to the motion, m² (for C_D)
    reference_length : float — characteristic size, m (for Re and KC)
    inertia : float — body inertia, kg·m²: about the rotation axis (torsion, floating roll or
        pitch: the dry inertia) or about the body's own centre (physical pendulum; 0 = point
        body, SPEC P1)
    pendulum_length : float or None — pivot to body centre, m (pendulum only)
    stiffness : float or None — spring N/m (spring) or N·m/rad (torsion); for the floating rig
        the linear restoring C1 (N/m heave, N·m/rad roll/pitch), worked out by the parser
    rod_mass : float — pendulum rod mass, kg (physical pendulum; 0 = massless rod)
    rod_volume : float — pendulum rod displaced volume, m³ (0 = no rod buoyancy)
    tare_linear_damping, tare_quadratic_damping : float — rig (pivot/bearing/air) damping
        measured in a tare test, in the same units as the reported K_L, K_Q; subtracted
    wall_distance : float or None — gap from the body to the nearest wall, m
    scale : float or None — model/full-scale length ratio (e.g. 0.3 for a 30 % model)
    floating : tuple or None — the floating rig's restoring as given in the rig file (issue #16):
        ``("gm", GM)`` (m), ``("waterplane_area", A_wp)`` (m²), ``("restoring", (C1, C3, C5))``
        (SI polynomial) or ``("gz", ((deg, m), ...))`` (righting-arm curve)
    source : str — where the rig came from (file name), for messages
    """

    test: TestKind
    axis: str
    gravity: float
    density: float
    kinematic_viscosity: float
    mass: float
    volume: float
    reference_area: float
    reference_length: float
    inertia: float = 0.0
    pendulum_length: float | None = None
    stiffness: float | None = None
    rod_mass: float = 0.0
    rod_volume: float = 0.0
    tare_linear_damping: float = 0.0
    tare_quadratic_damping: float = 0.0
    wall_distance: float | None = None
    scale: float | None = None
    source: str = ""
    floating: tuple[str, Any] | None = None

    @property
    def rotational(self) -> bool:
        """True for the torsion rig and a floating body in roll or pitch (coefficients about an axis)."""
        return self.test == "torsion" or (self.test == "floating" and self.axis != "heave")

    @property
    def translational_signal(self) -> bool:
        """True when the recorded coordinate is a position in m (spring, floating heave), not an angle."""
        return self.test == "spring" or (self.test == "floating" and self.axis == "heave")

    @property
    def buoyancy(self) -> float:
        """ρ g V of the body, N."""
        return self.density * self.gravity * self.volume

    @property
    def weight(self) -> float:
        """m g of the body, N."""
        return self.mass * self.gravity


@dataclass(frozen=True)
class Launch:
    """One recorded (or simulated) launch after reading and trimming.

    t : s, strictly increasing; y : m (spring) or rad (pendulum, torsion).
    notes : what the reader did (trimmed samples, release time), human-readable.
    info : what trimming found (release time, detrend, amplitude window), for the JSON.
    """

    t: Any
    y: Any
    file: str = ""
    notes: tuple[str, ...] = ()
    #: what trimming found, for the JSON (``release_time`` s in the file's time base, ``detrend``,
    #: ``amplitude_window``); empty for an untrimmed launch
    info: dict[str, Any] = field(default_factory=dict, compare=False)


@dataclass
class LaunchResult:
    """Identified coefficients of one launch (one object of the JSON ``launches`` list).

    Units: added_mass kg (kg·m² torsion); linear_damping N·s/m (N·m·s/rad);
    quadratic_damping N·s²/m² (N·m·s²/rad²); natural_frequency rad/s; amplitude m or rad
    (initial displacement); rms_residual in the signal's unit (m or rad).
    """

    file: str
    method: str
    added_mass: float
    added_mass_coefficient: float | None
    linear_damping: float
    quadratic_damping: float
    drag_coefficient: float | None
    natural_frequency: float
    damping_ratio: float
    reynolds_max: float
    kc: float
    rms_residual: float
    std_error: dict[str, float | None]
    warnings: list[str] = field(default_factory=list)
    amplitude: float = math.nan
    gap_ratio: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (NaN and inf become None)."""
        return jsonable(asdict(self))


def rig_document(rig: Rig) -> dict[str, Any]:
    """The rig in the rig-file layout (SI), for JSON results and virtual-rig output."""
    out: dict[str, Any] = {
        "test": rig.test,
        "axis": rig.axis,
        "gravity": rig.gravity,
        "fluid": {"density": rig.density, "kinematic_viscosity": rig.kinematic_viscosity},
        "body": {
            "mass": rig.mass,
            "volume": rig.volume,
            "reference_area": rig.reference_area,
            "reference_length": rig.reference_length,
            "inertia": rig.inertia,
        },
    }
    if rig.test == "pendulum":
        out["pendulum"] = {"length": rig.pendulum_length, "rod_mass": rig.rod_mass, "rod_volume": rig.rod_volume}
    elif rig.test == "spring":
        out["spring"] = {"stiffness": rig.stiffness}
    elif rig.test == "floating":
        # a rig built in Python may give only its linear restoring C1 (as ``stiffness``)
        spec: tuple[str, Any] = rig.floating if rig.floating is not None else ("restoring", (rig.stiffness,))
        kind, value = spec
        if kind == "restoring":
            value = list(value)
        elif kind == "gz":
            value = [list(row) for row in value]
        out["floating"] = {kind: value}
    else:
        out["torsion"] = {"stiffness": rig.stiffness}
    if rig.tare_linear_damping or rig.tare_quadratic_damping:
        out["tare"] = {"linear_damping": rig.tare_linear_damping, "quadratic_damping": rig.tare_quadratic_damping}
    if rig.wall_distance is not None:
        out["wall_distance"] = rig.wall_distance
    if rig.scale is not None:
        out["scale"] = rig.scale
    return out
