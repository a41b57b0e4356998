"""The curated top-level API: the whole chain with a dozen names.

Everything here is re-exported lazily by ``hydrokit`` (``hydrokit.load_vehicle`` …), so
``import hydrokit`` stays light. These functions are glue: they read files through ``io``
when given paths and call the library layers (``identify``, ``estimate``, ``model``,
``simulate``); each returns a result object with ``to_dict()``, ``plot(ax=None)`` and a
notebook view. Units are SI and radians throughout.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from hydrokit.errors import InputError

if TYPE_CHECKING:  # pragma: no cover - imports for annotations only
    from hydrokit.estimate.forces import ForceFit
    from hydrokit.estimate.geometry import Estimate, Geometry
    from hydrokit.identify.result import CampaignResult
    from hydrokit.identify.types import Launch, Rig
    from hydrokit.model.allocation import Allocation
    from hydrokit.model.assembly import Assembly
    from hydrokit.model.mission import Mission
    from hydrokit.model.thrusters import ThrusterSet
    from hydrokit.model.vehicle import Service, Vehicle
    from hydrokit.simulate.batch import BatchTrajectory
    from hydrokit.simulate.driver import Trajectory
    from hydrokit.simulate.fleet import FleetResult
    from hydrokit.simulate.mission import MissionResult
    from hydrokit.simulate.transport import TransportResult
    from hydrokit.sysid.fit import SysidResult

PathLike = str | os.PathLike[str]


def load_vehicle(name_or_path: PathLike) -> Vehicle:
    """Read a vehicle file or bundled vehicle, with its ``thrusters:`` block when it has one.

    Parameters
    ----------
    name_or_path : str or path — a vehicle YAML file, or a bundled name (``bluerov2-heavy``,
        ``minerva``, ``lingyun``, ``lingyun-diagonal``, ``udrobot``)

    Returns
    -------
    Vehicle — SI parameters; ``vehicle.thrusters`` is a ThrusterSet or None

    Examples
    --------
    >>> import hydrokit
    >>> v = hydrokit.load_vehicle("bluerov2-heavy")
    >>> v.mass, len(v.thrusters)
    (13.5, 8)
    """
    from hydrokit.io.vehicle import resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml

    path = resolve_vehicle(name_or_path)
    return vehicle_from_dict(read_yaml(path), str(path))


def vehicle_from_dict(data: dict[str, Any], source: str = "vehicle") -> Vehicle:
    """A Vehicle (with its ``thrusters:`` block) from a vehicle-file mapping already in memory.

    Parameters
    ----------
    data : dict — the fields of a vehicle file (SI, see docs/model.md)
    source : str — named in error messages

    Examples
    --------
    >>> import hydrokit, yaml
    >>> from hydrokit.io.vehicle import resolve_vehicle
    >>> doc = yaml.safe_load(resolve_vehicle("minerva").read_text())
    >>> doc["added_mass"][0] = 2 * doc["added_mass"][0]
    >>> bool(hydrokit.vehicle_from_dict(doc).M_A[0, 0] == 2 * hydrokit.load_vehicle("minerva").M_A[0, 0])
    True
    """
    from hydrokit.io.thrusters import parse_thrusters
    from hydrokit.io.vehicle import parse_vehicle

    vehicle = parse_vehicle(data, source)
    if data.get("thrusters"):
        vehicle = replace(vehicle, thrusters=parse_thrusters(data, source))
        _check_service_commands(vehicle, source)
    return vehicle


def _check_service_commands(vehicle: Vehicle, source: str) -> None:
    """Each command of the ``service:`` block within its thruster's command limits (one line
    naming the field, the value and the limits, in the thruster's unit)."""
    from hydrokit.simulate.commands import thruster_commands

    if vehicle.service is not None and vehicle.service.command:
        try:
            thruster_commands(vehicle, vehicle.service.commands)
        except InputError as exc:
            raise InputError(f"field 'service.command': {exc}", source) from None


def service_propulsion(vehicle: Vehicle, tau: Any = None, commands: Any = None) -> Service | None:
    """The vehicle's service condition when the caller gives no propulsion, else None.

    No propulsion is no thruster ``commands`` and ``tau`` None or six zeros (N, N·m); a non-zero
    constant, a force table or a callable ``tau`` is the caller's propulsion, flown as given.

    Parameters
    ----------
    vehicle : Vehicle — its ``service`` (the file's ``service:`` block) or None
    tau : None, 6 floats (N, N·m), rows [t, X … N] or a callable — the caller's force
    commands : None or {thruster name: command} — the caller's thruster commands

    Returns
    -------
    Service or None — what to fly instead (``service.commands`` in each thruster's unit,
    ``service.tau`` in N and N·m, reaching ``service.speed`` m/s); None when the caller gave
    propulsion or the vehicle states no service condition
    """
    if vehicle.service is None or commands is not None or callable(tau):
        return None
    if tau is not None:
        import numpy as np

        f = np.asarray(tau, dtype=float)
        if f.shape != (6,) or np.any(f != 0.0):
            return None
    return vehicle.service


def with_service(vehicle: Vehicle, options: dict[str, Any]) -> tuple[dict[str, Any], Service | None]:
    """``options`` of :func:`manoeuvre` with the vehicle's service condition filled in when they
    give no propulsion (:func:`service_propulsion`): ``tau`` its force, ``commands`` its thruster
    commands, and ``nu0`` (when not given) its speed ahead, so the approach starts where it ends.
    Returns the options (a new dict) and the service flown (None: the options unchanged)."""
    service = service_propulsion(vehicle, options.get("tau"), options.get("commands"))
    if service is None:
        return dict(options), None
    out = {**options, "tau": service.tau, "commands": service.commands or None}
    if out.get("nu0") is None:
        out["nu0"] = (service.speed, 0.0, 0.0, 0.0, 0.0, 0.0)
    return out, service


def load_rig(path: PathLike) -> Rig:
    """Read a rig file (spring, pendulum or torsion test; SI units; see docs/identify.md)."""
    from hydrokit.io.rig import load_rig as _load

    return _load(path)


def load_mission(name_or_path: PathLike) -> Mission:
    """Read a mission file or bundled mission (``lingyun_path``, ``minerva_square``).

    Examples
    --------
    >>> import hydrokit
    >>> m = hydrokit.load_mission("minerva_square")
    >>> m.vehicle, m.controller
    ('minerva', 'pid')
    """
    from hydrokit.io.mission import load_mission as _load

    return _load(name_or_path)


