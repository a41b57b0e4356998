"""Thruster models: pose, thrust curve, rotor dynamics and saturation.

A thruster's thrust curve is an object with one interface (:class:`ThrustCurve`):
``thrust(command, advance_speed)``, its inverse ``command(thrust, advance_speed)``,
``limits()`` (thrust, N) and ``command_limits()``. Three curves exist:

:class:`PropellerCurve` (``model == "propeller"``)
    Open-water curve (REHMAN eq. 1.12, SPEC §4 and §8):
    ``f = loss · K_T(J) · ρ D⁴ |n| n`` with ``J = V_a / (n D)`` and ``K_T`` a polynomial of
    ``J``; forward (n > 0) and reverse (n < 0) rotation have their own polynomial and
    thrust-loss factor. The command is the propeller speed ``n`` in rev/s.
:class:`TableCurve` (``model == "table"``)
    Thrust interpolated in a strictly increasing table of thrust vs command (e.g. the
    BlueROV2 T200 curve F(V) tabulated against the normalised input V). The command has
    the table's unit.
:class:`IdealCurve` (``model == "ideal"``)
    The command *is* the thrust in N (only limits and rotor lag apply).

A :class:`Thruster` holds one curve (built from its fields, or given as ``curve=``);
:class:`ThrusterSet` calls the curves without knowing which kind each is, so a new kind of
curve needs no change here. All arrays are in file order. SI units: m, N, rev/s, s, kg/m³.
"""

from __future__ import annotations

import abc
import dataclasses
import math
from collections.abc import Sequence
from dataclasses import InitVar, dataclass, field
from typing import Any, ClassVar, Literal, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from hydrokit.core.constants import SEAWATER_DENSITY
from hydrokit.core.validate import quantities, quantity
from hydrokit.errors import InputError

Array = NDArray[np.float64]
ThrustModel = Literal["propeller", "table", "ideal"]

#: Default validity range of an open-water K_T(J) polynomial; outside it the curve is held
#: at its end value (cubic fits diverge for large |J|, which happens as n → 0 with inflow).
DEFAULT_ADVANCE_RATIO_RANGE = (-0.5, 1.0)

#: Sea water, kg/m³ (SPEC §8): the density a curve has until a ThrusterSet binds its own.
DEFAULT_DENSITY = SEAWATER_DENSITY

#: Iteration cap for inverting a propeller curve: up to 20 regula-falsi (Illinois) steps,
#: then bisection; 2⁻⁶⁰ of the speed range is far below any meaningful rev/s resolution.
#: It usually stops within a few steps, at a thrust error of 1e-12 relative.
_BISECTION_STEPS = 80


def _horner(coeffs: tuple[float, ...], x: float) -> float:
    """Polynomial value, highest power first (the same operation order as np.polyval)."""
    y = 0.0
    for c in coeffs:
        y = y * x + c
    return y


def _pad_cubic(coeffs: tuple[float, ...]) -> tuple[float, ...]:
    """Coefficients padded with leading zeros to four (a cubic), or unchanged if longer.

    Horner's scheme from y = 0 keeps y = +0.0 through leading zero coefficients (for any
    finite x), so the padded polynomial gives :func:`_horner`'s value bit for bit.
    """
    return (0.0,) * (4 - len(coeffs)) + tuple(coeffs) if len(coeffs) <= 4 else tuple(coeffs)


# ============================================================================== the laws
# Plain floats (and a sequence of polynomial coefficients): called as Python by the curves and
# the thruster set below, compiled by ``compile_law`` (hydrokit.simulate.compiled) for the
# compiled manoeuvre loop. One implementation of each law.


def propeller_thrust(
    n: float,
    va: float,
    D: float,
    rho: float,
    j_lo: float,
    j_hi: float,
    kt_forward: Any,
    kt_reverse: Any,
    loss_forward: float,
    loss_reverse: float,
) -> float:
    """Open-water propeller thrust ``loss · K_T(J) ρ D⁴ |n| n``, N (REHMAN eq. 1.12).

    Parameters
    ----------
    n : float — propeller speed, rev/s
    va : float — advance speed V_a, m/s
    D : float — diameter, m; rho : float — water density, kg/m³
    j_lo, j_hi : float — validity range of the K_T polynomials, – (J is clamped to it)
    kt_forward, kt_reverse : sequence of float — K_T(J) for n > 0 and n < 0, highest power
        first, – (in the compiled loop: arrays padded to one length with leading zeros)
    loss_forward, loss_reverse : float — thrust-loss factors, –

    Notes
    -----
    ``J = V_a / (n D)``; where ``|n D| · 1e6 ≤ |V_a|`` J is far outside any curve's range and
    only the signs matter (J at the range's end). K_T is clamped at ≥ 0 (NaN kept).
    """
    if n == 0.0:
        return 0.0
    nD = n * D
    if abs(nD) * 1e6 > abs(va):
        J = va / nD
        J = j_lo if j_lo > J else J  # max(J, j_lo)
        J = j_hi if j_hi < J else J  # min(J, j_hi)
    else:  # |J| > 1e6
        J = j_hi if (va > 0) == (n > 0) else j_lo
    k = kt_forward if n > 0 else kt_reverse
    kt = 0.0
    for c in k:  # Horner, highest power first (np.polyval's order)
        kt = kt * J + c
    kt = 0.0 if kt < 0.0 else kt  # max(kt, 0.0), NaN kept
    loss = loss_forward if n > 0 else loss_reverse
    return loss * kt * rho * D**4 * abs(n) * n


