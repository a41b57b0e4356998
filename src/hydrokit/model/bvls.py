"""Bounded-variable least squares on small dense matrices: ``min |A x − b|`` with lb ≤ x ≤ ub.

The law behind the constrained thrust allocation (:func:`hydrokit.model.allocation.allocate_constrained`),
written once on numpy arrays so that numba compiles it unchanged (``compile_law(...,
allocates=True)``): the Python allocator and the compiled closed loop call the same compiled
kernel (:func:`hydrokit.model.allocation.constrained_kernel`).

:func:`bvls` follows scipy's BVLS (:func:`scipy.optimize.lsq_linear` with ``method="bvls"``,
Stark & Parker 1995) step by step — the same initialisation loop, the same choice of the variable
to free, the same step back to the first bound crossed and the same stopping rules — so the two
agree to round-off (tests/model/test_bvls.py checks it against scipy on random problems, and
against the KKT conditions). :func:`lstsq_small` is ``numpy.linalg.lstsq`` for the allocation's
small matrices, by Householder QR when that is safe.
"""

from __future__ import annotations

import math

import numpy as np

_EPS = float(np.finfo(float).eps)


def _cols(A, idx, nf):  # noqa: ANN001, ANN202
    out = np.empty((A.shape[0], nf))
    for jj in range(nf):
        for r in range(A.shape[0]):
            out[r, jj] = A[r, idx[jj]]
    return out


def _on_bound_part(x, on_bound):  # noqa: ANN001, ANN202
    out = np.zeros_like(x)
    for i in range(x.shape[0]):
        if on_bound[i] != 0:
            out[i] = x[i]
    return out


def _kkt(g, on_bound):  # noqa: ANN001, ANN202
    best = -np.inf
    for i in range(g.shape[0]):
        v = abs(g[i]) if on_bound[i] == 0 else g[i] * on_bound[i]
        if v > best:
            best = v
    return best


def lstsq_small(A, b, rcond):  # noqa: ANN001, ANN201
    """``np.linalg.lstsq(A, b, rcond)[0]`` for the allocation's small matrices (A: (m, n), b: (m,),
    rcond: relative singular-value cut-off, –).

    When A has at least as many rows as columns and its Householder R has no diagonal below
    1e-7 of its largest (so its condition number is far below 1/rcond for every rcond used
    here, ≤ 1e-14, and LAPACK's SVD cuts no singular value), both give the unique
    least-squares solution, equal to round-off; that case is solved by Householder QR in
    place, without LAPACK's call overhead (the SVD path cost about a third of a fleet step).
    Otherwise (fewer rows than columns, or nearly dependent columns): LAPACK's SVD, the
    minimum-norm solution with rcond's cut-off, exactly as numpy.
    """
    m, n = A.shape
    if n == 0 or m < n or rcond > 1e-14:
        return np.linalg.lstsq(A, b, rcond=rcond)[0]
    R = np.empty((m, n))
    for i in range(m):
        for j in range(n):
            R[i, j] = A[i, j]
    y = b.copy()
    for k in range(n):
        s2 = 0.0
        for i in range(k + 1, m):
            s2 += R[i, k] * R[i, k]
        rkk = R[k, k]
        norm = math.sqrt(s2 + rkk * rkk)
        if norm == 0.0:
            return np.linalg.lstsq(A, b, rcond=rcond)[0]
        alpha = -norm if rkk >= 0.0 else norm
        v0 = rkk - alpha
        vv = v0 * v0 + s2  # |v|², v = (v0, R[k+1:, k])
        R[k, k] = v0
        for j in range(k + 1, n):
            d = 0.0
            for i in range(k, m):
                d += R[i, k] * R[i, j]
            f = 2.0 * d / vv
            for i in range(k, m):
                R[i, j] -= f * R[i, k]
        d = 0.0
        for i in range(k, m):
            d += R[i, k] * y[i]
        f = 2.0 * d / vv
        for i in range(k, m):
            y[i] -= f * R[i, k]
        R[k, k] = alpha
    big = 0.0
    small = np.inf
    for k in range(n):
        big = max(big, abs(R[k, k]))
        small = min(small, abs(R[k, k]))
    if small <= 1e-7 * big:
        return np.linalg.lstsq(A, b, rcond=rcond)[0]
    x = np.empty(n)
    for k in range(n - 1, -1, -1):
        s = y[k]
        for j in range(k + 1, n):
            s -= R[k, j] * x[j]
        x[k] = s / R[k, k]
    return x


