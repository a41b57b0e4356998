"""Steps 2–4 of ``hydrokit run``: other sources, the comparison table, the choice, the vehicle.

Sources of a full-scale coefficient (SI, the vehicle file's units):

- ``tank`` — the identified campaign, scaled with λ (mean, 95 % CI, standard error);
- ``geometry`` — the semi-empirical estimate of the geometry file (added mass and damping);
- ``bem`` — the boundary-element added mass (``--bem``; damping stays semi-empirical);
- ``cfd`` — the Chin fit K_L, K_Q of a CFD or tow-tank force curve (damping only);
- ``sysid`` — identified from the vehicle's own free-running runs (value ± σ of every free
  diagonal coefficient, :mod:`hydrokit.pipeline.sysid`);
- ``published`` — values printed by a source (shown, never chosen).

The rule of a DOF names the preferred source; a coefficient that source lacks (no value, or an
estimate of 0: the shape tables give none) falls back along tank → sysid → cfd → bem →
geometry, and finally keeps the base vehicle's value. The report states
which source every chosen number came from (CELY2019 §5 compares tank with CFD the same way).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.io.project import Project
from hydrokit.model.uncertainty import COEFFICIENTS

FALLBACK = ("tank", "sysid", "cfd", "bem", "geometry")
#: sources that measure a coefficient (any finite value counts; the estimates' 0 means "none")
MEASURED = ("tank", "cfd", "sysid")
#: two-sided 95 % normal quantile (the sysid interval: σ from the Fisher information)
Z95 = 1.959963984540054
#: coefficients whose negative values are not chosen (energy would be fed in)
DAMPING = ("linear_damping", "quadratic_damping")
#: the coefficient keys of a published entry
PUBLISHED_KEYS = COEFFICIENTS


def geometry_sources(project: Project, bem: bool) -> dict[str, Any]:
    """``{"geometry": {dof: {coef: value}}, "bem": … or None}`` from the project's geometry file."""
    from hydrokit.api import estimate_geometry, load_geometry

    assert project.geometry is not None
    geo = load_geometry(project.geometry)
    out: dict[str, Any] = {"geometry": _diagonals(estimate_geometry(geo).composite), "bem": None}
    if bem:
        comp = estimate_geometry(geo, bem=True).composite
        out["bem"] = {d: {"added_mass": v["added_mass"]} for d, v in _diagonals(comp).items()}
    return out


def _diagonals(comp: Any) -> dict[str, dict[str, float]]:
    return {
        d: {
            "added_mass": float(comp.added_mass[i, i]),
            "linear_damping": float(comp.linear_damping[i, i]),
            "quadratic_damping": float(comp.quadratic_damping[i, i]),
        }
        for i, d in enumerate(DOF_NAMES)
    }


def cfd_sources(project: Project, tank: dict[str, Any], density: float) -> dict[str, Any]:
    """Per DOF with a force curve: the Chin fit (K_L, K_Q with standard errors) and Morison C_D."""
    from hydrokit.api import fit_forces
    from hydrokit.io.forces import read_forces

    out = {}
    for dof, spec in project.forces.items():
        speed, force = read_forces(spec.file)
        area = spec.area
        if area is None:
            t = tank.get(dof)
            area = t["reference_area_full"] if t and t.get("reference_area_full") else 1.0
        fit = fit_forces(speed, force, area, spec.density or density)
        out[dof] = {
            "linear_damping": fit.K_L,
            "quadratic_damping": fit.K_Q,
            "se": {"linear_damping": fit.K_L_se, "quadratic_damping": fit.K_Q_se},
            "drag_coefficient": fit.C_D,
            "area": area,
            "points": fit.n,
        }
    return out


def cfd_sweep_inputs(project: Project, density: float) -> tuple[Any, Any, Any, list[Any]]:
    """(body, settings, sweep, cases) of the project's ``cfd:`` section, checked: a bad body or
    setting is refused here, before the run identifies anything."""
    from hydrokit.api import load_cfd_body
    from hydrokit.cfd.case import Settings
    from hydrokit.cfd.sweep import SweepSpec, make_cases
    from hydrokit.errors import InputError
    from hydrokit.io.project import CFD_AXES

    spec = project.cfd
    assert spec is not None
    src = str(project.source)
    body = load_cfd_body(spec.body)
    try:
        settings = Settings(
            density=spec.density or density, viscosity=spec.viscosity, turbulence=spec.turbulence, **spec.settings
        )
        sweep = SweepSpec(spec.speeds, axes=tuple(CFD_AXES[d] for d in spec.dofs), grids=spec.grids)
    except TypeError as exc:
        raise InputError(f"field 'cfd.settings': {exc}; expected fields of hydrokit.cfd.case.Settings", src) from None
    except InputError as exc:
        raise InputError(f"field 'cfd': {exc}", src) from None
    return body, settings, sweep, make_cases(body, sweep, settings)


