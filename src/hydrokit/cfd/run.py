"""Running one case: mesh, check, solve until the force history settles, read the results.

:func:`run_case` works in a private folder and returns a JSON-ready outcome; :func:`cached_case`
wraps it with the cache (one ``<key>.json`` per case, written whole after the run) so a rerun
or an interrupted sweep recomputes only the missing cases. A case that fails (mesh, divergence,
timeout) becomes an outcome with ``status: failed`` and OpenFOAM's one-line reason; it is not
cached, and the other cases of a sweep go on.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import shutil
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.cfd import history
from hydrokit.cfd.case import Case, foam_file, solver, write_case, write_second_stage, write_stl
from hydrokit.cfd.foam import OpenFOAM, SolverError, find_openfoam

#: force-history points kept in an outcome (for convergence plots)
HISTORY_POINTS = 200
#: checkMesh findings that make a mesh unusable (others are kept as notes in the outcome)
_FATAL_MESH = ("negative volume", "incorrectly oriented", "not planar")
#: sectors of the full body represented by a wedge of this angle: forces × 360/angle
WEDGE_DEG = 5.0


def _mesh_dicts(case: Case) -> dict[str, Any]:
    if case.path == "wedge":
        from hydrokit.cfd import wedge

        x, r = case.body.profile[:, 0], case.body.profile[:, 1]
        # y⁺ = 1 for turbulent flow; at low Re that height exceeds a laminar boundary layer
        # (δ ≈ 5 L / √Re): then a twentieth of δ, and never more than 2 % of the body's radius.
        # A y⁺ asked for in the settings is laid out as asked (within the 2 %) and held on every
        # grid level, so a wall-function grid study refines the grid, not the wall treatment
        L, re, y_plus = case.body.length, case.reynolds, case.settings.y_plus
        if y_plus > 0:
            first = min(wedge.first_cell_height(L, re, y_plus), 0.02 * float(r.max()))
        else:
            first = min(wedge.first_cell_height(L, re, 1.0), 0.25 * L / math.sqrt(re), 0.02 * float(r.max()))
        return {
            "blockMeshDict": wedge.blockmesh_dict(
                x,
                r,
                first_cell=first,
                level=case.settings.grid,
                upstream=case.settings.upstream,
                downstream=case.settings.downstream,
                radial=case.settings.lateral,
                wedge_deg=WEDGE_DEG,
                hold_first_cell=y_plus > 0,
            )
        }
    from hydrokit.cfd import mesh3d

    return mesh3d.mesh_dicts(case)


def _check_mesh(log: Path) -> dict[str, Any]:
    text = log.read_text(errors="replace")
    cells = re.search(r"^\s*cells:\s+(\d+)", text, re.MULTILINE)
    failed = re.search(r"Failed (\d+) mesh checks", text)
    ortho = re.search(r"Mesh non-orthogonality Max:\s*([\d.eE+-]+)", text)
    skew = re.search(r"Max skewness = ([\d.eE+-]+)", text)
    problems = [" ".join(m.split()) for m in re.findall(r"\*\*\*([^\n]*)", text)]
    return {
        "cells": int(cells.group(1)) if cells else 0,
        "failed_checks": int(failed.group(1)) if failed else 0,
        "problems": problems,
        "max_non_orthogonality": float(ortho.group(1)) if ortho else None,
        "max_skewness": float(skew.group(1)) if skew else None,
    }


def _y_plus(case_dir: Path) -> list[float] | None:
    files = sorted(case_dir.glob("postProcessing/yPlus/*/yPlus.dat"))
    if not files:
        return None
    rows = history.read_dat(files[-1])
    if rows.size == 0 or rows.shape[1] < 4:
        return None
    return [float(rows[-1, 1]), float(rows[-1, 2]), float(rows[-1, 3])]  # min, max, average


#: velocity-slice points kept in an outcome (for the report's figure)
SLICE_POINTS = 4000


def _slice(case: Case, folder: Path) -> dict[str, list[float]] | None:
    """|U| on the z = 0 plane near the body from the last write: x, y (m, body axes) and |U|/U∞,
    at most :data:`SLICE_POINTS` points within one body length of the body."""
    files = sorted(folder.glob("postProcessing/slice/*/*_zNormal.raw"), key=lambda p: float(p.parent.name))
    if not files:
        return None
    try:
        data = np.loadtxt(files[-1], comments="#", ndmin=2)
    except ValueError:
        return None
    if data.shape[1] < 6 or not len(data):
        return None
    x, y = data[:, 0], data[:, 1]
    if case.path == "wedge":  # profile coordinates: x from the nose, y the radius
        x = case.body.centre_of_buoyancy - x
    speed = np.linalg.norm(data[:, 3:6], axis=1) / case.flow.speed
    lo, hi = case.body.bounds()
    L = case.body.length
    near = (x > lo[0] - L) & (x < hi[0] + 1.5 * L) & (np.abs(y) < max(hi[1], -lo[1]) + 0.75 * L)
    idx = np.flatnonzero(near)
    if idx.size > SLICE_POINTS:
        idx = idx[np.linspace(0, idx.size - 1, SLICE_POINTS).astype(int)]
    return {k: [float(f"{v:.5g}") for v in arr[idx]] for k, arr in (("x", x), ("y", y), ("speed", speed))}


def _thin(it: np.ndarray, values: np.ndarray) -> dict[str, list[float]]:
    step = max(1, int(math.ceil(len(it) / HISTORY_POINTS)))
    keep = np.r_[np.arange(0, len(it), step), len(it) - 1] if len(it) else np.zeros(0, int)
    keep = np.unique(keep)
    out = {"iteration": [float(i) for i in it[keep]]}
    for j, name in enumerate(("X", "Y", "Z", "K", "M", "N")):
        out[name] = [float(v) for v in values[keep, j]]
    return out


def body_loads(case: Case, raw: np.ndarray) -> np.ndarray:
    """Loads on the whole body from OpenFOAM's (n, 6) history: a wedge holds 5° of the body, so
    its axial force × 360/5 is the body's and the other five vanish by symmetry (the wedge's own
    radial force is not a load on the body)."""
    if case.path == "wedge":  # built in profile coordinates, whose x points aft: X = −F_x
        return raw * np.array([-360.0 / WEDGE_DEG, 0, 0, 0, 0, 0])
    return raw


def loads_and_parts(case: Case, post: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Iterations (n,), loads on the body (n, 6) and the force's pressure and viscous parts in
    body axes (n, 6: X, Y, Z of the pressure part, then of the viscous part, N; None when
    OpenFOAM wrote no parts), from one reading of ``postProcessing/forces``."""
    it, raw, pressure, viscous = history.read_all(post)
    if len(pressure) == 0:
        return it, body_loads(case, raw), None
    zeros = np.zeros_like(pressure)
    parts = [body_loads(case, np.column_stack([part, zeros]))[:, :3] for part in (pressure, viscous)]
    return it, body_loads(case, raw), np.column_stack(parts)


