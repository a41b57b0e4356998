"""Point drag elements (issue #11): closed forms, invariants, the vehicle file and every
integrator path (numpy, compiled, batch, fleet, closed loop).

A drag element at r sees v_P = v_r + ω × r and pushes back with f = −L∘v_P − Q∘|v_P|∘v_P at r.
The case worked through by hand below (one element on the y axis, the body yawing) is the one
REHMAN §2.6 uses for a transverse cylinder on an arm: Q = 83.28 N·s²/m² (REHMAN Table 1) at
ρ = 0.75 m gives the yaw coefficient Q ρ³ = 35.1 N·m·s² (not Q ρ² = 46.8).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import hydrokit
from hydrokit.core.drag import DragElement, drag_wrench, pack_elements
from hydrokit.errors import InputError
from hydrokit.io.vehicle import parse_vehicle
from hydrokit.model.dynamics import pack, vehicle_dynamics
from hydrokit.model.vehicle import Vehicle
from hydrokit.simulate.compiled import make_dynamics

RHO_ARM = 0.75  # m, REHMAN §2.6 lever arm
Q_CYL = 83.28  # N·s²/m², REHMAN Table 1, transverse cylinder


def base_doc(**changes: object) -> dict:
    """A vehicle with no damping at all, W = B at the origin, diagonal M_A: whatever drag acts
    comes from the elements."""
    doc = {
        "name": "drag-test",
        "gravity": 9.81,
        "fluid": {"density": 1000.0},
        "mass": 20.0,
        "volume": 0.02,
        "inertia": [2.0, 3.0, 4.0],
        "center_of_gravity": [0, 0, 0],
        "center_of_buoyancy": [0, 0, 0],
        "added_mass": [5.0, 6.0, 7.0, 0.5, 0.6, 1.0],
        "linear_damping": [0] * 6,
        "quadratic_damping": [0] * 6,
    }
    doc.update(changes)
    return doc


def vehicle(elements: list[dict] | None = None, **changes: object) -> Vehicle:
    doc = base_doc(**changes)
    if elements is not None:
        doc["drag_elements"] = elements
    return parse_vehicle(doc, "t")


def element_wrench(v: Vehicle, nu: np.ndarray, compiled: bool) -> np.ndarray:
    """The elements' wrench as the whole model sees it: M (ν̇ with − ν̇ without) at zero attitude."""
    bare = dataclasses.replace(v, drag_elements=())
    make = make_dynamics if compiled else vehicle_dynamics
    x = np.concatenate([np.zeros(6), nu])
    diff = make(v)(0.0, x, np.zeros(6))[6:] - make(bare)(0.0, x, np.zeros(6))[6:]
    return v.M @ diff


# ---------------------------------------------------------------------------- closed forms
@pytest.mark.parametrize("compiled", [False, True], ids=["numpy", "compiled"])
@pytest.mark.parametrize("omega", [0.8, -1.3])
def test_yawing_arm_quadratic_closed_form(compiled: bool, omega: float) -> None:
    # r = (0, ρ, 0), ν = (0, 0, 0, 0, 0, ω): v_P = ω e_z × ρ e_y = (−ρω, 0, 0), so
    # f_x = −Q_x |ρω| (−ρω) = Q_x ρ² ω|ω| (the arm's tip moves aft, drag pushes it forward) and
    # N = (r × f)_z = r_x f_y − r_y f_x = −Q_x ρ³ ω|ω| (opposes the spin).
    assert Q_CYL * RHO_ARM**3 == pytest.approx(35.1, abs=0.05)  # REHMAN §2.6: 35.1 = 83.28 · 0.75³
    v = vehicle([{"name": "arm", "position": [0, RHO_ARM, 0], "quadratic": [Q_CYL, 0, 0]}])
    w = element_wrench(v, np.array([0, 0, 0, 0, 0, omega]), compiled)
    expected = np.array([Q_CYL * RHO_ARM**2 * omega * abs(omega), 0, 0, 0, 0, -Q_CYL * RHO_ARM**3 * omega * abs(omega)])
    np.testing.assert_allclose(w, expected, rtol=1e-10, atol=1e-12)  # round-off of M (ν̇ − ν̇₀) only
    assert np.sign(w[0]) == np.sign(omega) and np.sign(w[5]) == -np.sign(omega)


