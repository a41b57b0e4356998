"""Every fit ``hydrokit sysid`` can make, it writes (issue #56 item 3).

For each family of ``--free`` name — a hull term and a hull coefficient, a ``delta()`` term, a
``T()`` term, an ``n()`` term, a control surface's field, a thruster's field and the wind model's
field — one small fit through the command line: a race-rudder ship in a logged wind
(:mod:`tests.simulate.test_acceptance_race_rudder`'s, with one term of each kind added) is fitted
from one 20 s run file with the one parameter free, starting off its truth; the written
vehicle.yaml is read back and must hold the value of sysid.json in SI, and ``hydrokit simulate``
flies it, its draws too. Before the fix a ``T()`` or ``n()`` term was fitted and then refused by
the vehicle writer, which checked the term with the file's control surfaces but without its
thrusters: exit 2 after the whole fit, ``T(prop) names no thruster of the vehicle (thrusters:
none)``. A name the writer cannot hold now fails before any run is read.
"""

from __future__ import annotations

import copy
import json
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from tests.simulate.test_acceptance_race_rudder import (
    HULL,
    N_PROP,
    NEUTRAL_DEG,
    RACE_RUDDER,
    SEED,
    SHIP,
    U0,
    WIND,
    wind_ship_runs,
)

from hydrokit.core.names import DOF_NAMES
from hydrokit.model.wind import BLENDERMANN_1994

#: one term of each input factor added to the acceptance ship (SI: N·m per (m/s)²·rad, per N·rad
#: and per (rev/s)·rad), each giving about a third of the fin's yaw moment at 15° of rudder
EXTRA_TERMS = {"N_uu*delta(rudder)": -20.0, "N_T(prop)*delta(rudder)": -0.3, "N_n(prop)*delta(rudder)": -0.1}
#: family → (free name, its value in the base file: the fit's start, in the file's unit; None: not
#: in the file, so the fit adds it at 0)
CASES = {
    "hull term": ("terms.N_ur", -390.0),
    "hull coefficient": ("quadratic_damping.surge", 28.0),
    "delta() term": ("terms.N_uu*delta(rudder)", -10.0),
    "T() term": ("terms.N_T(prop)*delta(rudder)", None),
    "n() term": ("terms.N_n(prop)*delta(rudder)", -0.05),
    "control-surface field": ("control_surfaces.rudder.lift_slope", 2.0),
    "thruster field": ("thrusters.prop.wake_fraction", 0.15),
    "wind field": ("wind.CD_t", 0.5),
}
#: how far the fit must close the gap between start and truth: |fit − truth| < GAP × |start − truth|.
#: One free parameter, the rest at the truth, 20 s at the sensor noise of SHIP_NOISE: the fits
#: closed all but 0.2–8 % of it (the wind's CD_t the least, 0.9 σ off), so 0.25 fails a fit
#: that stops short or does not move, and leaves room for the noise
GAP = 0.25
#: the flight: 20 s from the approach speed, the propeller at N_PROP, 15° of rudder, a 2.5 m/s
#: beam wind from starboard
FLIGHT = (
    "--duration", 20, "--dt", 0.05, "--initial-velocity", f"{U0},0,0,0,0,0", "--command", f"prop={N_PROP:g}",
    "--deflection", "rudder=15", "--wind", "2.5,90",
)  # fmt: skip


def truth_document() -> dict[str, Any]:
    """The acceptance ship's vehicle document with :data:`EXTRA_TERMS` and Blendermann's loaded
    tanker written as its four numbers (so the base file can carry another CD_t)."""
    d = copy.deepcopy(SHIP)
    d["control_surfaces"] = [{**copy.deepcopy(RACE_RUDDER), "neutral_deflection_deg": NEUTRAL_DEG}]
    d["terms"] = {**{k: v for k, v in SHIP["terms"].items() if "delta" not in k}, **HULL, **EXTRA_TERMS}
    d["wind"] = {k: v for k, v in WIND.items() if k != "vessel"}
    d["wind"]["parameters"] = list(BLENDERMANN_1994[str(WIND["vessel"])])
    return d


def start_document(name: str, start: float | None) -> dict[str, Any]:
    """The truth's document with ``name`` at ``start`` (None: the term left out), by hand where
    the file keeps it (not through the writer under test)."""
    d = truth_document()
    group, _, rest = name.partition(".")
    if group == "terms":
        if start is None:
            del d["terms"][rest]
        else:
            d["terms"][rest] = start
    elif group == "quadratic_damping":
        d[group][DOF_NAMES.index(rest)] = start
    elif group in ("control_surfaces", "thrusters"):
        d[group][0][rest.partition(".")[2]] = start
    else:  # wind.CD_t: the first of Blendermann's four numbers
        d["wind"]["parameters"][0] = start
    return d


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One 20 s zigzag-like run of the truth in a logged gusty wind (seed 13), as a run file with
    wind_speed and wind_direction columns."""
    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.runlog import run_csv

    (run,) = wind_ship_runs(vehicle_from_dict(truth_document(), "truth"), 1, 20.0, seed=SEED)
    text = run_csv(run.time, {c: y for c, (_, y) in run.channels.items()}, run.commands, deflections=run.deflections)
    lines = text.splitlines()
    head = next(k for k, line in enumerate(lines) if not line.startswith("#"))
    lines[head] += ",wind_speed,wind_direction"
    wind = zip(run.environment["wind_speed"], run.environment["wind_direction"])
    lines[head + 1 :] = [f"{line},{a:.9g},{b:.9g}" for line, (a, b) in zip(lines[head + 1 :], wind)]
    path = tmp_path_factory.mktemp("runs") / "run1.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def _fly(run_cli: Any, vehicle: Path, out: Path, *extra: Any) -> np.ndarray:
    """``hydrokit simulate`` of ``vehicle`` over :data:`FLIGHT`: the trajectory's rows."""
    code, _, err = run_cli("simulate", vehicle, *FLIGHT, "--out", out, *extra)
    assert code == 0, err
    return np.loadtxt(out, delimiter=",", skiprows=1)