def propeller_speed(
    f: float,
    va: float,
    n_max: float,
    D: float,
    rho: float,
    j_lo: float,
    j_hi: float,
    kt_forward: Any,
    kt_reverse: Any,
    loss_forward: float,
    loss_reverse: float,
) -> float:
    """The propeller speed n (rev/s, within ±``n_max``, rev/s) giving thrust ``f`` (N) at V_a =
    ``va`` (m/s): the inverse of :func:`propeller_thrust` (the same parameters after ``n_max``).

    Closed form ``n = sign(f) √(|f| / (loss K_T(0) ρ D⁴))`` at V_a = 0; otherwise a bracketed
    root search (regula falsi, Illinois; bisection after 20 steps) on [0, n_max] or [−n_max, 0]
    (the sense follows the sign of f). A demand beyond what the curve gives at the speed limit
    returns the speed limit.
    """
    if f == 0.0:
        return 0.0
    fwd = f > 0
    if va == 0.0:
        k = kt_forward if fwd else kt_reverse
        kt0 = 0.0
        for c in k:
            kt0 = kt0 * 0.0 + c
        loss = loss_forward if fwd else loss_reverse
        n = math.sqrt(abs(f) / (loss * kt0 * rho * D**4))
        return min(n, n_max) if fwd else -min(n, n_max)
    lo, hi = (0.0, n_max) if fwd else (-n_max, 0.0)
    g_lo = propeller_thrust(lo, va, D, rho, j_lo, j_hi, kt_forward, kt_reverse, loss_forward, loss_reverse) - f
    g_hi = propeller_thrust(hi, va, D, rho, j_lo, j_hi, kt_forward, kt_reverse, loss_forward, loss_reverse) - f
    if g_hi <= 0.0:  # even the speed limit does not give f (forward)
        return hi
    if g_lo >= 0.0:  # (reverse)
        return lo
    # thrust − f changes sign on [lo, hi] (thrust(0) = 0 and grows with n in both senses):
    # superlinear, never leaves the bracket
    side = 0
    n = lo  # (set by the first step: the loop runs at least once)
    for it in range(_BISECTION_STEPS):
        # after 20 false-position steps (flat stretches of the clamped curve slow it down)
        # bisection halves the bracket every step
        n = (lo * g_hi - hi * g_lo) / (g_hi - g_lo) if it < 20 else 0.5 * (lo + hi)
        g = propeller_thrust(n, va, D, rho, j_lo, j_hi, kt_forward, kt_reverse, loss_forward, loss_reverse) - f
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


def advance_speed_law(
    wake: float,
    ex: float,
    ey: float,
    ez: float,
    ax: float,
    ay: float,
    az: float,
    u: float,
    v: float,
    w: float,
    p: float,
    q: float,
    r: float,
) -> float:
    """A propeller's advance speed V_a = (1 − w) e · (v + ω × r_p), m/s, written as
    (1 − w)(e · v + a · ω) with the moment arm a = r_p × e: ``wake`` = 1 − w (–), ``ex, ey, ez``
    the unit thrust direction, ``ax, ay, az`` the arm (m), ``u, v, w`` (m/s) and ``p, q, r``
    (rad/s) the body velocity relative to the water."""
    return wake * ((ex * u + ey * v + ez * w) + (ax * p + ay * q + az * r))


def thruster_inputs(kind, prop, kf, kr, lim, wake, dirs, arms, T, force, c, nr, f, rate, tau):  # noqa: ANN001, ANN201
    """The thrusters' part of a vehicle's input vector at one instant, in place: each thruster's
    thrust ``f`` (N) and rotation rate ``rate`` (rev/s; a propeller's rotor state, 0 for an ideal
    thruster) at the rotor state ``c`` (each thruster's command unit) and the body velocity
    relative to the water ``nr`` (6 floats, m/s, rad/s), and ``tau = force + T f`` (N, N·m).

    The packed description (:func:`hydrokit.manoeuvre.compiled._pack_drive`): ``kind`` 0 ideal
    (the command is the thrust) or 2 propeller (K_T(J) at the advance speed, wake included);
    ``prop`` rows [D, ρ, J_lo, J_hi, loss_f, loss_r]; ``kf``, ``kr`` the K_T polynomials padded
    with leading zeros; ``lim`` rows [c_min, c_max, f_min, f_max]; ``wake`` 1 − w; ``dirs`` e_i;
    ``arms`` r_i × e_i; ``T`` the 6 × m configuration matrix (thrust deduction included);
    ``force`` 6 floats (N, N·m). The same law as :meth:`ThrusterSet.thrust` at
    :meth:`ThrusterSet.advance_speed` (the command clipped to its limits, the thrust to the
    thrust limits) and :meth:`ThrusterSet.rotation_rate`; plain floats and loops, compiled by
    ``compile_law`` for the compiled manoeuvre loop, where it is evaluated at every RK4 stage
    as :func:`hydrokit.simulate.commands.fly_commands` evaluates its thrust."""
    m = kind.shape[0]
    for j in range(m):
        cj = c[j]
        cj = lim[j, 0] if cj < lim[j, 0] else (lim[j, 1] if cj > lim[j, 1] else cj)
        if kind[j] == 2:
            va = advance_speed_law(
                wake[j], dirs[j, 0], dirs[j, 1], dirs[j, 2], arms[j, 0], arms[j, 1], arms[j, 2],
                nr[0], nr[1], nr[2], nr[3], nr[4], nr[5],
            )  # fmt: skip
            fj = propeller_thrust(
                cj, va, prop[j, 0], prop[j, 1], prop[j, 2], prop[j, 3], kf[j], kr[j], prop[j, 4], prop[j, 5]
            )
            rate[j] = cj
        else:  # ideal: the command is the thrust, and there is no rotor rate
            fj = cj
            rate[j] = 0.0
        f[j] = lim[j, 2] if fj < lim[j, 2] else (lim[j, 3] if fj > lim[j, 3] else fj)
    for i in range(6):
        s = 0.0
        for j in range(m):
            s += T[i, j] * f[j]
        tau[i] = force[i] + s


