"""A sweep of cases — virtual tow tank and rotating arm — run on the executor, fitted into coefficients.

Cases (LI2021 §2.2 and CELY2019 §3.4):

* straight ahead at every speed of ``speeds`` (and, for ``axes`` y and z, pure sway and heave
  at the same speeds: CELY2019's per-axis force curves);
* each drift angle β and angle of attack α at the reference speed (the largest speed unless
  given): the virtual tow tank;
* each yaw rate r and pitch rate q at the reference speed: the virtual rotating arm;
* with ``grids = 3``, every case on grid levels 1, 2 and 3 (a refinement triplet, ratio √2):
  the finest grid's loads are reported, with Roache's GCI per load.

Each case is one task of :class:`hydrokit._parallel.Executor` (serial, a local Dask cluster or a
scheduler) and is cached by the hash of its inputs (:func:`hydrokit.cfd.run.cached_case`).
"""

from __future__ import annotations

import math
import shutil
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.cfd.case import Body, Case, Flow, Settings
from hydrokit.cfd.gci import grid_study
from hydrokit.errors import InputError

LOADS = ("X", "Y", "Z", "K", "M", "N")
#: what each kind of case fits (see hydrokit.estimate.derivatives)
MODELS: dict[str, dict[str, list[str]]] = {
    "drift": {"Y": ["uv", "v|v|"], "N": ["uv", "v|v|"], "X": ["u|u|", "vv"]},
    "attack": {"Z": ["uw", "w|w|"], "M": ["uw", "w|w|"], "X": ["u|u|", "ww"]},
    "yaw": {"Y": ["ur"], "N": ["ur", "r|r|"]},
    "pitch": {"Z": ["uq"], "M": ["uq", "q|q|"]},
}


@dataclass(frozen=True)
class SweepSpec:
    """What to compute (SI: m/s, rad, rad/s).

    speeds : speeds of the straight-ahead cases; drifts, attacks : β and α at the reference
    speed; yaw_rates, pitch_rates : rotating-arm rates at the reference speed; axes : body axes
    with a speed sweep ("x" always; "y", "z" add pure sway and heave); grids : 1 or 3;
    reference_speed : the speed of angle and rate cases (default: the largest speed).
    """

    speeds: tuple[float, ...]
    drifts: tuple[float, ...] = ()
    attacks: tuple[float, ...] = ()
    yaw_rates: tuple[float, ...] = ()
    pitch_rates: tuple[float, ...] = ()
    axes: tuple[str, ...] = ("x",)
    grids: int = 1
    reference_speed: float | None = None

    def __post_init__(self) -> None:
        if not self.speeds:
            raise InputError("no speeds: expected at least one speed in m/s")
        if self.grids not in (1, 3):
            raise InputError(f"--grids = {self.grids!r}: expected 1 or 3 (a refinement triplet)")

    @property
    def reference(self) -> float:
        return float(self.reference_speed if self.reference_speed is not None else max(self.speeds))


def _label(flow: Flow, grid: int) -> str:
    parts = [f"U{flow.speed:g}"]
    if flow.axis != "x":
        parts.append(f"axis-{flow.axis}")
    if flow.drift:
        parts.append(f"beta{math.degrees(flow.drift):+g}")
    if flow.attack:
        parts.append(f"alpha{math.degrees(flow.attack):+g}")
    if flow.yaw_rate:
        parts.append(f"r{flow.yaw_rate:+g}")
    if flow.pitch_rate:
        parts.append(f"q{flow.pitch_rate:+g}")
    parts.append(f"g{grid}")
    return "_".join(parts)


def make_cases(body: Body, spec: SweepSpec, settings: Settings) -> list[Case]:
    """Every case of the sweep, without duplicates, in a stable order.

    A sweep with angles or rates runs all its cases on the 3-D path, its straight ones too:
    derivatives are differences between cases, and a wedge's zero point beside 3-D angle cases
    put the mesh difference into them (a Myring's X at β = 5° was 15 % above the wedge's at
    β = 0, read as X_vv). A profile's pure speed sweep keeps the fast wedge.
    """
    if (spec.drifts or spec.attacks or spec.yaw_rates or spec.pitch_rates) and settings.path == "auto":
        settings = replace(settings, path="3d")
    flows: list[Flow] = []
    for axis in spec.axes:
        flows += [Flow(U, axis=axis) for U in spec.speeds]
    U = spec.reference
    flows += [Flow(U, drift=b) for b in spec.drifts if b != 0]
    flows += [Flow(U, attack=a) for a in spec.attacks if a != 0]
    flows += [Flow(U, yaw_rate=r) for r in spec.yaw_rates if r != 0]
    flows += [Flow(U, pitch_rate=q) for q in spec.pitch_rates if q != 0]
    if (spec.drifts or spec.attacks or spec.yaw_rates or spec.pitch_rates) and U not in spec.speeds:
        flows.append(Flow(U))  # the zero point of the angle and rate sweeps
    grids = (1,) if spec.grids == 1 else (1, 2, 3)
    seen: set[str] = set()
    cases = []
    for flow in flows:
        for g in grids:
            c = Case(body, flow, replace(settings, grid=g), _label(flow, g))
            if c.key() not in seen:
                seen.add(c.key())
                cases.append(c)
    return cases