@pytest.mark.parametrize("compiled", [False, True], ids=["numpy", "compiled"])
def test_yawing_arm_linear_closed_form(compiled: bool) -> None:
    # same point, linear only: f_x = −L_x (−ρω) = L_x ρ ω and N = −ρ f_x = −L_x ρ² ω
    L, omega = 12.0, -0.6
    v = vehicle([{"name": "arm", "position": [0, RHO_ARM, 0], "linear": [L, 0, 0]}])
    w = element_wrench(v, np.array([0, 0, 0, 0, 0, omega]), compiled)
    expected = np.array([L * RHO_ARM * omega, 0, 0, 0, 0, -L * RHO_ARM**2 * omega])
    np.testing.assert_allclose(w, expected, rtol=1e-10, atol=1e-12)  # round-off of M (ν̇ − ν̇₀) only


@pytest.mark.parametrize("compiled", [False, True], ids=["numpy", "compiled"])
def test_pure_translation_is_a_diagonal_quadratic_damping(compiled: bool) -> None:
    # ω = 0: every element sees v_P = v_r, so the forces add up to −(Σ Q)∘|v|∘v — the D_Q of a
    # vehicle with d = Σ Q. A mirrored pair (r and −r, same Q) leaves no moment, so the whole
    # right-hand side must equal that D_Q vehicle's (a second, independent code path).
    Q1, Q2 = [30.0, 40.0, 50.0], [5.0, 7.0, 11.0]
    elements = [
        {"name": "a", "position": [0.3, 0.5, -0.2], "quadratic": Q1},
        {"name": "a'", "position": [-0.3, -0.5, 0.2], "quadratic": Q1},
        {"name": "b", "position": [0.0, 0.0, 0.0], "quadratic": Q2},
    ]
    with_elements = vehicle(elements)
    d = [2 * a + b for a, b in zip(Q1, Q2)] + [0, 0, 0]
    with_dq = vehicle(quadratic_damping=d)
    make = make_dynamics if compiled else vehicle_dynamics
    rng = np.random.default_rng(5)
    for _ in range(10):
        x = np.concatenate([np.zeros(6), rng.normal(size=3), np.zeros(3)])
        a = make(with_elements)(0.0, x, np.zeros(6))
        b = make(with_dq)(0.0, x, np.zeros(6))
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-13)  # the same sum in another order
    # one element off the origin alone also turns the body: the moment is r × f
    one = vehicle([elements[0]])
    nu = np.array([0.4, -0.3, 0.2, 0, 0, 0])
    f = -np.array(Q1) * np.abs(nu[:3]) * nu[:3]
    np.testing.assert_allclose(
        element_wrench(one, nu, compiled),
        np.concatenate([f, np.cross([0.3, 0.5, -0.2], f)]),
        rtol=1e-9,
        atol=1e-12,
    )


coef = st.floats(0.0, 200.0)
pos = st.floats(-2.0, 2.0)
vel = st.floats(-3.0, 3.0)


@settings(max_examples=200, deadline=None)
@given(
    rows=st.lists(st.tuples(*([pos] * 3), *([coef] * 6)), min_size=1, max_size=4),
    nu=st.tuples(*([vel] * 6)),
)
def test_drag_elements_never_feed_energy_in(rows: list[tuple[float, ...]], nu: tuple[float, ...]) -> None:
    # wrench · ν_r = Σ f·v + (r × f)·ω = Σ f·(v + ω × r) = Σ f·v_P = −Σ (L v_P² + Q |v_P|³) ≤ 0
    P = np.array(rows, dtype=float)
    n = np.array(nu)
    power = float(drag_wrench(P, n) @ n)
    r = P[:, :3]
    vp = n[:3] + np.cross(n[3:], r)
    exact = -float(np.sum(P[:, 3:6] * vp**2 + P[:, 6:9] * np.abs(vp) ** 3))
    assert power <= 1e-9 * (1.0 + abs(exact))
    assert power == pytest.approx(exact, rel=1e-9, abs=1e-9)


