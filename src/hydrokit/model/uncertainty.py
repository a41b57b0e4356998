"""Coefficient uncertainty of a vehicle: the ``uncertainty:`` block of a vehicle file.

``hydrokit run`` and ``hydrokit sysid`` write the standard errors of the coefficients they
identified and their covariance; :func:`make_uncertainty` checks such a block and
:meth:`Uncertainty.draw` samples vehicles from it (one seeded generator, so the same seed gives
the same vehicles on any machine). A parameter is named

- ``"<coefficient>.<dof>"`` with coefficient one of ``added_mass`` (kg, kg·m²),
  ``linear_damping`` (N·s/m, N·m·s/rad) or ``quadratic_damping`` (N·s²/m², N·m·s²/rad²) and
  dof one of surge … yaw: a diagonal entry (positive convention);
- ``"terms.<term>"`` with a derivative term of the grammar (:mod:`hydrokit.model.terms`): that
  term's SI coefficient, SNAME signs (``terms.N_r|r|`` in N·m·s²/rad², ``terms.Y_vdot`` in
  kg — for an acceleration term the value is −M_A[dof, acceleration], as ``hydrokit sysid``
  names it). A velocity term must be one of the vehicle's ``terms:``.

Drawn diagonal coefficients below zero are set to 0 (and counted); a term's coefficient keeps
its sign, which the grammar does not fix (X_u|u| < 0 is drag, a cross term may be either).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.errors import InputError
from hydrokit.model.terms import Term, TermSet, parse_term

#: the diagonal coefficients an uncertainty block may name
COEFFICIENTS = ("added_mass", "linear_damping", "quadratic_damping")
#: the prefix of a derivative-term parameter (``terms.N_r|r|``)
TERM_PREFIX = "terms."
#: relative asymmetry, and negative eigenvalue relative to the largest, tolerated in a covariance
#: (the run writes a symmetric matrix; round-off of a hand-made one is no error)
COVARIANCE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ParameterRef:
    """Where a named parameter sits in a vehicle.

    kind : one of :data:`COEFFICIENTS` (diagonal entry ``dof``), ``"accel"`` (−M_A[dof, index])
    or ``"term"`` (the velocity term ``term``); dof : DOF index 0–5 of the force;
    index : the acceleration's velocity index (accel), else ``dof``; term : the parsed term
    """

    kind: str
    dof: int
    index: int
    term: Term | None = None


def check_parameter(name: Any, what: str, source: str, surfaces: tuple[str, ...] = ()) -> ParameterRef:
    """The :class:`ParameterRef` of ``"<coefficient>.<dof>"`` or ``"terms.<term>"``, or an
    error starting with ``what`` (``"field 'uncertainty.parameters[2]' ="``, ``"variation"``).
    ``surfaces`` are the control-surface names a ``delta(NAME)`` factor may use."""
    text = str(name)
    if isinstance(name, str) and text.startswith(TERM_PREFIX) and text[len(TERM_PREFIX) :].strip():
        try:
            term = parse_term(text[len(TERM_PREFIX) :], "", surfaces)
        except InputError as exc:
            raise InputError(f"{what} {text[:80]!r}: {exc}", source) from None
        if term.acceleration is not None:
            return ParameterRef("accel", term.dof, term.acceleration, term)
        return ParameterRef("term", term.dof, term.dof, term)
    coef, _, dof = text.partition(".")
    if not isinstance(name, str) or coef not in COEFFICIENTS or dof not in DOF_NAMES:
        raise InputError(
            f"{what} {text[:80]!r}: expected '<coefficient>.<dof>' with coefficient one of "
            f"{', '.join(COEFFICIENTS)} and dof one of {', '.join(DOF_NAMES)}, or 'terms.<term>' (e.g. terms.N_r|r|)",
            source,
        )
    i = DOF_NAMES.index(dof)
    return ParameterRef(coef, i, i)


def _signature(dof: int, kinds: np.ndarray, idx: np.ndarray) -> tuple[Any, ...]:
    """A term's force DOF and its factors in a fixed order (a product does not depend on the
    order of its factors: N_r|r| and N_|r|r are one term)."""
    factors = sorted((int(k), tuple(int(i) for i in ix)) for k, ix in zip(kinds, idx) if k != 0)
    return (int(dof), tuple(factors))


def term_index(terms: TermSet, term: Term) -> int | None:
    """Position of ``term`` in ``terms`` (the same force DOF and factors, however spelt), or None."""
    one = TermSet.build([(term, 0.0)])
    want = _signature(one.dof[0], one.kinds[0], one.idx[0])
    for k in range(len(terms.names)):
        if _signature(terms.dof[k], terms.kinds[k], terms.idx[k]) == want:
            return k
    return None


def _ref(vehicle: Any, name: str, what: str = "parameter") -> tuple[ParameterRef, int]:
    """The reference of ``name`` in ``vehicle`` and, for a velocity term, its position; errors
    start with ``what``."""
    surfaces = tuple(vehicle.surfaces.names) if getattr(vehicle, "surfaces", None) is not None else ()
    ref = check_parameter(name, what, "", surfaces)
    k = -1
    if ref.kind == "term":
        assert ref.term is not None
        found = term_index(vehicle.terms, ref.term)
        if found is None:
            raise InputError(
                f"{what} {name[:80]!r}: the vehicle {vehicle.name!r} has no such term; expected one of its "
                "'terms:' or an acceleration term"
            )
        k = found
    return ref, k


def parameter_value(vehicle: Any, name: str) -> float:
    """The vehicle's current value of the parameter ``name`` (SI; see the module docstring)."""
    ref, k = _ref(vehicle, name)
    if ref.kind == "added_mass":
        return float(vehicle.M_A[ref.dof, ref.dof])
    if ref.kind == "linear_damping":
        return float(vehicle.D_L[ref.dof, ref.dof])
    if ref.kind == "quadratic_damping":
        return float(vehicle.D_Q[ref.dof])
    if ref.kind == "accel":
        return float(-vehicle.M_A[ref.dof, ref.index])  # SNAME: X_udot = −M_A[0, 0]
    return float(vehicle.terms.coef[k])