def computed_cfd_sources(
    project: Project, density: float, cache_dir: Any, mapper: Any = None, progress: Any = None
) -> dict[str, Any]:
    """The CFD column computed with OpenFOAM (``hydrokit cfd``) for the DOFs of ``cfd:``: per DOF
    the Chin fit of its speed sweep (weighted by each case's σ), as :func:`cfd_sources` gives.
    ``progress`` is called with 1 as each case finishes (cached ones at once)."""
    from dataclasses import replace

    from hydrokit.cfd.foam import find_openfoam
    from hydrokit.cfd.sweep import assemble, run_sweep
    from hydrokit.io.project import CFD_AXES

    body, settings, sweep, cases = cfd_sweep_inputs(project, density)
    find_openfoam()
    result = run_sweep(body, sweep, settings, cache_dir, cases=cases, mapper=mapper, progress=progress)
    spec = project.cfd
    assert spec is not None
    out: dict[str, Any] = {}
    for dof in spec.dofs:
        fit = result.fits.get(CFD_AXES[dof])
        if fit is None:
            continue
        if dof in spec.area:  # the project's reference area: C_D over it, the K's unchanged
            result = assemble(replace(body, area=spec.area[dof]), sweep, settings, result.outcomes)
            fit = result.fits.get(CFD_AXES[dof], fit)
        out[dof] = {
            "linear_damping": fit.K_L,
            "quadratic_damping": fit.K_Q,
            "se": {"linear_damping": fit.K_L_se, "quadratic_damping": fit.K_Q_se},
            "drag_coefficient": fit.C_D,
            "area": fit.area,
            "points": fit.n,
            "computed": f"OpenFOAM ({len(result.outcomes)} cases, {len(result.failed)} failed)",
        }
    return out


def _given(source: str, value: float | None) -> bool:
    """A usable value: finite, and for the estimates also non-zero (a shape table that has no
    entry, e.g. a block's rotational added mass or any linear damping, gives 0)."""
    if value is None or not math.isfinite(value):
        return False
    return source in MEASURED or value > 0


def _tank_value(step: dict[str, Any], coef: str) -> float | None:
    return step["full_scale"][coef]["mean"]


