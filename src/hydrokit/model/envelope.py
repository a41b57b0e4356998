"""What an identification's runs covered (issue #56 item 7): the ``envelope:`` block of a vehicle
file, and a prediction compared with it.

``hydrokit sysid`` (and ``sysid compare``, ``hydrokit run``'s sysid step) measure the fitted runs
(:func:`hydrokit.sysid.envelope.run_envelope`) and write the block into the vehicle it writes; a
vehicle file holds it as

```yaml
envelope:
  runs: [pond1, pond2]           # the fitted runs it was measured on
  length: 3.0                    # m, L of "nearly straight" (|r| L/U <= 0.1)
  command_range: {prop: [0.0, 10.0]}     # per thruster: the runs' least and largest command, its unit
  speed_per_command:             # the runs' steady, nearly straight speed at each held set of commands
    - {command: {prop: 8.0}, speed: 0.36, scatter: 0.04, runs: 3, samples: 1200}   # its unit; m/s, m/s
  speed_manoeuvring:             # … and their steady speed there while manoeuvring (turning or not)
    - {command: {prop: 10.0}, speed: 0.29, scatter: 0.01, turning: 0.21, runs: 1, samples: 4200}   # turning: r', –
  speed: [0.0, 0.55]             # m/s, the runs' least and largest speed through the water
  deflection_deg: {rudder: 35.0}         # largest |δ| per surface, deg
  yaw_rate: 0.12                 # largest |r|, rad/s
  drift_deg: 8.0                 # largest |β| = |atan2(−v, u)| where u > 0.1 × the largest speed, deg
```

A prediction (``hydrokit manoeuvre``, ``hydrokit simulate``) is compared with it by :func:`compare`:

- **the model does not hold** when its steady straight speed at a held set of commands the runs
  held too differs from the runs' speed there by more than
  max(:data:`SCATTER_K` × scatter, :data:`SPEED_FRACTION` × speed): the fit misses its own runs'
  speed, so what it predicts elsewhere is not a prediction. Runs that never go straight (a pond's
  random-rudder and zigzag trials) bound the straight speed from both sides by their steady speed
  while manoeuvring at those commands (``speed_manoeuvring``): turning costs speed, so the
  straight speed is not below it, and it costs at most :func:`largest_speed_loss` of the
  straight speed at the runs' turning r' = rms(r) L / mean U, so the straight speed is not above
  speed / (1 − that loss) — each beyond the same tolerance;
- **an extrapolation** when a command lies outside the runs' range (by more than
  :data:`COMMAND_TOLERANCE` of the thruster's largest command), or a deflection, yaw rate, drift
  angle or speed goes past the envelope's largest by more than :data:`MARGIN` of it.

A vehicle without the block (hand-written, or the block deleted) is not compared.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

#: commands within this fraction of each other are one held level …
COMMAND_TOLERANCE = 0.02
#: … the fraction taken of at least this share of the thruster's largest |command| (a level at 0)
COMMAND_FLOOR = 0.05
#: nearly straight: |r| L / U at most this (a turn of 20 L diameter or wider)
STRAIGHT_RATE = 0.1
#: steady: a stretch at least this many L long whose speed changes by at most 2 % over it (a speed
#: that has not stopped changing over two lengths run is not the steady speed)
STEADY_LENGTHS = 2.0
#: … and whose speed's least-squares line changes it by at most this fraction of its mean
STEADY_CHANGE = 0.02
#: … and, manoeuvring, by at most this fraction (a zigzag's speed swings with each turn, and a
#: model ship's speed settles slowly): the end of such a stretch is then within SPEED_FRACTION of
#: its mean, the tolerance of the comparison
MANOEUVRING_CHANGE = 0.20
#: a prediction's speed holds when within max(SCATTER_K × the runs' scatter, SPEED_FRACTION × their speed)
SCATTER_K = 3.0
SPEED_FRACTION = 0.10
#: a deflection, yaw rate, drift or speed beyond the envelope's by more than this fraction is an extrapolation
MARGIN = 0.05
#: the drift angle is measured where u exceeds this fraction of the largest speed (β of a vehicle at rest is noise)
DRIFT_SPEED_FRACTION = 0.1
#: what every envelope line starts with (the commands print it as is, the reports find it by it)
MARK = "envelope: "
#: the words of a model that misses its own runs' speed
NOT_HOLD = "the model does not hold at its own runs' speed"
#: a ship turning at r' = L/R keeps at least 1 / (1 + LOSS_PER_TURNING r') of its straight speed
LOSS_PER_TURNING = 4.0
#: the words of a prediction outside the envelope
EXTRAPOLATES = "the prediction extrapolates beyond the identification"


@dataclass(frozen=True)
class SpeedLevel:
    """The runs' speed at one held set of commands.

    Attributes
    ----------
    command : tuple of (str, float) — each thruster's held command, its unit (rev/s, the table's, N)
    speed : float — the mean over the runs of each run's mean steady, nearly straight speed, m/s
    scatter : float — the standard deviation of those run means (of the samples with one run), m/s
    runs : int — runs that held it steadily; samples : int — speed samples used
    turning : float or None — the runs' turning there, r' = rms(r) L / mean speed (–); None for a
        straight level (``speed_per_command``)
    """

    command: tuple[tuple[str, float], ...]
    speed: float
    scatter: float
    runs: int
    samples: int
    turning: float | None = None

    @property
    def commands(self) -> dict[str, float]:
        return dict(self.command)


@dataclass(frozen=True)
class Envelope:
    """The ``envelope:`` block of a vehicle file (module docstring); SI, angles in rad.

    Attributes
    ----------
    speed_per_command : tuple of SpeedLevel — steady and nearly straight
    speed_manoeuvring : tuple of SpeedLevel — steady, turning or not (``turning`` set)
    command_range : tuple of (str, float, float) — per thruster its least and largest command
    speed : (float, float) or None — least and largest speed, m/s
    deflection : tuple of (str, float) — largest |δ| per surface, rad
    yaw_rate : float or None — largest |r|, rad/s; drift : float or None — largest |β|, rad
    length : float or None — L of "nearly straight", m
    runs : tuple of str — the fitted runs measured
    """

    speed_per_command: tuple[SpeedLevel, ...] = ()
    command_range: tuple[tuple[str, float, float], ...] = ()
    speed: tuple[float, float] | None = None
    deflection: tuple[tuple[str, float], ...] = ()
    yaw_rate: float | None = None
    drift: float | None = None
    length: float | None = None
    runs: tuple[str, ...] = ()
    speed_manoeuvring: tuple[SpeedLevel, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The block as the vehicle file and sysid.json hold it (``*_deg`` in degrees, else SI)."""
        doc: dict[str, Any] = {"runs": list(self.runs)}
        if self.length is not None:
            doc["length"] = _g(self.length)
        doc["command_range"] = {n: [_g(lo), _g(hi)] for n, lo, hi in self.command_range}
        doc["speed_per_command"] = [_level_dict(lv) for lv in self.speed_per_command]
        doc["speed_manoeuvring"] = [_level_dict(lv) for lv in self.speed_manoeuvring]
        if self.speed is not None:
            doc["speed"] = [_g(self.speed[0]), _g(self.speed[1])]
        doc["deflection_deg"] = {n: _g(math.degrees(d)) for n, d in self.deflection}
        if self.yaw_rate is not None:
            doc["yaw_rate"] = _g(self.yaw_rate)
        if self.drift is not None:
            doc["drift_deg"] = _g(math.degrees(self.drift))
        return doc