def _rule(case: Case) -> dict[str, Any]:
    """The case's convergence rule as :func:`history.converged` and :func:`history.judge` take it."""
    s = case.settings
    return {
        "window": s.window,
        "min_iterations": s.min_iterations,
        "tolerance": s.tolerance,
        "length": case.body.length,
    }


def settled(case: Case, post: Path) -> bool:
    """True when the history in ``post`` (``postProcessing/forces``) has converged by the case's
    settings: the loads and the force's pressure and viscous parts (the solver's stop signal)."""
    _, values, parts = loads_and_parts(case, post)
    return history.converged(values, parts=parts, **_rule(case))


def judged(case: Case, values: np.ndarray, parts: np.ndarray | None) -> history.Judgement:
    """A finished run's judgement of :func:`loads_and_parts`' loads and parts by the case's settings."""
    return history.judge(values, parts=parts, **_rule(case))


def _force_parts(parts: np.ndarray | None, samples: int) -> dict[str, list[float]]:
    """Mean pressure and viscous force [X, Y, Z], N, body axes, over the judged last ``samples``
    rows of :func:`loads_and_parts`' (n, 6) parts (empty when OpenFOAM wrote no parts)."""
    if parts is None or len(parts) == 0:
        return {}
    mean = parts[max(0, len(parts) - max(1, samples)) :].mean(axis=0)
    return {"pressure": [float(v) for v in mean[:3]], "viscous": [float(v) for v in mean[3:]]}


