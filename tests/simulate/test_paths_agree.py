"""Every path that flies a vehicle flies the same model (issue #56 items 1–2).

A matrix: vehicles that each carry one feature of the input vector — ``delta()``, ``T()`` and
``n()`` term factors, a physical fin, a rudder in the propeller race with each inflow (the
actuator disc and the MMG method), a propeller with rotor lag and wake, a table thruster, a
current, a planar ship and a 6-DOF AUV — flown by ``hydrokit manoeuvre``'s two loops (compiled and
Python). Each manoeuvre's own record (state, held deflections, held propeller command) is then
fed, step by step, to ``simulate``'s open-loop driver with thrusters
(:func:`hydrokit.simulate.commands.fly_commands`: the compiled right-hand side given τ and each
thruster's thrust and rotation rate at every RK4 stage): the two must agree to round-off, step
after step. The reference is a second path — not the same code run twice — so the tolerance is a
relative 1e-9 per step (round-off is ~1e-14; a dropped input moves a step by 1e-4 or more).

Then each feature's coefficient, moved, must move every path's result: the defect this guards
against (the manoeuvre loops set every thrust input to zero, so a ``T()`` term or a race rudder
changed nothing) changed the manoeuvre by 0.0 %. ``bench/paths.py`` prints the matrix.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from tests.simulate.test_sysid_propeller_rudder import RACE_RUDDER
from tests.simulate.test_sysid_surfaces import SHIP

#: the propeller speed the ships fly at, rev/s
N_PROP = 20.0
#: REMUS 100's propeller speed and torque trim (docs/manoeuvre.md), rev/s and N·m
REMUS = {"commands": {"propeller": 11.567}, "tau": (0, 0, 0, -0.543, 0, 0)}
#: a BlueROV2 T200-like table thruster pushing the ship (command –, thrust N)
TABLE_THRUSTER = {
    "name": "prop",
    "position": [-1.45, 0, 0],
    "direction": [1, 0, 0],
    "thrust_table": {"command": [-1.0, 0.0, 1.0], "thrust": [-20.0, 0.0, 25.0]},
    "max_thrust": 25.0,
    "min_thrust": -20.0,
}


def _ship(change: Callable[[dict[str, Any]], None]) -> dict[str, Any]:
    d = copy.deepcopy(SHIP)
    d["terms"] = {k: v for k, v in SHIP["terms"].items() if "delta" not in k}
    change(d)
    return d


def _terms(t: dict[str, float]) -> Callable[[dict[str, Any]], None]:
    return lambda d: d["terms"].update(t)


def _fin(slipstream: dict[str, Any] | None) -> Callable[[dict[str, Any]], None]:
    def change(d: dict[str, Any]) -> None:
        fin = {k: v for k, v in RACE_RUDDER.items() if k != "slipstream"}
        if slipstream is not None:  # a smaller rudder in the race: a turn of a few lengths, not a spin
            fin["slipstream"] = dict(slipstream)
            fin["area"] = 0.004
        d["control_surfaces"] = [fin]

    return change


def _rudder_terms(d: dict[str, Any]) -> None:
    d["terms"].update({"Y_uu*delta(rudder)": 40.0, "N_uu*delta(rudder)": -80.0})


def _both(*changes: Callable[[dict[str, Any]], None]) -> Callable[[dict[str, Any]], None]:
    def change(d: dict[str, Any]) -> None:
        for c in changes:
            c(d)

    return change


def _lag_wake(d: dict[str, Any]) -> None:
    _rudder_terms(d)
    d["thrusters"][0].update(time_constant=2.0, wake_fraction=0.3)


def _table(d: dict[str, Any]) -> None:
    _rudder_terms(d)
    d["thrusters"] = [copy.deepcopy(TABLE_THRUSTER)]


#: feature → (vehicle document change, the coefficient path to move, its factor, run options)
FEATURES: dict[str, tuple[Callable[[dict[str, Any]], None], tuple[Any, ...], float, dict[str, Any]]] = {
    "delta()": (_rudder_terms, ("terms", "N_uu*delta(rudder)"), 1.5, {}),
    "T()": (
        _terms({"Y_T(prop)*delta(rudder)": 0.15, "N_T(prop)*delta(rudder)": -0.3}),
        ("terms", "N_T(prop)*delta(rudder)"),
        1.5,
        {},
    ),
    "n()": (
        _terms({"Y_n(prop)*delta(rudder)": 0.04, "N_n(prop)*delta(rudder)": -0.08}),
        ("terms", "N_n(prop)*delta(rudder)"),
        1.5,
        {},
    ),
    "fin": (_fin(None), ("control_surfaces", 0, "area"), 1.5, {}),
    "race (actuator disc)": (_fin({"thruster": "prop"}), ("control_surfaces", 0, "area"), 1.5, {}),
    "race (MMG)": (_fin(RACE_RUDDER["slipstream"]), ("control_surfaces", 0, "slipstream", "kappa"), 1.6, {}),
    "propeller lag + wake": (_lag_wake, ("thrusters", 0, "wake_fraction"), 0.3, {}),
    "table thruster": (_table, ("thrusters", 0, "thrust_table", "thrust", 2), 1.3, {"command": 0.8}),
    "current": (_rudder_terms, ("terms", "N_uu*delta(rudder)"), 1.5, {"current_ned": [0.05, 0.02, 0.0]}),
}


def feature_vehicle(feature: str, scale: float = 1.0) -> Any:
    """The ship of ``feature`` with its coefficient times ``scale``."""
    from hydrokit.api import vehicle_from_dict

    change, where, _, _ = FEATURES[feature]
    d = _ship(change)
    node: Any = d
    for p in where[:-1]:
        node = node[p]
    node[where[-1]] = node[where[-1]] * scale
    return vehicle_from_dict(d, f"path-{feature}")


def fly(vehicle: Any, loop: bool, options: dict[str, Any], deflection_deg: float = 35.0, **kw: Any) -> Any:
    """A turning circle of ``deflection_deg`` (°) (cut at ``duration``) of ``vehicle`` by the compiled loop (``loop``
    True) or the Python loop; the propeller at :data:`N_PROP` unless ``options`` say."""
    from hydrokit.manoeuvre.definitions import turning_circle
    from hydrokit.manoeuvre.run import run_manoeuvre

    name = vehicle.thruster_names[0]
    opts = {"commands": {name: options.get("command", N_PROP)}, **kw}
    if "current_ned" in options:
        opts["current_ned"] = options["current_ned"]
    return run_manoeuvre(
        vehicle, turning_circle(math.radians(deflection_deg)), dt=0.05, approach=150.0, compiled_loop=loop, **opts
    )


def step_errors(vehicle: Any, res: Any, commands: dict[str, float], tau: Any = (0, 0, 0, 0, 0, 0), **kw: Any) -> float:
    """The largest relative difference between the manoeuvre's steps and ``simulate``'s from the
    same state with the same held deflections and propeller command (15 steps across the
    record, the rotors settled: the approach spun them up)."""
    from hydrokit.simulate.commands import CommandForce, command_table, fly_commands

    table = command_table(vehicle, commands)
    worst = 0.0
    for k in np.linspace(0, res.time.size - 2, 15).astype(int):
        dt = float(res.time[k + 1] - res.time[k])
        cf = CommandForce(vehicle.thrusters, table, force=tau, start="settled", current_ned=kw.get("current_ned"))
        tr = fly_commands(vehicle, dt, dt, cf, eta0=res.eta[k], nu0=res.nu[k], deflection=res.deflection[k], **kw)
        got = np.concatenate([tr.eta[-1], tr.nu[-1]])
        ref = np.concatenate([res.eta[k + 1], res.nu[k + 1]])
        worst = max(worst, float(np.max(np.abs(got - ref) / (1e-3 + np.abs(ref)))))
    return worst


def loops_for(feature: str) -> list[bool]:
    """The manoeuvre loops a feature flies in: both, or the Python loop alone where the compiled
    one hands over (a table curve, a current with thrusters: :func:`drive_compiles`)."""
    return [False] if feature in ("table thruster", "current") else [True, False]


@pytest.mark.parametrize("feature", list(FEATURES))
def test_manoeuvre_flies_simulates_model(feature: str) -> None:
    """Each loop's steps are simulate's steps, to round-off (module docstring)."""
    v = feature_vehicle(feature)
    _, _, _, options = FEATURES[feature]
    name = v.thruster_names[0]
    cmd = {name: options.get("command", N_PROP)}
    kw = {"current_ned": options["current_ned"]} if "current_ned" in options else {}
    for loop in loops_for(feature):
        res = fly(v, loop, options, duration=30.0)
        assert step_errors(v, res, cmd, **kw) < 1e-9, (feature, "compiled" if loop else "python")


@pytest.mark.parametrize("feature", list(FEATURES))
def test_a_features_coefficient_moves_every_path(feature: str) -> None:
    """The feature's coefficient, moved, moves the manoeuvre of every loop and simulate's run: the
    heading after 30 s of the turn changes by more than 0.1° (the thrust-blind loops changed it by
    0.0 for ``T()``, ``n()`` and the race)."""
    from hydrokit.simulate.commands import CommandForce, command_table, fly_commands

    _, _, factor, options = FEATURES[feature]
    base, moved = feature_vehicle(feature), feature_vehicle(feature, factor)
    name = base.thruster_names[0]
    cmd = {name: options.get("command", N_PROP)}
    for loop in loops_for(feature):
        a, b = fly(base, loop, options, duration=30.0), fly(moved, loop, options, duration=30.0)
        assert abs(a.eta[-1, 5] - b.eta[-1, 5]) > math.radians(0.1), (feature, loop)
    # simulate --command with the same rudder schedule (35° held after 5 s)
    kw = {"current_ned": options["current_ned"]} if "current_ned" in options else {}
    rows = np.array([[0.0, 0.0], [5.0, 0.0], [5.5, math.radians(35)], [40.0, math.radians(35)]])
    heads = []
    for v in (base, moved):
        cf = CommandForce(v.thrusters, command_table(v, cmd), current_ned=kw.get("current_ned"))
        tr = fly_commands(v, 40.0, 0.05, cf, nu0=(0.3, 0, 0, 0, 0, 0), deflection=rows, **kw)
        heads.append(float(tr.eta[-1, 5]))
    assert abs(heads[0] - heads[1]) > math.radians(0.1), feature


def test_a_six_dof_auv_flies_simulates_model() -> None:
    """The bundled REMUS 100 with physical fins (6 DOF, depth and pitch held by the stern planes,
    the propeller at 11.567 rev/s against its torque): the same step-by-step agreement."""
    from hydrokit.api import load_vehicle

    v = load_vehicle("remus100-fins")
    for loop in (True, False):
        opts = {"command": REMUS["commands"]["propeller"]}
        res = fly(v, loop, opts, deflection_deg=15.0, duration=10.0, tau=REMUS["tau"])
        assert step_errors(v, res, REMUS["commands"], tau=REMUS["tau"]) < 1e-9, loop


def test_the_bundled_mariner_agrees_with_simulate() -> None:
    """A planar ship from the bundled files (the Mariner, a constant force: no thrusters) by both
    loops against simulate's driver with the same held force and deflections."""
    from hydrokit.api import load_vehicle
    from hydrokit.manoeuvre.definitions import zigzag
    from hydrokit.manoeuvre.run import run_manoeuvre
    from hydrokit.simulate.driver import simulate

    v = load_vehicle("mariner")
    tau = (727000.0, 0, 0, 0, 0, 0)
    for loop in (True, False):
        res = run_manoeuvre(v, zigzag(math.radians(10), math.radians(10)), tau=tau, dt=0.5, compiled_loop=loop)
        worst = 0.0
        for k in np.linspace(0, res.time.size - 2, 10).astype(int):
            dt = float(res.time[k + 1] - res.time[k])
            tr = simulate(v, dt, dt, tau, eta0=res.eta[k], nu0=res.nu[k], deflection=res.deflection[k])
            got = np.concatenate([tr.eta[-1], tr.nu[-1]])
            ref = np.concatenate([res.eta[k + 1], res.nu[k + 1]])
            worst = max(worst, float(np.max(np.abs(got - ref) / (1e-3 + np.abs(ref)))))
        assert worst < 1e-9, loop


