"""The standard manoeuvres of a free-running vehicle (SPEC §9.2; IMO MSC.137(76), ITTC 7.5-04-02-01).

:func:`fly_manoeuvre` runs a vehicle straight until its velocities are steady (the approach),
then gives the first order — the **execute** — and flies the manoeuvre with a logic that reads
the state every step, as a helmsman or an autopilot would:

- **turning circle** (IMO 4.2.2): the steering surface to δ and held until the heading has
  changed 720° (the steady part is measured over the last 360°);
- **zigzag A/B** (IMO 4.2.6): surface to A; when the heading has changed by B in the direction of
  the turn, to −A; when it is B off the original course on the other side, to +A; … four
  executes and the overshoot after the last;
- **spiral** (ITTC 2.2.5): *direct* (Dieudonné): the deflection stepped from +δ_max down to
  −δ_max and back, each held until the yaw rate is steady; *reverse* (Bech): a yaw-rate
  autopilot holds a series of yaw rates and the mean deflection each needs is recorded; a
  course-unstable vehicle shows a loop (direct) or an S-shaped curve (reverse);
- **pull-out** (ITTC 2.2.6): a steady turn at ±δ, then the surface back to zero; the yaw rate of a
  course-stable vehicle decays to zero, an unstable one keeps a residual rate;
- **depth change** (AUVs): planes to A in the diving (or rising) sense until the depth has
  changed by M, then to −A until the pitch is back to its original value, then to zero (with the
  hold on: to holding the original pitch, as a pitch-unstable AUV cannot fly with its planes at
  zero); the depth overshoot is read at the depth's peak;
- **vertical zigzag A/B** (AUVs): the zigzag on the pitch angle with the stern planes.

**The hold** (``hold``, default on for a 6-DOF vehicle with a second surface): AUV trials are
flown at constant depth, so during a turn or zigzag the stern planes hold depth and pitch, and
during a depth change or vertical zigzag the rudder holds the heading — PID loops of
:mod:`hydrokit.model.control` (:class:`_Keeper`); during the approach the steering surface holds
its own axis too (an AUV on autopilot), and the execute hands it to the manoeuvre.

**Propulsion** is a constant force, or the vehicle's thrusters at held commands
(:class:`ThrusterDrive`, ``run_manoeuvre(commands=…)``): at every RK4 stage each thruster's thrust
comes from its own curve (:meth:`hydrokit.model.thrusters.ThrusterSet.thrust`) at its advance
speed, so a propeller at constant revolutions gives more thrust as the vehicle slows in a turn (K_T
rises as J falls) — the speed loss in a turn comes out of the propeller's K_T(J), as in a real
trial. The rotors spin up from rest with their lag during the approach; the commands are held
throughout. The whole input vector reaches the right-hand side — τ, every deflection, every
thruster's thrust and rotation rate — so ``T()`` and ``n()`` term factors and a rudder in the
propeller race see the thrust: the model flown is the one ``simulate --command`` flies and
``sysid`` fits (issue #56: until then both manoeuvre loops set the thrust inputs to zero).

The sense of a turn is read from the vehicle's response (a positive rudder turns a REMUS to
port: Prestero's N_uuδr < 0), never assumed. Commands reach the surfaces through the servo law
:func:`hydrokit.model.surfaces.servo_step` (instant without rate limit or lag). The record is
measured by :func:`hydrokit.manoeuvre.result.measure` (metrics from :mod:`hydrokit.manoeuvre.metrics`);
its time is 0 at the execute and its positions are relative to the execute point. What to fly
(:class:`~hydrokit.manoeuvre.definitions.Manoeuvre`, :func:`turning_circle`, :func:`zigzag`, …) lives in
:mod:`hydrokit.manoeuvre.definitions`; this module keeps those names, and the result's, too.

**The loop.** The logics, the hold and the approach's steadiness test are laws written once on
plain floats over small arrays (:mod:`hydrokit.manoeuvre.laws`). With a vehicle and a
constant force, :func:`run_manoeuvre` flies them in the compiled loop
(:mod:`hydrokit.manoeuvre.compiled`: the same laws compiled by ``compile_law``, RK4 at
the manoeuvre's step); :func:`fly_manoeuvre` with any Python right-hand side, a force ``tau(x)``
or thruster commands calls the same laws as Python (:class:`_PythonLoop`). The two agree to
rounding (tests/simulate/test_manoeuvre_compiled.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.core.kinematics import rotation_zyx
from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError, SimulationError
from hydrokit.manoeuvre import laws as L
from hydrokit.manoeuvre.definitions import (  # noqa: F401  (their old home, re-exported)
    KINDS,
    REVERSE_SPIRAL_RATE,
    SPIRAL_FRACTIONS,
    VERTICAL,
    Manoeuvre,
    _pair,
    depth_change,
    from_options,
    pull_out,
    spiral,
    turning_circle,
    vertical_zigzag,
    zigzag,
)
from hydrokit.manoeuvre.result import (  # noqa: F401  (their old home, re-exported)
    HOLD_LOST_LENGTHS,
    HOLD_LOST_WILD,
    JSON_DIGITS,
    ManoeuvreResult,
    _asdict,
    _depth_change_problem,
    _depth_lost,
    _half_time,
    _label,
    _moved,
    _pull_out_problem,
    _settle_time,
    _spiral_problem,
    measure,
    rounded,
)
from hydrokit.simulate.commands import short_repr, thruster_commands

#: the longest turning circle, zigzag, depth change or vertical zigzag, in L/U at the approach speed
#: (each ends as soon as it is measured; the spiral and pull-out budget their steps instead)
BUDGET = {"turning_circle": 2000.0, "zigzag": 500.0, "depth_change": 500.0, "vertical_zigzag": 500.0}
# the thresholds of the logics and the hold live with their laws (manoeuvre/laws.py); named here too
TURN_TARGET, TURN_STEADY, TURN_MAX = L.TURN_TARGET, L.TURN_STEADY, L.TURN_MAX
STEADY_WINDOW, STEADY_DRIFT_ABS, STEADY_DRIFT_REL = L.STEADY_WINDOW, L.STEADY_DRIFT_ABS, L.STEADY_DRIFT_REL
STEADY_MAX_HOLD, HOLD_MAX_PITCH, HOLD_PERIOD = L.STEADY_MAX_HOLD, L.HOLD_MAX_PITCH, L.HOLD_PERIOD
HOLD_MIN_SPEED, HOLD_TOLERANCE = L.HOLD_MIN_SPEED, L.HOLD_TOLERANCE
DEPTH_BAND, DEPTH_BAND_MIN, DEPTH_SETTLE = L.DEPTH_BAND, L.DEPTH_BAND_MIN, L.DEPTH_SETTLE

Dynamics = Callable[..., np.ndarray]
Servo = Callable[..., Any]
#: the whole right-hand side of a manoeuvre given the deflections: rhs(t, x, δ, h) → ẋ, with
#: h the time (s) into the step begun last for a thruster drive's rotor state (None: now)
Rhs = Callable[[float, np.ndarray, np.ndarray, "float | None"], np.ndarray]


# --------------------------------------------------------------------------------------------
# manoeuvre logics: read the state each step, return the surface command (rad)
#
# The logics and the hold are laws written once on plain floats in
# :mod:`hydrokit.manoeuvre.laws`; the classes below hold their arrays and read the
# results out of them. The Python loop calls the laws as Python, the compiled loop
# (:mod:`hydrokit.manoeuvre.compiled`) the same functions compiled.

_CODES = {
    "turning_circle": L.TURN,
    "zigzag": L.ZIGZAG,
    "vertical_zigzag": L.ZIGZAG,
    "spiral": L.SPIRAL,
    "pull_out": L.PULL_OUT,
}


class _Logic:
    """A manoeuvre's state machine: settings ``P``, memory ``S``, record ``H`` and rows ``R``
    (:mod:`hydrokit.manoeuvre.laws`); ``angle`` is the state index it measures (ψ 5, θ 4).

    Parameters
    ----------
    m : Manoeuvre; limit : the steering surface's limit, rad; probe : ∂(angular acceleration)/∂δ
    at the execute, 1/s² per rad; time_scale : L/U at the execute, s; dt : the step, s
    """

    def __init__(self, m: Manoeuvre, limit: float, probe: float, time_scale: float, dt: float = 0.0) -> None:
        self.m = m
        self.limit = limit
        self.probe = probe  # sign and size of d(angular acceleration)/dδ at the execute
        self.scale = time_scale
        self.a = m.deflection if m.deflection is not None else limit
        self.code = _CODES.get(m.kind, L.DEPTH_CHANGE if m.max_pitch is None else L.DEPTH_PILOT)
        self.angle = 4 if m.kind in VERTICAL else 5
        self.targets: list[float] = []
        if m.kind == "spiral":
            top = abs(self.a)
            fr = [*SPIRAL_FRACTIONS, *(-f for f in reversed(SPIRAL_FRACTIONS[:-1]))]
            levels = fr + fr[-2::-1]  # down from +1 to −1 and back up to +1
            if m.mode == "direct":
                self.targets = [top * f for f in levels]
            else:  # one pass: δ(r) is single-valued
                self.targets = [REVERSE_SPIRAL_RATE / time_scale * f for f in fr]
        P = np.zeros(L.P_SIZE)
        P[L.P_KIND], P[L.P_A], P[L.P_LIMIT], P[L.P_PROBE], P[L.P_SCALE] = self.code, self.a, limit, probe, time_scale
        P[L.P_CHECK], P[L.P_DEPTH], P[L.P_ANGLE] = m.check_angle, m.depth, self.angle
        P[L.P_REVERSE], P[L.P_DT], P[L.P_RATE] = float(m.mode == "reverse"), dt, 11
        P[L.P_NT], P[L.P_MAXPITCH] = len(self.targets), m.max_pitch or 0.0
        P[L.P_TARGETS : L.P_TARGETS + len(self.targets)] = self.targets
        self.P = P
        self.S = np.zeros(L.S_SIZE)
        self.H = np.zeros((1024, L.H_COLS))
        self.R = np.zeros((L.MAX_ROWS, L.R_COLS))
        self.x0: np.ndarray = np.zeros(12)

    def start(self, x0: np.ndarray) -> None:
        self.x0 = x0.copy()
        L.helm_init(self.P, self.S, self.x0)

    def reserve(self, rows: int) -> None:
        """Room for ``rows`` rows in the record ``H`` (grown by doubling)."""
        if rows > self.H.shape[0]:
            grown = np.zeros((max(rows, 2 * self.H.shape[0]), L.H_COLS))
            grown[: self.H.shape[0]] = self.H
            self.H = grown

    def command(self, t: float, x: np.ndarray) -> float:
        """The steering surface's command (rad) at ``t`` (s, 0 at the execute) in the state ``x``."""
        self.reserve(int(self.S[L.S_NH]) + 1)
        return float(L.helm_command(self.P, self.S, self.H, self.R, t, x))

    @property
    def done(self) -> bool:
        return bool(self.S[L.S_DONE])

    @property
    def executes(self) -> list[float]:
        return [float(v) for v in self.S[L.S_EXEC : L.S_EXEC + int(self.S[L.S_NEXEC])]]

    @property
    def phase(self) -> int:
        return int(self.S[L.S_PHASE])

    @property
    def notes(self) -> list[str]:
        if not self.S[L.S_NOTE]:
            return []
        return [
            f"turning circle: the yaw rate or speed still changed by more than {TURN_STEADY:.1%} over the "
            f"last 360° after {math.degrees(self.S[L.S_NOTE_A]):.0f}°; the steady values are those of the last 360°"
        ]

    @property
    def points(self) -> list[dict[str, Any]]:
        """A spiral's steps: mean deflection (rad), yaw rate (rad/s), speed (m/s), settled, target, held (s)."""
        rows = self.R[: int(self.S[L.S_NROWS])] if self.code == L.SPIRAL else self.R[:0]
        return [
            {
                "deflection": float(r[0]),
                "yaw_rate": float(r[1]),
                "speed": float(r[2]),
                "settled": bool(r[3]),
                "target": float(r[4]),
                "held": float(r[5]),
            }
            for r in rows
        ]

    @property
    def sides(self) -> list[dict[str, Any]]:
        """A pull-out's sides (ITTC 2.2.6): the turn released, its residual rate and decay times."""
        rows = self.R[: int(self.S[L.S_NROWS])] if self.code == L.PULL_OUT else self.R[:0]
        out = []
        for r in rows:
            h = self.H[int(r[6]) : int(r[7])]
            ok = bool(r[5])
            out.append(
                {
                    "deflection": float(r[0]),
                    "yaw_rate_before": float(r[1]),
                    "time": float(r[2]),
                    "turn_settled": bool(r[3]),
                    "residual_yaw_rate": float(r[4]),
                    "decay_settled": ok,
                    "time_to_half": _half_time(h[:, 0], h[:, 1], float(r[1])),
                    "time_to_settle": _settle_time(h[:, 0], h[:, 1], float(r[1]), float(r[4])) if ok else None,
                }
            )
        return out

    @property
    def straight(self) -> bool | None:
        """Pull-out: whether the vehicle was brought back to a straight course between the sides."""
        s = self.S[L.S_STRAIGHT]
        return None if s < 0 else bool(s)

    def steps(self) -> int:
        return len(self.targets) if self.code == L.SPIRAL else L.PULL_OUT_PHASES

    def budget(self) -> float:
        """The longest the manoeuvre may take, s: :data:`BUDGET` L/U at the approach speed, or,
        for a spiral or pull-out, every step held to :data:`STEADY_MAX_HOLD` L/U at a tenth of
        the approach speed (it ends as soon as every step is steady)."""
        if self.code in (L.SPIRAL, L.PULL_OUT):
            return self.steps() * STEADY_MAX_HOLD * 10.0 * self.scale
        return BUDGET[self.m.kind] * self.scale