def load_geometry(path: PathLike) -> Geometry:
    """Read a geometry file (shapes, vehicles and meshes placed in a common frame; m, kg)."""
    from hydrokit.io.geometry import load_geometry as _load

    return _load(path)


def read_launch(
    path: PathLike,
    rig: Rig | PathLike,
    *,
    release: float | None = None,
    end: float | None = None,
    trim: bool = True,
    detrend: str = "mean",
    amplitude_window: tuple[float, float] | None = None,
) -> Launch:
    """Read one launch CSV of ``rig`` and (by default) trim it to the free decay.

    Parameters
    ----------
    path : launch CSV (time s; position m, or angle rad / angle_deg)
    rig : Rig or rig-file path
    release, end : float, optional — release (start of free motion) and last useful time, s in
        the file's time base (default: detected, after any forced motion such as a hand heel)
    trim : bool — cut the record at the release (t = 0 there) and the end
    detrend : str — "none", "mean" (default) or "linear": remove a constant or drifting rest value
    amplitude_window : (HI, LO), optional — m or rad: keep from the first extreme ≤ HI until the
        amplitude falls below LO

    Returns
    -------
    Launch — t in s, y in m or rad, with notes of what reading and trimming did
    """
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.io.launch import read_launch as _read

    rig_obj = _as_rig(rig)
    raw = _read(path, rig_obj)
    if not trim:
        return raw
    return trim_launch(raw, release=release, end=end, detrend=detrend, amplitude_window=amplitude_window)


def identify_campaign(
    rig: Rig | PathLike,
    launches_or_paths: Sequence[Launch | PathLike],
    method: str = "output-error",
    *,
    release: float | None = None,
    end: float | None = None,
    progress: Callable[[str], None] | None = None,
    damping_model: str = "quadratic",
    restoring_terms: int = 1,
    detrend: str = "mean",
    amplitude_window: tuple[float, float] | None = None,
    equivalent_at: Sequence[float] = (),
    equivalent_model: str = "cubic",
) -> CampaignResult:
    """Identify added mass, linear and quadratic damping from many launches of one rig.

    Parameters
    ----------
    rig : Rig or rig-file path
    launches_or_paths : Launch objects (already trimmed) or launch CSV paths
    method : str — "output-error" (default), "equation-error", "morison" or "log-decrement"
    release, end : float, optional — release and last useful time of path launches, s
    progress : callable, optional — called with each launch's file name when it is done
    damping_model : str — "linear" (B1), "quadratic" (B1, B2; default) or "cubic" (B1, B2, B3 q̇³);
        output-error only, spring/torsion/floating rigs
    restoring_terms : int — 1 (the rig's restoring, default), 3 or 5: also fit C3 q³ (and C5 q⁵)
        added to the rig's restoring; output-error only, spring/torsion/floating rigs
    detrend, amplitude_window : how path launches are trimmed (see :func:`read_launch`)
    equivalent_at : amplitudes, m or rad: add per launch ``equivalent_damping`` B_e(a) with its
        standard error (spring, torsion and floating rigs)
    equivalent_model : str — "cubic" (default: B_e from a cubic-damping fit of each record, which
        follows a bending damping curve) or "fitted" (from ``damping_model`` itself); output-error

    Returns
    -------
    CampaignResult — launches, per-coefficient mean with 95 % CI, amplitude-group tests,
    full-scale values when the rig has a scale

    Examples
    --------
    >>> import hydrokit
    >>> from hydrokit.data import campaign_files
    >>> rig, files = campaign_files("udrobot", "spring_x")
    >>> res = hydrokit.identify_campaign(rig, files[:6])
    >>> 0.2 < res.mean("added_mass") < 0.4     # kg (CELY2019 Table 7: 0.287 kg)
    True
    """
    from hydrokit.identify.result import identify_launches
    from hydrokit.identify.types import Launch

    rig_obj = _as_rig(rig)
    launches = [
        x
        if isinstance(x, Launch)
        else read_launch(x, rig_obj, release=release, end=end, detrend=detrend, amplitude_window=amplitude_window)
        for x in launches_or_paths
    ]
    settings: dict[str, Any] = {}
    if (damping_model, restoring_terms) != ("quadratic", 1):
        settings = {"damping_model": damping_model, "restoring_terms": restoring_terms}
    if equivalent_at:
        settings["equivalent_at"] = tuple(equivalent_at)
        settings["equivalent_model"] = equivalent_model
    return identify_launches(rig_obj, launches, method, progress=progress, **settings)


def simulate(
    vehicle: Vehicle | PathLike, duration: float, dt: float, tau: Any = (0, 0, 0, 0, 0, 0), **options: Any
) -> Trajectory:
    """Simulate ``vehicle`` open loop under a constant τ, a τ(t) table or a callable.

    Parameters
    ----------
    vehicle : Vehicle or vehicle name/path
    duration, dt : float — s
    tau : 6 floats (N, N·m), rows [t, X, Y, Z, K, M, N] or a callable ``tau(t, x)``
    **options : eta0 (m, rad), nu0 (m/s, rad/s), current_ned (m/s), integrator ("rk4",
        "rk4-numpy", "dop853", "rk45"), attitude ("euler", "quaternion"), output_every,
        deflection (one per control surface, rad, or rows [t, δ…])

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> import hydrokit
    >>> tr = hydrokit.simulate("bluerov2-heavy", duration=2.0, dt=0.01, tau=[10, 0, 0, 0, 0, 0])
    >>> bool(tr.nu[-1, 0] > 0)      # surging forward (m/s)
    True
    """
    from hydrokit.simulate.driver import simulate as _simulate

    veh = _as_vehicle(vehicle)
    traj = _simulate(veh, duration, dt, tau, **options)
    simulate_envelope(veh, traj, tau, options.get("deflection"))
    return traj


