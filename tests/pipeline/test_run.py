"""``hydrokit run`` end to end on a tiny virtual project: numbers against independent
recomputation, the cache, the written vehicle, the report in a browser, and bad input."""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError

CAMPAIGN = DATA_DIR / "campaigns" / "udrobot"
PROJECT = DATA_DIR / "projects" / "udrobot"
# the spring-surge truth at model scale (campaign README: m_a = k/ω_n² − m, K_L, K_Q)
TRUTH = {"added_mass": 0.286623, "linear_damping": 2.679292, "quadratic_damping": 5.595909}
LAUNCHES = [f"spring_x_L{a}_{j}.csv" for a in (1, 2, 3, 4) for j in (1, 2)]


def make_project(folder: Path, samples: int = 6, mission: bool = True) -> Path:
    """8 spring-surge launches, the bundled base vehicle and a 12 s version of the mission."""
    (folder / "launches").mkdir(parents=True, exist_ok=True)
    for name in LAUNCHES:
        shutil.copy(CAMPAIGN / "spring_x" / name, folder / "launches" / name)
    shutil.copy(CAMPAIGN / "spring_x.yaml", folder / "spring_x.yaml")
    shutil.copy(PROJECT / "base.yaml", folder / "base.yaml")
    shutil.copy(PROJECT / "cfd_x.csv", folder / "cfd_x.csv")
    m = yaml.safe_load((PROJECT / "mission.yaml").read_text())
    m["duration"] = 12.0
    (folder / "mission.yaml").write_text(yaml.safe_dump(m))
    doc = {
        "name": "tiny",
        "virtual": True,
        "vehicle": "base.yaml",
        "scale_ratio": 0.3,
        "campaigns": [{"dof": "surge", "rig": "spring_x.yaml", "launches": "launches/*.csv", "truth": TRUTH}],
        "forces": {"surge": {"file": "cfd_x.csv", "area": 0.0495}},
        "uncertainty": {"samples": samples, "seed": 4},
    }
    if mission:
        doc["mission"] = "mission.yaml"
    path = folder / "project.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """(project file, run folder, exit code, seconds) of one CLI run, shared by the tests."""
    from hydrokit.cli.main import main

    folder = tmp_path_factory.mktemp("tiny")
    project = make_project(folder)
    out = folder / "run"
    code = main(["run", str(project), "--out", str(out), "--workers", "1", "--quiet"])
    return project, out, code


def results(out: Path) -> dict:
    return json.loads((out / "results.json").read_text())


def test_the_run_writes_every_output(first_run):
    _, out, code = first_run
    assert code == 0
    for name in (
        "report.html",
        "results.json",
        "vehicle.yaml",
        "mission/pid.csv",
        "mission/s-plane.csv",
        "mission/metrics.json",
    ):
        assert (out / name).is_file(), name
    assert not list(out.glob("**/*.part"))


def test_full_scale_values_are_the_launch_mean_scaled_with_lambda(first_run):
    _, out, _ = first_run
    doc = results(out)
    camp = doc["campaigns"]["surge"]
    lam = 1 / 0.3
    exps = {"added_mass": 3, "linear_damping": 2, "quadratic_damping": 2}  # ENG2009 §II.D
    for coef, e in exps.items():
        s = camp["campaign"]["summary"][coef]
        kept = [L[coef] for L in camp["campaign"]["launches"] if L["file"] not in (s["rejected"] or [])]
        # results.json holds 10 significant digits (JSON_DIGITS): the launches and the mean each
        # carry a rounding of at most 5e-10 relative
        assert camp["full_scale"][coef]["mean"] == pytest.approx(np.mean(kept) * lam**e, rel=2e-9)
        # the tank is chosen (rule "tank") and goes into the vehicle unchanged
        assert doc["chosen"]["surge"][coef] == {
            "value": camp["full_scale"][coef]["mean"],
            "source": "tank",
            "se": camp["full_scale"][coef]["se"],
        }
        # the virtual truth is recovered: within 3 % (8 launches with sensor lag and quantisation)
        assert camp["full_scale"][coef]["mean"] == pytest.approx(TRUTH[coef] * lam**e, rel=0.03)


def test_uncertainty_block_is_launch_scatter_plus_between_group_variance(first_run):
    _, out, _ = first_run
    doc = results(out)
    camp = doc["campaigns"]["surge"]
    summary = camp["campaign"]["summary"]
    rejected = set().union(*(summary[c]["rejected"] or [] for c in TRUTH))
    kept = {L["file"]: [L[c] for c in TRUTH] for L in camp["campaign"]["launches"] if L["file"] not in rejected}
    rows = np.array(list(kept.values()))
    members = [[kept[f] for f in files if f in kept] for files in camp["campaign"]["groups"].values()]
    groups = [np.mean(m, axis=0) for m in members if m]
    assert len(groups) == 4  # 10, 20, 30, 40 mm
    f = np.array([(1 / 0.3) ** e for e in (3, 2, 2)])
    # random effects: launch scatter / n, plus the variance of the 4 group means / 4 on the diagonal
    model = np.cov(rows, rowvar=False) / len(rows) + np.diag(np.var(groups, axis=0, ddof=1) / len(groups))
    expected = model * np.outer(f, f)
    veh = yaml.safe_load((out / "vehicle.yaml").read_text())
    unc = veh["uncertainty"]
    assert unc["parameters"] == ["added_mass.surge", "linear_damping.surge", "quadratic_damping.surge"]
    assert np.allclose(unc["covariance"], expected, rtol=1e-9)
    # recomputed from results.json's 10-digit launch values: their scatter is ~0.5 % of the
    # values, so it carries ~1e-8 relative rounding
    assert unc["added_mass"][0] == pytest.approx(math.sqrt(expected[0, 0]), rel=1e-7)
    assert unc["quadratic_damping"][:3] == [pytest.approx(math.sqrt(expected[2, 2]), rel=1e-7), 0.0, 0.0]


def test_written_vehicle_loads_and_simulates(first_run, run_cli, tmp_path):
    _, out, _ = first_run
    v = hydrokit.load_vehicle(out / "vehicle.yaml")
    doc = results(out)
    assert v.M_A[0, 0] == pytest.approx(doc["chosen"]["surge"]["added_mass"]["value"])
    base = hydrokit.load_vehicle(PROJECT / "base.yaml")
    # untested DOFs keep the base vehicle's values (no source has them)
    assert v.M_A[3, 3] == base.M_A[3, 3] and v.D_Q[5] == base.D_Q[5]
    assert len(v.thrusters) == len(base.thrusters)
    code, _, err = run_cli(
        "simulate",
        out / "vehicle.yaml",
        "--duration",
        "1",
        "--dt",
        "0.01",
        "--force",
        "10,0,0,0,0,0",
        "--out",
        tmp_path / "sim",
    )
    assert code == 0, err
    # the written coefficients drive the flight: from rest under X = 10 N the linear solution is
    # u = X/K_L (1 - exp(-K_L t/(m + m_a))) with the chosen K_L and m_a. Up to 0.05 s (u ≤ 0.025
    # m/s) K_Q lowers u by under 0.2 % (Δu/u ≈ K_Q ∫u dt/(m + m_a)) and the pitch coupling of the
    # CG offset raises it by under 0.7 % (measured); without m_a u would be 2.1x as large
    rows = np.loadtxt(tmp_path / "sim", delimiter=",", skiprows=1)
    k_l = doc["chosen"]["surge"]["linear_damping"]["value"]
    inertia = v.mass + doc["chosen"]["surge"]["added_mass"]["value"]
    for t, u in rows[1:6, [0, 7]]:
        assert u == pytest.approx(10.0 / k_l * (1.0 - math.exp(-k_l * t / inertia)), rel=0.01), t


def test_cfd_comparison_against_the_printed_fit(first_run):
    _, out, _ = first_run
    row = next(r for r in results(out)["comparison"] if r["coefficient"] == "quadratic_damping")
    # cfd_x.csv is CELY2019 Table 5's x-axis Chin fit evaluated at 10 speeds: the fit returns it
    assert row["cfd"] == pytest.approx(43.2322, rel=1e-5)  # the CSV holds 6 significant digits
    assert row["relative_to_tank_percent"]["cfd"] == pytest.approx(
        100 * (row["cfd"] - row["tank"]) / row["tank"],
        rel=1e-8,  # from 10-digit values
    )


def test_mission_metrics_match_flying_the_written_vehicle(first_run):
    project, out, _ = first_run
    doc = results(out)
    run = hydrokit.fly(project.parent / "mission.yaml", "pid", vehicle=out / "vehicle.yaml")
    assert doc["missions"]["controllers"]["pid"]["metrics"]["cross_track_rms"] == pytest.approx(
        run.metrics["cross_track_rms"], rel=1e-12
    )
    mc = doc["monte_carlo"]
    assert mc["samples"] == 6 and set(mc["controllers"]) == {"pid", "s-plane"}
    x = mc["controllers"]["pid"]["metrics"]["cross_track_rms"]
    assert x["p5"] <= x["median"] <= x["p95"]


def _snapshot(out: Path) -> dict[str, tuple[int, int, bytes]]:
    """Every file of a run folder (cache included): inode, mtime (ns) and bytes. An atomic
    rewrite moves a new file in, so even identical bytes get a new inode."""
    return {
        str(p.relative_to(out)): (p.stat().st_ino, p.stat().st_mtime_ns, p.read_bytes())
        for p in sorted(out.rglob("*"))
        if p.is_file()
    }


def test_the_json_files_carry_no_float_noise(first_run):
    _, out, _ = first_run
    for name in ("results.json", "mission/metrics.json"):
        text = (out / name).read_text()
        digits = [len(m.replace(".", "").strip("0")) for m in re.findall(r"(?<![\w.])\d+\.\d+", text)]
        assert digits and max(digits) <= 10, name  # JSON_DIGITS significant digits at most
        assert "999999999" not in text and "000000000" not in text.replace("0.000000000", "")


def test_a_second_run_with_nothing_changed_writes_nothing(first_run, run_cli):
    project, out, _ = first_run
    before = _snapshot(out)
    assert ".cache/report.json" in before  # the stamp of the folder's files
    code, _, err = run_cli("run", project, "--out", out, "--workers", "1", "--quiet")
    assert code == 0, err
    assert "up to date" in err and "nothing written" in err
    assert _snapshot(out) == before


def test_a_second_run_takes_every_step_from_the_cache(first_run):
    project, out, _ = first_run
    before = results(out)
    again = hydrokit.run_project(project, out, workers=1)
    assert all(t["cached"] for t in again.timings if t["step"] != "cfd fit")
    strip = lambda d: {k: v for k, v in d.items() if k not in ("timings", "engine")}  # noqa: E731
    assert strip(again.to_dict()) == strip(before)


def test_a_changed_input_or_an_edited_output_renders_the_report_again(tmp_path, run_cli):
    project = make_project(tmp_path, samples=0, mission=False)
    out = tmp_path / "run"
    args = ("run", project, "--out", out, "--workers", "1", "--quiet")
    assert run_cli(*args)[0] == 0
    first = _snapshot(out)
    # the project's description is an input of the report only: every step stays cached
    doc = yaml.safe_load(project.read_text())
    doc["description"] = "Second description <b>escaped</b>"
    project.write_text(yaml.safe_dump(doc))
    code, _, err = run_cli(*args)
    assert code == 0 and "wrote" in err, err
    second = _snapshot(out)
    assert second["report.html"][:2] != first["report.html"][:2]
    assert "Second description &lt;b&gt;escaped&lt;/b&gt;" in second["report.html"][2].decode()
    assert all(t["cached"] for t in results(out)["timings"] if t["step"] != "cfd fit")
    # a report edited by hand is rendered again (the step timings in it are this run's)
    (out / "report.html").write_text("edited")
    assert run_cli(*args)[0] == 0
    assert "Second description" in (out / "report.html").read_text()
    code, _, err = run_cli(*args, "--force")
    assert code == 0 and "wrote" in err and _snapshot(out)["results.json"][0] != second["results.json"][0]


def test_a_changed_launch_recomputes_its_campaign_and_what_follows(tmp_path):
    project = make_project(tmp_path, samples=2)
    out = tmp_path / "run"
    first = hydrokit.run_project(project, out, workers=1)
    launch = tmp_path / "launches" / LAUNCHES[0]
    launch.unlink()  # one launch fewer
    second = hydrokit.run_project(project, out, workers=1)
    cached = {t["step"]: t["cached"] for t in second.timings}
    assert cached["identify surge"] is False and cached["mission"] is False and cached["monte carlo"] is False
    assert len(second.document["campaigns"]["surge"]["campaign"]["launches"]) == len(LAUNCHES) - 1
    assert second.chosen["surge"]["added_mass"]["value"] != first.chosen["surge"]["added_mass"]["value"]
    forced = hydrokit.run_project(project, out, workers=1, force=True)
    assert not any(t["cached"] for t in forced.timings)


def test_dask_local_cluster_gives_the_serial_result(tmp_path):
    pytest.importorskip("distributed")
    project = make_project(tmp_path, samples=4)
    serial = hydrokit.run_project(project, tmp_path / "serial", workers=1)
    dask = hydrokit.run_project(project, tmp_path / "dask", workers=2)
    assert dask.document["engine"].startswith("Dask LocalCluster, 2 workers (127.0.0.1)")
    assert dask.chosen == serial.chosen
    assert dask.document["monte_carlo"] == serial.document["monte_carlo"]


def test_bad_project_exits_2_writes_nothing_and_keeps_the_cache(first_run, run_cli, tmp_path):
    project, out, _ = first_run
    report_before = (out / "report.html").read_bytes()
    cache_before = sorted(p.name for p in (out / ".cache").iterdir())
    bad = project.parent / "bad.yaml"
    doc = yaml.safe_load(project.read_text())
    doc["campaigns"][0]["launches"] = "launches/*.nothing"
    bad.write_text(yaml.safe_dump(doc))
    code, _, err = run_cli("run", bad, "--out", out, "--workers", "1")
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "campaigns[0].launches" in lines[0] and "matches no file" in lines[0]
    assert "Traceback" not in err
    assert (out / "report.html").read_bytes() == report_before
    assert sorted(p.name for p in (out / ".cache").iterdir()) == cache_before


def test_a_mission_for_a_vehicle_without_thrusters_is_refused(tmp_path, run_cli):
    project = make_project(tmp_path)
    base = yaml.safe_load((tmp_path / "base.yaml").read_text())
    base.pop("thrusters")
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(base))
    with pytest.raises(InputError, match=r"'mission'.*no 'thrusters:' block"):
        hydrokit.run_project(project, tmp_path / "run", workers=1)
    code, _, err = run_cli("run", project, "--out", tmp_path / "run2", "--workers", "1")
    assert code == 2 and not (tmp_path / "run2" / "report.html").exists() and len(err.strip().splitlines()) == 1


def test_an_unreachable_scheduler_is_one_line(tmp_path, run_cli):
    pytest.importorskip("distributed")
    project = make_project(tmp_path, samples=0, mission=False)
    code, _, err = run_cli("run", project, "--out", tmp_path / "run", "--scheduler", "tcp://127.0.0.1:9")
    assert code == 2 and "--scheduler" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "run" / "report.html").exists()


def test_report_renders_in_chromium_with_every_figure(first_run, open_in_chromium, figures_ok, tmp_path):
    _, out, _ = first_run
    source = (out / "report.html").read_text()
    page = open_in_chromium(out / "report.html", tmp_path / "run.png")
    assert page.console == [], page.console
    assert figures_ok(page) == []
    # per-launch fits (8), coefficient summaries (3 + C_D vs Re), mission (2), Monte Carlo (1)
    assert len(page.images) == source.count("<img") == 8 + 4 + 2 + 1
    assert page.text("h1") == ["hydrokit run: tiny"]
    assert page.text("p")[0] == (
        "The 8 tank launches (surge) are virtual: simulated by hydrokit's virtual rig, not measured. "
        "Where the truth is known the report shows identified against true values."
    )
    # the browser shows the JSON's numbers: the full-scale comparison, row by row (4 significant
    # digits; the true value is the virtual truth × λ^e and each source its % from the tank)
    doc = results(out)
    cells = page.text("td")

    def shown(row: list[str]) -> bool:
        return any(cells[i : i + len(row)] == row for i in range(len(cells)))

    lam = 1 / 0.3
    labels = {"added_mass": ("added mass", "kg", 3), "linear_damping": ("K_L", "N·s/m", 2)}
    labels["quadratic_damping"] = ("K_Q", "N·s²/m²", 2)
    assert [r["coefficient"] for r in doc["comparison"]] == list(labels)
    for r in doc["comparison"]:
        label, unit, e = labels[r["coefficient"]]
        tank, (lo, hi) = r["tank"], r["tank_ci"]

        def versus(x: float, tank: float = tank) -> str:
            return f"{x:.4g} ({100 * (x - tank) / tank:+.1f} %)"

        cfd = versus(r["cfd"]) if r["cfd"] is not None else "–"
        truth = versus(TRUTH[r["coefficient"]] * lam**e)
        row = [
            "surge",
            label,
            unit,
            f"{tank:.4g} [{lo:.4g}, {hi:.4g}]",
            truth,
            "–",
            "–",
            cfd,
            "–",
            f"{tank:.4g}",
            "tank",
        ]
        assert shown(row), row
    # the mission table: the flown metrics and the Monte Carlo envelope of the cross-track RMS
    for c, flown in doc["missions"]["controllers"].items():
        m = flown["metrics"]
        mc = doc["monte_carlo"]["controllers"][c]
        x = mc["metrics"]["cross_track_rms"]
        row = [c] + [f"{m[k]:.4g}" for k in ("cross_track_rms", "cross_track_max", "depth_error_rms")]
        row += ["yes" if m["completed"] else "no", f"{x['median']:.3g} [{x['p5']:.3g}, {x['p95']:.3g}]"]
        row += [f"{100 * mc['completed_fraction']:.0f} %"]
        assert shown(row), row
    assert "truth inside envelope (% of times)" in page.text("th")


@pytest.mark.bem
def test_bem_source_is_compared_and_can_be_chosen(tmp_path):
    pytest.importorskip("capytaine")
    project = make_project(tmp_path, samples=0, mission=False)
    shutil.copy(DATA_DIR / "geometry" / "sphere.yaml", tmp_path / "sphere.yaml")
    doc = yaml.safe_load(project.read_text())
    doc.update({"geometry": "sphere.yaml", "choose": {"surge": "bem", "default": "tank"}})
    project.write_text(yaml.safe_dump(doc))
    res = hydrokit.run_project(project, tmp_path / "run", workers=1, bem=True)
    row = next(r for r in res.document["comparison"] if r["coefficient"] == "added_mass")
    # a sphere's added mass is half the displaced fluid mass: ½ ρ π d³/6 (d = 0.5 m, ρ = 1025)
    half = 0.5 * 1025 * math.pi * 0.5**3 / 6
    assert row["geometry"] == pytest.approx(half, rel=0.01)
    assert row["bem"] == pytest.approx(half, rel=0.02)
    assert res.chosen["surge"]["added_mass"]["source"] == "bem"
    # a source without damping (BEM gives added mass only) falls back to the tank for K_L, K_Q
    assert res.chosen["surge"]["quadratic_damping"]["source"] == "tank"


def test_an_error_inside_a_step_is_the_only_stderr_line(tmp_path, run_cli):
    project = make_project(tmp_path, samples=0, mission=False)
    (tmp_path / "launches" / LAUNCHES[3]).write_text("time,position\n0,abc\n")
    code, out, err = run_cli("run", project, "--out", tmp_path / "run", "--workers", "1")  # progress bars on
    assert code == 2
    assert err.splitlines() == [err.strip()] and LAUNCHES[3] in err and "'abc'" in err
    assert not (tmp_path / "run" / "report.html").exists()


def test_report_shows_the_all_launch_statistics_next_to_a_rejection(first_run):
    """Issue #13: results with and without outlier rejection; the report must show both."""
    import re

    from hydrokit.report.html import fmt
    from hydrokit.report.run import campaign_section

    _, out, _ = first_run
    camp = results(out)["campaigns"]["surge"]
    summary = camp["campaign"]["summary"]
    untouched = "".join(campaign_section("surge", camp, {}))
    row = re.search(r"<tr><td[^>]*>added_mass</td>(.*?)</tr>", untouched, re.S)
    assert row is not None
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row.group(1), re.S)
    assert cells[4:6] == ["0", "same"]  # rejected count, then the all-launch column

    # the same campaign as if the rule had rejected one launch: the two means must both show
    e = summary["added_mass"]
    e["rejected"] = [camp["campaign"]["launches"][0]["file"]]
    e["without_rejection"] = {**e["without_rejection"], "mean": 0.4321, "ci": [0.41, 0.45]}
    html = "".join(campaign_section("surge", camp, {}))
    row = re.search(r"<tr><td[^>]*>added_mass</td>(.*?)</tr>", html, re.S)
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row.group(1), re.S)
    assert cells[4] == "1"
    assert cells[5] == f"{fmt(0.4321)} [{fmt(0.41)}, {fmt(0.45)}]"
    assert cells[1].startswith(fmt(e["mean"]))  # the kept-launch mean stays in its column