def _group(outcome: dict[str, Any]) -> tuple[Any, ...]:
    f = outcome["flow"]
    return (f["speed"], f["drift"], f["attack"], f["yaw_rate"], f["pitch_rate"], f.get("axis", "x"))


@dataclass(frozen=True)
class CFDResult(Result):
    """A finished sweep: one row of loads per flow, fits and derivatives.

    rows : per flow (finest grid): speed (m/s), drift_deg, attack_deg, yaw_rate, pitch_rate
        (rad/s), axis, X Y Z (N), K M N (N·m), their ``_std`` and (grids = 3) ``_gci``, status;
        with grids = 3 and the force parts recorded, X Y Z ``_parts_gci`` / ``_parts_convergence`` /
        ``_parts_extrapolated`` (the pressure and viscous parts' grid studies combined)
    outcomes : every case's outcome as run (settings, mesh, iterations, history, times)
    fits : per body axis, the Chin/Morison force–speed fit (hydrokit.estimate.forces.ForceFit)
    derivatives : fitted derivatives (hydrokit.estimate.derivatives.Derivative)
    """

    body: str
    length: float
    area: float
    density: float
    viscosity: float
    reference_speed: float
    rows: tuple[dict[str, Any], ...]
    outcomes: tuple[dict[str, Any], ...] = field(repr=False, default=())
    fits: dict[str, Any] = field(default_factory=dict, repr=False)
    derivatives: tuple[Any, ...] = field(default=(), repr=False)
    executor: str = "serial"
    wall_time: float = 0.0
    warnings: tuple[str, ...] = ()

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [o for o in self.outcomes if o.get("status") == "failed"]

    def to_dict(self) -> dict[str, Any]:
        """What ``cfd.json`` holds: the body, every case (settings, cells, iterations, status,
        y⁺, force history, wall time; the velocity slice is left to the report), the rows, fits
        and derivatives."""
        return jsonable(
            {
                "body": {"name": self.body, "length": self.length, "area": self.area},
                "fluid": {"density": self.density, "viscosity": self.viscosity},
                "reference_speed": self.reference_speed,
                "executor": self.executor,
                "wall_time": self.wall_time,
                "warnings": list(self.warnings),
                "rows": list(self.rows),
                "fits": {axis: fit.to_dict() for axis, fit in self.fits.items()},
                "derivatives": [d.__dict__ for d in self.derivatives],
                "cases": [{k: v for k, v in o.items() if k != "slice"} for o in self.outcomes],
            }
        )

    def coefficients(self) -> dict[str, Any]:
        """What ``coefficients.yaml`` holds (SI): CELY2019's Chin fit per axis with standard
        errors, the derivatives (dimensional and ÷ ½ρL^k), LI2021's linear derivatives at the
        reference speed, and a vehicle ``terms:`` block with its ``uncertainty:`` (σ of each term)."""
        from hydrokit.estimate.derivatives import linear_at

        chin = {}
        for axis, f in self.fits.items():
            c_se = 2 * f.K_D_se / (f.density * f.area)
            chin[axis] = {
                "K_L": f.K_L,
                "K_L_se": f.K_L_se,
                "K_Q": f.K_Q,
                "K_Q_se": f.K_Q_se,
                "r2_chin": f.r2_chin,
                "K_D": f.K_D,
                "K_D_se": f.K_D_se,
                "C_D": f.C_D,
                "C_D_se": c_se,
                "r2_morison": f.r2_morison,
                "area": f.area,
                "points": f.n,
            }
        derivs, linear = {}, {}
        for d in self.derivatives:
            derivs[d.name] = {
                "value": d.value,
                "se": d.se,
                "nondimensional": d.nondimensional,
                "nondimensional_se": d.nondimensional_se,
                "k": d.k,
                "points": d.points,
            }
            lin = linear_at(d, self.reference_speed, self.density, self.length)
            if lin is not None:
                name, v, se, nd, nd_se = lin
                linear[name] = {"value": v, "se": se, "nondimensional": nd, "nondimensional_se": nd_se}
        terms = {d.name: d.value for d in self.derivatives}
        sigma = {d.name: d.se for d in self.derivatives}
        if "x" in self.fits:  # surge resistance as X_u|u| (N·s²/m², negative: it opposes u)
            f = self.fits["x"]
            terms.setdefault("X_u|u|", -f.K_D)
            sigma.setdefault("X_u|u|", f.K_D_se)
        return jsonable(
            {
                "source": "CFD (OpenFOAM, computed by hydrokit cfd)",
                "body": self.body,
                "reference_length": self.length,
                "reference_area": self.area,
                "density": self.density,
                "viscosity": self.viscosity,
                "reference_speed": self.reference_speed,
                "chin": chin,
                "derivatives": derivs,
                "linear_derivatives": linear,
                "terms_nondimensional": False,
                "terms": terms,
                "uncertainty": {"terms": sigma},
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """forces.csv: ``case, speed, drift_deg, attack_deg, yaw_rate, pitch_rate, X … N`` and σ (and
        GCI; and the force's GCI from its pressure and viscous parts, where the cases recorded them)."""
        cols = ["case", "speed", "drift_deg", "attack_deg", "yaw_rate", "pitch_rate", *LOADS]
        cols += [f"{k}_std" for k in LOADS]
        if any("X_gci" in r for r in self.rows):
            cols += [f"{k}_gci" for k in LOADS]
        if any("X_parts_gci" in r for r in self.rows):
            cols += [f"{k}_parts_gci" for k in ("X", "Y", "Z")]
        cols += ["axis", "status"]
        return cols, [[r.get(c) for c in cols] for r in self.rows]

    def forces_csv(self) -> str:
        """The text of ``forces.csv`` (see :meth:`table`; empty cells where a case failed)."""
        cols, rows = self.table()
        return "\n".join([",".join(cols)] + [",".join(_cell(v) for v in r) for r in rows]) + "\n"

    def resistance_csv(self) -> str | None:
        """``resistance.csv`` in ``hydrokit fit-forces``' format (speed m/s, force N = −X, plus
        force_std N) from the straight-ahead cases, or None without any."""
        rows = [r for r in self.rows if r["axis"] == "x" and r["status"] != "failed" and _kind(r) == "straight"]
        if not rows:
            return None
        lines = ["speed,force,force_std"] + [f"{r['speed']:.10g},{-r['X']:.10g},{r['X_std']:.6g}" for r in rows]
        return "\n".join(lines) + "\n"

    def plot(self, ax: Any = None) -> Any:
        """Resistance (−X) against speed with σ bars and the Chin fit; returns the axes."""
        from hydrokit.plot.cfd import resistance_axes

        return resistance_axes(self, ax)


def rows_from(outcomes: Sequence[dict[str, Any]], grids: int) -> tuple[list[dict[str, Any]], list[str]]:
    """One row per flow from the case outcomes: the finest grid's loads, σ and (three grids) GCI."""
    groups: dict[tuple[Any, ...], dict[int, dict[str, Any]]] = {}
    for o in outcomes:
        groups.setdefault(_group(o), {})[int(o["settings"]["grid"])] = o
    rows, notes = [], []
    for key, by_grid in groups.items():
        fine = by_grid[max(by_grid)]
        speed, drift, attack, r, q, axis = key
        row: dict[str, Any] = {
            "case": fine["label"],
            "speed": speed,
            "drift_deg": math.degrees(drift),
            "attack_deg": math.degrees(attack),
            "yaw_rate": r,
            "pitch_rate": q,
            "axis": axis,
            "status": fine.get("status"),
        }
        ok = fine.get("status") != "failed"
        for j, k in enumerate(LOADS):
            row[k] = fine["forces"][j] if ok else math.nan
            row[f"{k}_std"] = fine["std"][j] if ok else math.nan
        if grids == 3:
            have = all(g in by_grid and by_grid[g].get("status") != "failed" for g in (1, 2, 3))
            for j, k in enumerate(LOADS):
                if not have:
                    row[f"{k}_gci"] = math.nan
                    continue
                s1, s2, s3 = (by_grid[g]["forces"][j] for g in (3, 2, 1))
                study = grid_study(s1, s2, s3, math.sqrt(2.0))
                row[f"{k}_gci"] = study.gci
                row[f"{k}_convergence"] = study.kind
                if k == "X" and study.kind != "monotonic":
                    notes.append(f"{fine['label']}: X converges {study.kind}ly over the three grids")
                    if fine.get("model") != "laminar" and fine["settings"].get("turbulence_order", 1) == 1:
                        # first-order k, ω moved the Myring's finest friction against the rest
                        notes.append(
                            f"{fine['label']}: k and ω were convected first-order; --turbulence-order 2 "
                            "(settings: turbulence_order: 2) continues each grid second-order"
                        )
            if have:
                _part_studies(row, [by_grid[g] for g in (3, 2, 1)], notes)
            layers = [by_grid[g].get("prism_layers") for g in (1, 2, 3) if g in by_grid]
            if len(set(layers)) > 1 and None not in layers:
                # a stack laid from a target y⁺ fits in fewer layers as the surface cells shrink
                notes.append(
                    f"{fine['label']}: the three grids carry {' / '.join(map(str, layers))} prism layers; "
                    "their GCI includes that change of near-wall resolution (docs/cfd.md)"
                )
        rows.append(row)
    return rows, notes


#: grid-study kinds from best to worst: a sum of parts is as good as its worst part
_KINDS = ("converged", "monotonic", "oscillatory", "diverging")


def _part_studies(row: dict[str, Any], fine_to_coarse: list[dict[str, Any]], notes: list[str]) -> None:
    """Grid study of each force's pressure and viscous parts apart (``{X,Y,Z}_parts_gci`` N,
    ``_parts_convergence``, ``_parts_extrapolated`` N) when all three grids recorded them.

    The two parts of a hull's resistance converge at their own rates and often from opposite
    sides (the Myring wedge, Re_L 1e6, second-order k and ω: friction 0.771 / 0.780 / 0.786 N,
    pressure 0.094 / 0.089 / 0.088 N), so their sum can fail the three-grid test ("diverging",
    0.865 / 0.869 / 0.874 N) while each part converges monotonically. The parts' GCIs add (both
    errors come from one grid); their extrapolations add where both are monotonic.
    """
    parts = [o.get("force_parts") or {} for o in fine_to_coarse]
    if not all("pressure" in p and "viscous" in p for p in parts):
        return
    for j, k in enumerate(("X", "Y", "Z")):
        studies = [
            grid_study(parts[0][name][j], parts[1][name][j], parts[2][name][j], math.sqrt(2.0))
            for name in ("pressure", "viscous")
        ]
        kind = max((st.kind for st in studies), key=_KINDS.index)
        row[f"{k}_parts_gci"] = sum(st.gci for st in studies)
        row[f"{k}_parts_convergence"] = kind
        ok = kind in ("converged", "monotonic")
        row[f"{k}_parts_extrapolated"] = sum(st.extrapolated for st in studies) if ok else math.nan
        if k == "X" and ok and row.get("X_convergence") not in ("converged", "monotonic"):
            notes.append(
                f"{row['case']}: X's pressure and viscous parts each converge monotonically "
                f"(extrapolated {row['X_parts_extrapolated']:.6g} N, GCI ±{row['X_parts_gci']:.3g} N "
                "from the parts: X_parts_gci)"
            )


def run_sweep(
    body: Body,
    spec: SweepSpec,
    settings: Settings,
    cache_dir: Path,
    *,
    keep_dir: Path | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int], object] | None = None,
    cases: list[Case] | None = None,
    mapper: Callable[..., list[Any]] | None = None,
) -> CFDResult:
    """Run (or take from the cache) every case of the sweep and fit the results.

    Parameters
    ----------
    body, spec, settings : the sweep
    cache_dir : Path — case outcomes by hash (``<key>.json``) and running cases (``run-<key>/``)
    keep_dir : Path, optional — where finished case folders are kept for ParaView
    workers, scheduler : as :class:`hydrokit._parallel.Executor`
    progress : callable, optional — called with 1 as each case finishes
    cases : list of Case, optional — the cases of ``make_cases`` when already made
    mapper : callable, optional — ``mapper(fn, items, progress)`` of a caller's running executor
        (the main job's); ``workers`` and ``scheduler`` are then not used
    """
    from hydrokit._parallel import Executor
    from hydrokit.cfd.run import cached_case

    started = time.perf_counter()
    cases = cases if cases is not None else make_cases(body, spec, settings)
    cache_dir.mkdir(parents=True, exist_ok=True)
    items = [(c, str(cache_dir), None if keep_dir is None else str(keep_dir)) for c in cases]
    try:
        if mapper is not None:
            outcomes = mapper(cached_case, items, progress)
            where = str(getattr(mapper, "description", "the caller's executor"))
        else:
            with Executor(workers, scheduler) as ex:
                outcomes = ex.map(cached_case, items, progress=progress)
                where = ex.description
    except BaseException:
        # a signal or an error tore the workers down mid-case: their case folders are half-made
        # (a serial run removes its own); the cache keeps only whole outcomes
        for c in cases:
            shutil.rmtree(cache_dir / f"run-{c.key()}", ignore_errors=True)
        raise
    return assemble(body, spec, settings, outcomes, executor=where, wall_time=time.perf_counter() - started)


