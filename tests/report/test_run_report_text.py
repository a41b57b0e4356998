"""The main job's report says what its data are, per source."""

from __future__ import annotations

import html

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