def with_coefficients(vehicle: Any, values: Any) -> Any:
    """``vehicle`` with parameters replaced; ``values`` maps ``"<coefficient>.<dof>"`` or
    ``"terms.<term>"`` to the new value (SI, see the module docstring). Everything else is kept."""
    refs = [_ref(vehicle, key, "variation") for key in values]
    return _with(vehicle, refs, list(values.values()))


def _with(vehicle: Any, refs: list[tuple[ParameterRef, int]], values: Any) -> Any:
    M_A, D_L, D_Q = vehicle.M_A.copy(), vehicle.D_L.copy(), np.array(vehicle.D_Q, float)
    coef = None
    for (ref, k), v in zip(refs, values):
        if ref.kind == "added_mass":
            M_A[ref.dof, ref.dof] = v
        elif ref.kind == "linear_damping":
            D_L[ref.dof, ref.dof] = v
        elif ref.kind == "quadratic_damping":
            D_Q[ref.dof] = v
        elif ref.kind == "accel":
            M_A[ref.dof, ref.index] = -v
        else:
            coef = vehicle.terms.coef.copy() if coef is None else coef
            coef[k] = v
    out = replace(vehicle, M_A=M_A, D_L=D_L, D_Q=D_Q)
    return out if coef is None else replace(out, terms=replace(vehicle.terms, coef=coef))


@dataclass(frozen=True, eq=False)
class Uncertainty:
    """Covariance of a vehicle's coefficients (SI, full scale).

    Attributes
    ----------
    parameters : tuple of str — ``"<coefficient>.<dof>"`` or ``"terms.<term>"`` (module
        docstring), one per row of ``covariance``
    covariance : (p, p) — symmetric positive semi-definite, in the squared units of the parameters
    """

    parameters: tuple[str, ...]
    covariance: np.ndarray

    @property
    def std(self) -> np.ndarray:
        """Standard deviation σ of each parameter (SI)."""
        return np.sqrt(np.clip(np.diag(self.covariance), 0.0, None))

    def draw(self, mean: np.ndarray, n: int, seed: int) -> tuple[np.ndarray, int]:
        """``n`` parameter vectors from N(mean, covariance), negative diagonal coefficients set
        to 0 (a ``terms.*`` parameter keeps its sign: the grammar does not fix it).

        One ``numpy.random.default_rng(seed)``; the eigen-decomposition method, so a singular
        covariance (a parameter with σ = 0, or two that move together) is fine.
        Returns the (n, p) samples and how many entries were clipped at zero.
        """
        rng = np.random.default_rng(seed)
        if not self.parameters:
            return np.zeros((n, 0)), 0
        x = rng.multivariate_normal(np.asarray(mean, float), self.covariance, size=n, method="eigh")
        clip = np.array([not str(p).startswith(TERM_PREFIX) for p in self.parameters])
        below = (x < 0) & clip
        x[below] = 0.0
        return x, int(np.sum(below))

    def sample_vehicles(self, vehicle: Any, n: int, seed: int) -> tuple[list[Any], np.ndarray, int]:
        """``n`` copies of ``vehicle`` whose parameters are drawn about its own values.

        Returns the vehicles, the (n, p) drawn values (SI) and the count clipped at zero.
        """
        mean = np.array([parameter_value(vehicle, p) for p in self.parameters], float)
        values, clipped = self.draw(mean, n, seed)
        refs = [_ref(vehicle, p) for p in self.parameters]
        vehicles = [_with(vehicle, refs, row) for row in values]
        return vehicles, values, clipped


