"""General hydrodynamic derivative terms as data (SPEC §3, LI2021 eq. 10–21, SNAME names).

A term is a force/moment letter, an underscore and a product of factors, parsed by a small
grammar — never ``eval``:

    name    := DOF "_" factor ("*"? factor)*        DOF ∈ X Y Z K M N
    factor  := VEL                                   u v w (m/s) or p q r (rad/s)
             | "|" VEL "|"                           magnitude
             | "(" VEL "/|" VEL "|)"                 sign of a velocity (0 at rest)
             | "sqrt(" VEL "^2" ("+" VEL "^2")+ ")"  magnitude of several velocities
             | VEL "dot"                             acceleration (alone: an added-mass entry)
             | "delta(" NAME ")"                     a control surface's deflection (rad; issue #45)
             | "T(" NAME ")"                         a thruster's thrust (N; issue #48)
             | "n(" NAME ")"                         a thruster's rotation rate (rev/s; issue #48)
    power   := factor "^" DIGIT                      the factor repeated (2–5 times)
    const   := DOF "_0"                              a constant force or moment (N, N·m)

Examples: ``X_uu``, ``Y_v|v|``, ``Y_vq``, ``Z_|w|``, ``N_p|p|``, ``X_udot``,
``Z_w*sqrt(v^2+w^2)``, ``N_(v/|v|)*sqrt(v^2+w^2)*|r|``, ``Y_uu*delta(rudder)`` (Prestero 2001's
Y_uuδr), ``X_uu*delta(rudder)^2``, ``Y_T(prop)*delta(rudder)``, ``N_n(prop)^2*delta(rudder)``,
``X_0``. In ``delta(NAME)`` NAME is a control surface of the vehicle
(:mod:`hydrokit.model.surfaces`); a deflection is dimensionless and counts for nothing in the
scaling below. In ``T(NAME)`` and ``n(NAME)`` NAME is a thruster of the vehicle file's
``thrusters:`` block; ``n()`` needs a propeller (a thruster with ``kt_forward``).

The deflections, thrusts and rotation rates reach the evaluation as one *input vector*
[δ_1 … δ_ns, T_1 … T_m, n_1 … n_m] (rad, N, rev/s; surfaces and thrusters in file order): a
factor's index is its place there (:func:`input_layout`). A caller that gives fewer inputs
(only the deflections) leaves the missing ones at 0.

Dimensional value (``nondimensional: false``) is used as is: the force is value × product (SI).
Non-dimensional values are scaled by ½ρL^k (SPEC §3): with n_a the number of angular-rate
factors and n the number of velocity factors of the product (a sqrt counts as one velocity,
linear if all its parts are linear; a sign factor counts for nothing), a force term has
k = 2 + n_a and a moment term one more; terms with n ≠ 2 use the reference speed U:
factor U^(2 − n). Acceleration terms: k = 3 (force / linear), 4 (mixed), 5 (moment / angular).
A constant term (``X_0``, n = 0) is thus ½ρL²U² X'_0 (a moment ½ρL³U² N'_0). A rotation rate
n counts as an angular rate (n' = n L / U: one more L and one velocity); a thrust T counts as a
force (T' = T / (½ρL²U²)), so each thrust factor divides the scale by ½ρL²U²: a force term
``Y_T(prop)*delta(rudder)`` is the same number non-dimensional or in SI, its moment twin
``N_T(prop)*delta(rudder)`` is L × the non-dimensional value (N·m/N), and
``N_n(prop)^2*delta(rudder)`` is ½ρL⁵ × the value (N·m·s²).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hydrokit.core.names import FORCE_SYMBOLS, VELOCITY_SYMBOLS
from hydrokit.errors import InputError

# the grammar works on single characters: "XYZKMN" and "uvwpqr", in core.names' DOF order
DOFS = "".join(FORCE_SYMBOLS)
VELS = "".join(VELOCITY_SYMBOLS)
# factor kinds (codes used by the compiled evaluator); the index of DELTA, THRUST and RATE is
# their place in the input vector [δ…, T…, n…] (module docstring)
VEL, ABS, SIGN, NORM, DELTA, THRUST, RATE = 1, 2, 3, 4, 5, 6, 7
MAX_FACTORS = 5
#: most thrusters whose thrust or rotation rate the terms and fins may read (sizes scratch)
MAX_THRUSTERS = 16


def input_layout(n_surfaces: int, n_thrusters: int) -> tuple[int, int, int]:
    """(first thrust, first rotation rate, length) of the input vector [δ…, T…, n…] of a vehicle
    with ``n_surfaces`` control surfaces and ``n_thrusters`` thrusters."""
    return n_surfaces, n_surfaces + n_thrusters, n_surfaces + 2 * n_thrusters


@dataclass(frozen=True)
class Factor:
    """One factor: kind (VEL, ABS, SIGN, NORM) and velocity indices (0–5, u…r)."""

    kind: int
    indices: tuple[int, ...]

    @property
    def angular(self) -> bool:
        """A factor that counts as an angular rate in the scaling (p, q, r; a rotation rate)."""
        if self.kind == RATE:
            return True
        return self.kind not in (DELTA, THRUST) and all(i >= 3 for i in self.indices)

    @property
    def velocity(self) -> bool:
        """A factor that counts as a velocity in the scaling (not a sign, a deflection or a thrust)."""
        return self.kind not in (SIGN, DELTA, THRUST)


@dataclass(frozen=True)
class Term:
    """A parsed derivative term.

    dof : int — 0–5 (X … N); factors : tuple of Factor; acceleration : int or None — the
    velocity index of an acceleration term (X_udot → 0).
    """

    name: str
    dof: int
    factors: tuple[Factor, ...] = ()
    acceleration: int | None = None

    def scale_power(self) -> int:
        """k of ½ρL^k (see module docstring)."""
        moment = self.dof >= 3
        if self.acceleration is not None:
            return 3 + moment + (self.acceleration >= 3)
        n_a = sum(1 for f in self.factors if f.velocity and f.angular)
        return 2 + n_a + moment

    def order(self) -> int:
        """Number of velocity factors (signs and deflections excluded)."""
        return sum(1 for f in self.factors if f.velocity)

    @property
    def surfaces(self) -> tuple[int, ...]:
        """Indices of the control surfaces the term's deflection factors name."""
        return tuple(f.indices[0] for f in self.factors if f.kind == DELTA)

    @property
    def inputs(self) -> tuple[int, ...]:
        """Input-vector indices of the term's deflection, thrust and rotation-rate factors."""
        return tuple(f.indices[0] for f in self.factors if f.kind in (DELTA, THRUST, RATE))

    def thrusts(self) -> int:
        """Number of thrust factors T(NAME)."""
        return sum(1 for f in self.factors if f.kind == THRUST)

    def dimensional(self, value: float, density: float, length: float, speed: float | None, source: str = "") -> float:
        """The SI coefficient of a non-dimensional ``value`` (module docstring: ½ρL^k U^(2−n),
        divided by ½ρL²U² per thrust factor)."""
        k = self.scale_power()
        n_t = self.thrusts()
        out = (0.5 * density) ** (1 - n_t) * length ** (k - 2 * n_t) * value
        if self.acceleration is None:
            n = self.order()
            e = 2 - n - 2 * n_t
            if e != 0:
                if speed is None or speed <= 0:
                    raise InputError(
                        f"term {self.name!r} has {n} velocity factor(s) and {n_t} thrust factor(s): a "
                        "non-dimensional value needs 'reference_speed' (m/s) in the vehicle file, or give it "
                        "with nondimensional: false",
                        source,
                    )
                out *= speed**e
        return out