def test_simulate_samples_draws_an_envelope_from_the_files_covariance(first_run, run_cli, tmp_path):
    """Issue 32 class 8: ``hydrokit simulate VEHICLE --samples 50`` on a run's vehicle.yaml flies 50
    vehicles drawn from its uncertainty block; their spread is the stated σ's."""
    _, out, _ = first_run
    args = ("--force", "50,0,0,0,0,0", "--duration", "40", "--output-every", "100", "--seed", "7")
    code, stdout, err = run_cli("simulate", out / "vehicle.yaml", "--samples", "50", *args, "--out", tmp_path / "s.csv")
    assert code == 0, err
    assert "50 samples of 3 coefficient(s)" in stdout
    doc = yaml.safe_load((out / "vehicle.yaml").read_text())
    unc = doc["uncertainty"]
    cov = np.asarray(unc["covariance"], float)
    header = (tmp_path / "s_samples.csv").read_text().splitlines()[0].split(",")
    rows = np.loadtxt(tmp_path / "s_samples.csv", delimiter=",", skiprows=1)
    col = {name: rows[:, k] for k, name in enumerate(header)}
    assert rows.shape[0] == 50
    drawn = np.column_stack([col[p] for p in unc["parameters"]])
    # the std of 50 normal draws is σ within ±10 % (1 sd: 1/√98); ±30 % is 3 sd for the seeded draw
    assert np.std(drawn, axis=0, ddof=1) == pytest.approx(np.sqrt(np.diag(cov)), rel=0.3)
    # each sample's steady surge speed is the closed form of its own damping under the same net surge
    # force X (the nominal's d_L u₀ + d_Q u₀²: the pitch the CG offset gives is the same to 1e-5)
    u0 = np.loadtxt(tmp_path / "s.csv", delimiter=",", skiprows=1)[-1, 7]
    d_l, d_q = doc["linear_damping"][0], doc["quadratic_damping"][0]
    force = d_l * u0 + d_q * u0**2
    k_l, k_q = col["linear_damping.surge"], col["quadratic_damping.surge"]
    steady = (-k_l + np.sqrt(k_l**2 + 4 * k_q * force)) / (2 * k_q)
    assert col["final_u"] == pytest.approx(steady, rel=1e-4)
    # and the speed's spread is the delta method's σ_u = √(gᵀ Σ g), g = ∂u/∂(m_a, d_L, d_Q), within 3 sd
    g = np.array([0.0, -u0, -(u0**2)]) / (d_l + 2 * d_q * u0)
    assert np.std(col["final_u"], ddof=1) == pytest.approx(math.sqrt(g @ cov @ g), rel=0.3)
    assert np.std(col["final_u"], ddof=1) > 0.005  # a real spread (about 1 % of the speed), not round-off
    env_header = (tmp_path / "s_envelope.csv").read_text().splitlines()[0].split(",")
    env = np.loadtxt(tmp_path / "s_envelope.csv", delimiter=",", skiprows=1)[-1]
    for band, q in (("p5", 5), ("p50", 50), ("p95", 95)):
        assert env[env_header.index(f"u_{band}")] == pytest.approx(np.percentile(col["final_u"], q), rel=1e-8)
    assert env[env_header.index("u_min")] == pytest.approx(col["final_u"].min(), rel=1e-8)