def comparison(
    project: Project, tank: dict[str, Any], others: dict[str, Any], base: Any
) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """The comparison rows and the chosen coefficients.

    Parameters
    ----------
    tank : DOF → identification step document
    others : {"geometry": …, "bem": …, "cfd": …, "sysid": …} (any may be None)
    base : the base Vehicle (its diagonal values are the last fallback)

    Returns
    -------
    rows : one per DOF and coefficient with every source's value, its relative difference
        from the tank value (%) and from the sysid value (%); the sysid value's σ and 95 %
        interval; chosen : DOF → coefficient → {value, source, se}
    """
    from hydrokit.pipeline.sysid import diagonal_values

    sysid = diagonal_values(others.get("sysid"))
    spec = getattr(project, "sysid", None)
    sysid_truth = (spec.truth if spec is not None else None) or {}
    dofs = [d for d in DOF_NAMES if d in tank or d in sysid or any(d in (others.get(k) or {}) for k in ("cfd",))]
    dofs += [d for d in project.published if d not in dofs]
    base_diag = {
        "added_mass": np.diag(base.M_A),
        "linear_damping": np.diag(base.D_L),
        "quadratic_damping": np.asarray(base.D_Q),
    }
    rows = []
    chosen: dict[str, Any] = {}
    for dof in DOF_NAMES:
        i = DOF_NAMES.index(dof)
        for coef in COEFFICIENTS:
            vals: dict[str, float | None] = {
                "tank": _tank_value(tank[dof], coef) if dof in tank else None,
                "geometry": ((others.get("geometry") or {}).get(dof) or {}).get(coef),
                "bem": ((others.get("bem") or {}).get(dof) or {}).get(coef),
                "cfd": ((others.get("cfd") or {}).get(dof) or {}).get(coef),
                "sysid": (sysid.get(dof, {}).get(coef) or {}).get("value"),
            }
            rule = project.choose[dof]
            order = [rule] + [s for s in FALLBACK if s != rule]
            # a negative damping feeds energy in: said in the report, never written into the vehicle
            negative = {s: v for s, v in vals.items() if coef in DAMPING and _given(s, v) and v is not None and v < 0}
            source = next((s for s in order if _given(s, vals[s]) and s not in negative), "base")
            value = float(base_diag[coef][i]) if source == "base" else float(vals[source])  # type: ignore[arg-type]
            se = None
            if source == "tank":
                se = tank[dof]["full_scale"][coef]["se"]
            elif source == "cfd":
                se = others["cfd"][dof]["se"].get(coef)
            elif source == "sysid":
                se = sysid[dof][coef]["sigma"]
            chosen.setdefault(dof, {})[coef] = {"value": value, "source": source, "se": se}
            if negative:
                chosen[dof][coef]["negative"] = negative
            if dof not in dofs:
                continue
            pub = project.published.get(dof, {})
            published = pub.get(coef) if isinstance(pub.get(coef), (int, float)) else None
            ref = vals["tank"]
            truth = ((tank.get(dof) or {}).get("truth") or {}).get(coef, {}).get("full")
            sigma = (sysid.get(dof, {}).get(coef) or {}).get("sigma")
            s_val = vals["sysid"]
            row: dict[str, Any] = {
                "dof": dof,
                "coefficient": coef,
                "tank": ref,
                "tank_ci": tank[dof]["full_scale"][coef]["ci"] if dof in tank else None,
                "truth": truth if truth is not None else sysid_truth.get(f"{coef}.{dof}"),
                "truth_source": "tank" if truth is not None else ("sysid" if f"{coef}.{dof}" in sysid_truth else None),
                **{k: vals[k] if _given(k, vals[k]) else None for k in ("geometry", "bem", "cfd", "sysid")},
                "sysid_sigma": sigma,
                "sysid_ci": _interval(s_val, sigma),
                "published": published,
                "published_source": pub.get("source"),
                "base": float(base_diag[coef][i]),
                "chosen": value,
                "chosen_source": source,
                "rule": rule,
            }
            row["relative_to_tank_percent"] = {
                k: (100.0 * (row[k] - ref) / ref if ref and row[k] is not None else None)
                for k in ("geometry", "bem", "cfd", "sysid", "published", "truth")
            }
            row["relative_to_sysid_percent"] = {
                k: (100.0 * (row[k] - s_val) / s_val if s_val and row[k] is not None else None)
                for k in ("tank", "geometry", "bem", "cfd", "published", "truth")
            }
            rows.append(row)
    return rows, chosen


def _interval(value: float | None, sigma: float | None) -> list[float] | None:
    if value is None or sigma is None or not (math.isfinite(value) and math.isfinite(sigma)):
        return None
    return [value - Z95 * sigma, value + Z95 * sigma]


def sysid_terms(project: Project, sysid: dict[str, Any] | None) -> list[dict[str, Any]]:
    """The free ``terms.*`` of the sysid step: name, DOF, value, σ, unit, and whether it is
    written into the vehicle (its force's DOF chooses sysid; the comparison has no other
    source for a term)."""
    from hydrokit.pipeline.sysid import term_dof

    out = []
    for name, p in ((sysid or {}).get("parameters") or {}).items():
        if not name.startswith("terms."):
            continue
        dof = term_dof(name)
        out.append(
            {
                "name": name,
                "dof": dof,
                "value": p["value"],
                "sigma": p["sigma"],
                "unit": p["unit"],
                "truth": p.get("truth"),
                "written": project.choose[dof] == "sysid",
            }
        )
    return out