class _Parser:
    def __init__(
        self, name: str, source: str, surfaces: tuple[str, ...], thrusters: tuple[str, ...], rated: tuple[str, ...]
    ):
        self.name = name
        self.s = name.replace(" ", "")
        self.i = 0
        self.source = source
        self.surfaces = surfaces
        self.thrusters = thrusters
        self.rated = rated

    def named(self, what: str) -> str:
        """The NAME of ``delta(NAME)``, ``T(NAME)`` or ``n(NAME)`` (its opening already eaten)."""
        j = self.i
        while j < len(self.s) and (self.s[j].isalnum() or self.s[j] in "_-."):
            j += 1
        name = self.s[self.i : j]
        if not name:
            raise self.fail(f"a {what}'s name in ()")
        self.i = j
        self.eat(")")
        return name

    def thruster(self, kind: int) -> Factor:
        """A ``T(NAME)`` or ``n(NAME)`` factor (the opening eaten), indexed in the input vector."""
        letter = "T" if kind == THRUST else "n"
        name = self.named("thruster")
        if name not in self.thrusters:
            known = ", ".join(self.thrusters) or "none"
            raise InputError(
                f"term {self.name!r}: {letter}({name}) names no thruster of the vehicle (thrusters: {known})",
                self.source,
            )
        if kind == RATE and name not in self.rated:
            raise InputError(
                f"term {self.name!r}: n({name}): thruster {name!r} has no propeller curve; expected a thruster with "
                "kt_forward, diameter and max_rpm (its rotation rate in rev/s)",
                self.source,
            )
        first_t, first_n, _ = input_layout(len(self.surfaces), len(self.thrusters))
        i = self.thrusters.index(name)
        return Factor(kind, ((first_t if kind == THRUST else first_n) + i,))

    def fail(self, what: str) -> InputError:
        return InputError(
            f"term {self.name!r}: {what} at position {self.i + 1}; expected SNAME form like X_uu, Y_v|v|, "
            "Z_w*sqrt(v^2+w^2), N_(v/|v|)*|r|, X_udot, Y_uu*delta(rudder), Y_T(prop)*delta(rudder), X_0",
            self.source,
        )

    def peek(self, text: str) -> bool:
        return self.s.startswith(text, self.i)

    def eat(self, text: str) -> None:
        if not self.peek(text):
            raise self.fail(f"'{text}' missing")
        self.i += len(text)

    def vel(self) -> int:
        if self.i < len(self.s) and self.s[self.i] in VELS:
            self.i += 1
            return VELS.index(self.s[self.i - 1])
        raise self.fail("a velocity u, v, w, p, q or r")

    def power(self, factors: list[Factor]) -> None:
        """``^N`` after a factor: the factor repeated N times in all (2 ≤ N ≤ 5)."""
        if not factors or self.i + 1 >= len(self.s) or self.s[self.i + 1] not in "2345":
            raise self.fail("'^' must follow a factor and give a power 2 to 5")
        factors.extend([factors[-1]] * (int(self.s[self.i + 1]) - 1))
        self.i += 2

    def parse(self) -> Term:
        s = self.s
        if len(s) < 3 or s[0] not in DOFS or s[1] != "_":
            raise self.fail("unknown force/moment letter (X Y Z K M N followed by '_')")
        dof = DOFS.index(s[0])
        if s[2:] == "0":
            return Term(self.name, dof)  # a constant force or moment
        self.i = 2
        factors: list[Factor] = []
        accel = None
        while self.i < len(s):
            if self.peek("*"):
                if not factors or self.i + 1 >= len(s) or s[self.i + 1] == "*":
                    raise self.fail("'*' must stand between two factors")
                self.i += 1
                continue
            if self.peek("^"):
                self.power(factors)
                continue
            if self.peek("T(") or self.peek("n("):
                kind = THRUST if s[self.i] == "T" else RATE
                self.i += 2
                factors.append(self.thruster(kind))
            elif self.peek("delta("):
                self.i += 6
                surface = self.named("control surface")
                if surface not in self.surfaces:
                    known = ", ".join(self.surfaces) or "none"
                    raise InputError(
                        f"term {self.name!r}: delta({surface}) names no control surface of the vehicle "
                        f"(control_surfaces: {known})",
                        self.source,
                    )
                factors.append(Factor(DELTA, (self.surfaces.index(surface),)))
            elif self.peek("sqrt("):
                self.i += 5
                idx = [self.vel()]
                self.eat("^2")
                while self.peek("+"):
                    self.i += 1
                    idx.append(self.vel())
                    self.eat("^2")
                self.eat(")")
                if len(idx) < 2:
                    raise self.fail("sqrt of a single velocity (write |v|)")
                if len(idx) > 3:
                    raise self.fail("sqrt of more than three velocities")
                factors.append(Factor(NORM, tuple(idx)))
            elif self.peek("("):
                self.i += 1
                a = self.vel()
                self.eat("/|")
                b = self.vel()
                self.eat("|)")
                if a != b:
                    raise self.fail("a sign factor must divide a velocity by its own magnitude")
                factors.append(Factor(SIGN, (a,)))
            elif self.peek("|"):
                self.i += 1
                a = self.vel()
                self.eat("|")
                factors.append(Factor(ABS, (a,)))
            else:
                a = self.vel()
                if self.peek("dot"):
                    self.i += 3
                    if factors or self.i != len(s):
                        raise self.fail("an acceleration term has no other factor")
                    accel = a
                else:
                    factors.append(Factor(VEL, (a,)))
        if accel is None and not factors:
            raise self.fail("no factor")
        if len(factors) > MAX_FACTORS:
            raise self.fail(f"more than {MAX_FACTORS} factors")
        return Term(self.name, dof, tuple(factors), accel)


