"""Feedback controllers: PID and S-plane per axis, and the speed/depth/heading autopilot.

Controllers hold *settings* only. Their memory (integral, last measurement) lives in a small
frozen state object that is passed in and returned, so a run is repeatable and two runs never
share state::

    pid = PID(kp=200.0, ki=10.0, kd=50.0, output_min=-100, output_max=100)
    s = pid.initial_state()
    force, s = pid.update(s, measurement=z, setpoint=z_d, dt=0.05, rate=z_dot)

Sign convention (LI2021 §1.4, SPEC §5): the error is *measurement − set-point*
(e = u − u_d, z − z_d, ψ − ψ_d wrapped to ±π) and the output pushes against it:
PID ``P = −k_p e − k_i ∫e dt − k_d ė``; S-plane ``P = −K (2 / (1 + exp(−k1 e − k2 ė)) − 1)``.
ė is the rate of the *measurement* (derivative on measurement: no kick when the set-point
jumps, and it is what the vehicle's sensors give).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

# wrap_angle is defined once, in core; it stays importable from here (plot/ and simulate/ use it)
from hydrokit.core.kinematics import wrap_angle
from hydrokit.core.validate import quantity
from hydrokit.errors import InputError

Array = NDArray[np.float64]


@dataclass(frozen=True)
class AxisState:
    """Memory of one axis controller.

    Attributes
    ----------
    integral : float — ∫e dt, error unit × s
    previous : float or None — last measurement (for ė when no rate is given)
    """

    integral: float = 0.0
    previous: float | None = None


class AxisController(Protocol):
    """What the autopilot needs from a single-axis controller."""

    def initial_state(self) -> AxisState: ...

    def update(
        self,
        state: AxisState,
        measurement: float,
        setpoint: float,
        dt: float,
        rate: float | None = None,
    ) -> tuple[float, AxisState]: ...


def _error_and_rate(
    state: AxisState, measurement: float, setpoint: float, dt: float, rate: float | None, angle: bool
) -> tuple[float, float]:
    previous = state.previous
    return error_and_rate(
        measurement,
        setpoint,
        angle,
        0.0 if rate is None else float(rate),
        rate is not None,
        0.0 if previous is None else previous,
        previous is not None,
        dt,
    )


def error_and_rate(measurement, setpoint, angle, rate, has_rate, previous, has_previous, dt):  # noqa: ANN001, ANN201
    """Error and its rate for one axis loop, on plain floats: e = y − y_d (wrapped to ±π for an
    ``angle``, rad), and ė = the measured ``rate`` when ``has_rate``, else the finite difference
    (y − y_prev)/dt of the ``previous`` measurement (wrapped for an angle; 0 without one, or when
    dt ≤ 0). Units: the axis unit (m/s, m, rad) and per s; dt in s. Written once: the controllers
    call it as Python, the compiled closed loop compiles it (``compile_law``)."""
    e = measurement - setpoint
    if angle:
        e = wrap_angle(e)
    if not has_rate:
        if not has_previous or dt <= 0:
            rate = 0.0
        else:
            d = measurement - previous
            rate = (wrap_angle(d) if angle else d) / dt
    return e, rate


@dataclass(frozen=True)
class PID:
    """PID with derivative on measurement, output limits and anti-windup.

    Parameters
    ----------
    kp : float — proportional gain, output unit per error unit (e.g. N per m/s)
    ki : float — integral gain, output unit per (error unit · s)
    kd : float — derivative gain, output unit per (error unit / s)
    output_min, output_max : float — output limits, output unit (N or N·m)
    angle : bool — the measured quantity is an angle (rad): errors wrapped to ±π

    Notes
    -----
    ``P = −k_p e − k_i I − k_d ẏ`` with e = y − y_d (SPEC §5). Anti-windup by clamping:
    while the error drives the output into a limit, the integral advances at most to the
    value that puts the output exactly at that limit (and never further); in addition
    |k_i I| is bounded by the larger output limit, so the integral alone can never demand
    more than the actuator gives.
    """

    kp: float
    ki: float = 0.0
    kd: float = 0.0
    output_min: float = -math.inf
    output_max: float = math.inf
    angle: bool = False

    def __post_init__(self) -> None:
        for name in ("kp", "ki", "kd"):
            object.__setattr__(self, name, quantity(getattr(self, name), f"PID {name}", nonneg=True))
        # ±∞ = no limit (the defaults)
        lo = quantity(self.output_min, "PID output_min", allow_inf=True)
        hi = quantity(self.output_max, "PID output_max", allow_inf=True)
        if not lo < hi:
            raise InputError(f"PID output limits [{lo}, {hi}]: expected output_min < output_max")
        object.__setattr__(self, "output_min", lo)
        object.__setattr__(self, "output_max", hi)

    def initial_state(self) -> AxisState:
        """A fresh state: zero integral, no previous measurement."""
        return AxisState()

    def update(
        self,
        state: AxisState,
        measurement: float,
        setpoint: float,
        dt: float,
        rate: float | None = None,
    ) -> tuple[float, AxisState]:
        """One control step.

        Parameters
        ----------
        state : AxisState — from :meth:`initial_state` or the previous call
        measurement, setpoint : float — y and y_d, in the axis unit (m/s, m, rad)
        dt : float — time since the previous call, s
        rate : float or None — measured ẏ (axis unit per s); None = finite difference

        Returns
        -------
        output : float — saturated controller output (N or N·m)
        state : AxisState — the new state
        """
        e, rate = _error_and_rate(state, measurement, setpoint, dt, rate, self.angle)
        out, integral = pid_law(
            self.kp, self.ki, self.kd, self.output_min, self.output_max, state.integral, e, rate, dt
        )
        return out, AxisState(integral=integral, previous=float(measurement))


def pid_law(kp, ki, kd, output_min, output_max, integral0, e, rate, dt):  # noqa: ANN001, ANN201
    """One step of :class:`PID` on plain floats: (output, new integral) from the gains, the output
    limits, the integral ∫e dt so far, the error e = y − y_d (already wrapped for an angle), the
    measured rate ẏ and the step ``dt`` (s). The law of :meth:`PID.update` (its Notes), written
    once: the manoeuvre hold calls it as Python and compiles it (``compile_law``)."""
    integral = integral0 + e * dt
    if ki > 0:
        bound = max(abs(output_min), abs(output_max)) / ki
        integral = min(max(integral, -bound), bound)
    pd = -kp * e - kd * rate
    raw = pd - ki * integral
    if ki > 0 and raw > output_max and e < 0:
        # integrate only up to the value that puts the output exactly at the limit
        at_limit = (pd - output_max) / ki
        integral = max(integral, min(integral0, at_limit))
    elif ki > 0 and raw < output_min and e > 0:
        at_limit = (pd - output_min) / ki
        integral = min(integral, max(integral0, at_limit))
    raw = pd - ki * integral
    out = min(max(raw, output_min), output_max)
    return out, integral


@dataclass(frozen=True)
class SPlane:
    """S-plane controller (LI2021 §1.4, SPEC §5).

    Parameters
    ----------
    k1 : float — error gain, 1 per error unit (e.g. 1/m)
    k2 : float — error-rate gain, s per error unit
    scale : float — output magnitude K (actuator range), N or N·m
    angle : bool — the measured quantity is an angle (rad): errors wrapped to ±π

    Notes
    -----
    ``u = 2 / (1 + exp(−k1 e − k2 ė)) − 1`` lies in (−1, 1), is odd (u(−x) = −u(x)) and
    equals tanh((k1 e + k2 ė)/2); the output is ``P = −K u``. LI2021 prints the formula with
    the parenthesis closing after the ``− 1`` (``2/(1 + exp(…) − 1)``), which is unbounded
    and singular at zero error; the bracketing above is the one that gives the stated
    (−1, 1) range.
    """

    k1: float
    k2: float
    scale: float
    angle: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "k1", quantity(self.k1, "S-plane k1", nonneg=True))
        object.__setattr__(self, "k2", quantity(self.k2, "S-plane k2", nonneg=True))
        object.__setattr__(self, "scale", quantity(self.scale, "S-plane scale", positive=True))

    @staticmethod
    def surface(e: ArrayLike, e_rate: ArrayLike, k1: float, k2: float) -> Array:
        """The S-surface ``2/(1 + exp(−k1 e − k2 ė)) − 1`` (–), in (−1, 1)."""
        x = k1 * np.asarray(e, dtype=float) + k2 * np.asarray(e_rate, dtype=float)
        return np.tanh(0.5 * x)  # same function, without overflow for large |x|

    def initial_state(self) -> AxisState:
        """A fresh state (no previous measurement)."""
        return AxisState()

    def update(
        self,
        state: AxisState,
        measurement: float,
        setpoint: float,
        dt: float,
        rate: float | None = None,
    ) -> tuple[float, AxisState]:
        """One control step; arguments and returns as :meth:`PID.update`."""
        e, rate = _error_and_rate(state, measurement, setpoint, dt, rate, self.angle)
        out = splane_law(self.k1, self.k2, self.scale, e, rate)
        return out, AxisState(integral=state.integral, previous=float(measurement))


def splane_law(k1, k2, scale, e, rate):  # noqa: ANN001, ANN201
    """One step of :class:`SPlane` on plain floats: the output ``−scale · tanh((k1 e + k2 ė)/2)``
    (N or N·m, the S-surface :meth:`SPlane.surface` without overflow) from the gains k1 (1 per
    error unit), k2 (s per error unit), the error e = y − y_d (already wrapped for an angle) and
    its rate ė. Written once: :meth:`SPlane.update` calls it as Python, the compiled closed loop
    compiles it (``compile_law``)."""
    # numpy's tanh, as SPlane.surface: the step and the array formula agree to the last bit
    return -scale * float(np.tanh(0.5 * (k1 * e + k2 * rate)))


def depth_to_pitch(z, z_d, gain, max_pitch):  # noqa: ANN001, ANN201
    """Pitch set-point θ_d (rad) of a vehicle that dives with its stern planes (issue #45):
    θ_d = clip(gain · (z − z_d), ±max_pitch), ``gain`` in rad/m, depths z, z_d in m (NED, down
    positive), ``max_pitch`` in rad — too shallow (z < z_d) gives nose down (θ_d < 0), the outer
    loop of the usual depth autopilot of a torpedo AUV (Fossen 2011 §13.1, depth via pitch).
    Plain floats: the Python autopilot calls it and the compiled loop compiles it."""
    th = gain * (z - z_d)
    if th > max_pitch:
        return max_pitch
    if th < -max_pitch:
        return -max_pitch
    return th


@dataclass(frozen=True)
class Reference:
    """Set-points for the autopilot.

    Attributes
    ----------
    speed : float — surge speed u_d, m/s
    depth : float — depth z_d (NED, down positive), m
    heading : float — heading ψ_d, rad
    roll, pitch : float — φ_d, θ_d for the optional hold loops, rad
    """

    speed: float
    depth: float
    heading: float
    roll: float = 0.0
    pitch: float = 0.0


@dataclass(frozen=True)
class AutopilotState:
    """States of the autopilot's loops, in the order speed, depth, heading, roll, pitch."""

    loops: tuple[AxisState, ...] = field(default_factory=tuple)


def euler_rates(eta: ArrayLike, nu: ArrayLike) -> tuple[float, float, float, float]:
    """ż (m/s), φ̇, θ̇, ψ̇ (rad/s) from η and ν (zyx Euler angles, Fossen 2011 eq. 2.29)."""
    _, _, _, phi, theta, _ = np.asarray(eta, dtype=float).tolist()
    u, v, w, p, q, r = np.asarray(nu, dtype=float).tolist()
    return _euler_rates(phi, theta, u, v, w, p, q, r)


def _euler_rates(
    phi: float, theta: float, u: float, v: float, w: float, p: float, q: float, r: float
) -> tuple[float, float, float, float]:
    cphi, sphi = math.cos(phi), math.sin(phi)
    cth, sth = math.cos(theta), math.sin(theta)
    zdot = -sth * u + cth * sphi * v + cth * cphi * w
    cth = cth if abs(cth) > 1e-9 else math.copysign(1e-9, cth)
    phidot = p + (sphi * q + cphi * r) * sth / cth
    thetadot = cphi * q - sphi * r
    psidot = (sphi * q + cphi * r) / cth
    return zdot, phidot, thetadot, psidot


@dataclass(frozen=True)
class Autopilot:
    """Speed, depth and heading loops (+ optional roll and pitch hold) → demanded τ.

    Parameters
    ----------
    speed : AxisController — surge speed loop, output X in N
    depth : AxisController — depth loop, output Z in N
    heading : AxisController — heading loop (angle=True), output N in N·m
    roll, pitch : AxisController or None — optional hold loops, outputs K, M in N·m
    depth_pitch : (gain rad/m, max pitch rad) or None — depth through pitch: the pitch loop's
        set-point becomes :func:`depth_to_pitch` of the depth error (the stern planes of a torpedo
        AUV then hold depth); needs a ``pitch`` loop

    Notes
    -----
    τ = [P_speed, 0, P_depth, P_roll, P_pitch, P_heading] as LI2021 §1.4 (roll and pitch
    zero without the hold loops). Rates: ż and ψ̇ (and φ̇, θ̇) from the Euler kinematics;
    the speed loop differentiates u itself.
    """

    speed: AxisController
    depth: AxisController
    heading: AxisController
    roll: AxisController | None = None
    pitch: AxisController | None = None
    depth_pitch: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        if self.depth_pitch is not None and self.pitch is None:
            raise InputError("depth_pitch: depth through pitch needs a pitch loop; expected pitch gains too")

    def _loops(self) -> list[AxisController | None]:
        return [self.speed, self.depth, self.heading, self.roll, self.pitch]

    def initial_state(self) -> AutopilotState:
        """Fresh states for every loop."""
        return AutopilotState(tuple(c.initial_state() if c is not None else AxisState() for c in self._loops()))

    def update(
        self, state: AutopilotState, reference: Reference, eta: ArrayLike, nu: ArrayLike, dt: float
    ) -> tuple[Array, AutopilotState]:
        """Demanded τ (N, N·m) for the measured η, ν and the set-points; and the new state.

        ``dt`` is the control period, s.
        """
        # plain floats: the same values as the array elements, without numpy scalar overhead
        _, _, z, phi, theta, psi = np.asarray(eta, dtype=float).tolist()
        u, v, w, p, q, r = np.asarray(nu, dtype=float).tolist()
        zdot, phidot, thetadot, psidot = _euler_rates(phi, theta, u, v, w, p, q, r)
        s = state.loops or self.initial_state().loops
        tau = [0.0] * 6
        new = list(s)
        tau[0], new[0] = self.speed.update(s[0], u, reference.speed, dt, None)
        tau[2], new[1] = self.depth.update(s[1], z, reference.depth, dt, zdot)
        tau[5], new[2] = self.heading.update(s[2], psi, reference.heading, dt, psidot)
        if self.roll is not None:
            tau[3], new[3] = self.roll.update(s[3], phi, reference.roll, dt, phidot)
        if self.pitch is not None:
            theta_d = reference.pitch
            if self.depth_pitch is not None:
                theta_d = depth_to_pitch(z, reference.depth, self.depth_pitch[0], self.depth_pitch[1])
            tau[4], new[4] = self.pitch.update(s[4], theta, theta_d, dt, thetadot)
        return np.array(tau, dtype=float), AutopilotState(tuple(new))
