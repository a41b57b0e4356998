"""Virtual rig: simulated launches with a sensor model (SPEC §1.5).

A virtual launch looks like a real record: the body is held still at the launch displacement
for ``hold_time`` seconds, released, and recorded for ``duration`` seconds by a sensor that
samples at ``sample_rate``, adds white noise and quantises to its resolution.

Effects the estimators do not model, so that virtual data are honest test material (issue:
"virtual data must be honest"): a first-order sensor lag (``lag``), an encoder whose zero
falls at a random place on its grid in every launch (``random_zero``), a hand release that
misses the nominal amplitude and gives the body a small push (:func:`simulate_launch`'s
``amplitude_jitter`` and ``release_rate_std``). Each launch draws its own noise from ``rng``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.rig_model import rig_constants, simulate_normalised
from hydrokit.identify.types import Launch, Rig


@dataclass(frozen=True)
class SensorModel:
    """A displacement or angle sensor.

    Parameters
    ----------
    sample_rate : float — samples per second, Hz (default 100)
    noise_std : float — standard deviation of white noise, m (spring) or rad
    resolution : float — quantisation step, m or rad (0 = none)
    hold_time : float — still record before the release, s (default 0.5, as for imu, encoder and camera)
    name : str — description for reports
    lag : float — first-order sensor time constant, s (0 = none; an IMU filter or a
        camera's exposure delays the recorded signal, which no estimator models)
    random_zero : bool — the quantisation grid has a random offset in each launch (an
        encoder's zero is wherever counting started)
    """

    sample_rate: float = 100.0
    noise_std: float = 0.0
    resolution: float = 0.0
    hold_time: float = 0.5
    name: str = "ideal sensor"
    lag: float = 0.0
    random_zero: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.sample_rate) and self.sample_rate > 0):
            raise InputError(f"sample_rate = {self.sample_rate}: expected a positive number (Hz)")
        for name in ("noise_std", "resolution", "hold_time", "lag"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise InputError(f"sensor {name} = {v}: expected a finite number ≥ 0")

    @classmethod
    def imu(cls, sample_rate: float = 100.0, noise_deg: float = 0.05, hold_time: float = 0.5) -> SensorModel:
        """An IMU angle sensor (CELY2019 pendulum: 100 Hz); noise given in degrees, stored in rad."""
        return cls(
            sample_rate, math.radians(noise_deg), 0.0, hold_time, f"IMU {sample_rate:g} Hz, {noise_deg:g}° noise"
        )

    @classmethod
    def encoder(cls, counts_per_mm: float = 2.45, sample_rate: float = 100.0, hold_time: float = 0.5) -> SensorModel:
        """A linear encoder (CELY2019 spring rig: 2.45 counts/mm, i.e. 0.408 mm steps)."""
        step = 1e-3 / counts_per_mm
        return cls(
            sample_rate, 0.0, step, hold_time, f"encoder {counts_per_mm:g} counts/mm ({step * 1e3:.3f} mm steps)"
        )

    @classmethod
    def camera(cls, fps: float = 30.0, noise_deg: float = 0.2, hold_time: float = 0.5) -> SensorModel:
        """A video camera tracking the rod angle (ENG2009: 30 fps)."""
        return cls(fps, math.radians(noise_deg), 0.0, hold_time, f"camera {fps:g} fps, {noise_deg:g}° noise")

    def measure(self, y: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Lag, noise and quantisation applied to the true signal ``y`` (m or rad, sampled at
        ``sample_rate``).

        Notes
        -----
        The lag is the exact discrete first-order filter y_f[k] = y_f[k−1] + a (y[k] − y_f[k−1]),
        a = 1 − exp(−Δt/τ), started at rest on the first sample.
        """
        out = np.asarray(y, float).copy()
        if self.lag > 0 and out.size:
            a = 1.0 - math.exp(-1.0 / (self.sample_rate * self.lag))
            for k in range(1, out.size):
                out[k] = out[k - 1] + a * (y[k] - out[k - 1])
        if self.noise_std > 0:
            out += rng.normal(0.0, self.noise_std, out.shape)
        if self.resolution > 0:
            zero = rng.uniform(-0.5, 0.5) * self.resolution if self.random_zero else 0.0
            out = np.round((out + zero) / self.resolution) * self.resolution - zero
        return out


#: most samples one virtual launch records (hold and run)
MAX_LAUNCH_SAMPLES = 10_000_000


def simulate_launch(
    rig: Rig,
    added_mass: float,
    linear_damping: float,
    quadratic_damping: float,
    amplitude: float,
    duration: float,
    sensor: SensorModel | None = None,
    rng: np.random.Generator | int | None = None,
    file: str = "",
    amplitude_jitter: float = 0.0,
    release_rate_std: float = 0.0,
) -> Launch:
    """One launch as the sensor would record it.

    Parameters
    ----------
    rig : Rig
    added_mass : float — true m_a, kg (kg·m² torsion)
    linear_damping : float — true K_L, N·s/m (N·m·s/rad torsion)
    quadratic_damping : float — true K_Q, N·s²/m² (N·m·s²/rad² torsion)
    amplitude : float — release displacement, m (spring) or rad
    duration : float — recorded time after the release, s
    sensor : SensorModel — default: ideal 100 Hz
    rng : Generator or seed
    file : str — name for messages
    amplitude_jitter : float — relative standard deviation of the actual release displacement
        about ``amplitude`` (a hand release misses the mark), –
    release_rate_std : float — standard deviation of the rate given at the release (a push),
        m/s or rad/s

    Returns
    -------
    Launch with t starting at 0 (hold, then release at ``sensor.hold_time``).
    """
    sensor = sensor or SensorModel()
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    if not (duration > 0 and math.isfinite(duration)):
        raise InputError(f"duration = {duration}: expected a positive time (s)")
    c = rig_constants(rig)
    w2, b, g = c.to_normalised(added_mass, linear_damping, quadratic_damping)
    dt = 1.0 / sensor.sample_rate
    n_hold = int(round(sensor.hold_time * sensor.sample_rate))
    n_run = int(round(duration * sensor.sample_rate)) + 1
    if not 2 <= n_hold + n_run <= MAX_LAUNCH_SAMPLES:
        raise InputError(
            f"sample_rate = {sensor.sample_rate:.4g} Hz over {sensor.hold_time + duration:.4g} s gives "
            f"{n_hold + n_run:.4g} samples; expected 2 to {MAX_LAUNCH_SAMPLES:g} per launch"
        )
    t_run = np.arange(n_run) * dt
    # 8 RK4 steps per sample: truth far more accurate than any sensor
    if not (amplitude_jitter >= 0 and release_rate_std >= 0):
        raise InputError(
            f"amplitude_jitter = {amplitude_jitter}, release_rate_std = {release_rate_std}: expected numbers ≥ 0"
        )
    a0 = float(amplitude) * (1.0 + amplitude_jitter * rng.standard_normal()) if amplitude_jitter else float(amplitude)
    v0 = release_rate_std * rng.standard_normal() if release_rate_std else 0.0
    q, _, _ = simulate_normalised(t_run, w2, b, g, a0, v0, c.sine, 8, restoring=c.restoring)
    y = np.concatenate([np.full(n_hold, a0), q])
    t = np.arange(n_hold + n_run) * dt
    with np.errstate(all="ignore"):  # a non-finite record is refused next, in words
        measured = sensor.measure(y, rng)
    if not (np.all(np.isfinite(measured)) and np.all(np.isfinite(t))):
        raise InputError(
            f"amplitude = {amplitude:.4g}, added_mass = {added_mass:.4g}, linear_damping = {linear_damping:.4g}, "
            f"quadratic_damping = {quadratic_damping:.4g}, sensor noise {sensor.noise_std:.4g}, step "
            f"{sensor.resolution:.4g}: the launch leaves the float range; expected values of a realistic size (SI)"
        )
    return Launch(t=t, y=measured, file=file, notes=(f"virtual rig, {sensor.name}",))