def manoeuvre(vehicle: Vehicle | PathLike, manoeuvre: Any, **options: Any) -> Any:
    """Fly a standard manoeuvre (IMO MSC.137(76), ITTC 7.5-04-02-01) and measure it.

    Parameters
    ----------
    vehicle : Vehicle or vehicle name/path — with ``control_surfaces``
    manoeuvre : a :class:`hydrokit.manoeuvre.definitions.Manoeuvre` from ``turning_circle(deg)``,
        ``zigzag(a, b)``, ``spiral(...)``, ``pull_out(...)``, ``depth_change(...)``,
        ``vertical_zigzag(a, b)`` of that module
    **options : surface, tau (N, N·m), nu0 (m/s, rad/s), eta0, dt (s), duration (s), approach (s),
        current_ned (m/s), loop ("compiled" or "python"), hold (bool or None: hold depth and
        pitch with the stern planes in horizontal manoeuvres, heading with the rudder in vertical
        ones; None = on for a 6-DOF vehicle with such a second surface), commands ({thruster
        name: command} — rev/s for a propeller, the table's unit, N for an ideal thruster; held
        from rest through the rotor lag; ``tau`` adds to their thrust) — see
        :func:`hydrokit.manoeuvre.run.run_manoeuvre`

    Without propulsion (no ``commands``, ``tau`` not given or zeros) the vehicle file's
    ``service:`` block is flown (:func:`with_service`): its commands and force, the approach
    starting at its speed unless ``nu0`` is given; a vehicle without one is refused.

    Returns
    -------
    ManoeuvreResult — metrics from the execute point, ``to_dict()``, ``plot()``
    """
    from hydrokit.manoeuvre.run import run_manoeuvre

    veh = _as_vehicle(vehicle)
    settings = with_service(veh, options)[0]
    res = run_manoeuvre(veh, manoeuvre, **settings)
    manoeuvre_envelope(veh, res, settings.get("commands"), settings.get("tau"))
    return res


def command_units(vehicle: Vehicle) -> dict[str, str]:
    """Each thruster's command unit ({name: "rev/s" | the table's | "N"}; empty without thrusters)."""
    from hydrokit.simulate.mission import COMMAND_UNITS

    ts = vehicle.thrusters
    return {} if ts is None else {n: COMMAND_UNITS[t.model] for n, t in zip(ts.names, ts.thrusters)}


def _surge_force(tau: Any) -> float | None:
    """The largest |X| (N) of a constant force or a force table ([t, X … N] rows); 0 for None;
    None for a callable (not known before it is flown)."""
    import numpy as np

    if tau is None:
        return 0.0
    if callable(tau):
        return None
    f = np.asarray(tau, dtype=float)
    return float(abs(f[0])) if f.ndim == 1 else float(np.max(np.abs(f[:, 1])))


def _envelope_lines(result: Any, findings: Any, check: Any, runs: Sequence[str]) -> list[str]:
    """The envelope's lines of ``findings``, added to the result's warnings (and, where it has
    the field, its ``envelope`` record)."""
    from hydrokit.model.envelope import lines

    out = lines(findings)
    if hasattr(result, "envelope"):
        result.envelope = {
            "holds": None if check is None else bool(check["holds"]),  # None: no speed to compare
            "speed_check": check,
            "findings": [f.to_dict() for f in findings],
            "runs": list(runs),
        }
    result.warnings.extend(out)
    return out


def manoeuvre_envelope(vehicle: Vehicle, result: Any, commands: Any = None, tau: Any = None) -> list[str]:
    """A flown manoeuvre compared with the envelope of the vehicle's identification (issue #56
    item 7; :func:`hydrokit.model.envelope.compare`): the approach's steady speed at its held
    thruster ``commands`` (under no surge force in ``tau``) against the runs' speed there, and its
    commands, largest deflections, yaw rate, drift and speed against the runs' ranges.

    Parameters
    ----------
    vehicle : Vehicle — its ``envelope`` (None: nothing compared, nothing said)
    result : ManoeuvreResult — ``envelope`` set to {holds, speed_check, findings, runs} and the
        lines added to its ``warnings``
    commands : {thruster: command} or None — as flown (each in its unit)
    tau : the constant force flown (6 floats, N, N·m), rows, a callable or None

    Returns
    -------
    list of str — the lines to print (``envelope: the model does not hold …``, ``envelope: the
    prediction extrapolates …``); empty when the prediction stays inside or there is no envelope
    """
    from hydrokit.model.envelope import compare, extremes

    env = vehicle.envelope
    if env is None:
        return []
    ext = extremes(result.nu, result.deflection, result.surface_names)
    held = {str(n): float(c) for n, c in (commands or {}).items()}
    # an approach that had not settled is still speeding up: a speed already too high is said
    rising = any(w.startswith("the approach was not steady") for w in result.warnings)
    steady = (held, float(result.approach_speed)) if held and _surge_force(tau) == 0.0 else None
    findings, check = compare(
        env,
        commands={n: [c] for n, c in held.items()},
        steady=steady,
        deflection=ext["deflection"],
        yaw_rate=ext["yaw_rate"],
        drift=ext["drift"],
        speed=ext["speed"],
        units=command_units(vehicle),
        rising=rising,
    )
    return _envelope_lines(result, findings, check, env.runs)


