from __future__ import annotations

import re

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.io.vehicle import resolve_vehicle

# the CSV holds 9 significant digits: the CLI's numbers equal the API's to half a unit in the 9th
CSV_RTOL = 6e-9


def api_table(vehicle, duration, dt, tau, **options):
    """time, eta, nu of the Python API's run with the same inputs as a CLI run."""
    tr = hydrokit.simulate(vehicle, duration, dt, tau, **options)
    return np.column_stack([tr.time, tr.eta, tr.nu])


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
    # the numbers are the API's for the same vehicle, force, step and output stride
    ref = api_table("bluerov2-heavy", 2.0, 0.01, [30, 0, 3, 0, 0, 3], output_every=10)
    np.testing.assert_allclose(data, ref, rtol=CSV_RTOL, atol=1e-15)
    assert data[-1, 7] > 0.1  # surging forward under 30 N (not a run at rest)
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
    data = np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)
    # every option reaches the run: the CSV is the API's run with the same table, initial velocity,
    # current, integrator and attitude (rk4 or Euler angles instead differ by ~1e4 x CSV_RTOL, no
    # current by 0.017 m, a constant 30 N by 0.03 m)
    ref = api_table(
        "minerva",
        2.0,
        0.01,
        [[0, 0, 0, 0, 0, 0, 0], [1, 30, 0, 0, 0, 0, 0]],
        nu0=[0.1, 0, 0, 0, 0, 0],
        current_ned=[0.1, 0, 0],
        integrator="dop853",
        attitude="quaternion",
    )
    np.testing.assert_allclose(data, ref, rtol=CSV_RTOL, atol=1e-15)
    assert data[0, 7] == 0.1  # the initial surge velocity as given


@pytest.mark.parametrize(
    "args,message",
    [
        (["--force", "1,2,3"], "error: --force '1,2,3': expected 6 comma-separated finite numbers (N, N·m)"),
        (["--dt", "-1"], "error: --dt '-1': expected a finite number > 0 (s)"),
        (["--output-every", "0"], "error: --output-every '0': expected a whole number ≥ 1"),
    ],
    ids=["force", "dt", "output-every"],
)
def test_simulate_bad_options(run_cli, tmp_path, args, message):
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", "bluerov2-heavy", "--duration", "1", *args, "--out", out)
    assert code == 2
    assert err.splitlines() == [message], err
    assert not out.exists()


@pytest.mark.parametrize(
    ("vehicle", "args", "message"),
    [
        ("bluerov2-heavy", ["--samples", "5"], "--samples 5: vehicle 'bluerov2-heavy' has no 'uncertainty:' block"),
        ("sigma", ["--samples", "1"], "--samples 1: expected a whole number from 2 to 100000"),
        ("sigma", ["--samples", "3", "--integrator", "dop853"], "--integrator 'dop853' with --samples: the samples"),
        ("sigma", ["--samples", "3", "--attitude", "quaternion"], "expected --attitude euler"),
    ],
    ids=["no-uncertainty", "one-sample", "adaptive", "quaternion"],
)
def test_samples_the_run_cannot_honour_are_refused_before_the_run(run_cli, tmp_path, vehicle, args, message):
    """``--samples`` (issue 32 class 8) needs the file's σ and the compiled Euler RK4 of the batch."""
    if vehicle == "sigma":
        doc = yaml.safe_load(resolve_vehicle("bluerov2-heavy").read_text())
        doc["uncertainty"] = {"quadratic_damping": [10.0, 0, 0, 0, 0, 0]}
        vehicle = tmp_path / "v.yaml"
        vehicle.write_text(yaml.safe_dump(doc))
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", vehicle, "--duration", "1", *args, "--out", out)
    assert code == 2
    assert len(err.splitlines()) == 1 and message in err, err
    assert not out.exists()


def test_samples_of_a_hand_written_sigma_spread_the_steady_speed(run_cli, tmp_path):
    """A vehicle file with only standard errors (no covariance): its σ is drawn independently, and
    each sample's steady surge speed is the closed form of its own damping."""
    doc = yaml.safe_load(resolve_vehicle("bluerov2-heavy").read_text())
    doc["uncertainty"] = {"quadratic_damping": [20.0, 0, 0, 0, 0, 0]}
    # neutrally buoyant with B at G: a pure surge run, no pitch or heave to couple into it
    doc["volume"] = doc["mass"] / doc.get("fluid", {"density": 1025.0})["density"]
    doc["center_of_buoyancy"] = doc["center_of_gravity"]
    (tmp_path / "v.yaml").write_text(yaml.safe_dump(doc))
    code, _, err = run_cli(
        "simulate", tmp_path / "v.yaml", "--samples", "40", "--force", "40,0,0,0,0,0", "--duration", "30",
        "--output-every", "100", "--out", tmp_path / "t.csv",
    )  # fmt: skip
    assert code == 0, err
    rows = np.loadtxt(tmp_path / "t_samples.csv", delimiter=",", skiprows=1)
    header = (tmp_path / "t_samples.csv").read_text().splitlines()[0].split(",")
    assert header[1] == "quadratic_damping.surge"
    d_q, u = rows[:, 1], rows[:, header.index("final_u")]
    assert np.std(d_q, ddof=1) == pytest.approx(20.0, rel=0.35)  # 40 draws: 1 sd of the std is 11 %
    v = hydrokit.load_vehicle(tmp_path / "v.yaml")
    d_l = v.D_L[0, 0]
    steady = (-d_l + np.sqrt(d_l**2 + 4 * d_q * 40.0)) / (2 * d_q)  # d_L u + d_Q u² = 40 N
    assert u == pytest.approx(steady, rel=1e-6)  # 30 s is 100 time constants
    assert np.ptp(u) > 0.01  # a real spread


def test_simulate_bad_vehicle_file(run_cli, tmp_path):
    bad = tmp_path / "v.yaml"
    bad.write_text(yaml.safe_dump({"mass": 1.0}))
    code, _, err = run_cli("simulate", bad, "--out", tmp_path / "t.csv")
    assert code == 2
    # the first field the reader needs after mass, named with the file
    assert err.splitlines() == [f"error: {bad}: missing field 'volume' (see docs/model.md for the vehicle file)"]
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
                "allow_negative_damping": True,  # refused unless intended (issue 32 class 6)
                "fluid": {"density": 1000.0},
            }
        )
    )
    code, _, err = run_cli(
        "simulate",
        bad,
        "--duration",
        "60",
        "--dt",
        "0.001",
        "--initial-velocity",
        "1,0,0,0,0,0",
        "--out",
        tmp_path / "t.csv",
    )
    assert code == 2
    (line,) = err.splitlines()
    found = re.fullmatch(
        r"error: the state became non-finite at t = ([0-9.]+) s \(step (\d+)\); "
        r"check the coefficients' signs and the step size",
        line,
    )
    assert found, line
    t_bad, step = float(found[1]), int(found[2])
    assert t_bad == pytest.approx(step * 0.001, rel=1e-9)
    # closed form: neutrally buoyant, CG = CB, surge only: (m + m_a) u' = 100 u², so
    # u = u0 / (1 - 100 u0 t / 11) is infinite at t* = 11 / 100 = 0.11 s; RK4 overflows within a
    # few steps after it (not before: a run that ignored the added mass would blow up at 0.10 s)
    assert 0.11 <= t_bad <= 0.11 + 5 * 0.001, line
    assert not (tmp_path / "t.csv").exists()