def parse_term(
    name: str,
    source: str = "",
    surfaces: tuple[str, ...] | list[str] = (),
    thrusters: tuple[str, ...] | list[str] = (),
    propellers: tuple[str, ...] | list[str] | None = None,
) -> Term:
    """Parse an SNAME term name (see module docstring); InputError names a bad term.

    ``surfaces`` are the names of the vehicle's control surfaces that ``delta(NAME)`` may use,
    ``thrusters`` those of its thrusters (file order) that ``T(NAME)`` may use, and
    ``propellers`` the thrusters with a rotation rate that ``n(NAME)`` may use (None: all).
    """
    if not isinstance(name, str) or not name.strip():
        raise InputError(f"term name {name!r}: expected text like X_uu", source)
    rated = tuple(thrusters) if propellers is None else tuple(propellers)
    return _Parser(name.strip(), source, tuple(surfaces), tuple(thrusters), rated).parse()


@dataclass(frozen=True)
class TermSet:
    """Velocity-dependent terms in array form (for the compiled evaluator).

    dof : (n,) int; coef : (n,) float, SI; kinds : (n, 4) int; idx : (n, 4, 3) int (−1 unused)
    """

    names: tuple[str, ...]
    dof: np.ndarray
    coef: np.ndarray
    kinds: np.ndarray
    idx: np.ndarray

    @staticmethod
    def empty() -> TermSet:
        return TermSet(
            (),
            np.zeros(0, np.int64),
            np.zeros(0),
            np.zeros((0, MAX_FACTORS), np.int64),
            -np.ones((0, MAX_FACTORS, 3), np.int64),
        )

    @staticmethod
    def build(terms: list[tuple[Term, float]]) -> TermSet:
        n = len(terms)
        dof = np.zeros(n, np.int64)
        coef = np.zeros(n)
        kinds = np.zeros((n, MAX_FACTORS), np.int64)
        idx = -np.ones((n, MAX_FACTORS, 3), np.int64)
        for k, (t, c) in enumerate(terms):
            dof[k] = t.dof
            coef[k] = c
            for j, f in enumerate(t.factors):
                kinds[k, j] = f.kind
                for m, i in enumerate(f.indices[:3]):
                    idx[k, j, m] = i
        return TermSet(tuple(t.name for t, _ in terms), dof, coef, kinds, idx)

    def force(self, nu: np.ndarray, delta: np.ndarray | None = None) -> np.ndarray:
        """Σ coef · product, per DOF (N, N·m) at ν_r and the input vector ``delta`` (deflections
        rad, then thrusts N and rotation rates rev/s; module docstring)."""
        out = np.zeros(6)
        d = np.zeros(0) if delta is None else np.asarray(delta, float)
        add_term_forces(self.dof, self.coef, self.kinds, self.idx, np.asarray(nu, float), d, d.shape[0], out)
        return out


