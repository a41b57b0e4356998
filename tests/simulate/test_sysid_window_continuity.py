"""Windows tied by continuity (issue #48 item 3, ``window_continuity``): a heavy weight closes
the joins, and the windowed fit then becomes the whole-run fit (single shooting)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from tests.simulate.test_sysid_surfaces import FREE, _ship

from hydrokit.errors import InputError
from hydrokit.sysid.model import free_parameters, values_of, with_values
from hydrokit.sysid.ship import ship_runs
from hydrokit.sysid.window import check_continuity


def test_continuity_weight_is_checked() -> None:
    assert check_continuity(0) == 0.0 and check_continuity("2.5") == 2.5
    for bad in ("-1", "abc", "nan", "inf", None):
        with pytest.raises(InputError, match=r"--window-continuity: window continuity .* expected a weight ≥ 0"):
            check_continuity(bad)


@pytest.mark.needs_jit(reason="three output-error fits of 7 parameters over 2 × 40 s of a ship's runs")
def test_continuity_closes_the_joins_and_gives_the_whole_run_fit() -> None:
    """With every measured state's jump at a join weighted 10⁴ (a jump of 0.01 σ costs one
    measurement σ), the windows form one trajectory per run from one free initial state: the
    whole-run problem. Its estimates must then agree with the whole-run fit's to a fraction of σ
    (0.5 σ: the two stop on different rules, :mod:`hydrokit.sysid.lm`) and its σ
    within 10 %; without the joins the largest jump is tens of times larger."""
    from hydrokit.sysid.fit import identify

    truth = _ship()
    runs = ship_runs(truth, 2, 40.0, seed=11, dt=0.01)
    _, params = free_parameters(truth, FREE)
    true = values_of(truth, params)
    base = with_values(truth, params, true * np.array([1.2, 0.8, 1.2, 0.8, 1.2, 0.85, 1.15]))
    kw: dict[str, Any] = {"samples": 0, "check_step": False, "dt": 0.05}
    whole = identify(base, runs, FREE, window=None, **kw)
    free = identify(base, runs, FREE, window=20.0, **kw)
    tied = identify(base, runs, FREE, window=20.0, window_continuity=1e4, **kw)
    assert whole.windows == {}
    assert free.windows["count"] == tied.windows["count"] == 4 and tied.windows["continuity"] == 1e4
    assert any("tied at their joins by continuity (weight 10000)" in w for w in tied.warnings)
    assert tied.windows["largest_jump_sigma"] < 0.01
    assert free.windows["largest_jump_sigma"] > 10 * tied.windows["largest_jump_sigma"]
    z = (tied.values - whole.values) / whole.sigma
    assert np.all(np.abs(z) < 0.5), z
    np.testing.assert_allclose(tied.sigma, whole.sigma, rtol=0.1)
