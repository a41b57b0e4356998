"""The compiled manoeuvre loop (issue #50 item 2) against the Python loop.

Second method: the Python loop (:class:`hydrokit.manoeuvre.run._PythonLoop`, RK4 by
``integrators.rk4_step`` around ``make_dynamics``) flies the same manoeuvre; both call the same
laws (:mod:`hydrokit.manoeuvre.laws`), one as Python and one compiled, so the records
agree to rounding: rtol 1e-9 (the only differences are the order of a few floating-point
operations, ~1e-15 per step, grown over at most a few tens of thousands of steps of a stable
manoeuvre; measured ≤ 3e-12 on a 46 000-step REMUS spiral).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.api import load_vehicle
from hydrokit.errors import InputError
from hydrokit.manoeuvre import laws as L
from hydrokit.manoeuvre import run as M
from hydrokit.manoeuvre.samples import numeric_metrics

REMUS = {"tau": (3.86, 0, 0, -0.543, 0, 0), "nu0": (1.5, 0, 0, 0, 0, 0), "dt": 0.05}
MARINER = {"tau": (727000.0, 0, 0, 0, 0, 0), "nu0": (7.7, 0, 0, 0, 0, 0), "dt": 0.5}
rad = math.radians
#: as interpreted Python (NUMBA_DISABLE_JIT, the coverage run) each case flies both loops through
#: the interpreted right-hand side: only the Mariner's short turn runs there
SLOW = pytest.mark.needs_jit(reason="both loops of a long manoeuvre through the interpreted right-hand side")
CASES = {
    "turning circle (depth held)": ("remus100", M.turning_circle(rad(15)), REMUS),
    "zigzag 15/15": ("remus100", M.zigzag(rad(15), rad(15)), REMUS),
    "direct spiral, first steps": ("remus100", M.spiral("direct"), {**REMUS, "duration": 300.0}),
    "reverse spiral": ("mariner", M.spiral("reverse"), {**MARINER, "duration": 4000.0}),
    "pull-out": ("remus100", M.pull_out(rad(10)), REMUS),
    "depth change, closed loop": ("remus100", M.depth_change(5.0, rad(15), rad(20)), REMUS),
    "depth change, open loop": ("remus100", M.depth_change(-3.0, rad(15)), REMUS),
    "vertical zigzag": ("remus100", M.vertical_zigzag(rad(10), rad(10)), REMUS),
    "mariner turning circle": ("mariner", M.turning_circle(rad(35)), MARINER),
}


@pytest.mark.parametrize("case", [pytest.param(c, marks=() if c == "mariner turning circle" else SLOW) for c in CASES])
def test_compiled_loop_flies_as_the_python_loop(case):
    name, m, options = CASES[case]
    vehicle = load_vehicle(name)
    fast = M.run_manoeuvre(vehicle, m, **options)
    ref = M.run_manoeuvre(vehicle, m, compiled_loop=False, **options)
    assert fast.time.shape == ref.time.shape
    np.testing.assert_allclose(fast.array(), ref.array(), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(fast.executes, ref.executes, rtol=1e-9, atol=1e-9)
    a, b = numeric_metrics(fast.metrics), numeric_metrics(ref.metrics)
    assert a.keys() == b.keys() and a
    for k, v in b.items():
        assert (a[k] is None) == (v is None), k
        if v is not None:
            assert a[k] == pytest.approx(v, rel=1e-9, abs=1e-9), k
    assert fast.problem == ref.problem
    assert fast.hold == ref.hold


def test_the_compiled_laws_are_the_python_laws():
    """One implementation: each law the compiled loop calls is the code object of the Python law."""
    from hydrokit.manoeuvre import compiled as C

    for name in ("helm_command", "turn_command", "spiral_command", "pull_out_command", "keeper_command", "pid_law"):
        law = getattr(L, name, None) or getattr(__import__("hydrokit.model.control", fromlist=[name]), name)
        compiled = C._LAWS[name]
        assert getattr(compiled, "py_func", compiled).__code__ is law.__code__, name


def test_engine_refuses_a_force_of_the_state():
    from hydrokit.manoeuvre.compiled import Engine
    from hydrokit.simulate.compiled import make_dynamics

    v = load_vehicle("remus100")
    s = v.surfaces
    with pytest.raises(InputError, match="compiled manoeuvre loop takes a constant force"):
        M.fly_manoeuvre(
            make_dynamics(v),
            M.zigzag(rad(10), rad(10)),
            0,
            (s.max_deflection, s.rate_limit, s.time_constant),
            tau=lambda x: np.zeros(6),
            engine=Engine(v, np.zeros(6)),
        )


def test_a_force_of_the_state_keeps_the_python_loop(monkeypatch):
    """A τ(x) is not compiled: run_manoeuvre builds an Engine only for a constant force (or its
    own thruster drive), and flies τ(x) in the Python loop."""
    from hydrokit.manoeuvre import compiled as C

    built = []
    real = C.Engine
    monkeypatch.setattr(C, "Engine", lambda *a, **k: built.append(a) or real(*a, **k))
    v = load_vehicle("mariner")
    m = M.zigzag(rad(10), rad(10))
    const = M.run_manoeuvre(v, m, **MARINER)
    assert len(built) == 1
    force = np.asarray(MARINER["tau"], float)
    of_x = M.run_manoeuvre(v, m, **{**MARINER, "tau": lambda x: force})
    assert len(built) == 1
    np.testing.assert_allclose(of_x.array(), const.array(), rtol=1e-9, atol=1e-9)


#: REMUS 100 on its propeller at 694 rpm (11.567 rev/s) with the propeller's roll torque K (N·m)
REMUS_COMMAND = {"commands": {"propeller": 11.567}, "tau": (0, 0, 0, -0.543, 0, 0), "dt": 0.05}


@SLOW
def test_compiled_loop_flies_thruster_commands_as_the_python_loop(monkeypatch):
    """--command in the compiled loop: ThrusterDrive's law (rotor lag, K_T(J) at the advance speed,
    the configuration matrix) flown by the kernels from model/thrusters.py's laws, against the
    Python loop calling the same laws through ThrusterDrive. rtol 1e-9 as above (measured ~1e-14
    on this 15° turn)."""
    from hydrokit.manoeuvre import compiled as C

    built = []
    real = C.Engine
    monkeypatch.setattr(C, "Engine", lambda *a, **k: built.append(k) or real(*a, **k))
    v = load_vehicle("remus100")
    m = M.turning_circle(rad(15))
    fast = M.run_manoeuvre(v, m, **REMUS_COMMAND)
    assert len(built) == 1 and built[0].get("drive") is not None  # the compiled loop flew it
    ref = M.run_manoeuvre(v, m, compiled_loop=False, **REMUS_COMMAND)
    assert len(built) == 1
    assert fast.problem is None and ref.problem is None
    assert fast.time.shape == ref.time.shape
    np.testing.assert_allclose(fast.array(), ref.array(), rtol=1e-9, atol=1e-9)
    a, b = numeric_metrics(fast.metrics), numeric_metrics(ref.metrics)
    assert a.keys() == b.keys() and a
    for k, val in b.items():
        if val is not None:
            assert a[k] == pytest.approx(val, rel=1e-9, abs=1e-9), k
    for key in ("thrust_at_execute", "thrust_at_end"):
        assert fast.propulsion[key]["propeller"] == pytest.approx(ref.propulsion[key]["propeller"], rel=1e-9)
    # the rotor spun up from rest during the approach: at the end its thrust is the open-water
    # curve's at the held speed and the end's advance speed, a second evaluation of the law
    assert fast.propulsion["thrust_at_end"]["propeller"] > 0


def test_the_compiled_thruster_laws_are_the_python_laws():
    """One implementation: the compiled drive calls model/thrusters.py's laws' code objects."""
    from hydrokit.manoeuvre import compiled as C
    from hydrokit.model import thrusters as T

    for compiled, law in ((C._thruster_inputs, T.thruster_inputs), (C._rotor_lag, T.rotor_lag)):
        assert getattr(compiled, "py_func", compiled).__code__ is law.__code__