def run_case(case: Case, folder: Path, foam: OpenFOAM | None = None) -> dict[str, Any]:
    """Build and run ``case`` in ``folder`` (created; must not exist); return its outcome.

    Returns
    -------
    dict — ``status`` (converged, averaged, not converged or failed), ``forces`` and ``std``
    (X Y Z in N, K M N in N·m, body axes, SNAME signs), ``mesh`` (cells, checks), ``iterations``,
    ``y_plus`` [min, max, mean] (turbulent cases), ``history`` (thinned force history),
    ``force_parts`` (``pressure`` and ``viscous`` force [X, Y, Z], N, over the same iterations),
    ``prism_layers`` (3-D path: the layers asked of snappyHexMesh, count),
    ``wall_time`` and ``foam_time`` (s: all, and inside OpenFOAM's programs), ``reason`` when failed.
    """
    started = time.perf_counter()
    foam = foam or find_openfoam()
    folder.mkdir(parents=True)
    times: dict[str, float] = {}
    outcome: dict[str, Any] = {
        "key": case.key(),
        "label": case.label,
        "path": case.path,
        "model": case.model,
        "reynolds": case.reynolds,
        "flow": asdict(case.flow),
        "settings": asdict(case.settings),
    }

    def run(program: str, args: tuple[str, ...] = (), **kw: Any) -> None:
        t0 = time.perf_counter()
        try:
            foam.run(program, folder, args, timeout=case.settings.timeout, **kw)
        finally:
            times[program] = times.get(program, 0.0) + time.perf_counter() - t0

    try:
        dicts = _mesh_dicts(case)
        write_case(case, folder, dicts)
        if case.path == "3d":
            from hydrokit.cfd.mesh3d import end_triangles, layer_plan, surface_names

            outcome["prism_layers"] = layer_plan(case)[0]  # asked of snappyHexMesh (count)

            surfaces = dict(zip(surface_names(case), case.body.surfaces(), strict=True))
            if "ends.stl" in dicts["snappyHexMeshDict"]["geometry"]:  # refined, not a wall
                surfaces["ends"] = end_triangles(case)
            for name, tri in surfaces.items():
                write_stl(folder / "constant" / "triSurface" / f"{name}.stl", tri, name)
            run("blockMesh")
            run("surfaceFeatureExtract")
            run("snappyHexMesh", ("-overwrite",))
        else:
            run("blockMesh")
        run("checkMesh", check=False)
        outcome["mesh"] = _check_mesh(folder / "log.checkMesh")
        if outcome["mesh"]["cells"] == 0:
            raise SolverError(f"the mesh has no cells (log: {folder / 'log.checkMesh'})")
        fatal = [p for p in outcome["mesh"]["problems"] if any(w in p for w in _FATAL_MESH)]
        if fatal:  # a solver would run on it and return numbers; they would mean nothing
            raise SolverError(f"checkMesh: {fatal[0]} (log: {folder / 'log.checkMesh'})")
        post = folder / "postProcessing" / "forces"
        n = case.settings.processes
        if n > 1:
            # Debian's OpenFOAM ships scotch as a stub: slabs along the flow instead
            foam_file(
                folder / "system" / "decomposeParDict",
                {"numberOfSubdomains": n, "method": "simple", "simpleCoeffs": {"n": [n, 1, 1], "delta": 0.001}},
            )
            run("decomposePar", ("-force",))
        run(solver(case), monitor=lambda: settled(case, post), processes=n)
        it, values, parts = loads_and_parts(case, post)
        first: tuple[np.ndarray, np.ndarray] | None = None
        if case.settings.turbulence_order == 2 and case.model != "laminar":
            first, stages = _second_stage(case, folder, post, run)
            outcome["stages"] = stages
            if first is not None:
                it, values, parts = loads_and_parts(case, post)
        if len(values) and not np.any(values):
            # every load exactly zero: the mesher kept no face of the body (a surface it could not
            # refine into, or a region choice that dropped it); a converged zero is no answer
            raise SolverError(
                f"the body has no faces in the mesh (all loads are 0); see {folder / 'log.snappyHexMesh'}"
            )
        if len(values) == 0 or not np.all(np.isfinite(values)):
            raise SolverError(f"the solver wrote no finite forces (diverged?) (log: {folder / f'log.{solver(case)}'})")
        j = judged(case, values, parts)
        whole = (it, values) if first is None else (np.r_[first[0], it], np.r_[first[1], values])
        outcome.update(
            status=j.status,
            forces=[float(v) for v in j.mean],
            std=[float(v) for v in j.std],
            iterations=j.iterations + (0 if first is None else len(first[0])),
            samples=j.samples,
            autocorrelation_time=j.tau,
            y_plus=_y_plus(folder),
            slice=_slice(case, folder),
            history=_thin(*whole),
            force_parts=_force_parts(parts, j.samples),
        )
    except SolverError as exc:
        outcome.update(status="failed", reason=str(exc))
    outcome["foam_time"] = sum(times.values())
    outcome["foam_times"] = times
    outcome["wall_time"] = time.perf_counter() - started
    return outcome


