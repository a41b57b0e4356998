"""The wind-load law (model/wind.py) against hand calculations, and a ship drifting under a steady
beam wind against the closed-form balance of the wind's side force and the hull's sway damping."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.vehicle import load_vehicle
from hydrokit.model.dynamics import environment_table, vehicle_dynamics
from hydrokit.model.wind import BLENDERMANN_1994, make_wind
from hydrokit.simulate.compiled import make_dynamics
from hydrokit.simulate.driver import simulate

A_F, A_L, L = 0.135, 0.520, 3.0

SHIP = """
name: windship
gravity: 9.81
fluid: {density: 1000.0}
dofs: [surge, sway, yaw]
mass: 100.0
volume: 0.1
inertia: [10, 60, 60]
center_of_gravity: [0, 0, 0]
center_of_buoyancy: [0, 0, 0]
added_mass: [5, 50, 0, 0, 0, 30]
linear_damping: [20, 40, 0, 0, 0, 15]
quadratic_damping: [10, 80, 0, 0, 0, 5]
"""

BLENDERMANN = """wind:
  frontal_area: 0.135
  lateral_area: 0.52
  length: 3.0
  model: blendermann1994
  vessel: tanker_loaded
"""


def _ship(tmp_path: Path, wind: str = BLENDERMANN, name: str = "ship.yaml") -> Path:
    p = tmp_path / name
    p.write_text(SHIP + wind)
    return p


def test_blendermann_by_hand_at_a_few_angles() -> None:
    """Blendermann (1994) as tabulated in MSS blendermann94.m (Fossen 2021 §10.1), loaded tanker: CD_t 0.70, CD_l,AF 0.90
    (bow) and 0.55 (stern), δ 0.40; each coefficient written out by hand for one side (γ = 0, 45°,
    90°, 135°, 180°), mirrored for the other."""
    w = make_wind(A_F, A_L, L, model="blendermann1994", vessel="tanker_loaded", s_L=0.3)
    cdt, bow, stern, delta = 0.70, 0.90, 0.55, 0.40
    for deg in (0.0, 45.0, 90.0, 135.0, 180.0):
        a = math.radians(deg)
        cd = bow if deg <= 90 else stern
        den = 1 - 0.5 * delta * (1 - cd * A_F / A_L / cdt) * math.sin(2 * a) ** 2
        cx, cy = -cd * math.cos(a) / den, -cdt * math.sin(a) / den
        cn = cy * (0.3 / L - 0.18 * (a - math.pi / 2))
        # rtol 1e-12: the same arithmetic, in another order
        np.testing.assert_allclose(w.coefficients(a), (cx, cy, cn), rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(w.coefficients(-a), (cx, -cy, -cn), rtol=1e-12, atol=1e-15)
    # physical signs: head wind pushes aft, a wind from starboard pushes to port and, forward of
    # the beam, turns the bow to port (away from the wind)
    cx0, _, _ = w.coefficients(0.0)
    _, cy90, _ = w.coefficients(math.pi / 2)
    _, _, cn45 = w.coefficients(math.pi / 4)
    assert cx0 < 0 and cy90 < 0 and cn45 < 0


def test_wrench_from_the_relative_wind() -> None:
    """X = ½ρ V² A_F C_X, Y = ½ρ V² A_L C_Y, N = ½ρ V² A_L L C_N at γ_R = atan2(v_R, u_R)."""
    w = make_wind(A_F, A_L, L, density=1.2, model="blendermann1994", vessel="ferry")
    u_r, v_r = 0.8, 1.1
    g, v2 = math.atan2(v_r, u_r), u_r**2 + v_r**2
    cx, cy, cn = w.coefficients(g)
    q = 0.5 * 1.2 * v2
    want = [q * A_F * cx, q * A_L * cy, 0, 0, 0, q * A_L * L * cn]
    np.testing.assert_allclose(w.wrench(u_r, v_r), want, rtol=1e-12)
    assert BLENDERMANN_1994["ferry"] == w.parameters


def test_table_interpolates_and_mirrors() -> None:
    w = make_wind(
        A_F,
        A_L,
        L,
        angles=np.radians([0, 90, 180]),
        C_X=[-0.8, 0.0, 0.6],
        C_Y=[0.0, -0.9, 0.0],
        C_N=[0.0, -0.1, 0.0],
    )
    # halfway between rows: the mean of the rows
    np.testing.assert_allclose(w.coefficients(math.radians(45)), (-0.4, -0.45, -0.05), rtol=1e-12)
    np.testing.assert_allclose(w.coefficients(math.radians(-135)), (0.3, 0.45, 0.05), rtol=1e-12)
    full = make_wind(
        A_F, A_L, L, angles=np.radians([-180, 0, 180]), C_X=[1.0, -1.0, 1.0], C_Y=[0, 0.2, 0], C_N=[0, 0, 0]
    )
    np.testing.assert_allclose(full.coefficients(math.radians(-90)), (0.0, 0.1, 0.0), atol=1e-12)


def test_bad_wind_fields_name_the_field() -> None:
    with pytest.raises(InputError, match=r"wind\.coefficients\.angle_deg.*0 to 180"):
        make_wind(A_F, A_L, L, angles=np.radians([0, 90]), C_X=[0, 0], C_Y=[0, 0], C_N=[0, 0])
    with pytest.raises(InputError, match=r"wind\.vessel.*tanker_loaded"):
        make_wind(A_F, A_L, L, model="blendermann1994", vessel="tanker")
    with pytest.raises(InputError, match=r"wind\.lateral_area"):
        make_wind(A_F, -1.0, L)


def test_vehicle_file_wind_block(tmp_path: Path) -> None:
    table = """wind:
  frontal_area: 0.135
  lateral_area: 0.52
  length: 3.0
  density: 1.2
  coefficients: {angle_deg: [0, 90, 180], C_X: [-0.8, 0, 0.6], C_Y: [0, -0.9, 0], C_N: [0, -0.1, 0]}