def simulate_envelope(vehicle: Vehicle, trajectory: Any, tau: Any = None, deflection: Any = None) -> list[str]:
    """A simulated run compared with the envelope of the vehicle's identification (issue #56 item
    7): the thruster commands and the deflections given against the runs' ranges, and — when the
    run ends steady and nearly straight (its last hold's second half:
    :func:`hydrokit.model.envelope.straight_and_steady`) — its speed there against the runs' speed
    at the same commands (under no surge force) and their largest speed.

    Parameters
    ----------
    vehicle : Vehicle — its ``envelope`` (None: nothing compared, nothing said)
    trajectory : Trajectory — the lines are added to its ``warnings``
    tau : the force flown: 6 floats (N, N·m), rows [t, X … N], a callable, or a
        :class:`hydrokit.simulate.commands.CommandForce` (thruster commands over time)
    deflection : None, one deflection per surface (rad) or rows [t, δ…]

    Returns
    -------
    list of str — the lines to print; empty inside the envelope or without one
    """
    import numpy as np

    from hydrokit.model.envelope import compare, straight_and_steady
    from hydrokit.simulate.commands import CommandForce

    env = vehicle.envelope
    if env is None:
        return []
    names = list(vehicle.thrusters.names) if vehicle.thrusters is not None else []
    commands: dict[str, Any] = {}
    held: dict[str, float] = {}
    start = float(trajectory.time[0])
    surge = _surge_force(tau)
    if isinstance(tau, CommandForce):
        commands = {n: tau.values[:, k].tolist() for k, n in enumerate(names)}
        held = {n: float(tau.values[-1, k]) for k, n in enumerate(names)}
        start = max(start, float(tau.time[-1]))
        surge = float(np.max(np.abs(tau.force_table[:, 1])))
    defl: dict[str, float] = {}
    if deflection is not None:
        d = np.asarray(deflection, float)
        cols = d[:, 1:] if d.ndim == 2 else d[None, :]  # rows [t, δ…], or one δ per surface
        defl = {n: float(np.max(np.abs(cols[:, k]))) for k, n in enumerate(vehicle.surfaces.names)}
    t = np.asarray(trajectory.time, float)
    part = t >= start + 0.5 * (t[-1] - start)  # the second half of the last hold
    speed = np.linalg.norm(np.asarray(trajectory.nu, float)[part, :3], axis=1)
    steady, straight = straight_and_steady(t[part], speed, trajectory.nu[part, 5], env.length)
    final = float(np.mean(speed[straight])) if steady and surge is not None else None
    findings, check = compare(
        env,
        commands=commands,
        steady=(held, final) if final is not None and held and surge == 0.0 else None,
        deflection=defl,
        speed=final,
        units=command_units(vehicle),
        what="steady speed at the end",
    )
    return _envelope_lines(trajectory, findings, check, env.runs)


def sysid(
    runs: Any,
    vehicle: Vehicle | PathLike,
    free: str | Any,
    holdout: Any = (),
    method: str = "output-error",
    dt: float = 0.01,
    samples: int = 40,
    seed: int = 0,
    workers: int | None = None,
    scheduler: str | None = None,
    window: float | str | None = "auto",
) -> Any:
    """Identify a vehicle's free coefficients from its own free-running logs (issue #44).

    Parameters
    ----------
    runs : run CSV paths (the frozen format of docs/sysid.md) or RunLog objects — training runs
    vehicle : Vehicle or vehicle name/path — the base, with its ``thrusters:``; every coefficient
        not free keeps its value
    free : "added_mass.surge,linear_damping.yaw,…" or a list of such names (``terms.<term>`` too)
    holdout : runs used only for validation (open-loop prediction, NRMSE)
    method : "output-error" (default) or "equation-error"
    dt : float — integration step, s
    samples : int — Monte Carlo draws from the covariance for the prediction envelope
    seed : int — seed of those draws
    workers : int or None — threads of the compiled batch simulations (None: all cores)
    scheduler : str or None — a running Dask scheduler's address: the runs are simulated on its workers
    window : float, "auto" or None — fit windows of about this many seconds, each from its
        smoothed state; "auto" (default): 30 s windows only when a run drifts; None: whole runs

    Returns
    -------
    SysidResult — values, σ, covariance, correlations, condition number, residuals, warnings;
    ``to_dict()``, ``plot()``
    """
    v = _as_vehicle(vehicle)
    listed = [n.strip() for n in free.split(",")] if isinstance(free, str) else list(free)
    return identify_runs(
        v,
        runs,
        listed,
        holdout,
        method=method,
        dt=dt,
        samples=samples,
        seed=seed,
        workers=workers,
        scheduler=scheduler,
        window=window,
    )


def identify_runs(
    vehicle: Vehicle,
    runs: Any,
    free: Sequence[str],
    holdout: Any = (),
    *,
    method: str = "output-error",
    dt: float = 0.01,
    on_read: Callable[[list[Any], list[Any]], None] | None = None,
    document: Mapping[str, Any] | None = None,
    **options: Any,
) -> SysidResult:
    """Read the run files and identify: the one path of :func:`sysid`, ``hydrokit sysid`` and the
    main job's ``sysid:`` source.

    Every option is checked before a run is read (a bad free name or method costs no reading) —
    with ``document``, the free names are also written at their start values into a copy of it
    and loaded back (:func:`hydrokit.io.vehicle.check_writable`), so a name the fit could not
    write into its vehicle file fails before the fit, not after it — then the runs are read with
    the vehicle's thrusters and surfaces (:func:`hydrokit.io.runlog.read_runs`), a ``window``
    longer than a run is refused, and :func:`hydrokit.sysid.fit.identify` fits.

    Parameters
    ----------
    vehicle : Vehicle — the base, with its ``thrusters:``
    runs, holdout : run CSV paths or RunLog objects — training and validation runs
    free : the free parameter names (``added_mass.surge``, ``terms.<term>`` …)
    method : "output-error" or "equation-error"
    dt : float — integration step, s
    on_read : callable(training, holdout) or None — called with the runs once they are read and
        checked, before the fit (the CLI prints them)
    document : mapping or None — the base vehicle file's fields the result will be written into
        (``hydrokit sysid``'s vehicle.yaml, :func:`hydrokit.io.vehicle.identified_vehicle_document`)
    **options : the rest of :func:`hydrokit.sysid.fit.identify`'s keywords (samples, seed,
        progress, workers, scheduler, window — s, "auto" or None …)

    Returns
    -------
    SysidResult
    """
    from hydrokit.io.runlog import read_runs
    from hydrokit.sysid.fit import check_options, identify
    from hydrokit.sysid.window import check_window

    names = list(free)
    start, params = check_options(vehicle, names, method, dt)  # every option before a run is read
    if document is not None:  # and every name the writer must hold, at its start value
        from hydrokit.io.vehicle import check_writable

        check_writable(document, start, [p.name for p in params])
    train, held = read_runs(runs, vehicle), read_runs(holdout, vehicle)
    check_window(options.get("window"), train)  # a window longer than a run: refused before the fit
    if on_read is not None:
        on_read(list(train), list(held))
    return identify(vehicle, train, names, held, method=method, dt=dt, **options)