class _Keeper:
    """Holds depth and pitch with a stern plane and the heading with a rudder, with the PID law
    of :mod:`hydrokit.model.control` (an AUV's autopilot during trials at constant depth).

    Depth: an outer PID on z gives the pitch set-point θ_d (rad, within ±:data:`HOLD_MAX_PITCH`),
    with the time constant 5 L/U (ż ≈ −U θ); pitch and heading: a PID on the angle (rate from the
    Euler kinematics) with natural frequency U/L, critically damped, whose output is an angular
    acceleration (rad/s²) turned into a deflection by dividing it by ∂q̇/∂δ (or ∂ṙ/∂δ), probed
    on the vehicle's own right-hand side every :data:`HOLD_PERIOD` s (gain scheduling: fin
    forces grow as U²). Set-points: the depth and heading at the start of the approach. The
    surface that steers the manoeuvre holds only until the execute. The law is
    :func:`hydrokit.manoeuvre.laws.keeper_command` on the array ``K``.
    """

    def __init__(
        self,
        rhs: Rhs,
        n_s: int,
        hold: tuple[int | None, int | None],
        steering: int,
        lim: np.ndarray,
        length: float | None,
        x0: np.ndarray,
    ) -> None:
        self.rhs, self.n_s = rhs, n_s
        self.plane, self.rudder = hold
        self.lim = lim
        self.K = np.zeros(L.K_SIZE)
        p = -1 if self.plane is None else self.plane
        r = -1 if self.rudder is None else self.rudder
        L.keeper_init(
            self.K,
            p,
            r,
            steering,
            float(lim[p]) if p >= 0 else 0.0,
            float(lim[r]) if r >= 0 else 0.0,
            length or 0.0,
            x0,
        )

    @property
    def trim(self) -> float | None:
        """The pitch a closed-loop depth change starts from, rad (None: 0)."""
        v = float(self.K[L.K_TRIM])
        return None if math.isnan(v) else v

    @trim.setter
    def trim(self, value: float) -> None:
        self.K[L.K_TRIM] = value

    def tune(self, t: float, x: np.ndarray) -> None:
        """Probe the holding surfaces' effect in the state ``x`` and schedule the gains (t in s)."""
        g_q = 0.0 if self.plane is None else _probe(self.rhs, x, self.n_s, self.plane, float(self.lim[self.plane]), 10)
        g_r = (
            0.0 if self.rudder is None else _probe(self.rhs, x, self.n_s, self.rudder, float(self.lim[self.rudder]), 11)
        )
        L.keeper_tune(self.K, t, x, g_q, g_r)

    def settled(self, x: np.ndarray) -> bool:
        """True when the held depth and heading are within :data:`HOLD_TOLERANCE` (m, rad) of their
        set-points (the approach is steady only then)."""
        return bool(L.keeper_settled(self.K, x))

    def command(self, t: float, x: np.ndarray, dt: float, cmd: np.ndarray, approach: bool) -> None:
        """Set the holding surfaces' commands in ``cmd`` (rad) for the state ``x`` at ``t`` (s)."""
        if L.keeper_due(self.K, t):
            self.tune(t, x)
        L.keeper_command(self.K, x, dt, cmd, approach)