def add_term_forces(dof, coef, kinds, idx, nr, delta, n_delta, f):  # noqa: ANN001, ANN201
    """Add Σ coef · product of every term to ``f`` (N, N·m), per DOF, at ν_r = ``nr`` (m/s,
    rad/s) and the input vector ``delta`` (deflections rad, thrusts N, rotation rates rev/s; the
    first ``n_delta`` are real, a missing one is 0).

    The one implementation of the terms: :meth:`TermSet.force` calls it as Python and the
    compiled integrators (:mod:`hydrokit.simulate.compiled`) compile it with numba.
    """
    for k in range(dof.shape[0]):
        prod = coef[k]
        for j in range(kinds.shape[1]):
            kind = kinds[k, j]
            if kind == 0:
                break
            i0 = idx[k, j, 0]
            if kind == VEL:
                prod *= nr[i0]
            elif kind == ABS:
                prod *= abs(nr[i0])
            elif kind == SIGN:
                val = nr[i0]
                prod *= 1.0 if val > 0 else (-1.0 if val < 0 else 0.0)
            elif kind == DELTA or kind == THRUST or kind == RATE:
                prod *= delta[i0] if i0 < n_delta else 0.0
            else:
                ss = 0.0
                for m in range(idx.shape[2]):
                    ii = idx[k, j, m]
                    if ii >= 0:
                        ss += nr[ii] * nr[ii]
                prod *= math.sqrt(ss)
        f[dof[k]] += prod
