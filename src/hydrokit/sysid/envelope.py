"""What the fitted runs covered (issue #56 item 7): the :class:`~hydrokit.model.envelope.Envelope`
that ``hydrokit sysid`` writes into the identified vehicle.

A fit that misses its own runs' speed at their propeller revolutions is a model that does not hold
there; to say so, the vehicle must carry what its runs did. From the fitted runs (their logged
commands, deflections, ``u``, ``v``, ``w`` and ``r``):

- **speed per command.** Each run is cut into *holds*: stretches where every thruster's command
  stays within :func:`~hydrokit.model.envelope.command_tolerance` (2 %) of the stretch's first.
  The first half of a hold is left for the rotor and the vehicle to settle; its second half is
  used when it is steady and nearly straight (:func:`~hydrokit.model.envelope.straight_and_steady`:
  it runs at least 2 L, the speed's least-squares line changes it by at most 2 % over it, and at
  least half its samples turn at |r| L/U ≤ 0.1), and of it the nearly straight samples. Holds of all
  runs within 2 % of one another are one level: its command is their samples' mean, its speed the
  mean over the runs of each run's mean speed, its scatter the standard deviation of those run
  means (of the samples, with one run).
- **speed while manoeuvring per command.** The same holds' second halves, turning or not, when
  steady within :data:`~hydrokit.model.envelope.MANOEUVRING_CHANGE` (20 %: a zigzag's speed
  swings with each turn, and a model ship's settles slowly) over at least 2 L, grouped the same way but run by run (each
  run's own turning bounds the straight speed), each level with its turning r' = rms(r) L / mean
  speed (–): runs that never go straight (a pond's random-rudder and zigzag
  trials) still bound the straight speed at their commands from both sides
  (:func:`hydrokit.model.envelope.largest_speed_loss`).
- **ranges.** Each thruster's least and largest command; the least and largest speed through the
  water |(u, v, w)| (the channels logged); each surface's largest |δ|; the largest |r|; the
  largest drift |atan2(−v, u)| where u > 0.1 × the largest speed.

The speed is the logged body velocity (a DVL's or the log's own), so on runs in a current it is
the speed over the ground.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from hydrokit.model.envelope import (
    DRIFT_SPEED_FRACTION,
    MANOEUVRING_CHANGE,
    Envelope,
    SpeedLevel,
    command_tolerance,
    straight_and_steady,
    vehicle_length,
)

#: a hold's part: its run (index), the command vector per sample, the speeds (m/s) and, for the
#: manoeuvring levels, the yaw rates (rad/s)
Hold = tuple[int, np.ndarray, np.ndarray, np.ndarray | None]
#: the fewest speed samples in the part of a hold used
MIN_SAMPLES = 10


def _at(t: np.ndarray, channel: Any) -> np.ndarray | None:
    """A channel (t, y) at the times ``t`` (linear; None when the run has no such channel)."""
    if channel is None:
        return None
    tc, y = channel
    return np.interp(t, np.asarray(tc, float), np.asarray(y, float)) if len(tc) else None


def _holds(cmds: np.ndarray, scale: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) sample ranges where every column of ``cmds`` stays within tolerance of the
    range's first row."""
    out, start = [], 0
    for k in range(1, cmds.shape[0] + 1):
        if k == cmds.shape[0] or any(
            abs(cmds[k, j] - cmds[start, j]) > command_tolerance(cmds[start, j], scale[j]) for j in range(cmds.shape[1])
        ):
            out.append((start, k))
            start = k
    return out