def sysid_dive_files(
    base: Vehicle, out_dir: str, n_runs: int, duration: float, seed: int, spread: float, amplitude: float, noise: float
) -> dict[str, str]:
    """Virtual dives of ``base`` with hidden coefficients, as the texts ``hydrokit sysid generate`` writes.

    Parameters
    ----------
    base : Vehicle — with its thrusters; the hidden coefficients are drawn around its own
    out_dir : str — the folder the file names are in
    n_runs : int — number of dives
    duration : float — length of each dive, s
    seed : int — seed of the hidden coefficients, the commands and the noise
    spread : float — hidden coefficients = base × uniform(1 − spread, 1 + spread) (fraction)
    amplitude : float — largest fraction of a thrust limit used (0–1)
    noise : float — multiplier of every sensor σ (0: noise-free logs)

    Returns
    -------
    dict — DIR/diveN.csv run files (:func:`hydrokit.io.runlog.run_csv`) and DIR/truth.json (the
    hidden values, SI), path → text (:mod:`hydrokit.sysid.data` generates them)
    """
    import json
    from pathlib import Path

    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.data import HIDDEN, generate_runs, hidden_vehicle
    from hydrokit.sysid.model import free_parameters, values_of

    truth = hidden_vehicle(base, seed, spread)
    dives = generate_runs(truth, n_runs, duration, seed, amplitude, noise)
    _, params = free_parameters(truth, HIDDEN)
    note = f"virtual dive of {base.name} with hidden coefficients (seed {seed})"
    files = {str(Path(out_dir) / f"{d.name}.csv"): run_csv(d.time, d.rows(), d.commands, comment=note) for d in dives}
    hidden = {p.name: float(v) for p, v in zip(params, values_of(truth, params))}
    doc = {"vehicle": base.name, "seed": seed, "spread": spread, "hidden": hidden}
    files[str(Path(out_dir) / "truth.json")] = json.dumps(doc, indent=2) + "\n"
    return files


def simulate_batch(
    vehicles: Sequence[Vehicle | PathLike], duration: float, dt: float, tau: Any = (0, 0, 0, 0, 0, 0), **options: Any
) -> BatchTrajectory:
    """Simulate many vehicles (e.g. Monte Carlo coefficient samples) in parallel, compiled.

    Parameters
    ----------
    vehicles : Vehicles or names/paths sharing one derivative-term structure
    duration, dt : float — s
    tau : 6 floats (N, N·m) for all, or one row per vehicle
    **options : eta0, nu0, current_ned, output_every, attitude (see :func:`simulate`)

    Returns
    -------
    BatchTrajectory
    """
    from hydrokit.simulate.batch import simulate_batch as _batch

    return _batch([_as_vehicle(v) for v in vehicles], duration, dt, tau, **options)


def fly(
    mission_or_vehicle: Mission | Vehicle | PathLike,
    controller: str | None = None,
    *,
    vehicle: Vehicle | PathLike | None = None,
    waypoints: Any = None,
    gains: dict[str, dict[str, dict[str, float]]] | None = None,
    duration: float | None = None,
    progress: Callable[[float], None] | None = None,
    loop: str = "compiled",
    **mission_options: Any,
) -> MissionResult:
    """Fly a closed-loop waypoint mission (guidance, PID or S-plane autopilot, allocation,
    thrusters) and return its trajectory and tracking metrics.

    Parameters
    ----------
    mission_or_vehicle : Mission, mission name/path, or a Vehicle (then give ``waypoints``
        and ``gains``; other mission fields via ``mission_options``: speed m/s, dt s,
        acceptance_radius m, lookahead m, current (3,) m/s)
    controller : str, optional — "pid" or "s-plane" (default: the mission's)
    vehicle : Vehicle or name/path, optional — fly the mission with this vehicle instead of
        the one it names (e.g. an identified one)
    waypoints : (k, 3) — NED waypoints, m (with a Vehicle)
    gains : dict — controller → loop → gains, as in a mission file (with a Vehicle)
    duration : float, optional — s
    progress : callable, optional — called with the simulated time, s
    loop : str — "compiled" (numba, default) or "python" (the reference loop); the same
        run to ~1e-12 (dimensionless choice)

    Returns
    -------
    MissionResult

    Examples
    --------
    >>> import hydrokit
    >>> run = hydrokit.fly("minerva_square", duration=5.0)
    >>> run.label, bool(run.time[-1] <= 5.0)
    ('PID', True)
    """
    from hydrokit.model.mission import Mission, create_mission
    from hydrokit.model.vehicle import Vehicle
    from hydrokit.simulate.mission import fly_mission

    if isinstance(mission_or_vehicle, Vehicle):
        if waypoints is None or gains is None:
            raise InputError("fly(vehicle, …): give waypoints (m, NED) and gains, or pass a Mission")
        kind = controller or next(iter(gains))
        mission = create_mission(
            waypoints,
            gains,
            vehicle=mission_or_vehicle.name,
            controller=kind,
            duration=duration if duration is not None else mission_options.pop("duration", 300.0),
            **mission_options,
        )
        veh = mission_or_vehicle
    else:
        if mission_options:
            raise InputError(
                f"unexpected option(s) {sorted(mission_options)} for a mission file; "
                "they apply only when flying a Vehicle with waypoints"
            )
        mission = mission_or_vehicle if isinstance(mission_or_vehicle, Mission) else load_mission(mission_or_vehicle)
        veh = _as_vehicle(vehicle) if vehicle is not None else load_vehicle(mission.vehicle)
    return fly_mission(mission, veh, controller, duration=duration, progress=progress, loop=loop)


