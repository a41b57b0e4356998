"""System identification as a source of ``hydrokit run`` (issue #44, item 7): the project's
``sysid:`` section, the comparison beside tank/geometry/CFD with σ, ``choose: sysid``, the step
cache, and one-line errors naming the field.

The plumbing tests replace :func:`hydrokit.sysid.fit.identify` by a stand-in that returns
known values (the fit itself is tested in tests/simulate/test_sysid.py), so they are fast with
the JIT off; the bundled project runs for real under ``needs_jit`` and is compared with the
hidden values its generator wrote.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.project import PROJECTS_DIR, load_project

BUNDLED = PROJECTS_DIR / "bluerov2_sysid"
VEHICLE = DATA_DIR / "vehicles" / "bluerov2-sysid.yaml"
FREE = ["added_mass.surge", "linear_damping.surge", "quadratic_damping.heave", "terms.N_r|r|"]


class FakeIdentify:
    """Stands in for ``identify``: value = 1.1 × the start vehicle's value (a term: −0.7),
    σ = 2 % of it, and a correlation of 0.5 between the first two parameters."""

    def __init__(self) -> None:
        self.calls: list[dict[str, Any]] = []

    def __call__(self, vehicle: Any, runs: Any, free: Any, holdout: Any = (), **kw: Any) -> Any:
        from hydrokit.sysid.fit import SysidResult
        from hydrokit.sysid.model import free_parameters, values_of

        self.calls.append({"vehicle": vehicle, "runs": [r.name for r in runs], "free": list(free), **kw})
        kw["progress"](1, 0.0)
        veh, params = free_parameters(vehicle, list(free))
        start = values_of(veh, params)
        values = np.where([p.kind == "term" for p in params], -0.7, 1.1 * start)
        sigma = 0.02 * np.abs(values)
        corr = np.eye(len(values))
        corr[0, 1] = corr[1, 0] = 0.5
        cov = corr * np.outer(sigma, sigma)
        t = np.linspace(0.0, 1.0, 8)
        every = [(r, False) for r in runs] + [(r, True) for r in holdout]
        chans = {"samples": 8, "residual_rms": 0.01, "whiteness": {"lag1": 0.1, "outside": 0.0}}
        return SysidResult(
            vehicle=veh,
            parameters=tuple(p.name for p in params),
            units=tuple(p.unit for p in params),
            values=values,
            sigma=sigma,
            start=start,
            base=start,
            fisher_sigma=sigma,
            covariance=cov,
            correlation=corr,
            condition=3.0,
            equation_error={"values": values, "sigma": sigma},
            runs=[
                {
                    "name": r.name,
                    "holdout": h,
                    "duration": 6.0,
                    "channels": {"z": {**chans, "nrmse": 0.02 if h else None}},
                }
                for r, h in every
            ],
            noise={"z": 0.01},
            predictions=[
                {
                    "name": r.name,
                    "holdout": h,
                    "channels": {"z": {"time": t, "measured": t, "simulated": t, "low": t, "high": t}},
                }
                for r, h in every
            ],
            messages=("added_mass.surge and linear_damping.surge move together (ρ = +0.5): test",),
            method=kw.get("method", "output-error"),
            iterations=1,
            step_check=0.01,
            timing={"total": 0.1, "simulation": 0.05},
        )


@pytest.fixture
def fake(monkeypatch: pytest.MonkeyPatch) -> FakeIdentify:
    f = FakeIdentify()
    monkeypatch.setattr("hydrokit.sysid.fit.identify", f)
    return f


@pytest.fixture
def quick(fake: FakeIdentify, monkeypatch: pytest.MonkeyPatch) -> FakeIdentify:
    """``fake`` without the figures (drawn by the first test; ~0.3 s each)."""
    monkeypatch.setattr("hydrokit.pipeline.sysid._figures", lambda result: [])
    return fake


def make_project(tmp_path: Path, sysid: dict[str, Any] | None = None, **fields: Any) -> Path:
    """A project in ``tmp_path`` with the bundled dives, truth, geometry and a base vehicle copy
    that holds the term N_r|r| = −0.5 N·m·s²/rad²."""
    for name in ("dive1.csv", "dive2.csv", "dive3.csv", "truth.json", "geometry.yaml"):
        shutil.copy(BUNDLED / name, tmp_path / name)
    base = yaml.safe_load(VEHICLE.read_text())
    base["terms"] = {"N_r|r|": -0.5}
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(base))
    doc: dict[str, Any] = {
        "name": "t",
        "vehicle": "base.yaml",
        "geometry": "geometry.yaml",
        "sysid": {
            "runs": ["dive1.csv", "dive2.csv"],
            "holdout": ["dive3.csv"],
            "free": list(FREE),
            "truth": "truth.json",
        }
        | (sysid or {}),
        "choose": {"default": "sysid"},
        "uncertainty": {"samples": 0, "seed": 1},
    } | fields
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump(doc, allow_unicode=True))
    return path


def run(path: Path, out: Path, **kw: Any) -> Any:
    from hydrokit.pipeline import run_project

    return run_project(path, out, workers=1, **kw)


def row(result: Any, dof: str, coef: str) -> dict[str, Any]:
    return next(r for r in result.document["comparison"] if r["dof"] == dof and r["coefficient"] == coef)


def test_the_sysid_values_appear_beside_the_geometry_with_sigma_and_are_chosen(tmp_path, fake):
    from hydrokit.api import load_vehicle
    from hydrokit.report.run import run_report

    res = run(make_project(tmp_path), tmp_path / "out")
    base = load_vehicle(tmp_path / "base.yaml")
    r = row(res, "surge", "added_mass")
    # the stand-in's value: 1.1 × the base's surge added mass, σ 2 % of it
    assert r["sysid"] == pytest.approx(1.1 * base.M_A[0, 0], rel=1e-12)
    assert r["sysid_sigma"] == pytest.approx(0.022 * base.M_A[0, 0], rel=1e-12)
    lo, hi = r["sysid_ci"]
    assert (hi - lo) / 2 == pytest.approx(1.959964 * r["sysid_sigma"], rel=1e-6)
    assert r["geometry"] is not None and r["chosen_source"] == "sysid" and r["chosen"] == r["sysid"]
    assert r["relative_to_sysid_percent"]["geometry"] == pytest.approx(100 * (r["geometry"] / r["sysid"] - 1))
    # the hidden value the generator wrote is the row's truth
    truth = json.loads((tmp_path / "truth.json").read_text())["hidden"]
    assert r["truth"] == truth["added_mass.surge"] and r["truth_source"] == "sysid"
    # a coefficient sysid did not fit falls back to the geometry (its sway added mass) and then
    # to the base (the block estimate gives no roll added mass: 0 means none)
    assert res.chosen["sway"]["added_mass"]["source"] == "geometry"
    assert res.chosen["roll"]["added_mass"] == {"value": base.M_A[3, 3], "source": "base", "se": None}
    assert {r["dof"] for r in res.document["comparison"]} == {"surge", "heave"}
    doc = res.to_dict()
    assert doc["sysid"]["parameters"]["quadratic_damping.heave"]["sigma"] == pytest.approx(0.022 * base.D_Q[2])
    assert doc["sysid"]["start_vehicle"]["from_tank"] == {}
    assert "sysid" in res.table()[0] and any(name == "sysid runs" for name, _ in res.summary_rows())
    html = run_report(res)
    assert "sysid ± σ [95 %]" in html and "System identification from the vehicle" in html
    assert "Coefficients: the vehicle's own dives (sysid)" in html and "tank [95 % CI]" not in html
    assert any("move together" in w for w in doc["warnings"])


def test_the_vehicle_carries_the_sysid_covariance_and_the_free_term(tmp_path, quick):
    from hydrokit.api import vehicle_from_dict
    from hydrokit.model.uncertainty import parameter_value

    res = run(make_project(tmp_path), tmp_path / "out")
    vdoc = res.document["vehicle"]
    unc = vdoc["uncertainty"]
    names = res.document["sysid"]["names"]
    cov = np.asarray(res.document["sysid"]["covariance"])
    # every free parameter is chosen (or written: N_r|r| is yaw's, and yaw chooses sysid)
    assert unc["parameters"] == names
    np.testing.assert_allclose(unc["covariance"], cov, rtol=1e-15)
    v = vehicle_from_dict(vdoc, "vehicle.yaml")  # the file reader accepts the block (terms too)
    assert v.uncertainty.parameters == tuple(names)
    k = names.index("terms.N_r|r|")
    assert parameter_value(v, "terms.N_r|r|") == pytest.approx(-0.7) and unc["covariance"][k][k] == pytest.approx(
        0.014**2
    )
    assert list(vdoc["terms"]) == ["N_r|r|"]  # replaced, not added twice
    assert res.document["sysid"]["terms"][0] | {"written": True} == res.document["sysid"]["terms"][0]


def test_a_term_of_a_dof_that_does_not_choose_sysid_is_shown_not_written(tmp_path, quick):
    path = make_project(tmp_path, choose={"surge": "sysid", "default": "geometry"})
    res = run(path, tmp_path / "out")
    assert res.chosen["surge"]["added_mass"]["source"] == "sysid"
    assert res.chosen["heave"]["quadratic_damping"]["source"] == "geometry"  # the rule, though sysid has one
    term = res.document["sysid"]["terms"][0]
    assert term["name"] == "terms.N_r|r|" and term["dof"] == "yaw" and not term["written"]
    assert res.document["vehicle"]["terms"]["N_r|r|"] == -0.5  # the base's
    assert res.document["vehicle"]["uncertainty"]["parameters"] == ["added_mass.surge", "linear_damping.surge"]


def test_the_step_is_cached_and_redone_when_a_run_or_the_base_vehicle_changes(tmp_path, quick):
    fake = quick
    path = make_project(tmp_path)
    out = tmp_path / "out"
    first = run(path, out)
    assert len(fake.calls) == 1 and fake.calls[0]["runs"] == ["dive1", "dive2"]
    again = run(path, out)
    assert len(fake.calls) == 1  # a cache hit: identify not called
    assert next(t for t in again.timings if t["step"] == "sysid")["cached"]
    assert again.document["comparison"] == first.document["comparison"]
    # one sample of a run file changes: the step is redone
    text = (tmp_path / "dive2.csv").read_text().splitlines()
    i = next(k for k, line in enumerate(text) if line[:1].isdigit()) + 3
    cells = text[i].split(",")
    cells[2] = str(float(cells[2]) + 1e-4)
    text[i] = ",".join(cells)
    (tmp_path / "dive2.csv").write_text("\n".join(text) + "\n")
    run(path, out)
    assert len(fake.calls) == 2
    # the held-out run and the base vehicle are inputs too
    with open(tmp_path / "base.yaml", "a") as f:
        f.write("description: changed\n")
    run(path, out)
    assert len(fake.calls) == 3
    run(path, out, force=True)
    assert len(fake.calls) == 4


def test_sysid_starts_from_the_base_with_the_tanks_diagonals():
    from hydrokit.api import load_vehicle
    from hydrokit.pipeline.sysid import start_vehicle

    base = load_vehicle(VEHICLE)
    full = {"mean": 20.0}
    tank = {
        "surge": {
            "full_scale": {
                "added_mass": {"mean": 9.5},
                "linear_damping": {"mean": -1.0},  # negative damping: not written in
                "quadratic_damping": {"mean": float("nan")},
            }
        },
        "heave": {"full_scale": {"added_mass": full, "linear_damping": full, "quadratic_damping": full}},
    }
    v, written = start_vehicle(base, tank)
    assert written == {
        "added_mass.surge": 9.5,
        "added_mass.heave": 20.0,
        "linear_damping.heave": 20.0,
        "quadratic_damping.heave": 20.0,
    }
    assert v.M_A[0, 0] == 9.5 and v.D_L[0, 0] == base.D_L[0, 0] and v.D_Q[0] == base.D_Q[0]
    assert v.D_L[2, 2] == 20.0 and v.D_Q[2] == 20.0 and v.M_A[1, 1] == base.M_A[1, 1]
    assert start_vehicle(base, {})[0] is base


def test_identified_terms_are_written_as_the_file_terms_that_give_them():
    from hydrokit.api import vehicle_from_dict
    from hydrokit.model.uncertainty import parameter_value
    from hydrokit.pipeline.sysid import write_terms

    base = yaml.safe_load(VEHICLE.read_text())
    base.pop("thrusters")
    values = [("terms.Z_wdot", -15.0), ("terms.X_u|u|", -120.0)]
    # the file's added mass as 6 numbers (Z_wdot: 18.68 − term) and as a 6×6 matrix
    for added_mass in (base["added_mass"], np.diag(base["added_mass"]).tolist()):
        doc = write_terms(dict(base, added_mass=added_mass, terms={"X_|u|u": -1.0}), values)
        assert doc["terms"] == {
            "X_|u|u": {"value": -120.0, "nondimensional": False},
            "Z_wdot": {"value": pytest.approx(3.68), "nondimensional": False},
        }
        v = vehicle_from_dict(doc)
        assert [parameter_value(v, n) for n, _ in values] == pytest.approx([-15.0, -120.0], rel=1e-12)


def test_the_project_parses_free_as_comma_text_and_resolves_paths(tmp_path):
    path = make_project(
        tmp_path, sysid={"free": "added_mass.surge , terms.N_r|r|", "method": "equation-error", "dt": 0.02}
    )
    p = load_project(path)
    assert p.sysid is not None
    assert p.sysid.free == ("added_mass.surge", "terms.N_r|r|")
    assert p.sysid.runs == (tmp_path / "dive1.csv", tmp_path / "dive2.csv")
    assert p.sysid.method == "equation-error" and p.sysid.dt == 0.02
    assert p.sysid.truth is not None and math.isfinite(p.sysid.truth["added_mass.yaw"])
    assert tmp_path / "dive3.csv" in p.input_files() and tmp_path / "truth.json" in p.input_files()
    assert p.scale_ratio is None and p.campaigns == ()


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ({"sysid": {"runs": []}}, r"field 'sysid\.runs' is empty: expected a glob or a list of run files"),
        ({"sysid": {"runs": "logs/*.csv"}}, r"field 'sysid\.runs' = 'logs/\*\.csv': the glob matches no file"),
        ({"sysid": {"runs": ["dive1.csv", 3]}}, r"field 'sysid\.runs' = .*expected a glob or a list of run files"),
        ({"sysid": {"holdout": ["dive2.csv"]}}, r"field 'sysid\.holdout' = 'dive2\.csv': also a training run"),
        ({"sysid": {"free": ["added_mass.hover"]}}, r"field 'sysid\.free\[0\]' = 'added_mass\.hover': expected"),
        (
            {"sysid": {"free": "added_mass.surge,added_mass.surge"}},
            r"field 'sysid\.free\[1\]' = 'added_mass\.surge': named twice",
        ),
        (
            {"sysid": {"free": "added_mass.surge,terms.X_udot"}},
            r"'sysid\.free\[1\]' = 'terms\.X_udot': named twice \(as 'added_mass\.surge'",
        ),
        ({"sysid": {"free": "terms.Q_uu"}}, r"field 'sysid\.free\[0\]' = 'terms\.Q_uu'"),
        ({"sysid": {"free": ""}}, r"field 'sysid\.free' is empty"),
        ({"sysid": {"free": 7}}, r"field 'sysid\.free' = '7': expected a list or comma-separated text"),
        (
            {"sysid": {"method": "magic"}},
            r"field 'sysid\.method' = 'magic': expected one of output-error, equation-error",
        ),
        ({"sysid": {"dt": 0.5}}, r"field 'sysid\.dt' = 0\.5"),
        ({"sysid": {"truth": "geometry.yaml"}}, r"field 'sysid\.truth' = 'geometry\.yaml': expected the truth\.json"),
        ({"sysid": {"truth": "nan.json"}}, r"field 'sysid\.truth' = 'nan\.json': a hidden value is not finite"),
        ({"sysid": {"seed": 3}}, r"sysid\.seed"),
        ({"sysid": None}, r"field 'campaigns' is empty and there is no 'sysid'"),
        ({"choose": "hunch"}, r"field 'choose' = 'hunch': expected one of tank, geometry, bem, cfd, sysid"),
    ],
)
def test_bad_sysid_fields_are_one_line_errors_naming_the_field(tmp_path, change, says):
    from hydrokit.pipeline import run_project

    path = make_project(tmp_path)
    (tmp_path / "nan.json").write_text('{"hidden": {"added_mass.surge": NaN}}')
    doc = yaml.safe_load(path.read_text())
    for key, value in change.items():
        if isinstance(value, dict):
            doc[key].update(value)
        elif value is None:
            doc.pop(key)
        else:
            doc[key] = value
    path.write_text(yaml.safe_dump(doc))
    with pytest.raises(InputError, match=says) as info:
        run_project(path, tmp_path / "out", workers=1)
    assert "\n" not in str(info.value) and str(path) in str(info.value)
    assert not (tmp_path / "out" / ".cache").exists()


def test_a_free_term_the_grammar_reads_but_the_vehicle_lacks_is_fine_and_a_bad_run_names_its_file(tmp_path, quick):
    path = make_project(tmp_path, sysid={"free": ["linear_damping.yaw", "terms.Y_v|v|"]})
    res = run(path, tmp_path / "out")
    assert [t["name"] for t in res.document["sysid"]["terms"]] == ["terms.Y_v|v|"]
    assert res.document["vehicle"]["terms"]["Y_v|v|"]["value"] == pytest.approx(-0.7)
    # a run without the column of one thruster: the reader's one line, before any step
    text = (tmp_path / "dive1.csv").read_text().replace(",VRL", ",XX", 1)
    (tmp_path / "dive1.csv").write_text(text)
    with pytest.raises(InputError, match=r"dive1\.csv.*VRL"):
        run(path, tmp_path / "out2")


def test_a_project_with_campaigns_needs_a_scale_ratio(tmp_path):
    camp = DATA_DIR / "campaigns" / "udrobot"
    path = make_project(
        tmp_path,
        campaigns=[{"dof": "surge", "rig": str(camp / "spring_x.yaml"), "launches": str(camp / "spring_x" / "*.csv")}],
    )
    with pytest.raises(InputError, match=r"field 'scale_ratio' is missing: expected the model/full length ratio"):
        load_project(path)


def test_a_vehicle_without_thrusters_cannot_have_a_sysid_source(tmp_path):
    path = make_project(tmp_path)
    base = yaml.safe_load((tmp_path / "base.yaml").read_text())
    base.pop("thrusters")
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(base))
    with pytest.raises(InputError, match=r"field 'sysid': the vehicle base\.yaml has no 'thrusters:' block"):
        load_project(path)


@pytest.mark.needs_jit(reason="identifies 12 parameters from the bundled dives on the compiled batch RK4 (~6 s)")
def test_the_bundled_project_recovers_the_hidden_coefficients(tmp_path):
    from hydrokit.pipeline import run_project
    from hydrokit.report.run import write_run

    res = run_project("bluerov2_sysid", tmp_path, workers=1)
    write_run(res, tmp_path)
    truth = json.loads((BUNDLED / "truth.json").read_text())["hidden"]
    rows = [r for r in res.document["comparison"] if r["sysid"] is not None]
    assert len(rows) == 12 and all(r["chosen_source"] == "sysid" for r in rows)
    # against the generator's hidden values: every one within 3.5 σ (12 parameters: a 4σ miss
    # has probability 8e-4 per parameter if the stated σ is right; bench/sysid.py measures the
    # 95 % coverage at 94 %) and the relative error below 10 %
    for r in rows:
        t = truth[f"{r['coefficient']}.{r['dof']}"]
        assert abs(r["sysid"] - t) < 3.5 * r["sysid_sigma"], r
        assert abs(r["sysid"] / t - 1) < 0.1, r
    assert (tmp_path / "report.html").read_text().count("data:image/png") == 4  # 3 runs + correlation
    written = yaml.safe_load((tmp_path / "vehicle.yaml").read_text())
    assert written["uncertainty"]["parameters"] == [f"{r['coefficient']}.{r['dof']}" for r in rows]
    # and what the fitted runs covered (issue #56 item 7), as sysid.json has it
    assert written["envelope"] == res.document["sysid"]["result"]["envelope"]
    assert written["envelope"]["runs"] == ["dive1", "dive2"]


def test_a_fit_that_does_not_describe_the_runs_says_so_first(tmp_path, monkeypatch):
    """The step carries the verdict: its reasons lead the warnings and the report's sysid
    section, and the identifiability line no longer reads as good news."""
    from dataclasses import replace

    from hydrokit.report.run import run_report

    fake = FakeIdentify()
    reason = "dive3 (held out): held-out NRMSE of φ 2.18 > 0.5 and residuals lag-1 ρ 0.99: the model does not fit"

    def failing(*args: Any, **kw: Any) -> Any:
        res = fake(*args, **kw)
        return replace(res, verdict={"fits": False, "reasons": [reason]}, messages=())

    monkeypatch.setattr("hydrokit.sysid.fit.identify", failing)
    monkeypatch.setattr("hydrokit.pipeline.sysid._figures", lambda result: [])
    res = run(make_project(tmp_path), tmp_path / "out")
    step = res.document["sysid"]
    assert step["verdict"] == {"fits": False, "reasons": [reason], "details": []}
    assert step["warnings"][0] == f"sysid: {reason}"
    html = run_report(res)
    section = html[html.index("System identification from the vehicle") :]
    assert section.index("Verdict: the model does NOT describe these runs") < section.index("Identifiability")
    assert "these σ understate the error" in section and "every σ below its value.</p>" not in section
    # the vehicle it writes carries the verdict, and flying it says so (hydrokit simulate/manoeuvre)
    written = yaml.safe_load(res.files["vehicle.yaml"])
    assert written["identification"]["verdict"] == "does not fit"
    assert written["identification"]["reasons"] == [reason]
    assert "date" not in written["identification"]  # the same inputs write the same file
    from hydrokit.io.vehicle import load_vehicle

    (tmp_path / "written.yaml").write_text(res.files["vehicle.yaml"])
    assert "does not fit" in load_vehicle(tmp_path / "written.yaml").warnings[0]
