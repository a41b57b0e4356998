"""``hydrokit simulate --command`` / ``--command-csv``: the vehicle's thrusters driven by commands,
against the closed form of a surge-only response through a first-order rotor lag.

The boat: planar, linear surge damping d = 40 N·s/m and no quadratic one, surge mass
m + m_A = 110 kg, an ideal (force-commanded) thruster on the centreline with a rotor lag
τ = 0.5 s. Under a command F held from t_0 (rotor at rest before), the thrust is
F (1 − e^{−(t − t_0)/τ}) and (m + m_A) u̇ + d u = thrust gives, with k = d / (m + m_A),
u = F/d (1 − e^{−k s}) + A (e^{−s/τ} − e^{−k s}), A = −F / ((m + m_A)(k − 1/τ)), s = t − t_0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

MASS, D, TAU, F = 110.0, 40.0, 0.5, 40.0

BOAT = """
name: boat
mass: 100.0
volume: 0.09756
inertia: [10, 50, 50]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [10, 80, 80, 1, 20, 20]
linear_damping: [40, 40, 0, 0, 0, 30]
quadratic_damping: [0, 0, 0, 0, 0, 0]
dofs: [surge, sway, yaw]
thrusters:
  - {name: main, position: [0, 0, 0], direction: [1, 0, 0], max_thrust: 100, time_constant: 0.5}
"""


def surge(t, t0=0.0):
    """The closed form of the module docstring (0 before t0), m/s."""
    s = np.maximum(np.asarray(t, float) - t0, 0.0)
    k = D / MASS
    a = -F / (MASS * (k - 1.0 / TAU))
    return F / D * (1 - np.exp(-k * s)) + a * (np.exp(-s / TAU) - np.exp(-k * s))


@pytest.fixture
def run(run_cli, tmp_path):
    boat = tmp_path / "boat.yaml"
    boat.write_text(BOAT)
    return lambda *a: run_cli("simulate", boat, "--duration", "10", "--dt", "0.01", *a)


def test_constant_command_through_the_rotor_lag(run, tmp_path):
    """rtol 1e-7: RK4 at dt = 0.01 s on time scales of 0.5 s and 2.75 s errs by ~1e-9 relative."""
    out = tmp_path / "u.csv"
    code, _, err = run("--command", f"main={F}", "--out", out)
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 7], surge(data[:, 0]), rtol=1e-7, atol=1e-9)
    assert data[-1, 7] > 0.9 * F / D  # it got going: the comparison is not of two zeros


def test_command_csv_rows_are_held(run, tmp_path):
    """0 N until t = 2 s, then 40 N held (zero-order hold: no ramp between the rows), rotor from
    rest: the same response 2 s later. Same rtol as above."""
    table = tmp_path / "cmd.csv"
    table.write_text("# the thruster's command, N\ntime,main\n0,0\n2,40\n")
    out = tmp_path / "u.csv"
    code, _, err = run("--command-csv", table, "--out", out)
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 7], surge(data[:, 0], 2.0), rtol=1e-7, atol=1e-9)
    assert np.all(data[data[:, 0] <= 2.0, 7] == 0.0)


def test_command_adds_to_force(run, tmp_path):
    """--force 10 N with --command main=30 is the same run as --command main=40 with the lag on the
    30 N only: u = (10/d)(1 − e^{−k t}) + (30/40) × the closed form (superposition, linear)."""
    out = tmp_path / "u.csv"
    code, _, err = run("--command", "main=30", "--force", "10,0,0,0,0,0", "--out", out)
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    t = data[:, 0]
    want = 10.0 / D * (1 - np.exp(-D / MASS * t)) + 0.75 * surge(t)
    np.testing.assert_allclose(data[:, 7], want, rtol=1e-7, atol=1e-9)
    assert math.isclose(float(data[-1, 7]), float(want[-1]), rel_tol=1e-7)


def test_thrust_reaches_the_terms(run_cli, tmp_path):
    """A term X_T(main) = −0.5 (a thrust deduction written as a term) takes half the thruster's
    lagged thrust back: the surge is half the closed form (the right-hand side is given each
    thruster's thrust, not only τ). Same rtol as above."""
    boat = tmp_path / "deduct.yaml"
    boat.write_text(BOAT + "terms:\n  X_T(main): -0.5\n")
    out = tmp_path / "u.csv"
    code, _, err = run_cli("simulate", boat, "--duration", "10", "--dt", "0.01", "--command", f"main={F}", "--out", out)
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 7], 0.5 * surge(data[:, 0]), rtol=1e-7, atol=1e-9)
    code, _, err = run_cli("simulate", boat, "--command", "main=1", "--integrator", "dop853", "--out", out)
    assert code == 2 and "--integrator dop853 with thruster commands" in err, err


@pytest.mark.parametrize(
    ("args", "csv", "match"),
    [
        (("--command", "stern=3"), None, "command 'stern': the vehicle has thrusters main; expected one of them"),
        (("--command", "main=400"), None, "expected within thruster 'main''s command limits [-100, 100] N"),
        (("--command", "main:4"), None, "--command 'main:4': expected NAME=VALUE"),
        (("--command", "main=4"), "time,main\n0,1\n", "--command and --command-csv: expected one of them"),
        ((), "time,mian\n0,1\n", "unknown column 'mian'; expected time (s) and a column per thruster: main"),
        ((), "time,main\n0,1\n0,2\n", "column 'time' = 0 at row 3 after 0; expected strictly increasing"),
        ((), "time,main\n0,x\n", "row 2, column 'main' = 'x': expected a finite number"),
        ((), "time,main\n0,1\n1,500\n", "row 3, column 'main' = 500 N: expected within thruster 'main''s command"),
    ],
)
def test_bad_commands(run, tmp_path, args, csv, match):
    extra: tuple = ()
    if csv is not None:
        (tmp_path / "c.csv").write_text(csv)
        extra = ("--command-csv", tmp_path / "c.csv")
    out = tmp_path / "bad.csv"
    code, _, err = run(*args, *extra, "--out", out)
    assert code == 2 and match in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_no_thrusters(run_cli, tmp_path):
    boat = tmp_path / "bare.yaml"
    boat.write_text(BOAT.split("thrusters:")[0])
    code, _, err = run_cli("simulate", boat, "--duration", "1", "--command", "main=1", "--out", tmp_path / "o.csv")
    assert code == 2 and "vehicle 'boat' has no thrusters" in err, err
