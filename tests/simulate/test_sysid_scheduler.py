"""``hydrokit sysid --scheduler`` (issue #44): the runs of every iteration are independent tasks;
on a Dask scheduler the fit gives the same estimates as in this process."""

from __future__ import annotations

import numpy as np
import pytest

import hydrokit
from hydrokit.sysid.data import generate_runs, hidden_vehicle
from hydrokit.sysid.fit import identify


def _runs():
    base = hydrokit.load_vehicle("bluerov2-sysid")
    return base, generate_runs(hidden_vehicle(base, 4), 2, 1.5, seed=4, dt=0.01)


@pytest.mark.needs_jit(reason="two fits, one of them through a Dask worker (64 s as interpreted Python)")
def test_fit_on_a_dask_scheduler_equals_the_local_fit():
    distributed = pytest.importorskip("dask.distributed")
    base, runs = _runs()
    free = ["added_mass.yaw", "quadratic_damping.yaw"]
    here = identify(base, runs, free, dt=0.02, samples=0, check_step=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as c:
        there = identify(base, runs, free, dt=0.02, samples=0, check_step=False, scheduler=c.scheduler_address)
    # the same arithmetic on the same inputs, only run elsewhere: equal to the last bit
    np.testing.assert_array_equal(there.values, here.values)
    np.testing.assert_array_equal(there.sigma, here.sigma)


def test_unreachable_scheduler_is_one_line(tmp_path):
    from hydrokit.errors import InputError

    base, runs = _runs()
    with pytest.raises(InputError, match=r"--scheduler = 'tcp://127.0.0.1:1': cannot reach a Dask scheduler"):
        identify(base, runs[:1], ["added_mass.yaw"], dt=0.02, samples=0, scheduler="tcp://127.0.0.1:1")
