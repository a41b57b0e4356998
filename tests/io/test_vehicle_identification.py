"""The ``identification:`` block of a vehicle written by a fit (issue #48): the fit's verdict travels
with the file, and a vehicle that does not fit says so wherever it is loaded."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.io.vehicle import (
    identified_vehicle_document,
    load_vehicle,
    read_identification,
    resolve_vehicle,
    vehicle_text,
)
from hydrokit.io.yamlfile import read_yaml

UNFIT_REASON = (
    "pond3 (held out): held-out NRMSE of v 0.57, r 1.20 > 0.5 and residuals lag-1 ρ 0.95, 0.99: "
    "the model misses something."
)


def _result(fits: bool) -> SimpleNamespace:
    """A fit's result as the writer reads it: two fitted runs, one held out whose v, r move and
    whose w does not (its NRMSE is not a prediction: left out)."""
    chan = lambda nrmse, moving: {"nrmse": nrmse, "moving": moving}  # noqa: E731
    return SimpleNamespace(
        parameters=["linear_damping.yaw"],
        values=[2.25],
        covariance=[[0.09]],
        method="output-error",
        runs=[
            {"name": "pond1", "holdout": False, "channels": {"r": chan(0.1, True)}},
            {"name": "pond2", "holdout": False, "channels": {"r": chan(0.2, True)}},
            {
                "name": "pond3",
                "holdout": True,
                "channels": {"v": chan(0.57, True), "r": chan(1.2, True), "w": chan(float("nan"), False)},
            },
        ],
        verdict={"fits": fits, "reasons": ["every moving channel predicted."] if fits else [UNFIT_REASON]},
    )


@pytest.mark.parametrize("fits", [True, False])
def test_the_block_holds_the_verdict_and_round_trips(tmp_path: Path, fits: bool) -> None:
    result = _result(fits)
    doc = identified_vehicle_document(result, read_yaml(resolve_vehicle("bluerov2-heavy")))
    block = doc["identification"]
    assert block["verdict"] == ("fits" if fits else "does not fit")
    assert block["reasons"] == result.verdict["reasons"]
    # the held-out run's moving channels only, the fitted runs' never
    assert block["holdout_nrmse"] == {"pond3": {"v": 0.57, "r": 1.2}}
    assert block["runs"] == ["pond1", "pond2"] and block["holdout"] == ["pond3"]
    assert block["tool"].startswith("hydrokit sysid ") and block["date"].endswith("Z")
    path = tmp_path / "vehicle.yaml"
    path.write_text(vehicle_text(doc, "# test"), encoding="utf-8")
    v = load_vehicle(path)
    assert v.identification is not None and v.identification.fits is fits
    assert v.identification.reasons == tuple(block["reasons"])
    assert v.identification.holdout_nrmse == block["holdout_nrmse"]
    assert v.identification.runs == ("pond1", "pond2") and v.identification.date == block["date"]
    assert read_identification(path) == v.identification
    said = [w for w in v.warnings if "identification" in w]
    if fits:
        assert said == []
    else:
        # first of the vehicle's warnings, naming the file and the first reason
        assert v.warnings[0] == said[0] and len(said) == 1
        assert said[0].startswith(f'{path}: its identification says "does not fit" (pond3 (held out): ')
        assert said[0].endswith("misses something): the predictions below are not trustworthy")


def test_a_refit_replaces_the_base_block(tmp_path: Path) -> None:
    """A vehicle fitted from a base that did not fit carries the new fit's verdict, not the old one."""
    base = read_yaml(resolve_vehicle("bluerov2-heavy"))
    old = identified_vehicle_document(_result(False), base)
    new = identified_vehicle_document(_result(True), old)
    assert new["identification"]["verdict"] == "fits"


def test_a_result_without_a_verdict_writes_no_block() -> None:
    result = _result(True)
    del result.verdict
    doc = identified_vehicle_document(result, read_yaml(resolve_vehicle("bluerov2-heavy")))
    assert "identification" not in doc


def _with_block(tmp_path: Path, block: Any) -> Path:
    doc = read_yaml(resolve_vehicle("bluerov2-heavy"))
    doc["identification"] = block
    path = tmp_path / "v.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