def _level_dict(lv: SpeedLevel) -> dict[str, Any]:
    doc: dict[str, Any] = {
        "command": {n: _g(c) for n, c in lv.command},
        "speed": _g(lv.speed),
        "scatter": _g(lv.scatter),
    }
    if lv.turning is not None:
        doc["turning"] = _g(lv.turning)
    return {**doc, "runs": lv.runs, "samples": lv.samples}


def largest_speed_loss(turning: float) -> float:
    """The largest share of its straight speed a ship loses turning at r' = ``turning`` (–):
    1 − 1 / (1 + k r'), k = :data:`LOSS_PER_TURNING`.

    On the steady turning circles (5–35° rudder, constant propeller) of the models hydrokit
    carries, k = (U₀/U − 1) / r' (r' = L/R) is 0.2–0.5 for the REMUS 100, 0.6–1.3 for the Esso
    Osaka MMG model, 0.9–1.4 for the generated full-bodied tanker and 1.7–2.5 for the Mariner (the
    largest: a 49 % loss at r' = 0.39); 4 is 1.6 times that. A zigzag or a random rudder at the
    same rms r' loses less than the steady turn (its speed recovers between turns), so the bound
    holds for them too."""
    r = max(0.0, float(turning))
    return LOSS_PER_TURNING * r / (1.0 + LOSS_PER_TURNING * r)


