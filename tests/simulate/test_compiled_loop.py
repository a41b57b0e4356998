"""The compiled closed loop against the Python reference loop.

Every bundled mission, with both controllers, is flown both ways; every state, set-point,
τ and thruster column agrees to 1e-9 of the column's scale, the saturation flags, legs and
waypoint times match and so do the metrics.

Propeller commands are compared through n|n| (what the thrust is proportional to) rather
than n: the inverse n = sign(f)·√(|f|/k) has an infinite slope at f = 0, so a structurally
zero demand (a thruster with no share of τ) computed as ±1e-14 N by one loop and ∓3e-14 N by
the other (round-off of the allocation product in a different order) gives commands of
±5e-7 rev/s — 2e-8 of the 25 rev/s range, while the thrust itself agrees to 1e-15.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from hydrokit import load_mission, load_vehicle
from hydrokit.errors import InputError, SimulationError
from hydrokit.model.allocation import Allocator, _ConstrainedSolver
from hydrokit.model.control import PID, AxisState, SPlane
from hydrokit.model.thrusters import IdealCurve, PropellerCurve, TableCurve, Thruster, ThrusterSet
from hydrokit.simulate.closed_loop import ClosedLoopResult
from hydrokit.simulate.compiled_loop import _constrained, run_closed_loop_compiled
from hydrokit.simulate.mission import MissionResult, fly_mission

DATA = Path(__file__).resolve().parents[2] / "src" / "hydrokit" / "data"
MISSIONS = ["minerva_square", "lingyun_path", str(DATA / "projects" / "udrobot" / "mission.yaml")]
TOL = 1e-9
COLUMNS = ("eta", "nu", "reference", "tau_demand", "thrust_demand", "thrust", "command_demand", "command")


def _fly_both(mission, vehicle, kind, **kw):  # noqa: ANN001, ANN202
    a = fly_mission(mission, vehicle, kind, loop="python", **kw)
    b = fly_mission(mission, vehicle, kind, loop="compiled", **kw)
    return a, b


def _disagreement(
    a: MissionResult | ClosedLoopResult, b: MissionResult | ClosedLoopResult, th: ThrusterSet
) -> dict[str, float]:
    """Largest |difference| / column scale of each block (propeller commands as n|n|)."""
    prop = np.array([isinstance(cv, PropellerCurve) for cv in th.curves])
    cmax = th.command_max
    ra = a.run if isinstance(a, MissionResult) else a
    rb = b.run if isinstance(b, MissionResult) else b
    out = {}
    for name in COLUMNS:
        x, y = getattr(ra, name), getattr(rb, name)
        assert x.shape == y.shape, name
        if name.startswith("command"):
            x = np.where(prop, x * np.abs(x) / cmax**2, x)
            y = np.where(prop, y * np.abs(y) / cmax**2, y)
        col = np.abs(x).max(axis=0)
        scale = np.maximum(col, 1e-12 * max(float(col.max()), 1e-300))
        out[name] = float(np.max(np.abs(x - y) / scale))
    return out


@pytest.fixture(scope="module")
def bundled() -> dict[str, tuple]:
    out = {}
    for name in MISSIONS:
        mis = load_mission(name)
        out[name] = (mis, load_vehicle(mis.vehicle))
    return out


@pytest.mark.parametrize("kind", ["pid", "s-plane"])
@pytest.mark.parametrize("name", MISSIONS, ids=["minerva_square", "lingyun_path", "udrobot"])
def test_bundled_missions_agree(bundled, name: str, kind: str) -> None:
    mis, veh = bundled[name]
    a, b = _fly_both(mis, veh, kind)
    np.testing.assert_array_equal(a.run.time, b.run.time)
    worst = _disagreement(a, b, veh.thrusters)
    assert max(worst.values()) < TOL, worst
    np.testing.assert_array_equal(a.run.limited, b.run.limited)
    np.testing.assert_array_equal(a.run.leg, b.run.leg)
    assert a.run.thruster_names == b.run.thruster_names and a.run.dt == b.run.dt
    assert a.metrics.keys() == b.metrics.keys()
    for key, va in a.metrics.items():
        vb = b.metrics[key]
        if key == "waypoint_times":
            assert [t is None for t in va] == [t is None for t in vb]
            assert all(t is None or t == pytest.approx(u, rel=TOL, abs=TOL) for t, u in zip(va, vb))
        elif isinstance(va, float):
            assert vb == pytest.approx(va, rel=TOL, abs=1e-12), key
        else:
            assert va == vb, key


def test_saturating_mission_agrees(bundled) -> None:
    """Double speed and stiff gains: the constrained allocation (BVLS + polishing) runs on
    a good share of the steps, and both loops still agree."""
    mis, veh = bundled["lingyun_path"]
    gains = {k: {loop: dict(g) for loop, g in v.items()} for k, v in mis.gains.items()}
    for g in gains["pid"].values():
        g["kp"] *= 4
    path = dataclasses.replace(mis.path, speeds=mis.path.speeds * 2.0)
    # weighted pseudo-inverse too (a larger weight uses a thruster less)
    hard = dataclasses.replace(mis, gains=gains, path=path, weights=(1.0, 2.0, 1.0, 0.5))
    a, b = _fly_both(hard, veh, "pid", duration=120.0)
    assert a.metrics["saturation_fraction"] > 0.2
    fmin, fmax = veh.thrusters.f_min, veh.thrusters.f_max
    at_limit = np.isclose(a.run.thrust_demand, fmax) | np.isclose(a.run.thrust_demand, fmin)
    assert at_limit.any(axis=1).sum() > 50  # the constrained solution put thrusters at a limit
    worst = _disagreement(a, b, veh.thrusters)
    assert max(worst.values()) < TOL, worst
    np.testing.assert_array_equal(a.run.limited, b.run.limited)
    assert b.metrics["saturation_time"] == pytest.approx(a.metrics["saturation_time"], rel=TOL)


def _random_set(m: int, seed: int) -> ThrusterSet:
    rng = np.random.default_rng(seed)
    curves = [IdealCurve(), TableCurve((-1.0, 0.0, 1.0), (-30.0, 0.0, 40.0))]
    ths = []
    for i in range(m):
        ths.append(
            Thruster(
                name=f"T{i}",
                position=tuple(rng.normal(size=3) * 0.3),  # type: ignore[arg-type]
                direction=tuple(rng.normal(size=3)),  # type: ignore[arg-type]
                max_thrust=float(rng.uniform(20, 60)),
                min_thrust=-float(rng.uniform(10, 40)),
                curve=curves[i % 2],
            )
        )
    return ThrusterSet(tuple(ths))


@pytest.mark.parametrize("m,seed", [(4, 1), (6, 2), (8, 3), (12, 4), (16, 5)])
def test_compiled_constrained_allocation_matches_scipy(m: int, seed: int) -> None:
    """The BVLS port gives scipy's constrained allocation, also with more thrusters than DOF.

    Both stages agree to round-off. The last step (polishing: free thrusters get the exact
    minimum-norm solution, kept only if it stays within the limits) has a knife edge when a
    free thruster's polished value lands on its limit (±1e-13 N): then one side keeps the
    polished point and the other the stage-2 point, which differ by the stage-2 penalty bias
    (~1e-6 relative). With 12–16 random thrusters that happens in a few of the 40 draws
    (none with ≤ 8); the two answers are then equally good (the same weighted residual to
    1e-8, the size of that bias).
    """
    th = _random_set(m, seed)
    T = th.configuration_matrix()
    al = Allocator(T, th.f_min, th.f_max)
    s = _ConstrainedSolver(al.T, al.f_min, al.f_max, al.Q)
    lo_s, hi_s = s.bounds
    rng = np.random.default_rng(seed + 100)
    span = float(np.max(th.f_max))
    edges = 0
    for _ in range(40):
        tau = rng.normal(size=6) * span * rng.uniform(0.5, 4.0)
        ref = s.solve(tau)[0]
        got = _constrained(
            tau,
            np.asfortranarray(T),
            al.f_min,
            al.f_max,
            lo_s,
            hi_s,
            s.Q,
            np.asfortranarray(s.QT),
            np.asfortranarray(s.A),
            s.scale,
            s.thrust_scale,
            s.q_max,
            s.polish_tol,
        )
        if np.max(np.abs(got - ref)) <= TOL * span:
            continue
        edges += 1
        assert np.all(got >= al.f_min) and np.all(got <= al.f_max)
        q_ref = np.linalg.norm(s.Q * (T @ ref - tau))
        q_got = np.linalg.norm(s.Q * (T @ got - tau))
        assert q_got == pytest.approx(q_ref, rel=1e-8, abs=1e-8)
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-4 * span)
    assert edges <= (0 if m <= 8 else 10), edges


class _Custom:
    """An axis controller the compiled loop does not know."""

    def initial_state(self) -> AxisState:
        return AxisState()

    def update(self, state, measurement, setpoint, dt, rate=None):  # noqa: ANN001, ANN201
        return -10.0 * (measurement - setpoint), state


def test_unsupported_controller_falls_back_or_raises(bundled, monkeypatch) -> None:
    mis, veh = bundled["lingyun_path"]
    ap = dataclasses.replace(mis.autopilot("pid"), roll=_Custom())
    with pytest.raises(InputError, match="roll loop is a _Custom"):
        run_closed_loop_compiled(veh, veh.thrusters, ap, mis.path, mis.eta0, mis.nu0, duration=1.0, dt=mis.dt)
    monkeypatch.setattr(type(mis), "autopilot", lambda self, kind=None: ap)
    with pytest.warns(UserWarning, match="flying the Python loop"):
        res = fly_mission(mis, veh, "pid", duration=1.0)
    assert res.run.time[-1] == pytest.approx(1.0)


def test_progress_and_bad_loop(bundled) -> None:
    mis, veh = bundled["minerva_square"]
    seen: list[float] = []
    res = fly_mission(mis, veh, "pid", duration=10.0, progress=seen.append)
    assert len(seen) > 10 and seen == sorted(seen) and seen[-1] == pytest.approx(res.run.time[-1])
    with pytest.raises(InputError, match="loop = 'numba'"):
        fly_mission(mis, veh, "pid", duration=1.0, loop="numba")


def test_divergence_names_the_time_like_the_python_loop(bundled) -> None:
    mis, veh = bundled["lingyun_path"]
    gains = {k: {loop: dict(g) for loop, g in v.items()} for k, v in mis.gains.items()}
    bad = dataclasses.replace(mis, gains=gains, dt=20.0)  # RK4 far beyond its stability limit
    msgs = []
    for loop in ("python", "compiled"):
        with warnings.catch_warnings(), pytest.raises(SimulationError, match="non-finite at t = ") as err:
            warnings.simplefilter("ignore", RuntimeWarning)
            fly_mission(bad, veh, "pid", duration=20000.0, loop=loop)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


@pytest.mark.parametrize("kind", ["pid", "s-plane"])
def test_output_every_stop_when_done_roll_pitch_loops(bundled, kind: str) -> None:
    """Decimation, stopping at the last waypoint, a current on the thrusters' inflow and the
    optional roll and pitch hold loops (PID with anti-windup / S-plane)."""
    from hydrokit.simulate.closed_loop import run_closed_loop
    from hydrokit.simulate.compiled import make_dynamics

    mis, veh = bundled["minerva_square"]
    hold = (
        PID(kp=20.0, ki=2.0, kd=5.0, output_min=-3.0, output_max=3.0, angle=True)
        if kind == "pid"
        else SPlane(k1=4.0, k2=1.0, scale=3.0, angle=True)
    )
    ap = dataclasses.replace(mis.autopilot(kind), roll=hold, pitch=hold)
    kw = dict(duration=400.0, dt=mis.dt, current_ned=[0.05, -0.08, 0.01], output_every=7, stop_when_done=True)
    a = run_closed_loop(make_dynamics(veh, kw["current_ned"]), veh.thrusters, ap, mis.path, mis.eta0, mis.nu0, **kw)
    b = run_closed_loop_compiled(veh, veh.thrusters, ap, mis.path, mis.eta0, mis.nu0, **kw)
    assert a.time.shape == b.time.shape and a.time[-1] < 400.0
    np.testing.assert_array_equal(a.limited, b.limited)
    worst = _disagreement(a, b, veh.thrusters)
    assert max(worst.values()) < TOL, worst
    assert a.waypoint_times == pytest.approx(b.waypoint_times)
    assert math.isclose(a.dt, b.dt)


@pytest.mark.parametrize("ctl", [PID(kp=1.0), SPlane(k1=1.0, k2=0.0, scale=1.0)])
def test_controllers_are_supported(ctl) -> None:  # noqa: ANN001
    from hydrokit.simulate.compiled_loop import unsupported_reason

    th = _random_set(4, 0)
    from hydrokit.model.control import Autopilot

    assert unsupported_reason(th, Autopilot(speed=ctl, depth=ctl, heading=ctl)) is None


def test_cli_loop_option(run_cli, tmp_path: Path) -> None:  # noqa: ANN001
    """``hydrokit mission --loop compiled|python``: the same trajectory CSV and metrics."""
    import json

    out = {}
    for loop in ("python", "compiled"):
        d = tmp_path / loop
        code, _, err = run_cli("mission", "minerva_square", "--out", d, "--duration", 20, "--no-plots", "--loop", loop)
        assert code == 0, err
        text = (d / "trajectory.csv").read_text(encoding="utf-8").splitlines()
        header = [line for line in text if not line.startswith("#")][0]
        rows = np.loadtxt(text, delimiter=",", comments="#", skiprows=text.index(header) + 1)
        out[loop] = (header, rows, json.loads((d / "metrics.json").read_text(encoding="utf-8")))
    (h_py, a, m_py), (h_c, b, m_c) = out["python"], out["compiled"]
    assert h_py == h_c and a.shape == b.shape
    # to the CSV's printed digits; absolute 1e-6 for the round-off-sized entries (a command
    # of ±5e-7 rev/s for a thrust demand of ±1e-14 N, a lateral position of 1e-15 m)
    assert np.all(np.abs(a - b) <= 1e-6 * np.abs(a).max(axis=0) + 1e-6)
    assert m_py["controllers"]["PID"]["cross_track_rms"] == pytest.approx(
        m_c["controllers"]["PID"]["cross_track_rms"], rel=TOL
    )
    code, _, err = run_cli("mission", "minerva_square", "--out", tmp_path / "x", "--loop", "numba")
    assert code == 2
    assert err.splitlines() == [
        "error: Invalid value for '--loop': 'numba' is not one of 'compiled', 'python'. (see 'hydrokit mission --help')"
    ]
    assert not (tmp_path / "x").exists()
