"""A logged input is held from its row: every stage of the RK4 step starting at the row sees it.

A force table holds a changing input at a doubled node (t_k keeps the value held up to it, t_k +
JUMP·dt the new one); the integrator's first stage of a step reads it ``held_offset(dt)`` after the
step's start, so the step starting at t_k sees the row's value at all four stages while the last
stage of the step ending there still sees the old one (:func:`hydrokit.sysid.model.force_table`).
Before, that first stage (a sixth of the step) saw the old value: an error of the order of dt — on
the generated tanker's zigzags the step check read 0.4 σ at 10 ms and the estimate sat d² ≈ 5 off
the truth for it alone (bench/zigzag_d2.py).

Checked two ways, each against an independent reference:
- the simulation of a run whose rudder steps at its rows, against the same run integrated row by
  row with each row's value held as a constant (a table without jumps), at the same step;
- a fit of a zigzag (sensor noise as logged) of the 3 m ship of :mod:`tests.simulate.test_sysid_surfaces` (its
  truth integrated by DOP853, not by the fit's RK4) at a coarse step against the same fit at an
  eighth of the step.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from tests.simulate.test_sysid_surfaces import FREE, _run, _ship

from hydrokit.sysid.model import (
    free_parameters,
    held_offset,
    prepare_run,
    simulate_run,
    stack_packs,
    values_of,
    with_values,
)


@pytest.fixture(scope="module")
def zigzag() -> tuple[Any, Any]:
    truth = _ship()
    return truth, _run(truth, "z1", 60.0, [5.0, 14.0, 22.0, 33.0, 41.0, 52.0], seed=1)


def test_a_step_starting_at_a_row_sees_the_rows_input(zigzag: tuple[Any, Any]) -> None:
    """sysid's simulation of the run (dt 0.05 s: two steps a row) against the same table integrated
    row interval by row interval, each interval's table starting at the node of its row's new value
    (so no stage can read the old one) and continued from the state reached: equal to 1e-8 of each
    channel's spread (round-off and the JUMP·dt slope: 1e-9); with the first stage read at the step's
    start (the old convention) they are ~1e-4 of the spread apart."""
    from hydrokit.simulate.compiled import no_drive_batch, rk4_batch
    from hydrokit.sysid.model import JUMP, drive_pack, read_columns, vehicle_arrays

    truth, run = zigzag
    dt = 0.05
    prep = prepare_run(run, truth.thrusters, dt, surfaces=truth.surfaces.names)
    packs = stack_packs([truth])
    x0 = np.zeros((1, 12))
    x0[0, 6] = 0.37
    t = np.asarray(run.time, float) - float(run.time[0])
    kcols = read_columns(packs, prep.table.shape[1])
    drive = drive_pack(prep, [truth]) if kcols == prep.table.shape[1] else no_drive_batch(1)
    env = np.zeros((1, 4))

    def by_rows(held: float) -> np.ndarray:
        """Each row interval on its own (``held`` 0: its table has no old value to read)."""
        x, states = x0.copy(), [x0[0].copy()]
        for k in range(t.size - 1):
            a, b = t[k], t[k + 1]
            keep = (prep.table[:, 0] > a + 0.5 * JUMP * dt) & (prep.table[:, 0] <= b + 1e-9)
            seg = prep.table[keep, :kcols].copy()
            seg[:, 0] -= a
            n = int(round((b - a) / dt))
            out, done = np.empty((1, n + 1, 12)), np.empty(1, dtype=np.int64)
            rk4_batch(x, dt, n, 1, False, seg[None], env, vehicle_arrays(packs), drive, out, done, held)
            x = out[:, -1].copy()
            states.append(x[0].copy())
        return np.array(states)

    def whole(held: float) -> np.ndarray:
        n = int(round(t[-1] / dt))
        out, done = np.empty((1, n + 1, 12)), np.empty(1, dtype=np.int64)
        tab = np.ascontiguousarray(prep.table[None, :, :kcols])
        rk4_batch(x0.copy(), dt, n, 1, False, tab, env, vehicle_arrays(packs), drive, out, done, held)
        return out[0, :: int(round(0.1 / dt))]

    ref = by_rows(0.0)
    now, before = whole(held_offset(dt)), whole(0.0)
    for col in (0, 1, 5, 6, 7, 11):  # x, y, ψ, u, v, r
        spread = float(np.std(ref[:, col]))
        assert np.max(np.abs(now[:, col] - ref[:, col])) < 1e-8 * spread, col
        assert np.max(np.abs(before[:, col] - ref[:, col])) > 1e-6 * spread, col  # the check sees the old lag
    # and simulate_run, what the fit calls, is that integration
    pred, _ = simulate_run(prep, packs, x0)
    i = prep.channels.index("psi")
    k0 = sum(ts.size for ts in prep.times[:i])
    rows = np.rint(prep.times[i] / 0.1).astype(int)
    assert np.max(np.abs(pred[0, k0 : k0 + rows.size] - ref[rows, 5])) < 1e-8 * float(np.std(ref[:, 5]))


@pytest.mark.needs_jit(reason="two output-error fits of 7 parameters over 60 s")
def test_the_fit_no_longer_depends_on_its_step(zigzag: tuple[Any, Any]) -> None:
    """The zigzag fitted at dt 0.1 s and at 0.0125 s: the estimates agree to 0.01 σ and
    the step check reads below 0.01 σ (before: 1.1 σ apart, step check 0.41 σ — the sixth of a step
    by which each logged rudder came late is an error of the order of dt)."""
    from hydrokit.sysid.fit import identify

    truth, run = zigzag
    _, params = free_parameters(truth, FREE)
    true = values_of(truth, params)
    base = with_values(truth, params, true * np.array([1.1, 0.9, 1.1, 0.9, 1.1, 0.9, 1.1]))
    coarse = identify(base, [run], FREE, samples=0, dt=0.1)
    fine = identify(base, [run], FREE, samples=0, dt=0.0125, check_step=False)
    assert coarse.step_check < 0.01, coarse.step_check
    assert np.max(np.abs(coarse.values - fine.values) / coarse.sigma) < 0.01
