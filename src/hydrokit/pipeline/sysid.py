"""The ``sysid`` source of ``hydrokit run``: a vehicle's coefficients from its own dives.

The project's ``sysid:`` section names run files (docs/sysid.md), the free parameters, the
method and the estimator's window as ``hydrokit sysid`` takes it (``window``: a length in s,
``auto`` by default, or ``none``; ``window_continuity``, dimensionless); :func:`sysid_step`
identifies them with :func:`hydrokit.api.identify_runs` and returns a JSON-ready document
(value, σ and covariance per parameter, the estimator and why, the identifiability messages,
per-run residuals and held-out NRMSE, figures) that the comparison reads as one more source,
beside tank, geometry, BEM and CFD.

Start vehicle: the project's base vehicle with every tank-identified diagonal coefficient
(full-scale mean) written in — the best knowledge the project holds before the dives. Every
coefficient that is not free keeps that value in the fit, and a wrong fixed value biases the
free ones, so the tank's numbers are the better guess; the free ones start from the
equation-error fit of the runs anyway. A negative tank damping is not written in (it would feed
energy in); the base's value stays.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from hydrokit.core.names import DOF_NAMES
from hydrokit.io.project import SysidSpec

# write_terms and doc_surfaces moved to hydrokit.io.vehicle (writing a vehicle document is the io
# layer's job); re-exported here for one release.
from hydrokit.io.vehicle import doc_surfaces, write_terms  # noqa: F401
from hydrokit.model.uncertainty import COEFFICIENTS, check_parameter

#: Monte Carlo draws of the prediction band in the run's sysid figures
BAND_SAMPLES = 40
#: damping coefficients: a negative tank value is not written into the start vehicle
_DAMPING = ("linear_damping", "quadratic_damping")


def tank_values(tank: Mapping[str, Any]) -> dict[str, float]:
    """``{"<coefficient>.<dof>": full-scale mean}`` of every identified campaign (SI); a
    non-finite value, or a negative damping, is left out."""
    out = {}
    for dof, step in tank.items():
        for coef in COEFFICIENTS:
            v = step["full_scale"][coef]["mean"]
            if v is None or not math.isfinite(v) or (coef in _DAMPING and v < 0):
                continue
            out[f"{coef}.{dof}"] = float(v)
    return out


def start_vehicle(base: Any, tank: Mapping[str, Any]) -> tuple[Any, dict[str, float]]:
    """The vehicle sysid starts from: ``base`` with the tank's diagonals (module docstring).
    Returns it and the values written in (name → SI)."""
    from hydrokit.model.uncertainty import with_coefficients

    values = tank_values(tank)
    return (with_coefficients(base, values) if values else base), values


def sysid_step(
    spec: SysidSpec,
    vehicle: Any,
    seed: int,
    advance: Callable[[int], None],
    rel: Callable[[Any], str],
    from_tank: Mapping[str, float] | None = None,
) -> dict[str, Any]:
    """Identify ``spec.free`` of ``vehicle`` from ``spec.runs`` (``spec.holdout`` for validation).

    Parameters
    ----------
    spec : SysidSpec — the project's ``sysid:`` section
    vehicle : Vehicle with thrusters — the start (:func:`start_vehicle`)
    seed : int — seed of the prediction band's draws
    advance : callable(n) — progress, called once per accepted iteration
    rel : callable(path) → str — how the report names a file
    from_tank : name → value (SI) written into the start from the tank campaigns

    Returns
    -------
    dict — ``verdict`` (``fits``, ``reasons``: does the model describe the runs), ``window``
    (as asked: a length, s, ``"auto"`` or ``"none"``) and ``window_continuity`` (–),
    ``estimator`` (which estimator fitted the runs and why: ``method``, ``window_s`` — s, None for
    whole runs — ``jacobian_step_s`` — s — and ``why``, as sysid.json), ``parameters``
    (name → value, sigma, unit, start, base, equation_error, identifiable, truth), ``covariance``
    (SI², in ``names`` order), ``result`` (sysid.json without the prediction series),
    ``figures`` (base64 PNG), ``warnings`` (the verdict's reasons first when it does not fit),
    ``identification`` (the vehicle file's block: :func:`hydrokit.io.vehicle.identification_block`).
    """
    from hydrokit.api import identify_runs
    from hydrokit.io.vehicle import identification_block

    result = identify_runs(
        vehicle,
        spec.runs,
        list(spec.free),
        spec.holdout,
        method=spec.method,
        dt=spec.dt,
        window=spec.window,
        window_continuity=spec.window_continuity,
        samples=BAND_SAMPLES,
        seed=seed,
        progress=lambda it, cost: advance(1),
    )
    doc = result.to_dict()
    truth = spec.truth or {}
    params = {}
    for entry in doc["parameters"]:
        params[entry["name"]] = {
            "value": entry["value"],
            "sigma": entry["sigma"],
            "unit": entry["unit"],
            "start": entry["start"],
            "base": entry["base"],
            "equation_error": entry["equation_error"],
            "identifiable": entry["identifiable"],
            "truth": truth.get(entry["name"]),
        }
    said = [] if result.verdict["fits"] else [f"sysid: {r}" for r in result.verdict["reasons"]]
    warnings = said + [f"sysid: {m}" for m in (*result.messages, *result.warnings)]
    for name, p in params.items():
        s = p["sigma"]
        if s is not None and math.isfinite(s) and s >= abs(p["value"]):
            warnings.append(
                f"sysid: {name} = {p['value']:.4g} ± {s:.2g}: σ exceeds the value, not identifiable from these runs"
            )
    return {
        "verdict": doc["verdict"],
        "runs": [rel(p) for p in spec.runs],
        "holdout": [rel(p) for p in spec.holdout],
        "pattern": spec.pattern,
        "free": list(spec.free),
        "method": spec.method,
        "dt": spec.dt,
        "window": "none" if spec.window is None else spec.window,
        "window_continuity": spec.window_continuity,
        "estimator": dict(result.estimator),
        "start_vehicle": {"name": vehicle.name, "from_tank": dict(from_tank or {})},
        "names": list(result.parameters),
        "parameters": params,
        "covariance": np.asarray(result.covariance, float).tolist(),
        "truth_file": rel(spec.truth_file) if spec.truth_file is not None else None,
        "result": {k: v for k, v in doc.items() if k not in ("parameters", "covariance")},
        "figures": _figures(result),
        "warnings": warnings,
        "identification": identification_block(result),
    }


def _figures(result: Any) -> list[dict[str, str]]:
    """Measured vs simulated per run (held-out ones marked) and the correlation heat map."""
    import base64

    from hydrokit.plot._mpl import to_png
    from hydrokit.plot.sysid import correlation_figure, run_figure

    out = []
    for p in result.predictions:
        note = " (held out: open-loop prediction)" if p["holdout"] else ""
        out.append(
            {
                "name": f"sysid-{p['name']}",
                "caption": f"{p['name']}{note}: measured (dots), simulated (line), 95 % band from the covariance",
                "png": base64.b64encode(to_png(run_figure(p), dpi=70)).decode("ascii"),
            }
        )
    fig = correlation_figure(result.parameters, result.correlation)
    out.append(
        {
            "name": "sysid-correlation",
            "caption": "Correlation of the identified parameters",
            "png": base64.b64encode(to_png(fig, dpi=70)).decode("ascii"),
        }
    )
    return out


def diagonal_values(step: Mapping[str, Any] | None) -> dict[str, dict[str, dict[str, float]]]:
    """DOF → coefficient → {value, sigma} of the free diagonal coefficients of a sysid step."""
    out: dict[str, dict[str, dict[str, float]]] = {}
    if not step:
        return out
    for name, p in step["parameters"].items():
        coef, _, dof = name.partition(".")
        if coef in COEFFICIENTS and dof in DOF_NAMES:
            out.setdefault(dof, {})[coef] = {"value": p["value"], "sigma": p["sigma"]}
    return out


def _named_surfaces(name: str) -> tuple[str, ...]:
    """The surface names a term's ``delta(NAME)`` factors use (``terms.Y_uu*delta(rudder)`` →
    rudder): the DOF of a term does not depend on which surfaces the vehicle has."""
    import re

    return tuple(re.findall(r"delta\(\s*([^()\s]+)\s*\)", name))


def _named_thrusters(name: str) -> tuple[str, ...]:
    """The thruster names a term's ``T(NAME)`` and ``n(NAME)`` factors use, as
    :func:`_named_surfaces` (``terms.N_T(prop)*delta(rudder)`` → prop)."""
    import re

    return tuple(re.findall(r"(?<![A-Za-z])[Tn]\(\s*([^()\s]+)\s*\)", name))


def term_dof(name: str) -> str:
    """The DOF whose force a ``terms.<term>`` parameter enters (``terms.N_r|r|`` → yaw;
    ``terms.N_uu*delta(rudder)`` → yaw; ``terms.Y_T(prop)*delta(rudder)`` → sway)."""
    return DOF_NAMES[check_parameter(name, "parameter", "", _named_surfaces(name), _named_thrusters(name)).dof]
