"""Step 1 of ``hydrokit run``: identify one campaign and bring it to full scale.

Every launch is read, trimmed and fitted as an independent task (serial or on Dask); the
campaign is summarised here. The step's output is a JSON document: the campaign's result
document, the full-scale means with their 95 % CI, standard errors and the 3×3 covariance of
(added mass, K_L, K_Q) means, the truth when the data are virtual, and the figures as base64 PNG.
"""

from __future__ import annotations

import base64
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from hydrokit.core.names import COEFFICIENTS
from hydrokit.identify.result import IdentifiedLaunch, coefficient_units, summarize_campaign
from hydrokit.identify.scaling import EXPONENTS
from hydrokit.io.project import CampaignSpec

#: reduced-resolution launch figures keep a 70-launch report small
LAUNCH_DPI = 80


def fit_task(task: tuple[Any, str, str]) -> tuple[Any, Any, np.ndarray, str]:
    """One launch: read, trim, fit and draw its fit/residual figure (a picklable task for a
    worker process, so the figures are drawn in parallel too).

    Parameters
    ----------
    task : (Rig, launch file path, method)

    Returns
    -------
    (Launch, LaunchResult, fitted signal at the launch's sample times in m or rad, base64 PNG)
    """
    from hydrokit.api import read_launch
    from hydrokit.identify.result import fit_launch, predict
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.identify import launch_fit

    rig, path, method = task
    item = fit_launch(rig, read_launch(path, rig), method)
    fitted = predict(item)
    name = Path(path).stem
    unit = "m" if rig.translational_signal else "rad"
    fig = launch_fit(np.asarray(item.launch.t), np.asarray(item.launch.y), fitted, name, unit, compact=True)
    return item.launch, item.result, fitted, _png64(to_png(fig, LAUNCH_DPI))


def _png64(png: bytes) -> str:
    return base64.b64encode(png).decode("ascii")


def t95(n: int) -> float:
    """Two-sided 95 % Student-t quantile for the mean of ``n`` values (normal when n is large)."""
    from scipy import stats

    return float(stats.t.ppf(0.975, max(n - 1, 1)))


def air_tare_step(spec: CampaignSpec, rig: Any, relative: Callable[[str], str] = str) -> dict[str, Any]:
    """The ENG2009 §IV.A air tare fitted to the campaign's in-air launches: effective length (m)
    and pivot friction as K_L (N·s/m) and K_Q (N·s²/m²; γ m r with the ``eng2009`` convention
    of ``spec.tare_convention``) with standard errors, to subtract."""
    from hydrokit.api import read_launch
    from hydrokit.errors import InputError
    from hydrokit.identify.tare import fit_air_tare, quadratic_factor

    if rig.test != "pendulum":
        raise InputError(
            f"campaigns ({spec.dof}).tare: an air tare is for a pendulum rig; {relative(str(spec.rig))} is a {rig.test} rig"
        )
    air = [read_launch(p, rig) for p in spec.tare]
    fit, info = fit_air_tare(air, rig.mass, rig.gravity, convention=spec.tare_convention)
    se = info["std_error"]
    return {
        "files": [relative(str(p)) for p in spec.tare],
        "convention": spec.tare_convention,
        "effective_length": fit.effective_length,
        "linear_damping": fit.linear_damping,
        "quadratic_damping": fit.quadratic_damping,
        "std_error": {
            "linear_damping": se["beta"] * rig.mass,
            "quadratic_damping": se["gamma"] * quadratic_factor(rig.mass, fit.effective_length, spec.tare_convention),
        },
        "alpha": info["alpha"],
        "rms_residual": info.get("rms_residual"),
        "rig_length": rig.pendulum_length,
    }


def campaign_covariance(results: list[Any], summary: dict[str, Any], groups: dict[str, list[str]]) -> dict[str, Any]:
    """Covariance of the campaign means of (m_a, K_L, K_Q), model scale, from the launches no rule
    rejected: the launch-to-launch part (sample covariance / n) plus, on the diagonal, the
    between-amplitude-group variance of the group means / k (random effects: the launches of one
    amplitude share its model error — sensor lag, release, unmodelled damping — which the
    launch scatter alone does not show; on the bundled virtual campaigns the launch part alone
    put the true surge (K_L, K_Q) at a Mahalanobis distance² of 17, the sum at 0.8)."""
    rejected = set().union(*(set(summary[c]["rejected"] or []) for c in COEFFICIENTS))
    ok = {
        r.file: [getattr(r, c) for c in COEFFICIENTS]
        for r in results
        if r.file not in rejected
        and all(getattr(r, c) is not None and math.isfinite(getattr(r, c)) for c in COEFFICIENTS)
    }
    n = len(ok)
    if n < 2:
        nan = np.full((3, 3), np.nan)
        return {"total": nan, "launches": nan, "between_groups": nan, "n": n, "groups": 0}
    launches = np.cov(np.asarray(list(ok.values()), float), rowvar=False) / n
    members = [[ok[f] for f in files if f in ok] for files in groups.values()]
    means = [np.mean(m, axis=0) for m in members if m]
    k = len(means)
    between = np.diag(np.var(np.asarray(means), axis=0, ddof=1) / k) if k >= 2 else np.zeros((3, 3))
    return {"total": launches + between, "launches": launches, "between_groups": between, "n": n, "groups": k}