def fly_batch(
    mission: Mission | PathLike,
    vehicles_or_variations: Any = None,
    controller: str | None = None,
    *,
    vehicle: Vehicle | PathLike | None = None,
    gains: Sequence[dict[str, dict[str, float]]] | None = None,
    currents: Any = None,
    eta0: Any = None,
    nu0: Any = None,
    n: int | None = None,
    duration: float | None = None,
    paths_every: int | None = None,
) -> FleetResult:
    """Fly N copies of a mission in one compiled, parallel call (a fleet) and return each
    copy's tracking metrics (and, with ``paths_every``, its path every that many steps).

    Parameters
    ----------
    mission : Mission or mission name/path
    vehicles_or_variations : None (the mission's vehicle, or ``vehicle``), a Vehicle or
        name/path, N Vehicles (same thrusters and model terms), or a mapping
        ``"<coefficient>.<dof>"`` → N values (added_mass, linear_damping, quadratic_damping;
        SI) applied to ``vehicle`` or the mission's vehicle
    controller : str, optional — "pid" or "s-plane" (default: the mission's)
    vehicle : Vehicle or name/path, optional — the base vehicle of a variations mapping
    gains : N mappings, optional — loop → gains of the controller per copy (as in a mission file)
    currents : (3,) or (N, 3), optional — NED current, m/s
    eta0, nu0 : (6,) or (N, 6), optional — start pose (m, rad) and body velocity (m/s, rad/s)
    n : int, optional — copies, when nothing else gives N
    duration : float, optional — s
    paths_every : int, optional — keep η every this many steps (memory ∝ steps / paths_every)

    Returns
    -------
    FleetResult — per-run metrics (``metrics[name]`` arrays, ``table()``, ``to_dict()``)

    Examples
    --------
    >>> import hydrokit
    >>> fleet = hydrokit.fly_batch("minerva_square", {"linear_damping.surge": [5.0, 50.0]}, duration=5.0)
    >>> fleet.n, bool(fleet.metrics["final_time"][0] == 5.0)
    (2, True)
    """
    from hydrokit.model.mission import Mission
    from hydrokit.model.vehicle import Vehicle
    from hydrokit.simulate.fleet import fly_fleet

    mis = mission if isinstance(mission, Mission) else load_mission(mission)
    arg = vehicles_or_variations
    variations = None
    if arg is None or isinstance(arg, dict):
        variations = arg
        vehicles: Any = _as_vehicle(vehicle) if vehicle is not None else load_vehicle(mis.vehicle)
    elif isinstance(arg, (Vehicle, str, os.PathLike)):
        vehicles = _as_vehicle(arg)
    else:
        vehicles = [_as_vehicle(v) for v in arg]
    return fly_fleet(
        mis,
        vehicles,
        controller,
        variations=variations,
        gains=gains,
        currents=currents,
        eta0=eta0,
        nu0=nu0,
        n=n,
        duration=duration,
        paths_every=paths_every,
    )


def estimate_geometry(
    geometry: Geometry | PathLike,
    bem: bool = False,
    resolution: int | None = None,
    quadratic_damping: str = "elements",
) -> Estimate:
    """Added mass, damping and mass properties of a geometry (shapes, vehicles, meshes).

    Parameters
    ----------
    geometry : Geometry or geometry-file path
    bem : bool — added mass of eligible parts from the boundary-element solver (hydrokit[bem])
    resolution : int, optional — BEM panels around the circumference
    quadratic_damping : str — how the parts' quadratic damping combines: "elements" (default:
        point drag elements at the part origins), "rehman" (diagonal with d·r³ rotational terms)
        or "shifted" (Hᵀ D H diagonal, d·r², dimensionally wrong; for comparison)

    Returns
    -------
    Estimate

    Examples
    --------
    >>> import hydrokit
    >>> from hydrokit.data import geometry_file
    >>> est = hydrokit.estimate_geometry(geometry_file("sphere"))
    >>> round(float(est.composite.added_mass[0, 0]), 1)   # ½ρV of a 0.5 m sphere in sea water, kg
    33.5
    """
    from hydrokit.estimate.geometry import Geometry
    from hydrokit.estimate.geometry import estimate_geometry as _estimate

    geo = geometry if isinstance(geometry, Geometry) else load_geometry(geometry)
    return _estimate(geo, bem=bem, resolution=resolution, quadratic_damping=quadratic_damping)


def fit_forces(speed: Any, force: Any, area: float, density: float) -> ForceFit:
    """Fit F = K_L U + K_Q|U|U (Chin) and F = K_D|U|U (Morison) to a force–speed curve.

    Parameters
    ----------
    speed : array — U, m/s
    force : array — resisting force F, N
    area : float — reference area A_ref for C_D, m²
    density : float — fluid density ρ, kg/m³

    Returns
    -------
    ForceFit

    Examples
    --------
    >>> import hydrokit
    >>> fit = hydrokit.fit_forces([0.5, 1.0, 1.5, 2.0], [2.5, 10.0, 22.5, 40.0], area=0.1, density=1000.0)
    >>> round(fit.K_D, 6), round(fit.C_D, 6)     # F = 10 U², C_D = 2·10/(1000·0.1)
    (10.0, 0.2)
    """
    from hydrokit.estimate.forces import fit_forces as _fit

    return _fit(speed, force, area, density)


def allocate(
    vehicle: Vehicle | ThrusterSet | PathLike,
    tau: Any,
    method: str = "constrained",
    weights: Sequence[float] | None = None,
) -> Allocation:
    """Allocate a demanded force/moment τ to the vehicle's thrusters.

    Parameters
    ----------
    vehicle : Vehicle with thrusters, a ThrusterSet, or a vehicle name/path (only its
        ``thrusters:`` block is read)
    tau : 6 floats — X, Y, Z (N), K, M, N (N·m), body axes
    method : str — "constrained" (least residual within the thrust limits, then least
        thrust) or "pinv" (weighted pseudo-inverse)
    weights : m floats, optional — pinv weights (larger = used less)

    Returns
    -------
    Allocation — thrust per thruster (N), achieved τ, commands (rev/s, table unit or N)

    Examples
    --------
    >>> import hydrokit
    >>> a = hydrokit.allocate("minerva", [100, 0, 0, 0, 0, 0])
    >>> round(float(a.achieved_tau[0]), 6)
    100.0
    """
    from hydrokit.model.allocation import allocate_constrained, allocate_pinv
    from hydrokit.model.thrusters import ThrusterSet
    from hydrokit.model.vehicle import Vehicle

    if isinstance(vehicle, ThrusterSet):
        ts = vehicle
    elif isinstance(vehicle, Vehicle):
        ts = vehicle.thrusters
    else:
        from hydrokit.io.thrusters import load_thrusters

        ts = load_thrusters(vehicle)
    if ts is None or len(ts) == 0:
        raise InputError(
            f"vehicle '{getattr(vehicle, 'name', vehicle)}' has no thrusters: allocation needs a 'thrusters:' block"
        )
    tau_v = _six(tau, "tau")
    if method not in ("constrained", "pinv"):
        raise InputError(f"method = {method!r}: expected constrained or pinv")
    if weights is not None:
        if method != "pinv":
            raise InputError("weights apply only to method 'pinv'")
        if len(weights) != len(ts):
            raise InputError(f"weights: {len(weights)} given; expected one per thruster ({len(ts)})")
    T = ts.configuration_matrix()
    if method == "pinv":
        res = allocate_pinv(T, tau_v, weights=weights, f_min=ts.f_min, f_max=ts.f_max, names=ts.names)
    else:
        res = allocate_constrained(T, tau_v, ts.f_min, ts.f_max, names=ts.names)
    from hydrokit.simulate.mission import COMMAND_UNITS

    return replace(
        res,
        tau=tau_v,
        names=list(ts.names),
        configuration_matrix=T,
        f_min=ts.f_min,
        f_max=ts.f_max,
        command=ts.command_for_thrust(res.thrust),
        command_unit=[COMMAND_UNITS[t.model] for t in ts.thrusters],
        warnings=list(ts.notes) + list(res.warnings),
        vehicle=str(getattr(vehicle, "name", vehicle)),
    )


