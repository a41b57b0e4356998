"""What a vehicle log holds, in SI on the log's own clock: the readers' common result.

:func:`hydrokit.io.ardupilot.read_log_channels` and :func:`hydrokit.io.rosbag.read_bag_channels`
return a :class:`LogChannels`; :mod:`hydrokit.io.runfile` turns it into a run file. It lives in
its own module so the readers and the run-file writer do not import each other.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

__all__ = ["LogChannels", "Stream", "clean_stream"]


@dataclass(frozen=True)
class Stream:
    """One channel's samples: ``t`` in s (the log's clock, strictly increasing), ``y`` in SI."""

    t: np.ndarray
    y: np.ndarray
    source: str

    @property
    def rate(self) -> float:
        """Median sample rate, Hz (0 for a single sample)."""
        return float(1.0 / np.median(np.diff(self.t))) if self.t.size > 1 else 0.0


@dataclass(frozen=True)
class LogChannels:
    """What a vehicle log holds, in SI on the log's own clock.

    motion : channel (``phi``, ``p``, ``u``, ``z`` …) → samples (rad, rad/s, m/s, m)
    pressure : absolute pressure of the depth sensor, Pa, or None
    outputs : output number (1-based), or a thruster's name (one topic per thruster) → samples:
        PWM in µs (``output_unit`` ``"pwm"``) or a command already in the thruster's unit
        (``"command"``, e.g. a ROS command array)
    params : autopilot parameters found in the log (``MOT_1_DIRECTION``, ``SERVO1_FUNCTION`` …)
    notes, warnings : what was chosen and what looks odd, for the summary
    corrupt : corrupt packets skipped by the reader (−1: not counted)
    """

    source: str
    motion: Mapping[str, Stream]
    pressure: Stream | None
    outputs: Mapping[int | str, Stream]
    output_unit: Literal["pwm", "command"] = "pwm"
    params: Mapping[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    corrupt: int = -1
    output_source: str = ""


def clean_stream(t: Sequence[float] | np.ndarray, y: Sequence[float] | np.ndarray, source: str) -> Stream:
    """Samples sorted by time, repeated stamps dropped (the first kept), non-finite values dropped."""
    ta = np.asarray(t, float)
    ya = np.asarray(y, float)
    ok = np.isfinite(ta) & np.isfinite(ya)
    ta, ya = ta[ok], ya[ok]
    order = np.argsort(ta, kind="stable")
    ta, ya = ta[order], ya[order]
    keep = np.concatenate([[True], np.diff(ta) > 0]) if ta.size else np.zeros(0, bool)
    return Stream(ta[keep], ya[keep], source)