def _g(x: float) -> float:
    """``x`` to 6 significant digits (a file a person reads; the speeds' noise is far larger)."""
    return float(f"{float(x):.6g}")


def command_tolerance(level: float, scale: float) -> float:
    """How far a command may be from ``level`` and still be at it (its unit): :data:`COMMAND_TOLERANCE`
    of |level|, or of :data:`COMMAND_FLOOR` × ``scale`` (the thruster's largest |command|) if larger."""
    return COMMAND_TOLERANCE * max(abs(level), COMMAND_FLOOR * abs(scale))


@dataclass(frozen=True)
class Finding:
    """One way a prediction leaves the envelope.

    kind : str — ``does not hold`` or ``extrapolation``; quantity : str — what (``speed``, ``command
    prop``, ``deflection rudder``, ``yaw rate``, ``drift``); value : float — the prediction's (its
    unit); limit : float — the envelope's (the runs' speed, or the largest they reached); unit : str;
    text : str — the sentence (without :data:`MARK`)
    """

    kind: str
    quantity: str
    value: float
    limit: float
    unit: str
    text: str

    def to_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in ("kind", "quantity", "value", "limit", "unit", "text")}


def _scale(envelope: Envelope, name: str) -> float:
    return max((max(abs(lo), abs(hi)) for n, lo, hi in envelope.command_range if n == name), default=0.0)


def matching_level(
    envelope: Envelope, commands: Mapping[str, float], levels: Sequence[SpeedLevel] | None = None
) -> SpeedLevel | None:
    """The level of ``levels`` (default: the straight ones) whose every command ``commands``
    holds (thrusters not named at 0), or None."""
    for lv in envelope.speed_per_command if levels is None else levels:
        names = set(lv.commands) | set(commands)
        if all(
            abs(float(commands.get(n, 0.0)) - lv.commands.get(n, 0.0))
            <= command_tolerance(lv.commands.get(n, 0.0), _scale(envelope, n))
            for n in names
        ):
            return lv
    return None


def _command_text(commands: Mapping[str, float], units: Mapping[str, str]) -> str:
    return ", ".join(f"{n}={c:.4g}" + (f" {units[n]}" if units.get(n) else "") for n, c in commands.items())