# -- helpers -----------------------------------------------------------------------------------


def _as_rig(rig: Any) -> Rig:
    from hydrokit.identify.types import Rig

    return rig if isinstance(rig, Rig) else load_rig(rig)


def _as_vehicle(vehicle: Any) -> Vehicle:
    from hydrokit.model.vehicle import Vehicle

    return vehicle if isinstance(vehicle, Vehicle) else load_vehicle(vehicle)


def _six(values: Any, what: str) -> Any:
    import numpy as np

    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} = {values!r}: expected 6 numbers (N, N·m)") from None
    if a.shape != (6,) or not np.all(np.isfinite(a)):
        raise InputError(f"{what} = {values!r}: expected 6 finite numbers X, Y, Z (N), K, M, N (N·m)")
    return a


def linearize(vehicle: Vehicle | PathLike, trim: Any = (0, 0, 0, 0, 0, 0)) -> Any:
    """The 6-DOF model linearised at the body velocity ``trim`` (zero attitude): A, B, C, D.

    Parameters
    ----------
    vehicle : Vehicle or name/path
    trim : 6 floats — u, v, w (m/s), p, q, r (rad/s)

    Returns
    -------
    Linearization — ``.A`` (12×12), ``.B`` (12×6), ``.eigenvalues`` (1/s),
    ``.to_statespace()`` (a ``control.StateSpace``; ``pip install 'hydrokit[control]'``)

    Examples
    --------
    >>> import hydrokit
    >>> lin = hydrokit.linearize("minerva", trim=[0.5, 0, 0, 0, 0, 0])
    >>> lin.A.shape, lin.B.shape, bool(lin.tau0[0] > 0)
    ((12, 12), (12, 6), True)
    """
    from hydrokit.simulate.linearize import linearize as _linearize

    return _linearize(_as_vehicle(vehicle), trim)


def export_vehicle(
    vehicle: Vehicle | PathLike, format: str, trim: Any = (0, 0, 0, 0, 0, 0), added_mass: str = "plugin"
) -> bytes:
    """The vehicle as another tool reads it (the bytes ``hydrokit export`` writes).

    Parameters
    ----------
    vehicle : Vehicle or name/path
    format : str — "gazebo" (gz-sim SDF), "uuv-simulator" (fossen plugin block) or
        "python-control" (``.npz`` of A, B, C, D at ``trim``, and the vehicle's ``provenance``)
    trim : 6 floats — u, v, w (m/s), p, q, r (rad/s), for python-control
    added_mass : str — gazebo: "plugin" (Hydrodynamics ``*Dot*`` parameters) or "inertial"
        (``<fluid_added_mass>``, gz-sim Garden or later with DART)

    Raises
    ------
    InputError
        What the target cannot take (:func:`hydrokit.io.export.export_checks`): M_RB + M_A not
        positive definite, M_A not positive semi-definite, or an added mass too large against
        the rigid-body mass for an engine that applies it explicitly (ρ(M_RB⁻¹ M_A) ≥ 1).
    """
    import io

    import numpy as np

    from hydrokit.io.export import export_checks, gazebo_sdf, uuv_parameters

    if format not in ("gazebo", "uuv-simulator", "python-control"):
        raise InputError(f"format = {format!r}: expected gazebo, uuv-simulator or python-control")
    veh = _as_vehicle(vehicle)
    notes = export_checks(veh, format, added_mass)
    if format == "gazebo":
        return gazebo_sdf(veh, added_mass=added_mass, notes=notes).encode("utf-8")
    if format == "uuv-simulator":
        return uuv_parameters(veh, notes=notes).encode("utf-8")
    buf = io.BytesIO()
    np.savez(buf, **linearize(veh, trim).npz_arrays(), provenance=np.array(veh.provenance, dtype=str))
    return buf.getvalue()


def load_assembly(name_or_path: PathLike, damping_model: str = "elements") -> Assembly:
    """Read an assembly file or bundled assembly (``rehman_transport``,
    ``rehman_transport_public``): a geometry file whose parts also name their ``parent`` and
    ``joint`` (docs/transport.md).

    Parameters
    ----------
    name_or_path : file path or bundled name
    damping_model : how composites carry the parts' quadratic drag: ``elements`` (each part's
        drag at its own point, default), ``rehman`` (d·r³ diagonal) or ``shifted`` (Hᵀ D H)
    """
    from hydrokit.io.assembly import load_assembly as _load

    return _load(name_or_path, quadratic_damping=damping_model)


def transport(
    assembly: Assembly | PathLike,
    duration: float,
    dt: float,
    model: str = "rigid",
    rpm: dict[str, float] | None = None,
    force: dict[str, Any] | None = None,
    output_every: int = 1,
) -> TransportResult:
    """Fly a joined assembly (two vehicles carrying a payload, REHMAN) open loop.

    Parameters
    ----------
    assembly : Assembly or assembly file / bundled name
    duration : float — s; dt : float — step, s
    model : ``rigid`` (one composite body; joint loads from Newton–Euler on each subtree),
        ``multibody`` (each part a body, stiff spring–damper joints) or ``independent``
        (each child subtree of the root with a share of the root part, flying alone)
    rpm : dict — ``PART.THRUSTER`` → propeller speed, rpm (converted to rev/s here)
    force : dict — part name → [fx, fy, fz, mx, my, mz], N and N·m in the part's axes at its origin
    output_every : int — record every n-th step

    Returns
    -------
    TransportResult — trajectories of the assembly origin and every part, joint loads
    (assembly body axes, at the joint point), separations, thrusts; ``summary()``
    """
    from hydrokit.model.assembly import Assembly as _Assembly
    from hydrokit.simulate.transport import fly_transport

    asm = assembly if isinstance(assembly, _Assembly) else load_assembly(assembly)
    commands: dict[str, float] = {}
    for name, value in (rpm or {}).items():
        i = asm.thruster_index(name)
        th = asm.thrusters.thrusters[i]  # type: ignore[union-attr]
        if th.model != "propeller":
            raise InputError(f"rpm of thruster '{name}': it is a {th.model} thruster; rpm needs a propeller model")
        commands[name] = float(value) / 60.0
    return fly_transport(asm, duration, dt, model, commands, force, output_every)