# --------------------------------------------------------------------------------------------
# propulsion from thruster commands


class ThrusterDrive:
    """The vehicle's thrusters at held commands: the thrusters' part of the input vector of
    :func:`fly_manoeuvre` (τ, each thruster's thrust and rotation rate) at any state.

    ``τ(x) = force + T f(c, V_a(ν_r))``: T the thrusters' configuration matrix, f each thruster's
    thrust from its own curve (:meth:`ThrusterSet.thrust`: a propeller's K_T(J) ρ D⁴ |n| n, a
    table, or the command itself for an ideal thruster) at the advance speed of the velocity
    relative to the water (:meth:`ThrusterSet.advance_speed`), c the rotor state. The rotors start
    from rest and follow the commands with their first-order lag (:meth:`ThrusterSet.rotor_step`,
    exact for a held command). The thrust, the rotation rate (read by ``T()`` and ``n()`` term
    factors and by a rudder in the propeller race) and τ are evaluated at every RK4 stage, at the
    stage's state and rotor state (:meth:`inputs`) — the same model as ``simulate --command``
    (:meth:`hydrokit.simulate.commands.CommandForce.inputs`), issue #56.

    Parameters
    ----------
    thrusters : ThrusterSet
    command : m floats — held commands, file order: rev/s (propeller), the table's unit (table),
        N (ideal); within the thrusters' command limits
    force : 6 floats — constant force added to the thrust, N, N·m (body axes)
    current_ned : None, 3 floats (m/s, NED) or rows [t (s), v_N, v_E, v_D (m/s)]
    """

    def __init__(self, thrusters: Any, command: Any, force: Any = (0, 0, 0, 0, 0, 0), current_ned: Any = None) -> None:
        from hydrokit.model.dynamics import current_table

        self.thrusters = thrusters
        self.target = np.asarray(command, float)
        self.force = np.asarray(force, float)
        self.T = thrusters.configuration_matrix()
        self.c = np.zeros(len(thrusters))  # rotor state now: from rest
        self.c0 = self.c.copy()  # the rotor state at the start of the step being taken
        self.current = current_table(current_ned)[:, :4]  # the water's: the wind does not reach the propellers

    def begin_step(self, t: float, dt: float) -> None:
        """Start the step [t, t + dt] (s): its stages read the rotors from the state now
        (:meth:`inputs` with ``h``); ``c`` becomes the state at its end (both in place, so the
        compiled loop's packed copy is the same array)."""
        self.c0[:] = self.c
        self.c[:] = self.thrusters.rotor_step(self.c0, self.target, dt)

    def inputs(self, t: float, x: np.ndarray, h: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(τ in N and N·m, each thruster's thrust in N, its rotation rate in rev/s) in the
        12-state ``x`` (Euler angles) at time ``t`` (s; the current's): at the rotor state ``h``
        s into the step begun last (:meth:`begin_step`), or at the rotor state now (``h`` None)."""
        from hydrokit.model.dynamics import interp_table

        ts = self.thrusters
        c = self.c if h is None else ts.rotor_step(self.c0, self.target, h)
        nu_r = np.asarray(x[6:12], float)
        if np.any(self.current[:, 1:]):
            vc = interp_table(self.current, t)[0]
            nu_r = nu_r.copy()
            nu_r[:3] -= rotation_zyx(float(x[3]), float(x[4]), float(x[5])).T @ vc
        f = ts.thrust(c, ts.advance_speed(nu_r))
        return self.force + self.T @ f, f, ts.rotation_rate(f, command=c)

    def thrust(self, x: np.ndarray) -> np.ndarray:
        """Each thruster's thrust (N) in the 12-state ``x`` at the rotor state now."""
        return self.inputs(0.0, x)[1]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """τ (N, N·m) in the state ``x`` at the rotor state now."""
        return self.inputs(0.0, x)[0]


def commands_from_text(text: str) -> dict[str, float]:
    """``NAME=VALUE[,NAME=VALUE]`` (the command line's ``--command``) as {name: value}; the names
    and limits are checked against the vehicle by :func:`thruster_commands`."""
    out: dict[str, float] = {}
    for part in str(text).split(","):
        name, sep, value = part.partition("=")
        name = name.strip()
        try:
            c = float(value)
        except ValueError:
            c = math.nan
        if not sep or not name or not math.isfinite(c):
            raise InputError(
                f"--command {part.strip()[:60]!r}: expected NAME=VALUE with a finite VALUE (the thruster's unit)"
            )
        if name in out:
            raise InputError(f"--command: thruster {name!r} named twice; expected each thruster once")
        out[name] = c
    return out


# --------------------------------------------------------------------------------------------
# the runner


def fly_manoeuvre(
    f: Dynamics,
    manoeuvre: Manoeuvre,
    surface: int,
    servo: tuple[np.ndarray, np.ndarray, np.ndarray],
    *,
    tau: Any = (0, 0, 0, 0, 0, 0),
    x0: Any = None,
    dt: float = 0.02,
    duration: float | None = None,
    approach: float = 600.0,
    keep_approach: float = 10.0,
    length: float | None = None,
    servo_step: Servo | None = None,
    hold: tuple[int | None, int | None] | None = None,
    progress: Callable[[float, float], None] | None = None,
    engine: Any = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, _Logic, list[str]]:
    """Approach, execute and fly ``manoeuvre`` with the dynamics ``f(t, x, τ, δ) → ẋ``.

    Parameters
    ----------
    f : callable — 12-state Euler right-hand side (x = [x y z φ θ ψ u v w p q r], SI)
    manoeuvre : Manoeuvre
    surface : int — index of the steering surface
    servo : (max deflection rad, rate limit rad/s, time constant s) arrays, one per surface
    tau : 6 floats (N, N·m) or a callable ``tau(x) → 6 floats`` (N, N·m); one with a
        ``begin_step(t, dt)`` method (a :class:`ThrusterDrive`) is told of every step before it
        is taken (t, dt in s)
    x0 : 12 floats — initial state (default rest at the origin)
    dt : float — step, s; duration : float or None — longest manoeuvre after the execute, s
        (None: the manoeuvre's own budget in L/U, :data:`BUDGET`, or every spiral or pull-out step
        held to :data:`STEADY_MAX_HOLD` L/U at a tenth of the approach speed)
    approach : float — longest straight run before the execute, s
    keep_approach : float — seconds of the approach kept in the record, s
    length : float or None — L, m: the windows that judge "steady" are multiples of L/U at the
        execute (1 s without L)
    servo_step : the servo law (default :func:`hydrokit.model.surfaces.servo_step`)
    hold : None, or (plane, rudder): indices of the surfaces that hold depth and pitch, and
        heading (either None), with :class:`_Keeper`; the steering surface holds only until the
        execute
    progress : callable(simulated seconds, longest seconds) or None
    engine : None (the Python loop around ``f``) or a
        :class:`hydrokit.manoeuvre.compiled.Engine` built on the same vehicle as ``f``
        and with constant ``tau``: the same laws flown by the compiled loop

    Returns
    -------
    (time, states (n, 12), deflections (n, n_surfaces), logic, warnings), time 0 at the execute.
    """
    if engine is not None and ((callable(tau) and tau is not getattr(engine, "drive", None)) or servo_step is not None):
        raise InputError(
            "the compiled manoeuvre loop takes a constant force or its own thruster drive and the servo law; "
            "expected engine=None"
        )
    if servo_step is None:
        from hydrokit.model.surfaces import servo_step as law

        servo_step = law
    lim, rate, tc = (np.asarray(a, float) for a in servo)
    n_s = lim.size
    if not (0 <= surface < n_s):
        raise InputError(f"surface index {surface}: expected 0 … {n_s - 1}")
    if not (math.isfinite(dt) and dt > 0 and (duration is None or (math.isfinite(duration) and duration >= dt))):
        raise InputError(f"dt = {dt} s, duration = {duration} s: expected 0 < dt ≤ duration")
    if manoeuvre.deflection is not None and abs(manoeuvre.deflection) > lim[surface] * (1 + 1e-9):
        raise InputError(
            f"{manoeuvre.kind}: deflection {math.degrees(manoeuvre.deflection):.4g}°: expected at most the "
            f"surface's max_deflection_deg {math.degrees(lim[surface]):.4g}°"
        )
    tau_of: Callable[[np.ndarray], np.ndarray]
    if callable(tau):
        tau_of = lambda x: np.asarray(tau(x), float)  # noqa: E731
    else:
        tau_c = np.asarray(tau, float)
        if tau_c.shape != (6,) or not np.all(np.isfinite(tau_c)):
            raise InputError(f"force {tau_c.tolist()}: expected 6 finite numbers (N, N·m)")
        tau_of = lambda x: tau_c  # noqa: E731
    rhs = right_hand_side(f, tau, tau_of)
    x = np.zeros(12) if x0 is None else np.asarray(x0, float).copy()
    if x.shape != (12,) or not np.all(np.isfinite(x)):
        raise InputError(f"initial state {x.tolist()}: expected 12 finite numbers")
    warnings: list[str] = []
    keeper = None
    if hold is not None and (hold[0] is not None or hold[1] is not None):
        for h in hold:
            if h is not None and not (0 <= h < n_s):
                raise InputError(f"hold surface index {h}: expected 0 … {n_s - 1}")
        keeper = _Keeper(rhs, n_s, hold, surface, lim, length, x)
    loop = engine if engine is not None else _PythonLoop(f, tau, tau_of, servo_step, rhs)
    sv = _Servo(lim, rate, tc, np.zeros(n_s), np.zeros(n_s), np.zeros(n_s))

    # the approach: straight, surfaces at zero, until ν is steady over a window
    window = max(int(round(2.0 / dt)), 10)
    n_app = max(int(approach / dt), window + 1)
    rows = np.empty((n_app + 1, 12))
    rows[0] = x
    used = np.empty((n_app, n_s))  # the deflections held over each approach step
    k_app, status = loop.approach(x, n_app, window, dt, keeper, sv, rows, used)
    if status < 0:
        raise SimulationError(
            f"the state became non-finite at t = {(k_app + 1) * dt:.6g} s; check the coefficients and dt"
        )
    if status == 0:
        warnings.append(
            f"the approach was not steady after {approach:g} s (velocities still changing); the manoeuvre "
            "starts from the state reached"
        )
    n_rows = k_app + 2
    x = rows[n_rows - 1].copy()
    keep = min(n_rows - 1, int(keep_approach / dt))
    app = rows[n_rows - 1 - keep : n_rows]
    t_app = (np.arange(app.shape[0]) - keep) * dt
    # the execute
    u_exec = math.sqrt(float(x[6] ** 2 + x[7] ** 2 + x[8] ** 2))
    if u_exec < HOLD_MIN_SPEED:
        # nothing to steer: a manoeuvre at (nearly) no way would idle to its longest budget
        raise InputError(
            f"manoeuvre: speed at the execute {u_exec:.3g} m/s after a {(k_app + 1) * dt:.4g} s approach, below "
            f"the hold's minimum {HOLD_MIN_SPEED:g} m/s; expected more propulsion (--force X, N, or --command)"
        )
    time_scale = length / u_exec if length and u_exec > 1e-6 else 1.0
    limit = float(lim[surface])
    probe = _probe(rhs, x, n_s, surface, limit, 10 if manoeuvre.kind in VERTICAL else 11)
    logic = _make_logic(manoeuvre, limit, probe, time_scale, dt)
    logic.start(x)
    x_exec = x.copy()
    if logic.code == L.DEPTH_PILOT:
        if keeper is None or keeper.plane != surface:
            keeper = _Keeper(rhs, n_s, (surface, None if keeper is None else keeper.rudder), surface, lim, length, x)
        keeper.trim = float(x[4])
    t_start = n_rows * dt  # the keeper's clock runs on from the approach
    if duration is None:  # the logic's own budget, scaled by the vehicle's L/U
        duration = max(logic.budget(), dt)
    n_max = int(math.floor(duration / dt + 1e-9))
    size = min(n_max + 1, 65536)  # grown by doubling: an automatic budget may be long
    states = np.empty((size, 12))
    defl = np.empty((size, n_s))
    report = max(1, n_max // 100)
    k0 = 0
    while True:
        logic.reserve(states.shape[0])
        k_end = min(states.shape[0], k0 + report) if progress is not None else states.shape[0]
        k, status = loop.fly(x, k0, k_end, n_max, dt, t_start, surface, logic, keeper, sv, states, defl)
        if status < 0:
            raise SimulationError(
                f"the state became non-finite at t = {(k + 1) * dt:.6g} s; check the coefficients and dt"
            )
        if status > 0:
            break
        if progress is not None:
            progress(k_end * dt, duration)
        if k_end == states.shape[0]:
            size = min(2 * size, n_max + 1)
            states = np.concatenate([states, np.empty((size - k_end, 12))])
            defl = np.concatenate([defl, np.empty((size - k_end, n_s))])
        k0 = k_end
    if progress is not None:
        progress(k * dt, k * dt)
    n = k + 1
    time = np.concatenate([t_app[:-1], np.arange(n) * dt])
    all_states = np.concatenate([app[:-1], states[:n]])
    all_states[:, :2] -= x_exec[:2]
    app_defl = used[k_app + 1 - keep : k_app + 1] if keep else np.zeros((0, n_s))
    all_defl = np.concatenate([app_defl, defl[:n]])
    return time, all_states, all_defl, logic, warnings


@dataclass
class _Servo:
    """The surfaces' servo settings (max deflection rad, rate limit rad/s, time constant s) and
    its state: deflections, commands, scratch (rad)."""

    lim: np.ndarray
    rate: np.ndarray
    tc: np.ndarray
    delta: np.ndarray
    cmd: np.ndarray
    new: np.ndarray


class _PythonLoop:
    """The manoeuvre loop in Python around any right-hand side ``f(t, x, τ, δ)``: the laws of
    :mod:`hydrokit.manoeuvre.laws` called as Python, RK4 by
    :func:`hydrokit.simulate.integrators.rk4_step` (the compiled loop,
    :mod:`hydrokit.manoeuvre.compiled`, wires the same laws). Both methods advance ``x``
    in place and return (last step index, status: 1 done, 0 not yet, −1 non-finite)."""

    def __init__(
        self, f: Dynamics, tau: Any, tau_of: Callable[[np.ndarray], np.ndarray], servo_step: Servo, rhs: Rhs
    ) -> None:
        self.f, self.tau_of, self.servo_step, self.rhs = f, tau_of, servo_step, rhs
        self.begin_step = getattr(tau, "begin_step", None)  # a ThrusterDrive: rotor lag, step by step

    def _step(self, t: float, x: np.ndarray, dt: float, delta: np.ndarray) -> bool:
        from hydrokit.simulate.integrators import rk4_step

        if self.begin_step is not None:  # the thrusters' inputs at every stage, at its rotor state
            self.begin_step(t, dt)
            rhs = self.rhs
            y = rk4_step(lambda s, y, u: rhs(s, y, u, s - t), t, x, dt, u=delta)
        else:  # a force held over the step (zero-order hold)
            f, tau = self.f, self.tau_of(x)
            y = rk4_step(lambda s, y, u: f(s, y, tau, u), t, x, dt, u=delta)
        x[:] = y
        return bool(np.all(np.isfinite(y)))

    def approach(
        self,
        x: np.ndarray,
        n_app: int,
        window: int,
        dt: float,
        keeper: Any,
        sv: _Servo,
        rows: np.ndarray,
        used: np.ndarray,
    ) -> tuple[int, int]:
        for k in range(n_app):
            if keeper is not None:
                keeper.command(k * dt, x, dt, sv.cmd, True)
            self.servo_step(sv.delta, sv.cmd, dt, sv.lim, sv.rate, sv.tc, sv.new)
            sv.delta[:] = sv.new
            used[k] = sv.delta
            if not self._step(k * dt, x, dt, sv.delta):
                return k, -1
            rows[k + 1] = x
            if k >= window and k % window == 0 and L.approach_steady(rows, k + 2, window, x):
                if keeper is None or keeper.settled(x):
                    return k, 1
        return n_app - 1, 0

    def fly(
        self,
        x: np.ndarray,
        k0: int,
        k_end: int,
        n_max: int,
        dt: float,
        t_start: float,
        surface: int,
        logic: _Logic,
        keeper: Any,
        sv: _Servo,
        states: np.ndarray,
        defl: np.ndarray,
    ) -> tuple[int, int]:
        K = keeper.K if keeper is not None else _NO_KEEPER
        P, S, H, R = logic.P, logic.S, logic.H, logic.R
        for k in range(k0, k_end):
            t = k * dt
            if keeper is not None and L.keeper_due(K, t_start + t):
                keeper.tune(t_start + t, x)
            L.manoeuvre_command(P, S, H, R, K, t, x, dt, sv.cmd, surface)
            self.servo_step(sv.delta, sv.cmd, dt, sv.lim, sv.rate, sv.tc, sv.new)
            sv.delta[:] = sv.new
            states[k] = x
            defl[k] = sv.delta
            if S[L.S_DONE] or k == n_max:
                return k, 1
            if not self._step(t, x, dt, sv.delta):
                return k, -1
        return k_end - 1, 0


#: the hold of a manoeuvre flown without one (K_ON = 0)
_NO_KEEPER = np.zeros(L.K_SIZE)


def _probe(rhs: Rhs, x: np.ndarray, n_s: int, surface: int, limit: float, index: int) -> float:
    """∂(angular acceleration at ``index``)/∂δ of the surface in the state ``x``, 1/s² per rad
    (the other surfaces at 0; the thrusters' inputs as they are now)."""
    eps = 0.1 * limit
    d = np.zeros(n_s)
    d[surface] = eps
    return float((rhs(0.0, x, d, None)[index] - rhs(0.0, x, np.zeros(n_s), None)[index]) / eps)


def right_hand_side(f: Dynamics, tau: Any, tau_of: Callable[[np.ndarray], np.ndarray]) -> Rhs:
    """The manoeuvre's right-hand side given the deflections: ``f`` with the force of ``tau``,
    and for a :class:`ThrusterDrive` its whole thrusters' part of the input vector (τ, each
    thrust and rotation rate, :meth:`ThrusterDrive.inputs`), as ``simulate --command`` feeds
    the same ``f`` (:func:`hydrokit.simulate.commands.fly_commands`)."""
    from hydrokit.simulate.commands import driven_rhs

    inputs = getattr(tau, "inputs", None)
    if inputs is None:

        def held(t: float, x: np.ndarray, d: np.ndarray, h: float | None = None) -> np.ndarray:
            return f(t, x, tau_of(x), d)

        return held
    stage: list[float | None] = [None]  # the time into the step of the stage being evaluated
    g = driven_rhs(f, lambda t, x: inputs(t, x, stage[0]), len(tau.thrusters))

    def rhs(t: float, x: np.ndarray, d: np.ndarray, h: float | None = None) -> np.ndarray:
        stage[0] = h
        return g(t, x, d)

    return rhs


def _make_logic(m: Manoeuvre, limit: float, probe: float, scale: float, dt: float = 0.0) -> _Logic:
    return _Logic(m, limit, probe, scale, dt)


# --------------------------------------------------------------------------------------------
# the vehicle-level entry point


def steering_surface(names: tuple[str, ...], kind: str, name: str | None = None) -> int:
    """Index of the surface that steers ``kind``: ``name`` if given, else the one whose name says
    rudder (horizontal manoeuvres) or stern plane / elevator / dive plane (vertical ones)."""
    if not names:
        raise InputError("the vehicle has no control_surfaces; a manoeuvre needs a surface to steer with")
    if name is not None:
        if name not in names:
            raise InputError(f"--surface {name!r}: the vehicle has {', '.join(names)}; expected one of them")
        return names.index(name)
    words = ("stern", "plane", "elevator", "dive") if kind in VERTICAL else ("rudder",)
    hits = [k for k, n in enumerate(names) if any(w in n.lower() for w in words)]
    if len(hits) == 1 or (len(names) == 1 and not hits):
        return hits[0] if hits else 0
    what = "a stern plane" if kind in VERTICAL else "a rudder"
    raise InputError(
        f"cannot tell which surface is {what} among {', '.join(names)}; expected --surface NAME naming one"
    )


def check_vehicle(vehicle: Any, manoeuvre: Manoeuvre) -> None:
    """Refuse, before anything is flown, a manoeuvre the vehicle's model cannot fly: a depth change
    or vertical zigzag of a planar model (``dofs`` without heave and pitch) — InputError."""
    dofs = tuple(vehicle.dofs)
    if manoeuvre.kind in VERTICAL and not (2 in dofs and 4 in dofs):
        kept = ", ".join(DOF_NAMES[k] for k in dofs)
        raise InputError(
            f"{manoeuvre.kind.replace('_', ' ')}: vehicle {vehicle.name!r} is planar (dofs: {kept}); "
            "expected a vehicle with heave and pitch in its dofs"
        )


def check_settings(manoeuvre: Manoeuvre, limit: float, dt: float, duration: float | None) -> None:
    """Refuse, before anything is flown, a step ``dt`` (s), a ``duration`` (s; None: automatic) or
    a deflection beyond the steering surface's ``limit`` (rad) that cannot work — InputError."""
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"dt = {dt} s: expected a finite step > 0 s")
    if duration is not None and not (math.isfinite(duration) and duration >= dt):
        raise InputError(f"duration = {duration} s: expected at least the step dt = {dt:g} s")
    if manoeuvre.deflection is not None and abs(manoeuvre.deflection) > limit * (1 + 1e-9):
        raise InputError(
            f"{manoeuvre.kind}: deflection {math.degrees(manoeuvre.deflection):.4g}°: expected at most the "
            f"surface's max_deflection_deg {math.degrees(limit):.4g}°"
        )


def check_propulsion(force: Any, u0: float) -> None:
    """Refuse a manoeuvre with nothing to drive it ahead: a constant ``force`` (N, N·m) with no
    forward X (X ≤ 0 N), no thruster commands and an initial surge speed ``u0`` ≤ 0 m/s — its
    approach would never gain way and the manoeuvre would idle to its longest budget (InputError)."""
    X = np.asarray(force, float).reshape(-1)[:1]
    if X.size and math.isfinite(float(X[0])) and float(X[0]) <= 0.0 and u0 <= 0.0:
        raise InputError(
            f"manoeuvre: no propulsion (force X = {float(X[0]):g} N, initial surge speed {u0:g} m/s) — expected "
            "--force with a forward X (N) or --command NAME=VALUE for the vehicle's thrusters (rev/s)"
        )


def holding_surfaces(
    f: Dynamics, dofs: tuple[int, ...], n_s: int, kind: str, steering: int, hold: bool | None = None
) -> tuple[int | None, int | None]:
    """(plane, rudder): the surfaces that hold depth and pitch, and heading (None: not held).

    A surface's axis is read from its effect at 1 m/s ahead: it pitches (a stern plane, a
    horizontal hinge) when |∂q̇/∂δ| > |∂ṙ/∂δ|, else it yaws (a rudder). In a horizontal
    manoeuvre the steering surface holds the heading during the approach and the strongest
    pitching surface among the others holds depth and pitch throughout (a 6-DOF vehicle: heave
    and pitch kept); in a vertical one the steering planes hold depth during the approach and
    the strongest yawing surface holds the heading throughout. ``hold`` None or True: on — a
    horizontal manoeuvre's approach is always held straight (the steering surface's heading
    hold, also for a planar ship: one whose rudder at zero turns it would otherwise start its
    manoeuvre from a curve), a vertical one's depth only when a second surface holds the heading
    (or with True); False: off.
    """
    if hold is False:
        return None, None
    x = np.zeros(12)
    x[6] = 1.0
    tau = np.zeros(6)
    base = f(0.0, x, tau, np.zeros(n_s))
    pitch: list[tuple[float, int]] = []
    yaw: list[tuple[float, int]] = []
    for k in range(n_s):
        if k == steering:
            continue
        d = np.zeros(n_s)
        d[k] = 0.01
        dx = np.abs(f(0.0, x, tau, d) - base)
        if dx[10] > dx[11] and 2 in dofs and 4 in dofs:
            pitch.append((float(dx[10]), k))
        elif dx[11] > dx[10] and 5 in dofs:
            yaw.append((float(dx[11]), k))
    if kind in VERTICAL:
        other = max(yaw)[1] if yaw else None
        return (steering, other) if (other is not None or hold) else (None, None)
    other = max(pitch)[1] if pitch else None
    # the steering surface always holds the heading during a horizontal manoeuvre's approach: a
    # trial is approached on a steady straight course, and a vehicle that does not go straight
    # with its rudder at zero (a neutral rudder, a propeller's side force) would enter the
    # manoeuvre already turning and have its advance and transfer measured from a curve
    return other, steering


def run_manoeuvre(
    vehicle: Any,
    manoeuvre: Manoeuvre,
    *,
    surface: str | None = None,
    tau: Any = (0, 0, 0, 0, 0, 0),
    nu0: Any = None,
    eta0: Any = None,
    dt: float = 0.02,
    duration: float | None = None,
    approach: float = 600.0,
    current_ned: Any = None,
    loop: str = "compiled",
    hold: bool | None = None,
    commands: Any = None,
    progress: Callable[[float, float], None] | None = None,
    compiled_loop: bool = True,
) -> ManoeuvreResult:
    """Fly ``manoeuvre`` with ``vehicle`` (module docstring) and measure it.

    Parameters
    ----------
    vehicle : Vehicle — with ``control_surfaces``
    manoeuvre : Manoeuvre — :func:`turning_circle`, :func:`zigzag`, …
    surface : str or None — the steering surface's name (None: the rudder, or the stern plane
        for the vertical manoeuvres, found by name)
    tau : 6 floats (N, N·m) — constant propulsion and other forces (body axes); or
        ``tau(x) → 6 floats``; with ``commands`` it is added to the thrusters' force (e.g. the
        propeller's torque K)
    nu0 : 6 floats — initial velocity u, v, w (m/s), p, q, r (rad/s) of the approach (default 0)
    eta0 : 6 floats — initial pose x, y, z (m), φ, θ, ψ (rad); ψ is the original course
    dt : float — step, s; duration : float or None — longest manoeuvre after the execute, s
        (None: scaled by the vehicle's L/U, :func:`fly_manoeuvre`; it ends as soon as measured)
    approach : float — longest straight approach, s
    current_ned : None or 3 floats — ocean current, m/s (NED)
    loop : "compiled" (the numba right-hand side) or "python" (the numpy one)
    hold : bool or None — hold depth and pitch with the stern planes in the horizontal
        manoeuvres (heading with the rudder in the vertical ones), during the approach and the
        manoeuvre, as AUV trials are run; the steering surface holds its axis during the
        approach. None: on for a vehicle that has such a second surface (:func:`holding_surfaces`)
    commands : None or {thruster name: command} — propulsion by the vehicle's ``thrusters:``
        (:class:`ThrusterDrive`): each command in its thruster's unit, rev/s for a propeller, the
        table's unit for a table curve, N for an ideal thruster; thrusters not named get 0. The
        rotors spin up from rest with their lag during the approach and the commands are held
        through the manoeuvre; the thrust follows each thruster's advance speed step by step
    progress : callable(simulated seconds, longest seconds) or None
    compiled_loop : bool — with ``loop="compiled"`` and a constant ``tau``: the whole manoeuvre
        loop (logic, hold, servo, thruster drive, RK4) compiled
        (:mod:`hydrokit.manoeuvre.compiled`, about 50× faster); False: the same laws in
        the Python loop around the compiled right-hand side (the reference the compiled loop is
        tested against). A ``tau(x)``, and ``commands`` with a table-curve thruster or in a
        current, fly in the Python loop.

    Returns
    -------
    ManoeuvreResult — ``problem`` says what was not reached (e.g. a heading of 90°), with the
    metrics that need it set to None; the record is complete either way.
    """
    names = tuple(vehicle.surfaces.names)
    check_vehicle(vehicle, manoeuvre)
    idx = steering_surface(names, manoeuvre.kind, surface)
    check_settings(manoeuvre, float(vehicle.surfaces.max_deflection[idx]), dt, duration)
    x0 = np.zeros(12)
    for part, a in ((slice(0, 6), eta0), (slice(6, 12), nu0)):
        if a is not None:
            v = np.asarray(a, float)
            if v.shape != (6,) or not np.all(np.isfinite(v)):
                raise InputError(
                    f"initial {'pose' if part.start == 0 else 'velocity'} {v.tolist()}: expected 6 finite numbers"
                )
            x0[part] = v
    drive: ThrusterDrive | None = None
    notes: list[str] = []
    if commands is not None:
        command = thruster_commands(vehicle, commands)
        force = np.asarray(tau, float) if not callable(tau) else None
        if force is None or force.shape != (6,) or not np.all(np.isfinite(force)):
            raise InputError(f"force {short_repr(tau)} with commands: expected 6 finite numbers (N, N·m)")
        drive = ThrusterDrive(vehicle.thrusters, command, force, current_ned)
        notes = list(vehicle.thrusters.notes)
    if loop not in ("compiled", "python"):
        raise InputError(f"loop = {loop!r}: expected compiled or python")
    if not callable(tau):  # every setting is checked before the dynamics are built
        tau_c = np.asarray(tau, float)
        if tau_c.shape != (6,) or not np.all(np.isfinite(tau_c)):
            raise InputError(f"force {short_repr(tau)}: expected 6 finite numbers (N, N·m)")
        if commands is None:
            check_propulsion(tau_c, float(x0[6]))
    if loop == "compiled":
        from hydrokit.simulate.compiled import make_dynamics

        f = make_dynamics(vehicle, current_ned)
    else:
        from hydrokit.model.dynamics import vehicle_dynamics

        f = vehicle_dynamics(vehicle, current_ned)
    engine = None
    if loop == "compiled" and not callable(tau) and compiled_loop:
        from hydrokit.manoeuvre.compiled import Engine, drive_compiles

        if drive is None:
            engine = Engine(vehicle, tau, current_ned)
        elif drive_compiles(drive):
            engine = Engine(vehicle, tau, current_ned, drive=drive)
    s = vehicle.surfaces
    held = holding_surfaces(f, tuple(vehicle.dofs), len(names), manoeuvre.kind, idx, hold)
    time, states, defl, logic, warnings = fly_manoeuvre(
        f,
        manoeuvre,
        idx,
        (s.max_deflection, s.rate_limit, s.time_constant),
        tau=tau if drive is None else drive,
        x0=x0,
        dt=dt,
        duration=duration,
        approach=approach,
        length=vehicle.reference_length,
        hold=held,
        progress=progress,
        engine=engine,
    )
    res = measure(
        manoeuvre,
        time,
        states,
        defl,
        logic,
        vehicle=vehicle.name,
        surface_names=names,
        surface=names[idx],
        reference_length=vehicle.reference_length,
        planar=bool(vehicle.planar),
        warnings=[*vehicle.warnings, *notes, *warnings],
        duration=duration,
        hold=_hold_names(held, idx, names),
    )
    if drive is not None:
        res.propulsion = _propulsion(drive, time, states)
    return res


def _propulsion(drive: ThrusterDrive, time: np.ndarray, states: np.ndarray) -> dict[str, Any]:
    """manoeuvre.json's ``propulsion``: the commands and each thruster's thrust (N) at the execute
    and at the end, at the rotor state reached (the commands, once the rotors have spun up)."""
    from hydrokit.simulate.mission import COMMAND_UNITS

    ts = drive.thrusters
    k0 = int(np.searchsorted(time, 0.0))
    names = ts.names
    return {
        "commands": dict(zip(names, drive.target.tolist())),
        "command_units": {n: COMMAND_UNITS[t.model] for n, t in zip(names, ts.thrusters)},
        "force": drive.force.tolist(),
        "thrust_at_execute": dict(zip(names, drive.thrust(states[k0]).tolist())),
        "thrust_at_end": dict(zip(names, drive.thrust(states[-1]).tolist())),
    }


def _hold_names(held: tuple[int | None, int | None], steering: int, names: tuple[str, ...]) -> dict[str, str]:
    out = {}
    for what, k in zip(("depth", "heading"), held):
        if k is not None:
            out[what] = names[k] + (" (approach)" if k == steering else "")
    return out
