from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

GEOMETRY = Path(__file__).resolve().parents[2] / "src" / "hydrokit" / "data" / "geometry"


def test_estimate_rehman_assembly_writes_loadable_vehicle(run_cli, tmp_path):
    out = tmp_path / "frag.yaml"
    code, stdout, err = run_cli("estimate", GEOMETRY / "rehman_assembly.yaml", "--out", out)
    assert code == 0, err
    assert "diagonal only" in stdout and "DNV-RP-H103" in stdout
    from hydrokit.io.vehicle import load_vehicle

    v = load_vehicle(out)
    assert v.mass == pytest.approx(130 + 2 * 450 / 9.81 + 2 * 460)
    frag = yaml.safe_load(out.read_text())
    MA = np.array(frag["added_mass"])
    assert MA.shape == (6, 6)
    # yaw added inertia gains the vehicles' surge added mass at 1.85 m (parallel-axis): far above
    # the diagonal-only sum REHMAN uses
    assert MA[5, 5] > 2 * 293 * 1.85**2


@pytest.mark.parametrize("model", ["elements", "rehman", "shifted"])
def test_estimate_damping_model(run_cli, tmp_path, model):
    out = tmp_path / "frag.yaml"
    code, stdout, err = run_cli("estimate", GEOMETRY / "rehman_assembly.yaml", "--damping-model", model, "--out", out)
    assert code == 0, err
    frag = yaml.safe_load(out.read_text())
    DQ = frag["quadratic_damping"]
    # yaw: the Minervas' own yaw drag (100 each) plus, for each part on the y axis, its common-x
    # drag Qx at |ry| — d·r³ (rehman, REHMAN Table 1) or d·r² (shifted, the old bug). Common Qx is
    # the manipulators' transverse drag ½ρ C_D L D with C_D = 1.05 κ(L/D = 4), κ interpolated in
    # DNV-RP-C205 Table 6-2 between 0.58 (L/D 2) and 0.62 (L/D 5) — not REHMAN's 0.65 — and the
    # Minervas' sway drag 584 (turned 90° in yaw). rel 1e-9: the file rounds to 9 decimals.
    q_manip = 0.5 * 1025 * 1.05 * (0.58 + 0.04 * 2 / 3) * 1.0 * 0.25
    if model == "elements":
        elements = frag["drag_elements"]
        assert [e["name"] for e in elements] == ["manipulator-1", "manipulator-2", "minerva-1", "minerva-2"]
        assert DQ[5] == pytest.approx(2 * 100)  # only the Minervas' own yaw drag stays in the diagonal
        assert elements[2]["quadratic"] == pytest.approx([584, 292, 635])
    else:
        assert "drag_elements" not in frag
        power = 3 if model == "rehman" else 2
        want = 2 * 100 + 2 * (q_manip * 0.75**power + 584 * 1.85**power)
        assert DQ[5] == pytest.approx(want, rel=1e-9)
    assert (model == "shifted") == ("dimensionally wrong" in stdout)
    assert f"quadratic damping ({model})" in stdout
    from hydrokit.io.vehicle import load_vehicle

    assert load_vehicle(out).mass == pytest.approx(130 + 2 * 450 / 9.81 + 2 * 460)


def test_estimate_unknown_damping_model(run_cli, tmp_path):
    code, _, err = run_cli(
        "estimate", GEOMETRY / "rehman_assembly.yaml", "--damping-model", "r2", "--out", tmp_path / "o.yaml"
    )
    assert code == 2
    assert err.splitlines() == [
        "error: Invalid value for '--damping-model': 'r2' is not one of 'elements', 'rehman', 'shifted'. "
        "(see 'hydrokit estimate --help')"
    ]
    assert not (tmp_path / "o.yaml").exists()


