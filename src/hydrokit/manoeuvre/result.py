"""A flown manoeuvre: the record of :func:`hydrokit.manoeuvre.run.fly_manoeuvre` measured into a
:class:`ManoeuvreResult` (:func:`measure`).

:func:`measure` extracts the metrics with :mod:`hydrokit.manoeuvre.metrics` and says in words what
a run did not reach (a spiral step never steady, a pull-out's sides not opposite, a depth hold
lost); the result writes manoeuvre.json (floats to :data:`JSON_DIGITS` significant digits) with
the IMO criteria of :mod:`hydrokit.manoeuvre.criteria`. A replayed trial
(:mod:`hydrokit.manoeuvre.replay`) is measured by the same code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.core.names import STATE_COLUMNS
from hydrokit.manoeuvre import laws as L
from hydrokit.manoeuvre import metrics as mm
from hydrokit.manoeuvre.criteria import imo_criteria
from hydrokit.manoeuvre.definitions import VERTICAL, Manoeuvre

#: significant digits of the floats in manoeuvre.json (the trajectory CSV keeps 9 too)
JSON_DIGITS = 9


@dataclass
class ManoeuvreResult(Result):
    """A flown manoeuvre.

    Attributes
    ----------
    manoeuvre : Manoeuvre
    vehicle : str — the vehicle's name; surface : str — the surface that steered
    time : (n,) — s, 0 at the execute (the approach's last seconds are negative)
    eta : (n, 6) — x, y (m, from the execute point), z (m), φ, θ, ψ (rad)
    nu : (n, 6) — u, v, w (m/s), p, q, r (rad/s)
    deflection : (n, n_surfaces) — every surface's deflection, rad
    surface_names : tuple of str
    executes : tuple of float — s, every order given (the first is 0)
    metrics : dict — the manoeuvre's results (SI; ``*_deg`` in degrees), None where not reached
    approach_speed : float — m/s; reference_length : float or None — L, m
    planar : bool — a surface-craft model (3 or 4 DOF): the IMO criteria apply
    hold : dict — what was held and by which surface ({"depth": "sternplane", "heading":
        "rudder (approach)"}; empty: nothing held); :attr:`approach_deflection` — the surfaces'
        trim at the execute (rad; manoeuvre.json ``approach_deflection_deg``)
    intervals : dict or None — with ``--samples``: every numeric metric's ``median``, ``low95``
        and ``high95`` over vehicles drawn from the file's covariance and how many ``samples``
        reached it (:mod:`hydrokit.manoeuvre.samples`); None without
    sampling : dict or None — the draw behind ``intervals`` (count, seed, parameters, σ)
    sample_tracks : list of (k, 4) arrays — time (s), x, y, z (m) of the drawn vehicles' runs
    hold_lost : str or None — what happened when the depth hold lost its depth (the depth
        ended more than :data:`HOLD_LOST_LENGTHS` L, at least 1 m, from the execute's, or strayed
        :data:`HOLD_LOST_WILD` times that; ``problem`` says so too)
    propulsion : dict or None — with thruster commands: ``commands`` and ``command_units`` per
        thruster, ``force`` (N, N·m), ``thrust_at_execute`` and ``thrust_at_end`` per thruster (N);
        None with a constant force only
    problem : str or None — what the run did not reach (the metrics it needs are None)
    warnings : list of str
    envelope : dict or None — the run compared with the envelope of the vehicle's identification
        (:func:`hydrokit.api.manoeuvre_envelope`): ``holds`` (False: the model missed its own runs'
        speed at the approach's commands; None: nothing compared), ``speed_check`` (the approach's
        speed, the runs' speed, scatter and the tolerance; None when no held level of the runs
        matched), ``findings`` (kind, quantity, value, limit, unit, text) and ``runs``; None: the
        vehicle has no envelope
    """

    manoeuvre: Manoeuvre
    vehicle: str
    surface: str
    time: np.ndarray
    eta: np.ndarray
    nu: np.ndarray
    deflection: np.ndarray
    surface_names: tuple[str, ...]
    executes: tuple[float, ...]
    metrics: dict[str, Any]
    approach_speed: float
    reference_length: float | None = None
    planar: bool = False
    problem: str | None = None
    warnings: list[str] = field(default_factory=list)
    hold: dict[str, str] = field(default_factory=dict)
    propulsion: dict[str, Any] | None = None
    hold_lost: str | None = None
    intervals: dict[str, Any] | None = None
    sampling: dict[str, Any] | None = None
    sample_tracks: list[np.ndarray] = field(default_factory=list)
    envelope: dict[str, Any] | None = None

    @property
    def kind(self) -> str:
        return self.manoeuvre.kind

    @property
    def approach_deflection(self) -> dict[str, float]:
        """Each surface's deflection at the end of the approach, rad: the trim the holds found to
        run straight (0 for a vehicle that goes straight with its surfaces at zero; a neutral
        rudder or a propeller's side force needs some). The manoeuvre's deflections are absolute."""
        before = np.nonzero(self.time < 0)[0]
        row = self.deflection[before[-1]] if before.size else self.deflection[0]
        return {n: float(d) for n, d in zip(self.surface_names, row)}

    @property
    def columns(self) -> list[str]:
        """Trajectory columns: simulate's thirteen, then one per surface (rad)."""
        return [*STATE_COLUMNS, *self.surface_names]

    def array(self) -> np.ndarray:
        """(n, 13 + n_surfaces) in :attr:`columns` order (what trajectory.csv holds)."""
        return np.column_stack([self.time, self.eta, self.nu, self.deflection])

    def table(self) -> tuple[list[str], list[list[Any]]]:
        return self.columns, self.array().tolist()

    def imo(self) -> list[dict[str, Any]]:
        """IMO MSC.137(76) §5.3 criteria that this run can check (empty when none apply)."""
        if not self.planar:
            return []
        return imo_criteria(
            self.kind, self.manoeuvre.parameters(), self.metrics, self.reference_length, self.approach_speed
        )

    def to_dict(self) -> dict[str, Any]:
        """manoeuvre.json: the settings, the metrics under the manoeuvre's name, IMO checks."""
        doc: dict[str, Any] = {
            "manoeuvre": self.kind,
            "vehicle": self.vehicle,
            "surface": self.surface,
            "parameters": self.manoeuvre.parameters(),
            "approach_speed": self.approach_speed,
            "reference_length": self.reference_length,
            self.kind: self.metrics,
            "executes": list(self.executes),
            "complete": self.problem is None,
            "problem": self.problem,
            "warnings": list(self.warnings),
            "hold": dict(self.hold),
            "hold_lost": self.hold_lost,
            "approach_deflection_deg": {n: math.degrees(d) for n, d in self.approach_deflection.items()},
            "units": mm.UNITS,
        }
        if self.propulsion is not None:
            doc["propulsion"] = self.propulsion
        if self.planar:
            doc["imo_criteria"] = self.imo()
        if self.intervals is not None:
            doc["intervals"] = self.intervals
            doc["sampling"] = self.sampling
        if self.envelope is not None:
            doc["envelope"] = self.envelope
        return rounded(jsonable(doc))

    def summary_rows(self) -> list[tuple[str, Any]]:
        rows: list[tuple[str, Any]] = [("manoeuvre", self.kind), ("surface", self.surface)]
        rows += [(k, v) for k, v in self.metrics.items() if not isinstance(v, (list, dict))]
        return rows + [("problem", self.problem or "none")]

    def plot(self, ax: Any = None) -> Any:
        """The track with the metrics drawn on it, on ``ax`` (or new axes); returns the axes."""
        from hydrokit.plot.manoeuvre import track_axes

        return track_axes(self, ax)


def rounded(obj: Any, digits: int = JSON_DIGITS) -> Any:
    """``obj`` (JSON-ready: dicts, lists, floats …) with every float rounded to ``digits``
    significant digits, so that 15° written from radians reads 15.0, not 14.999999999999998."""
    if isinstance(obj, dict):
        return {k: rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, list):
        return [rounded(v, digits) for v in obj]
    if isinstance(obj, float) and math.isfinite(obj):
        return float(f"{obj:.{digits}g}")
    return obj


def _settle_time(t: np.ndarray, r: np.ndarray, r0: float, r_end: float) -> float | None:
    """Time (s, from the record's start) after which the rate ``r`` stays within 5 % of its change
    ``r0 − r_end`` (rad/s) of its final value ``r_end`` (the 5 % settling time; the band at least
    1 % of ``r_end``, the steady turn's own ripple); None: never."""
    if t.size == 0:
        return None
    band = max(0.05 * abs(r0 - r_end), 0.01 * abs(r_end))
    out = np.flatnonzero(np.abs(r - r_end) > band)
    if out.size == 0:
        return 0.0
    k = int(out[-1]) + 1
    return None if k >= t.size else float(t[k] - t[0])


def _half_time(t: np.ndarray, r: np.ndarray, r0: float) -> float | None:
    """Time (s, from the record's start) for |r| to fall to half |r0|; None if it never does."""
    if t.size == 0 or r0 == 0:
        return None
    c = mm.first_reach(-np.abs(r), -0.5 * abs(r0))
    return None if c is None else float(c.at(t) - t[0])


def measure(
    manoeuvre: Manoeuvre,
    time: np.ndarray,
    states: np.ndarray,
    defl: np.ndarray,
    logic: Any,
    *,
    vehicle: str,
    surface_names: tuple[str, ...],
    surface: str,
    reference_length: float | None = None,
    planar: bool = False,
    warnings: list[str] | None = None,
    duration: float | None = None,
    hold: dict[str, str] | None = None,
) -> ManoeuvreResult:
    """The :class:`ManoeuvreResult` of a record from :func:`hydrokit.manoeuvre.run.fly_manoeuvre` (metrics
    extracted)."""
    after = time >= -1e-12
    t, x = time[after], states[after]
    approach = float(np.linalg.norm(x[0, 6:9]))
    kind = manoeuvre.kind
    warnings = [*(warnings or []), *getattr(logic, "notes", [])]
    problem: str | None = None
    metrics: dict[str, Any]
    if kind == "turning_circle":
        tc = mm.turning_circle_metrics(t, x[:, :6], x[:, 6:])
        metrics = _asdict(tc)
        if not planar:
            metrics["max_depth_change"] = float(np.max(np.abs(x[:, 2] - x[0, 2])))
        if (miss := tc.missing()) is not None:
            problem = (
                f"turning circle: the heading changed by at most {tc.heading_change_deg:.1f}° in {t[-1]:.4g} s after "
                f"the execute and never reached {miss}; expected a larger deflection or a longer --duration"
            )
    elif kind in ("zigzag", "vertical_zigzag"):
        ang = 5 if kind == "zigzag" else 4
        zz = mm.zigzag_metrics(t, x[:, ang], logic.executes, manoeuvre.check_angle, x[:, :2], approach)
        metrics = _asdict(zz)
        if kind == "vertical_zigzag" or not planar:
            metrics["max_depth_change"] = float(np.max(np.abs(x[:, 2] - x[0, 2])))
        if (miss := zz.missing()) is not None:
            what = "heading" if kind == "zigzag" else "pitch"
            change = math.degrees(float(np.max(np.abs(np.unwrap(x[:, ang]) - x[0, ang]))))
            problem = (
                f"{kind.replace('_', ' ')}: the {what} never reached {miss} in {t[-1]:.4g} s after the execute "
                f"(largest change {change:.1f}°); expected a larger deflection, a smaller check angle or a longer --duration"
            )
    elif kind == "spiral":
        metrics = mm.spiral_summary(logic.points, manoeuvre.mode, reference_length)
        problem = _spiral_problem(logic, t[-1])
    elif kind == "pull_out":
        metrics = mm.pull_out_summary(logic.sides)
        problem = _pull_out_problem(logic, t[-1])
    elif manoeuvre.max_pitch is not None:  # depth_change, closed loop
        metrics = mm.depth_change_closed_metrics(t, x, logic.executes, manoeuvre.depth, manoeuvre.max_pitch)
        if metrics["time_to_settle"] is None:
            problem = _depth_change_problem(manoeuvre, t, x, logic.executes)
    else:  # depth_change
        metrics = mm.depth_change_metrics(t, x, logic.executes, manoeuvre.depth)
        if metrics["depth_overshoot"] is None:
            problem = _depth_change_problem(manoeuvre, t, x, logic.executes)
    hold_lost = None
    if hold and "depth" in hold and kind not in VERTICAL:
        hold_lost, strayed = _depth_lost(x[:, 2] - x[0, 2], reference_length)
        if strayed is not None:
            warnings.append(f"{_label(kind)}: the depth hold by {hold['depth']} let {strayed}")
        if hold_lost is not None:
            warnings.append(f"{_label(kind)}: the depth hold by {hold['depth']} was lost: {hold_lost}")
            problem = (
                f"{_label(kind)}: depth hold lost — {hold_lost}; the trial is flown at constant depth, so "
                "its metrics would be those of a climb or a dive" + (f" (and {problem})" if problem else "")
            )
    return ManoeuvreResult(
        manoeuvre=manoeuvre,
        vehicle=vehicle,
        surface=surface,
        time=time,
        eta=states[:, :6],
        nu=states[:, 6:],
        deflection=defl,
        surface_names=surface_names,
        executes=tuple(logic.executes),
        metrics=metrics,
        approach_speed=approach,
        reference_length=reference_length,
        planar=planar,
        problem=problem,
        warnings=warnings,
        hold=dict(hold or {}),
        hold_lost=hold_lost,
    )


#: a depth hold is lost when the depth ends more than this many L (at least 1 m) from its set-point …
HOLD_LOST_LENGTHS = 2.0
#: … or strays more than this many times that at any time (less, and back: a transient, warned of)
HOLD_LOST_WILD = 4.0


def _label(kind: str) -> str:
    """The manoeuvre's name in a sentence: "turning circle", "pull-out", "depth change" …"""
    return "pull-out" if kind == "pull_out" else kind.replace("_", " ")


def _moved(dz: np.ndarray) -> str:
    """How the depth changed over a record (``dz``: m, + deeper): "rose 238 m", "sank 3.1 m",
    "rose 2 m and sank 4 m" — the largest excursions each way (from 1 cm and a tenth of the larger)."""
    rise, fall = max(0.0, -float(np.min(dz))), max(0.0, float(np.max(dz)))
    least = max(0.01, 0.1 * max(rise, fall))  # a small excursion the other way is not news
    parts = [f"{w} {v:.3g} m" for w, v in (("rose", rise), ("sank", fall)) if v >= least]
    return " and ".join(parts) if parts else "kept its depth within 1 cm"


def _depth_lost(dz: np.ndarray, length: float | None) -> tuple[str | None, str | None]:
    """(lost, strayed): what happened when a depth hold was lost — the depth ends more than
    :data:`HOLD_LOST_LENGTHS` L (≥ 1 m) from where the manoeuvre started, or strayed more than
    :data:`HOLD_LOST_WILD` times that ("the vehicle rose 224 m (more than 2.67 m …)") — or when it
    strayed that far but came back (a transient, said as a warning); None for what did not happen."""
    limit = max(1.0, HOLD_LOST_LENGTHS * (length or 0.0))
    worst, end = float(np.max(np.abs(dz))), abs(float(dz[-1]))
    if worst <= limit:
        return None, None
    if end > limit:
        return (
            f"the vehicle {_moved(dz)} and ended {end:.3g} m from the depth at the execute (more than {limit:.3g} m)",
            None,
        )
    if worst > HOLD_LOST_WILD * limit:
        return (
            f"the vehicle {_moved(dz)} (more than {HOLD_LOST_WILD * limit:.3g} m from the depth at the execute)",
            None,
        )
    return None, (
        f"the vehicle stray: it {_moved(dz)} (more than {limit:.3g} m) before it was brought back to within "
        f"{end:.2g} m of the depth at the execute"
    )


def _depth_change_problem(m: Manoeuvre, t: np.ndarray, x: np.ndarray, executes: Any) -> str:
    """What a depth change that did not level off did, in words."""
    dz = x[:, 2] - x[0, 2]
    want = f"{abs(m.depth):g} m {'deeper' if m.depth > 0 else 'shallower'}"
    sense = 1.0 if m.depth > 0 else -1.0
    wrong = -sense * dz
    if len(executes) < 2:
        why = "never reached it"
        if float(np.max(wrong)) > max(1.0, abs(m.depth)):
            why += " — it went the other way: depth control lost"
        return (
            f"depth change: asked {want}, the vehicle {_moved(dz)} in {t[-1]:.4g} s after the execute and {why}; "
            "expected a larger plane angle or a longer --duration"
        )
    return (
        f"depth change: the vehicle reached {want} at {executes[1]:.4g} s but never "
        f"{'levelled off' if m.max_pitch is None else 'settled there'} (it {_moved(dz)} in {t[-1]:.4g} s); "
        "expected a smaller plane angle or a longer --duration"
    )


def _spiral_problem(logic: Any, t_end: float) -> str | None:
    """What keeps a spiral from being measured (None: every step steady, the verdict drawn)."""
    pts, n = logic.points, len(logic.targets)
    if len(pts) < n:
        return (
            f"spiral: only {len(pts)} of {n} steps were completed in {t_end:.4g} s after the execute; "
            "expected a longer --duration (or none: the default scales with the vehicle's L/U)"
        )
    loose = [p for p in pts if not p["settled"]]
    if loose:
        worst = max(loose, key=lambda p: p["held"])
        return (
            f"spiral: {len(loose)} of {n} steps never reached a steady yaw rate (the step at "
            f"{math.degrees(worst['target']) if logic.m.mode == 'direct' else worst['target']:.4g}"
            f"{'°' if logic.m.mode == 'direct' else ' rad/s'} still drifted after {worst['held']:.4g} s); "
            "their rows say settled = false"
        )
    if logic.m.mode == "direct":
        rates = [p["yaw_rate"] for p in pts]
        floor = L.STEADY_DRIFT_ABS / logic.scale
        if all(r > floor for r in rates) or all(r < -floor for r in rates):
            side = "starboard (r > 0)" if rates[0] > 0 else "port (r < 0)"
            top = math.degrees(abs(logic.a))
            return (
                f"spiral: the vehicle kept turning to {side} at every deflection from +{top:.4g}° to "
                f"−{top:.4g}° and back (slowest |r| {min(abs(r) for r in rates):.3g} rad/s): the surface "
                "cannot reverse its turn, so no loop or stability verdict can be drawn"
            )
    return None


def _pull_out_problem(logic: Any, t_end: float) -> str | None:
    """What keeps a pull-out from being measured (None: two opposite sides, each turn and release
    steady)."""
    sides = logic.sides
    if len(sides) < 2:
        return (
            f"pull-out: only {len(sides)} of 2 sides completed in {t_end:.4g} s after the execute; expected a "
            "longer --duration (or none: the default scales with the vehicle's L/U)"
        )
    for s in sides:
        d = math.degrees(s["deflection"])
        if not s["turn_settled"]:
            return f"pull-out: the turn at {d:+.4g}° never reached a steady yaw rate (it was released anyway)"
        if not s["decay_settled"] or s.get("time_to_settle") is None:
            return f"pull-out: after the release from {d:+.4g}° the yaw rate never settled (residual not measured)"
    a, b = (s["yaw_rate_before"] for s in sides)
    if a * b >= 0:
        return (
            f"pull-out: the {math.degrees(sides[1]['deflection']):+.4g}° side turned the same way as the "
            f"{math.degrees(sides[0]['deflection']):+.4g}° side (yaw rates {a:.3g} and {b:.3g} rad/s): the two "
            "sides are not opposite"
            + ("" if logic.straight else "; the vehicle was not brought back to a straight course between them")
        )
    return None


def _asdict(obj: Any) -> dict[str, Any]:
    from dataclasses import asdict

    d = asdict(obj)
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in d.items()}
