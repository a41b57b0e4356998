"""Virtual pool dives for system identification: logs of a vehicle with hidden coefficients.

A dive is flown open loop on multi-sine thruster commands (surge, sway, heave and yaw excited
at once with independent random phases, 0.03–0.8 Hz, allocated to the thrusters by the
pseudo-inverse of the configuration matrix so that roll and pitch get no moment, and scaled so
that no thruster exceeds ``amplitude`` of its thrust limit). The commands change at the log
rate (50 Hz) and are held; the vehicle is integrated on the compiled RK4 at a step four times
finer than the one the fit uses, through the same thruster model (rotor lag, curve). Sensors,
as in an ArduSub dive with a DVL:

============== ====== ======================== =========
channels       rate   noise σ (default)        unit
============== ====== ======================== =========
phi, theta     50 Hz  0.005                    rad
psi            50 Hz  0.01 (wrapped to ±π)     rad
p, q, r        50 Hz  0.005                    rad/s
z              10 Hz  0.005                    m
u, v, w        5 Hz   0.01                     m/s
============== ====== ======================== =========

An empty cell in the file means the sensor had no sample at that row.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.model import CHANNELS, force_table, stack_packs, with_values

#: channel → (rate Hz, default noise σ SI)
SENSORS: dict[str, tuple[float, float]] = {
    "phi": (50.0, 0.005),
    "theta": (50.0, 0.005),
    "psi": (50.0, 0.01),
    "p": (50.0, 0.005),
    "q": (50.0, 0.005),
    "r": (50.0, 0.005),
    "z": (10.0, 0.005),
    "u": (5.0, 0.01),
    "v": (5.0, 0.01),
    "w": (5.0, 0.01),
}
#: the log's row rate, Hz (commands change at most this often)
ROW_RATE = 50.0
#: the twelve coefficients hidden by default: added mass, linear and quadratic damping in
#: surge, sway, heave and yaw
HIDDEN = tuple(
    f"{c}.{d}" for d in ("surge", "sway", "heave", "yaw") for c in ("added_mass", "linear_damping", "quadratic_damping")
)
#: a value for a hidden coefficient the base vehicle has as 0 (BlueROV2 has no linear sway or
#: yaw damping): of the size of its neighbours, SI
FILL = {"linear_damping.sway": 12.0, "linear_damping.yaw": 0.6, "linear_damping.roll": 1.0, "linear_damping.pitch": 1.0}


@dataclass(frozen=True)
class VirtualRun:
    """One generated dive (satisfies :class:`hydrokit.sysid.model.RunData`).

    name : str; time : (n,) row times, s; channels : channel → (t, y) samples (SI, psi
    unwrapped); commands : thruster → (n,) commands held per row; truth : (n, 12) true states
    on the rows
    """

    name: str
    time: np.ndarray
    channels: Mapping[str, tuple[np.ndarray, np.ndarray]]
    commands: Mapping[str, np.ndarray]
    truth: np.ndarray
    thrusts: Mapping[str, np.ndarray] = field(default_factory=dict)

    def rows(self) -> dict[str, np.ndarray]:
        """Channel → values on every row, NaN where there is no sample, psi wrapped to ±π."""
        out = {}
        for c, (t, y) in self.channels.items():
            col = np.full(self.time.size, np.nan)
            col[np.searchsorted(self.time, t)] = np.angle(np.exp(1j * y)) if c == "psi" else y
            out[c] = col
        return out


def hidden_vehicle(base: Vehicle, seed: int, spread: float = 0.3, names: tuple[str, ...] = HIDDEN) -> Vehicle:
    """``base`` with the coefficients ``names`` multiplied by factors drawn uniformly in
    [1 − spread, 1 + spread] (one ``default_rng(seed)``); a zero base value is replaced by
    :data:`FILL` first."""
    from hydrokit.sysid.model import free_parameters, values_of

    vehicle, params = free_parameters(base, names, "hidden")
    vals = values_of(vehicle, params)
    vals = np.array([FILL.get(p.name, v) if v == 0 else v for p, v in zip(params, vals)])
    rng = np.random.default_rng(seed)
    return with_values(vehicle, params, vals * rng.uniform(1 - spread, 1 + spread, vals.size))


def _multisine(t: np.ndarray, rng: np.random.Generator, f_lo: float, f_hi: float, n: int = 8) -> np.ndarray:
    f = np.geomspace(f_lo, f_hi, n) * rng.uniform(0.9, 1.1, n)
    phase = rng.uniform(0, 2 * np.pi, n)
    amp = 1.0 / np.sqrt(np.arange(1, n + 1))  # more power at low frequency: speed range for drag
    s = (amp[None, :] * np.sin(2 * np.pi * f[None, :] * t[:, None] + phase[None, :])).sum(axis=1)
    return s / np.max(np.abs(s))


def excitation_thrust(
    vehicle: Vehicle,
    time: np.ndarray,
    seed: int,
    amplitude: float = 0.6,
    dofs: tuple[str, ...] = ("surge", "sway", "heave", "yaw"),
) -> np.ndarray:
    """Thruster forces (n, m) on the rows ``time`` (s), N: independent multi-sines in ``dofs``
    allocated by the pseudo-inverse of the configuration matrix and scaled so that the largest
    |force| / limit is ``amplitude`` (0–1)."""
    from hydrokit.model.allocation import weighted_pinv

    th = vehicle.thrusters
    if th is None:
        raise InputError(f"vehicle {vehicle.name!r} has no thrusters: a dive needs its thruster commands")
    if not 0 < amplitude <= 1:
        raise InputError(f"amplitude = {amplitude}: expected 0 < amplitude ≤ 1 (fraction of the thrust limit)")
    rng = np.random.default_rng(seed)
    tau = np.zeros((time.size, 6))
    for d in dofs:
        # yaw at half weight: a BlueROV2 yaws fast, and a fast spin couples surge and sway
        # through the Coriolis terms (their added masses then move together)
        weight = 0.5 if d == "yaw" else 1.0
        tau[:, DOF_NAMES.index(d)] = weight * rng.uniform(0.6, 1.0) * _multisine(time - time[0], rng, 0.03, 0.8)
    f = tau @ weighted_pinv(th.configuration_matrix()).T
    limit = np.minimum(th.f_max, -th.f_min)
    return f * (amplitude / np.max(np.abs(f) / limit))


def excitation(
    vehicle: Vehicle,
    time: np.ndarray,
    seed: int,
    amplitude: float = 0.6,
    dofs: tuple[str, ...] = ("surge", "sway", "heave", "yaw"),
) -> dict[str, np.ndarray]:
    """Thruster commands on the rows ``time`` (s): independent multi-sines in ``dofs``
    (:func:`excitation_thrust`), in each thruster's command unit.

    ``amplitude`` (0–1) is the largest fraction of a thruster's thrust limit used.
    """
    f = excitation_thrust(vehicle, time, seed, amplitude, dofs)
    th = vehicle.thrusters
    assert th is not None
    cmd = np.array([th.command_for_thrust(row) for row in f])
    return {n: cmd[:, i] for i, n in enumerate(th.names)}


#: the DOFs a closed-loop dive may hold, with the channels of the hold (position, rate)
HOLDS = {"heave": ("z", "w"), "yaw": ("psi", "r")}


@dataclass(frozen=True)
class Hold:
    """A simple depth and/or heading hold flown during a virtual dive (what ArduSub's
    *depth hold* and *stabilise* do): a PD law per held DOF on the latest logged sample of the
    position (z, ψ) and rate (w, r) channels, τ_d = −k_p (y − y_start) − k_d ẏ, with
    k_p = M_dd ω² and k_d = 2 ζ ω M_dd (M the vehicle's rigid-body + added inertia) and y_start
    the first logged sample (where the hold engages), added to
    the pilot's multi-sine, allocated within the thrust limits every log row.

    dofs : held DOFs, some of ``heave``, ``yaw``; bandwidth : ω, rad/s; damping : ζ, –;
    dither : fraction of the open-loop multi-sine kept on the held DOFs (0 = none: the loop
    alone decides the held DOFs' commands), –
    """

    dofs: tuple[str, ...] = ("heave", "yaw")
    bandwidth: float = 1.0
    damping: float = 0.9
    dither: float = 0.0

    def __post_init__(self) -> None:
        bad = [d for d in self.dofs if d not in HOLDS]
        if bad or not self.dofs:
            raise InputError(f"hold dofs {list(self.dofs)}: expected some of {', '.join(HOLDS)}")
        if not (self.bandwidth > 0 and self.damping > 0 and 0 <= self.dither <= 1):
            raise InputError(
                f"hold bandwidth = {self.bandwidth} rad/s, damping = {self.damping}, dither = {self.dither}: expected "
                "bandwidth > 0, damping > 0 and 0 ≤ dither ≤ 1"
            )


def _integrate(packs: Mapping[str, np.ndarray], x0: np.ndarray, table: np.ndarray, dt: float, n: int) -> np.ndarray:
    """The first vehicle of ``packs`` from ``x0`` over ``n`` steps of ``dt`` (s) under the force
    table rows [t, X … N] (t from 0; held inputs as :func:`~hydrokit.sysid.model.force_table`
    writes them) on the compiled RK4: the (n + 1, 12) states; InputError if it diverged."""
    from hydrokit.simulate.compiled import no_drive, rk4_run, vehicle_member
    from hydrokit.sysid.model import held_offset, vehicle_arrays

    out = np.empty((n + 1, 12))
    V = vehicle_member(vehicle_arrays(packs), 0)
    x = np.ascontiguousarray(x0, dtype=float)
    tab = np.ascontiguousarray(table)
    done = rk4_run(x, 0.0, dt, n, 1, False, tab, np.zeros((1, 4)), V, no_drive(), out, held_offset(dt))
    if done < n:
        raise InputError(f"the truth vehicle diverged at t = {done * dt:.2f} s; lower the amplitude")
    return out


def _closed_loop(
    truth: Vehicle,
    time: np.ndarray,
    pilot: np.ndarray,
    x0: np.ndarray,
    hold: Hold,
    noise: Mapping[str, tuple[np.ndarray, np.ndarray]],
    dt: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Fly ``truth`` from ``x0`` with the pilot's generalised force ``pilot`` (n, 6) plus the
    ``hold`` acting on the logged samples (true state + ``noise``: channel → row indices and
    noise values, SI): the
    commands (n, m) on the rows and the true states (n, 12). Each row's force table follows the
    rotor lag exactly from the rotor state at the row (as :func:`force_table` does over a whole
    run), so replaying the commands open loop gives the same states."""
    from hydrokit.model.allocation import Allocator
    from hydrokit.model.control import PID

    th = truth.thrusters
    assert th is not None
    T = th.configuration_matrix()
    alloc = Allocator(T, th.f_min, th.f_max)
    h = float(time[1] - time[0])
    sub = int(round(h / dt))
    if abs(sub * dt - h) > 1e-9 * h:
        raise InputError(f"dt = {dt} s: expected a step dividing the log row period {h:g} s")
    packs = stack_packs([truth])
    M = truth.M
    laws = []
    for d in hold.dofs:
        i = DOF_NAMES.index(d)
        mass = float(M[i, i])
        w = hold.bandwidth
        pid = PID(kp=mass * w * w, kd=2 * hold.damping * w * mass, angle=d == "yaw")
        laws.append((i, pid, *HOLDS[d]))
    nodes = 0.5 * dt * np.arange(2 * sub + 1)
    n = time.size
    cmds = np.empty((n, len(th)))
    states = np.empty((n, 12))
    states[0] = x0
    seen: dict[str, float] = {}
    mem = {i: pid.initial_state() for i, pid, *_ in laws}
    setpoint: dict[int, float] = {}
    c = np.zeros(len(th))
    for k in range(n):
        for ch, (rows, e) in noise.items():
            j = int(np.searchsorted(rows, k))
            if j < rows.size and rows[j] == k:
                seen[ch] = float(states[k, CHANNELS.index(ch)] + e[j])
        tau = pilot[k].copy()
        for i, pid, pos, rate in laws:
            # engaged at the first logged sample (every channel has one on row 0)
            setpoint.setdefault(i, seen.get(pos, float(x0[CHANNELS.index(pos)])))
            out, mem[i] = pid.update(mem[i], seen.get(pos, setpoint[i]), setpoint[i], h, seen.get(rate, 0.0))
            tau[i] += out
        f, _ = alloc(tau)
        cmds[k] = th.command_for_thrust(f)
        if k == 0:
            c = np.clip(cmds[0], th.command_min, th.command_max)
        if k == n - 1:
            break
        lag = th.rotor_step(c[None], cmds[k][None], nodes[:, None])
        table = np.column_stack([nodes, np.array([th.thrust(row) for row in lag]) @ T.T])
        states[k + 1] = _integrate(packs, states[k], table, dt, sub)[-1]
        c = th.rotor_step(c, cmds[k], h)
    return cmds, states


def generate_runs(
    truth: Vehicle,
    n_runs: int = 4,
    duration: float = 90.0,
    seed: int = 0,
    amplitude: float = 0.6,
    noise_scale: float = 1.0,
    dt: float = 0.0025,
    hold: Hold | None = None,
    commands: Mapping[str, np.ndarray] | None = None,
) -> list[VirtualRun]:
    """Virtual dives of ``truth`` (module docstring).

    Parameters
    ----------
    truth : Vehicle with thrusters — the hidden coefficients
    n_runs : int; duration : float — s per run; seed : int — one generator for everything
    amplitude : float — fraction of the thrust limits used (0–1)
    noise_scale : float — multiplies every sensor σ (0: noise-free logs)
    dt : float — integration step of the truth, s
    hold : Hold or None — fly under a depth/heading hold (closed loop: the held DOFs'
        commands then follow the logged state); None: open loop
    commands : thruster → commands on the rows (every 1/50 s from 0, curve unit), e.g. a
        schedule of ``hydrokit sysid plan``: flown open loop in every run instead of the
        random multi-sines (``duration`` is then the schedule's)
    """
    if commands is not None:
        lengths = {np.size(v) for v in commands.values()}
        if len(lengths) != 1 or min(lengths) < 2:
            raise InputError("commands: expected one column of ≥ 2 rows per thruster, all of one length")
        duration = (lengths.pop() - 1) / ROW_RATE
    if not (duration >= 1.0 and n_runs >= 1):
        raise InputError(f"n_runs = {n_runs}, duration = {duration}: expected ≥ 1 run of ≥ 1 s")
    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    th = truth.thrusters
    runs = []
    for k in range(n_runs):
        time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / ROW_RATE), 6)
        sub_seed = int(rng.integers(2**31))
        x0 = np.zeros(12)
        x0[2] = 1.0 + rng.uniform(0, 1)  # start 1–2 m deep
        x0[5] = rng.uniform(-np.pi, np.pi)
        n_steps = int(round(duration / dt))
        if hold is None:
            if commands is None:
                cmd = excitation(truth, time, sub_seed, amplitude)
            else:
                cmd = {n: np.asarray(commands[n], float) for n in th.names}  # type: ignore[union-attr]
            probe = VirtualRun(f"dive{k + 1}", time, {}, cmd, np.zeros((0, 12)))
            try:
                out = _integrate(packs, x0, force_table(probe, th, dt), dt, n_steps)
            except InputError as exc:
                raise InputError(f"dive {k + 1}: {exc}") from None
            states = out[np.round(time / dt).astype(int)]
            channels = {}
            for c, (rate, sigma) in SENSORS.items():
                every = int(round(ROW_RATE / rate))
                rows = np.arange(0, time.size, every)
                y = states[rows, CHANNELS.index(c)] + noise_scale * sigma * rng.standard_normal(rows.size)
                channels[c] = (time[rows], y)
        else:
            assert th is not None
            f = excitation_thrust(truth, time, sub_seed, amplitude)
            pilot = f @ th.configuration_matrix().T
            for d in hold.dofs:
                pilot[:, DOF_NAMES.index(d)] *= hold.dither
            # the sensor noise is drawn first: the autopilot sees the samples that are logged
            noise = {}
            for c, (rate, sigma) in SENSORS.items():
                rows = np.arange(0, time.size, int(round(ROW_RATE / rate)))
                noise[c] = (rows, noise_scale * sigma * rng.standard_normal(rows.size))
            try:
                cmds, states = _closed_loop(truth, time, pilot, x0, hold, noise, dt)
            except InputError as exc:
                raise InputError(f"dive {k + 1}: {exc}") from None
            cmd = {n: cmds[:, i] for i, n in enumerate(th.names)}
            channels = {c: (time[rows], states[rows, CHANNELS.index(c)] + e) for c, (rows, e) in noise.items()}
        runs.append(VirtualRun(f"dive{k + 1}", time, channels, cmd, states))
    return runs
