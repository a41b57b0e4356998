"""The CFD report and output documents from an assembled sweep (no OpenFOAM needed)."""

from __future__ import annotations

import json
import math

import numpy as np
import yaml

from hydrokit.cfd.body import profile_body
from hydrokit.cfd.case import Settings
from hydrokit.cfd.sweep import SweepSpec, assemble, make_cases
from hydrokit.report.cfd import render


def _result(name: str = "hull"):
    t = np.linspace(0.0, np.pi, 41)
    body = profile_body(0.5 * (1 - np.cos(t)), np.r_[0.0, 0.1 * np.sin(t[1:-1]), 0.0], name)
    spec = SweepSpec((0.5, 1.0, 1.5, 2.0), drifts=(math.radians(-5), math.radians(5)))
    outs = []
    for i, c in enumerate(make_cases(body, spec, Settings())):
        u, v, _ = c.flow.velocity()
        outs.append(
            {
                "label": c.label,
                "status": "failed" if i == 1 else "converged",
                "reason": "simpleFoam failed (exit 1): <bad>",
                "flow": {**c.flow.__dict__},
                "settings": {**c.settings.__dict__},
                "forces": [-20 * u * u, -30 * u * v, 0, 0, 0, -9 * u * v],
                "std": [0.01] * 6,
                "mesh": {"cells": 1000, "failed_checks": 0},
                "history": {"iteration": [1.0, 2.0], "X": [-1.0, -2.0]},
            }
        )
    return assemble(body, spec, Settings(), outs)


def test_the_report_escapes_user_text_and_shows_every_section():
    html = render(_result("<script>alert(1)</script>.stl"))
    assert "<script>alert" not in html and "&lt;script&gt;" in html
    for heading in ("Cases", "Loads", "Force against speed", "Virtual tow tank", "Derivatives", "Convergence"):
        assert f"<h2>{heading}" in html
    assert html.count("data:image/png;base64,") == 3
    assert "&lt;bad&gt;" in html  # a failed case's reason is shown, escaped


def test_cfd_json_is_strict_and_coefficients_yaml_is_a_terms_block():
    res = _result()
    text = json.dumps(res.to_dict(), allow_nan=False)  # a failed case's NaN loads become null
    doc = json.loads(text)
    assert [c["status"] for c in doc["cases"]].count("failed") == 1
    coef = yaml.safe_load(yaml.safe_dump(res.coefficients()))
    assert set(coef["terms"]) >= {"Y_uv", "N_uv", "X_u|u|"} and coef["terms_nondimensional"] is False
    assert set(coef["uncertainty"]["terms"]) == set(coef["terms"])
    assert coef["chin"]["x"]["points"] == 3  # four speeds, one failed
