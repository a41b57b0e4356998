"""Virtual free-running runs of a planar rudder-steered ship (surge, sway, yaw) for system
identification (issue #48): the propeller turns at a constant speed, the rudder is held at
random angles for random times (a zigzag-like schedule that does not look at the heading, so a
course-unstable hull keeps turning until the rudder reverses), the truth is integrated on the
compiled RK4 at a step finer than any fit's, and position, heading, velocities and yaw rate
are logged with Gaussian noise.

The truth is flown by identification's own simulation (:func:`hydrokit.sysid.model.simulate_run`,
the model ``simulate`` and ``manoeuvre`` fly): the propeller's thrust at every RK4 stage's true
advance speed. :func:`zigzag_runs` flies zigzag trials of a ship (issue #56), its helm reversing
the rudder on the heading.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.model.thrusters import PropellerCurve
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.model import CHANNELS, prepare_run, simulate_run, stack_packs

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
    th = truth.thrusters
    if th is None or not truth.surfaces.names:
        raise InputError(f"vehicle {truth.name!r}: expected a propeller and a rudder for ship runs")
    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / rate), 9)
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
        states = _true_states(truth, packs, f"run{k + 1}", time, commands, deflections, x0, dt)
        logged = _logged(states, time, rng, noise)
        out.append(ShipRun(f"run{k + 1}", time, logged, commands, deflections, states))
    return out


def _true_states(
    truth: Vehicle,
    packs: Mapping[str, Any],
    name: str,
    time: np.ndarray,
    commands: Mapping[str, np.ndarray],
    deflections: Mapping[str, np.ndarray],
    x0: np.ndarray,
    dt: float,
) -> np.ndarray:
    """The true states (n, 12) on the rows ``time`` (s) of ``truth`` flown from ``x0`` with the
    held ``commands`` and ``deflections``: identification's simulation
    (:func:`~hydrokit.sysid.model.simulate_run`, the thrust at every stage's true advance speed)
    on the compiled RK4 at ``dt`` (s), read at every row."""
    rows = {c: (time, np.zeros(time.size)) for c in CHANNELS}
    probe = ShipRun(name, time, rows, commands, deflections, np.zeros((time.size, 12)))
    prep = prepare_run(probe, truth.thrusters, dt, surfaces=truth.surfaces.names)
    pred, done = simulate_run(prep, packs, np.asarray(x0, float)[None])
    if done[0] < round((time[-1] - time[0]) / dt) or not np.all(np.isfinite(pred)):
        raise InputError(f"ship run {name}: the truth vehicle diverged at t = {done[0] * dt:.2f} s")
    return pred[0].reshape(len(CHANNELS), time.size).T


def _logged(states: np.ndarray, time: np.ndarray, rng: np.random.Generator, noise: float) -> dict[str, Any]:
    """The channels of :data:`SHIP_NOISE` logged on the rows: true state + Gaussian noise × ``noise``."""
    return {
        c: (time, states[:, CHANNELS.index(c)] + noise * s * rng.standard_normal(time.size))
        for c, s in SHIP_NOISE.items()
    }


#: the hull, rudder and asymmetry terms of :data:`TANKER`, SI (N, N·m per the factors' units; hydrokit's
#: positive rudder turns to port). A least-squares fit of KVLCC2's MMG model (Yasukawa & Yoshimura
#: 2015, J. Mar. Sci. Technol. 20:37, Tables 1–3: the 7 m model's hull with its cubic terms, the rudder
#: in the propeller's race, K_T(J), w_P0 0.40, t_P 0.22) over the states of its own zigzags (those of
#: :data:`ZIGZAGS`) and ±20°, ±35° turns at 11.85 rev/s, to these terms (relative RMS misfit 5 % in X
#: and Y, 12 % in N); then two changes of ours: X_vr (which holds MMG's (m + m_y) v r less the rigid
#: body's m v r) lowered from 2540 to 1100 N·s²/m, so that the 35° turn loses half its speed rather than
#: MMG's 60 %, and the propeller's side moment N_T(prop) from the fit's −0.11 to −0.22 N·m/N, so that
#: the turn to starboard is 9 % wider than to port, as a right-handed single screw makes it (the
#: trials of issue #56; MMG's own asymmetry is its flow-straightening γ_R, 0.395/0.640)
TANKER_TERMS: dict[str, float] = {
    "X_u|u|": -36.0,
    "X_vv": -100.0,
    "X_vr": 1100.0,
    "X_rr": 870.0,
    "X_uu*delta(rudder)^2": -57.4,
    "Y_uv": -541.0,
    "Y_ur": 413.0,
    "Y_v|v|": -1990.0,
    "Y_r|r|": 15200.0,
    "Y_v|r|": 3610.0,
    "Y_uu*delta(rudder)": 82.2,
    "Y_T(prop)*delta(rudder)": 0.408,
    "Y_T(prop)": 0.03,
    "N_uv": -1260.0,
    "N_ur": -3440.0,
    "N_v|v|": 3430.0,
    "N_r|r|": -37000.0,
    "N_v|r|": -11400.0,
    "N_uu*delta(rudder)": -249.0,
    "N_T(prop)*delta(rudder)": -1.96,
    "N_T(prop)": -0.22,
}
#: a KVLCC2-like 7 m free-running model (Yasukawa & Yoshimura 2015, Table 1: L 7 m, B 1.27 m, d 0.46 m,
#: ∇ 3.27 m³, x_G 0.25 m, propeller D 0.216 m at x −3.36 m; m_x', m_y', J_z' 0.022, 0.223, 0.011 of
#: ½ρL²d, ½ρL⁴d; yaw radius of gyration L/4), planar, with :data:`TANKER_TERMS`: course-unstable
#: (an error in the yaw rate doubles in 15 s on a straight course), its ±35° turning circles at
#: 11.8 rev/s have an advance of 2.8–3.0 L, a tactical diameter of 3.2–3.5 L and a steady speed of
#: half the approach's (``bench/zigzag_turns.py`` prints them)
TANKER: dict[str, Any] = {
    "name": "kvlcc2-like",
    "description": "KVLCC2-like 7 m free-running model, derivative terms (sysid.ship.TANKER, issue #56)",
    "fluid": {"density": 1000.0},
    "gravity": 9.81,
    "mass": 3270.0,
    "volume": 3.27,
    "inertia": [527.4, 10014.0, 10014.0],
    "center_of_gravity": [0.25, 0, 0],
    "center_of_buoyancy": [0.25, 0, 0],
    "added_mass": [248.0, 2513.0, 0, 0, 0, 6075.0],
    "linear_damping": [0, 0, 0, 0, 0, 0],
    "quadratic_damping": [0, 0, 0, 0, 0, 0],
    # the derivatives hold the added mass's Munk moment and MMG's (m + m_x) u r, (m + m_y) v r
    "added_mass_coriolis": False,
    "dofs": ["surge", "sway", "yaw"],
    "control_surfaces": [{"name": "rudder", "position": [-3.5, 0, 0], "max_deflection_deg": 35}],
    "thrusters": [
        {
            "name": "prop",
            "position": [-3.36, 0, 0],
            "direction": [1, 0, 0],
            "diameter": 0.216,
            "kt_forward": [-0.1385, -0.2753, 0.2931],
            "wake_fraction": 0.40,
            "thrust_deduction": 0.22,
            "max_rpm": 1200,
            "max_thrust": 400,
            "min_thrust": -400,
        }
    ],
    "service": {"command": {"prop": 11.8}, "speed": 1.168},
    "terms": TANKER_TERMS,
}
#: the free parameters of a fit of :data:`TANKER` from its zigzags: every term
TANKER_FREE: tuple[str, ...] = tuple(f"terms.{t}" for t in TANKER_TERMS)


def tanker_start(seed: int, spread: float = 0.3) -> dict[str, Any]:
    """:data:`TANKER`'s document with each of its terms × (1 ± uniform(spread − 0.1, spread)), the
    sign drawn (``default_rng(seed)``; 0.3: 20–30 % off): the start of a fit of its zigzags."""
    import copy

    rng = np.random.default_rng(seed)
    n = len(TANKER_TERMS)
    factors = 1 + rng.choice([-1.0, 1.0], n) * rng.uniform(max(spread - 0.1, 0.0), spread, n)
    doc = copy.deepcopy(TANKER)
    doc["name"] = "kvlcc2-like-start"
    doc["terms"] = {k: float(v * f) for (k, v), f in zip(TANKER_TERMS.items(), factors)}
    return doc


#: the zigzags of a data set, (rudder angle, heading change that reverses it) in degrees, each
#: flown to starboard and to port: IMO's 10/10 and 20/20 and the large-rudder zigzags with a 5°
#: check that reach the drift and yaw rate of a turn's first quarter
ZIGZAGS: tuple[tuple[float, float], ...] = ((10, 10), (15, 15), (20, 20), (25, 5), (30, 5), (35, 5))
#: the steering gear's rate, deg/s: a full-scale gear's 2.32 °/s Froude-scaled to a 1:46 model
#: (2.32 √46)
RUDDER_RATE_DEG = 15.8
#: the logged heading is the compass smoothed by a centred local quadratic over this long, s (what
#: a basin's processed records hold: a heading smoother than its sensor, not delayed)
HEADING_SMOOTHING = 1.0
#: the straight approach logged before the first execute, s
APPROACH = 5.0


def zigzag_runs(
    truth: Vehicle,
    seed: int,
    zigzags: Sequence[tuple[float, float]] = ZIGZAGS,
    duration: float = 150.0,
    speed: float | None = None,
    u0: float | None = None,
    rate: float = 20.0,
    noise: float = 1.0,
    smoothing: float = HEADING_SMOOTHING,
    rudder_rate: float = RUDDER_RATE_DEG,
    dt: float = 0.0025,
) -> list[ShipRun]:
    """Zigzag trials of the planar ship ``truth``: each of ``zigzags`` to starboard and to port,
    flown as a basin flies them (issue #56).

    The rudder goes to the zigzag's angle after a straight approach of :data:`APPROACH` s and is
    reversed each time the heading has changed by the check angle from the approach's heading
    (IMO MSC.137(76)'s zigzag, continued for the whole run), moving at ``rudder_rate``; the
    logged deflection is the rudder's angle on each row, held to the next. The helm flies the
    truth row by row with the thrust at the state's advance speed; the run's states are then
    integrated again from the logged inputs as :func:`ship_runs` does (the thrust at the true
    advance speed). Position, heading, velocities and yaw rate are logged with
    :data:`SHIP_NOISE` × ``noise``, the heading then smoothed by a centred local quadratic over
    ``smoothing`` s.

    Parameters
    ----------
    truth : Vehicle with one propeller and one control surface — the generating model
    seed : int — one generator for the initial headings and the noise
    zigzags : (angle, check) pairs, degrees — each flown to starboard (first execute to
        starboard: hydrokit's negative rudder), then to port; the runs in that order
    duration : float — length of each run, s
    speed : float or None — propeller speed, rev/s (None: the first thruster's command of the
        vehicle's ``service:`` block)
    u0 : float or None — initial surge speed, m/s (None: the service speed)
    rate : float — sample rate of every channel, Hz
    noise : float — multiplies :data:`SHIP_NOISE` (0: noise-free logs)
    smoothing : float — length of the heading's smoothing window, s (0: the compass as logged)
    rudder_rate : float — the rudder's rate, deg/s
    dt : float — integration step of the truth, s (divides 1/rate)

    Raises
    ------
    InputError
        A vehicle without a thruster or a control surface, no propeller speed (none given and no
        service condition), or a truth that diverged.
    """
    th = truth.thrusters
    if th is None or not truth.surfaces.names:
        raise InputError(f"vehicle {truth.name!r}: expected a propeller and a rudder for zigzag runs")
    service = truth.service
    if speed is None or u0 is None:
        if service is None or not service.command:
            raise InputError(f"vehicle {truth.name!r} has no service: block; expected a propeller speed and u0")
        speed = float(service.command[0][1]) if speed is None else speed
        u0 = float(service.speed) if u0 is None else u0
    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / rate), 9)
    commands = {n: np.full(time.size, float(speed)) for n in th.names}
    out = []
    for angle, check in zigzags:
        for side in (1.0, -1.0):
            name = f"zigzag{angle:g}-{check:g}{'s' if side > 0 else 'p'}"
            x0 = np.zeros(12)
            x0[5] = rng.uniform(-math.pi, math.pi)
            x0[6] = u0
            # the helm flies at 0.01 s at the finest: it only decides when the rudder moves
            helm_dt = max(dt, 0.01) if (1.0 / rate) % max(dt, 0.01) < 1e-9 else dt
            delta = _zigzag_rudder(
                truth, packs, time, commands, x0, side, math.radians(angle), math.radians(check), rudder_rate, helm_dt
            )
            deflections = {truth.surfaces.names[0]: delta, **{s: np.zeros(time.size) for s in truth.surfaces.names[1:]}}
            states = _true_states(truth, packs, name, time, commands, deflections, x0, dt)
            logged = _logged(states, time, rng, noise)
            if smoothing > 0:
                logged["psi"] = (time, _centred_quadratic(logged["psi"][1], max(1, int(round(smoothing * rate)))))
            out.append(ShipRun(name, time, logged, commands, deflections, states))
    return out


def _zigzag_rudder(
    truth: Vehicle,
    packs: Mapping[str, Any],
    time: np.ndarray,
    commands: Mapping[str, np.ndarray],
    x0: np.ndarray,
    side: float,
    angle: float,
    check: float,
    rudder_rate: float,
    dt: float,
) -> np.ndarray:
    """The rudder's angle on each row (rad) of a zigzag ``angle``/``check`` (rad) flown by the
    helm of :func:`zigzag_runs` (``side`` +1: first to starboard), ``truth`` integrated row by
    row from ``x0`` with each row's inputs held: the thrust at the row's true advance speed."""
    from hydrokit.sysid.data import _integrate

    th = truth.thrusters
    assert th is not None
    config = th.configuration_matrix()
    command = np.array([commands[n][0] for n in th.names], dtype=float)
    rates = np.array([c if isinstance(cv, PropellerCurve) else 0.0 for c, cv in zip(command, th.curves)])
    n_surfaces = len(truth.surfaces.names)
    h = float(time[1] - time[0])
    sub = max(1, int(round(h / dt)))
    step = math.radians(rudder_rate) * h
    delta = np.zeros(time.size)
    x, held, wanted = np.asarray(x0, float).copy(), 0.0, 0.0
    for k in range(time.size):
        change = x[5] - x0[5]
        if time[k] >= APPROACH - 1e-9:
            if wanted == 0.0:
                wanted = -side * angle  # hydrokit's negative rudder turns to starboard
            elif wanted < 0 and change >= check:
                wanted = angle
            elif wanted > 0 and change <= -check:
                wanted = -angle
        held += float(np.clip(wanted - held, -step, step))
        delta[k] = held
        if k == time.size - 1:
            break
        thrust = th.thrust(command, th.advance_speed(x[6:12]))
        inputs = np.zeros(n_surfaces)
        inputs[0] = held
        row = np.concatenate([[0.0], config @ thrust, inputs, thrust, rates])[None]
        x = _integrate(packs, x, row, dt, sub)[-1]
    return delta


def _centred_quadratic(y: np.ndarray, width: int) -> np.ndarray:
    """``y`` smoothed by a local quadratic least-squares fit over ``width`` samples centred on each
    (Savitzky & Golay 1964: zero phase, and flat through the slow manoeuvre — a moving average of
    1 s would shrink a zigzag's heading swings by 0.4 %); near the ends the window shrinks to the
    samples there are on both sides."""
    half = width // 2
    out = np.asarray(y, float).copy()
    n = out.size
    for k in range(n):
        m = min(half, k, n - 1 - k)
        if m < 2:
            continue
        j = np.arange(-m, m + 1)
        c = 3.0 * (3 * m * m + 3 * m - 1 - 5 * j * j) / ((2 * m - 1) * (2 * m + 1) * (2 * m + 3))
        out[k] = float(c @ y[k - m : k + m + 1])
    return out


__all__ = [
    "SHIP_NOISE",
    "TANKER",
    "TANKER_FREE",
    "TANKER_TERMS",
    "ZIGZAGS",
    "ShipRun",
    "ship_runs",
    "tanker_start",
    "zigzag_runs",
]
