"""The pieces of system identification that touch the vehicle model (issue #44).

- free parameters named as the ``uncertainty:`` block names them (``added_mass.surge``,
  ``linear_damping.yaw``, ``quadratic_damping.heave``), ``terms.<term>`` for a derivative term
  of the grammar (:mod:`hydrokit.model.terms`; added to the vehicle with value 0 when absent),
  or a field of a physical surface or a thruster (``control_surfaces.rudder.lift_slope``,
  ``thrusters.prop.wake_fraction``) or of the wind-load model (``wind.CD_t``,
  ``wind.coefficients.C_Y.90``; :func:`hydrokit.model.uncertainty.parameter_ref`), read from
  and written into a :class:`~hydrokit.model.vehicle.Vehicle`;
- the generalised force of a run: thruster commands → rotor lag → thrust curve → τ = T f,
  tabulated for the compiled integrator with the zero-order hold of the commands kept exact,
  followed by the vehicle's input vector: the deflections of its control surfaces (rad, held like
  the commands), each thruster's thrust (N) and rotation rate (rev/s), read by the ``T()`` and
  ``n()`` term factors and a race's fin (the compiled kernels' rows [t, X, Y, Z, K, M, N, δ_1 …
  δ_ns, T_1 … T_m, n_1 … n_m], issues #45 and #48); when a thruster's field is free, each
  candidate vehicle's table is built with its own thrusters (:func:`vehicle_tables`);
- many vehicles over one run on the compiled batch RK4, read at each channel's sample times.

Advance speed: the simulation evaluates a propeller's thrust (K_T(J)) at every RK4 stage at the
advance speed of the *simulated* body velocity through the water, V_a = (1 − w) e·(v + ω × r),
from its rotor state, which the table carries after the input vector
(:func:`hydrokit.simulate.compiled.rk4_run`'s drive, :func:`drive_pack`; issue #56) — the model
``simulate --command`` and ``manoeuvre`` fly, so the fitted model is the flown one (the speed
lost in a turn comes from the fitted resistance and the propeller curve together). The table's
own thrust and τ columns hold the thrust at the *measured* velocity (linearly interpolated, an
unmeasured component 0; bollard pull without any): what the equation error uses, where the
state is the measured one, and what the simulation trades for the simulated one. Table and
ideal curves and measured thrusts do not depend on it. (Until issue #56 the simulation too took
the measured velocity's thrust — an input derived from measurements, as in a captive test —
and so fitted a different model from the one flown.)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, Protocol

import numpy as np

from hydrokit.core.names import DOF_NAMES, POSE_SYMBOLS, VELOCITY_SYMBOLS
from hydrokit.errors import InputError
from hydrokit.model.dynamics import pack, stack_scal
from hydrokit.model.terms import MAX_THRUSTERS, TermSet, parse_term
from hydrokit.model.uncertainty import (
    COEFFICIENTS,
    SURFACE_FIELDS,
    SURFACE_PREFIX,
    THRUSTER_FIELDS,
    THRUSTER_PREFIX,
    WIND_PREFIX,
    field_unit,
    parameter_ref,
    parameter_value,
    with_coefficients,
)
from hydrokit.model.vehicle import Vehicle

#: state / channel order (m, rad, m/s, rad/s)
CHANNELS: tuple[str, ...] = (*POSE_SYMBOLS, *VELOCITY_SYMBOLS)
#: SI unit of each diagonal coefficient, translational and rotational DOF
UNITS = {
    "added_mass": ("kg", "kg·m²"),
    "linear_damping": ("N·s/m", "N·m·s/rad"),
    "quadratic_damping": ("N·s²/m²", "N·m·s²/rad²"),
}


class RunData(Protocol):
    """What identification needs of a run (:class:`hydrokit.io.runlog.RunLog` has it).

    A run of a vehicle with control surfaces also has ``deflections`` (surface → (n,) rad on
    every row), read with ``getattr`` so that runs without surfaces need not have it.
    """

    @property
    def name(self) -> str: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def channels(self) -> Mapping[str, tuple[np.ndarray, np.ndarray]]: ...
    @property
    def commands(self) -> Mapping[str, np.ndarray]: ...
    @property
    def thrusts(self) -> Mapping[str, np.ndarray]: ...


@dataclass(frozen=True)
class Parameter:
    """One free parameter.

    name : str — ``added_mass.surge`` …, ``terms.N_r|r|`` or ``control_surfaces.rudder.lift_slope``;
    kind : coefficient name, ``"term"`` / ``"accel"``, or ``"surface"`` / ``"thruster"`` (a
    field); dof : DOF index of the force it enters (0–5; a surface's field yaw, a thruster's
    surge); index : term position in the TermSet, the acceleration's velocity index (accel), or
    the surface's or thruster's position (file order); unit : the unit of the value (SI; a
    ``*_deg`` field in degrees, as the vehicle file gives it)
    """

    name: str
    kind: str
    dof: int
    index: int
    unit: str


def _term_unit(term: Any) -> str:
    """The SI unit of a term's coefficient: its force's over the product of its factors' units
    (``Y_uv`` → N/(m/s)², ``N_ur`` → N·m/((m/s)·(rad/s)), ``Y_uu*delta(rudder)`` →
    N/((m/s)²·rad), ``Y_T(prop)*delta(rudder)`` → N/(N·rad), ``N_0`` → N·m)."""
    from hydrokit.model.terms import DELTA, RATE, SIGN, THRUST

    force = "N" if term.dof < 3 else "N·m"
    if term.acceleration is not None:
        return f"{force}·s²/{'m' if term.acceleration < 3 else 'rad'}"
    powers: dict[str, int] = {}
    for f in term.factors:
        if f.kind == SIGN:
            continue
        unit = {DELTA: "rad", THRUST: "N", RATE: "rev/s"}.get(f.kind, "rad/s" if f.angular else "m/s")
        powers[unit] = powers.get(unit, 0) + 1
    if not powers:
        return force
    sup = {1: "", 2: "²", 3: "³", 4: "⁴"}
    parts = [
        (f"({u})" if "/" in u and (p > 1 or len(powers) > 1) else u) + sup.get(p, f"^{p}") for u, p in powers.items()
    ]
    below = parts[0] if len(parts) == 1 and "/" not in parts[0] else f"({'·'.join(parts)})"
    if len(parts) == 1 and parts[0].startswith("("):
        below = parts[0]
    return f"{force}/{below}"


def valid_names(vehicle: Vehicle) -> list[str]:
    """Every free name ``vehicle`` surely has: the diagonal coefficients of its kept DOFs, its
    own terms (``terms.<term>``; any other term of the grammar is valid too), the fields of its
    physical surfaces and of its thrusters (``control_surfaces.NAME.FIELD``,
    ``thrusters.NAME.FIELD``) and of its wind model (``wind.FIELD``)."""
    kept = [DOF_NAMES[i] for i in vehicle.dofs]
    out = [f"{c}.{d}" for c in COEFFICIENTS for d in kept] + [f"terms.{n}" for n in vehicle.terms.names]
    for s in vehicle.surfaces.surfaces:
        fin = s.fin
        if fin is None:
            continue
        for fld, (_, _, need) in SURFACE_FIELDS.items():
            race = fin.slipstream_diameter > 0
            if not need or (need == "race" and race) or (need == "mmg" and race and fin.inflow == "mmg"):
                out.append(f"{SURFACE_PREFIX}{s.name}.{fld}")
    if vehicle.thrusters is not None:
        out += [f"{THRUSTER_PREFIX}{n}.{f}" for n in vehicle.thrusters.names for f in THRUSTER_FIELDS]
    if vehicle.wind is not None:
        from hydrokit.model.wind import wind_field_names

        out += [WIND_PREFIX + f for f in wind_field_names(vehicle.wind)]
    return out


def nearest_names(name: str, vehicle: Vehicle) -> str:
    """``" (nearest: a, b)"`` — the valid names closest to a bad ``name`` (difflib), or ``""``."""
    import difflib

    near = difflib.get_close_matches(name, valid_names(vehicle), n=3, cutoff=0.6)
    return f" (nearest: {', '.join(near)})" if near else ""


def free_parameters(vehicle: Vehicle, names: Sequence[str], source: str = "--free") -> tuple[Vehicle, list[Parameter]]:
    """Check free names and return the vehicle (with absent velocity terms added at 0) and the
    parameters, in the order given.

    Raises
    ------
    InputError
        A name that is neither ``<coefficient>.<dof>``, ``terms.<term>``,
        ``control_surfaces.NAME.FIELD``, ``thrusters.NAME.FIELD`` nor ``wind.FIELD`` of the
        vehicle (with the nearest valid names), or given twice.
    """
    from hydrokit.model.terms import MAX_FACTORS

    out: list[Parameter] = []
    terms = vehicle.terms
    if not names:
        raise InputError("no free parameter; expected names like added_mass.surge,linear_damping.yaw", source)
    for raw in names:
        name = str(raw).strip()
        if any(p.name == name for p in out):
            raise InputError(f"free parameter {name!r} is named twice; expected each once", source)
        head, _, rest = name.partition(".")
        if head in COEFFICIENTS and rest in DOF_NAMES:
            i = DOF_NAMES.index(rest)
            out.append(Parameter(name, head, i, i, UNITS[head][i >= 3]))
            continue
        if name.startswith((SURFACE_PREFIX, THRUSTER_PREFIX, WIND_PREFIX)):
            try:
                ref = parameter_ref(vehicle, name)
            except InputError as exc:
                raise InputError(f"{exc.detail}{nearest_names(name, vehicle)}", source) from None
            out.append(Parameter(name, ref.kind, ref.dof, ref.index, field_unit(name)))
            continue
        if head != "terms" or not rest:
            raise InputError(
                f"free parameter {name[:80]!r} does not exist{nearest_names(name, vehicle)}; expected "
                f"'<coefficient>.<dof>' with coefficient one of {', '.join(COEFFICIENTS)} and dof one of "
                f"{', '.join(DOF_NAMES)}, 'terms.<term>' (e.g. terms.N_r|r|), "
                "'control_surfaces.<name>.<field>', 'thrusters.<name>.<field>' or 'wind.<field>'",
                source,
            )
        try:
            term = parse_term(rest, f"{source} {name}", vehicle.surfaces.names, vehicle.thruster_names)
        except InputError as exc:
            raise InputError(f"{exc.detail}{nearest_names(name, vehicle)}", exc.source) from None
        if term.acceleration is not None:
            out.append(Parameter(name, "accel", term.dof, term.acceleration, _term_unit(term)))
            continue
        if term.name not in terms.names:
            k = len(terms.names)
            kinds = np.zeros((1, MAX_FACTORS), np.int64)
            idx = -np.ones((1, MAX_FACTORS, 3), np.int64)
            built = TermSet.build([(term, 0.0)])
            kinds[:], idx[:] = built.kinds, built.idx
            terms = TermSet(
                (*terms.names, term.name),
                np.concatenate([terms.dof, built.dof]),
                np.concatenate([terms.coef, [0.0]]),
                np.concatenate([terms.kinds, kinds]),
                np.concatenate([terms.idx, idx]),
            )
        else:
            k = terms.names.index(term.name)
        out.append(Parameter(name, "term", term.dof, k, _term_unit(term)))
    return replace(vehicle, terms=terms), out


def values_of(vehicle: Vehicle, params: Sequence[Parameter]) -> np.ndarray:
    """The vehicle's current value of each parameter (SI;
    :func:`hydrokit.model.uncertainty.parameter_value`, the one reader of the names)."""
    return np.array([parameter_value(vehicle, p.name) for p in params], dtype=float)


def with_values(vehicle: Vehicle, params: Sequence[Parameter], values: Any) -> Vehicle:
    """``vehicle`` with each parameter set to ``values`` (SI); nothing else changes
    (:func:`hydrokit.model.uncertainty.with_coefficients`)."""
    vals = np.asarray(values, float)
    return with_coefficients(vehicle, {p.name: float(v) for p, v in zip(params, vals)})


# ------------------------------------------------------------------------------ inputs
#: where a held input's jump lies in a force table: between t_k and t_k + JUMP · dt (s)
JUMP = 1e-6


def held_offset(dt: float) -> float:
    """How far after a step's start its first stage reads a force table of step ``dt`` (s): past
    a jump node's pair (:data:`JUMP`), so that a held input changing at the step's start reaches
    all four stages (:func:`hydrokit.simulate.compiled.rk4_run`)."""
    return 2.0 * JUMP * dt


def force_table(
    run: RunData, thrusters: Any, dt: float, surfaces: Sequence[str] | None = None, advance: bool = True
) -> np.ndarray:
    """The generalised thruster force of a run and its input vector as rows
    [t, X, Y, Z, K, M, N, δ_1 … δ_ns, T_1 … T_m, n_1 … n_m] (s, N, N·m, rad, N, rev/s).

    Parameters
    ----------
    run : the run (commands on every row; ``deflections`` surface → rad on every row, if any)
    thrusters : ThrusterSet — the vehicle's thrusters
    dt : float — integration step, s
    surfaces : sequence of str or None — the vehicle's control-surface names, file order: the δ
        columns in that order, each required in ``run.deflections``, then each thruster's
        thrust T (N) and rotation rate n (rev/s) — the vehicle's input vector
        (:func:`hydrokit.model.terms.input_layout`; up to MAX_THRUSTERS thrusters). None: the
        run's deflections in their own order (as :func:`hydrokit.io.runlog.read_run` gives
        them), no thrust or rate columns
    advance : bool — evaluate propeller curves at the measured advance speed (module
        docstring); False: at zero advance speed (bollard pull)

    Each command row is held until the next row (zero-order hold); the rotor follows it with
    its first-order lag τ ċ = c_target − c (:meth:`~hydrokit.model.thrusters.ThrusterSet.rotor_step`,
    exact over each interval), starting settled at the first command; the thrust is the curve
    at the lagged command, within the thrust limits; τ = T f with T the configuration matrix.
    Measured thrust columns (``thrust:NAME``) are held as given. Nodes lie every ``dt/2`` from
    the first row (the RK4 stages of step ``dt``, where the table is then exact) and at every
    row where an input changes, doubled there (t and t + :data:`JUMP`·dt) so that the linear
    interpolation of the compiled integrator reproduces a jump exactly: the node at the row keeps
    the value held up to it (the last stage of the step ending there), and the integrator reads
    the first stage of the step starting there :func:`held_offset` later, past the jump
    (:func:`hydrokit.simulate.compiled.rk4_run`'s ``held``) — every stage of that step sees the
    row's value, a zero-order hold (before, its first stage, a sixth of the step, saw the old one:
    an error of the order of dt, 0.4 σ at 10 ms on a ship's zigzags). Deflections are held
    (zero-order) the same way, without a servo: they are the surfaces' logged angles. The rate
    of a propeller is its lagged command (a measured thrust's: the curve inverted at the advance
    speed, :meth:`~hydrokit.model.thrusters.ThrusterSet.rotation_rate`), of another thruster 0.
    """
    from hydrokit.model.thrusters import PropellerCurve
    from hydrokit.sysid.kernels import rotor_nodes, rotor_rows

    t = np.asarray(run.time, float)
    deflections: Mapping[str, np.ndarray] = getattr(run, "deflections", None) or {}
    inputs = surfaces is not None  # the vehicle's layout is known: its input vector follows
    if surfaces is None:
        surfaces = list(deflections)
    for s_name in surfaces:
        if s_name not in deflections:
            raise InputError(
                f"run {run.name}: no deflection for control surface '{s_name}'; expected a column '{s_name}' (rad)"
            )
    defl = np.zeros((t.size, len(surfaces)))
    for j, s_name in enumerate(surfaces):
        defl[:, j] = deflections[s_name]
    names = thrusters.names
    m = len(names)
    cmd = np.zeros((t.size, m))
    measured = np.zeros(m, bool)
    for i, n in enumerate(names):
        if n in run.commands:
            cmd[:, i] = run.commands[n]
        elif n in run.thrusts:
            cmd[:, i] = run.thrusts[n]
            measured[i] = True
        else:
            raise InputError(f"run {run.name}: no input for thruster '{n}'")
    change = np.nonzero(np.any(np.diff(np.hstack([cmd, defl]), axis=0) != 0, axis=1))[0] + 1
    eps = JUMP * dt
    # nodes every dt/2 from the first row: RK4 evaluates the force only there, where linear
    # interpolation between nodes returns the exact node value
    grid = t[0] + 0.5 * dt * np.arange(int(np.floor((t[-1] - t[0]) / (0.5 * dt) + 1e-9)) + 1)
    nodes = np.unique(np.concatenate([grid, t[change], t[change] + eps, t[-1:]]))
    seg = np.clip(np.searchsorted(t, nodes, side="right") - 1, 0, t.size - 1)
    # the rotor state at each row (exact over each held interval), then at every node from the
    # row before it
    # (ThrusterSet.rotor_step's law, rotor_lag, compiled: a loop over the rows and the nodes)
    target = np.ascontiguousarray(np.clip(cmd, thrusters.command_min, thrusters.command_max))
    tc = np.ascontiguousarray(thrusters.time_constants, dtype=float)
    c_row = np.empty((t.size, m))
    c_row[0] = target[0]
    rotor_rows(target, np.ascontiguousarray(t), tc, c_row)
    # a node exactly at a row takes the rotor state arriving there (held target of the row before)
    at_row = np.isin(nodes, t)
    c = np.empty((nodes.size, m))
    rotor_nodes(c_row[seg], target[seg], np.ascontiguousarray(nodes - t[seg]), tc, c)
    c[at_row] = c_row[seg[at_row]]
    f = np.empty_like(c)
    va = _advance_speeds(run, thrusters, nodes) if advance else np.zeros((nodes.size, m))
    jump = np.isin(nodes, t[change])
    for i, cv in enumerate(thrusters.curves):
        if measured[i]:
            f[:, i] = cmd[seg, i]
            # the held thrust changes at the row itself: node t_k keeps the old value
            f[jump, i] = cmd[np.maximum(seg[jump] - 1, 0), i]
            continue
        ci = np.clip(c[:, i], thrusters.command_min[i], thrusters.command_max[i])
        thrust = curve_thrusts(cv, ci, va[:, i])
        f[:, i] = np.clip(thrust, thrusters.f_min[i], thrusters.f_max[i])
    tau = f @ thrusters.configuration_matrix().T
    d = defl[seg]
    d[jump] = defl[np.maximum(seg[jump] - 1, 0)]  # held: node t_k keeps the old deflection
    if not inputs or m > MAX_THRUSTERS:
        return np.column_stack([nodes, tau, d])
    # the driven propellers' rotor states, after the input vector: the batch RK4 evaluates their
    # thrust at each stage's simulated advance speed (simulate_run, issue #56)
    drv = driven(run, thrusters)
    rotor = np.clip(c[:, drv], thrusters.command_min[drv], thrusters.command_max[drv])
    rate = np.zeros_like(f)
    for i, cv in enumerate(thrusters.curves):
        if not isinstance(cv, PropellerCurve):
            continue
        if not measured[i]:
            rate[:, i] = np.clip(c[:, i], thrusters.command_min[i], thrusters.command_max[i])
            continue
        for k in range(nodes.size):  # a measured thrust's rate: the curve inverted at V_a
            one = np.zeros(m)
            one[i] = f[k, i]
            rate[k, i] = thrusters.command_for_thrust(one, va[k])[i]
    return np.column_stack([nodes, tau, d, f, rate, rotor])


def driven(run: RunData, thrusters: Any) -> list[int]:
    """The thrusters (file order) of ``run`` whose thrust the simulation evaluates at the
    simulated state: propeller curves under commands (not a measured thrust)."""
    from hydrokit.model.thrusters import PropellerCurve

    return [
        i
        for i, (n, cv) in enumerate(zip(thrusters.names, thrusters.curves))
        if isinstance(cv, PropellerCurve) and n in run.commands
    ]


def drive_pack(prep: PreparedRun, vehicles: Sequence[Vehicle]) -> tuple[np.ndarray, ...]:
    """The batch RK4's driven propellers over ``prep`` for ``vehicles``
    (:func:`hydrokit.simulate.compiled.drive_member`): value indices [rotor state, thrust, rate]
    in the table, the thruster indices, each vehicle's wake factor 1 − w and configuration
    columns, and the curves' constants and limits; no driven propeller when the table holds no
    rotor columns (no input vector, or more than MAX_THRUSTERS thrusters) or the run is not at
    hand."""
    from hydrokit.model.thrusters import PropellerCurve
    from hydrokit.simulate.compiled import no_drive_batch

    nv = len(vehicles)
    th = vehicles[0].thrusters if nv else None
    if th is None or prep.run is None or prep.surfaces is None:
        return no_drive_batch(nv)
    drv = driven(prep.run, th)
    m, ns = len(th), len(prep.surfaces)
    if not drv or prep.table.shape[1] != 1 + 6 + ns + 2 * m + len(drv):
        return no_drive_batch(nv)
    curves = [th.curves[i] for i in drv]
    assert all(isinstance(cv, PropellerCurve) for cv in curves)
    n_poly = max(max(len(cv.law_args[4]), len(cv.law_args[5])) for cv in curves)  # type: ignore[attr-defined]
    kf, kr, prop = np.zeros((len(drv), n_poly)), np.zeros((len(drv), n_poly)), np.zeros((len(drv), 6))
    for j, cv in enumerate(curves):
        D, rho, jlo, jhi, k_f, k_r, lf, lr = cv.law_args  # type: ignore[attr-defined]
        prop[j] = (D, rho, jlo, jhi, lf, lr)
        kf[j, n_poly - len(k_f) :] = k_f  # leading zeros keep Horner's value
        kr[j, n_poly - len(k_r) :] = k_r
    lim = np.column_stack([th.command_min[drv], th.command_max[drv], th.f_min[drv], th.f_max[drv]])
    wake = np.array([[v.thrusters._wake_factor[i] for i in drv] for v in vehicles], dtype=float)
    Tv = np.array([v.thrusters.configuration_matrix()[:, drv] for v in vehicles], dtype=float)
    cols = np.array([6 + ns + 2 * m, 6 + ns, 6 + ns + m], dtype=np.int64)
    f64 = lambda a: np.ascontiguousarray(a, dtype=float)  # noqa: E731
    return (
        cols, np.array(drv, dtype=np.int64), f64(wake), f64(th.directions[drv]), f64(th._moment_arms[drv]), f64(Tv),
        f64(prop), f64(kf), f64(kr), f64(lim),
    )  # fmt: skip


def curve_thrusts(curve: Any, command: np.ndarray, advance_speed: np.ndarray) -> np.ndarray:
    """The thrust (N) of one thruster's ``curve`` at each ``command`` (its unit) and advance
    speed (m/s): ``type(curve).thrust_batch`` — for a table curve its law
    (:func:`~hydrokit.model.thrusters.table_interp`) compiled and looped over the nodes, equal bit
    for bit. A propeller curve keeps its Python law: compiled, its D⁴ is a product rather than
    ``pow`` (an ulp apart), which moved the windows bench's unidentifiable X_vr, X_vv, X_rr by
    0.003 σ."""
    from hydrokit.model.thrusters import IdealCurve, TableCurve
    from hydrokit.sysid.kernels import as_array, table_thrusts

    x = np.ascontiguousarray(command, dtype=float)
    out = np.empty(x.size)
    if type(curve) is TableCurve:
        table_thrusts(x, as_array(curve.commands), as_array(curve.thrusts), out)
        return out
    if type(curve) is IdealCurve:
        return x.copy()
    return np.asarray(
        type(curve).thrust_batch([curve] * x.size, x, np.ascontiguousarray(advance_speed, dtype=float)), float
    )


def _advance_speeds(run: RunData, thrusters: Any, nodes: np.ndarray) -> np.ndarray:
    """(k, m) advance speed of every thruster at ``nodes`` from the run's measured body velocity
    (linear between samples, held beyond; unmeasured components 0), m/s."""
    nu = np.zeros((nodes.size, 6))
    for j, c in enumerate(VELOCITY_SYMBOLS):
        if c in run.channels:
            ts, ys = run.channels[c]
            if np.size(ts):
                nu[:, j] = np.interp(nodes, ts, ys)
    # V_a is linear in ν: its matrix from the unit velocities
    A = np.column_stack([thrusters.advance_speed(e) for e in np.eye(6)])
    return nu @ A.T


# ------------------------------------------------------------------------------ simulation
@dataclass(frozen=True)
class PreparedRun:
    """A run ready for the batch integrator.

    name : str; t0 : float — s; duration : float — s; table : (k, 7 + n_surfaces) force and
    deflection rows (s, N, N·m, rad), time from t0;
    channels : tuple of channel names; times : per channel sample times from t0 (s);
    values : per channel measured values (SI); dt : float — integration step, s;
    env : (k, 4 or 6) the run's logged current and wind (rows [t, v_N, v_E, v_D, w_N, w_E], m/s,
    time from t0; :meth:`hydrokit.io.runlog.RunLog.environment_table`), None: still water and air;
    run, surfaces : the run and the surface names the table was built from (None: the table is
    all there is); thruster_key : the thrusters' wake fractions and thrust deductions it was
    built with (:func:`vehicle_tables` rebuilds it for a vehicle whose differ)
    """

    name: str
    t0: float
    duration: float
    table: np.ndarray
    channels: tuple[str, ...]
    times: tuple[np.ndarray, ...]
    values: tuple[np.ndarray, ...]
    dt: float
    env: np.ndarray | None = None
    run: Any = None
    surfaces: tuple[str, ...] | None = None
    thruster_key: tuple[float, ...] = ()

    def env_from(self, a: float) -> np.ndarray | None:
        """The environment table with time from ``a`` s after t0 (a window's), None for none."""
        if self.env is None:
            return None
        tab = self.env.copy()
        tab[:, 0] -= a
        return tab

    @property
    def n_samples(self) -> int:
        return int(sum(t.size for t in self.times))

    @property
    def measured(self) -> np.ndarray:
        """All measured values, channel after channel (SI)."""
        return np.concatenate(self.values)


def prepare_run(
    run: RunData,
    thrusters: Any,
    dt: float,
    t_start: float | None = None,
    t_end: float | None = None,
    surfaces: Sequence[str] | None = None,
) -> PreparedRun:
    """Force table and samples of ``run`` (optionally its window [t_start, t_end], s);
    ``surfaces``: the vehicle's control-surface names (:func:`force_table`)."""
    t = np.asarray(run.time, float)
    a = float(t[0] if t_start is None else t_start)
    b = float(t[-1] if t_end is None else t_end)
    table = force_table(run, thrusters, dt, surfaces)
    table = table[(table[:, 0] >= a - dt) & (table[:, 0] <= b + dt)].copy()
    table[:, 0] -= a
    chans, times, values = [], [], []
    for c in CHANNELS:
        if c not in run.channels:
            continue
        ts, ys = run.channels[c]
        keep = (ts >= a) & (ts <= b)
        if np.any(keep):
            chans.append(c)
            times.append(np.asarray(ts[keep], float) - a)
            values.append(np.asarray(ys[keep], float))
    env = run.environment_table() if hasattr(run, "environment_table") else None
    if env is not None:
        env = env.copy()
        env[:, 0] -= a
    return PreparedRun(
        run.name,
        a,
        b - a,
        table,
        tuple(chans),
        tuple(times),
        tuple(values),
        dt,
        env,
        run,
        None if surfaces is None else tuple(surfaces),
        thruster_key(thrusters),
    )


def thruster_key(thrusters: Any) -> tuple[float, ...]:
    """The thruster fields a force table depends on that a fit may free: every thruster's wake
    fraction and thrust deduction (–)."""
    if thrusters is None:
        return ()
    return tuple(float(getattr(t, f)) for t in thrusters.thrusters for f in THRUSTER_FIELDS)


def vehicle_tables(prep: PreparedRun, vehicles: Sequence[Vehicle]) -> np.ndarray | None:
    """Each vehicle's force table over ``prep`` (nv, k, columns) when a vehicle's thrusters
    differ from those ``prep.table`` was built with (a free ``thrusters.NAME.FIELD``: the wake
    fraction moves the advance speed and so the thrust, the thrust deduction the force); None
    when all share ``prep.table`` or the run is not at hand. Vehicles with equal thrusters
    share one build."""
    keys = [thruster_key(v.thrusters) for v in vehicles]
    if prep.run is None or all(k == prep.thruster_key for k in keys):
        return None
    a, b = prep.t0, prep.t0 + prep.duration
    built: dict[tuple[float, ...], np.ndarray] = {prep.thruster_key: prep.table}
    out = []
    for v, key in zip(vehicles, keys):
        if key not in built:
            tab = force_table(prep.run, v.thrusters, prep.dt, prep.surfaces)
            tab = tab[(tab[:, 0] >= a - prep.dt) & (tab[:, 0] <= b + prep.dt)].copy()
            tab[:, 0] -= a
            built[key] = tab
        out.append(built[key])
    return np.ascontiguousarray(np.stack(out))


def stack_packs(vehicles: Sequence[Vehicle]) -> dict[str, Any]:
    """The compiled integrator's per-vehicle arrays for ``vehicles`` (one term structure), and
    the vehicles themselves (``"vehicles"``, an object array: their thrusters build the force
    tables, :func:`vehicle_tables`)."""
    packs = [pack(v) for v in vehicles]
    held = np.empty(len(vehicles), dtype=object)
    held[:] = list(vehicles)

    def stack(name: str) -> np.ndarray:
        return np.ascontiguousarray(np.stack([getattr(p, name) for p in packs]))

    return {
        "Minv": stack("Minv"),
        "Mc": stack("Mc"),
        "DL": stack("DL"),
        "DQ": stack("DQ"),
        "scal": stack_scal([p.scal for p in packs]),
        "t_dof": packs[0].t_dof,
        "t_coef": stack("t_coef"),
        "t_kind": packs[0].t_kind,
        "t_idx": packs[0].t_idx,
        "vehicles": held,
    }


#: the stacked per-vehicle arrays of :func:`stack_packs`, in the order of the compiled right-hand
#: side's packed tuple (:attr:`hydrokit.model.dynamics.Packed.V`)
VEHICLE_KEYS = ("Minv", "Mc", "DL", "DQ", "scal", "t_dof", "t_coef", "t_kind", "t_idx")


def vehicle_arrays(packs: Mapping[str, Any]) -> tuple[np.ndarray, ...]:
    """The stacked packs as the batch integrators' one tuple (V_all)."""
    return tuple(packs[k] for k in VEHICLE_KEYS)


def take(packs: Mapping[str, Any], index: Sequence[int]) -> dict[str, Any]:
    """The stacked arrays of the vehicles ``index`` (repeats allowed)."""
    ix = np.asarray(index, int)
    shared = ("t_dof", "t_kind", "t_idx")
    return {k: (v if k in shared else np.ascontiguousarray(v[ix])) for k, v in packs.items()}


def read_columns(packs: Mapping[str, Any], n_columns: int) -> int:
    """How many of a force table's ``n_columns`` columns [t, X … N, δ…, T…, n…] the vehicles of
    ``packs`` read: up to their deflections when no term has a thrust or rotation-rate factor
    (``T()``, ``n()``) and no control surface is a physical fin (whose slipstream reads a thrust);
    all of them otherwise, or when the vehicles are not at hand. A column past the end reads as
    0, as a missing input does (:func:`hydrokit.model.terms.add_term_forces`), and only these
    read the T and n columns."""
    from hydrokit.model.terms import RATE, THRUST
    from hydrokit.model.thrusters import PropellerCurve

    vehicles = packs.get("vehicles")
    if vehicles is None or len(vehicles) == 0:
        return n_columns
    if any(isinstance(cv, PropellerCurve) for cv in getattr(vehicles[0].thrusters, "curves", ())):
        return n_columns  # a propeller's thrust is evaluated at the simulated state: its rotor columns
    kinds = np.asarray(packs["t_kind"])
    if np.any((kinds == THRUST) | (kinds == RATE)):
        return n_columns
    if any(s.fin is not None for v in vehicles for s in v.surfaces.surfaces):
        return n_columns
    return min(n_columns, 7 + max(len(v.surfaces.names) for v in vehicles))


def simulate_run(prep: PreparedRun, packs: Mapping[str, Any], x0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every vehicle of ``packs`` over ``prep`` from its initial state ``x0`` (nv, 12).

    Returns the predictions (nv, n_samples) at the sample times, channel after channel, linearly
    interpolated between integration steps, and the steps each vehicle took (fewer: it diverged).
    """
    from hydrokit.simulate.compiled import no_drive_batch, rk4_batch
    from hydrokit.sysid.kernels import sample_states

    x0 = np.ascontiguousarray(x0, dtype=float)
    nv = x0.shape[0]
    dt = prep.dt
    n_steps = max(1, int(math.ceil(prep.duration / dt - 1e-9)))
    out = np.empty((nv, n_steps + 1, 12))  # the steps a vehicle did not take are NaN (below)
    done = np.empty(nv, dtype=np.int64)
    own = vehicle_tables(prep, list(packs["vehicles"])) if "vehicles" in packs else None
    # one table for all vehicles unless their thrusters differ (a copy per vehicle cost more than
    # the fit's linear algebra), cut to the columns the vehicles read (the integrator interpolates
    # every column at every stage)
    k = read_columns(packs, prep.table.shape[1])
    tab = np.ascontiguousarray(own[:, :, :k] if own is not None else prep.table[None, :, :k])
    vehicles = packs.get("vehicles")
    drive = drive_pack(prep, list(vehicles)) if vehicles is not None and k == prep.table.shape[1] else None
    rk4_batch(
        x0,
        float(dt),
        n_steps,
        1,
        False,
        tab,
        np.zeros((1, 4)) if prep.env is None else np.ascontiguousarray(prep.env),
        vehicle_arrays(packs),
        drive if drive is not None else no_drive_batch(nv),
        out,
        done,
        held_offset(float(dt)),
    )
    for v in np.nonzero(done < n_steps)[0]:
        out[v, done[v] + 1 :] = np.nan
    state, i0, w = [], [], []
    for c, ts in zip(prep.channels, prep.times):
        pos = ts / dt
        i = np.clip(np.floor(pos).astype(np.int64), 0, n_steps - 1)
        state.append(np.full(ts.size, CHANNELS.index(c), dtype=np.int64))
        i0.append(i)
        w.append(pos - i)
    pred = np.empty((nv, sum(a.size for a in i0)))
    sample_states(out, np.concatenate(state), np.concatenate(i0), np.concatenate(w), pred)
    return pred, done
