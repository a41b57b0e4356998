"""Configuration matrix (LI2021 eq. 22-30, Minerva SPEC §8) and allocation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from hydrokit.errors import InputError
from hydrokit.model.allocation import (
    Allocator,
    allocate_constrained,
    allocate_pinv,
    configuration_matrix,
    uncontrollable_dofs,
    weighted_pinv,
)

# Lingyun poses (LI2021 Tables 5/6 give them symbolically; these values are our choice,
# inside the 1.25 m x 0.47 m x 0.93 m hull of LI2021 Table 1).
R_HX, R_HY, R_VY, R_VZ = 0.60, 0.35, 0.30, 0.40
LINGYUN_POS = [(-R_HX, -R_HY, 0), (-R_HX, R_HY, 0), (0, -R_VY, -R_VZ), (0, R_VY, -R_VZ)]
LINGYUN_DIR = [(1, 0, 0), (1, 0, 0), (0, 0, -1), (0, 0, -1)]

# Minerva poses chosen to reproduce the published matrix (docs/control.md):
C10, S10 = math.cos(math.radians(10)), math.sin(math.radians(10))
MINERVA_POS = [(0.166, 0, 0), (0, 0.20, 0), (0, -0.20, 0), (-0.20, -0.305, 0), (-0.20, 0.305, 0)]
MINERVA_DIR = [(0, 1, 0), (0, 0, 1), (0, 0, 1), (C10, -S10, 0), (C10, S10, 0)]


def lingyun_T() -> np.ndarray:
    return configuration_matrix(LINGYUN_POS, LINGYUN_DIR)


def test_lingyun_matrix_structure_eq29() -> None:
    T = lingyun_T()
    # LI2021 eq. 29: surge from both horizontal thrusters, heave from both vertical ones
    # (pointing up, -z), roll from the vertical pair's lateral arm, yaw from the horizontal
    # pair's lateral arm; sway and pitch rows zero. Exact small-integer arithmetic.
    expected = np.array(
        [
            [1, 1, 0, 0],
            [0, 0, 0, 0],
            [0, 0, -1, -1],
            [0, 0, R_VY, -R_VY],
            [0, 0, 0, 0],
            [R_HY, -R_HY, 0, 0],
        ]
    )
    np.testing.assert_allclose(T, expected, atol=1e-15)
    assert uncontrollable_dofs(T) == ["sway", "pitch"]


def test_lingyun_normalised_allocation_eq30(lingyun_reference: dict) -> None:
    B_printed = np.array(lingyun_reference["allocation_normalised_eq30"], dtype=float)
    T = lingyun_T()
    rows = [0, 2, 3, 5]  # X, Z, K, N: the actuated DOF
    # Normalise each moment row by its lever arm (tau_K / r_vy, tau_N / r_hy):
    Tn = T[rows] / np.array([1, 1, R_VY, R_HY])[:, None]
    # The printed B is laid out DOF x thruster: it is (Tn^+)^T, which here is also Tn / 2
    # (Tn Tn^T = 2 I). Round-off only, hence 1e-12.
    np.testing.assert_allclose(np.linalg.pinv(Tn).T, B_printed, atol=1e-12)
    np.testing.assert_allclose(Tn / 2, B_printed, atol=1e-12)


def test_minerva_matrix_reproduces_published(published: dict) -> None:
    printed = np.array(published["minerva_mo2015"]["configuration_matrix"], dtype=float)
    T = configuration_matrix(MINERVA_POS, MINERVA_DIR)
    # SPEC §8 prints 3 decimals: agreement to half a unit of the last printed digit
    np.testing.assert_allclose(T, printed, atol=5e-4)
    assert uncontrollable_dofs(T) == ["pitch"]


@given(st.lists(st.floats(-100, 100), min_size=4, max_size=4))
@settings(max_examples=50, deadline=None)
def test_pinv_exact_for_achievable_tau(f_true: list[float]) -> None:
    T = lingyun_T()
    tau = T @ np.array(f_true)  # achievable by construction
    res = allocate_pinv(T, tau)
    # square full-rank reduced problem: exact up to round-off of |tau| ~ 1e2
    np.testing.assert_allclose(T @ res.thrust, tau, atol=1e-9)
    np.testing.assert_allclose(res.thrust, f_true, atol=1e-9)


def test_weighted_pinv_shifts_effort() -> None:
    # two parallel thrusters on the same line: any split achieves X; W = diag(1, 4)
    # minimises f1^2 + 4 f2^2 -> f1 = 4 f2 (closed form), f1 + f2 = 10.
    T = configuration_matrix([(0, 0, 0), (0, 0, 0)], [(1, 0, 0), (1, 0, 0)])
    f = weighted_pinv(T, [1.0, 4.0]) @ np.array([10.0, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(f, [8.0, 2.0], rtol=1e-12)


def test_constrained_respects_limits_and_minimises_residual() -> None:
    # Hand-checked: Lingyun asked for X = 300 N with 100 N thrusters -> both at 100 N,
    # residual exactly 100 N (nothing else can reduce it).
    T = lingyun_T()
    lo, hi = np.full(4, -80.0), np.full(4, 100.0)
    res = allocate_constrained(T, [300, 0, 0, 0, 0, 0], lo, hi, ["HT1", "HT2", "VT1", "VT2"])
    np.testing.assert_allclose(res.thrust, [100, 100, 0, 0], atol=1e-8)
    assert res.residual == pytest.approx(100.0, rel=1e-10)
    assert res.saturated == ["HT1", "HT2"]


def test_constrained_trades_surge_against_yaw_by_least_squares() -> None:
    # X = 150 N, N = 0.35*100 N m with limits +-100 N on HT1/HT2 (arm 0.35 m).
    # Unconstrained: f1 = (X + N/a)/2 = 125 > 100. With f1 = 100 at its limit, the
    # remaining variable f2 minimises (100 + f2 - 150)^2 + (0.35(100 - f2) - 35)^2
    # -> f2 (1 + a^2) = 50 -> f2 = 50 / 1.1225 (hand-derived).
    T = lingyun_T()
    lim = np.full(4, 100.0)
    res = allocate_constrained(T, [150, 0, 0, 0, 0, 0.35 * 100], -lim, lim)
    # exact to round-off: the polish puts HT1 at its limit and solves HT2 in closed form (the
    # stage-2 penalty alone is 3e-8 N off)
    assert res.thrust[0] == pytest.approx(100.0, abs=1e-10)
    assert res.thrust[1] == pytest.approx(50 / (1 + R_HY**2), rel=1e-12)
    assert np.all(res.thrust <= lim + 1e-12) and np.all(res.thrust >= -lim - 1e-12)


def test_constrained_equals_pinv_when_within_limits() -> None:
    T = configuration_matrix(MINERVA_POS, MINERVA_DIR)
    tau = np.array([40, 10, -20, 3, 0, 5.0])
    lim = np.full(5, 500.0)
    a = allocate_constrained(T, tau, -lim, lim)
    b = allocate_pinv(T, tau)
    # pinv is the minimum-norm exact solution; stage 2 of the constrained method finds the
    # same one: its penalty alone leaves 2e-8 N, the polish (no thruster at a limit: all free,
    # solved by the pseudo-inverse) makes it exact to round-off
    np.testing.assert_allclose(a.thrust, b.thrust, rtol=0, atol=1e-10)


def test_constrained_picks_smallest_thrust_among_equal_residuals() -> None:
    # Three collinear thrusters, demand beyond reach in +X but one is capped low:
    # limits (10, 10, 10) -> all at 10. With demand 15 all splits summing to 15 tie on
    # residual; the least-norm one is (5, 5, 5).
    T = configuration_matrix([(0, 0, 0)] * 3, [(1, 0, 0)] * 3)
    lim = np.full(3, 10.0)
    res = allocate_constrained(T, [15, 0, 0, 0, 0, 0], -lim, lim)
    np.testing.assert_allclose(res.thrust, [5, 5, 5], atol=1e-6)
    assert res.residual == pytest.approx(0.0, abs=1e-8)


@given(st.lists(st.floats(-400, 400), min_size=6, max_size=6))
@settings(max_examples=40, deadline=None)
def test_constrained_never_exceeds_limits(tau: list[float]) -> None:
    T = configuration_matrix(MINERVA_POS, MINERVA_DIR)
    lo = np.array([-50, -80, -80, -60, -60.0])
    hi = np.array([50, 100, 100, 120, 120.0])
    res = allocate_constrained(T, tau, lo, hi)
    assert np.all(res.thrust <= hi) and np.all(res.thrust >= lo)
    # no feasible point does better: the pinv solution clipped to the box and 50 random
    # points in the box (a convex problem: any better point would show up as a violation)
    clipped = np.clip(np.linalg.pinv(T) @ np.array(tau), lo, hi)
    assert res.residual <= np.linalg.norm(T @ clipped - np.array(tau)) + 1e-6
    rng = np.random.default_rng(0)
    samples = lo + (hi - lo) * rng.random((50, 5))
    others = np.linalg.norm(samples @ T.T - np.array(tau), axis=1)
    assert res.residual <= others.min() + 1e-6


def test_uncontrollable_dof_is_warned_and_rest_allocated() -> None:
    T = lingyun_T()
    lim = np.full(4, 100.0)
    res = allocate_constrained(T, [20, 5, 0, 0, 0, 0], -lim, lim)
    assert res.uncontrollable == ["sway", "pitch"]
    assert any("cannot actuate sway" in w for w in res.warnings)
    np.testing.assert_allclose(res.thrust, [10, 10, 0, 0], atol=1e-8)


def test_allocator_fast_path_and_fallback() -> None:
    T = lingyun_T()
    lo, hi = np.full(4, -80.0), np.full(4, 100.0)
    alloc = Allocator(T, lo, hi)
    f, limited = alloc([50, 0, 0, 0, 0, 0])
    assert not limited
    np.testing.assert_allclose(f, [25, 25, 0, 0], rtol=1e-12)
    f, limited = alloc([300, 0, 0, 0, 0, 0])
    assert limited
    np.testing.assert_allclose(f, [100, 100, 0, 0], atol=1e-8)


def test_bad_tau_rejected() -> None:
    with pytest.raises(InputError, match="expected 6 finite numbers"):
        allocate_pinv(lingyun_T(), [1, 2, 3])


@given(st.lists(st.floats(-300, 300), min_size=6, max_size=6))
@settings(max_examples=25, deadline=None)
def test_constrained_least_norm_agrees_with_slsqp(tau: list[float]) -> None:
    # Second method for stage 2: SLSQP on min |f|^2 s.t. T f = a*, limits. Our solution must
    # be feasible, achieve the same T f, and be no larger than SLSQP's (to SLSQP's 1e-6
    # tolerance on a thrust scale of ~100 N).
    from scipy.optimize import minimize

    # a redundant 8-thruster layout (BlueROV2-Heavy-like: 4 vectored horizontal, 4 vertical)
    c = math.sqrt(0.5)
    pos = [
        (0.156, 0.111, 0.085),
        (0.156, -0.111, 0.085),
        (-0.156, 0.111, 0.085),
        (-0.156, -0.111, 0.085),
        (0.12, 0.218, 0),
        (0.12, -0.218, 0),
        (-0.12, 0.218, 0),
        (-0.12, -0.218, 0),
    ]
    dirs = [(c, -c, 0), (c, c, 0), (c, c, 0), (c, -c, 0)] + [(0, 0, -1)] * 4
    T = configuration_matrix(pos, dirs)
    lo = np.full(8, -30.0)
    hi = np.array([40, 40, 40, 40, 30, 30, 30, 30.0])
    tau = list(np.array(tau) * np.array([0.2, 0.2, 0.2, 0.02, 0.02, 0.02]))  # this vehicle's scale
    res = allocate_constrained(T, tau, lo, hi)
    a_star = res.achieved_tau
    sol = None
    for start in (np.clip(res.thrust * 0.5, lo, hi), res.thrust, np.zeros(8)):
        sol = minimize(
            lambda f: f @ f,
            start,
            jac=lambda f: 2 * f,
            constraints=[{"type": "eq", "fun": lambda f: T @ f - a_star, "jac": lambda f: T}],
            bounds=list(zip(lo, hi)),
            method="SLSQP",
            options={"ftol": 1e-12, "maxiter": 500},
        )
        if sol.success:
            break
    # the reference itself can fail ("positive directional derivative"); such an example proves
    # nothing either way
    assume(sol.success)
    np.testing.assert_allclose(T @ sol.x, a_star, atol=1e-6)
    assert np.linalg.norm(res.thrust) <= np.linalg.norm(sol.x) + 1e-6 * 40


def test_a_thrust_exactly_at_its_limit_is_not_saturation() -> None:
    # forward-only thrusters (f_min = 0, f_max = 0 for a dead one): the unconstrained answer
    # [25, 25, 0, 0] touches those limits but breaks none, so it is returned as is, unlimited
    T = lingyun_T()
    f, limited = Allocator(T, np.zeros(4), np.array([100.0, 100.0, 0.0, 0.0]))([50, 0, 0, 0, 0, 0])
    assert not limited
    np.testing.assert_allclose(f, [25, 25, 0, 0], rtol=1e-12)
    f, limited = Allocator(T, np.zeros(4), np.full(4, 100.0))(np.zeros(6))
    assert not limited and not np.any(f)


def test_stage_two_finds_the_least_thrust_split_that_bounded_least_squares_misses() -> None:
    # a layout with four parallel thrusters (one direction, four places) and limits that bind:
    # BVLS (stage 1) reaches the least residual with one split of the parallel group, not the
    # smallest; stage 2 must give the least-norm split, checked by SLSQP (a second method) on
    # min |f|² s.t. T f = a*, limits
    from scipy.optimize import lsq_linear, minimize

    pos = [
        (0.04, -0.39, -0.01),
        (-0.42, 0.3, 0.34),
        (-0.43, 0.13, -0.18),
        (0.17, 0.38, -0.41),
        (0.09, -0.46, -0.43),
        (0.24, -0.24, -0.41),
        (0.35, -0.22, 0.46),
        (-0.11, -0.3, -0.32),
    ]
    group = (-0.99, -0.1, -0.03)
    dirs = [group] * 4 + [(0.8, 0.56, 0.19), (-0.94, -0.34, -0.02), (-0.51, 0.47, -0.73), (0.12, 0.98, 0.16)]
    T = configuration_matrix(pos, dirs)
    lo = np.array([-1.4, -1.4, -1.9, -4.0, -2.1, -1.9, -1.7, -0.7])
    hi = np.array([17.9, 8.1, 13.7, 6.2, 6.2, 5.2, 2.2, 11.6])
    tau = np.array([-15.8, -1.7, 5.7, 4.5, -0.7, -0.1])
    res = allocate_constrained(T, tau, lo, hi)
    a_star = res.achieved_tau
    sol = minimize(
        lambda f: f @ f,
        np.zeros(8),
        jac=lambda f: 2 * f,
        constraints=[{"type": "eq", "fun": lambda f: T @ f - a_star, "jac": lambda f: T}],
        bounds=list(zip(lo, hi)),
        method="SLSQP",
        options={"ftol": 1e-12, "maxiter": 500},
    )
    assert sol.success
    np.testing.assert_allclose(T @ sol.x, a_star, atol=1e-6)
    assert np.linalg.norm(res.thrust) == pytest.approx(np.linalg.norm(sol.x), rel=1e-6)
    np.testing.assert_allclose(res.thrust, sol.x, atol=1e-4)
    bvls = lsq_linear(T, tau, bounds=(lo, hi), method="bvls", tol=1e-12).x
    assert np.linalg.norm(bvls) > np.linalg.norm(sol.x) + 0.1  # stage 1 alone is not enough


def test_pinv_checks_either_limit_given_alone() -> None:
    # LI2021's four thrusters asked for the wrench of 37.5 N on each (achievable: the pseudo-
    # inverse returns exactly that). With only an upper
    # limit of 30 N every one is reported over it; with only a lower limit of −30 N none is; a
    # missing limit is no limit (not a reason to skip the other)
    T = lingyun_T()
    f_true = np.array([37.5, 37.5, 37.5, 37.5])
    tau = T @ f_true
    names = ["T1", "T2", "T3", "T4"]
    upper = allocate_pinv(T, tau, f_max=[30.0] * 4, names=names)
    np.testing.assert_allclose(upper.thrust, f_true, atol=1e-9)
    assert upper.saturated == names
    assert upper.warnings == ["pseudo-inverse thrust exceeds the limits of T1, T2, T3, T4"]
    lower = allocate_pinv(T, tau, f_min=[-30.0] * 4, names=names)
    assert lower.saturated == [] and lower.warnings == []


def test_capability_weights_are_the_reciprocal_reach_even_below_one_newton() -> None:
    # small thrusters (limits ±0.5 N): each DOF's reach Σ_j |T_ij| · 0.5 N is under 1 N (or
    # N·m) for some DOFs; Q is still 1/reach for every DOF the layout reaches, and 1 where it
    # reaches nothing
    T = lingyun_T()
    alloc = Allocator(T, [-0.5] * 4, [0.5] * 4)
    assert alloc.Q is not None
    reach = np.abs(T) @ np.full(4, 0.5)
    assert np.any((reach > 0) & (reach < 1.0)) and np.any(reach == 0)
    np.testing.assert_allclose(alloc.Q[reach > 0] * reach[reach > 0], 1.0, rtol=1e-12)
    assert np.all(alloc.Q[reach == 0] == 1.0)


def test_a_row_no_larger_than_the_tolerance_counts_as_all_zero() -> None:
    # ZERO_ROW_TOL = 1e-9: a yaw lever of 1e-9 (round-off of a pose given to 1e-3 m) is none;
    # twice that is a lever; an explicit tol works the same way
    T = np.eye(6)
    for lever, unc in ((1e-9, ["yaw"]), (2e-9, [])):
        T[5, 5] = lever
        assert uncontrollable_dofs(T) == unc
    T[5, 5] = 0.5
    assert uncontrollable_dofs(T, tol=0.5) == ["yaw"]
    assert uncontrollable_dofs(T, tol=0.4999) == []


def test_pinv_reports_a_lower_limit_given_alone_and_keeps_the_limits_given() -> None:
    # the wrench of −37.5 N on each of LI2021's four thrusters (achievable: residual 0). A lower
    # limit of −30 N alone: every one is below it, and at it within 1e-6 of the limit; an upper
    # limit of 50 N alone: none is over it. The JSON keeps the limit given and writes the
    # missing one as null (no limit)
    T = lingyun_T()
    names = ["T1", "T2", "T3", "T4"]
    tau = T @ np.full(4, -37.5)
    lower = allocate_pinv(T, tau, f_min=[-30.0] * 4, names=names)
    assert lower.residual < 1e-9
    assert lower.saturated == names
    assert lower.warnings == ["pseudo-inverse thrust exceeds the limits of T1, T2, T3, T4"]
    assert lower.to_dict()["thrust_limits"] == [[-30.0, None]] * 4
    upper = allocate_pinv(T, tau, f_max=[50.0] * 4, names=names)
    assert upper.saturated == [] and upper.warnings == []
    assert upper.to_dict()["thrust_limits"] == [[None, 50.0]] * 4
    assert allocate_pinv(T, tau, names=names).to_dict()["thrust_limits"] is None
    import dataclasses

    with pytest.raises(dataclasses.FrozenInstanceError):
        lower.residual = 0.0  # type: ignore[misc]


def test_pinv_residual_is_what_the_thrusters_cannot_give() -> None:
    # a surge thruster and a heave thruster at the origin: the sway part of τ is out of reach
    T = np.zeros((6, 2))
    T[0, 0] = T[2, 1] = 1.0
    r = allocate_pinv(T, [10.0, 3.0, -4.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(r.thrust, [10.0, -4.0], atol=1e-12)
    assert r.residual == pytest.approx(3.0, rel=1e-12)


def test_thrust_within_a_millionth_of_a_limit_is_at_it() -> None:
    # _at_limit's tolerance is 1e-6 of the limit (at least 1e-6 N): 37.5 − 3e-5 N against an upper
    # limit of 37.5 N is at it, 37.5 − 5e-5 N is not
    T = lingyun_T()
    for f, at in ((37.5 - 3e-5, ["T1", "T2", "T3", "T4"]), (37.5 - 5e-5, [])):
        r = allocate_pinv(T, T @ np.full(4, f), f_min=[-37.5] * 4, f_max=[37.5] * 4, names=["T1", "T2", "T3", "T4"])
        assert r.saturated == at
    # limits of ±0.5 N: the tolerance is its floor, 1e-6 N (0.5 − 0.8e-6 N is at it, 0.5 − 1.5e-6 N not)
    for f, at in ((0.5 - 0.8e-6, ["T1", "T2", "T3", "T4"]), (0.5 - 1.5e-6, [])):
        r = allocate_pinv(T, T @ np.full(4, f), f_min=[-0.5] * 4, f_max=[0.5] * 4, names=["T1", "T2", "T3", "T4"])
        assert r.saturated == at


def test_pinv_thrust_at_a_limit_of_either_sign_is_not_beyond_it() -> None:
    # T = I: thrust = demand. Limits [5, 20] N (a thruster that cannot idle) and [−20, −5] N: a
    # thrust exactly at 5 or −5 N is at its limit, not beyond it (the relative margin once
    # shrank the wrong way for a positive lower or a negative upper limit); 4.99 N is beyond
    T = np.eye(6)
    lo, hi = [5.0, -20.0, -20, -20, -20, -20], [20.0, -5.0, 20, 20, 20, 20]
    at = allocate_pinv(T, [5.0, -5.0, 0, 0, 0, 0], f_min=lo, f_max=hi)
    assert at.warnings == [] and at.saturated == ["T1", "T2"]
    beyond = allocate_pinv(T, [4.99, -4.99, 0, 0, 0, 0], f_min=lo, f_max=hi)
    assert beyond.warnings == ["pseudo-inverse thrust exceeds the limits of T1, T2"]
    # round-off past ±20 N by 1e-8 N (5e-10 of the limit) is not beyond; by 1e-7 N (5e-9) it is
    assert allocate_pinv(T, [10, -10, 20 + 1e-8, -20 - 1e-8, 0, 0], f_min=lo, f_max=hi).warnings == []
    far = allocate_pinv(T, [10, -10, 20 + 1e-7, -20 - 1e-7, 0, 0], f_min=lo, f_max=hi)
    assert far.warnings == ["pseudo-inverse thrust exceeds the limits of T3, T4"]


@pytest.mark.parametrize(
    ("positions", "directions"),
    [
        ([(0, 0), (1, 1)], [(1, 0), (0, 1)]),  # matching shapes, but planar
        ([(0, 0, 0), (1, 0, 0)], [(1, 0, 0)]),  # three-dimensional, but 2 positions and 1 direction
        ([(0, 0, 0, 0)], [(1, 0, 0, 0)]),
    ],
)
def test_configuration_matrix_needs_two_m_by_3_arrays(positions, directions):
    with pytest.raises(InputError, match=r"positions \(.*\) and directions \(.*\): expected two \(m, 3\) arrays"):
        configuration_matrix(positions, directions)


def test_allocation_document_keeps_the_demand_and_the_matrix():
    # the --json document is self-contained: τ (N, N·m) and T as given, each as plain floats
    T = lingyun_T()
    tau = np.array([10.0, 0.0, 0.0, 0.0, 0.0, 2.0])
    doc = allocate_pinv(T, tau).to_dict()
    assert doc["tau"] == tau.tolist()
    assert doc["configuration_matrix"] == T.tolist()
    assert doc["thrust"] == pytest.approx((np.linalg.pinv(T) @ tau).tolist(), abs=1e-12)


@pytest.mark.parametrize(
    ("f_min", "f_max", "limits"),
    [
        (None, None, None),
        ([-30.0], None, [[-30.0, None]]),
        (None, [50.0], [[None, 50.0]]),
        ([-30.0], [50.0], [[-30.0, 50.0]]),
    ],
)
def test_allocation_document_writes_a_missing_limit_side_as_null(f_min, f_max, limits):
    # an Allocation made by hand with one side only: that side kept, the other null (no limit)
    from hydrokit.model.allocation import Allocation

    a = Allocation(np.array([1.0]), np.zeros(6), 0.0, [], [], f_min=f_min, f_max=f_max)
    assert a.to_dict()["thrust_limits"] == limits


def test_allocation_summary_shows_thrust_to_the_millinewton():
    from hydrokit.model.allocation import Allocation

    a = Allocation(np.array([1.23456, -0.0004]), np.zeros(6), 0.0, ["T1"], [], method="pinv", names=["T1", "T2"])
    rows = dict(a.summary_rows())
    assert rows["thrust (N)"] == [1.235, -0.0]
    assert rows["method"] == "pinv" and rows["saturated"] == "T1" and rows["not actuated"] == "none"


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_redundant_thrusters_share_exactly_once_one_is_at_its_limit(sign: float) -> None:
    # three collinear surge thrusters, the first capped at 10 N, the others at 30 N; X = ±50 N.
    # The least-norm split with T f = τ (KKT, by hand): the first at its limit, the other two
    # share the rest, 20 N each. The polish fixes the thruster found at the limit and solves
    # the free ones exactly: 1e-12 N (the stage-2 penalty alone leaves about 1e-9 N)
    T = configuration_matrix([(0, 0, 0)] * 3, [(1, 0, 0)] * 3)
    hi = np.array([10.0, 30.0, 30.0])
    res = allocate_constrained(T, [sign * 50.0, 0, 0, 0, 0, 0], -hi, hi)
    np.testing.assert_allclose(res.thrust, sign * np.array([10.0, 20.0, 20.0]), rtol=0, atol=1e-12)
    assert res.saturated == ["T1"]


@pytest.mark.parametrize("excess", [0.5, 2.0])
def test_stage_two_is_kept_unless_it_loses_more_than_its_tolerance(monkeypatch, excess: float) -> None:
    # the two-stage guard: stage 2 (least norm) may give up at most 1e-8 · thrust scale · max
    # DOF weight of stage 1's weighted residual (here 1e-8 · 100 N · 2 = 2e-6); beyond that
    # stage 1's answer is returned with its own residual. A polish made to miss τ by a chosen
    # weighted amount tries both sides of the tolerance
    from hydrokit.model import allocation as alloc

    T = lingyun_T()
    Q = np.array([2.0, 1, 1, 1, 1, 1])
    tol = 1e-8 * 100.0 * 2.0
    d = excess * tol / float(np.linalg.norm(Q * T[:, 0]))  # N on HT1 → weighted miss = excess·tol
    monkeypatch.setattr(alloc, "_polish", lambda T, a1, f, *rest: f + np.array([d, 0.0, 0.0, 0.0]))
    # the law as Python (it calls the module's _polish), in place of its compiled kernel
    monkeypatch.setattr(alloc, "constrained_kernel", lambda: alloc.constrained_law)
    lim = np.full(4, 100.0)
    res = allocate_constrained(T, [50.0, 0, 0, 0, 0, 0], -lim, lim, dof_weights=Q)
    exact = np.array([25.0, 25.0, 0.0, 0.0])  # T has full column rank: the one exact split
    if excess < 1:
        # stage 2's penalty point (within 3e-9 N of the exact split, unpolished here) plus d
        np.testing.assert_allclose(res.thrust, exact + [d, 0, 0, 0], rtol=0, atol=1e-8)
        assert res.residual == pytest.approx(d * float(np.linalg.norm(T[:, 0])), rel=0.02)
    else:
        np.testing.assert_allclose(res.thrust, exact, rtol=0, atol=1e-12)
        assert res.residual < 1e-12


def test_allocator_saturated_calls_are_allocate_constrained_with_the_same_weights() -> None:
    # X = 150 N against N = 35 N·m with ±100 N (the surge/yaw trade above): weighting surge ten
    # times moves the split; the allocator's saturated path is allocate_constrained bit for bit
    T = lingyun_T()
    lim = np.full(4, 100.0)
    tau = [150.0, 0, 0, 0, 0, 35.0]
    Q = [10.0, 1, 1, 1, 1, 1]
    f, limited = Allocator(T, -lim, lim, dof_weights=Q)(tau)
    assert limited
    np.testing.assert_array_equal(f, allocate_constrained(T, tau, -lim, lim, dof_weights=Q).thrust)
    plain = allocate_constrained(T, tau, -lim, lim).thrust
    assert abs(f[1] - plain[1]) > 1.0  # the weights matter here (N)


def test_allocator_takes_a_fixed_thruster_and_refuses_mismatched_limits() -> None:
    # min = max is a thruster held at one thrust (allowed); limits of the wrong count, or a
    # min above its max, are refused in words when the allocator is made
    T = lingyun_T()
    lo, hi = np.array([-100.0, -100, 5.0, -100]), np.array([100.0, 100, 5.0, 100])
    f, limited = Allocator(T, lo, hi)([300.0, 0, 0, 0, 0, 0])
    assert limited and f[2] == pytest.approx(5.0, abs=1e-9)
    np.testing.assert_allclose(f[:2], [100.0, 100.0], atol=1e-8)
    for bad_lo, bad_hi in [(np.full(3, -10.0), np.full(4, 10.0)), (np.full(4, -10.0), [10.0, 10, 10]), (hi, lo)]:
        with pytest.raises(InputError, match="thrust limits: expected 4 pairs with min ≤ max"):
            Allocator(T, bad_lo, bad_hi)
