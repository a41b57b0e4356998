"""``hydrokit identify``/``scale``/``rig`` end to end, and the bad-input table of docs/identify.md."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

RIG = {
    "test": "pendulum",
    "axis": "surge",
    "gravity": 9.79,
    "fluid": {"density": 998.2, "kinematic_viscosity": 1.0e-6},
    "body": {"mass": 0.146, "volume": 1.07597e-4, "reference_area": 0.004, "reference_length": 0.087},
    "pendulum": {"length": 0.39},
}

INERTIA = {"body.inertia": 0.01}  # kg m², for floating-rig cases built from RIG


def write_rig(path: Path, **changes) -> Path:
    doc = json.loads(json.dumps(RIG))
    for key, value in changes.items():
        node = doc
        parts = key.split(".")
        for p in parts[:-1]:
            node = node[p]
        if value is None:
            node.pop(parts[-1], None)
        else:
            node[parts[-1]] = value
    path.write_text(yaml.safe_dump(doc))
    return path


def write_launch(path: Path, t, y, column: str = "angle") -> Path:
    lines = ["# test launch", f"time,{column}"] + [f"{a:.4f},{b:.7g}" for a, b in zip(t, y)]
    path.write_text("\n".join(lines) + "\n")
    return path


# how the HTML report prints a number in a table: 4 significant digits (3 for Re, KC, residual)
def g4(x: float) -> str:
    return f"{x:.4g}"


def summary_cells(s: dict) -> str:
    """A summary cell as the report shows it: mean ± std [95 % CI]."""
    return f"{g4(s['mean'])} ± {g4(s['std'])} [{g4(s['ci'][0])}, {g4(s['ci'][1])}]"


def html_row(*cells: str) -> str:
    """A report table row: the first cell is the left-aligned label."""
    return f'<tr><td class="l">{cells[0]}</td>' + "".join(f"<td>{c}</td>" for c in cells[1:]) + "</tr>"


# the report's coefficient columns, in its order (m_a, C_m, K_L, K_Q, C_D, ω_n, ζ)
SUMMARY_COLUMNS = ("added_mass", "added_mass_coefficient", "linear_damping", "quadratic_damping")
SUMMARY_COLUMNS += ("drag_coefficient", "natural_frequency", "damping_ratio")


def method_row(method: str, summary: dict) -> str:
    n = summary["added_mass"]["n"]
    return html_row(method, str(n), *(summary_cells(summary[k]) for k in SUMMARY_COLUMNS))


@pytest.fixture
def good(tmp_path):
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch
    from hydrokit.io.rig import load_rig

    rig_path = write_rig(tmp_path / "rig.yaml")
    rig = load_rig(rig_path)
    files = []
    for k, amp in enumerate((5, 10, 15)):
        L = simulate_launch(rig, 0.05, 0.02, 0.3, math.radians(amp), 12.0, SensorModel.imu(), rng=k)
        files.append(write_launch(tmp_path / f"l{k}.csv", L.t, L.y))
    return rig_path, files


def test_identify_writes_frozen_json(run_cli, good, tmp_path):
    rig_path, files = good
    # a launch file whose name is markup: the report must show it as text
    evil = tmp_path / "<script>l2.csv"
    evil.write_text(files[2].read_text())
    files = [files[0], files[1], evil]
    out = tmp_path / "out.json"
    code, stdout, err = run_cli(
        "identify", rig_path, *files, "--json", out, "--plots", tmp_path / "plots", "--report", tmp_path / "r.html"
    )
    assert code == 0, err
    doc = json.loads(out.read_text())
    assert set(doc) >= {"launches", "summary"}
    L = doc["launches"][0]
    for key in ("file", "method", *SUMMARY_COLUMNS, "reynolds_max", "kc", "rms_residual", "std_error", "warnings"):
        assert key in L
    assert L["method"] == "output-error"  # the default
    assert set(L["std_error"]) == {"added_mass", "linear_damping", "quadratic_damping"}
    # m_a/(ρV) and 2K_Q/(ρA) as defined by the issue
    assert L["added_mass_coefficient"] == pytest.approx(L["added_mass"] / (998.2 * 1.07597e-4))
    assert L["drag_coefficient"] == pytest.approx(2 * L["quadratic_damping"] / (998.2 * 0.004))
    s = doc["summary"]["added_mass"]
    assert s["n"] == 3 and s["ci"][0] < s["mean"] < s["ci"][1] and "rule" in s
    assert s["mean"] == pytest.approx(0.05, rel=0.01)
    assert len(list((tmp_path / "plots").glob("*_fit.png"))) == 3
    html = (tmp_path / "r.html").read_text()
    # the report shows the JSON's numbers: the summary row of the method and one row per launch
    assert method_row("output-error", doc["summary"]) in html
    for L, name in zip(doc["launches"], ("l0.csv", "l1.csv", "&lt;script&gt;l2.csv")):
        numbers = [g4(L[k]) for k in ("amplitude", "added_mass", "linear_damping", "quadratic_damping")]
        tail = [f"{L[k]:.3g}" for k in ("reynolds_max", "kc", "rms_residual")]
        assert html_row(name, *numbers, g4(L["drag_coefficient"]), *tail) in html, name
    assert "<script>" not in html  # the file name is escaped wherever it appears
    # every figure of --plots is in the report (fit and adequacy per launch, coefficients vs Re)
    assert html.count('alt="l0: measured and fitted signal, residual"') == 1
    assert html.count("<img") == len(list((tmp_path / "plots").glob("*.png"))) == 3 + 3 + 1


@pytest.mark.parametrize("method", ["equation-error", "morison", "log-decrement"])
def test_identify_other_methods(run_cli, good, tmp_path, method):
    rig_path, files = good
    out = tmp_path / "o.json"
    code, _, err = run_cli("identify", rig_path, *files, "--json", out, "--method", method)
    assert code == 0, err
    doc = json.loads(out.read_text())
    assert {L["method"] for L in doc["launches"]} == {method}
    assert doc["summary"]["added_mass"]["mean"] == pytest.approx(0.05, rel=0.1)


def test_angle_deg_column_is_converted(run_cli, good, tmp_path):
    rig_path, files = good
    text = files[0].read_text().replace("time,angle", "time,angle_deg")
    rows = [ln.split(",") for ln in text.splitlines()[2:]]
    deg = "\n".join(f"{a},{math.degrees(float(b)):.6g}" for a, b in rows)
    p = tmp_path / "deg.csv"
    p.write_text("time,angle_deg\n" + deg + "\n")
    code, _, err = run_cli("identify", rig_path, p, files[0], "--json", tmp_path / "d.json")
    assert code == 0, err
    a, b = json.loads((tmp_path / "d.json").read_text())["launches"]
    assert a["added_mass"] == pytest.approx(b["added_mass"], rel=1e-3)


def _bad_cases(tmp_path, good):
    rig_path, files = good
    t = np.arange(0, 10, 0.01)
    y = 0.1 * np.exp(-0.1 * t) * np.cos(2.2 * t)
    cases = {
        "missing column": (rig_path, write_launch(tmp_path / "c1.csv", t, y, column="theta"), "missing column 'angle'"),
        "NaN": (rig_path, Path(str(write_launch(tmp_path / "c2.csv", t, y))), "row 10, column 'angle' = nan"),
        "non-monotonic time": (
            rig_path,
            write_launch(tmp_path / "c3.csv", np.r_[t[:50], t[48:40:-1], t[60:]], np.r_[y[:50], y[48:40:-1], y[60:]]),
            "time goes back from 0.49 to 0.48 s at row 52",
        ),
        "duplicate time": (
            rig_path,
            write_launch(tmp_path / "c4.csv", np.r_[t[:50], t[49:]], np.r_[y[:50], y[49:]]),
            "duplicate time 0.49 s at rows 51 and 52",
        ),
        "fewer than two cycles": (
            rig_path,
            write_launch(tmp_path / "c5.csv", t, 0.1 * np.exp(-0.1 * t) * np.cos(0.8 * t)),
            "only 1.5 cycles; expected at least two cycles",
        ),
        "growing": (
            rig_path,
            write_launch(tmp_path / "c6.csv", t, 0.01 * np.exp(0.3 * t) * np.cos(2.2 * t) / np.exp(3)),
            "the oscillation grows",
        ),
        "non-oscillating": (rig_path, write_launch(tmp_path / "c7.csv", t, 0.1 * np.exp(-t)), "does not oscillate"),
        "degrees in angle": (
            rig_path,
            write_launch(tmp_path / "c8.csv", t, np.degrees(y)),
            "'angle' reaches 5.73, which looks like degrees",
        ),
        "unknown test": (write_rig(tmp_path / "r1.yaml", test="catapult"), files[0], "field 'test' = 'catapult'"),
        "negative mass": (write_rig(tmp_path / "r2.yaml", **{"body.mass": -1.0}), files[0], "field 'body.mass' = -1.0"),
        "negative volume": (
            write_rig(tmp_path / "r3.yaml", **{"body.volume": -1e-4}),
            files[0],
            "field 'body.volume' = -0.0001",
        ),
        "pendulum without length": (
            write_rig(tmp_path / "r4.yaml", pendulum=None),
            files[0],
            "field 'pendulum.length' is missing",
        ),
        "buoyancy equals weight": (
            write_rig(tmp_path / "r5.yaml", **{"body.volume": 0.146 / 998.2}),
            files[0],
            "buoyancy 1.42934 N equals the weight 1.42934 N",
        ),
        "GM ≤ 0 (floating)": (
            write_rig(
                tmp_path / "r6.yaml", test="floating", axis="roll", pendulum=None, floating={"gm": -0.3}, **INERTIA
            ),
            files[0],
            "field 'floating.gm' = -0.3",
        ),
        "GZ table not from zero": (
            write_rig(
                tmp_path / "r7.yaml",
                test="floating",
                axis="roll",
                pendulum=None,
                floating={"gz": [[5, 0], [10, 0.01]]},
                **INERTIA,
            ),
            files[0],
            "field 'floating.gz' starts at [5.0, 0.0]",
        ),
        "missing file": (rig_path, tmp_path / "nope.csv", "no such file"),
    }
    nan_file = cases["NaN"][1]
    lines = nan_file.read_text().splitlines()
    lines[10] = lines[10].split(",")[0] + ",nan"
    nan_file.write_text("\n".join(lines) + "\n")
    return cases


def test_bad_input_table(run_cli, good, tmp_path):
    good_rig = good[0]
    for name, (rig, launch, expected) in _bad_cases(tmp_path, good).items():
        out = tmp_path / f"{name.replace(' ', '_')}.json"
        code, stdout, err = run_cli("identify", rig, launch, "--json", out)
        assert code == 2, (name, err)
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        assert len(lines) == 1, (name, err)
        # the one line names the bad file first, then the field or column and the bad value
        bad_file = launch if rig == good_rig else rig
        assert lines[0].startswith(f"error: {bad_file}: "), (name, lines[0])
        assert expected in lines[0], (name, lines[0])
        assert "Traceback" not in err
        assert not out.exists(), name  # no partial JSON


def test_buoyant_pendulum_is_identified(run_cli, tmp_path):
    from hydrokit.identify.virtual_rig import SensorModel, simulate_launch
    from hydrokit.io.rig import load_rig

    rig_path = write_rig(tmp_path / "b.yaml", **{"body.volume": 3.0e-4})  # B = 2.9 N > W = 1.43 N
    rig = load_rig(rig_path)
    L = simulate_launch(rig, 0.15, 0.02, 0.3, 0.2, 12.0, SensorModel.imu(), rng=0)
    f = write_launch(tmp_path / "b.csv", L.t, L.y)
    code, _, err = run_cli("identify", rig_path, f, "--json", tmp_path / "b.json")
    assert code == 0, err
    assert json.loads((tmp_path / "b.json").read_text())["launches"][0]["added_mass"] == pytest.approx(0.15, rel=0.01)


def test_scale_command_eng2009(run_cli):
    code, out, err = run_cli("scale", "--ratio", "0.3", "--added-mass", "0.58", "--quadratic-damping", "9.5439")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "λ = L_full / L_model = 3.33333"
    full = {line.split(":")[0]: float(line.rsplit(" ", 1)[1]) for line in lines[1:3]}
    assert lines[1].startswith("added_mass: model 0.58 → full scale ")
    assert lines[2].startswith("quadratic_damping: model 9.5439 → full scale ")
    # similitude: m_a ∝ λ³, K_Q ∝ λ² (λ = 1/0.3), to the 6 digits printed; ENG2009 Tables III/IV
    # print the full-scale values to 2 decimals: 21.48 kg and 106.04 N s²/m²
    assert full["added_mass"] == pytest.approx(0.58 / 0.3**3, rel=1e-5)
    assert full["quadratic_damping"] == pytest.approx(9.5439 / 0.3**2, rel=1e-5)
    assert round(full["added_mass"], 2) == 21.48 and round(full["quadratic_damping"], 2) == 106.04
    assert "  - comparison at equal speed — this is NOT Reynolds similarity; Re grows by λ at full scale" in lines


def test_rig_simulate_then_identify_round_trip(run_cli, good, tmp_path):
    rig_path, _ = good
    out_dir = tmp_path / "virtual"
    code, _, err = run_cli(
        "rig",
        "simulate",
        rig_path,
        "--added-mass",
        "0.05",
        "--linear-damping",
        "0.02",
        "--quadratic-damping",
        "0.3",
        "--amplitudes",
        "5,15",
        "--launches",
        "2",
        "--out",
        out_dir,
    )
    assert code == 0, err
    files = sorted(out_dir.glob("*.csv"))
    assert len(files) == 4
    assert files[0].read_text().startswith("#")
    code, _, err = run_cli("identify", rig_path, *files, "--json", tmp_path / "v.json")
    assert code == 0, err
    doc = json.loads((tmp_path / "v.json").read_text())
    assert doc["summary"]["added_mass"]["mean"] == pytest.approx(0.05, rel=0.01)


def test_rig_plan_prints_bounds(run_cli, good, monkeypatch):
    from hydrokit.identify.design import plan_experiment
    from hydrokit.identify.virtual_rig import SensorModel
    from hydrokit.io.rig import load_rig

    monkeypatch.setenv("COLUMNS", "200")  # one text line per table row
    rig_path, _ = good
    code, out, err = run_cli(
        "rig",
        "plan",
        rig_path,
        "--added-mass",
        "0.05",
        "--linear-damping",
        "0.02",
        "--quadratic-damping",
        "0.3",
        "--amplitudes",
        "2.5,15",
    )
    assert code == 0, err
    # the printed bounds are the API's for the same rig, truth and the documented default sensor
    # (100 Hz, 0.05° noise, no step), 20 s records and 6 launches per amplitude
    sensor = SensorModel(100.0, math.radians(0.05), 0.0, 0.0)
    plan = plan_experiment(
        load_rig(rig_path), 0.05, 0.02, 0.3, [math.radians(2.5), math.radians(15)], sensor, 20.0, launches=6
    )
    rows = [[c.strip() for c in line.split("│")[1:-1]] for line in out.splitlines() if line.startswith("│")]
    assert [r[0] for r in rows] == ["2.5°", "15°"]
    for cells, p in zip(rows, plan):
        assert cells[1] == f"{p['speed_max']:.3g}"
        for cell, k in zip(cells[2:5], ("added_mass", "linear_damping", "quadratic_damping")):
            assert cell == f"{p[k]:.3g} ({100 * p[k + '_rel']:.2g} %)", k
    assert "predicted standard errors, 6 launch(es) per amplitude, sensor 100 Hz, noise 0.05 °, step 0 °" in out


def test_demo_writes_report(run_cli, tmp_path):
    code, out, err = run_cli("demo", "--out", tmp_path / "demo", "--campaign", "rov2")
    assert code == 0, err
    html = (tmp_path / "demo" / "report.html").read_text()
    doc = json.loads((tmp_path / "demo" / "results.json").read_text())
    run = doc["pendulum rig, surge"]
    assert list(run) == ["output-error", "equation-error", "morison"]
    # the report's summary table is the JSON's numbers, one row per method
    for method, result in run.items():
        assert method_row(method, result["summary"]) in html, method
    # the full-scale table: λ = 1/0.3, m_a ∝ λ³ and K_Q ∝ λ² (equal C_D at equal speed)
    lam = run["output-error"]["full_scale"]["lambda"]
    assert lam == pytest.approx(1 / 0.3, rel=1e-12)
    oe_full = run["output-error"]["full_scale"]
    ma, kq = (
        run["output-error"]["summary"]["added_mass"]["mean"],
        run["output-error"]["summary"]["quadratic_damping"]["mean"],
    )
    assert oe_full["added_mass"] == pytest.approx(ma * lam**3, rel=1e-12)
    assert oe_full["quadratic_damping"] == pytest.approx(kq * lam**2, rel=1e-12)
    full_row = html_row("output-error", g4(ma * lam**3), g4(oe_full["linear_damping"]), g4(kq * lam**2))
    assert full_row in html
    oe = run["output-error"]["summary"]
    # ENG2009 Table II means used as truth for the bundled ROV II campaign; the launches swing on
    # the effective length 0.3904 m (ENG2009 §IV.A air tare) while the rig file holds the measured
    # 0.39 m, and without the tare m + m_a ∝ 1/r comes out 0.1 % high: m_a 0.5857 kg
    assert oe["added_mass"]["mean"] == pytest.approx((5.0 + 0.58) * 0.3904 / 0.39 - 5.0, rel=0.01)


def test_scale_reports_cely2019_cm_convention_beside_similitude(run_cli, published):
    """CELY2019 Table 10 prints full-scale added masses equal to C_m × 9.2006 kg (an implied
    9.2 L reference), not λ³ × the 22 % model's added mass: `scale` shows both."""
    t10 = published["cely2019"]["table10_pendulum"]
    rho, v_model = 998.2, 107597e-9  # CELY2019 §3.3 model volume, water at 20 °C
    m_a_model = t10["C_m"][0] * rho * v_model
    code, out, err = run_cli(
        "scale",
        "--ratio",
        "0.22",
        "--added-mass",
        m_a_model,
        "--model-volume",
        v_model,
        "--full-volume",
        9.2006 / rho,
    )
    assert code == 0, err
    cm_form = float(out.split("Table 10 convention): ")[1].split(";")[0])
    assert cm_form == pytest.approx(t10["added_mass_kg"][0], rel=1e-4)  # 8.3027 kg as printed
    lam3 = float(out.split("λ³ similitude gives ")[1].split(" ")[0])
    assert lam3 == pytest.approx(m_a_model / 0.22**3, rel=1e-5) and lam3 > 1.05 * cm_form
    code, _, err = run_cli("scale", "--ratio", "0.22", "--added-mass", "0.1", "--model-volume", "1e-4")
    assert code == 2
    assert err.splitlines() == ["error: --model-volume and --full-volume go together (m³): give both or neither"]


def test_same_input_gives_byte_identical_outputs(run_cli, good, tmp_path):
    # issue #13 item 4: no clock, no random state and no dict-order drift in what is written
    rig_path, files = good
    outs = [tmp_path / "a.json", tmp_path / "b.json"]
    for out in outs:
        code, _, err = run_cli("identify", rig_path, *files, "--json", out)
        assert code == 0, err
    assert outs[0].read_bytes() == outs[1].read_bytes()
    dirs = [tmp_path / "m1", tmp_path / "m2"]
    for d in dirs:
        code, _, err = run_cli("mission", "minerva_square", "--out", d, "--duration", 20, "--no-plots")
        assert code == 0, err
    names = sorted(p.name for p in dirs[0].iterdir())
    assert names == sorted(p.name for p in dirs[1].iterdir()) and any(n.endswith(".csv") for n in names)
    for n in names:
        assert (dirs[0] / n).read_bytes() == (dirs[1] / n).read_bytes(), n
