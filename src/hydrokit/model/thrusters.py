"""Thruster models: pose, thrust curve, rotor dynamics and saturation.

Three thrust models, chosen per thruster by the fields it has:

``propeller``
    Open-water curve (REHMAN eq. 1.12, SPEC §4 and §8):
    ``f = loss · K_T(J) · ρ D⁴ |n| n`` with ``J = V_a / (n D)`` and ``K_T`` a polynomial of
    ``J``; forward (n > 0) and reverse (n < 0) rotation have their own polynomial and
    thrust-loss factor. The command is the propeller speed ``n`` in rev/s.
``table``
    Thrust interpolated in a strictly increasing table of thrust vs command (e.g. the
    BlueROV2 T200 curve F(V) tabulated against the normalised input V). The command has
    the table's unit.
``ideal``
    The command *is* the thrust in N (only limits and rotor lag apply).

All arrays are in file order. SI units: m, N, rev/s, s, kg/m³.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit.errors import InputError

Array = NDArray[np.float64]
ThrustModel = Literal["propeller", "table", "ideal"]

#: Default validity range of an open-water K_T(J) polynomial; outside it the curve is held
#: at its end value (cubic fits diverge for large |J|, which happens as n → 0 with inflow).
DEFAULT_ADVANCE_RATIO_RANGE = (-0.5, 1.0)

#: Iteration cap for inverting a propeller curve: up to 20 regula-falsi (Illinois) steps,
#: then bisection; 2⁻⁶⁰ of the speed range is far below any meaningful rev/s resolution.
#: It usually stops within a few steps, at a thrust error of 1e-12 relative.
_BISECTION_STEPS = 80


def _vec3(value: ArrayLike, what: str) -> tuple[float, float, float]:
    try:
        a = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{what} = {value!r}: expected 3 numbers") from None
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{what} = {value!r}: expected 3 finite numbers")
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True)
class Thruster:
    """One thruster: pose, limits and (optionally) a propeller or tabulated thrust curve.

    Parameters
    ----------
    name : str — unique name (file order is kept everywhere)
    position : 3 floats — r_i, propeller centre in body axes from the body origin, m
    direction : 3 floats — e_i, direction of positive thrust in body axes (normalised here;
        zero length is an error)
    max_thrust : float — largest forward thrust, N (> 0)
    min_thrust : float or None — largest reverse thrust, N (≤ 0); None means −max_thrust
    diameter : float or None — propeller diameter D, m (required by the propeller model;
        optional otherwise, where it only sizes the actuator disk for power estimates)
    kt_forward, kt_reverse : tuple of float or None — K_T(J) polynomial coefficients, highest
        power first (c3, c2, c1, c0 for a cubic), for forward and reverse rotation, –
    thrust_loss_forward, thrust_loss_reverse : float — thrust-loss factors, – (1 = none)
    advance_ratio_range : (float, float) — J range where the K_T polynomial holds, –
    wake_fraction : float — w in V_a = (1 − w) e_i·(v + ω × r_i), –
    max_speed : float or None — propeller speed limit, rev/s (required for ``propeller``)
    time_constant : float — first-order rotor lag τ, s (0 = instantaneous)
    table_command, table_thrust : tuple of float or None — thrust table: command (its own
        unit) and thrust, N; thrust strictly increasing
    """

    name: str
    position: tuple[float, float, float]
    direction: tuple[float, float, float]
    max_thrust: float
    min_thrust: float | None = None
    diameter: float | None = None
    kt_forward: tuple[float, ...] | None = None
    kt_reverse: tuple[float, ...] | None = None
    thrust_loss_forward: float = 1.0
    thrust_loss_reverse: float = 1.0
    advance_ratio_range: tuple[float, float] = DEFAULT_ADVANCE_RATIO_RANGE
    wake_fraction: float = 0.0
    max_speed: float | None = None
    time_constant: float = 0.0
    table_command: tuple[float, ...] | None = None
    table_thrust: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        where = f"thruster '{self.name}'"
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"thruster name {self.name!r}: expected a non-empty string")
        pos = _vec3(self.position, f"{where} position")
        d = np.asarray(_vec3(self.direction, f"{where} direction"))
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            raise InputError(
                f"{where} direction {list(self.direction)} has zero length; "
                "expected a non-zero 3-vector"
            )
        object.__setattr__(self, "position", pos)
        object.__setattr__(self, "direction", tuple(float(x) for x in d / norm))
        fmax = _finite(self.max_thrust, f"{where} max_thrust")
        if fmax <= 0:
            raise InputError(f"{where} max_thrust = {fmax}: expected a positive force in N")
        fmin = -fmax if self.min_thrust is None else _finite(self.min_thrust, f"{where} min_thrust")
        if fmin > 0:
            raise InputError(
                f"{where} min_thrust = {fmin}: expected a reverse thrust ≤ 0 N (negative)"
            )
        object.__setattr__(self, "max_thrust", fmax)
        object.__setattr__(self, "min_thrust", fmin)
        tc = _finite(self.time_constant, f"{where} time_constant")
        if tc < 0:
            raise InputError(f"{where} time_constant = {tc}: expected ≥ 0 s")
        object.__setattr__(self, "time_constant", tc)
        for attr in ("thrust_loss_forward", "thrust_loss_reverse"):
            v = _finite(getattr(self, attr), f"{where} {attr}")
            if v <= 0:
                raise InputError(f"{where} {attr} = {v}: expected a positive factor")
            object.__setattr__(self, attr, v)
        w = _finite(self.wake_fraction, f"{where} wake_fraction")
        if not 0 <= w < 1:
            raise InputError(f"{where} wake_fraction = {w}: expected 0 ≤ w < 1")
        object.__setattr__(self, "wake_fraction", w)
        if self.diameter is not None:
            D = _finite(self.diameter, f"{where} diameter")
            if D <= 0:
                raise InputError(f"{where} diameter = {D}: expected a positive length in m")
            object.__setattr__(self, "diameter", D)
        model = self.model
        if model == "propeller":
            if self.diameter is None:
                raise InputError(f"{where}: a propeller thruster needs its diameter (m)")
            if self.max_speed is None:
                raise InputError(f"{where}: a propeller thruster needs max_rpm (speed limit)")
            ns = _finite(self.max_speed, f"{where} max_speed")
            if ns <= 0:
                raise InputError(f"{where} max_speed = {ns}: expected a positive speed")
            object.__setattr__(self, "max_speed", ns)
            kf = _coeffs(self.kt_forward, f"{where} kt_forward")
            kr = _coeffs(self.kt_reverse, f"{where} kt_reverse") if self.kt_reverse else kf
            object.__setattr__(self, "kt_forward", kf)
            object.__setattr__(self, "kt_reverse", kr)
            if np.polyval(kf, 0.0) <= 0 or np.polyval(kr, 0.0) <= 0:
                raise InputError(f"{where}: K_T(0) must be positive for both rotation senses")
            lo, hi = (float(x) for x in self.advance_ratio_range)
            if not lo <= 0 < hi:
                raise InputError(
                    f"{where} advance_ratio_range = {list(self.advance_ratio_range)}: "
                    "expected [low ≤ 0, high > 0]"
                )
            object.__setattr__(self, "advance_ratio_range", (lo, hi))
        elif model == "table":
            c = _coeffs(self.table_command, f"{where} thrust_table command")
            f = _coeffs(self.table_thrust, f"{where} thrust_table thrust")
            if len(c) != len(f) or len(c) < 2:
                raise InputError(
                    f"{where} thrust_table: command and thrust need the same length ≥ 2, "
                    f"got {len(c)} and {len(f)}"
                )
            if np.any(np.diff(c) <= 0) or np.any(np.diff(f) <= 0):
                raise InputError(
                    f"{where} thrust_table: command and thrust must both be strictly increasing"
                )
            object.__setattr__(self, "table_command", c)
            object.__setattr__(self, "table_thrust", f)

    @property
    def model(self) -> ThrustModel:
        """Which thrust model applies: ``propeller``, ``table`` or ``ideal``."""
        if self.table_command is not None or self.table_thrust is not None:
            return "table"
        if self.kt_forward is not None:
            return "propeller"
        return "ideal"


def _finite(value: object, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise InputError(f"{what} = {value!r}: expected a number")
    v = float(value)
    if not math.isfinite(v):
        raise InputError(f"{what} = {v}: expected a finite number")
    return v


def _coeffs(value: object, what: str) -> tuple[float, ...]:
    if value is None or isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise InputError(f"{what} = {value!r}: expected a list of numbers")
    out = tuple(_finite(v, what) for v in value)  # type: ignore[union-attr]
    if not out:
        raise InputError(f"{what} is empty: expected a list of numbers")
    return out


@dataclass(frozen=True)
class ThrusterSet:
    """All thrusters of a vehicle, with vectorised thrust, inversion and rotor dynamics.

    Parameters
    ----------
    thrusters : sequence of Thruster — in file order; names must be unique
    density : float — water density ρ, kg/m³ (used by the propeller model)
    notes : tuple of str — warnings from reading the layout (e.g. ignored fields)
    """

    thrusters: tuple[Thruster, ...]
    density: float = 1025.0
    notes: tuple[str, ...] = field(default=(), compare=False)
    # derived arrays (not arguments)
    positions: Array = field(init=False, repr=False, compare=False)
    directions: Array = field(init=False, repr=False, compare=False)
    f_max: Array = field(init=False, repr=False, compare=False)
    f_min: Array = field(init=False, repr=False, compare=False)
    time_constants: Array = field(init=False, repr=False, compare=False)
    command_max: Array = field(init=False, repr=False, compare=False)
    command_min: Array = field(init=False, repr=False, compare=False)
    _wake_factor: Array = field(init=False, repr=False, compare=False)
    _moment_arms: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        ths = tuple(self.thrusters)
        if not ths:
            raise InputError("thrusters: the list is empty; expected at least one thruster")
        seen: set[str] = set()
        for th in ths:
            if th.name in seen:
                raise InputError(f"thrusters: duplicate name '{th.name}'; names must be unique")
            seen.add(th.name)
        rho = _finite(self.density, "fluid density")
        if rho <= 0:
            raise InputError(f"fluid density = {rho}: expected a positive value in kg/m³")
        object.__setattr__(self, "thrusters", ths)
        object.__setattr__(self, "density", rho)
        put = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        put("positions", np.array([t.position for t in ths], dtype=float))
        put("directions", np.array([t.direction for t in ths], dtype=float))
        put("time_constants", np.array([t.time_constant for t in ths], dtype=float))
        put("_wake_factor", np.array([1.0 - t.wake_fraction for t in ths]))
        put("_moment_arms", np.cross(self.positions, self.directions))
        cmax, cmin, fmax, fmin = [], [], [], []
        for t in ths:
            if t.model == "propeller":
                ns = float(t.max_speed)  # type: ignore[arg-type]
                cmax.append(ns)
                cmin.append(-ns)
                # thrust limits: the tighter of the rated force and the static thrust at n_max
                f_up = float(self._single_thrust(t, ns, 0.0))
                f_dn = float(self._single_thrust(t, -ns, 0.0))
                fmax.append(min(t.max_thrust, f_up))
                fmin.append(max(float(t.min_thrust), f_dn))  # type: ignore[arg-type]
            elif t.model == "table":
                c, f = t.table_command, t.table_thrust
                assert c is not None and f is not None
                cmax.append(c[-1])
                cmin.append(c[0])
                fmax.append(min(t.max_thrust, f[-1]))
                fmin.append(max(float(t.min_thrust), f[0]))  # type: ignore[arg-type]
            else:
                cmax.append(t.max_thrust)
                cmin.append(float(t.min_thrust))  # type: ignore[arg-type]
                fmax.append(t.max_thrust)
                fmin.append(float(t.min_thrust))  # type: ignore[arg-type]
        put("command_max", np.array(cmax))
        put("command_min", np.array(cmin))
        put("f_max", np.array(fmax))
        put("f_min", np.array(fmin))

    # ------------------------------------------------------------------ description
    @property
    def names(self) -> list[str]:
        """Thruster names in file order."""
        return [t.name for t in self.thrusters]

    def __len__(self) -> int:
        return len(self.thrusters)

    def configuration_matrix(self) -> Array:
        """The 6×m configuration matrix T, column i = [e_i; r_i × e_i] (LI2021 eq. 22–23)."""
        from hydrokit.model.allocation import configuration_matrix

        return configuration_matrix(self.positions, self.directions)

    # ------------------------------------------------------------------ kinematics
    def advance_speed(self, nu: ArrayLike) -> Array:
        """Advance speed of each propeller, m/s.

        ``V_a,i = (1 − w_i) e_i · (v + ω × r_i)`` with ν = [v; ω] the body velocity
        relative to the water (m/s, rad/s).
        """
        nu = np.asarray(nu, dtype=float)
        v, w = nu[:3], nu[3:6]
        # e_i · (v + ω × r_i) = e_i · v + ω · (r_i × e_i)
        return self._wake_factor * (self.directions @ v + self._moment_arms @ w)

    # ------------------------------------------------------------------ thrust curves
    def _single_thrust(self, t: Thruster, n: float, va: float) -> float:
        return float(self._propeller_thrust(t, np.array([n]), np.array([va]))[0])

    def _propeller_thrust(self, t: Thruster, n: Array, va: Array) -> Array:
        D = float(t.diameter)  # type: ignore[arg-type]
        lo, hi = t.advance_ratio_range
        with np.errstate(divide="ignore", invalid="ignore"):
            J = np.where(n != 0.0, va / (n * D), 0.0)
        J = np.clip(J, lo, hi)
        fwd = n >= 0
        kt = np.where(fwd, np.polyval(t.kt_forward, J), np.polyval(t.kt_reverse, J))
        kt = np.maximum(kt, 0.0)  # inflow may cancel thrust, never reverse it
        loss = np.where(fwd, t.thrust_loss_forward, t.thrust_loss_reverse)
        return loss * kt * self.density * D**4 * np.abs(n) * n

    def thrust(self, command: ArrayLike, advance_speed: ArrayLike | None = None) -> Array:
        """Thrust of every thruster for a command vector, N (saturated to the thrust limits).

        Parameters
        ----------
        command : m floats — propeller speed n in rev/s (propeller), table command (table)
            or thrust in N (ideal); clipped to the command limits first
        advance_speed : m floats or None — V_a, m/s (None = 0, bollard pull)

        Notes
        -----
        Propeller: ``f = loss · K_T(J) ρ D⁴ |n| n``, ``J = V_a/(n D)`` (REHMAN eq. 1.12),
        with K_T clamped at ≥ 0 and J to the curve's validity range.
        """
        c = np.clip(np.asarray(command, dtype=float), self.command_min, self.command_max)
        va = np.zeros(len(self)) if advance_speed is None else np.asarray(advance_speed, float)
        out = np.empty(len(self))
        for i, t in enumerate(self.thrusters):
            if t.model == "propeller":
                out[i] = self._propeller_thrust(t, c[i : i + 1], va[i : i + 1])[0]
            elif t.model == "table":
                out[i] = np.interp(c[i], t.table_command, t.table_thrust)  # type: ignore[arg-type]
            else:
                out[i] = c[i]
        return np.clip(out, self.f_min, self.f_max)

    def command_for_thrust(self, thrust: ArrayLike, advance_speed: ArrayLike | None = None) -> Array:
        """Invert the thrust curves: the command giving each demanded thrust.

        Parameters
        ----------
        thrust : m floats — demanded thrust, N (clipped to the limits first)
        advance_speed : m floats or None — V_a, m/s (None = 0)

        Returns
        -------
        command : m floats — rev/s (propeller), table unit (table) or N (ideal). A demand
            beyond what the curve gives at the speed limit returns the speed limit.

        Notes
        -----
        Propeller: closed form ``n = sign(f) √(|f| / (loss K_T(0) ρ D⁴))`` at V_a = 0;
        otherwise a bracketed root search (regula falsi, Illinois) on [0, n_max] or
        [−n_max, 0] (the sense follows the sign of f).
        """
        f = np.clip(np.asarray(thrust, dtype=float), self.f_min, self.f_max)
        va = np.zeros(len(self)) if advance_speed is None else np.asarray(advance_speed, float)
        out = np.empty(len(self))
        for i, t in enumerate(self.thrusters):
            if t.model == "ideal":
                out[i] = f[i]
            elif t.model == "table":
                out[i] = np.interp(f[i], t.table_thrust, t.table_command)  # type: ignore[arg-type]
            else:
                out[i] = self._invert_propeller(t, f[i], va[i], self.command_max[i])
        return out

    def _scalar_thrust(self, t: Thruster, n: float, va: float) -> float:
        """Propeller thrust for one thruster with plain floats (fast inside root finding)."""
        if n == 0.0:
            return 0.0
        D = t.diameter  # type: ignore[assignment]
        lo, hi = t.advance_ratio_range
        nD = n * D
        if abs(nD) * 1e6 > abs(va):
            J = min(max(va / nD, lo), hi)
        else:  # |J| > 1e6: far outside any curve's range, only its sign matters
            J = hi if (va > 0) == (n > 0) else lo
        coeffs = t.kt_forward if n > 0 else t.kt_reverse
        kt = 0.0
        for c in coeffs:  # type: ignore[union-attr]
            kt = kt * J + c
        loss = t.thrust_loss_forward if n > 0 else t.thrust_loss_reverse
        return loss * max(kt, 0.0) * self.density * D**4 * abs(n) * n  # type: ignore[operator]

    def _invert_propeller(self, t: Thruster, f: float, va: float, n_max: float) -> float:
        if f == 0.0:
            return 0.0
        D = float(t.diameter)  # type: ignore[arg-type]
        fwd = f > 0
        if va == 0.0:
            kt0 = np.polyval(t.kt_forward if fwd else t.kt_reverse, 0.0)
            loss = t.thrust_loss_forward if fwd else t.thrust_loss_reverse
            n = math.sqrt(abs(f) / (loss * kt0 * self.density * D**4))
            return min(n, n_max) if fwd else -min(n, n_max)
        f, va = float(f), float(va)
        lo, hi = (0.0, n_max) if fwd else (-n_max, 0.0)
        g_lo = self._scalar_thrust(t, lo, va) - f
        g_hi = self._scalar_thrust(t, hi, va) - f
        if g_hi <= 0.0:  # even the speed limit does not give f (forward)
            return hi
        if g_lo >= 0.0:  # (reverse)
            return lo
        # Regula falsi with the Illinois modification on the bracket [lo, hi] where
        # thrust − f changes sign (thrust(0) = 0 and grows with n in both senses);
        # converges superlinearly and never leaves the bracket.
        side = 0
        n = 0.5 * (lo + hi)
        for it in range(_BISECTION_STEPS):
            # after 20 false-position steps (flat stretches of the clamped curve slow it
            # down) plain bisection guarantees the bracket halves every step
            n = (lo * g_hi - hi * g_lo) / (g_hi - g_lo) if it < 20 else 0.5 * (lo + hi)
            g = self._scalar_thrust(t, n, va) - f
            if abs(g) <= 1e-12 * abs(f) or hi - lo <= 1e-12 * n_max:
                break
            if g < 0.0:
                lo, g_lo = n, g
                if side == -1:
                    g_hi *= 0.5
                side = -1
            else:
                hi, g_hi = n, g
                if side == 1:
                    g_lo *= 0.5
                side = 1
        return n

    def rotor_step(self, command: ArrayLike, target: ArrayLike, dt: float) -> Array:
        """Advance the first-order rotor dynamics τ ċ = c_target − c by ``dt`` (s), exactly.

        With the target held over the step (zero-order hold) the solution is
        ``c(t+dt) = c_t + (c − c_t) e^(−dt/τ)``; τ = 0 follows the target at once.
        Both arguments are command vectors (rev/s, table unit or N).
        """
        c = np.asarray(command, dtype=float)
        ct = np.clip(np.asarray(target, dtype=float), self.command_min, self.command_max)
        tc = self.time_constants
        with np.errstate(divide="ignore", over="ignore"):
            decay = np.where(tc > 0, np.exp(-dt / np.where(tc > 0, tc, 1.0)), 0.0)
        return ct + (c - ct) * decay