def identify_campaign_step(
    spec: CampaignSpec,
    rig: Any,
    mapper: Callable[..., list[Any]],
    advance: Callable[[int], None] | None = None,
    relative: Callable[[str], str] = str,
) -> dict[str, Any]:
    """Identify ``spec`` and return the step document (JSON-ready).

    Parameters
    ----------
    spec : CampaignSpec — DOF, rig, launch files, method, model/full length ratio
    rig : Rig — the parsed rig file
    mapper : ``mapper(fn, items, progress)`` → results in order (serial or Dask)
    advance : callable, optional — called with 1 after each launch
    relative : callable — a path as the report should show it (relative to the project)
    """
    from hydrokit._result import jsonable
    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.identify import drag_vs_reynolds

    tare = air_tare_step(spec, rig, relative) if spec.tare else None
    if tare is not None:
        from hydrokit.identify.tare import AirTare, apply_tare

        rig = apply_tare(rig, AirTare(tare["effective_length"], tare["linear_damping"], tare["quadratic_damping"]))
    fitted = mapper(fit_task, [(rig, str(p), spec.method) for p in spec.launches], advance)
    items = [IdentifiedLaunch(launch, result, None, pred) for launch, result, pred, _ in fitted]
    campaign = summarize_campaign(rig, spec.method, items)
    doc = campaign.to_dict()
    for launch in doc["launches"]:
        launch["file"] = relative(launch["file"])
    for entry in doc["summary"].values():
        if isinstance(entry, dict) and entry.get("rejected"):
            entry["rejected"] = [relative(f) for f in entry["rejected"]]
    doc["groups"] = {k: [relative(f) for f in files] for k, files in doc["groups"].items()}
    summary = campaign.summary
    lam = 1.0 / spec.scale_ratio
    exps = EXPONENTS[bool(rig.rotational)]
    factor = {c: lam ** exps[c] for c in COEFFICIENTS}
    parts = campaign_covariance(campaign.results, summary, campaign.groups)
    tare_var = np.zeros((3, 3))
    if tare is not None:
        # the subtracted tare is one number for every launch: its error does not average out
        se = tare["std_error"]
        tare_var = np.diag([0.0, se["linear_damping"] ** 2, se["quadratic_damping"] ** 2])
    f = np.array([factor[c] for c in COEFFICIENTS])
    full_cov = (parts["total"] + tare_var) * np.outer(f, f)
    full: dict[str, Any] = {}
    for i, c in enumerate(COEFFICIENTS):
        s = summary[c]
        ci = s["ci"] or [None, None]
        mean = None if s["mean"] is None else s["mean"] * factor[c]
        se = math.sqrt(full_cov[i, i]) if math.isfinite(full_cov[i, i]) else None
        full[c] = {
            "mean": mean,
            # 95 % interval of the stated uncertainty (launch scatter, amplitude groups, tare):
            # Student-t with the launches' degrees of freedom
            "ci": [mean - t95(s["n"]) * se, mean + t95(s["n"]) * se] if mean is not None and se else [None, None],
            "ci_launches": [None if v is None else v * factor[c] for v in ci],
            "se": se,
            "n": s["n"],
        }
    units = coefficient_units(rig)
    truth = None
    if spec.truth:
        truth = {c: {"model": spec.truth[c], "full": spec.truth[c] * factor[c]} for c in COEFFICIENTS}
    warnings = [
        relative(w.split(": ", 1)[0]) + ": " + w.split(": ", 1)[1] if ": " in w else w for w in campaign.warnings
    ]
    if rig.scale and abs(rig.scale - spec.scale_ratio) > 1e-9 * spec.scale_ratio:
        warnings.append(
            f"{relative(str(spec.rig))}: scale {rig.scale} differs from the project's scale_ratio "
            f"{spec.scale_ratio} for {spec.dof}; the project's value is used"
        )
    figures = [
        {"name": Path(p).stem, "caption": f"{Path(p).stem}: measured and fitted, residual", "png": png}
        for p, (*_, png) in zip(spec.launches, fitted)
    ]
    summary_figs = []
    for c in COEFFICIENTS:
        ax = campaign.plot(coefficient=c)
        summary_figs.append(
            {
                "name": f"{spec.dof}_{c}",
                "caption": f"{spec.dof}: {c} per launch against amplitude; mean and 95 % CI; hollow = rejected",
                "png": _png64(to_png(ax.figure, 90)),
            }
        )
    fig = drag_vs_reynolds(campaign.results, summary.get("drag_coefficient", {}), f"{spec.dof}: C_D against Re")
    summary_figs.append(
        {
            "name": f"{spec.dof}_drag_vs_reynolds",
            "caption": f"{spec.dof}: C_D per launch against its peak Reynolds number (±1.96 SE); hollow = rejected",
            "png": _png64(to_png(fig, 90)),
        }
    )
    return jsonable(
        {
            "dof": spec.dof,
            "rig_file": relative(str(spec.rig)),
            "launches_pattern": spec.pattern,
            "method": spec.method,
            "scale_ratio": spec.scale_ratio,
            "lambda": lam,
            "rotational": bool(rig.rotational),
            "reference_area_full": rig.reference_area * lam**2 if rig.reference_area else None,
            "units": units,
            "campaign": doc,
            "full_scale": full,
            "covariance": full_cov,
            "covariance_parts": {
                "launches": parts["launches"] * np.outer(f, f),
                "between_groups": parts["between_groups"] * np.outer(f, f),
                "tare": tare_var * np.outer(f, f),
                "n_launches": parts["n"],
                "n_groups": parts["groups"],
            },
            "truth": truth,
            "tare": tare,
            "warnings": warnings,
            "summary_figures": summary_figs,
            "launch_figures": figures,
        }
    )