def test_simulate_with_commands_and_no_deflection_holds_the_surfaces_at_zero() -> None:
    """``fly_commands`` on a vehicle with control surfaces and no ``deflection`` (it failed with
    '0 deflections'): the same run as with every surface at zero given."""
    from hydrokit.simulate.commands import CommandForce, command_table, fly_commands

    v = feature_vehicle("race (MMG)")
    cf = CommandForce(v.thrusters, command_table(v, {"prop": N_PROP}))
    a = fly_commands(v, 5.0, 0.05, cf)
    b = fly_commands(v, 5.0, 0.05, cf, deflection=[0.0])
    np.testing.assert_array_equal(a.nu, b.nu)  # the same code run twice: bit for bit
    assert a.nu[-1, 0] > 0.1  # the propeller pushed it ahead


def test_missions_feed_the_thrust_to_the_model(tmp_path: Any) -> None:
    """A finned AUV with a ``T()`` term (rudder moment per N of thrust) on a mission: both closed
    loops (Python and compiled) and the fleet give the model each step's thrust and rotation
    rate (they gave none before issue #56), agree to round-off, and each recorded step is
    simulate's right-hand side fed the recorded state, thrust and deflections (an ideal thruster
    without lag: its thrust is held over the step, its rate 0); the term, moved, moves the run."""
    import yaml
    from tests.simulate.test_closed_loop_surfaces import AUV, MISSION

    import hydrokit
    from hydrokit.simulate.compiled import make_dynamics
    from hydrokit.simulate.fleet import fly_fleet
    from hydrokit.simulate.integrators import rk4_step
    from hydrokit.simulate.mission import fly_mission

    def load(n_t: float) -> tuple[Any, Any]:
        doc = copy.deepcopy(AUV)
        doc["terms"]["N_T(prop)*delta(rudder)"] = n_t
        v = tmp_path / f"auv{n_t}.yaml"
        v.write_text(yaml.safe_dump(doc))
        m = tmp_path / f"mission{n_t}.yaml"
        m.write_text(yaml.safe_dump(dict(MISSION, vehicle=str(v), duration=40)))
        return hydrokit.load_mission(m), hydrokit.load_vehicle(v)

    mission, vehicle = load(-0.05)
    a = fly_mission(mission, vehicle, loop="python")
    b = fly_mission(mission, vehicle, loop="compiled")
    np.testing.assert_allclose(b.eta, a.eta, rtol=0, atol=1e-9)  # two loops: round-off
    fleet = fly_fleet(mission, [vehicle], paths_every=mission.output_every)
    np.testing.assert_allclose(fleet.paths[0], b.eta, rtol=0, atol=1e-9)
    f = make_dynamics(vehicle)
    run, T = b.run, vehicle.thrusters.configuration_matrix()
    worst = 0.0
    for k in np.linspace(0, run.time.size - 2, 12).astype(int):
        x = np.concatenate([run.eta[k], run.nu[k]])
        thrust = run.thrust[k]
        d, rate = run.deflection[k], np.zeros(len(thrust))
        y = rk4_step(
            lambda t_, x_, u_, d=d, th=thrust, n=rate: f(t_, x_, u_, d, th, n), run.time[k], x, mission.dt, u=T @ thrust
        )
        ref = np.concatenate([run.eta[k + 1], run.nu[k + 1]])
        worst = max(worst, float(np.max(np.abs(y - ref) / (1e-3 + np.abs(ref)))))
    assert worst < 1e-9
    other = fly_mission(*load(-0.15), loop="compiled")
    assert float(np.max(np.abs(other.eta[:, 5] - b.eta[:, 5]))) > math.radians(0.5)