def compare(
    envelope: Envelope,
    *,
    commands: Mapping[str, Iterable[float]] | None = None,
    steady: tuple[Mapping[str, float], float] | None = None,
    deflection: Mapping[str, float] | None = None,
    yaw_rate: float | None = None,
    drift: float | None = None,
    speed: float | None = None,
    units: Mapping[str, str] | None = None,
    what: str = "approach",
    rising: bool = False,
) -> tuple[list[Finding], dict[str, Any] | None]:
    """A prediction compared with ``envelope`` (module docstring).

    Parameters
    ----------
    envelope : Envelope
    commands : {thruster: the commands it was given} or None — each in its unit
    steady : (commands, speed) or None — a steady straight speed (m/s) the prediction reached at
        held commands ({thruster: command}, others 0) under no added surge force
    deflection : {surface: largest |δ|, rad} or None
    yaw_rate : float or None — largest |r|, rad/s; drift : float or None — largest |β|, rad
    speed : float or None — largest speed, m/s
    units : {thruster: unit} — for the sentences
    what : str — what ``steady`` is, in the sentence ("approach", "steady speed at the end")
    rising : bool — ``steady`` is a speed still rising (an approach that had not settled): only
        a speed already too high is said

    Returns
    -------
    (findings, speed_check) — the findings (a ``does not hold`` first, then one ``extrapolation``
    per quantity), and the speed comparison made ({command, speed, runs_speed, scatter, runs,
    tolerance, holds, and for a manoeuvring level turning, largest_loss, bound}; None when the
    commands matched no level the runs held)
    """
    units = dict(units or {})
    found: list[Finding] = []
    check = None
    if steady is not None:
        found, check = _speed_checks(envelope, steady, rising, units, what)
    notes: list[Finding] = []
    ranges = {n: (lo, hi) for n, lo, hi in envelope.command_range}
    for name, given in (commands or {}).items():
        values = [float(c) for c in given]
        if name not in ranges or not values:
            continue
        lo, hi = ranges[name]
        tol = COMMAND_TOLERANCE * max(abs(lo), abs(hi))
        worst = max(values, key=lambda c: max(lo - c, c - hi))
        if worst < lo - tol or worst > hi + tol:
            unit = units.get(name, "")
            notes.append(
                Finding(
                    "extrapolation",
                    f"command {name}",
                    worst,
                    lo if worst < lo else hi,
                    unit,
                    f"command {name}={worst:.4g}{' ' + unit if unit else ''} (its runs' commands spanned "
                    f"{lo:.4g} to {hi:.4g})",
                )
            )
    limits = dict(envelope.deflection)
    for name, flown_d in (deflection or {}).items():
        if name in limits and flown_d > limits[name] * (1 + MARGIN) + 1e-12:
            a, b = math.degrees(flown_d), math.degrees(limits[name])
            notes.append(
                Finding(
                    "extrapolation", f"deflection {name}", a, b, "deg", f"{name} {a:.3g}° (its runs: up to {b:.3g}°)"
                )
            )
    for quantity, value, limit, unit, deg in (
        ("yaw rate", yaw_rate, envelope.yaw_rate, "rad/s", False),
        ("drift", drift, envelope.drift, "deg", True),
        ("speed", speed, envelope.speed[1] if envelope.speed else None, "m/s", False),
    ):
        if value is None or limit is None or not value > limit * (1 + MARGIN) + 1e-12:
            continue
        a, b = (math.degrees(value), math.degrees(limit)) if deg else (value, limit)
        shown = "°" if deg else f" {unit}"
        notes.append(
            Finding(
                "extrapolation", quantity, a, b, unit, f"{quantity} {a:.3g}{shown} (its runs: up to {b:.3g}{shown})"
            )
        )
    return found + notes, check


def _speed_checks(
    envelope: Envelope, steady: tuple[Mapping[str, float], float], rising: bool, units: Mapping[str, str], what: str
) -> tuple[list[Finding], dict[str, Any] | None]:
    """``steady`` (held commands, a straight speed in m/s) against the runs' straight level at those
    commands, else their manoeuvring level (:func:`compare`)."""
    held, flown = steady
    lv = matching_level(envelope, held)
    if lv is None:  # the runs never went straight there: their manoeuvring, run by run
        check = None
        for one in envelope.speed_manoeuvring:
            if matching_level(envelope, held, (one,)) is not None:
                found, c = _manoeuvring_check(one, flown, rising, units, what)
                if found:  # the first run it misses
                    return found, c
                if check is None or c["bound"] < check["bound"]:  # else the tightest
                    check = c
        return [], check
    tol, check = _check(lv, flown)
    check["holds"] = abs(flown - lv.speed) <= tol or (rising and flown < lv.speed)
    text = (
        f"{NOT_HOLD}: {what} {flown:.3g} m/s at {_command_text(lv.commands, units)}, its runs ran {lv.speed:.3g} ± "
        f"{lv.scatter:.2g} m/s there ({lv.runs} run(s); more than {tol:.2g} m/s off) — its manoeuvres are not predictions"
    )
    return ([] if check["holds"] else [Finding("does not hold", "speed", flown, lv.speed, "m/s", text)]), check