def rotor_lag(c: float, target: float, dt: float, time_constant: float) -> float:
    """The rotor state (command unit) after ``dt`` (s) of the first-order lag τ ċ = c_t − c
    from ``c`` towards the held ``target``, exactly: ``c_t + (c − c_t) e^(−dt/τ)``; τ =
    ``time_constant`` (s) = 0 follows the target at once."""
    if time_constant > 0.0:
        return target + (c - target) * math.exp(-dt / time_constant)
    return target


def table_interp(x: float, xs: Sequence[float], ys: Sequence[float], n: int) -> float:
    """Linear interpolation in the table ``(xs[:n], ys[:n])`` at ``x``, held at the end values
    beyond it: ``np.interp(x, xs[:n], ys[:n])`` for one number, in its operation order, so equal
    to it bit for bit (also for a repeated x: the last of the equal points gives the value).

    Parameters
    ----------
    x : float — where to read the table, in the unit of ``xs`` (table command or N)
    xs : sequence of float — the table's abscissae, nondecreasing (table command or N)
    ys : sequence of float — the values at ``xs`` (N or table command)
    n : int — how many of the points are used (≥ 1; a compiled table is padded beyond it)

    Notes
    -----
    With j the last index where ``xs[j] ≤ x``: ``y = s (x − xs[j]) + ys[j]``,
    ``s = (ys[j+1] − ys[j]) / (xs[j+1] − xs[j])``; ``ys[j]`` when ``xs[j] = x`` (numpy's
    ``arr_interp``, numpy/core/src/multiarray/compiled_base.c).
    """
    if math.isnan(x):
        return x
    if x < xs[0]:
        return ys[0]
    if x > xs[n - 1]:
        return ys[n - 1]
    lo, hi = 0, n  # xs[lo] <= x and (hi == n or xs[hi] > x)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid
    if lo == n - 1 or xs[lo] == x:
        return ys[lo]
    slope = (ys[lo + 1] - ys[lo]) / (xs[lo + 1] - xs[lo])
    y = slope * (x - xs[lo]) + ys[lo]
    if math.isnan(y):  # an infinite table value: from the right end of the interval (as numpy)
        y = slope * (x - xs[lo + 1]) + ys[lo + 1]
        if math.isnan(y) and ys[lo] == ys[lo + 1]:
            y = ys[lo]
    return y


#: :func:`rotor_lag` broadcast over arrays (one law; numpy calls it element by element)
_ROTOR_LAG = np.vectorize(rotor_lag, otypes=[float])


# =========================================================================== thrust curves
class ThrustCurve(abc.ABC):
    """Command ↔ thrust of one thruster (steady state, no rotor lag).

    Subclasses set ``kind`` (the thruster's ``model`` string) and ``unit`` (the command's
    unit) and implement :meth:`thrust`, :meth:`command` and :meth:`limits`.
    """

    kind: ClassVar[str]
    unit: ClassVar[str]

    @abc.abstractmethod
    def thrust(self, command: float, advance_speed: float = 0.0) -> float:
        """Thrust for a command, N (not clipped to any rated limit).

        Parameters
        ----------
        command : float
            The command, in :attr:`unit` (rev/s, table unit or N).
        advance_speed : float, optional
            V_a, the axial inflow speed at the propeller, m/s.
        """

    @abc.abstractmethod
    def command(self, thrust: float, advance_speed: float = 0.0) -> float:
        """The command giving ``thrust`` (N) at ``advance_speed`` (m/s); the inverse of
        :meth:`thrust` within :meth:`limits`, held at the command limit beyond them."""

    @abc.abstractmethod
    def limits(self) -> tuple[float, float]:
        """(min, max) thrust the curve can give at V_a = 0, N (±∞: no own limit)."""

    def command_limits(self) -> tuple[float, float]:
        """(min, max) command, in :attr:`unit`; ±∞ when the curve has no own range."""
        return (-math.inf, math.inf)

    def in_fluid(self, density: float) -> ThrustCurve:
        """The same curve in water of ``density`` (kg/m³); unchanged if it does not depend
        on the density."""
        return self

    # Batch evaluation. ThrusterSet groups its thrusters by curve class and calls these
    # once per group and step; a subclass may override them with a faster computation that
    # gives the same values as its scalar methods (tests/model/test_closed_loop_speed_refactor.py).
    @classmethod
    def thrust_batch(cls, curves: Sequence[ThrustCurve], command: Array, advance_speed: Array) -> Array:
        """:meth:`thrust` of each of ``curves`` (all of this class) at the matching command
        and advance speed (m/s), N."""
        return np.array(
            [cv.thrust(c, v) for cv, c, v in zip(curves, command.tolist(), advance_speed.tolist())], dtype=float
        )

    @classmethod
    def command_batch(cls, curves: Sequence[ThrustCurve], thrust: Array, advance_speed: Array) -> Array:
        """:meth:`command` of each of ``curves`` (all of this class) for the matching thrust
        (N) and advance speed (m/s)."""
        return np.array(
            [cv.command(f, v) for cv, f, v in zip(curves, thrust.tolist(), advance_speed.tolist())], dtype=float
        )


