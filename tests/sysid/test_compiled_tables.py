"""The compiled loops of identification (hydrokit.sysid.kernels, issue #50: bench/sysid.py under
15 s) against a second method: the force table built row by row with the thruster set's own
Python methods (``ThrusterSet.rotor_step`` per row, ``thrust_batch`` of each curve), and the
batch RK4 with one shared force table against the batch RK4 with a copy per vehicle."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

import hydrokit
from hydrokit.io.runlog import RunLog
from hydrokit.sysid.data import generate_runs, hidden_vehicle
from hydrokit.sysid.model import curve_thrusts, force_table, prepare_run, simulate_run, stack_packs


def _python_rotor_and_thrust(run: Any, thrusters: Any, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotor state and thrust (before the thrust limits) at ``nodes`` with the thruster set's
    Python methods: the second method (bench/sysid.py's force tables before the kernels)."""
    t = np.asarray(run.time, float)
    cmd = np.column_stack([np.asarray(run.commands[n], float) for n in thrusters.names])
    c_row = np.empty_like(cmd)
    c_row[0] = np.clip(cmd[0], thrusters.command_min, thrusters.command_max)
    for k in range(1, t.size):
        c_row[k] = thrusters.rotor_step(c_row[k - 1], cmd[k - 1], float(t[k] - t[k - 1]))
    seg = np.clip(np.searchsorted(t, nodes, side="right") - 1, 0, t.size - 1)
    c = thrusters.rotor_step(c_row[seg], cmd[seg], (nodes - t[seg])[:, None])
    at_row = np.isin(nodes, t)
    c[at_row] = c_row[seg[at_row]]
    thrust = np.empty_like(c)
    for i, cv in enumerate(thrusters.curves):
        ci = np.clip(c[:, i], thrusters.command_min[i], thrusters.command_max[i])
        thrust[:, i] = type(cv).thrust_batch([cv] * nodes.size, ci, np.zeros(nodes.size))
    return c, thrust


def test_table_thrusters_force_table_equals_the_row_by_row_python_laws() -> None:
    base = hydrokit.load_vehicle("bluerov2-sysid")
    (run,) = generate_runs(hidden_vehicle(base, 3), 1, 20.0, seed=3)
    th = base.thrusters
    tab = force_table(run, th, 0.01, base.surfaces.names)
    nodes = tab[:, 0]
    _, thrust = _python_rotor_and_thrust(run, th, nodes)
    f = np.clip(thrust, th.f_min, th.f_max)
    m = len(th)
    # the same laws in the same order of operations (the table interpolation, the rotor's exact
    # exponential step), but compiled against Python: two implementations (numba's exp and code
    # generation may round differently on another CPU), so to round-off of the force's scale
    scale = np.abs(f).max()
    np.testing.assert_allclose(tab[:, 7 : 7 + m], f, rtol=1e-12, atol=1e-12 * scale)
    tau = f @ th.configuration_matrix().T
    np.testing.assert_allclose(tab[:, 1:7], tau, rtol=1e-12, atol=1e-12 * np.abs(tau).max())
    assert np.ptp(f) > 10.0  # the run drives the thrusters over most of their range


def test_propeller_curve_thrusts_equal_the_curve_method() -> None:
    from tests.simulate.test_sysid_surfaces import SHIP

    from hydrokit.api import vehicle_from_dict

    ship = vehicle_from_dict(copy.deepcopy(SHIP), "ship")
    (cv,) = ship.thrusters.curves
    rng = np.random.default_rng(5)
    n = rng.uniform(-cv.max_speed, cv.max_speed, 500)
    n[:3] = (0.0, cv.max_speed, -cv.max_speed)
    va = rng.uniform(-1.0, 2.0, 500)
    va[3] = 0.0
    want = np.array([cv.thrust(a, b) for a, b in zip(n, va)])
    got = curve_thrusts(cv, n, va)
    # the curve's own Python law (a compiled D**4 would be a product, an ulp from pow())
    np.testing.assert_array_equal(got, want)
    assert np.ptp(want) > 1.0