@settings(max_examples=25, deadline=None)
@given(nu=st.tuples(*([vel] * 6)))
def test_compiled_drag_power_never_positive(nu: tuple[float, ...]) -> None:
    v = vehicle(
        [
            {"name": "a", "position": [0.4, 0.75, -0.1], "linear": [3, 4, 5], "quadratic": [83.28, 20, 10]},
            {"name": "b", "position": [-0.6, -0.2, 0.3], "quadratic": [10, 60, 30]},
        ]
    )
    n = np.array(nu)
    w = element_wrench(v, n, compiled=True)
    # same as the numpy reference (round-off of M (ν̇ − ν̇₀)), hence also ≤ 0
    ref = drag_wrench(v.drag_packed, n)
    np.testing.assert_allclose(w, ref, rtol=1e-9, atol=1e-9 * (1 + np.max(np.abs(ref))))
    assert float(w @ n) <= 1e-8 * (1 + float(np.max(np.abs(ref))))


# ---------------------------------------------------------------------------- vehicle file
def test_vehicle_file_with_drag_elements_loads(tmp_path) -> None:  # noqa: ANN001
    doc = base_doc(
        drag_elements=[
            {"name": "arm-port", "position": [0, -0.75, 0], "quadratic": [83.28, 0, 0]},
            {"name": "skid", "position": [0.2, 0, 0.3], "linear": [1, 2, 3], "quadratic": [4, 5, 6]},
        ]
    )
    f = tmp_path / "v.yaml"
    f.write_text(yaml.safe_dump(doc))
    v = hydrokit.load_vehicle(f)
    assert [e.name for e in v.drag_elements] == ["arm-port", "skid"]
    assert v.drag_elements[0].linear == (0.0, 0.0, 0.0)  # optional, zeros by default
    np.testing.assert_array_equal(v.drag_packed, [[0, -0.75, 0, 0, 0, 0, 83.28, 0, 0], [0.2, 0, 0.3, 1, 2, 3, 4, 5, 6]])
    p = pack(v)
    assert p.scal[8] == 2 and p.scal.shape == (9 + 18 + 6 + 1,)  # then the DOF mask and the fin count (0)
    np.testing.assert_array_equal(p.scal[9:27].reshape(2, 9), v.drag_packed)
    assert not any("drag_elements" in w for w in v.warnings)  # a known field
    # without the field: no elements, and the packed scal still says n = 0
    plain = hydrokit.load_vehicle("bluerov2-heavy")
    assert plain.drag_elements == () and pack(plain).scal[8] == 0 and pack(plain).scal.shape == (9 + 6 + 1,)


BAD = [
    ({"name": "a", "position": [0, 0, 0], "quadratic": [1, -2, 0]}, r"drag_elements\[0\]\.quadratic.*-2\.0.*≥ 0"),
    ({"name": "a", "position": [0, 0]}, r"drag_elements\[0\]\.position.*\[0, 0\].*3 numbers"),
    ({"name": "a", "position": [0, 0, 0], "cd": 1.2}, r"drag_elements\[0\].*unknown key.*'cd'"),
    ({"name": "a", "position": [0, 0, 0], "linear": [1, "x", 0]}, r"drag_elements\[0\]\.linear\[1\]"),
    ({"name": "a", "position": [0, 0, 0], "linear": [1, float("nan"), 0]}, r"drag_elements\[0\]\.linear\[1\]"),
    ({"position": [0, 0, 0]}, r"drag_elements\[0\].*missing 'name'"),
    ("fin", r"drag_elements\[0\]' = 'fin': expected a mapping"),
]