def test_mission_samples_fly_the_vehicles_drawn_from_the_files_covariance(first_run, run_cli, tmp_path):
    """``hydrokit mission --samples`` flies vehicles drawn from the mission vehicle's uncertainty
    block; its metrics are those of flying the same draws one by one with ``hydrokit.fly``."""
    project, out, _ = first_run
    m = yaml.safe_load((project.parent / "mission.yaml").read_text())
    m["vehicle"] = str(out / "vehicle.yaml")
    (tmp_path / "m.yaml").write_text(yaml.safe_dump(m))
    code, stdout, err = run_cli(
        "mission", tmp_path / "m.yaml", "--samples", "8", "--seed", "5", "--controller", "pid", "--out", tmp_path / "o"
    )
    assert code == 0, err
    assert "8 samples of 3 coefficient(s): cross-track RMS 5–95 %" in stdout
    doc = json.loads((tmp_path / "o" / "monte_carlo.json").read_text())
    vehicle = hydrokit.load_vehicle(out / "vehicle.yaml")
    assert doc["parameters"] == list(vehicle.uncertainty.parameters)
    # second method: the same seeded draw, each vehicle flown on its own
    from hydrokit.model.uncertainty import with_coefficients

    mean = [vehicle.M_A[0, 0], vehicle.D_L[0, 0], vehicle.D_Q[0]]
    draws, _ = vehicle.uncertainty.draw(np.array(mean), 8, 5)
    rms = [
        hydrokit.fly(tmp_path / "m.yaml", "pid", vehicle=with_coefficients(vehicle, dict(zip(doc["parameters"], row))))
        for row in draws
    ]
    x = doc["controllers"]["pid"]["metrics"]["cross_track_rms"]
    values = [r.metrics["cross_track_rms"] for r in rms]
    assert x["median"] == pytest.approx(np.median(values), rel=1e-9)
    assert x["p95"] == pytest.approx(np.percentile(values, 95), rel=1e-9)
    assert len(set(values)) == 8  # the draws differ, and so do their flights
    header = (tmp_path / "o" / "envelope.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["time", "pid_x_p5", "pid_x_p50"]
