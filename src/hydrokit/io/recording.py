"""A recording read from any source (``hydrokit ingest``): one signal against time, in SI, and
the unit options shared by the readers."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import Rig

TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
#: signal unit → (SI factor, kind)
SIGNAL_UNITS = {"rad": (1.0, "angle"), "deg": (math.pi / 180.0, "angle"), "m": (1.0, "length"), "mm": (1e-3, "length")}


@dataclass(frozen=True)
class Recording:
    """One signal against time as read from a source.

    t : s, strictly increasing, in the source's own time base (not re-based)
    y : m (spring) or rad (pendulum, torsion)
    details : source-specific facts for ``ingest.json`` (video: pivot, tracking quality), or None
    image : a frame of the source for plots (video), or None
    """

    t: np.ndarray
    y: np.ndarray
    source: str
    signal: str
    notes: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    details: dict[str, Any] | None = None
    image: np.ndarray | None = None


def signal_scale(unit: str, rig: Rig) -> tuple[float, str]:
    """SI factor and unit name of ``--signal-unit`` (rad, deg, m, mm or counts:SCALE, SCALE in
    m or rad per count), checked against the rig (a length for the spring, an angle otherwise)."""
    want = "length" if rig.test == "spring" else "angle"
    if unit.startswith("counts:"):
        try:
            scale = float(unit.split(":", 1)[1])
        except ValueError:
            scale = math.nan
        if not (math.isfinite(scale) and scale > 0):
            raise InputError(f"--signal-unit {unit!r}: expected counts:SCALE with SCALE > 0 (m or rad per count)")
        return scale, unit
    if unit not in SIGNAL_UNITS:
        raise InputError(f"--signal-unit {unit!r}: expected rad, deg, m, mm or counts:SCALE")
    factor, kind = SIGNAL_UNITS[unit]
    if kind != want:
        raise InputError(f"--signal-unit {unit}: a {rig.test} rig records a{'' if want == 'length' else 'n'} {want}")
    return factor, unit


def check_times(t: np.ndarray, source: str, what: str = "time") -> None:
    """Finite, strictly increasing stamps, or one line naming the first bad one."""
    if t.size < 2:
        raise InputError(f"only {t.size} sample(s) of {what}; expected a recording", source)
    if not np.all(np.isfinite(t)):
        raise InputError(f"{what}: non-finite stamp at sample {int(np.nonzero(~np.isfinite(t))[0][0]) + 1}", source)
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.nonzero(dt <= 0)[0][0])
        raise InputError(
            f"{what}: non-monotonic stamps, {t[k]:.9g} then {t[k + 1]:.9g} s at samples {k + 1} and {k + 2}; "
            "expected strictly increasing times",
            source,
        )