@pytest.mark.parametrize(("entry", "match"), BAD)
def test_bad_drag_element_names_the_field(entry: object, match: str) -> None:
    with pytest.raises(InputError, match=match) as exc:
        parse_vehicle(base_doc(drag_elements=[entry]), "v.yaml")
    assert "\n" not in str(exc.value) and str(exc.value).startswith("v.yaml: ")


@pytest.mark.parametrize("value", [{"name": "a", "position": [0, 0, 0]}, "arm", 3, None])
def test_drag_elements_not_a_list(value: object) -> None:
    with pytest.raises(InputError, match=r"field 'drag_elements' = .*expected a list"):
        parse_vehicle(base_doc(drag_elements=value), "v.yaml")


def test_duplicate_drag_element_names() -> None:
    els = [{"name": "a", "position": [0, 0, 0]}, {"name": "a", "position": [1, 0, 0]}]
    with pytest.raises(InputError, match=r"drag_elements\[1\]\.name.*'a'.*unique.*drag_elements\[0\]"):
        parse_vehicle(base_doc(drag_elements=els), "v.yaml")


def test_make_vehicle_checks_elements_given_in_python() -> None:
    v = vehicle()
    args = (v.name, v.mass, v.volume, v.gravity, v.density, v.inertia, v.r_g, v.r_b, v.M_A, v.D_L, v.D_Q)
    from hydrokit.model.vehicle import make_vehicle

    ok = make_vehicle(*args, drag_elements=[DragElement("a", np.array([1, 2, 3]), quadratic=(1, 2, 3))])  # type: ignore[arg-type]
    assert ok.drag_elements == (DragElement("a", (1.0, 2.0, 3.0), (0.0, 0.0, 0.0), (1.0, 2.0, 3.0)),)
    with pytest.raises(
        InputError, match=r"drag_elements\[0\]\.linear' = \[-1\.0, 0\.0, 0\.0\]: expected 3 numbers ≥ 0"
    ):
        make_vehicle(*args, drag_elements=[DragElement("a", (0, 0, 0), linear=(-1, 0, 0))])
    with pytest.raises(InputError, match=r"drag_elements\[0\]\.position.*expected 3 finite numbers"):
        make_vehicle(*args, drag_elements=[DragElement("a", (0, math.inf, 0))])
    with pytest.raises(InputError, match=r"drag_elements\[0\]' = .*expected a DragElement"):
        make_vehicle(*args, drag_elements=[{"name": "a"}])  # type: ignore[list-item]
    # the old constructor call (no drag_elements) still works
    assert make_vehicle(*args).drag_elements == ()


@pytest.mark.parametrize(
    ("value", "field"),
    [
        ([{"name": "a", "position": [0, 0, 0], "quadratic": [-1, 0, 0]}], "drag_elements[0].quadratic"),
        ([{"name": "a", "position": [0, 0]}], "drag_elements[0].position"),
        ([{"name": "a", "position": [0, 0, 0], "area": 1}], "drag_elements[0]"),
        ({"name": "a"}, "drag_elements"),
    ],
)
def test_cli_simulate_bad_drag_elements_exits_2(run_cli, tmp_path, value: object, field: str) -> None:  # noqa: ANN001
    f = tmp_path / "v.yaml"
    f.write_text(yaml.safe_dump(base_doc(drag_elements=value)))
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", f, "--duration", "1", "--out", out)
    assert code == 2 and f"'{field}" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_cli_simulate_with_drag_elements(run_cli, tmp_path) -> None:  # noqa: ANN001
    f = tmp_path / "v.yaml"
    els = [{"name": "arm", "position": [0, RHO_ARM, 0], "quadratic": [Q_CYL, 0, 0]}]
    f.write_text(yaml.safe_dump(base_doc(drag_elements=els)))
    out = tmp_path / "t.csv"
    code, _, err = run_cli("simulate", f, "--duration", "1", "--dt", "0.01", "--force", "0,0,0,0,0,5", "--out", out)
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    plain = hydrokit.simulate(vehicle(), 1.0, 0.01, tau=[0, 0, 0, 0, 0, 5])
    # the element slows the spin-up (and pushes the body forward: X = Q ρ² r|r| > 0)
    assert 0 < data[-1, 12] < plain.nu[-1, 5] and data[-1, 7] > 0


