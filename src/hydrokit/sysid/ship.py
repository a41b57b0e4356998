"""Virtual free-running runs of a planar rudder-steered ship (surge, sway, yaw) for system
identification (issue #48): the propeller turns at a constant speed, the rudder is held at
random angles for random times (a zigzag-like schedule that does not look at the heading, so a
course-unstable hull keeps turning until the rudder reverses), the truth is integrated on the
compiled RK4 at a step finer than any fit's, and position, heading, velocities and yaw rate
are logged with Gaussian noise.

The propeller thrust is the curve at the *true* advance speed: the force table is built
:data:`PASSES` times, each with the previous pass's true velocities as if measured
(:func:`hydrokit.sysid.model.force_table` takes the advance speed from the run's
velocity channels).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from hydrokit.errors import InputError
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.model import CHANNELS, force_table, stack_packs

#: fixed-point passes of the thrust at the true advance speed (each changes the speed about
#: 15 times less than the one before: < 1e-6 m/s in the last)
PASSES = 6
#: sensor σ (SI) of the logged channels: GNSS position m, compass rad, velocities m/s, gyro rad/s
SHIP_NOISE: dict[str, float] = {"x": 0.02, "y": 0.02, "psi": 0.005, "u": 0.005, "v": 0.005, "r": 0.002}


@dataclass(frozen=True)
class ShipRun:
    """One generated run (satisfies :class:`hydrokit.sysid.model.RunData`).

    name : str; time : (n,) row times, s; channels : channel → (t, y) samples (SI);
    commands : thruster → (n,) propeller speed, rev/s; deflections : surface → (n,) rad held
    per row; truth : (n, 12) true states on the rows (SI)
    """

    name: str
    time: np.ndarray
    channels: Mapping[str, tuple[np.ndarray, np.ndarray]]
    commands: Mapping[str, np.ndarray]
    deflections: Mapping[str, np.ndarray]
    truth: np.ndarray
    thrusts: Mapping[str, np.ndarray] = field(default_factory=dict)


def ship_runs(
    truth: Vehicle,
    n_runs: int,
    duration: float,
    seed: int,
    speed: float = 20.0,
    rudder: float = math.radians(25.0),
    hold: tuple[float, float] = (4.0, 14.0),
    u0: float = 0.37,
    rate: float = 10.0,
    noise: float = 1.0,
    dt: float = 0.005,
) -> list[ShipRun]:
    """``n_runs`` runs of ``duration`` s of the planar ship ``truth`` (module docstring).

    Parameters
    ----------
    truth : Vehicle with one propeller and one control surface — the generating model
    n_runs : int — count; duration : float — s; seed : int — one generator for everything
    speed : float — propeller speed, rev/s (the command of the first thruster)
    rudder : float — largest |deflection|, rad (each hold draws uniformly in ±rudder, sign alternating)
    hold : (float, float) — shortest and longest time a deflection is held, s
    u0 : float — initial surge speed, m/s
    rate : float — sample rate of every channel, Hz
    noise : float — multiplies :data:`SHIP_NOISE` (0: noise-free logs)
    dt : float — integration step of the truth, s

    Raises
    ------
    InputError
        A vehicle without a thruster or a control surface, or a truth that diverged.
    """
    from hydrokit.sysid.data import _integrate

    th = truth.thrusters
    if th is None or not truth.surfaces.names:
        raise InputError(f"vehicle {truth.name!r}: expected a propeller and a rudder for ship runs")
    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / rate), 9)
    n_steps = int(round(duration / dt))
    rows = np.round(time / dt).astype(int)
    out = []
    for k in range(n_runs):
        delta = np.empty(time.size)
        t, sign = 0.0, float(rng.choice([-1.0, 1.0]))
        while t < duration + 1e-9:
            length = rng.uniform(*hold)
            delta[(time >= t - 1e-9) & (time < t + length - 1e-9)] = sign * rng.uniform(0.3, 1.0) * rudder
            t += length
            sign = -sign
        commands = {n: np.full(time.size, speed) for n in th.names}
        deflections = {truth.surfaces.names[0]: delta, **{s: np.zeros(time.size) for s in truth.surfaces.names[1:]}}
        x0 = np.zeros(12)
        x0[5] = rng.uniform(-math.pi, math.pi)
        x0[6] = u0
        chans: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        states = np.zeros((time.size, 12))
        for _ in range(PASSES):  # each pass: the thrust at the previous pass's true advance speed
            probe = ShipRun(f"run{k + 1}", time, chans, commands, deflections, states)
            table = force_table(probe, th, dt, truth.surfaces.names)
            try:
                states = _integrate(packs, x0, table, dt, n_steps)[rows]
            except InputError as exc:
                raise InputError(f"ship run {k + 1}: {exc}") from None
            chans = {c: (time, states[:, CHANNELS.index(c)]) for c in ("u", "v", "r")}
        logged = {
            c: (time, states[:, CHANNELS.index(c)] + noise * s * rng.standard_normal(time.size))
            for c, s in SHIP_NOISE.items()
        }
        out.append(ShipRun(f"run{k + 1}", time, logged, commands, deflections, states))
    return out


__all__ = ["SHIP_NOISE", "ShipRun", "ship_runs"]
