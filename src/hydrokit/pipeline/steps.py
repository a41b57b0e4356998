"""The steps of ``hydrokit run`` in order, each looked up in the cache before it is computed."""

from __future__ import annotations

import base64
import json
import os
import time
from collections.abc import Callable
from typing import Any

from hydrokit._result import jsonable
from hydrokit.errors import InputError
from hydrokit.io.project import Project
from hydrokit.model.uncertainty import COEFFICIENTS
from hydrokit.pipeline.cache import StepCache, digest, file_digest, run_key

CONTROLLERS = ("pid", "s-plane")

#: version of the sysid step's cached result: raised when what the step returns changes (2: the
#: verdict, the physical-sign bounds and free surface and thruster fields; 3: the window, as
#: hydrokit sysid's default, and the estimator), so results cached before are computed again
#: rather than read
SYSID_STEP_VERSION = 3


def _png64(png: bytes) -> str:
    return base64.b64encode(png).decode("ascii")


class Runner:
    """Runs the steps of one project (see :mod:`hydrokit.pipeline`)."""

    def __init__(
        self,
        project: Project,
        cache: StepCache,
        mapper: Any,
        progress: Callable[[str, int], Callable[[int], None]],
        bem: bool,
        samples: int,
    ):
        from hydrokit.api import load_mission, load_rig, vehicle_from_dict
        from hydrokit.io.yamlfile import read_yaml

        self.p, self.cache, self.mapper, self.progress = project, cache, mapper, progress
        self.bem, self.samples = bem, samples
        self.timings: list[dict[str, Any]] = []
        self.warnings: list[str] = []
        # everything is read and checked before the first step runs
        self.base_data = read_yaml(project.vehicle)
        self.base = vehicle_from_dict(self.base_data, self.rel(project.vehicle))
        self.mission = load_mission(project.mission) if project.mission else None
        if self.mission is not None and (self.base.thrusters is None or len(self.base.thrusters) == 0):
            raise InputError(
                f"field 'mission' = {self.rel(project.mission)!r}: the vehicle {self.rel(project.vehicle)} has no "
                "'thrusters:' block; expected a vehicle with thrusters to fly a mission",
                str(project.source),
            )
        self.rigs = {c.dof: load_rig(c.rig) for c in project.campaigns}
        self.cfd_cases: list[Any] = []
        if project.cfd is not None:  # the body and OpenFOAM are checked before any step runs
            from hydrokit.cfd.foam import find_openfoam
            from hydrokit.pipeline.compare import cfd_sweep_inputs

            self.cfd_cases = cfd_sweep_inputs(project, self.base.density)[3]
            find_openfoam()
        if project.sysid is not None:
            self._check_sysid()
        self.digests = {str(p): file_digest(p) for p in project.input_files()}

    def _check_sysid(self) -> None:
        """The method and the free names against the base vehicle, before any step runs."""
        from hydrokit.sysid.fit import METHODS
        from hydrokit.sysid.model import free_parameters

        spec = self.p.sysid
        assert spec is not None
        src = str(self.p.source)
        if spec.method not in METHODS:
            raise InputError(f"field 'sysid.method' = {spec.method!r}: expected one of {', '.join(METHODS)}", src)
        try:
            free_parameters(self.base, list(spec.free), "")
        except InputError as exc:
            raise InputError(f"field 'sysid.free': {exc.detail}", src) from None

    def rel(self, path: Any) -> str:
        """A path as the report shows it: relative to the project folder when inside it."""
        text = str(path)
        try:
            return os.path.relpath(os.path.abspath(text), os.path.abspath(self.p.root))
        except ValueError:  # another drive (Windows)
            return text

    def _timed(self, name: str, fn: Callable[..., Any], *args: Any) -> Any:
        hits = len(self.cache.hits)
        t0 = time.perf_counter()
        out = fn(*args)
        self.timings.append({"step": name, "seconds": time.perf_counter() - t0, "cached": len(self.cache.hits) > hits})
        return out

    def _cached(self, step: str, key: str, compute: Callable[[], Any]) -> Any:
        hit = self.cache.load(step, key)
        if hit is not None:
            return hit
        out = jsonable(compute())
        self.cache.store(step, key, out)
        return out

    # -- steps -----------------------------------------------------------------------------
    def identify(self) -> dict[str, Any]:
        from hydrokit.pipeline.tank import identify_campaign_step

        tank = {}
        for spec in self.p.campaigns:
            key = digest(
                "identify",
                spec.dof,
                spec.method,
                spec.scale_ratio,
                spec.truth,
                self.digests[str(spec.rig)],
                [(p.name, self.digests[str(p)]) for p in spec.launches],
                [(p.name, self.digests[str(p)]) for p in spec.tare],
                spec.tare_convention,
            )

            def compute(spec: Any = spec) -> dict[str, Any]:
                advance = self.progress(f"identify {spec.dof} ({len(spec.launches)} launches)", len(spec.launches))
                return identify_campaign_step(spec, self.rigs[spec.dof], self.mapper, advance, self.rel)

            tank[spec.dof] = self._timed(f"identify {spec.dof}", self._cached, f"identify-{spec.dof}", key, compute)
        return tank

    def sysid(self, tank: dict[str, Any]) -> dict[str, Any] | None:
        """The sysid source: identified from the project's runs, starting from the base vehicle
        with the tank's diagonals (:func:`hydrokit.pipeline.sysid.start_vehicle`)."""
        spec = self.p.sysid
        if spec is None:
            return None
        from hydrokit.pipeline.sysid import start_vehicle, sysid_step

        vehicle, from_tank = start_vehicle(self.base, tank)
        key = digest(
            "sysid",
            SYSID_STEP_VERSION,
            self.digests[str(self.p.vehicle)],
            from_tank,
            [(p.name, self.digests[str(p)]) for p in spec.runs],
            [(p.name, self.digests[str(p)]) for p in spec.holdout],
            list(spec.free),
            spec.method,
            spec.dt,
            spec.truth,
            spec.window,
            spec.window_continuity,
            self.p.seed,
        )

        def compute() -> dict[str, Any]:
            advance = self.progress(
                f"sysid: {len(spec.free)} parameters from {len(spec.runs)} run(s), {len(spec.holdout)} held out "
                "(iterations)",
                30,
            )
            return sysid_step(spec, vehicle, self.p.seed, advance, self.rel, from_tank)

        return self._timed("sysid", self._cached, "sysid", key, compute)  # type: ignore[no-any-return]

    def others(self, tank: dict[str, Any]) -> dict[str, Any]:
        from hydrokit.pipeline.compare import cfd_sources, geometry_sources

        out: dict[str, Any] = {"geometry": None, "bem": None, "cfd": None}
        if self.p.geometry is not None:
            key = digest("geometry", self.digests[str(self.p.geometry)], self.bem)

            def compute() -> dict[str, Any]:
                self.progress("geometry estimate" + (" and BEM" if self.bem else ""), 1)
                return geometry_sources(self.p, self.bem)

            out.update(self._timed("geometry", self._cached, "geometry", key, compute))
        if self.p.forces:
            out["cfd"] = self._timed("cfd fit", cfd_sources, self.p, tank, self.base.density)
        if self.p.cfd is not None:
            from hydrokit.pipeline.compare import computed_cfd_sources

            n = len(self.cfd_cases)
            res = sorted(c.reynolds for c in self.cfd_cases)
            span = f", Re_L {res[0]:.3g}–{res[-1]:.3g}" if res else ""
            advance = self.progress(f"CFD with OpenFOAM ({n} cases{span}; cached cases are free)", n)
            computed = self._timed(
                "cfd (OpenFOAM)",
                computed_cfd_sources,
                self.p,
                self.base.density,
                self.cache.directory / "cfd",
                self.mapper,
                advance,
            )
            out["cfd"] = {**(out["cfd"] or {}), **computed}
        return out

    def fly(self, vehicle_doc: dict[str, Any], truth_doc: dict[str, Any] | None) -> dict[str, Any] | None:
        if self.mission is None:
            return None
        from hydrokit.pipeline.missions import fly_nominal

        key = digest("missions", self.digests[str(self.p.mission)], vehicle_doc, truth_doc)

        def compute() -> dict[str, Any]:
            advance = self.progress("fly the mission (PID, S-plane)", 2 * (2 if truth_doc else 1))
            return fly_nominal(str(self.p.mission), vehicle_doc, truth_doc, advance)

        return self._timed("mission", self._cached, "missions", key, compute)

    def monte_carlo(self, vehicle_doc: dict[str, Any], flights: dict[str, Any]) -> dict[str, Any] | None:
        if self.mission is None or self.samples == 0:
            return None
        from hydrokit.pipeline.missions import monte_carlo_step

        key = digest("monte-carlo", self.digests[str(self.p.mission)], vehicle_doc, self.samples, self.p.seed)

        def compute() -> dict[str, Any]:
            from hydrokit.pipeline.fleet import task_count

            advance = self.progress(
                f"Monte Carlo ({self.samples} samples × 2 controllers, in chunks)",
                task_count(self.samples, CONTROLLERS),
            )
            return monte_carlo_step(
                str(self.p.mission), vehicle_doc, flights, self.samples, self.p.seed, self.mapper, advance
            )

        return self._timed("monte carlo", self._cached, "monte-carlo", key, compute)

    # -- the chain -------------------------------------------------------------------------
    def run(self) -> Any:
        from hydrokit.pipeline.compare import comparison, vehicle_document

        tank = self.identify()
        sysid = self.sysid(tank)
        others = self.others(tank)
        others["sysid"] = sysid
        rows, chosen = comparison(self.p, tank, others, self.base)
        vdoc = jsonable(vehicle_document(self.base_data, chosen, tank, self.p, sysid))
        truth_doc = None
        if self.p.campaigns and all(c.truth for c in self.p.campaigns):
            truth_doc = json.loads(json.dumps(vdoc))
            truth_doc["name"] = f"{self.p.name}-true"
            for dof, t in tank.items():
                i = ("surge", "sway", "heave", "roll", "pitch", "yaw").index(dof)
                for c in COEFFICIENTS:
                    v = truth_doc[c]
                    if isinstance(v[i], list):
                        v[i][i] = t["truth"][c]["full"]
                    else:
                        v[i] = t["truth"][c]["full"]
        flights = self.fly(vdoc, truth_doc)
        mc = self.monte_carlo(vdoc, flights) if flights is not None else None
        return self._result(tank, others, rows, chosen, vdoc, flights, mc)

    def _result(self, tank, others, rows, chosen, vdoc, flights, mc) -> Any:  # noqa: ANN001
        from hydrokit.io.vehicle import vehicle_text
        from hydrokit.pipeline.result import RunResult, rounded

        warnings: list[str] = []
        for t in tank.values():
            warnings += t["warnings"]
        sysid = others.get("sysid")
        if sysid is not None:
            warnings += sysid["warnings"]
        warnings += [f"{self.rel(self.p.vehicle)}: {w}" for w in self.base.warnings]
        warnings += negative_damping_warnings(chosen)
        if mc is not None and mc.get("clipped_at_zero"):
            warnings.append(f"Monte Carlo: {mc['clipped_at_zero']} sampled coefficient(s) below zero were set to 0")
        seen: dict[str, None] = {}
        for w in warnings:
            seen.setdefault(w, None)
        campaigns = {
            dof: {k: v for k, v in t.items() if k not in ("launch_figures", "summary_figures")}
            for dof, t in tank.items()
        }
        doc = {
            "hydrokit_result": "run",
            "project": {
                "name": self.p.name,
                "file": self.p.source.name,
                "description": self.p.description,
                "virtual_data": self.p.virtual,
                "scale_ratio": self.p.scale_ratio,
                "choose": self.p.choose,
                "inputs": {self.rel(k): v for k, v in self.digests.items()},
            },
            "units": {
                "added_mass": "kg (translation), kg m^2 (rotation); full scale",
                "linear_damping": "N s/m, N m s/rad; full scale",
                "quadratic_damping": "N s^2/m^2, N m s^2/rad^2; full scale",
                "path": "m (NED)",
                "time": "s",
            },
            "campaigns": campaigns,
            "sources": {k: v for k, v in others.items() if v is not None and k != "sysid"},
            "sysid": None if sysid is None else _sysid_summary(self.p, sysid),
            "comparison": rows,
            "chosen": chosen,
            "vehicle": vdoc,
            "missions": None if flights is None else {k: v for k, v in flights.items() if k not in ("figures", "csv")},
            "monte_carlo": None if mc is None else {k: v for k, v in mc.items() if k != "figures"},
            "warnings": list(seen),
            "engine": self.mapper.description,
        }
        figures: dict[str, list[dict[str, str]]] = {}
        for dof, t in tank.items():
            figures[f"summary:{dof}"] = t["summary_figures"]
            figures[f"launches:{dof}"] = t["launch_figures"]
        if sysid is not None:
            figures["sysid"] = sysid["figures"]
        if flights is not None:
            figures["missions"] = flights["figures"]
        if mc is not None:
            figures["monte_carlo"] = mc["figures"]
        header = (
            f"# {self.p.name}: identified vehicle written by hydrokit run from {self.p.source.name}.\n"
            "# Coefficients: chosen per DOF (see project.sources); uncertainty: standard errors (SI).\n"
        )
        files = {"vehicle.yaml": vehicle_text(vdoc, header)}
        if flights is not None:
            for name, text in flights["csv"].items():
                files[f"mission/{name}"] = text
            metrics = {"missions": doc["missions"], "monte_carlo": _without_paths(doc["monte_carlo"])}
            files["mission/metrics.json"] = json.dumps(rounded(jsonable(metrics)), indent=2, allow_nan=False) + "\n"
        key = run_key(self.digests, self.bem, self.samples)
        return RunResult(jsonable(doc), figures, files, self.timings, key)