@dataclass(frozen=True)
class IdealCurve(ThrustCurve):
    """The command is the thrust, N: ``thrust(c) = c``. Only rated limits and lag apply."""

    kind: ClassVar[str] = "ideal"
    unit: ClassVar[str] = "N"

    def thrust(self, command: float, advance_speed: float = 0.0) -> float:  # any inflow
        """``command`` itself, N."""
        return float(command)

    def command(self, thrust: float, advance_speed: float = 0.0) -> float:  # any inflow
        """``thrust`` itself, N."""
        return float(thrust)

    def limits(self) -> tuple[float, float]:
        """(−∞, ∞): the thruster's rated limits are the only ones."""
        return (-math.inf, math.inf)

    @classmethod
    def thrust_batch(cls, curves: Sequence[ThrustCurve], command: Array, advance_speed: Array) -> Array:
        """The commands themselves, N."""
        return np.array(command, dtype=float)

    @classmethod
    def command_batch(cls, curves: Sequence[ThrustCurve], thrust: Array, advance_speed: Array) -> Array:
        """The thrusts themselves, N."""
        return np.array(thrust, dtype=float)


@dataclass(frozen=True)
class TableCurve(ThrustCurve):
    """Thrust interpolated linearly in a table, held at its end values.

    Parameters
    ----------
    commands : sequence of float
        Command points, in the table's own unit (e.g. normalised input or PWM µs); strictly
        increasing, at least two.
    thrusts : sequence of float
        Thrust at each command point, N; strictly increasing (so the curve can be inverted).
    label : str, optional, init-only
        What error messages call the curve (e.g. ``thruster 'T1'``).
    """

    commands: tuple[float, ...]
    thrusts: tuple[float, ...]
    label: InitVar[str] = "table curve"
    kind: ClassVar[str] = "table"
    unit: ClassVar[str] = "table command"

    def __post_init__(self, label: str) -> None:
        c = quantities(self.commands, f"{label} thrust_table command")
        f = quantities(self.thrusts, f"{label} thrust_table thrust")
        if len(c) != len(f) or len(c) < 2:
            raise InputError(
                f"{label} thrust_table: command and thrust need the same length ≥ 2, got {len(c)} and {len(f)}"
            )
        if np.any(np.diff(c) <= 0) or np.any(np.diff(f) <= 0):
            raise InputError(f"{label} thrust_table: command and thrust must both be strictly increasing")
        object.__setattr__(self, "commands", c)
        object.__setattr__(self, "thrusts", f)

    def thrust(self, command: float, advance_speed: float = 0.0) -> float:  # any inflow
        """Interpolated thrust, N (the table holds for any advance speed)."""
        return table_interp(float(command), self.commands, self.thrusts, len(self.commands))

    def command(self, thrust: float, advance_speed: float = 0.0) -> float:  # any inflow
        """Interpolated command (table unit) for ``thrust`` (N)."""
        return table_interp(float(thrust), self.thrusts, self.commands, len(self.commands))

    def limits(self) -> tuple[float, float]:
        """First and last thrust of the table, N."""
        return (self.thrusts[0], self.thrusts[-1])

    def command_limits(self) -> tuple[float, float]:
        """First and last command of the table (table unit)."""
        return (self.commands[0], self.commands[-1])

    @staticmethod
    def _interp_groups(curves: Sequence[ThrustCurve], x: Array, inverse: bool) -> Array:
        # the one law, element by element (on the tables' tuples: faster than numpy indexing)
        out = np.empty(len(curves))
        for i, cv in enumerate(curves):
            t: Any = cv
            xp, fp = (t.thrusts, t.commands) if inverse else (t.commands, t.thrusts)
            out[i] = table_interp(float(x[i]), xp, fp, len(xp))
        return out

    @classmethod
    def thrust_batch(cls, curves: Sequence[ThrustCurve], command: Array, advance_speed: Array) -> Array:
        """Interpolated thrusts, N (one interpolation per distinct table)."""
        return cls._interp_groups(curves, np.asarray(command, dtype=float), inverse=False)

    @classmethod
    def command_batch(cls, curves: Sequence[ThrustCurve], thrust: Array, advance_speed: Array) -> Array:
        """Interpolated commands (table unit), one interpolation per distinct table."""
        return cls._interp_groups(curves, np.asarray(thrust, dtype=float), inverse=True)