def _check(lv: SpeedLevel, flown: float) -> tuple[float, dict[str, Any]]:
    """The tolerance of a speed ``flown`` (m/s) against level ``lv`` and the comparison's record."""
    tol = max(SCATTER_K * lv.scatter, SPEED_FRACTION * lv.speed)
    keys = {"command": dict(lv.command), "speed": flown, "runs_speed": lv.speed, "scatter": lv.scatter}
    return tol, {**keys, "runs": lv.runs, "tolerance": tol}


def _manoeuvring_check(
    lv: SpeedLevel, flown: float, rising: bool, units: Mapping[str, str], what: str
) -> tuple[list[Finding], dict[str, Any]]:
    """A straight speed ``flown`` (m/s) against a run's steady speed manoeuvring at its commands
    (:func:`compare`): not below it, and not above it / (1 − :func:`largest_speed_loss`)."""
    tol, check = _check(lv, flown)
    at = _command_text(lv.commands, units)
    loss = largest_speed_loss(lv.turning or 0.0)
    top = lv.speed / (1.0 - loss) + tol
    check.update(turning=lv.turning, largest_loss=loss, bound=top)
    runs = f"its run, manoeuvring there (r' = rms(r) L/U {lv.turning or 0.0:.2g}), ran {lv.speed:.3g} ± {lv.scatter:.2g} m/s"
    if flown > top:
        text = (
            f"{NOT_HOLD}: {what} {flown:.3g} m/s at {at}, where {runs} — turning that gently costs a ship at "
            f"most {100 * loss:.0f} % of its straight speed (so at most {top:.3g} m/s straight) — its manoeuvres "
            "are not predictions"
        )
        check["holds"] = False
        return [Finding("does not hold", "speed", flown, top, "m/s", text)], check
    if flown < lv.speed - tol and not rising:
        text = (
            f"{NOT_HOLD}: {what} {flown:.3g} m/s at {at}, where {runs} — a ship is not slower straight than "
            "turning — its manoeuvres are not predictions"
        )
        check["holds"] = False
        return [Finding("does not hold", "speed", flown, lv.speed, "m/s", text)], check
    check["holds"] = True
    return [], check


def lines(findings: Sequence[Finding]) -> list[str]:
    """The lines a command prints (and a result's warnings hold): each ``does not hold`` on its own,
    the extrapolations together on one line, each starting with :data:`MARK`."""
    out = [MARK + f.text for f in findings if f.kind == "does not hold"]
    notes = [f.text for f in findings if f.kind == "extrapolation"]
    if notes:
        out.append(f"{MARK}{EXTRAPOLATES}: " + "; ".join(notes))
    return out


def is_envelope_line(text: str) -> bool:
    """True for a line of :func:`lines`."""
    return text.startswith(MARK)


def does_not_hold(text: str) -> bool:
    """True for the line of a model that does not hold at its own runs' speed."""
    return text.startswith(MARK + NOT_HOLD)


