"""Grid convergence (Richardson/GCI) and force-history judgement, against closed forms and a printed example."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.cfd.gci import grid_study
from hydrokit.cfd.history import (
    autocorrelation_time,
    converged,
    judge,
    read_all,
    read_dat,
    read_force_parts,
    read_forces,
    remaining_change,
)


def test_richardson_recovers_an_exact_second_order_series():
    # S(h) = S0 + C h², h = 1, √2, 2: p = 2, S_ext = S0 exactly; asymptotic, so F_s = 1.25
    r = math.sqrt(2.0)
    s = [3.0 + 0.4 * h**2 for h in (1.0, r, r * r)]
    g = grid_study(*s, r21=r)
    assert g.kind == "monotonic"
    assert g.order == pytest.approx(2.0, abs=1e-12)
    assert g.extrapolated == pytest.approx(3.0, abs=1e-12)
    assert g.safety == 1.25
    assert g.gci == pytest.approx(1.25 * abs(s[1] - s[0]) / (r**2 - 1), rel=1e-12)


def test_first_order_convergence_is_outside_the_asymptotic_range():
    r = math.sqrt(2.0)
    g = grid_study(*[1.0 - 0.2 * h for h in (1.0, r, 2.0)], r21=r)
    assert g.order == pytest.approx(1.0, abs=1e-12)
    assert g.safety == 3.0
    assert g.extrapolated == pytest.approx(1.0, abs=1e-12)


def test_celik_2008_worked_example_with_unequal_ratios():
    # Celik et al. (2008) J. Fluids Eng. 130:078001, Table 1, φ = dimensionless reattachment length:
    # r21 = 1.5, r32 = 1.333, φ1..3 = 6.063, 5.972, 5.863 → p = 1.53, φ_ext = 6.1685, GCI_fine 2.17 % (F_s 1.25)
    g = grid_study(6.063, 5.972, 5.863, r21=1.5, r32=1.333)
    assert g.order == pytest.approx(1.53, abs=0.01)
    assert g.extrapolated == pytest.approx(6.1685, abs=0.002)
    # hydrokit takes F_s = 3 outside |p/2 − 1| ≤ 0.1; the paper always 1.25
    assert g.gci / 6.063 * 1.25 / g.safety == pytest.approx(0.0217, abs=0.0003)


def test_oscillatory_and_diverging_triplets_are_named_not_extrapolated():
    osc = grid_study(1.0, 1.1, 0.95, r21=1.4)
    assert osc.kind == "oscillatory" and math.isnan(osc.extrapolated)
    assert osc.gci == pytest.approx(0.5 * (1.1 - 0.95))
    div = grid_study(1.0, 1.2, 1.3, r21=1.4)  # the change grows as the grid is refined
    assert div.kind == "diverging" and div.gci == pytest.approx(3 * 0.2)
    same = grid_study(2.0, 2.0, 2.0, r21=1.4)
    assert same.kind == "converged" and same.gci == 0
    with pytest.raises(ValueError, match="expected both > 1"):
        grid_study(1, 2, 3, r21=0.7)


def _loads(x: np.ndarray) -> np.ndarray:
    out = np.zeros((len(x), 6))
    out[:, 0] = x
    out[:, 1] = 0.01 * x
    return out


def test_converged_needs_the_window_and_the_minimum_and_is_relative():
    n = np.arange(400)
    x = -10.0 * (1 + np.exp(-n / 20))  # settles to −10 N
    vals = _loads(x)
    assert converged(vals, window=100, min_iterations=150, tolerance=1e-3, length=1.0)
    assert not converged(vals[:140], window=100, min_iterations=150, tolerance=1e-3, length=1.0)
    # the same history scaled by 1e-6 (a tiny model) is judged the same: relative, not absolute
    assert converged(vals * 1e-6, window=100, min_iterations=150, tolerance=1e-3, length=1.0)
    # still moving by 2 % over the window: not converged
    assert not converged(vals[:120], window=60, min_iterations=50, tolerance=1e-3, length=1.0)


def test_autocorrelation_time_of_ar1_is_its_closed_form():
    rng = np.random.default_rng(1)
    phi = 0.8
    e = rng.standard_normal(200_000)
    x = np.empty_like(e)
    x[0] = 0
    for i in range(1, len(e)):
        x[i] = phi * x[i - 1] + e[i]
    # τ = (1 + φ)/(1 − φ) = 9 for AR(1); white noise gives 1
    assert autocorrelation_time(x) == pytest.approx(9.0, rel=0.08)
    assert autocorrelation_time(e) == pytest.approx(1.0, abs=0.1)
    assert autocorrelation_time(np.ones(100)) == 1.0


def test_an_oscillating_history_is_averaged_with_a_correlated_sigma():
    it = np.arange(2000)
    x = -5.0 + 0.3 * np.sin(2 * np.pi * it / 37.0)
    j = judge(_loads(x), window=100, min_iterations=100, tolerance=1e-3, length=1.0)
    assert j.status == "averaged"
    assert j.mean[0] == pytest.approx(-5.0, abs=0.01)
    # σ of a mean over a correlated series: larger than s/√n of independent samples
    naive = x[1000:].std(ddof=1) / math.sqrt(1000)
    assert j.std[0] > naive
    assert j.tau > 1


def test_a_drifting_history_is_not_converged_and_its_sigma_covers_the_drift():
    x = np.linspace(-5.0, -6.0, 1000)
    j = judge(_loads(x), window=100, min_iterations=100, tolerance=1e-3, length=1.0)
    assert j.status == "not converged"
    # quarters of the last half differ by 0.25 N: σ ≥ half of it
    assert j.std[0] >= 0.12


def test_a_settled_history_is_converged_with_the_window_half_range():
    x = -2.0 + 1e-4 * np.cos(np.arange(500))
    j = judge(_loads(x), window=100, min_iterations=100, tolerance=1e-3, length=1.0)
    assert j.status == "converged" and j.samples == 100
    last = x[-100:]
    assert j.std[0] == pytest.approx(0.5 * (last.max() - last.min()))


def test_a_creeping_history_is_converged_with_the_change_still_to_come_as_its_sigma():
    # x_n = L + A qⁿ: window means step geometrically by r = q^W, so Δ r/(1 − r) is exactly the
    # distance of the last window's mean from the limit L (closed form)
    q, W, n = 0.998, 100, np.arange(1500)
    x = -10.0 - 2.0 * q**n
    j = judge(_loads(x), window=W, min_iterations=100, tolerance=5e-3, length=1.0)
    assert j.status == "converged"
    assert j.std[0] == pytest.approx(abs(x[-W:].mean() + 10.0), rel=1e-6)
    half_range = 0.5 * np.ptp(x[-W:])
    assert j.std[0] > 4 * half_range  # the window's range alone understates it
    # Y = 0.01 X creeps the same way: its own remainder
    assert j.std[1] == pytest.approx(0.01 * j.std[0], rel=1e-6)
    assert remaining_change(_loads(x)[: 2 * W], W)[0] == 0.0  # fewer than three windows: no estimate
    # a creep slower than r = 0.95 per window is extrapolated with r = 0.95: 19 last steps
    slow = -10.0 - 2.0 * 0.9996 ** np.arange(1500)  # r = 0.9996^100 = 0.961
    means = [slow[k : k + W].mean() for k in (1300, 1400)]
    assert remaining_change(_loads(slow), W)[0] == pytest.approx(19 * abs(means[1] - means[0]), rel=1e-9)


def test_noise_about_a_settled_value_adds_no_creep():
    rng = np.random.default_rng(7)
    x = -2.0 + 1e-3 * rng.standard_normal(600)
    j = judge(_loads(x), window=100, min_iterations=100, tolerance=5e-3, length=1.0)
    assert j.status == "converged"
    assert j.std[0] == pytest.approx(0.5 * np.ptp(x[-100:]))
    # growing steps (a history that speeds up) are not extrapolated either
    y = -2.0 - 1e-4 * np.exp(np.arange(600) / 150.0)
    assert remaining_change(_loads(y), 100)[0] == 0.0


def _counter_moving(n: int, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """A total of −10 N that is flat to 1e-9 while its parts trade ``rate`` N per iteration:
    pressure falls, friction climbs (the Myring wedge at Re_L 1e7 on its finest grid)."""
    it = np.arange(n, dtype=float)
    pressure = -1.0 + rate * it
    viscous = -9.0 - rate * it
    total = pressure + viscous
    parts = np.zeros((n, 6))
    parts[:, 0], parts[:, 3] = pressure, viscous
    return _loads(total), parts


def test_a_total_flat_because_its_parts_trade_is_not_converged():
    loads, parts = _counter_moving(600, 1e-3)  # each part moves 0.1 N = 1 % of |F| per window
    kw = dict(window=100, min_iterations=100, tolerance=5e-4, length=1.0)
    assert converged(loads, **kw)  # the total alone looks settled
    assert not converged(loads, parts=parts, **kw)
    # parts that move less than the tolerance (5e-4 × 10 N = 5 mN per window) pass
    slow_loads, slow_parts = _counter_moving(600, 4e-5)
    assert converged(slow_loads, parts=slow_parts, **kw)
    # a finished run judged the same way: the trade goes on across the last half, so the case
    # is not converged (it was "converged" on the total)
    assert judge(loads, **kw).status == "converged"
    assert judge(loads, parts=parts, **kw).status == "not converged"
    assert judge(slow_loads, parts=slow_parts, **kw).status == "converged"
    with pytest.raises(ValueError, match="one per load row"):
        converged(loads, parts=parts[:-1], **kw)
    # the parts are forces: judged against |F| (5 mN here), not the moments' |F|·L (50 mN on a
    # 10 m body), so a 10 mN trade per window still holds a long body's case
    long = dict(kw, length=10.0)
    mid_loads, mid_parts = _counter_moving(600, 1e-4)
    assert not converged(mid_loads, parts=mid_parts, **long)
    assert judge(mid_loads, parts=mid_parts, **long).status == "not converged"


FORCE_DAT = """# Force
# CofR          : (0.00000000e+00 0.00000000e+00 0.00000000e+00)
#
# Time          \t(total_x total_y total_z)\t(pressure_x pressure_y pressure_z)\t(viscous_x viscous_y viscous_z)
1\t(-8.4e+00 3.5e-03 3.7e-03)\t(-5.4e+00 3.4e-03 3.6e-03)\t(-3.0e+00 1.0e-04 1.0e-04)
2\t(-4.3e-01 -5.5e-05 -6.1e-05)\t(-2.0e-01 -3.6e-05 -4.1e-05)\t(-2.3e-01 -1.9e-05 -2.0e-05)
3\t(-4.3e-01 -5.5e-05"""


def test_force_files_of_openfoam_v1912_are_read_without_their_unfinished_last_line(tmp_path):
    d = tmp_path / "forces" / "0"
    d.mkdir(parents=True)
    (d / "force.dat").write_text(FORCE_DAT)
    (d / "moment.dat").write_text(FORCE_DAT.replace("Force", "Moment"))
    rows = read_dat(d / "force.dat")
    assert rows.shape == (2, 10)
    it, loads = read_forces(tmp_path / "forces")
    assert list(it) == [1.0, 2.0]
    assert loads[1, 0] == pytest.approx(-0.43) and loads[0, 1] == pytest.approx(3.5e-3)
    assert loads[1, 3] == pytest.approx(-0.43)  # the moment file's total_x
    assert read_forces(tmp_path / "missing")[1].shape == (0, 6)
    pressure, viscous = read_force_parts(tmp_path / "forces")
    assert pressure.shape == viscous.shape == (2, 3)
    assert pressure[1, 0] == pytest.approx(-0.20) and viscous[1, 0] == pytest.approx(-0.23)
    assert pressure + viscous == pytest.approx(loads[:, :3])  # OpenFOAM's total is their sum
    assert read_force_parts(tmp_path / "missing")[0].shape == (0, 3)
    # one reading gives all four on the same rows
    it2, loads2, p2, v2 = read_all(tmp_path / "forces")
    assert list(it2) == [1.0, 2.0] and loads2 == pytest.approx(loads) and p2 + v2 == pytest.approx(loads2[:, :3])