@dataclass(frozen=True)
class PropellerCurve(ThrustCurve):
    """Open-water propeller curve ``f = loss · K_T(J) ρ D⁴ |n| n`` (REHMAN eq. 1.12).

    Parameters
    ----------
    diameter : float
        Propeller diameter D, m (> 0).
    kt_forward : sequence of float
        K_T(J) polynomial for n > 0, highest power first (c3, c2, c1, c0 for a cubic), –.
    max_speed : float
        Propeller speed limit n_max, rev/s (> 0): commands lie in [−n_max, n_max].
    kt_reverse : sequence of float or None, optional
        K_T(J) for n < 0, –; None = the forward polynomial.
    thrust_loss_forward, thrust_loss_reverse : float, optional
        Thrust-loss factors (installation, duct), – (> 0; 1 = none).
    advance_ratio_range : (float, float), optional
        J range where the polynomials hold, –; J is clamped to it (low ≤ 0 < high).
    density : float, optional
        Water density ρ, kg/m³. A :class:`ThrusterSet` rebinds it to the set's density.
    label : str, optional, init-only
        What error messages call the curve (e.g. ``thruster 'T1'``).

    Notes
    -----
    ``J = V_a / (n D)``; K_T is clamped at ≥ 0 (inflow may cancel thrust, never reverse
    it), and K_T(0) must be positive in both senses so the curve is invertible.
    """

    diameter: float
    kt_forward: tuple[float, ...]
    max_speed: float
    kt_reverse: tuple[float, ...] | None = None
    thrust_loss_forward: float = 1.0
    thrust_loss_reverse: float = 1.0
    advance_ratio_range: tuple[float, float] = DEFAULT_ADVANCE_RATIO_RANGE
    density: float = DEFAULT_DENSITY
    label: InitVar[str] = "propeller curve"
    kind: ClassVar[str] = "propeller"
    unit: ClassVar[str] = "rev/s"

    def __post_init__(self, label: str) -> None:
        put = lambda k, v: object.__setattr__(self, k, v)
        put("diameter", quantity(self.diameter, f"{label} diameter", positive=True, unit="m"))
        put("max_speed", quantity(self.max_speed, f"{label} max_speed", positive=True, unit="rev/s"))
        kf = quantities(self.kt_forward, f"{label} kt_forward")
        kr = self.kt_reverse
        # None or an empty list: the reverse sense uses the forward polynomial
        kr = kf if kr is None or (isinstance(kr, (list, tuple)) and not kr) else quantities(kr, f"{label} kt_reverse")
        put("kt_forward", kf)
        put("kt_reverse", kr)
        if _horner(kf, 0.0) <= 0 or _horner(kr, 0.0) <= 0:
            raise InputError(f"{label}: K_T(0) must be positive for both rotation senses")
        for attr in ("thrust_loss_forward", "thrust_loss_reverse"):
            put(attr, quantity(getattr(self, attr), f"{label} {attr}", positive=True))
        rng = quantities(self.advance_ratio_range, f"{label} advance_ratio_range", 2)
        if not rng[0] <= 0 < rng[1]:
            raise InputError(
                f"{label} advance_ratio_range = {list(self.advance_ratio_range)}: expected [low ≤ 0, high > 0]"
            )
        put("advance_ratio_range", rng)
        put("density", quantity(self.density, f"{label} density", positive=True, unit="kg/m³"))
        # the arguments of the laws after (n or f, V_a) (not fields: no effect on == or repr)
        put(
            "_law",
            (self.diameter, self.density, rng[0], rng[1], kf, kr, self.thrust_loss_forward, self.thrust_loss_reverse),
        )
        # the same constants as simulate/compiled_loop.py packs them (cubics padded with leading
        # zeros, which keep Horner's value bit for bit; D⁴ and the bollard denominators)
        D4 = self.diameter**4
        put(
            "_fast",
            (
                self.diameter,
                D4,
                self.density,
                rng[0],
                rng[1],
                _pad_cubic(kf),
                _pad_cubic(kr),
                self.thrust_loss_forward,
                self.thrust_loss_reverse,
                self.max_speed,
                self.thrust_loss_forward * _horner(kf, 0.0) * self.density * D4,
                self.thrust_loss_reverse * _horner(kr, 0.0) * self.density * D4,
            ),
        )

    @property
    def law_args(self) -> tuple[Any, ...]:
        """The arguments of :func:`propeller_thrust` and :func:`propeller_speed` after (n or f,
        V_a): (D m, ρ kg/m³, J_lo, J_hi, K_T forward, K_T reverse, loss forward, loss reverse)."""
        return cast("tuple[Any, ...]", self._law)  # type: ignore[attr-defined]

    def in_fluid(self, density: float) -> PropellerCurve:
        """This curve with ρ = ``density`` (kg/m³)."""
        return self if density == self.density else dataclasses.replace(self, density=density)

    def thrust(self, command: float, advance_speed: float = 0.0) -> float:
        """Thrust at propeller speed ``command`` (n, rev/s) and V_a (m/s), N
        (:func:`propeller_thrust`)."""
        return propeller_thrust(float(command), float(advance_speed), *self.law_args)

    def command(self, thrust: float, advance_speed: float = 0.0) -> float:
        """Propeller speed n (rev/s, within ±max_speed) giving ``thrust`` (N) at V_a (m/s)
        (:func:`propeller_speed`: closed form at V_a = 0, a bracketed root search otherwise;
        a demand beyond what the curve gives at the speed limit returns the speed limit)."""
        return propeller_speed(float(thrust), float(advance_speed), self.max_speed, *self.law_args)

    def limits(self) -> tuple[float, float]:
        """Static (V_a = 0) thrust at −n_max and +n_max, N."""
        return (self.thrust(-self.max_speed), self.thrust(self.max_speed))

    def command_limits(self) -> tuple[float, float]:
        """(−n_max, n_max), rev/s."""
        return (-self.max_speed, self.max_speed)

    @classmethod
    def thrust_batch(cls, curves: Sequence[ThrustCurve], command: Array, advance_speed: Array) -> Array:
        """:meth:`thrust` of each curve, N."""
        props = cast("Sequence[PropellerCurve]", curves)
        return np.array(
            [propeller_thrust(c, v, *cv.law_args) for cv, c, v in zip(props, command.tolist(), advance_speed.tolist())],
            dtype=float,
        )

    @classmethod
    def command_batch(cls, curves: Sequence[ThrustCurve], thrust: Array, advance_speed: Array) -> Array:
        """:meth:`command` of each curve, rev/s."""
        props = cast("Sequence[PropellerCurve]", curves)
        return np.array(
            [
                propeller_speed(f, v, cv.max_speed, *cv.law_args)
                for cv, f, v in zip(props, thrust.tolist(), advance_speed.tolist())
            ],
            dtype=float,
        )

    # the names the batch paths had before the laws above (kept for their callers): the laws
    def _thrust_fast(self, n: float, va: float) -> float:
        return self.thrust(n, va)

    def _command_fast(self, f: float, va: float) -> float:
        return self.command(f, va)


