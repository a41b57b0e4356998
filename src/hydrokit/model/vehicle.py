"""The 6-DOF vehicle (SPEC §3): parameters only, no simulation state.

(M_RB + M_A) ν̇_r + C_RB(ν_r) ν_r + C_A(ν_r) ν_r + D_L ν_r + D_Q(ν_r) ν_r − τ_terms(ν_r) − τ_drag(ν_r)
    + g(η) = τ

M_RB from mass, inertia tensor about the centre of gravity and r_G (Fossen eq. 3.44); M_A a full
6×6 matrix (positive: −X_udot …) plus the acceleration derivative terms; D_L 6×6 (positive);
D_Q the diagonal quadratic damping d_i (force −d_i |ν_i| ν_i); τ_terms the general derivative
terms (SNAME signs: X_uu < 0 is drag); τ_drag the wrench of the point drag elements, each at its
own point's velocity (:mod:`hydrokit.core.drag`, issue #11); g(η) from W at r_G and B at r_B.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit.core.drag import DragElement, pack_elements
from hydrokit.core.rigid_body import rigid_body_mass_matrix
from hydrokit.errors import InputError
from hydrokit.model.envelope import Envelope
from hydrokit.model.identification import Identification
from hydrokit.model.surfaces import SurfaceSet
from hydrokit.model.terms import TermSet
from hydrokit.model.wind import WindModel

#: relative asymmetry of M_RB + M_A tolerated (and symmetrised with a warning); larger is an error
SYMMETRY_TOLERANCE = 1e-3


@dataclass(frozen=True)
class Service:
    """How a vehicle moves at its service speed: the vehicle file's ``service:`` block, flown by
    ``hydrokit manoeuvre`` and ``hydrokit simulate`` when they are given no propulsion.

    Attributes
    ----------
    speed : float — the steady straight-line speed this propulsion reaches, m/s (> 0; stated by
        the file, checked against a run for the bundled vehicles)
    command : tuple of (str, float) — each thruster's held command in its unit (rev/s for a
        propeller, the table's unit for a table curve, N for an ideal thruster), in file order;
        thrusters not named are at 0; empty: no thruster driven
    force : tuple of 6 floats or None — a constant force X, Y, Z (N), K, M, N (N·m) in body
        axes, added to the thrusters' (e.g. the propeller's torque K); None: none
    """

    speed: float
    command: tuple[tuple[str, float], ...] = ()
    force: tuple[float, ...] | None = None

    @property
    def commands(self) -> dict[str, float]:
        """The commands as {thruster name: command} (each in its thruster's unit)."""
        return dict(self.command)

    @property
    def tau(self) -> tuple[float, ...]:
        """The constant force as 6 floats (zeros without one), N and N·m."""
        return self.force if self.force is not None else (0.0,) * 6


@dataclass(frozen=True, eq=False)
class Vehicle:
    """Vehicle parameters (SI, NED body axes). Build with :func:`make_vehicle`.

    Attributes
    ----------
    name : str
    mass : float — kg
    volume : float — displaced volume, m³
    gravity : float — m/s²
    density : float — fluid density, kg/m³
    inertia : (3, 3) — inertia tensor about the centre of gravity, kg·m²
    r_g, r_b : (3,) — centres of gravity and buoyancy from the body origin, m
    M_A : (6, 6) — added mass incl. acceleration terms (positive convention), kg, kg·m, kg·m²
    D_L : (6, 6) — linear damping (positive), N·s/m, N·s, N·m·s/rad
    D_Q : (6,) — quadratic damping d_i (positive), N·s²/m², N·m·s²/rad²
    terms : TermSet — general derivative terms, SI coefficients
    reference_length : float or None — L, m
    warnings : tuple of str — oddities found while building (symmetrised matrices …)
    added_mass_coriolis : bool — include C_A(ν_r) (default). Derivative sets whose cross terms
        already hold the added-mass Coriolis/Munk terms (LI2021 Table 4) set it false.
    drag_elements : tuple of DragElement — point drag elements (positions m, linear N·s/m,
        quadratic N·s²/m², body axes), evaluated at each point's own relative velocity
    thrusters : ThrusterSet or None — the vehicle file's ``thrusters:`` block, when loaded with
        it (:func:`hydrokit.load_vehicle` does); the open-loop model does not use it
    uncertainty : Uncertainty or None — the file's ``uncertainty:`` block (covariance of the
        diagonal coefficients, SI; :mod:`hydrokit.model.uncertainty`); the model does not use it,
        ``--samples`` draws vehicles from it
    provenance : tuple of str — where the coefficients came from, as the vehicle file says
        (``hydrokit run``'s ``project.sources``, a ``source`` or ``sources`` field); exports
        write it into their comments
    surfaces : SurfaceSet — control surfaces (rudders, planes, fins; :mod:`hydrokit.model.surfaces`):
        deflection variables of the ``delta(NAME)`` terms and, where given a fin model, forces of
        their own
    dofs : tuple of int — the degrees of freedom kept (0 surge … 5 yaw); a planar model
        (``dofs: [surge, sway, yaw]``) holds the others at zero and drops their equations
    thruster_names : tuple of str — the ``thrusters:`` block's names in file order, as the
        ``T(NAME)`` and ``n(NAME)`` term factors and a surface's race index them (the input vector
        [δ…, T…, n…], :func:`hydrokit.model.terms.input_layout`); empty when the file has none
    wind : WindModel or None — the file's ``wind:`` block (:mod:`hydrokit.model.wind`): the loads of
        a measured or given wind on the part above the water; None: the wind does not act
    identification : Identification or None — the file's ``identification:`` block, what the fit
        that wrote it claims (:mod:`hydrokit.model.identification`); None: no claim
    service : Service or None — the file's ``service:`` block, how the vehicle moves at its
        service speed (thruster commands and/or a constant force); the model does not use it, the
        manoeuvre and simulate commands fly it when given no propulsion; None: the file states none
    envelope : Envelope or None — the file's ``envelope:`` block, what the identification's runs
        covered (:mod:`hydrokit.model.envelope`); the model does not use it, the manoeuvre and
        simulate commands compare their predictions with it; None: no claim

    A vehicle is equal only to itself (``eq=False``): its fields are arrays, which have no
    single truth value; compare the fields of two vehicles with numpy.
    """

    name: str
    mass: float
    volume: float
    gravity: float
    density: float
    inertia: np.ndarray
    r_g: np.ndarray
    r_b: np.ndarray
    M_A: np.ndarray
    D_L: np.ndarray
    D_Q: np.ndarray
    terms: TermSet = field(default_factory=TermSet.empty)
    reference_length: float | None = None
    warnings: tuple[str, ...] = ()
    added_mass_coriolis: bool = True
    drag_elements: tuple[DragElement, ...] = ()
    thrusters: Any = field(default=None, repr=False)
    uncertainty: Any = field(default=None, repr=False)
    provenance: tuple[str, ...] = field(default=(), repr=False)
    surfaces: SurfaceSet = field(default_factory=SurfaceSet)
    dofs: tuple[int, ...] = (0, 1, 2, 3, 4, 5)
    thruster_names: tuple[str, ...] = ()
    wind: WindModel | None = field(default=None, repr=False)
    identification: Identification | None = field(default=None, repr=False)
    service: Service | None = field(default=None, repr=False)
    envelope: Envelope | None = field(default=None, repr=False)

    @property
    def n_inputs(self) -> int:
        """Length of the input vector [δ…, T…, n…] (deflections, thrusts, rotation rates)."""
        return len(self.surfaces) + 2 * len(self.thruster_names)

    @property
    def planar(self) -> bool:
        """True when some degrees of freedom are dropped."""
        return len(self.dofs) < 6

    @property
    def M_RB(self) -> np.ndarray:
        """Rigid-body mass matrix about the body origin (Fossen eq. 3.44)."""
        return rigid_body_mass_matrix(self.mass, self.inertia, self.r_g)

    @property
    def M_coriolis(self) -> np.ndarray:
        """The mass matrix whose Coriolis matrix enters the model: M_RB + M_A, or M_RB."""
        return self.M_RB + self.M_A if self.added_mass_coriolis else self.M_RB

    @property
    def M(self) -> np.ndarray:
        """M_RB + M_A (symmetric positive definite)."""
        return self.M_RB + self.M_A

    @property
    def drag_packed(self) -> np.ndarray:
        """The drag elements as (n, 9) rows [x, y, z, Lx, Ly, Lz, Qx, Qy, Qz] (m, N·s/m, N·s²/m²)."""
        return pack_elements(self.drag_elements)

    @property
    def weight(self) -> float:
        """W = m g, N."""
        return self.mass * self.gravity

    @property
    def buoyancy(self) -> float:
        """B = ρ g V, N."""
        return self.density * self.gravity * self.volume


def _check_finite(a: np.ndarray, field_name: str, source: str) -> None:
    if not np.all(np.isfinite(a)):
        raise InputError(f"field '{field_name}' holds NaN or infinite values; expected finite numbers", source)


_DRAG_COEFFICIENTS = (("linear", "N·s/m"), ("quadratic", "N·s²/m²"))


def _drag_elements(elements: object, source: str) -> tuple[DragElement, ...]:
    """``elements`` checked (finite; coefficients ≥ 0; unique names) with float tuples."""
    if elements is None:
        return ()
    if isinstance(elements, (str, bytes, dict)) or not isinstance(elements, (list, tuple)):
        raise InputError(f"field 'drag_elements' = {elements!r}: expected a list of DragElement", source)
    out: list[DragElement] = []
    seen: dict[str, int] = {}
    for k, e in enumerate(elements):
        where = f"drag_elements[{k}]"
        if not isinstance(e, DragElement):
            raise InputError(f"field '{where}' = {e!r}: expected a DragElement", source)
        if not isinstance(e.name, str) or not e.name.strip():
            raise InputError(f"field '{where}.name' = {e.name!r}: expected a non-empty name", source)
        if e.name in seen:
            raise InputError(
                f"field '{where}.name' = {e.name!r}: expected a unique name (drag_elements[{seen[e.name]}] has it)",
                source,
            )
        seen[e.name] = k
        values: dict[str, tuple[float, float, float]] = {}
        for attr, unit, nonneg in (("position", "m", False), *((c, u, True) for c, u in _DRAG_COEFFICIENTS)):
            raw = getattr(e, attr)
            try:
                a = np.asarray(raw, dtype=float)
            except (TypeError, ValueError):
                a = np.full(0, np.nan)
            if a.shape != (3,) or not np.all(np.isfinite(a)):
                raise InputError(f"field '{where}.{attr}' = {raw!r}: expected 3 finite numbers ({unit})", source)
            if nonneg and np.any(a < 0):
                raise InputError(
                    f"field '{where}.{attr}' = {a.tolist()}: expected 3 numbers ≥ 0 ({unit}; drag opposes the motion)",
                    source,
                )
            values[attr] = (float(a[0]), float(a[1]), float(a[2]))
        out.append(DragElement(e.name, values["position"], values["linear"], values["quadratic"]))
    return tuple(out)


def make_vehicle(
    name: str,
    mass: float,
    volume: float,
    gravity: float,
    density: float,
    inertia: np.ndarray,
    r_g: np.ndarray,
    r_b: np.ndarray,
    M_A: np.ndarray,
    D_L: np.ndarray,
    D_Q: np.ndarray,
    terms: TermSet | None = None,
    reference_length: float | None = None,
    source: str = "",
    warnings: list[str] | None = None,
    added_mass_coriolis: bool = True,
    drag_elements: tuple[DragElement, ...] | list[DragElement] | None = None,
    uncertainty: Any = None,
    provenance: tuple[str, ...] = (),
    surfaces: SurfaceSet | None = None,
    dofs: tuple[int, ...] | list[int] | None = None,
    thruster_names: tuple[str, ...] = (),
    wind: WindModel | None = None,
    identification: Identification | None = None,
    service: Service | None = None,
    envelope: Envelope | None = None,
) -> Vehicle:
    """Validate and build a :class:`Vehicle`.

    Checks: positive mass, volume, gravity, density; finite arrays; M_RB + M_A symmetric
    (an asymmetry below 0.1 % of the largest entry — e.g. RexROV's 10.774 vs 10.775 — is
    symmetrised with a warning) and positive definite; drag elements with 3 finite numbers
    each for position (m), linear (N·s/m) and quadratic (N·s²/m²), coefficients ≥ 0 (a negative
    one feeds energy in) and unique names; a ``service`` with a speed > 0 m/s, commands naming
    the vehicle's ``thruster_names``, 6 finite numbers of force, and a command or a force.

    Raises
    ------
    InputError
        One line naming the field and the problem.
    """
    warn = list(warnings or [])
    for fname, v in (("mass", mass), ("volume", volume), ("gravity", gravity), ("fluid.density", density)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"field '{fname}' = {v}: expected a positive number", source)
    arrays = {
        "inertia": inertia,
        "center_of_gravity": r_g,
        "center_of_buoyancy": r_b,
        "added_mass": M_A,
        "linear_damping": D_L,
        "quadratic_damping": D_Q,
    }
    for fname, a in arrays.items():
        _check_finite(np.asarray(a, float), fname, source)
    inertia = np.asarray(inertia, float)
    M_A = np.asarray(M_A, float)
    D_L = np.asarray(D_L, float)
    if not np.allclose(inertia, inertia.T, rtol=0, atol=1e-9 * max(1.0, np.abs(inertia).max())):
        raise InputError(f"field 'inertia' = {inertia.tolist()}: expected a symmetric tensor", source)
    try:
        inertia_eig = np.linalg.eigvalsh(inertia)
    except np.linalg.LinAlgError:
        raise InputError(
            "field 'inertia': no eigenvalues; expected a tensor of a realistic size (kg m^2)", source
        ) from None
    if np.any(inertia_eig <= 0):
        raise InputError(f"field 'inertia' = {inertia.tolist()}: expected a positive definite tensor (kg m^2)", source)
    M_RB = rigid_body_mass_matrix(mass, inertia, np.asarray(r_g, float))
    M = M_RB + M_A
    asym = float(np.max(np.abs(M - M.T)))
    scale = float(np.max(np.abs(M)))
    if asym > 0:
        if asym > SYMMETRY_TOLERANCE * scale:
            i, j = np.unravel_index(int(np.argmax(np.abs(M - M.T))), M.shape)
            raise InputError(
                f"field 'added_mass': M_RB + M_A is not symmetric (entry [{i}][{j}] = {M[i, j]:.6g} vs "
                f"[{j}][{i}] = {M[j, i]:.6g}); expected a symmetric matrix",
                source,
            )
        M_A = 0.5 * (M_A + M_A.T)
        warn.append(
            f"added_mass: M_RB + M_A asymmetric by {asym:.3g} (≤ {SYMMETRY_TOLERANCE:g} of the largest entry); symmetrised"
        )
        M = M_RB + M_A
    try:
        if not np.all(np.isfinite(M)):
            raise np.linalg.LinAlgError
        eig = np.linalg.eigvalsh(M)
    except np.linalg.LinAlgError:
        # entries so large that M_RB + M_A overflows, or LAPACK cannot converge on it
        raise InputError(
            f"fields 'mass', 'inertia', 'center_of_gravity', 'added_mass': M_RB + M_A has no eigenvalues "
            f"(largest entry {scale:.4g}); expected values of a realistic size (kg, kg m^2, m)",
            source,
        ) from None
    if eig.min() <= 0:
        raise InputError(
            f"field 'added_mass': M_RB + M_A is not positive definite (smallest eigenvalue {eig.min():.4g}); "
            "expected added-mass magnitudes (−X_udot > 0 …)",
            source,
        )
    elements = _drag_elements(drag_elements, source)
    kept = _dofs(dofs, source)
    D_Q = np.asarray(D_Q, float)
    if np.any(D_Q < 0):
        warn.append(f"quadratic_damping has negative entries {D_Q.tolist()}: energy is fed in at speed")
    return Vehicle(
        name,
        float(mass),
        float(volume),
        float(gravity),
        float(density),
        inertia,
        np.asarray(r_g, float),
        np.asarray(r_b, float),
        M_A,
        D_L,
        D_Q,
        terms if terms is not None else TermSet.empty(),
        reference_length,
        tuple(warn),
        bool(added_mass_coriolis),
        drag_elements=elements,
        uncertainty=uncertainty,
        provenance=tuple(provenance),
        surfaces=surfaces if surfaces is not None else SurfaceSet(),
        dofs=kept,
        thruster_names=tuple(thruster_names),
        wind=wind,
        identification=identification,
        service=_service(service, tuple(thruster_names), source),
        envelope=envelope,
    )


def _service(service: object, thrusters: tuple[str, ...], source: str) -> Service | None:
    """``service`` checked: a speed > 0 m/s, commands naming the vehicle's thrusters, 6 finite
    numbers of force, and something that propels (one line naming the field otherwise)."""
    if service is None:
        return None
    if not isinstance(service, Service):
        raise InputError(f"field 'service' = {service!r}: expected a Service", source)
    if not (isinstance(service.speed, (int, float)) and math.isfinite(service.speed) and service.speed > 0):
        raise InputError(f"field 'service.speed' = {service.speed!r}: expected a speed > 0 (m/s)", source)
    for name, value in service.command:
        if name not in thrusters:
            expected = f"thrusters {', '.join(thrusters)}; expected one of them"
            if not thrusters:
                expected = "no 'thrusters:' block; expected a 'force' only"
            raise InputError(f"field 'service.command.{name}': the vehicle has {expected}", source)
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise InputError(f"field 'service.command.{name}' = {value!r}: expected a finite number", source)
    if service.force is not None:
        f = np.asarray(service.force, dtype=float)
        if f.shape != (6,) or not np.all(np.isfinite(f)):
            raise InputError(f"field 'service.force' = {service.force!r}: expected 6 finite numbers (N, N·m)", source)
    if not service.command and service.force is None:
        raise InputError("field 'service': no 'command' and no 'force'; expected one of them or both", source)
    return Service(float(service.speed), tuple((n, float(c)) for n, c in service.command), _floats(service.force))


def _floats(values: object) -> tuple[float, ...] | None:
    return None if values is None else tuple(float(x) for x in np.asarray(values, dtype=float))


def _dofs(dofs: object, source: str) -> tuple[int, ...]:
    """Kept DOF indices, sorted: surge (0) must stay, none twice, each 0–5."""
    if dofs is None:
        return (0, 1, 2, 3, 4, 5)
    if not isinstance(dofs, (list, tuple)) or not dofs:
        raise InputError(f"field 'dofs' = {dofs!r}: expected a list of DOF indices 0–5", source)
    if any(not isinstance(d, int) or isinstance(d, bool) or not 0 <= d <= 5 for d in dofs):
        raise InputError(f"field 'dofs' = {list(dofs)}: expected DOF indices 0–5", source)
    if len(set(dofs)) != len(dofs):
        raise InputError(f"field 'dofs' = {list(dofs)}: a DOF is repeated", source)
    return tuple(sorted(dofs))
