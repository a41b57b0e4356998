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
from hydrokit.simulate.sysid_model import CHANNELS, force_table, stack_packs, with_values

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
    """One generated dive (satisfies :class:`hydrokit.simulate.sysid_model.RunData`).

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
    from hydrokit.simulate.sysid_model import free_parameters, values_of

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


def excitation(
    vehicle: Vehicle,
    time: np.ndarray,
    seed: int,
    amplitude: float = 0.6,
    dofs: tuple[str, ...] = ("surge", "sway", "heave", "yaw"),
) -> dict[str, np.ndarray]:
    """Thruster commands on the rows ``time`` (s): independent multi-sines in ``dofs``.

    ``amplitude`` (0–1) is the largest fraction of a thruster's thrust limit used.
    """
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
    T = th.configuration_matrix()
    f = tau @ np.linalg.pinv(T).T
    limit = np.minimum(th.f_max, -th.f_min)
    f *= amplitude / np.max(np.abs(f) / limit)
    cmd = np.array([th.command_for_thrust(row) for row in f])
    return {n: cmd[:, i] for i, n in enumerate(th.names)}


def generate_runs(
    truth: Vehicle,
    n_runs: int = 4,
    duration: float = 90.0,
    seed: int = 0,
    amplitude: float = 0.6,
    noise_scale: float = 1.0,
    dt: float = 0.0025,
) -> list[VirtualRun]:
    """Virtual dives of ``truth`` (module docstring).

    Parameters
    ----------
    truth : Vehicle with thrusters — the hidden coefficients
    n_runs : int; duration : float — s per run; seed : int — one generator for everything
    amplitude : float — fraction of the thrust limits used (0–1)
    noise_scale : float — multiplies every sensor σ (0: noise-free logs)
    dt : float — integration step of the truth, s
    """
    from hydrokit.simulate.compiled import rk4_batch

    if not (duration >= 1.0 and n_runs >= 1):
        raise InputError(f"n_runs = {n_runs}, duration = {duration}: expected ≥ 1 run of ≥ 1 s")
    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    runs = []
    for k in range(n_runs):
        time = np.round(np.arange(0.0, duration + 1e-9, 1.0 / ROW_RATE), 6)
        commands = excitation(truth, time, int(rng.integers(2**31)), amplitude)
        probe = VirtualRun(f"dive{k + 1}", time, {}, commands, np.zeros((0, 12)))
        tab = force_table(probe, truth.thrusters, dt)[None]
        n_steps = int(round(duration / dt))
        out = np.empty((1, n_steps + 1, 12))
        done = np.empty(1, dtype=np.int64)
        x0 = np.zeros((1, 12))
        x0[0, 2] = 1.0 + rng.uniform(0, 1)  # start 1–2 m deep
        x0[0, 5] = rng.uniform(-np.pi, np.pi)
        args = (packs[k] for k in ("Minv", "Mc", "DL", "DQ", "scal", "t_dof", "t_coef", "t_kind", "t_idx"))
        rk4_batch(x0, dt, n_steps, 1, False, np.ascontiguousarray(tab), np.zeros((1, 4)), *args, out, done)  # type: ignore[call-arg]
        if done[0] < n_steps:
            raise InputError(
                f"dive {k + 1}: the truth vehicle diverged at t = {done[0] * dt:.2f} s; lower the amplitude"
            )
        idx = np.round(time / dt).astype(int)
        states = out[0, idx]
        channels = {}
        for c, (rate, sigma) in SENSORS.items():
            every = int(round(ROW_RATE / rate))
            rows = np.arange(0, time.size, every)
            y = states[rows, CHANNELS.index(c)] + noise_scale * sigma * rng.standard_normal(rows.size)
            channels[c] = (time[rows], y)
        runs.append(VirtualRun(f"dive{k + 1}", time, channels, commands, states))
    return runs