# =============================================================================== thruster
#: the Thruster fields that describe a curve (the alternative to giving ``curve``)
_PROPELLER_FIELDS = (
    "kt_forward",
    "kt_reverse",
    "thrust_loss_forward",
    "thrust_loss_reverse",
    "advance_ratio_range",
    "max_speed",
)


@dataclass(frozen=True)
class Thruster:
    """One thruster: pose, limits, rotor lag and a thrust curve.

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
    thrust_deduction : float — t, the hull's resistance increase t·T: the thruster's force on the
        vehicle is (1 − t) T e_i, its moment that of the full thrust r_i × T e_i (the increase is
        a pressure drop on the hull acting along the thrust line's direction through the body
        origin; MMG: X_P = (1 − t_P) T), –, 0 ≤ t < 1
    max_speed : float or None — propeller speed limit, rev/s (required for ``propeller``)
    time_constant : float — first-order rotor lag τ, s (0 = instantaneous)
    table_command, table_thrust : tuple of float or None — thrust table: command (its own
        unit) and thrust, N; thrust strictly increasing
    curve : ThrustCurve or None — the thrust curve itself. None: built from the fields
        above (table fields → :class:`TableCurve`, ``kt_forward`` → :class:`PropellerCurve`
        with ρ = 1025 kg/m³ until a ThrusterSet binds its density, neither →
        :class:`IdealCurve`). Given: the curve fields above must be left unset (they stay
        None) or describe the same curve.
    channel : int or None — autopilot servo output driving it, 1-based (ArduPilot ``SERVOn``,
        ``RCOU`` ``Cn``); metadata for reading logs (``hydrokit ingest --run-out``), unused by
        the model
    motor : int or None — ArduSub motor number driving it (``MOT_n``, 1-based); metadata as
        ``channel``
    reversed : bool — a positive autopilot command pushes against ``direction`` (the layout's
        positive direction is the opposite of the autopilot frame's); metadata as ``channel``
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
    thrust_deduction: float = 0.0
    max_speed: float | None = None
    time_constant: float = 0.0
    table_command: tuple[float, ...] | None = None
    table_thrust: tuple[float, ...] | None = None
    curve: ThrustCurve | None = None
    channel: int | None = field(default=None, compare=False)
    motor: int | None = field(default=None, compare=False)
    reversed: bool = field(default=False, compare=False)

    def __post_init__(self) -> None:
        where = f"thruster '{self.name}'"
        put = lambda k, v: object.__setattr__(self, k, v)
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"thruster name {self.name!r}: expected a non-empty string")
        for key in ("channel", "motor"):
            v = getattr(self, key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= 32):
                raise InputError(f"{where} {key} = {v!r}: expected an output number 1…32 (1-based)")
            if v is not None:
                put(key, int(v))
        if not isinstance(self.reversed, (bool, np.bool_)):
            raise InputError(f"{where} reversed = {self.reversed!r}: expected true or false")
        put("reversed", bool(self.reversed))
        pos = quantities(self.position, f"{where} position", 3)
        d = np.asarray(quantities(self.direction, f"{where} direction", 3))
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            raise InputError(f"{where} direction {list(self.direction)} has zero length; expected a non-zero 3-vector")
        put("position", pos)
        put("direction", tuple(float(x) for x in d / norm))
        fmax = quantity(self.max_thrust, f"{where} max_thrust", positive=True, unit="N")
        fmin = -fmax if self.min_thrust is None else quantity(self.min_thrust, f"{where} min_thrust")
        if fmin > 0:
            raise InputError(f"{where} min_thrust = {fmin}: expected a reverse thrust ≤ 0 N (negative)")
        put("max_thrust", fmax)
        put("min_thrust", fmin)
        put("time_constant", quantity(self.time_constant, f"{where} time_constant", nonneg=True, unit="s"))
        w = quantity(self.wake_fraction, f"{where} wake_fraction")
        if not 0 <= w < 1:
            raise InputError(f"{where} wake_fraction = {w}: expected 0 ≤ w < 1")
        put("wake_fraction", w)
        td = quantity(self.thrust_deduction, f"{where} thrust_deduction")
        if not 0 <= td < 1:
            raise InputError(f"{where} thrust_deduction = {td}: expected 0 ≤ t < 1")
        put("thrust_deduction", td)
        if self.diameter is not None:
            put("diameter", quantity(self.diameter, f"{where} diameter", positive=True, unit="m"))
        built = self._curve_from_fields(where)
        curve = self.curve
        if curve is None:
            curve = built if built is not None else IdealCurve()
        elif not isinstance(curve, ThrustCurve):
            raise InputError(f"{where} curve = {curve!r}: expected a PropellerCurve, TableCurve or IdealCurve")
        elif built is not None and built != curve:
            raise InputError(f"{where}: give either 'curve' or the kt_forward/thrust_table fields, not both")
        put("curve", curve)
        curve_d = getattr(curve, "diameter", None)
        if self.diameter is None:
            put("diameter", curve_d)
        elif curve_d is not None and curve_d != self.diameter:
            raise InputError(f"{where} diameter = {self.diameter}: its curve has diameter {curve_d} m")
        if built is not None:
            # the fields read back as the curve holds them (kt_reverse filled in, tuples)
            if isinstance(built, PropellerCurve):
                for k in _PROPELLER_FIELDS:
                    put(k, getattr(built, k))
            elif isinstance(built, TableCurve):
                put("table_command", built.commands)
                put("table_thrust", built.thrusts)

    def _curve_from_fields(self, where: str) -> ThrustCurve | None:
        """The curve the kt_/table fields describe, or None if they describe none."""
        if self.table_command is not None or self.table_thrust is not None:
            return TableCurve(self.table_command, self.table_thrust, label=where)  # type: ignore[arg-type]
        if self.kt_forward is None:
            return None
        if self.diameter is None:
            raise InputError(f"{where}: a propeller thruster needs its diameter (m)")
        if self.max_speed is None:
            raise InputError(f"{where}: a propeller thruster needs max_rpm (speed limit)")
        return PropellerCurve(
            diameter=self.diameter,
            kt_forward=self.kt_forward,
            max_speed=self.max_speed,
            kt_reverse=self.kt_reverse,
            thrust_loss_forward=self.thrust_loss_forward,
            thrust_loss_reverse=self.thrust_loss_reverse,
            advance_ratio_range=self.advance_ratio_range,
            label=where,
        )

    @property
    def model(self) -> ThrustModel:
        """Which thrust model applies: ``propeller``, ``table`` or ``ideal`` (the curve's kind)."""
        return self.curve.kind  # type: ignore[union-attr, return-value]


# ============================================================================ thruster set
@dataclass(frozen=True)
class ThrusterSet:
    """All thrusters of a vehicle, with vectorised thrust, inversion and rotor dynamics.

    Parameters
    ----------
    thrusters : sequence of Thruster — in file order; names must be unique
    density : float — water density ρ, kg/m³ (bound into every curve that depends on it)
    notes : tuple of str — warnings from reading the layout (e.g. ignored fields)
    """

    thrusters: tuple[Thruster, ...]
    density: float = DEFAULT_DENSITY
    notes: tuple[str, ...] = field(default=(), compare=False)
    # derived arrays (not arguments)
    curves: tuple[ThrustCurve, ...] = field(init=False, repr=False, compare=False)
    positions: Array = field(init=False, repr=False, compare=False)
    directions: Array = field(init=False, repr=False, compare=False)
    f_max: Array = field(init=False, repr=False, compare=False)
    f_min: Array = field(init=False, repr=False, compare=False)
    time_constants: Array = field(init=False, repr=False, compare=False)
    command_max: Array = field(init=False, repr=False, compare=False)
    command_min: Array = field(init=False, repr=False, compare=False)
    _wake_factor: Array = field(init=False, repr=False, compare=False)
    _moment_arms: Array = field(init=False, repr=False, compare=False)
    # thrusters grouped by curve class: (class, curves, indices or None when it is all of them)
    _groups: tuple[tuple[type[ThrustCurve], tuple[ThrustCurve, ...], Array | None], ...] = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        ths = tuple(self.thrusters)
        if not ths:
            raise InputError("thrusters: the list is empty; expected at least one thruster")
        seen: set[str] = set()
        for th in ths:
            if th.name in seen:
                raise InputError(f"thrusters: duplicate name '{th.name}'; names must be unique")
            seen.add(th.name)
        rho = quantity(self.density, "fluid density", positive=True, unit="kg/m³")
        object.__setattr__(self, "thrusters", ths)
        object.__setattr__(self, "density", rho)
        put = lambda k, v: object.__setattr__(self, k, v)
        # the fluid is the vehicle's: every curve works in the set's water
        curves_l: list[ThrustCurve] = []
        for t in ths:
            cv = t.curve.in_fluid(rho)  # type: ignore[union-attr]
            # equal curves (e.g. one table for every thruster) share one object, so the batch
            # methods can tell them alike by identity
            curves_l.append(next((u for u in curves_l if type(u) is type(cv) and u == cv), cv))
        curves = tuple(curves_l)
        put("curves", curves)
        put("positions", np.array([t.position for t in ths], dtype=float))
        put("directions", np.array([t.direction for t in ths], dtype=float))
        put("time_constants", np.array([t.time_constant for t in ths], dtype=float))
        put("_wake_factor", np.array([1.0 - t.wake_fraction for t in ths]))
        put("_moment_arms", np.cross(self.positions, self.directions))
        cmax, cmin, fmax, fmin = [], [], [], []
        for t, cv in zip(ths, curves):
            # thrust limits: the tighter of the rated force and what the curve can give
            lo, hi = cv.limits()
            fmax.append(min(t.max_thrust, hi))
            fmin.append(max(float(t.min_thrust), lo))  # type: ignore[arg-type]
            # a curve without its own command range (ideal) is limited by the thrust limits
            c_lo, c_hi = cv.command_limits()
            cmin.append(c_lo if math.isfinite(c_lo) else cv.command(fmin[-1]))
            cmax.append(c_hi if math.isfinite(c_hi) else cv.command(fmax[-1]))
        put("command_max", np.array(cmax, dtype=float))
        put("command_min", np.array(cmin, dtype=float))
        put("f_max", np.array(fmax, dtype=float))
        put("f_min", np.array(fmin, dtype=float))
        kinds: dict[type[ThrustCurve], list[int]] = {}
        for i, cv in enumerate(curves):
            kinds.setdefault(type(cv), []).append(i)
        put(
            "_groups",
            tuple(
                (kind, tuple(curves[i] for i in idx), None if len(idx) == len(curves) else np.array(idx, dtype=np.intp))
                for kind, idx in kinds.items()
            ),
        )

    # ------------------------------------------------------------------ description
    @property
    def names(self) -> list[str]:
        """Thruster names in file order."""
        return [t.name for t in self.thrusters]

    def __len__(self) -> int:
        return len(self.thrusters)

    def configuration_matrix(self) -> Array:
        """The 6×m configuration matrix T, column i = [(1 − t_i) e_i; r_i × e_i] (LI2021 eq.
        22–23, with the thrust deduction t_i of :class:`Thruster`: the hull's resistance increase
        t_i T_i acts along e_i through the body origin, so it takes from the force only)."""
        from hydrokit.model.allocation import configuration_matrix

        T = configuration_matrix(self.positions, self.directions)
        T[:3] *= 1.0 - np.array([t.thrust_deduction for t in self.thrusters])
        return T

    def rotation_rate(
        self, thrust: ArrayLike, advance_speed: ArrayLike | None = None, command: ArrayLike | None = None
    ) -> Array:
        """Each thruster's rotation rate n, rev/s, for the ``n(NAME)`` term factors.

        A propeller's rotor state is its command: ``command`` (rev/s) when given; otherwise n is
        the one inversion of the curve, :meth:`command_for_thrust`, at ``thrust`` (N) and
        ``advance_speed`` (m/s, None = 0). A thruster without a propeller curve has no rate: 0.
        """
        c = (
            self.command_for_thrust(thrust, advance_speed)
            if command is None
            else self._per_thruster(command, "commands")
        )
        return np.array([c[i] if isinstance(cv, PropellerCurve) else 0.0 for i, cv in enumerate(self.curves)])

    # ------------------------------------------------------------------ kinematics
    def advance_speed(self, nu: ArrayLike) -> Array:
        """Advance speed of each propeller, m/s.

        ``V_a,i = (1 − w_i) e_i · (v + ω × r_i)`` with ν = [v; ω] the body velocity
        relative to the water (m/s, rad/s).
        """
        u, v, w, p, q, r = (float(x) for x in np.asarray(nu, dtype=float)[:6])
        # e_i · (v + ω × r_i) = e_i · v + ω · (r_i × e_i): the law, thruster by thruster
        out = np.empty(len(self._wake_factor))
        for i, (k, e, a) in enumerate(
            zip(self._wake_factor.tolist(), self.directions.tolist(), self._moment_arms.tolist())
        ):
            out[i] = advance_speed_law(k, e[0], e[1], e[2], a[0], a[1], a[2], u, v, w, p, q, r)
        return out

    # ------------------------------------------------------------------ thrust curves
    def thrust(self, command: ArrayLike, advance_speed: ArrayLike | None = None) -> Array:
        """Thrust of every thruster for a command vector, N (saturated to the thrust limits).

        Parameters
        ----------
        command : m floats — propeller speed n in rev/s (propeller), table command (table)
            or thrust in N (ideal); clipped to the command limits first
        advance_speed : m floats or None — V_a, m/s (None = 0, bollard pull)

        Notes
        -----
        Each thruster's :class:`ThrustCurve` gives its thrust; for a propeller
        ``f = loss · K_T(J) ρ D⁴ |n| n``, ``J = V_a/(n D)`` (REHMAN eq. 1.12), with K_T
        clamped at ≥ 0 and J to the curve's validity range.
        """
        c = self._per_thruster(command, "commands").clip(self.command_min, self.command_max)
        va = np.zeros(len(self)) if advance_speed is None else np.asarray(advance_speed, float)
        return self._batch(True, c, va).clip(self.f_min, self.f_max)

    def _per_thruster(self, x: ArrayLike, what: str) -> Array:
        """``x`` as one float per thruster, checked before any clipping broadcasts it."""
        a = np.asarray(x, dtype=float)
        if a.shape != (len(self),):
            raise InputError(f"expected {len(self)} {what} (one per thruster), got shape {a.shape}")
        return a

    def _batch(self, forward: bool, x: Array, va: Array) -> Array:
        """Each group's ``thrust_batch`` (forward) or ``command_batch`` on its thrusters."""
        if x.shape != (len(self),) or va.shape != (len(self),):
            raise InputError(
                f"expected {len(self)} commands or thrusts and advance speeds, got {x.shape} and {va.shape}"
            )
        groups = self._groups
        if len(groups) == 1:
            kind, curves, _ = groups[0]
            return kind.thrust_batch(curves, x, va) if forward else kind.command_batch(curves, x, va)
        out = np.empty(len(self))
        for kind, curves, idx in groups:
            out[idx] = (
                kind.thrust_batch(curves, x[idx], va[idx]) if forward else kind.command_batch(curves, x[idx], va[idx])
            )
        return out

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
        See :meth:`PropellerCurve.command`: closed form at V_a = 0, a bracketed root search
        otherwise.
        """
        f = self._per_thruster(thrust, "thrusts").clip(self.f_min, self.f_max)
        va = np.zeros(len(self)) if advance_speed is None else np.asarray(advance_speed, float)
        return self._batch(False, f, va)

    def rotor_step(self, command: ArrayLike, target: ArrayLike, dt: ArrayLike) -> Array:
        """Advance the first-order rotor dynamics τ ċ = c_target − c by ``dt`` (s), exactly.

        With the target held over the step (zero-order hold) the solution is
        ``c(t+dt) = c_t + (c − c_t) e^(−dt/τ)``; τ = 0 follows the target at once.
        Both arguments are command vectors (rev/s, table unit or N), or arrays of them whose last
        axis is the thruster; ``dt`` (s) a number or an array that broadcasts against them (the
        identification's force tables advance many nodes at once). The law is :func:`rotor_lag`,
        applied element by element.
        """
        c = np.asarray(command, dtype=float)
        ct = np.clip(np.asarray(target, dtype=float), self.command_min, self.command_max)
        step = np.asarray(dt, dtype=float)
        if c.shape == ct.shape == self.time_constants.shape and step.ndim == 0:  # one command vector: a loop over
            # the thrusters (np.vectorize costs ~50 µs a call; a force table calls this per row)
            h = float(step)
            return np.array(
                [rotor_lag(a, b, h, tau) for a, b, tau in zip(c.tolist(), ct.tolist(), self.time_constants.tolist())]
            )
        return np.asarray(_ROTOR_LAG(c, ct, step, self.time_constants), dtype=float)