@pytest.mark.needs_jit(reason="a CLI output-error fit of a 20 s run, then three 20 s flights")
@pytest.mark.parametrize("family", list(CASES))
def test_sysid_fits_writes_reloads_and_flies(run_cli: Any, tmp_path: Path, run_file: Path, family: str) -> None:
    from hydrokit.api import load_vehicle, vehicle_from_dict
    from hydrokit.model.uncertainty import parameter_value

    name, start = CASES[family]
    truth_file, base_file = tmp_path / "truth.yaml", tmp_path / "base.yaml"
    truth_file.write_text(yaml.safe_dump(truth_document()))
    base_file.write_text(yaml.safe_dump(start_document(name, start)))
    true = parameter_value(vehicle_from_dict(truth_document(), "truth"), name)
    begun = 0.0 if start is None else start
    assert abs(begun - true) > 0.1 * abs(true)  # the fit has a way to go

    # --- fit -----------------------------------------------------------------------------------
    fit = tmp_path / "fit"
    code, _, err = run_cli(
        "sysid", run_file, "--vehicle", base_file, "--free", name, "--out", fit,
        "--dt", 0.05, "--samples", 0, "--window", "none",
    )  # fmt: skip
    assert code == 0, err
    (fitted,) = json.loads((fit / "sysid.json").read_text())["parameters"]
    assert fitted["name"] == name
    value, sigma = fitted["value"], fitted["sigma"]
    assert abs(value - true) < GAP * abs(begun - true), (name, begun, value, sigma, true)

    # --- written and read back: the fitted SI value of sysid.json, where the model reads it ----
    vehicle = load_vehicle(fit / "vehicle.yaml")
    # rel 1e-12: the value goes through YAML's float text (repr, exact) and back
    assert parameter_value(vehicle, name) == pytest.approx(value, rel=1e-12)
    assert vehicle.uncertainty is not None and vehicle.uncertainty.parameters == (name,)

    # --- flown: the written file, and draws from its uncertainty block ----------------------------
    flown = _fly(run_cli, fit / "vehicle.yaml", tmp_path / "fit.csv")
    assert np.all(np.isfinite(flown))
    # simulate --samples flies a constant force (no thruster commands): the propeller's thrust as one
    code, _, err = run_cli(
        "simulate", fit / "vehicle.yaml", "--duration", 5, "--dt", 0.05, "--force", "5,0,0,0,0,0",
        "--deflection", "rudder=15", "--wind", "2.5,90", "--samples", 3, "--out", tmp_path / "draws.csv",
    )  # fmt: skip
    assert code == 0, err
    assert (tmp_path / "draws_envelope.csv").exists()
    # the fitted file flies like the truth, the base did not: the track (x, y, m) of the written
    # file is closer to the truth's than the base file's by the same factor GAP
    track = {
        k: _fly(run_cli, f, tmp_path / f"{k}.csv")[:, 1:3] for k, f in (("truth", truth_file), ("base", base_file))
    }
    miss = float(np.max(np.hypot(*(flown[:, 1:3] - track["truth"]).T)))
    base_miss = float(np.max(np.hypot(*(track["base"] - track["truth"]).T)))
    assert miss < GAP * base_miss, (family, miss, base_miss)


def test_a_name_the_writer_cannot_hold_fails_before_any_run_is_read(run_cli: Any, tmp_path: Path) -> None:
    """``n(NAME)`` of a thruster without a propeller curve: the fit's own name check takes any
    thruster, the vehicle file only a propeller. The run file does not exist, so an error about
    --free shows that the name was written (into a copy of the base) before any run was read."""
    doc = truth_document()
    doc["thrusters"].append({"name": "bow", "position": [1.2, 0, 0], "direction": [0, 1, 0], "max_thrust": 10})
    base = tmp_path / "base.yaml"
    base.write_text(yaml.safe_dump(doc))
    out = tmp_path / "fit"
    began = time.perf_counter()
    code, _, err = run_cli(
        "sysid", tmp_path / "missing.csv", "--vehicle", base, "--free", "terms.Y_n(bow)*delta(rudder)", "--out", out
    )
    assert code == 2, err
    assert time.perf_counter() - began < 10.0  # no fit: the name is refused up front
    line = err.strip()
    assert "\n" not in line and "Traceback" not in line, err
    assert line.startswith("error: --free: the fit could not be written into a vehicle file:"), line
    assert "n(bow)" in line and "missing.csv" not in line, line
    assert not out.exists() or not any(out.iterdir())


def test_the_main_job_places_and_writes_thrust_and_rate_terms() -> None:
    """``hydrokit run`` names a free term's DOF (:func:`hydrokit.pipeline.sysid.term_dof`) and
    writes it (:func:`hydrokit.io.vehicle.write_terms`) with the document's thrusters too."""
    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.vehicle import write_terms
    from hydrokit.pipeline.sysid import term_dof

    assert term_dof("terms.Y_T(prop)*delta(rudder)") == "sway"
    assert term_dof("terms.N_n(prop)^2*delta(rudder)") == "yaw"
    values = [("terms.Y_T(prop)*delta(rudder)", 0.25), ("terms.N_n(prop)*delta(rudder)", -0.125)]
    doc = write_terms(truth_document(), values)
    v = vehicle_from_dict(doc, "written")
    for name, value in values:
        assert v.terms.coef[v.terms.names.index(name[len("terms.") :])] == value  # written as given
