"""The bounded least squares behind the constrained allocation (model/bvls.py), compiled as the
allocator and the closed loop call it, against scipy's BVLS and against the KKT conditions."""

from __future__ import annotations

import numpy as np
import pytest

from hydrokit.model import allocation as alloc
from hydrokit.model.bvls import bvls, lstsq_small


def _kernels():  # noqa: ANN202
    from hydrokit._numba import compile_law

    return compile_law(lstsq_small, allocates=True), alloc.constrained_kernel()


def _problems(n_cases: int, seed: int):  # noqa: ANN202
    rng = np.random.default_rng(seed)
    for _ in range(n_cases):
        n = int(rng.integers(2, 9))
        m = int(rng.choice([n - 1, n, n + 3, 6 + n])) if n > 2 else n + 2
        A = np.asfortranarray(rng.normal(size=(m, n)))
        b = rng.normal(size=m) * 5.0
        lb = -rng.uniform(0.1, 1.5, n)
        ub = rng.uniform(0.1, 1.5, n)
        yield A, b, lb, ub


def _kkt_gap(A, b, lb, ub, x) -> float:  # noqa: ANN001
    """Largest violation of the KKT conditions of min ½|Ax − b|² on the box, in gradient units."""
    g = A.T @ (A @ x - b)
    tol = 1e-9 * np.maximum(1.0, np.abs(np.concatenate([lb, ub])).max())
    at_lo, at_hi = x <= lb + tol, x >= ub - tol
    free = ~(at_lo | at_hi)
    gap = np.concatenate([np.abs(g[free]), np.maximum(-g[at_lo], 0.0), np.maximum(g[at_hi], 0.0)])
    return float(gap.max(initial=0.0))


def test_bvls_agrees_with_scipy_and_meets_the_kkt_conditions() -> None:
    # 60 random boxes, over- and under-determined: the same optimum as scipy's BVLS (its cost is
    # strictly convex in A x, so A x agrees; x agrees where A has full column rank), and a KKT point
    from scipy.optimize import lsq_linear

    from hydrokit._numba import compile_law

    solve = compile_law(
        bvls,
        allocates=True,
        lstsq_small=compile_law(lstsq_small, allocates=True),
        _cols=compile_law(alloc._cols, allocates=True),
        _on_bound_part=compile_law(alloc._on_bound_part, allocates=True),
        _kkt=compile_law(alloc._kkt, allocates=True),
    )
    n_active = 0
    for A, b, lb, ub in _problems(60, 7):
        x = solve(A, b, lb, ub, 1e-12)
        ref = lsq_linear(A, b, bounds=(lb, ub), method="bvls", tol=1e-12).x
        assert np.all(x >= lb - 1e-12) and np.all(x <= ub + 1e-12)
        np.testing.assert_allclose(A @ x, A @ ref, rtol=0, atol=1e-9 * max(1.0, np.abs(b).max()))
        if A.shape[0] >= A.shape[1]:
            np.testing.assert_allclose(x, ref, rtol=0, atol=1e-8)
        assert _kkt_gap(A, b, lb, ub, x) < 1e-8
        n_active += int(np.any((x <= lb) | (x >= ub)))
    assert n_active > 30  # the boxes bind in most cases: the active-set moves are exercised


def test_lstsq_small_is_numpys_least_squares() -> None:
    # QR path (tall, well conditioned), SVD path (wide; nearly dependent columns): numpy's answer
    lstsq, _ = _kernels()
    rng = np.random.default_rng(3)
    tall = rng.normal(size=(9, 4))
    wide = rng.normal(size=(3, 5))
    dep = np.column_stack([tall[:, 0], tall[:, 0] * (1 + 1e-12), tall[:, 1]])
    for A in (tall, wide, dep):
        b = rng.normal(size=A.shape[0])
        for rcond in (np.finfo(float).eps, 1e-15):
            want = np.linalg.lstsq(A, b, rcond=rcond)[0]
            np.testing.assert_allclose(lstsq(np.asfortranarray(A), b, rcond), want, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("seed", [1, 2])
def test_the_allocator_and_the_compiled_loop_call_one_kernel(seed: int) -> None:
    # one implementation: the closed loop's constrained step is the allocator's kernel object,
    # and the allocator's saturated answer is that kernel's on the packed arrays
    from hydrokit.simulate import compiled_loop

    assert compiled_loop._constrained is alloc.constrained_kernel()
    rng = np.random.default_rng(seed)
    T = rng.normal(size=(6, 8))
    lim = np.full(8, 20.0)
    tau = rng.normal(size=6) * 200.0
    allocator = alloc.Allocator(T, -lim, lim)
    f, limited = allocator(tau)
    assert limited
    solver = alloc._ConstrainedSolver(allocator.T, allocator.f_min, allocator.f_max, allocator.Q)
    np.testing.assert_array_equal(f, alloc.constrained_kernel()(*solver.args(tau)))
    # and the law run as Python (numba's result to round-off: the same code)
    np.testing.assert_allclose(alloc.constrained_law(*solver.args(tau)), f, rtol=0, atol=1e-9)
