"""``hydrokit simulate --deflection / --deflection-csv`` (issue #45): degrees on the command
line, radians in the CSV, the same trajectory as the API, and one-line refusals."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import yaml

import hydrokit

VEHICLE = {
    "name": "rudder-only",
    "mass": 30.0,
    "volume": 30.0 / 1025.0,
    "fluid": {"density": 1025.0},
    "inertia": [0.2, 3.4, 3.4],
    "center_of_gravity": [0, 0, 0],
    "center_of_buoyancy": [0, 0, 0],
    "added_mass": [1.0, 35.0, 35.0, 0.1, 4.9, 4.9],
    "linear_damping": [1, 5, 5, 0.5, 2, 2],
    "quadratic_damping": [1.6, 130, 130, 0.13, 90, 90],
    "dofs": ["surge", "sway", "yaw"],
    "control_surfaces": [{"name": "rudder", "position": [-0.6, 0, 0], "max_deflection_deg": 15}],
    "terms": {"Y_uu*delta(rudder)": 9.64, "N_uu*delta(rudder)": -6.15},
}


@pytest.fixture
def vehicle_file(tmp_path):
    p = tmp_path / "v.yaml"
    p.write_text(yaml.safe_dump(VEHICLE))
    return p


def _read(path):
    return np.loadtxt(path, delimiter=",", skiprows=1)


def test_constant_and_tabulated_deflections_match_the_api(run_cli, vehicle_file, tmp_path):
    out, out2 = tmp_path / "a.csv", tmp_path / "b.csv"
    common = ["simulate", vehicle_file, "--duration", "5", "--dt", "0.01", "--force", "4,0,0,0,0,0"]
    code, _, err = run_cli(*common, "--deflection", "rudder=10", "--out", out)
    assert code == 0, err
    table = tmp_path / "d.csv"
    table.write_text(f"time,rudder\n0,{math.radians(10)}\n2,{math.radians(10)}\n")
    code, _, err = run_cli(*common, "--deflection-csv", table, "--out", out2)
    assert code == 0, err
    api = hydrokit.simulate(
        hydrokit.load_vehicle(vehicle_file), 5.0, 0.01, (4, 0, 0, 0, 0, 0), deflection=[math.radians(10)]
    )
    np.testing.assert_allclose(_read(out)[:, 6], api.eta[:, 5], rtol=6e-9, atol=1e-12)  # ψ: 9 significant digits
    np.testing.assert_allclose(_read(out2), _read(out), rtol=0, atol=1e-12)
    assert api.eta[-1, 5] < -0.05  # positive rudder, N_uuδr < 0: the heading falls (turn to port)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--deflection", "rudder=20"], r"rudder = 20°: expected at most 15°"),
        (["--deflection", "rudd=5"], r"'rudd=5': expected NAME=DEG with NAME one of rudder"),
        (["--deflection", "rudder=x"], r"'rudder=x': expected a finite angle"),
        (["--deflection", "rudder=1", "--deflection-csv", "d.csv"], r"expected one of them"),
    ],
)
def test_bad_deflections_exit_2_and_write_nothing(run_cli, vehicle_file, tmp_path, args, message):
    out = tmp_path / "o.csv"
    code, _, err = run_cli("simulate", vehicle_file, "--duration", "1", *args, "--out", out)
    assert code == 2 and not out.exists()
    assert len(err.strip().splitlines()) == 1 and re.search(message, err), err


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("time,rudder,stern\n0,0,0\n", r"unknown column 'stern'"),
        ("time\n0\n", r"missing column 'rudder'"),
        ("time,rudder\n0,0.5\n", r"rudder = 28.6\d*°: expected at most 15°"),
        ("time,rudder\n1,0\n0,0\n", r"'time' must increase strictly"),
        ("time,rudder\n0,abc\n", r"row 2, column 'rudder' = 'abc': expected a finite number"),
    ],
)
def test_bad_deflection_csv_names_file_and_column(run_cli, vehicle_file, tmp_path, text, message):
    table, out = tmp_path / "d.csv", tmp_path / "o.csv"
    table.write_text(text)
    code, _, err = run_cli("simulate", vehicle_file, "--deflection-csv", table, "--out", out)
    assert code == 2 and not out.exists()
    assert re.search(message, err) and "d.csv" in err, err