def location(ref: ParameterRef) -> tuple[Any, ...]:
    """What a parameter changes: two names with one location (``added_mass.surge`` and
    ``terms.X_udot``, or one term spelt twice) would overwrite each other."""
    if ref.kind == "added_mass":
        return ("M_A", ref.dof, ref.dof)
    if ref.kind == "accel":
        return ("M_A", ref.dof, ref.index)
    if ref.kind == "term":
        assert ref.term is not None
        one = TermSet.build([(ref.term, 0.0)])
        return ("term", _signature(one.dof[0], one.kinds[0], one.idx[0]))
    return (ref.kind, ref.dof)


def make_uncertainty(
    parameters: Any,
    covariance: Any,
    sigma: dict[str, Any],
    source: str,
    terms: TermSet | None = None,
    surfaces: tuple[str, ...] = (),
) -> Uncertainty | None:
    """Check an uncertainty block and build it (None when it states no σ at all).

    Parameters
    ----------
    parameters : list of str — names of the covariance's rows (may be empty):
        ``<coefficient>.<dof>`` or ``terms.<term>`` (module docstring)
    covariance : (p, p) nested lists — SI², symmetric positive semi-definite
    sigma : coefficient → 6 standard errors (SI) per DOF; a σ > 0 whose parameter the
        covariance does not hold is added as an independent parameter; one it holds must
        equal the square root of its diagonal entry (rel. 1e-6)
    source : str — the file named in errors
    terms : TermSet, optional — the vehicle's velocity terms: a ``terms.*`` velocity term must
        be one of them (None: not checked)
    surfaces : tuple of str — control-surface names a ``delta(NAME)`` factor may use

    Raises
    ------
    InputError
        One line naming the field (``uncertainty.covariance``, ``uncertainty.parameters[2]`` …).
    """
    names = list(parameters or [])
    seen: dict[tuple[Any, ...], str] = {}
    for k, name in enumerate(names):
        what = f"field 'uncertainty.parameters[{k}]' ="
        ref = check_parameter(name, what, source, surfaces)
        if ref.kind == "term" and terms is not None and ref.term is not None and term_index(terms, ref.term) is None:
            raise InputError(
                f"{what} {str(name)[:80]!r}: the vehicle has no such term; expected one of its 'terms:' "
                "(or an acceleration term)",
                source,
            )
        where = location(ref)
        if where in seen:
            also = "" if seen[where] == name else f" (as {seen[where]!r})"
            raise InputError(
                f"field 'uncertainty.parameters' names {name!r} twice{also}; expected each parameter once", source
            )
        seen[where] = name
    p = len(names)
    try:
        cov = np.asarray(covariance if covariance is not None else np.zeros((0, 0)), dtype=float)
    except (TypeError, ValueError):
        cov = np.full((1,), np.nan)
    if p == 0 and cov.size == 0:
        cov = np.zeros((0, 0))
    if cov.shape != (p, p) or not np.all(np.isfinite(cov)):
        raise InputError(
            f"field 'uncertainty.covariance': shape {cov.shape}; expected a {p}×{p} matrix of finite numbers "
            "(one row per entry of uncertainty.parameters, SI²)",
            source,
        )
    scale = float(np.max(np.abs(cov), initial=0.0))
    if p and float(np.max(np.abs(cov - cov.T))) > COVARIANCE_TOLERANCE * scale:
        raise InputError("field 'uncertainty.covariance': not symmetric; expected a covariance matrix", source)
    if p and float(np.linalg.eigvalsh(cov).min()) < -COVARIANCE_TOLERANCE * scale:
        raise InputError(
            f"field 'uncertainty.covariance': smallest eigenvalue {float(np.linalg.eigvalsh(cov).min()):.4g}; "
            "expected a positive semi-definite matrix (a covariance)",
            source,
        )
    extra: list[tuple[str, float]] = []
    for coef in COEFFICIENTS:
        for i, s in enumerate(sigma.get(coef) or ()):
            name = f"{coef}.{DOF_NAMES[i]}"
            if name in names:
                stated = math.sqrt(max(cov[names.index(name)][names.index(name)], 0.0))
                if not math.isclose(s, stated, rel_tol=1e-6, abs_tol=1e-300):
                    raise InputError(
                        f"field 'uncertainty.{coef}' = {s:.6g} for {DOF_NAMES[i]}: the covariance gives σ = "
                        f"{stated:.6g}; expected the square root of its diagonal entry",
                        source,
                    )
            elif s > 0:
                extra.append((name, s))
    if extra:
        names += [n for n, _ in extra]
        full = np.zeros((len(names), len(names)))
        full[:p, :p] = cov
        for k, (_, s) in enumerate(extra):
            full[p + k, p + k] = s * s
        cov = full
    if not names:
        return None
    return Uncertainty(tuple(names), 0.5 * (cov + cov.T))