def test_fit_forces_cli(run_cli, tmp_path):
    f = tmp_path / "f.csv"
    U = np.linspace(0.2, 10, 12)
    F = 1.0503 * U + 43.2322 * U * U  # CELY2019 Table 5 x-axis Chin coefficients, noise-free
    f.write_text("speed,force\n" + "\n".join(f"{u},{x}" for u, x in zip(U, F)) + "\n")
    code, stdout, err = run_cli(
        "fit-forces",
        f,
        "--area",
        "0.0495",
        "--density",
        "998.2",
        "--json",
        tmp_path / "o.json",
        "--plot",
        tmp_path / "o.png",
    )
    assert code == 0, err
    assert "K_L = 1.0503" in stdout and "K_Q = 43.2322" in stdout
    doc = json.loads((tmp_path / "o.json").read_text())
    # noise-free Chin data: the fit gives back the coefficients it was made from
    assert doc["K_L"] == pytest.approx(1.0503, rel=1e-9)
    assert doc["K_Q"] == pytest.approx(43.2322, rel=1e-9)
    # Morison K_D U|U| through the origin, closed form least squares: K_D = Σ F U² / Σ U⁴, and
    # C_D = 2 K_D / (ρ A)
    k_d = float(np.sum(F * U**2) / np.sum(U**4))
    assert doc["K_D"] == pytest.approx(k_d, rel=1e-9)
    assert doc["C_D"] == pytest.approx(2 * k_d / (998.2 * 0.0495), rel=1e-9)
    assert doc["n"] == 12 and doc["area"] == 0.0495 and doc["density"] == 998.2
    assert (tmp_path / "o.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "doc,match",
    [
        ({"parts": [{"shape": "sphere", "diameter": -0.5, "mass": 1}]}, "diameter"),
        ({"parts": [{"shape": "torus", "diameter": 0.5, "mass": 1}]}, "'parts\\[0\\].shape' = 'torus'"),
    ],
)
def test_estimate_bad_geometry(run_cli, tmp_path, doc, match):
    import re

    g = tmp_path / "g.yaml"
    g.write_text(yaml.safe_dump(doc))
    out = tmp_path / "o.yaml"
    code, _, err = run_cli("estimate", g, "--out", out)
    assert code == 2 and re.search(match, err), err
    assert len(err.strip().splitlines()) == 1 and not out.exists()


def test_fit_forces_one_point(run_cli, tmp_path):
    f = tmp_path / "f.csv"
    f.write_text("speed,force\n1.0,40\n")
    code, _, err = run_cli("fit-forces", f, "--area", "0.05", "--density", "998.2")
    assert code == 2
    assert err.splitlines() == [f"error: {f}: only 1 point(s); expected at least 3 speed–force pairs"]


def test_mesh_errors_are_one_line(run_cli, tmp_path):
    stl = tmp_path / "open.stl"
    stl.write_text(
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n"
    )
    g = tmp_path / "g.yaml"
    g.write_text(yaml.safe_dump({"parts": [{"mesh": "open.stl", "mass": 1.0}]}))
    code, _, err = run_cli("estimate", g, "--bem", "--out", tmp_path / "o.yaml")
    # with the bem extra (CI installs it) the mesh check answers; without it, the install hint
    expected = "not closed" if importlib.util.find_spec("capytaine") else "hydrokit[bem]"
    assert code == 2 and expected in err
    if expected == "not closed":
        assert "open.stl" in err  # the message names the mesh
    assert len(err.strip().splitlines()) == 1


def test_fit_forces_with_nothing_to_fit_names_the_file(run_cli, tmp_path):
    # issue 32 class 5: all-zero forces printed R² = nan and exited 0
    f = tmp_path / "zero.csv"
    f.write_text("speed,force\n" + "".join(f"{u},0\n" for u in (0.5, 1.0, 1.5, 2.0)))
    code, out, err = run_cli("fit-forces", f, "--area", "0.1", "--density", "1000")
    assert code == 2 and out == ""
    assert err.splitlines() == [
        f"error: {f}: force: all 4 forces are 0 N: nothing to fit; expected resisting forces that change with speed (N)"
    ], err