def test_shared_table_batch_equals_a_copy_per_vehicle() -> None:
    from hydrokit.simulate.compiled import no_drive_batch, rk4_batch
    from hydrokit.sysid.model import held_offset

    base = hydrokit.load_vehicle("bluerov2-sysid")
    truth = hidden_vehicle(base, 4)
    (run,) = generate_runs(truth, 1, 10.0, seed=4)
    prep = prepare_run(run, base.thrusters, 0.01, surfaces=base.surfaces.names)
    packs = stack_packs([base, truth, hidden_vehicle(base, 5)])
    x0 = np.zeros((3, 12))
    x0[:, 6] = (0.1, 0.2, 0.0)
    pred, done = simulate_run(prep, packs, x0)
    n_steps = int(np.ceil(prep.duration / prep.dt - 1e-9))
    out = np.full((3, n_steps + 1, 12), np.nan)
    done2 = np.empty(3, dtype=np.int64)
    tab = np.ascontiguousarray(np.broadcast_to(prep.table, (3, *prep.table.shape)))
    env = np.zeros((1, 4))
    keys = ("Minv", "Mc", "DL", "DQ", "scal", "t_dof", "t_coef", "t_kind", "t_idx")
    rk4_batch(
        x0,
        prep.dt,
        n_steps,
        1,
        False,
        tab,
        env,
        tuple(packs[k] for k in keys),
        no_drive_batch(3),
        out,
        done2,
        held_offset(prep.dt),
    )
    np.testing.assert_array_equal(done, done2)
    assert np.all(done == n_steps)
    # the prediction at the samples from the copied-table run, interpolated as simulate_run does;
    # numpy's formula against the compiled sampling loop: two implementations, so to round-off
    # of the channel's scale (a wrong table or row is off by far more)
    k = 0
    for c, ts in zip(prep.channels, prep.times):
        col = out[:, :, list(hydrokit.sysid.model.CHANNELS).index(c)]
        pos = ts / prep.dt
        i0 = np.clip(np.floor(pos).astype(int), 0, n_steps - 1)
        w = pos - i0
        want = col[:, i0] * (1 - w) + col[:, i0 + 1] * w
        np.testing.assert_allclose(pred[:, k : k + ts.size], want, rtol=1e-12, atol=1e-12 * np.abs(col).max())
        k += ts.size
    assert np.max(np.abs(pred[1] - pred[0])) > 0  # the vehicles differ


def test_measured_thrust_column_is_held_as_given() -> None:
    base = hydrokit.load_vehicle("bluerov2-sysid")
    th = base.thrusters
    t = np.arange(0.0, 1.0, 0.125)  # binary fractions: the dt/2 grid falls on the rows exactly
    cmds = {n: np.where(t >= 0.5, 0.5, 0.0) for n in th.names[1:]}
    thrusts = {th.names[0]: np.where(t >= 0.25, 7.0, -3.0)}
    run = RunLog("held", "held", t, {"u": (t, np.zeros(t.size))}, cmds, thrusts=thrusts)
    tab = force_table(run, th, 0.25, base.surfaces.names)
    f0 = tab[:, 7]
    # held: −3 N up to the row at 0.25 s itself, 7 N from just after it
    np.testing.assert_array_equal(f0[tab[:, 0] <= 0.25], -3.0)
    np.testing.assert_array_equal(f0[tab[:, 0] > 0.25], 7.0)
    # the other thrusters follow their rotor lag (τ = 0.1 s) from 0 at the step at 0.5 s:
    # the table curve at c = 0.5 (1 − e^(−Δt/τ)) (closed form of the lag, then the table)
    after = tab[:, 0] > 0.5
    dt_after = tab[after, 0] - 0.5
    c = 0.5 * (1.0 - np.exp(-dt_after / 0.1))
    cv = th.curves[1]
    want = np.interp(c, cv.commands, cv.thrusts)
    np.testing.assert_allclose(tab[after, 8], want, rtol=1e-12, atol=1e-12)
    assert np.all(tab[~after, 8] == 0.0) and tab[-1, 8] > 1.0