def bvls(A, b, lb, ub, tol):  # noqa: ANN001, ANN201
    """x minimising |A x − b| with lb ≤ x ≤ ub: ``scipy.optimize.lsq_linear(A, b, bounds=(lb, ub),
    method="bvls", tol=tol).x`` step by step.

    Parameters
    ----------
    A : (m, n) array — the system (any units: b's per x's)
    b : (m,) array — the right-hand side (b's units)
    lb, ub : (n,) arrays — the bounds, lb < ub (x's units; ±inf for none)
    tol : float — relative cost change and KKT optimality at which to stop, –

    Returns
    -------
    (n,) array — the solution (x's units)
    """
    m, n = A.shape
    x = lstsq_small(A, b, _EPS)
    inside = True
    for i in range(n):
        if not (x[i] >= lb[i] and x[i] <= ub[i]):
            inside = False
    if inside:
        return x
    rc = _EPS * max(m, n)
    on_bound = np.zeros(n)
    for i in range(n):
        if x[i] <= lb[i]:
            x[i] = lb[i]
            on_bound[i] = -1.0
        if x[i] >= ub[i]:
            x[i] = ub[i]
            on_bound[i] = 1.0
    free = np.empty(n, dtype=np.int64)
    nf = 0
    for i in range(n):
        if on_bound[i] == 0:
            free[nf] = i
            nf += 1
    r = A @ x - b
    cost = 0.5 * np.dot(r, r)
    g = A.T @ r
    iteration = 0
    # initialisation loop
    while nf > 0:
        iteration += 1
        b_free = b - A @ _on_bound_part(x, on_bound)
        z = lstsq_small(_cols(A, free, nf), b_free, rc)
        any_v = False
        keep = 0
        for jj in range(nf):
            i = free[jj]
            if z[jj] < lb[i]:
                x[i] = lb[i]
                on_bound[i] = -1.0
                any_v = True
            elif z[jj] > ub[i]:
                x[i] = ub[i]
                on_bound[i] = 1.0
                any_v = True
            else:
                x[i] = z[jj]
        r = A @ x - b
        cost = 0.5 * np.dot(r, r)
        g = A.T @ r
        if any_v:
            for jj in range(nf):
                i = free[jj]
                if on_bound[i] == 0:
                    free[keep] = i
                    keep += 1
            nf = keep
        else:
            break
    max_iter = n + iteration
    optimality = _kkt(g, on_bound)
    lbv = np.empty(n, dtype=np.int64)
    ubv = np.empty(n, dtype=np.int64)
    for _ in range(iteration, max_iter):
        if optimality < tol:
            break
        best = -np.inf
        move = 0
        for i in range(n):
            v = g[i] * on_bound[i]
            if v > best:
                best = v
                move = i
        on_bound[move] = 0.0
        while True:
            nf = 0
            for i in range(n):
                if on_bound[i] == 0:
                    free[nf] = i
                    nf += 1
            if nf == 0:  # every variable at a bound: lstsq of no columns changes nothing
                break
            b_free = b - A @ _on_bound_part(x, on_bound)
            z = lstsq_small(_cols(A, free, nf), b_free, rc)
            nl = 0
            nu_ = 0
            for jj in range(nf):
                i = free[jj]
                if z[jj] < lb[i]:
                    lbv[nl] = jj
                    nl += 1
            for jj in range(nf):
                i = free[jj]
                if z[jj] > ub[i]:
                    ubv[nu_] = jj
                    nu_ += 1
            if nl + nu_ > 0:
                alpha = np.inf
                pick = -1
                pick_lower = True
                for q in range(nl + nu_):
                    if q < nl:
                        jj = lbv[q]
                        a = (lb[free[jj]] - x[free[jj]]) / (z[jj] - x[free[jj]])
                    else:
                        jj = ubv[q - nl]
                        a = (ub[free[jj]] - x[free[jj]]) / (z[jj] - x[free[jj]])
                    if a < alpha:  # np.argmin: the first minimum
                        alpha = a
                        pick = jj
                        pick_lower = q < nl
                for jj in range(nf):
                    i = free[jj]
                    x[i] = x[i] * (1 - alpha) + alpha * z[jj]
                on_bound[free[pick]] = -1.0 if pick_lower else 1.0
            else:
                for jj in range(nf):
                    x[free[jj]] = z[jj]
                break
        r = A @ x - b
        cost_new = 0.5 * np.dot(r, r)
        cost_change = cost - cost_new
        stop = cost_change < tol * cost
        cost = cost_new
        g = A.T @ r
        optimality = _kkt(g, on_bound)
        if stop:
            break
    return x
