"""Identification of launch files and the JSON result document (issue #2 format).

``{"launches": [...], "summary": {...}, "pairwise": [...], "rig": {...}, "method": ...}``;
each launch object holds every :class:`hydrokit.identify.types.LaunchResult` field plus
``notes`` (what reading and trimming did).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from hydrokit.identify.types import Launch, LaunchResult, Rig


@dataclass
class IdentifiedLaunch:
    """One launch: the trimmed record, its result and the fitted estimator (for plots)."""

    launch: Launch
    result: LaunchResult
    estimator: Any


def identify_files(
    rig: Rig,
    files: Sequence[str],
    method: str = "output-error",
    release: float | None = None,
    end: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> list[IdentifiedLaunch]:
    """Read, trim and identify each launch file (errors name the file; nothing is written).

    Parameters
    ----------
    rig : Rig
    files : launch CSV paths
    method : estimator name
    release, end : float, optional — release and last useful time, s (default: detected)
    progress : callable, optional — called with each file name when it is done
    """
    from hydrokit.identify.estimators import identify_launch, with_notes
    from hydrokit.identify.preprocess import trim_launch
    from hydrokit.io.launch import read_launch

    out = []
    for f in files:
        raw = read_launch(f, rig)
        launch = trim_launch(raw, release=release, end=end)
        result, est = identify_launch(rig, launch, method, return_estimator=True)
        out.append(IdentifiedLaunch(launch, with_notes(result, launch.notes), est))
        if progress is not None:
            progress(f)
    return out


def results_document(rig: Rig, items: Sequence[IdentifiedLaunch], method: str) -> dict[str, Any]:
    """The JSON document of a run (see module docstring)."""
    from hydrokit.identify.campaign import group_by_amplitude, rank_sum_pairs, summarize
    from hydrokit.io.rig import rig_to_dict

    results = [it.result for it in items]
    launches = []
    for r in results:
        d = r.to_dict()
        d["notes"] = d.get("extra", {}).pop("notes", [])
        launches.append(d)
    groups = group_by_amplitude(results, angles=rig.test != "spring")
    pairwise = {}
    for coef in ("added_mass", "linear_damping", "quadratic_damping"):
        pairwise[coef] = rank_sum_pairs({k: [getattr(r, coef) for r in g] for k, g in groups.items()})
    doc = {
        "hydrokit_result": "identify",
        "method": method,
        "rig": rig_to_dict(rig),
        "units": _units(rig),
        "launches": launches,
        "summary": summarize(results),
        "groups": {k: [r.file for r in g] for k, g in groups.items()},
        "pairwise": pairwise,
    }
    return _clean(doc)


def _units(rig: Rig) -> dict[str, str]:
    if rig.rotational:
        return {"added_mass": "kg m^2", "linear_damping": "N m s/rad", "quadratic_damping": "N m s^2/rad^2",
                "natural_frequency": "rad/s", "amplitude": "rad", "rms_residual": "rad"}
    sig = "m" if rig.test == "spring" else "rad"
    return {"added_mass": "kg", "linear_damping": "N s/m", "quadratic_damping": "N s^2/m^2",
            "natural_frequency": "rad/s", "amplitude": sig, "rms_residual": sig}


def _clean(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "tolist"):
        return _clean(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(doc: dict[str, Any]) -> str:
    """JSON text (strict: NaN/inf already turned into null)."""
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"
