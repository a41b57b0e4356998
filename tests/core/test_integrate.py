"""The one RK4 law (core/integrate.py), as Python on arrays and compiled, against exp(λh).

ẋ = λx has the exact step x e^{λh}; one classical RK4 step multiplies by the degree-4 Taylor
polynomial of e^{λh}, so its local error is x (λh)⁵/5! + O(h⁶) (Hairer, Nørsett & Wanner 1993,
§II.1: RK4 is of order 4, local error O(h⁵)). The compiled integrators (simulate/compiled.py,
simulate/transport.py) call the compiled law; the numpy rk4_step calls the law on arrays.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

from hydrokit.core.integrate import rk4_combine_into, rk4_stage, rk4_stage_into, rk4_update
from hydrokit.simulate import compiled, transport
from hydrokit.simulate.compiled import rk4_combine_compiled, rk4_stage_compiled
from hydrokit.simulate.integrators import rk4_step


def _compiled_step(lam: np.ndarray, x0: np.ndarray, h: float) -> tuple[np.ndarray, bool]:
    """One RK4 step of ẋ = λx (element by element) driven through the compiled stage laws."""
    x = x0.copy()
    tmp = np.empty_like(x)
    k1 = lam * x
    rk4_stage_compiled(x, k1, 0.5 * h, tmp)
    k2 = lam * tmp
    rk4_stage_compiled(x, k2, 0.5 * h, tmp)
    k3 = lam * tmp
    rk4_stage_compiled(x, k3, h, tmp)
    k4 = lam * tmp
    finite = rk4_combine_compiled(x, k1, k2, k3, k4, h)
    return x, finite


@pytest.mark.parametrize("lam", [-1.7, 0.9, -40.0])
def test_rk4_local_error_is_the_fifth_order_term_of_exp(lam: float) -> None:
    x0 = 1.3
    for h in (0.02, 0.01, 0.005):
        if abs(lam * h) > 0.25:
            continue
        exact = x0 * math.exp(lam * h)
        z = lam * h
        # the leading term of the local error: x0 z⁵/120 (the next is z⁶/720, smaller by z/6)
        leading = x0 * z**5 / 120.0
        py = rk4_step(lambda t, x: lam * x, 0.0, np.array([x0]), h)[0]
        cx, finite = _compiled_step(np.array([lam]), np.array([x0]), h)
        assert finite
        for got in (py, cx[0]):
            err = exact - got
            # rtol: the O(z⁶) remainder is |z|/6 ≤ 4 % of the leading term at |z| ≤ 0.25; plus
            # rounding of x0 (1e-16) which is far below |leading| ≥ 1e-14 here
            assert err == pytest.approx(leading, rel=abs(z) / 6 * 1.2 + 1e-3)


def test_rk4_error_falls_as_h_to_the_fifth() -> None:
    lam, x0 = -2.3, 0.7
    errs = []
    for h in (0.04, 0.02):
        got = rk4_step(lambda t, x: lam * x, 0.0, np.array([x0]), h)[0]
        errs.append(abs(x0 * math.exp(lam * h) - got))
    # halving h divides the local error by 2⁵ = 32 (to the first neglected order, |λh|/6)
    assert errs[0] / errs[1] == pytest.approx(32.0, rel=0.05)


def test_compiled_law_equals_the_python_law() -> None:
    rng = np.random.default_rng(11)
    x, k1, k2, k3, k4 = (rng.normal(size=13) * 10.0 ** rng.uniform(-3, 3, 13) for _ in range(5))
    dt = 0.0137
    # compiled, Python loop and numpy arrays are three implementations of the law (numba may fuse
    # a multiply-add into an FMA on another CPU): they agree to a few ulps of the terms summed,
    # not bit for bit; a wrong weight or a swapped stage is off by far more
    ulps = 4 * np.finfo(float).eps
    out_c, out_p = np.empty(13), np.empty(13)
    rk4_stage_compiled(x, k2, 0.5 * dt, out_c)
    rk4_stage_into(x, k2, 0.5 * dt, out_p)
    terms = np.abs(x) + np.abs(0.5 * dt * k2)
    assert np.all(np.abs(out_c - out_p) <= ulps * terms)
    assert np.all(np.abs(rk4_stage(x, k2, 0.5 * dt) - out_p) <= ulps * terms)  # the same law on arrays
    xc, xp = x.copy(), x.copy()
    assert rk4_combine_compiled(xc, k1, k2, k3, k4, dt)
    assert rk4_combine_into(xp, k1, k2, k3, k4, dt)
    terms = np.abs(x) + dt / 6.0 * (np.abs(k1) + 2.0 * np.abs(k2) + 2.0 * np.abs(k3) + np.abs(k4))
    assert np.all(np.abs(xc - xp) <= ulps * terms)
    assert np.all(np.abs(rk4_update(x, k1, k2, k3, k4, dt) - xp) <= ulps * terms)
    # and a scalar by hand in the documented order: x + dt/6 (((k1 + 2k2) + 2k3) + k4)
    i = 4
    assert xp[i] == x[i] + dt / 6.0 * (((k1[i] + 2.0 * k2[i]) + 2.0 * k3[i]) + k4[i])  # Python both: exact
    assert abs(xc[i] - xp[i]) <= ulps * terms[i]


def test_combine_reports_a_non_finite_state_and_updates_every_element() -> None:
    x = np.array([1.0, 2.0, 3.0])
    k = np.array([0.0, np.inf, 1.0])
    z = np.zeros(3)
    xc = x.copy()
    assert not rk4_combine_compiled(xc, k, z, z, z, 0.6)
    assert xc[0] == 1.0 and math.isinf(xc[1]) and xc[2] == pytest.approx(3.0 + 0.6 / 6.0, rel=1e-15)
    xn = x.copy()
    assert not rk4_combine_compiled(xn, np.array([np.nan, 0.0, 0.0]), z, z, z, 0.1)
    assert math.isnan(xn[0])


def test_the_compiled_integrators_hold_no_rk4_arithmetic_of_their_own() -> None:
    # the step's weights appear only in core.integrate: a kernel that writes them again is a copy.
    # deriv_rk4_step (the RK4 of the vehicle model), rk4_run and the multibody step call the
    # laws; the other integrators of the vehicle model call deriv_rk4_step.
    from hydrokit.manoeuvre import compiled as manoeuvre_compiled

    def source(kernel: object) -> str:
        return inspect.getsource(getattr(kernel, "py_func", kernel))

    for kernel in (compiled.deriv_rk4_step, compiled.rk4_run, transport._multibody):
        src = source(kernel)
        assert "rk4_combine_compiled" in src and "rk4_stage_compiled" in src, kernel
    for kernel in (transport._rigid, manoeuvre_compiled._rk4):
        assert "deriv_rk4_step(" in source(kernel), kernel
    for kernel in (
        compiled.deriv_rk4_step,
        compiled.rk4_run,
        transport._rigid,
        transport._multibody,
        manoeuvre_compiled._rk4,
    ):
        src = source(kernel)
        assert "/ 6.0" not in src and "2.0 * k2" not in src, kernel