# ---------------------------------------------------------------------------- spin-down
@pytest.mark.parametrize("attitude", ["euler", "quaternion"])
def test_spin_down_follows_the_closed_form(attitude: str) -> None:
    # Two arms at (0, ±ρ, 0), each with Q/2 along x: their forces cancel (±Q/2 ρ² r|r|), their
    # moments add to N = −Q ρ³ |r| r, and with no other damping, diagonal M, CG = CB = origin
    # and W = B the motion stays a pure yaw (C(ν)ν = 0 for ν = r e_z):
    #     I ṙ = −Q ρ³ |r| r,  I = I_zz + N_ṙ-added   ⇒   r(t) = r0 / (1 + k r0 t),  k = Q ρ³ / I
    # (one arm alone would also push the body sideways, and surge couples back into v_P).
    half = Q_CYL / 2
    v = vehicle(
        [
            {"name": "port", "position": [0, -RHO_ARM, 0], "quadratic": [half, 0, 0]},
            {"name": "starboard", "position": [0, RHO_ARM, 0], "quadratic": [half, 0, 0]},
        ],
        inertia=[2.0, 3.0, 30.0],
        added_mass=[5.0, 6.0, 7.0, 0.5, 0.6, 5.0],
    )
    I_total = 30.0 + 5.0
    k = Q_CYL * RHO_ARM**3 / I_total  # 1/rad: ≈ 1.004
    r0, T, dt = 1.5, 10.0, 0.01
    tr = hydrokit.simulate(v, T, dt, nu0=[0, 0, 0, 0, 0, r0], attitude=attitude, integrator="rk4")
    t = tr.time
    r_exact = r0 / (1 + k * r0 * t)
    psi_exact = np.log1p(k * r0 * t) / k
    # RK4 at k r0 dt = 0.015 (global error O(dt⁴)) meets the closed form to ~4e-10 in r and
    # ~4e-9 in ψ; rtol 1e-8 leaves a margin for the platform's round-off, while a wrong law
    # (ρ² instead of ρ³) would be off by 25 % in r(T)
    np.testing.assert_allclose(tr.nu[:, 5], r_exact, rtol=1e-8)
    np.testing.assert_allclose(np.unwrap(tr.eta[:, 5]), psi_exact, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(tr.nu[:, :5], 0.0, atol=1e-12)  # stays a pure yaw
    assert r_exact[-1] < 0.1 * r0  # the run covers most of the decay


# ---------------------------------------------------------------------------- stacked paths
def _with(v: Vehicle, *rows: tuple[str, tuple, tuple]) -> Vehicle:
    return dataclasses.replace(v, drag_elements=tuple(DragElement(n, p, quadratic=q) for n, p, q in rows))


def test_batch_pads_vehicles_with_fewer_elements() -> None:
    base = vehicle(linear_damping=[5, 5, 5, 1, 1, 1])
    vs = [
        base,
        _with(base, ("a", (0.0, 0.75, 0.0), (83.28, 0.0, 0.0))),
        _with(base, ("a", (0.5, 0.0, 0.1), (10.0, 20.0, 30.0)), ("b", (-0.5, 0.2, 0.0), (5.0, 60.0, 0.0))),
    ]
    tau = [10, 5, 0, 0, 0, 3]
    res = hydrokit.simulate_batch(vs, duration=3.0, dt=0.01, tau=tau, output_every=10)
    finals = []
    for i, v in enumerate(vs):
        one = hydrokit.simulate(v, 3.0, 0.01, tau=tau, output_every=10)
        # the same compiled run, with zero padding never read: equal to round-off
        np.testing.assert_allclose(res.states[i], np.column_stack([one.eta, one.nu]), rtol=0, atol=1e-12)
        finals.append(one.nu[-1])
    assert not np.allclose(finals[0], finals[1]) and not np.allclose(finals[1], finals[2])


@pytest.fixture(scope="module")
def mission_and_vehicles():  # noqa: ANN201
    mis = hydrokit.load_mission("lingyun_path")
    veh = hydrokit.load_vehicle(mis.vehicle)
    return mis, [
        _with(veh, ("arm", (0.0, 0.75, 0.0), (83.28, 0.0, 0.0)), ("fin", (-1.0, 0.0, 0.2), (0.0, 40.0, 0.0))),
        veh,
        _with(veh, ("arm", (0.0, -0.75, 0.0), (83.28, 0.0, 0.0))),
    ]


def test_closed_loop_compiled_equals_python_with_elements(mission_and_vehicles) -> None:  # noqa: ANN001
    # the compiled closed loop carries its own (numba-cached) copy of the right-hand side
    from hydrokit.simulate.mission import fly_mission

    mis, vs = mission_and_vehicles
    a = fly_mission(mis, vs[0], duration=8.0)
    b = fly_mission(mis, vs[0], duration=8.0, loop="python")
    np.testing.assert_allclose(a.eta, b.eta, rtol=0, atol=1e-9)
    plain = fly_mission(mis, vs[1], duration=8.0)
    assert np.max(np.abs(a.eta - plain.eta)) > 1e-3  # the elements change the flight


def test_fleet_pads_vehicles_with_fewer_elements(mission_and_vehicles) -> None:  # noqa: ANN001
    from hydrokit.simulate.fleet import fly_fleet
    from hydrokit.simulate.mission import fly_mission

    mis, vs = mission_and_vehicles
    fleet = fly_fleet(mis, vs, duration=8.0, paths_every=mis.output_every)
    assert fleet.paths is not None
    for i, v in enumerate(vs):
        one = fly_mission(mis, v, duration=8.0)
        np.testing.assert_allclose(fleet.paths[i], one.eta, rtol=0, atol=1e-12)


def test_linearization_sees_the_elements() -> None:
    # linearize differences the compiled right-hand side: the element's Jacobian must appear
    from hydrokit.simulate.linearize import linearize

    L = 8.0
    base = vehicle(linear_damping=[1, 1, 1, 1, 1, 1])
    v = vehicle([{"name": "arm", "position": [0, RHO_ARM, 0], "linear": [L, 0, 0]}], linear_damping=[1] * 6)
    A0, A1 = linearize(base, trim=[0.5, 0, 0, 0, 0, 0]).A, linearize(v, trim=[0.5, 0, 0, 0, 0, 0]).A
    dA = v.M @ (A1 - A0)[6:, 6:]  # ∂(wrench)/∂ν of the element alone
    expected = np.zeros((6, 6))
    # f_x = −L (u − r ρ): ∂X/∂u = −L, ∂X/∂r = Lρ; N = −ρ f_x: ∂N/∂u = Lρ, ∂N/∂r = −Lρ²
    expected[0, 0], expected[0, 5], expected[5, 0], expected[5, 5] = -L, L * RHO_ARM, L * RHO_ARM, -L * RHO_ARM**2
    np.testing.assert_allclose(dA, expected, atol=1e-6)  # central differences with a 1e-6 step


def test_pack_elements_round_trip() -> None:
    els = (DragElement("a", (1.0, 2.0, 3.0), (4.0, 5.0, 6.0), (7.0, 8.0, 9.0)),)
    np.testing.assert_array_equal(pack_elements(els), [[1, 2, 3, 4, 5, 6, 7, 8, 9]])


def test_export_says_the_elements_are_left_out() -> None:
    # Gazebo's Hydrodynamics system and uuv_simulator's fossen model have no point drag: the
    # files say which elements they leave out instead of dropping them silently
    from hydrokit.io.export import gazebo_sdf, uuv_parameters

    v = vehicle([{"name": "arm-port", "position": [0, -0.75, 0], "quadratic": [83.28, 0, 0]}])
    for text in (gazebo_sdf(v), uuv_parameters(v)):
        assert "1 point drag element(s) (drag_elements) are not representable here" in text
        assert "arm-port" in text
    assert "drag_elements" not in gazebo_sdf(vehicle())