"""
    v = load_vehicle(_ship(tmp_path, table))
    assert v.wind is not None and v.wind.model == "table" and v.wind.density == 1.2
    np.testing.assert_allclose(v.wind.coefficients(math.pi / 2), (0.0, -0.9, -0.1), atol=1e-12)
    bad = table.replace("C_N: [0, -0.1, 0]", "C_N: [0, -0.1]")
    with pytest.raises(InputError, match=r"wind\.coefficients\.C_N.*expected 3"):
        load_vehicle(_ship(tmp_path, bad, "bad.yaml"))
    with pytest.raises(InputError, match=r"wind\.colour"):
        load_vehicle(_ship(tmp_path, BLENDERMANN + "  colour: red\n", "bad2.yaml"))


def test_compiled_and_numpy_agree_with_wind(tmp_path: Path) -> None:
    v = load_vehicle(_ship(tmp_path))
    env = environment_table([0.1, -0.05, 0.0], [[0.0, 1.5, 0.3], [10.0, 2.5, 1.9]])
    f, g = vehicle_dynamics(v, env), make_dynamics(v, env)
    rng = np.random.default_rng(3)
    for t in (0.0, 4.0, 12.0):
        x = rng.normal(size=12) * 0.4
        tau = rng.normal(size=6)
        a = f(t, x, tau)
        # the wind moves the accelerations: compare to the model without it too
        assert not np.allclose(a, vehicle_dynamics(v, [0.1, -0.05, 0.0])(t, x, tau))
        np.testing.assert_allclose(g(t, x, tau), a, rtol=1e-12, atol=1e-13)


def test_beam_wind_drift_balances_sway_damping(tmp_path: Path) -> None:
    """At rest, heading north, wind V from the east (γ_R = 90°): Blendermann's C_Y = −CD_t and
    C_X = C_N = 0 (s_L = 0), so the ship drifts west at v < 0 with
    −d v + d₂ v² = CD_t ½ρ_a A_L (V + v)² (linear d and quadratic d₂ sway damping)."""
    v = load_vehicle(_ship(tmp_path))
    V = 2.0
    k = 0.70 * 0.5 * 1.225 * A_L
    d, d2 = 40.0, 80.0
    roots = np.roots([d2 - k, -(d + 2 * k * V), -k * V * V])
    drift = float(roots[(roots < 0) & (roots > -V)][0])
    env = environment_table(None, (V, math.pi / 2))
    for integrator in ("rk4", "rk4-numpy"):
        tr = simulate(v, 150.0, 0.05, [0] * 6, [0] * 6, [0] * 6, env, integrator)
        # rtol 1e-6: the sway time constant is ~ (m + m_A)/d = 3.8 s, 150 s is ~40 of them
        np.testing.assert_allclose(tr.nu[-1][1], drift, rtol=1e-6)
        assert abs(tr.nu[-1][0]) < 1e-12 and abs(tr.nu[-1][5]) < 1e-12
    # the same wind on a vehicle with no wind model is refused, not ignored
    plain = tmp_path / "plain.yaml"
    plain.write_text(SHIP)
    with pytest.raises(InputError, match="no wind model"):
        vehicle_dynamics(load_vehicle(plain), env)


def test_the_fit_flies_each_run_in_its_logged_wind(tmp_path: Path) -> None:
    """A run logged with wind_speed/wind_direction columns: sysid's simulation of it (prepare_run,
    simulate_run) reproduces the trajectory the driver flew in the same wind, to the 9 digits of
    the run file; without the wind it misses by centimetres per second."""
    from hydrokit.api import load_vehicle as load_with_thrusters
    from hydrokit.io.runlog import read_run, run_csv
    from hydrokit.sysid.model import prepare_run, simulate_run, stack_packs

    ship = _ship(tmp_path, BLENDERMANN + "thrusters:\n  - {name: main, position: [0, 0, 0], direction: [1, 0, 0], "
                 "max_thrust: 50}\n")  # fmt: skip
    v = load_with_thrusters(ship)
    t = np.round(np.arange(0.0, 20.0 + 1e-9, 0.1), 9)
    speed, direction = 1.0 + 0.5 * np.sin(0.3 * t), 1.0 + 0.01 * t
    env = environment_table(None, np.column_stack([t, speed, direction]))
    tr = simulate(v, 20.0, 0.01, [5.0, 0, 0, 0, 0, 0], [0] * 6, [0.3, 0, 0, 0, 0, 0], env)
    rows = {"u": tr.nu[::10, 0], "v": tr.nu[::10, 1], "r": tr.nu[::10, 5], "psi": tr.eta[::10, 5]}
    lines = run_csv(t, rows, {"main": np.full(t.size, 5.0)}).splitlines()
    lines[0] += ",wind_speed,wind_direction"
    lines[1:] = [f"{ln},{s:.12g},{d:.12g}" for ln, s, d in zip(lines[1:], speed, direction)]
    path = tmp_path / "run.csv"
    path.write_text("\n".join(lines) + "\n")
    prep = prepare_run(read_run(path, ["main"]), v.thrusters, 0.01)
    x0 = np.concatenate([tr.eta[0], tr.nu[0]])[None]
    pred, done = simulate_run(prep, stack_packs([v]), x0)
    assert done[0] == 2000
    # 1e-8: the run file's 9 significant digits of states of ~0.3
    np.testing.assert_allclose(pred[0], prep.measured, rtol=0, atol=1e-8)
    calm = prepare_run(read_run(path, ["main"]), v.thrusters, 0.01)
    object.__setattr__(calm, "env", None)
    assert np.max(np.abs(simulate_run(calm, stack_packs([v]), x0)[0][0] - prep.measured)) > 0.01
