from __future__ import annotations

import numpy as np
import pytest
import yaml


def test_simulate_frozen_columns(run_cli, tmp_path):
    out = tmp_path / "traj.csv"
    code, stdout, err = run_cli(
        "simulate",
        "bluerov2-heavy",
        "--duration",
        "2",
        "--dt",
        "0.01",
        "--force",
        "30,0,3,0,0,3",
        "--output-every",
        "10",
        "--out",
        out,
        "--plots",
        tmp_path / "p",
    )
    assert code == 0, err
    lines = out.read_text().splitlines()
    assert lines[0] == "time,x,y,z,phi,theta,psi,u,v,w,p,q,r"
    assert len(lines) == 1 + 21
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data[-1, 0] == pytest.approx(2.0)
    assert (tmp_path / "p" / "states.png").stat().st_size > 1000


def test_simulate_options(run_cli, tmp_path):
    f = tmp_path / "force.csv"
    f.write_text("time,X,Y,Z,K,M,N\n0,0,0,0,0,0,0\n1,30,0,0,0,0,0\n")
    code, _, err = run_cli(
        "simulate",
        "minerva",
        "--duration",
        "2",
        "--force-csv",
        f,
        "--initial-velocity",
        "0.1,0,0,0,0,0",
        "--current-ned",
        "0.1,0,0",
        "--integrator",
        "dop853",
        "--attitude",
        "quaternion",
        "--out",
        tmp_path / "t.csv",
    )
    assert code == 0, err


@pytest.mark.parametrize(
    "args,match",
    [
        (["--force", "1,2,3"], "--force"),
        (["--dt", "-1"], "dt"),
        (["--output-every", "0"], "output-every"),
    ],
)
def test_simulate_bad_options(run_cli, tmp_path, args, match):
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", "bluerov2-heavy", "--duration", "1", *args, "--out", out)
    assert code == 2 and match in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_simulate_bad_vehicle_file(run_cli, tmp_path):
    bad = tmp_path / "v.yaml"
    bad.write_text(yaml.safe_dump({"mass": 1.0}))
    code, _, err = run_cli("simulate", bad, "--out", tmp_path / "t.csv")
    assert code == 2 and "missing field" in err and "v.yaml" in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "t.csv").exists()


def test_blow_up_is_exit_2_with_time(run_cli, tmp_path):
    bad = tmp_path / "v.yaml"
    bad.write_text(
        yaml.safe_dump(
            {
                "mass": 10.0,
                "volume": 0.01,
                "inertia": [1, 1, 1],
                "center_of_gravity": [0, 0, 0],
                "center_of_buoyancy": [0, 0, 0],
                "added_mass": [1] * 6,
                "linear_damping": [0] * 6,
                "quadratic_damping": [-100, 0, 0, 0, 0, 0],
                "fluid": {"density": 1000.0},
            }
        )
    )
    code, _, err = run_cli(
        "simulate", bad, "--duration", "60", "--initial-velocity", "1,0,0,0,0,0", "--out", tmp_path / "t.csv"
    )
    assert code == 2 and "non-finite at t =" in err
    assert not (tmp_path / "t.csv").exists()