def test_no_block_makes_no_claim(tmp_path: Path) -> None:
    doc = read_yaml(resolve_vehicle("bluerov2-heavy"))
    path = tmp_path / "v.yaml"
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    v = load_vehicle(path)
    assert v.identification is None and read_identification(path) is None
    assert not any("identification" in w for w in v.warnings)


def test_a_hand_written_block_with_an_unquoted_date(tmp_path: Path) -> None:
    path = tmp_path / "v.yaml"
    text = (
        resolve_vehicle("bluerov2-heavy").read_text() + "\nidentification: {verdict: does not fit, date: 2026-11-29}\n"
    )
    path.write_text(text, encoding="utf-8")
    v = load_vehicle(path)
    assert v.identification is not None and v.identification.date == "2026-11-29"
    # no reason given: the warning says the verdict alone
    assert v.warnings[0] == f'{path}: its identification says "does not fit": the predictions below are not trustworthy'


@pytest.mark.parametrize(
    ("block", "message"),
    [
        ({"verdict": "maybe"}, "field 'identification.verdict' = 'maybe': expected 'fits' or 'does not fit'"),
        ({"reasons": ["x"]}, "field 'identification.verdict' = None"),
        ({"verdict": "fits", "reasons": "one"}, "field 'identification.reasons' = 'one': expected a list of texts"),
        ({"verdict": "fits", "holdout_nrmse": {"d": {"v": -1}}}, "identification.holdout_nrmse.d.v' = -1"),
        ({"verdict": "fits", "holdout_nrmse": {"d": {"v": "big"}}}, "identification.holdout_nrmse.d.v"),
        ({"verdict": "fits", "tool": 3}, "field 'identification.tool' = 3: expected a text"),
        ({"verdict": "fits", "score": 3}, "score"),
        ("does not fit", "field 'identification'"),
    ],
)
def test_bad_blocks_are_one_line_errors(tmp_path: Path, block: Any, message: str) -> None:
    path = _with_block(tmp_path, block)
    for read in (load_vehicle, read_identification):
        with pytest.raises(InputError, match=re.escape(message)) as err:
            read(path)
        assert str(path) in str(err.value) and "\n" not in str(err.value)


def test_a_long_reason_is_shortened_at_a_word_in_the_warning(tmp_path: Path) -> None:
    """The Esso Osaka fit's first reason is ~350 characters: the warning quotes its start, the file
    keeps it whole."""
    reason = "pond3 (held out): " + " ".join(f"word{k}" for k in range(60)) + "."
    path = _with_block(tmp_path, {"verdict": "does not fit", "reasons": [reason]})
    v = load_vehicle(path)
    head, tail = f'{path}: its identification says "does not fit" (', "): the predictions below are not trustworthy"
    assert v.warnings[0].startswith(head) and v.warnings[0].endswith(tail)
    quoted = v.warnings[0][len(head) : -len(tail)]
    assert quoted.endswith(" …") and len(quoted) <= 202
    kept = quoted[:-2]
    assert reason.startswith(kept + " ") and kept.split()[-1] == f"word{len(kept.split()) - 4}"
    assert v.identification is not None and v.identification.reasons == (reason,)


def test_a_windowed_fit_names_its_run_files() -> None:
    """Windows are named RUN@STARTs: runs and holdout list the files once each, the held-out NRMSE
    stays per window."""
    result = _result(False)
    result.windows = {"count": 4}
    chan = {"v": {"nrmse": 0.8, "moving": True}}
    result.runs = [
        {"name": "pond1@0s", "holdout": False, "channels": {}},
        {"name": "pond1@30s", "holdout": False, "channels": {}},
        {"name": "pond3@0s", "holdout": True, "channels": chan},
        {"name": "pond3@28.05s", "holdout": True, "channels": chan},
    ]
    block = identified_vehicle_document(result, read_yaml(resolve_vehicle("bluerov2-heavy")))["identification"]
    assert block["runs"] == ["pond1"] and block["holdout"] == ["pond3"]
    assert list(block["holdout_nrmse"]) == ["pond3@0s", "pond3@28.05s"]