def straight_and_steady(
    time: Any,
    speed: Any,
    yaw_rate: Any,
    length: float | None,
    change: float = STEADY_CHANGE,
    straight_share: float = 0.5,
) -> tuple[bool, Any]:
    """Whether a stretch of samples is steady and nearly straight, and which samples are straight.

    Parameters
    ----------
    time : (n,) s; speed : (n,) m/s; yaw_rate : (n,) rad/s or None (not known: all straight)
    length : float or None — L, m (None: all straight, and no least distance)
    change : float — the largest change of the speed over the stretch, by its least-squares line,
        as a fraction of its mean speed
    straight_share : float — the least share of the samples that must be nearly straight (0: a
        steady stretch turning or not)

    Returns
    -------
    (steady, straight) — ``steady`` when the stretch runs at least :data:`STEADY_LENGTHS` L, its
    least-squares line changes the speed by at most ``change`` of its mean, and at least
    ``straight_share`` of its samples are nearly straight (|r| L / U ≤ :data:`STRAIGHT_RATE`); ``straight`` the boolean mask
    of those samples
    """
    import numpy as np

    t, u = np.asarray(time, float), np.asarray(speed, float)
    if yaw_rate is None or not length:
        straight = np.ones(t.size, bool)
    else:
        straight = np.abs(np.asarray(yaw_rate, float)) * length <= STRAIGHT_RATE * np.maximum(u, 1e-9)
    span = float(t[-1] - t[0]) if t.size else 0.0
    if t.size < 3 or not span > 0:
        return False, straight
    mean = float(np.mean(u))
    dt = t - np.mean(t)
    slope = float(np.sum(dt * (u - mean)) / np.sum(dt * dt))  # the least-squares line's
    far = mean * span >= STEADY_LENGTHS * (length or 0.0)
    steady = (
        far and mean > 0 and abs(slope) * span <= change * mean and int(np.sum(straight)) >= straight_share * t.size
    )
    return bool(steady), straight


def vehicle_length(vehicle: Any) -> float | None:
    """L of "nearly straight", m: the vehicle's ``reference_length``, or without one twice the
    farthest thruster or control surface from the body origin along x (a ship's rudder and
    propeller sit near its stern); None when neither says."""
    if getattr(vehicle, "reference_length", None):
        return float(vehicle.reference_length)
    xs = [abs(float(s.position[0])) for s in vehicle.surfaces.surfaces]
    ts = getattr(vehicle, "thrusters", None)
    if ts is not None and len(ts):
        xs += [abs(float(p[0])) for p in ts.positions]
    far = max(xs, default=0.0)
    return 2.0 * far if far > 0 else None


def extremes(nu: Any, deflection: Any = None, surface_names: Sequence[str] = ()) -> dict[str, Any]:
    """A prediction's largest speed, yaw rate, drift and deflections, measured as the envelope's are.

    Parameters
    ----------
    nu : (n, 6) — u, v, w (m/s), p, q, r (rad/s)
    deflection : (n, k) rad or None; surface_names : its k columns' surfaces

    Returns
    -------
    dict — ``speed`` (m/s, |(u, v, w)|), ``yaw_rate`` (rad/s), ``drift`` (rad, |atan2(−v, u)| where u
    > :data:`DRIFT_SPEED_FRACTION` × the largest speed; None when it never is) and ``deflection``
    ({surface: largest |δ|, rad})
    """
    import numpy as np

    v = np.asarray(nu, float)
    speed = np.linalg.norm(v[:, :3], axis=1)
    top = float(np.max(speed)) if speed.size else 0.0
    ahead = v[:, 0] > DRIFT_SPEED_FRACTION * top
    drift = float(np.max(np.abs(np.arctan2(-v[ahead, 1], v[ahead, 0])))) if top > 0 and np.any(ahead) else None
    d = None if deflection is None else np.atleast_2d(np.asarray(deflection, float))
    defl = {} if d is None or not d.size else {n: float(np.max(np.abs(d[:, k]))) for k, n in enumerate(surface_names)}
    return {
        "speed": top,
        "yaw_rate": float(np.max(np.abs(v[:, 5]))) if v.size else 0.0,
        "drift": drift,
        "deflection": defl,
    }