def assemble(
    body: Body,
    spec: SweepSpec,
    settings: Settings,
    outcomes: Sequence[dict[str, Any]],
    *,
    executor: str = "serial",
    wall_time: float = 0.0,
) -> CFDResult:
    """Rows, force–speed fits and derivatives from case outcomes."""
    from hydrokit.estimate.derivatives import fit_derivatives
    from hydrokit.estimate.forces import fit_forces

    rows, notes = rows_from(outcomes, spec.grids)
    warnings = list(notes)
    for o in outcomes:
        if o.get("status") == "failed":
            warnings.append(f"{o['label']}: failed — {o.get('reason', '')}")
        elif o.get("status") != "converged":
            warnings.append(f"{o['label']}: {o['status']} after {o.get('iterations')} iterations (σ from the history)")
    good = [r for r in rows if r["status"] != "failed"]
    fits: dict[str, Any] = {}
    for axis in spec.axes:
        j = "xyz".index(axis)
        straight = [
            r
            for r in good
            if r["axis"] == axis
            and r["drift_deg"] == 0
            and r["attack_deg"] == 0
            and r["yaw_rate"] == 0
            and r["pitch_rate"] == 0
        ]
        speeds = np.array([r["speed"] for r in straight])
        if len(straight) >= 3 and np.unique(speeds).size >= 2:
            # resistance: the force opposing the motion, positive (Chin's F = K_L U + K_Q |U| U)
            force = np.array([-r[LOADS[j]] for r in straight])
            sd = np.array([max(r[f"{LOADS[j]}_std"], r.get(f"{LOADS[j]}_gci", 0.0) or 0.0) for r in straight])
            area = body.area if axis == "x" else _side_area(body, j)
            fits[axis] = fit_forces(speeds, force, area, settings.density, sigma=sd)
        else:
            warnings.append(f"axis {axis}: {len(straight)} straight-ahead speed(s); expected 3 or more for a Chin fit")
    derivatives: list[Any] = []
    U = spec.reference
    for kind, model in MODELS.items():
        pts = [r for r in good if _kind(r) in (kind, "straight") and math.isclose(r["speed"], U) and r["axis"] == "x"]
        if sum(1 for r in pts if _kind(r) == kind) < 2:
            continue
        nu = np.array([_nu(r) for r in pts])
        loads = np.array([[r[k] for k in LOADS] for r in pts])
        sd = np.array([[max(r[f"{k}_std"], r.get(f"{k}_gci", 0.0) or 0.0) for k in LOADS] for r in pts])
        derivatives += fit_derivatives(nu, loads, sd, model, density=settings.density, length=body.length)
    seen: set[str] = set()
    unique = []
    for d in derivatives:  # X_u|u| from drift and attack sweeps alike: keep the first
        if d.name not in seen:
            seen.add(d.name)
            unique.append(d)
    return CFDResult(
        body.name,
        body.length,
        body.area,
        settings.density,
        settings.viscosity,
        U,
        tuple(rows),
        tuple(outcomes),
        fits,
        tuple(unique),
        executor,
        wall_time,
        tuple(warnings),
    )


def _side_area(body: Body, axis: int) -> float:
    from hydrokit.cfd.body import projected_area, revolve

    tri = body.triangles if body.kind == "mesh" else revolve(body.profile)
    return projected_area(tri, axis)


def _kind(r: dict[str, Any]) -> str:
    if r["drift_deg"]:
        return "drift"
    if r["attack_deg"]:
        return "attack"
    if r["yaw_rate"]:
        return "yaw"
    if r["pitch_rate"]:
        return "pitch"
    return "straight"


def _nu(r: dict[str, Any]) -> list[float]:
    flow = Flow(
        r["speed"],
        math.radians(r["drift_deg"]),
        math.radians(r["attack_deg"]),
        r["yaw_rate"],
        r["pitch_rate"],
        r["axis"],
    )
    u, v, w = flow.velocity()
    return [u, v, w, 0.0, r["pitch_rate"], r["yaw_rate"]]


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return "" if not math.isfinite(v) else f"{v:.10g}"
    text = str(v)
    return '"' + text.replace('"', '""') + '"' if any(ch in text for ch in ',"\n') else text
