"""The result of ``hydrokit run``: every number of the report, the figures and the output files."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from hydrokit._result import Result, html_table, jsonable

#: significant digits of the floats in the run's JSON files: float64 arithmetic leaves noise in
#: the last two or three of its 17 (14.999999999999998); 10 keep every measured digit with room
JSON_DIGITS = 10


def rounded(obj: Any, digits: int = JSON_DIGITS) -> Any:
    """``obj`` (JSON-ready: dicts, lists, numbers, text) with every float rounded to ``digits``
    significant digits; keys, ints, booleans, text and None as they were."""
    if isinstance(obj, dict):
        return {k: rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, list):
        return [rounded(v, digits) for v in obj]
    if isinstance(obj, float) and math.isfinite(obj):
        return float(f"{obj:.{digits}g}")
    return obj


@dataclass
class RunResult(Result):
    """One run of a project.

    Attributes
    ----------
    document : dict — everything ``results.json`` holds (SI units, stated per table)
    figures : dict — section → list of {name, caption, png (base64)}
    files : dict — output path relative to the run folder → text (``vehicle.yaml``,
        ``mission/…``), written with the report
    timings : list of {step, seconds, cached}
    key : str, optional — the run's key (:func:`hydrokit.pipeline.cache.run_key`): the run
        folder's files are rewritten only when it changes
    """

    document: dict[str, Any]
    figures: dict[str, list[dict[str, str]]] = field(default_factory=dict)
    files: dict[str, str] = field(default_factory=dict)
    timings: list[dict[str, Any]] = field(default_factory=list)
    key: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """``results.json``: the document with the step timings, floats rounded to
        :data:`JSON_DIGITS` significant digits."""
        return rounded(jsonable({**self.document, "timings": self.timings}))

    @property
    def chosen(self) -> dict[str, Any]:
        """DOF → coefficient → {value (SI, full scale), source, se}."""
        return self.document["chosen"]

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """The comparison: one row per DOF and coefficient, tank vs the other sources (SI, full
        scale; ``sysid_sigma`` the standard error of the sysid value)."""
        cols = [
            "dof",
            "coefficient",
            "tank",
            "geometry",
            "bem",
            "cfd",
            "sysid",
            "sysid_sigma",
            "published",
            "chosen",
            "chosen_source",
        ]
        return cols, [[r.get(c) for c in cols] for r in self.document["comparison"]]

    def summary_rows(self) -> list[tuple[str, Any]]:
        d = self.document
        rows: list[tuple[str, Any]] = [("project", d["project"]["name"]), ("campaigns", len(d["campaigns"]))]
        if d.get("sysid"):
            rows.append(("sysid runs", f"{len(d['sysid']['runs'])} + {len(d['sysid']['holdout'])} held out"))
        shown = {r["dof"] for r in d["comparison"] if r.get("sysid") is not None}
        for dof, coefs in d["chosen"].items():
            if dof in d["campaigns"] or dof in shown:
                rows.append((dof, ", ".join(f"{c} {v['value']:.4g} ({v['source']})" for c, v in coefs.items())))
        for c, m in (d.get("monte_carlo") or {}).get("controllers", {}).items():
            x = m["metrics"]["cross_track_rms"]
            if x["median"] is not None:
                rows.append((f"{c} cross-track RMS (m)", f"{x['median']:.3g} [{x['p5']:.3g}, {x['p95']:.3g}]"))
        return rows

    def _repr_html_(self) -> str:
        return html_table(f"RunResult: {self.document['project']['name']}", self.summary_rows())