def _second_stage(
    case: Case, folder: Path, post: Path, run: Any
) -> tuple[tuple[np.ndarray, np.ndarray] | None, list[dict[str, Any]]]:
    """``turbulence_order`` 2: once the first-order stage has settled, rewrite the schemes to a
    second-order k, ω and run the solver on from the state it wrote (its forces go to a new
    start-time folder, which the judgement then reads alone).

    Returns the first stage's (iterations, loads) — None when it did not settle, and the case
    stays first-order (a history that has not settled is no state to continue from) — and the
    ``stages`` record of cfd.json.
    """
    it, values, _ = loads_and_parts(case, post)
    stages: list[dict[str, Any]] = [
        {"convection": "upwind", "iterations": len(it), "settled": bool(settled(case, post))}
    ]
    if not stages[0]["settled"] or len(it) == 0:
        stages.append({"convection": "linearUpwind", "skipped": "the first-order stage did not settle"})
        return None, stages
    write_second_stage(case, folder, int(it[-1]))
    run(
        solver(case),
        log=f"log.{solver(case)}.2",
        monitor=lambda: settled(case, post),
        processes=case.settings.processes,
    )
    stages.append({"convection": "linearUpwind", "iterations": len(loads_and_parts(case, post)[0])})
    return (it, values), stages


def cached_case(item: tuple[Case, str, str | None]) -> dict[str, Any]:
    """Run one case through the cache: ``(case, cache_dir, keep_dir)`` → outcome.

    A cached outcome (``cache_dir/<key>.json``) is returned as it is, with ``cached: true``.
    Otherwise the case runs in ``cache_dir/run-<key>`` and its outcome is written whole to
    ``<key>.json`` when it did not fail; the case folder is moved to ``keep_dir/<label>-<key>``
    when ``keep_dir`` is given and removed otherwise. Module-level so Dask workers can run it.
    """
    case, cache_dir, keep_dir = item
    cache = Path(cache_dir)
    key = case.key()
    done = cache / f"{key}.json"
    if done.exists():
        with contextlib.suppress(ValueError, OSError):
            outcome = json.loads(done.read_text())
            if keep_dir is None or (Path(keep_dir) / _case_name(case)).exists():
                outcome["cached"] = True
                outcome["label"] = case.label
                return outcome
    work = cache / f"run-{key}"
    shutil.rmtree(work, ignore_errors=True)  # a run interrupted before: start again
    try:
        outcome = run_case(case, work)
        outcome["cached"] = False
        if outcome["status"] != "failed":
            tmp = cache / f".{key}.json.part"
            tmp.write_text(json.dumps(outcome, allow_nan=False if _finite(outcome) else True))
            os.replace(tmp, done)
        if keep_dir is not None and outcome["status"] != "failed":
            dest = Path(keep_dir) / _case_name(case)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.rmtree(dest, ignore_errors=True)
            shutil.move(str(work), dest)
            outcome["case_dir"] = str(dest)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return outcome


def _case_name(case: Case) -> str:
    label = re.sub(r"[^A-Za-z0-9_.+-]+|\.{2,}", "_", case.label)[:60].lstrip(".") or "case"
    return f"{label}-{case.key()}"


def _finite(outcome: dict[str, Any]) -> bool:
    try:
        json.dumps(outcome, allow_nan=False)
    except ValueError:
        return False
    return True


def running_iterations(cache_dir: Path) -> dict[str, tuple[int, int]]:
    """Cases running under ``cache_dir``: key → (iterations done, most iterations), from the
    force history and controlDict on disk (read by the progress display, in any process)."""
    out: dict[str, tuple[int, int]] = {}
    for run in Path(cache_dir).glob("run-*"):
        key = run.name[4:]
        top = 0
        with contextlib.suppress(OSError, ValueError):
            m = re.search(r"\bendTime\s+(\d+)", (run / "system" / "controlDict").read_text())
            top = int(m.group(1)) if m else 0
        done = 0
        for dat in run.glob("postProcessing/forces/*/force.dat"):
            with contextlib.suppress(OSError, ValueError), open(dat, "rb") as fh:
                fh.seek(0, os.SEEK_END)
                fh.seek(max(0, fh.tell() - 400))
                lines = fh.read().decode(errors="replace").splitlines()
                for ln in reversed(lines[1:] if len(lines) > 1 else lines):
                    word = ln.split()[0] if ln.split() else ""
                    if word and not word.startswith("#"):
                        done = int(float(word))
                        break
        out[key] = (done, top)
    return out