def run_envelope(runs: Sequence[Any], vehicle: Any) -> Envelope:
    """The envelope of the fitted ``runs`` (module docstring).

    Parameters
    ----------
    runs : runs with ``name``, ``time`` (s), ``channels`` (name → (t, y), SI), ``commands``
        (thruster → per row, its unit) and ``deflections`` (surface → per row, rad)
    vehicle : the base vehicle — its ``reference_length`` (or thruster and surface positions) sets
        the L of "nearly straight" (:func:`~hydrokit.model.envelope.vehicle_length`)

    Returns
    -------
    Envelope
    """
    length = vehicle_length(vehicle)
    ts = getattr(vehicle, "thrusters", None)
    listed = list(ts.names) if ts is not None else list(vehicle.thruster_names)
    names = [n for n in listed if all(n in r.commands for r in runs)]  # a measured thrust has no command
    scale = np.array([max(float(np.max(np.abs(r.commands[n]))) for r in runs) for n in names])
    command_range = tuple(
        (n, min(float(np.min(r.commands[n])) for r in runs), max(float(np.max(r.commands[n])) for r in runs))
        for n in names
    )
    defl = [getattr(r, "deflections", None) or {} for r in runs]  # runs without surfaces need not have it
    surfaces = [s for s in vehicle.surfaces.names if all(s in d for d in defl)]
    deflection = tuple((s, max(float(np.max(np.abs(d[s]))) for d in defl)) for s in surfaces)
    speeds, rates, drifts = [], [], []
    # run (index), command vector per sample, speeds, and manoeuvring the yaw rates (rad/s)
    holds: list[Hold] = []
    turning: list[Hold] = []
    for k_run, run in enumerate(runs):
        r_ch = run.channels.get("r")
        if r_ch is not None and len(r_ch[1]):
            rates.append(float(np.max(np.abs(r_ch[1]))))
        if "u" not in run.channels or not len(run.channels["u"][0]):
            continue
        t, u = (np.asarray(a, float) for a in run.channels["u"])
        v, w = _at(t, run.channels.get("v")), _at(t, run.channels.get("w"))
        U = np.sqrt(u**2 + (0.0 if v is None else v**2) + (0.0 if w is None else w**2))
        speeds.append(U)
        if v is not None:
            drifts.append((u, v))
        r = _at(t, r_ch)
        row = np.clip(np.searchsorted(np.asarray(run.time, float), t, side="right") - 1, 0, len(run.time) - 1)
        cmds = np.column_stack([np.asarray(run.commands[n], float)[row] for n in names]) if names else None
        if cmds is None:
            continue
        for a, b in _holds(cmds, scale):
            half = a + (b - a) // 2
            if b - half < MIN_SAMPLES:
                continue
            part = slice(half, b)
            steady, straight = straight_and_steady(t[part], U[part], None if r is None else r[part], length)
            if steady and int(np.sum(straight)) >= MIN_SAMPLES:
                holds.append((k_run, cmds[a:b][straight.nonzero()[0] + (half - a)], U[half:b][straight], None))
            rp = np.zeros(b - half) if r is None else r[part]
            if straight_and_steady(t[part], U[part], rp, length, MANOEUVRING_CHANGE, 0.0)[0]:
                turning.append((k_run, cmds[half:b], U[half:b], rp))
    top = max((float(np.max(U)) for U in speeds), default=None)
    drift = None
    if drifts and top:
        betas = [np.abs(np.arctan2(-v, u))[u > DRIFT_SPEED_FRACTION * top] for u, v in drifts]
        drift = max((float(np.max(b)) for b in betas if b.size), default=None)
    return Envelope(
        speed_per_command=_levels(holds, names, scale),
        # run by run: each run's own turning bounds the straight speed
        speed_manoeuvring=tuple(
            lv for k in range(len(runs)) for lv in _levels([h for h in turning if h[0] == k], names, scale, length)
        ),
        command_range=command_range,
        speed=None if not speeds else (min(float(np.min(U)) for U in speeds), float(top or 0.0)),
        deflection=deflection,
        yaw_rate=max(rates) if rates else None,
        drift=drift,
        length=length,
        runs=tuple(str(r.name) for r in runs),
    )


def _levels(
    holds: list[Hold], names: list[str], scale: np.ndarray, length: float | None = None
) -> tuple[SpeedLevel, ...]:
    """The holds of every run grouped into levels (module docstring), by command; for holds with
    their yaw rates, each level's turning r' = rms(r) L / mean speed (``length`` L, m)."""
    groups: list[list[Hold]] = []
    for hold in sorted(holds, key=lambda h: tuple(h[1][0])):
        first = hold[1][0]
        for g in groups:
            ref = g[0][1][0]
            if all(abs(first[j] - ref[j]) <= command_tolerance(ref[j], scale[j]) for j in range(len(names))):
                g.append(hold)
                break
        else:
            groups.append([hold])
    out = []
    for g in groups:
        cmds = np.concatenate([h[1] for h in g])
        per_run: dict[int, list[np.ndarray]] = {}
        for k_run, _, U, _ in g:
            per_run.setdefault(k_run, []).append(U)
        means = np.array([float(np.mean(np.concatenate(us))) for us in per_run.values()])
        samples = np.concatenate([h[2] for h in g])
        scatter = float(np.std(means, ddof=1)) if means.size > 1 else float(np.std(samples, ddof=1))
        turning = None
        yaw = [h[3] for h in g if h[3] is not None]
        if yaw:
            rr = np.concatenate(yaw)
            turning = float(np.sqrt(np.mean(rr**2)) * (length or 0.0) / max(float(np.mean(samples)), 1e-9))
        out.append(
            SpeedLevel(
                command=tuple((n, float(np.mean(cmds[:, j]))) for j, n in enumerate(names)),
                speed=float(np.mean(means)),
                scatter=scatter if math.isfinite(scatter) else 0.0,
                runs=int(means.size),
                samples=int(samples.size),
                turning=turning,
            )
        )
    return tuple(sorted(out, key=lambda lv: tuple(c for _, c in lv.command)))


__all__ = ["MIN_SAMPLES", "run_envelope"]