def _sysid_summary(project: Project, step: dict[str, Any]) -> dict[str, Any]:
    """results.json's ``sysid``: the step without its figures, with the free terms and whether
    each is written into the vehicle."""
    from hydrokit.pipeline.compare import sysid_terms

    out = {k: v for k, v in step.items() if k != "figures"}
    out["terms"] = sysid_terms(project, step)
    return out


def negative_damping_warnings(chosen: dict[str, Any]) -> list[str]:
    """One report warning per chosen coefficient whose value from some source came out negative
    (:func:`hydrokit.pipeline.compare.comparison` skips it)."""
    out = []
    for dof, coefs in chosen.items():
        for coef, c in coefs.items():
            for source, v in (c.get("negative") or {}).items():
                out.append(
                    f"{dof} {coef}: the {source} value {v:.4g} (SI, full scale) is negative — energy would be fed "
                    f"in; not written into the vehicle, which takes the {c['source']} value {c['value']:.4g}"
                )
    return out


def _without_paths(mc: dict[str, Any] | None) -> dict[str, Any] | None:
    if mc is None:
        return None
    out = dict(mc)
    out["controllers"] = {
        c: {k: v for k, v in s.items() if k not in ("sample_paths", "envelope")} for c, s in mc["controllers"].items()
    }
    out.pop("grid", None)
    return out
