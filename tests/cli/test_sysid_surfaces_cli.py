"""``hydrokit sysid`` and the main job's ``sysid:`` source with control surfaces (issues #48
item 1, #49 items 1 and 7): free ``delta()`` terms of a rudder-steered ship are fitted and
written into a vehicle file that loads back."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml
from tests.simulate.test_sysid_surfaces import SHIP, _run, _ship

#: the rudder derivatives freed (SI; SHIP holds their generating values 40 and −80)
RUDDER = ["terms.Y_uu*delta(rudder)", "terms.N_uu*delta(rudder)"]


def _write_runs(tmp_path: Path) -> list[Path]:
    """Two 20 s zigzag-like runs of the ship (all sensors at 10 Hz) as run files."""
    from hydrokit.io.runlog import run_csv

    truth = _ship()
    paths = []
    for name, switches, seed in (("z1", [3.0, 8.0, 13.0, 17.0], 1), ("z2", [4.0, 10.0, 15.0], 2)):
        run = _run(truth, name, 20.0, switches, seed=seed)
        rows = {c: y for c, (_, y) in run.channels.items()}
        p = tmp_path / f"{name}.csv"
        p.write_text(run_csv(run.time, rows, run.commands, comment="zigzag", deflections=run.deflections))
        paths.append(p)
    return paths


def _base(tmp_path: Path) -> Path:
    """The ship with its rudder derivatives 30 % off (the fit's start)."""
    doc = json.loads(json.dumps(SHIP))
    doc["terms"]["Y_uu*delta(rudder)"] = 28.0
    doc["terms"]["N_uu*delta(rudder)"] = -104.0
    p = tmp_path / "ship.yaml"
    p.write_text(yaml.safe_dump(doc))
    return p


@pytest.mark.needs_jit(reason="an output-error fit of two rudder derivatives over 20 s of zigzags")
def test_cli_fits_and_writes_rudder_derivatives_that_load_back(run_cli: Any, tmp_path: Path) -> None:
    import hydrokit

    z1, z2 = _write_runs(tmp_path)
    out = tmp_path / "fit"
    code, text, err = run_cli(
        "sysid", z1, "--holdout", z2, "--vehicle", _base(tmp_path), "--free", ",".join(RUDDER),
        "--out", out, "--samples", 0, "--dt", 0.02,
    )  # fmt: skip
    assert code == 0, err
    doc = json.loads((out / "sysid.json").read_text())
    assert list(doc)[0] == "verdict" and doc["verdict"]["fits"] is True, doc["verdict"]
    assert text.startswith("verdict: fits")
    fitted = {p["name"]: p for p in doc["parameters"]}
    # the generating values (SHIP) within 4 σ: the fit moved from 30 % off to the truth
    for name, true in zip(RUDDER, (40.0, -80.0)):
        assert abs(fitted[name]["value"] - true) < 4 * fitted[name]["sigma"], fitted[name]
    # the written vehicle loads with its rudder and reproduces the fitted values exactly
    v = hydrokit.api.load_vehicle(out / "vehicle.yaml")
    assert v.surfaces.names == ("rudder",)
    for name in RUDDER:
        k = v.terms.names.index(name[len("terms.") :])
        assert v.terms.coef[k] == pytest.approx(fitted[name]["value"], rel=1e-12)
    assert v.uncertainty.parameters == tuple(RUDDER)


@pytest.mark.needs_jit(reason="the same fit through the main job's sysid step")
def test_the_main_job_reads_surfaces_and_writes_the_fitted_rudder_terms(tmp_path: Path) -> None:
    from hydrokit.api import load_vehicle, vehicle_from_dict
    from hydrokit.io.project import SysidSpec
    from hydrokit.pipeline.sysid import sysid_step, write_terms

    z1, z2 = _write_runs(tmp_path)
    base = load_vehicle(_base(tmp_path))
    spec = SysidSpec((z1,), (z2,), tuple(RUDDER), "output-error", 0.02, "z*.csv")
    step = sysid_step(spec, base, 0, lambda n: None, str)
    assert step["verdict"]["fits"] is True, step["verdict"]
    values = [(n, step["parameters"][n]["value"]) for n in RUDDER]
    for (_, v), true in zip(values, (40.0, -80.0)):
        assert v == pytest.approx(true, rel=0.1)
    doc = write_terms(yaml.safe_load(_base(tmp_path).read_text()), values)
    veh = vehicle_from_dict(doc, "written")
    for name, v in values:
        assert veh.terms.coef[veh.terms.names.index(name[len("terms.") :])] == pytest.approx(v, rel=1e-12)