def _problem(n_runs: int = 2, duration: float = 15.0) -> tuple[Any, np.ndarray, np.ndarray]:
    from hydrokit.sysid.data import HIDDEN
    from hydrokit.sysid.model import free_parameters, values_of
    from hydrokit.sysid.problem import Problem
    from hydrokit.sysid.smooth import initial_noise, smooth_run

    base = hydrokit.load_vehicle("bluerov2-sysid")
    runs = generate_runs(hidden_vehicle(base, 6), n_runs, duration, seed=6)
    veh, params = free_parameters(base, list(HIDDEN)[:4])
    sm = [smooth_run(r) for r in runs]
    preps = [prepare_run(r, veh.thrusters, 0.01, surfaces=veh.surfaces.names) for r in runs]
    est = [np.array([i for i in range(12) if s.known[i]], dtype=int) for s in sm]
    problem = Problem(veh, params, preps, [s.at(s.time[0]) for s in sm], est, dict(initial_noise(sm)))
    theta = values_of(veh, params)
    z = np.concatenate([theta, *[s.at(s.time[0])[e] for s, e in zip(sm, est)]])
    scale = np.concatenate([np.abs(theta), np.full(z.size - theta.size, 0.01)])
    return problem, z, scale


def test_jacobian_equals_the_residuals_of_each_nudged_variable() -> None:
    problem, z, scale = _problem()
    r, J, ok = problem.evaluate(z, scale, True)
    assert ok and J is not None and J.shape == (r.size, z.size)
    # second method: each column from two evaluations of the residuals alone, z and z with the
    # variable nudged by 1e-6 of its scale (the same forward difference, rounded differently:
    # the residuals are ~1e2, their difference ~1e-4, so ~1e-12 relative to a column's size)
    for k in range(z.size):
        z2 = z.copy()
        z2[k] += 1e-6 * scale[k]
        r2, _, ok2 = problem.evaluate(z2, scale, False)
        assert ok2
        col = (r2 - r) / 1e-6
        np.testing.assert_allclose(J[:, k], col, rtol=0, atol=1e-6 * max(np.max(np.abs(col)), 1e-3))
    assert np.all(np.abs(J).max(axis=0) > 0)  # every variable moves some residual


def test_steps_a_diverged_vehicle_did_not_take_are_nan() -> None:
    from hydrokit.model.uncertainty import with_coefficients

    base = hydrokit.load_vehicle("bluerov2-sysid")
    (run,) = generate_runs(hidden_vehicle(base, 7), 1, 5.0, seed=7)
    prep = prepare_run(run, base.thrusters, 0.01, surfaces=base.surfaces.names)
    wild = with_coefficients(base, {"linear_damping.surge": -1e7})  # energy fed in: u grows without bound
    x0 = np.zeros((2, 12))
    x0[:, 6] = 1.0
    pred, done = simulate_run(prep, stack_packs([base, wild]), x0)
    n_steps = int(np.ceil(prep.duration / prep.dt - 1e-9))
    assert done[0] == n_steps and np.all(np.isfinite(pred[0]))
    assert done[1] < n_steps
    # the samples after the last step taken read no leftover memory: NaN
    late = np.concatenate([ts for ts in prep.times]) > (done[1] + 1) * prep.dt
    assert np.any(late) and np.all(np.isnan(pred[1][late]))


def test_table_columns_read_only_as_far_as_the_vehicle_needs() -> None:
    from tests.simulate.test_sysid_propeller_rudder import race_ship

    from hydrokit.sysid.model import read_columns

    rov = hydrokit.load_vehicle("bluerov2-sysid")
    # no surfaces, no T()/n() terms: the six forces only (the shared-table test above compares
    # such a cut table's simulation with the whole table's)
    assert read_columns(stack_packs([rov]), 23) == 7
    # a race rudder (a fin in the propeller's slipstream) and a T()·δ term read the thrust column
    ship = race_ship()
    assert read_columns(stack_packs([ship]), 10) == 10
    assert read_columns({"t_kind": np.zeros((0, 5), np.int64)}, 9) == 9  # vehicles not at hand