def vehicle_document(
    base_data: dict[str, Any],
    chosen: dict[str, Any],
    tank: dict[str, Any],
    project: Project,
    sysid: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """The base vehicle file's fields with the chosen diagonals and an ``uncertainty:`` block.

    ``uncertainty`` holds the standard errors (SI, full scale; 0 where the value carries no
    identified uncertainty) of the ``added_mass``, ``linear_damping`` and ``quadratic_damping``
    diagonals, and the covariance over the listed ``parameters``: every chosen coefficient with
    a σ > 0, whatever its source (block-diagonal: campaigns and sources are independent; within
    a campaign the means of one launch set co-vary; the coefficients chosen from sysid, and
    the free terms it writes, keep their joint covariance from the fit).

    ``sysid`` is the sysid step document: its free ``terms.*`` are written into ``terms`` (as
    :func:`hydrokit.io.vehicle.write_terms`) when their DOF's rule is sysid
    (:func:`sysid_terms`), with their σ under ``uncertainty.parameters``; when any value comes
    from sysid the file carries the fit's ``identification:`` block (its verdict) and its ``envelope:``
    block (what its runs covered), so that ``simulate`` and ``manoeuvre`` warn when they fly a vehicle
    whose fit does not describe its runs, or fly it outside them.
    """
    doc = {
        k: v for k, v in base_data.items() if k not in ("identification", "envelope")
    }  # the base's claim is not ours
    doc["name"] = f"{project.name}-identified"
    for coef in COEFFICIENTS:
        values = doc[coef]
        matrix = bool(values) and all(isinstance(r, list) for r in values)
        values = [list(map(float, r)) for r in values] if matrix else [float(x) for x in values]
        for i, dof in enumerate(DOF_NAMES):
            v = chosen[dof][coef]["value"]
            if matrix:
                values[i][i] = v
            else:
                values[i] = v
        doc[coef] = values
    params: list[str] = []
    blocks: list[np.ndarray] = []
    se = {c: [0.0] * 6 for c in COEFFICIENTS}
    for i, dof in enumerate(DOF_NAMES):
        for c in COEFFICIENTS:
            s = chosen[dof][c]["se"]
            se[c][i] = float(s) if s is not None and math.isfinite(s) else 0.0
        picked = [c for c in COEFFICIENTS if chosen[dof][c]["source"] == "tank"]
        if picked:
            cov = np.asarray(tank[dof]["covariance"], float)
            idx = [COEFFICIENTS.index(c) for c in picked]
            blocks.append(cov[np.ix_(idx, idx)])
            params += [f"{c}.{dof}" for c in picked]
        # a σ from another source (a CFD fit's standard errors) is sampled too, independent of
        # the tank's (another experiment); the fit's K_L–K_Q correlation is not kept
        for c in COEFFICIENTS:
            if chosen[dof][c]["source"] not in ("tank", "sysid") and se[c][i] > 0:
                blocks.append(np.array([[se[c][i] ** 2]]))
                params.append(f"{c}.{dof}")
    # the sysid parameters chosen (and terms written) keep their joint covariance from the fit
    if sysid:
        from hydrokit.pipeline.sysid import write_terms

        terms = [t for t in sysid_terms(project, sysid) if t["written"]]
        write_terms(doc, [(t["name"], t["value"]) for t in terms])
        names = list(sysid["names"])
        taken = [f"{c}.{dof}" for dof in DOF_NAMES for c in COEFFICIENTS if chosen[dof][c]["source"] == "sysid"] + [
            t["name"] for t in terms
        ]
        idx = [names.index(n) for n in names if n in taken]
        block = sysid.get("identification")
        if idx and block:  # the vehicle flies the fit's values: it carries the fit's verdict (no date:
            # the main job's files are the same on every run of the same inputs)
            doc["identification"] = {k: v for k, v in block.items() if k != "date"}
            envelope = (sysid.get("result") or {}).get("envelope")
            if envelope:  # and what its runs covered (issue #56 item 7)
                doc["envelope"] = envelope
        if idx:
            cov = np.asarray(sysid["covariance"], float)[np.ix_(idx, idx)]
            blocks.append(0.5 * (cov + cov.T))
            params += [names[k] for k in idx]
            for k in idx:  # the σ lists say what the covariance says (the file reader checks it)
                coef, _, dof = names[k].partition(".")
                if coef in COEFFICIENTS:
                    se[coef][DOF_NAMES.index(dof)] = math.sqrt(max(float(np.asarray(sysid["covariance"])[k][k]), 0.0))
    n = len(params)
    cov_all = np.zeros((n, n))
    k = 0
    for b in blocks:
        m = b.shape[0]
        cov_all[k : k + m, k : k + m] = np.nan_to_num(b)
        k += m
    doc["uncertainty"] = {
        "description": "standard errors of the identified full-scale means (SI) and their covariance; "
        "0 where a value has no identified uncertainty",
        "added_mass": se["added_mass"],
        "linear_damping": se["linear_damping"],
        "quadratic_damping": se["quadratic_damping"],
        "parameters": params,
        "covariance": cov_all.tolist(),
    }
    doc["project"] = {
        "name": project.name,
        "sources": {dof: {c: chosen[dof][c]["source"] for c in COEFFICIENTS} for dof in DOF_NAMES},
        "virtual_data": project.virtual,
    }
    return doc
