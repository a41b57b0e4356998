"""The main job's report says what its data are, per source, and its JSON carries no float noise."""

from __future__ import annotations

import html
import json
import re

import pytest

from hydrokit.pipeline.result import JSON_DIGITS, RunResult, rounded
from hydrokit.report.run import data_statement


def _doc(virtual: bool, tank: bool, sysid: bool, truth_file: str | None = None) -> dict:
    launch = {"file": "a.csv"}
    return {
        "project": {"virtual_data": virtual},
        "campaigns": {"surge": {"campaign": {"launches": [launch, launch]}, "truth": None}} if tank else {},
        "sysid": {
            "runs": ["dive1.csv", "dive2.csv"],
            "holdout": ["dive3.csv"],
            "truth_file": truth_file,
            "parameters": {"added_mass.surge": {"truth": 1.0 if truth_file else None}},
        }
        if sysid
        else None,
        "comparison": [],
    }


def _text(parts: list[str]) -> str:
    return html.unescape(" ".join(parts))


def test_generated_dives_are_not_called_tank_launches():
    # the bundled bluerov2_sysid project: virtual, no tank campaign, three generated dives
    text = _text(data_statement(_doc(True, False, True, "truth.json")))
    assert "banner" in text
    assert "3 dives (sysid runs: dive1.csv, dive2.csv, dive3.csv) are generated" in text
    assert "launch" not in text and "virtual rig" not in text
    assert "identified against true values" in text


def test_virtual_tank_launches_say_so():
    text = _text(data_statement(_doc(True, True, False)))
    assert "2 tank launches (surge) are virtual: simulated by hydrokit's virtual rig" in text
    assert "dives" not in text
    assert "true values" not in text  # no truth in this document


def test_measured_data_get_no_banner_and_each_source_its_word():
    parts = data_statement(_doc(False, True, True))
    text = _text(parts)
    assert "banner" not in text
    assert "2 tank launches (surge) are measured" in text and "3 dives" in text and "logs of the vehicle" in text


def test_measured_launches_beside_generated_dives():
    parts = data_statement(_doc(False, True, True, "truth.json"))
    assert len(parts) == 2
    assert "banner" in parts[0] and "dives" in parts[0] and "launches" not in parts[0]
    assert "banner" not in parts[1] and "tank launches (surge) are measured" in parts[1]


@pytest.mark.parametrize(
    "noisy", [14.999999999999998, 0.30000000000000004, 0.0028824999999999996, -1.9100000000000001e-7, 123456.0]
)
def test_rounding_removes_float_noise_and_keeps_the_value(noisy):
    r = rounded(noisy)
    assert r == pytest.approx(noisy, rel=10.0 ** (1 - JSON_DIGITS))
    mantissa = re.sub(r"e.*", "", repr(abs(r))).replace(".", "").strip("0")
    assert len(mantissa) <= JSON_DIGITS, repr(r)


def test_rounding_keeps_keys_and_every_other_value():
    doc = {"a": [1, True, None, "x", {"b": 2.0000000000000004}], "inf": None, "n": 3}
    assert rounded(doc) == {"a": [1, True, None, "x", {"b": 2.0}], "inf": None, "n": 3}
    res = RunResult({"v": 14.999999999999998, "k": {"w": [0.1 + 0.2]}}, timings=[{"step": "s", "seconds": 1 / 3}])
    text = json.dumps(res.to_dict())
    assert "14.999999" not in text and "0.30000000000000004" not in text
    assert res.to_dict() == {"v": 15.0, "k": {"w": [0.3]}, "timings": [{"step": "s", "seconds": 0.3333333333}]}