# --- CFD: the virtual tow tank and rotating arm on OpenFOAM ----------------------------------


def load_cfd_body(name_or_path: Any, area: float | None = None) -> Any:
    """A body for :func:`cfd` from a file or a bundled name.

    Parameters
    ----------
    name_or_path : a bundled body name (``myring``), a surface mesh (``.stl`` binary or ASCII,
        ``.obj``; m, body axes, origin = moment reference point), a profile of a body of revolution
        (``.csv`` with columns x, r in m) or a geometry file (``.yaml``: its sphere, spheroid,
        cylinder and mesh parts, placed as the file says)
    area : float, optional — reference area for C_D, m² (default: the frontal area)

    Returns
    -------
    hydrokit.cfd.case.Body
    """
    from pathlib import Path

    from hydrokit.cfd import body as cfd_body
    from hydrokit.cfd.case import Body
    from hydrokit.data import body_file

    if isinstance(name_or_path, Body):
        return name_or_path
    text = os.fspath(name_or_path)
    p = Path(text)
    if not p.exists() and p.suffix == "" and os.sep not in text:
        p = body_file(text)
    suffix = p.suffix.lower()
    if suffix == ".csv":
        from hydrokit.io.profile import read_profile

        x, r = read_profile(p)
        return cfd_body.profile_body(x, r, p.name, area)
    if suffix in (".stl", ".obj"):
        from hydrokit.estimate.mesh import check_mesh, read_mesh

        mesh = read_mesh(p)
        check_mesh(mesh)
        return cfd_body.mesh_body(mesh.vertices[mesh.triangles()], p.name, area)
    if suffix in (".yaml", ".yml"):
        return cfd_body.geometry_body(load_geometry(p), area)
    if not p.exists():
        raise InputError("no such file", str(p))
    raise InputError(
        f"file type {suffix or '(none)'!r}: expected a surface mesh (.stl, .obj), a profile (.csv with x, r) "
        "or a geometry file (.yaml)",
        str(p),
    )


def cfd(
    body: Any,
    speeds: Sequence[float] = (0.5, 1.0, 1.5, 2.0),
    drift: Sequence[float] = (),
    attack: Sequence[float] = (),
    yaw_rates: Sequence[float] = (),
    pitch_rates: Sequence[float] = (),
    *,
    axes: Sequence[str] = ("x",),
    density: float = 1025.0,
    viscosity: float = 1.19e-6,
    turbulence: str = "auto",
    grids: int = 1,
    reference_speed: float | None = None,
    area: float | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    cache_dir: PathLike | None = None,
    keep_cases: PathLike | None = None,
    settings: dict[str, Any] | None = None,
    progress: Callable[[int], object] | None = None,
) -> Any:
    """Forces, force–speed fits and derivatives of a body from OpenFOAM (a virtual tow tank and
    rotating arm, LI2021 §2.2 and CELY2019 §3.4). Needs OpenFOAM (``apt-get install openfoam``).

    Parameters
    ----------
    body : Body, bundled name or file — see :func:`load_cfd_body`
    speeds : m/s — straight-ahead speeds (and the per-axis sweeps of ``axes``)
    drift, attack : rad — drift angles β = atan2(v, u) and angles of attack α = atan2(w, u) at
        the reference speed (|angle| < π/2)
    yaw_rates, pitch_rates : rad/s — rotating-arm rates at the reference speed
    axes : body axes with a speed sweep ("x"; "y", "z" add pure sway and heave)
    density : kg/m³; viscosity : kinematic, m²/s (sea water at 15 °C: 1.19e-6)
    turbulence : auto (laminar below Re_L = 2000, else k-ω SST), laminar, kOmegaSST, kEpsilon
    grids : 1, or 3 for a refinement triplet with Richardson extrapolation and GCI
    reference_speed : m/s — speed of the angle and rate cases (default: the largest speed)
    area : m² — reference area of C_D (default: frontal area)
    workers, scheduler : local Dask workers or a scheduler address (default: serial)
    cache_dir : folder of cached case outcomes (default: $HYDROKIT_CACHE/cfd or ~/.cache/hydrokit/cfd)
    keep_cases : folder to keep each finished OpenFOAM case in (for ParaView)
    settings : further :class:`hydrokit.cfd.case.Settings` fields (mesh, iterations, domain)
    progress : called with 1 as each case finishes

    Returns
    -------
    hydrokit.cfd.sweep.CFDResult
    """
    from pathlib import Path

    from hydrokit.cfd.case import Settings
    from hydrokit.cfd.foam import find_openfoam
    from hydrokit.cfd.sweep import SweepSpec, make_cases, run_sweep

    b = load_cfd_body(body, area)
    try:
        s = Settings(density=density, viscosity=viscosity, turbulence=turbulence, **(settings or {}))
    except TypeError as exc:
        raise InputError(f"settings: {exc}; expected fields of hydrokit.cfd.case.Settings") from None
    spec = SweepSpec(
        tuple(float(u) for u in speeds),
        tuple(float(a) for a in drift),
        tuple(float(a) for a in attack),
        tuple(float(r) for r in yaw_rates),
        tuple(float(q) for q in pitch_rates),
        tuple(axes),
        grids,
        reference_speed,
    )
    if cache_dir is None:
        base = os.environ.get("HYDROKIT_CACHE")
        cache = Path(base) / "cfd" if base else Path.home() / ".cache" / "hydrokit" / "cfd"
    else:
        cache = Path(cache_dir)
    keep = Path(keep_cases) if keep_cases is not None else None
    cases = make_cases(b, spec, s)
    find_openfoam()  # after the inputs are checked: one line naming the install command
    return run_sweep(
        b, spec, s, cache, keep_dir=keep, workers=workers, scheduler=scheduler, progress=progress, cases=cases
    )