@pytest.mark.parametrize("feature", ["T()", "n()", "race (actuator disc)", "race (MMG)", "delta()", "fin"])
def test_transport_refuses_what_it_cannot_feed(feature: str) -> None:
    """The transport models feed no per-vehicle thrust: a part whose terms or race rudder read
    it is refused in one line instead of flown at zero thrust (issue #56); a deflection or a
    plain fin is no reason."""
    import dataclasses

    import hydrokit as hk
    from hydrokit.errors import InputError
    from hydrokit.model.dynamics import reads_thrust
    from hydrokit.simulate.transport import fly_transport

    v = feature_vehicle(feature)
    reads = feature in ("T()", "n()", "race (actuator disc)", "race (MMG)")
    assert bool(reads_thrust(v)) is reads
    asm = hk.load_assembly("rehman_transport")
    spoiled = dataclasses.replace(asm, bodies=(v, *asm.bodies[1:]))
    if reads:
        with pytest.raises(InputError, match="read its thrusters' thrust"):
            fly_transport(spoiled, 1.0, 0.1)
    else:
        assert fly_transport(asm, 1.0, 0.1).time.size > 1


def sysid_error(feature: str) -> float:
    """The largest difference, in each channel's standard deviation, between sysid's simulation
    of a run flown by ``simulate --command`` and logged at 1 Hz and that run (see below);
    ``feature`` "wind": the ``T()`` ship with a Blendermann wind model in a logged wind of 4 m/s
    from 60°."""
    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.runlog import RunLog
    from hydrokit.model.dynamics import environment_table
    from hydrokit.simulate.commands import CommandForce, command_table, fly_commands
    from hydrokit.sysid.model import CHANNELS, prepare_run, simulate_run, stack_packs

    wind = feature == "wind"
    if wind:
        from tests.simulate.test_acceptance_race_rudder import WIND

        change, *_ = FEATURES["T()"]
        doc = _ship(change)
        doc["wind"] = dict(WIND)
        v = vehicle_from_dict(doc, "path-wind")
    else:
        v = feature_vehicle(feature)
    dt, rudder = 0.05, math.radians(15.0)
    t_w = np.array([0.0, 40.0])
    speed, direction = np.full(2, 4.0), np.full(2, math.radians(60.0))
    env = environment_table(None, np.column_stack([t_w, speed, direction])) if wind else None
    cf = CommandForce(v.thrusters, command_table(v, {"prop": N_PROP}), start="settled", current_ned=env)
    tr = fly_commands(v, 40.0, dt, cf, nu0=(0.35, 0, 0, 0, 0, 0), current_ned=env, deflection=[rudder])
    every = int(round(1.0 / dt))
    t = tr.time[::every]
    x = np.concatenate([tr.eta, tr.nu], axis=1)[::every]
    chans = {c: (t, x[:, CHANNELS.index(c)]) for c in ("x", "y", "psi", "u", "v", "r")}
    logged = {"wind_speed": np.full(t.size, 4.0), "wind_direction": np.full(t.size, math.radians(60.0))}
    run = RunLog(
        "r",
        "",
        t,
        chans,
        {"prop": np.full(t.size, N_PROP)},
        deflections={"rudder": np.full(t.size, rudder)},
        environment=logged if wind else {},
    )
    prep = prepare_run(run, v.thrusters, dt, surfaces=v.surfaces.names)
    pred, done = simulate_run(prep, stack_packs([v]), np.concatenate([tr.eta[0], tr.nu[0]])[None, :])
    if done[0] != int(round(40.0 / dt)):
        return math.inf
    ref = np.concatenate(prep.values)
    scale = np.concatenate([np.full(y.size, np.std(y) + 1e-3) for y in prep.values])
    return float(np.max(np.abs(pred[0] - ref) / scale))


@pytest.mark.parametrize("feature", ["T()", "race (MMG)", "propeller lag + wake", "wind"])
def test_sysid_simulates_simulates_model(feature: str) -> None:
    """sysid's batch simulation of a run (the output-error fit's and the held-out prediction's)
    is simulate's model: a run flown by ``simulate --command`` (propeller at 20 rev/s, rotors
    settled, rudder held at 15°) and logged at 1 Hz, simulated by sysid from the same start,
    agrees to round-off at every sample. The propeller's thrust is evaluated at each stage's
    simulated advance speed (issue #56); before, sysid took it at the *logged* velocity
    interpolated between samples (here 1 s apart: a difference of ~1e-4 of the motion)."""
    err = sysid_error(feature)
    assert err < 1e-9, err
