"""Acceptance of issue #48: a generated ship with a rudder in its propeller's race (MMG inflow), a
wind-load model flown in a logged wind and a right-handed propeller's asymmetry (the rudder's
neutral deflection) is identified within its stated σ, and its turning circle is predicted inside
the interval drawn from the fit's covariance.

The truth flies random zigzag-like rudder schedules at a constant propeller speed in a gusty
wind whose speed and direction are logged in the runs (:func:`wind_ship_runs`; the compiled
RK4 at 0.01 s, the thrust at the true advance speed, Gaussian sensor noise of
:data:`~hydrokit.sysid.ship.SHIP_NOISE` at 10 Hz, fixed seeds). The fit (0.02 s) starts
25–30 % off on four parameters — the rudder's lift slope and neutral deflection (from 0), the
hull's Y_uv and N_ur — with everything else the truth's (the wind model included), so what is
left is the sensor noise: each fitted value must lie within k = 3 of its stated σ, and each σ be
small (< 20 % of the value; < 0.5° for the neutral deflection of 1.5°), or the test could not
fail. The 35° turning circle to either side (the propeller makes them differ by 9 %, as the
Esso Osaka trials did) is then flown by the truth and by 24 vehicles drawn from the fit's
covariance (``manoeuvre --samples``' :func:`~hydrokit.manoeuvre.samples.add_intervals`):
the truth's advance and tactical diameter must lie inside the draws' 95 % interval, which must
be narrower than 30 % of the value.

Over seeds 11–20 (``bench/race_rudder_acceptance.py``) the parameters first missed the truth by
1.4 of their stated σ (RMS): the fit took each run's start position from the smoother (about 1 cm
off) and held it. The start position is now estimated with the other initial states, and the
misses came down to 1.17, 1.01, 0.99 and 0.94 σ (RMS per parameter) — honest σ. The test runs
seed 13 and a change that widens the misses fails it.
"""

from __future__ import annotations

import copy
import math
from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from tests.simulate.test_sysid_propeller_rudder import RACE_RUDDER
from tests.simulate.test_sysid_surfaces import SHIP

from hydrokit.io.runlog import RunLog
from hydrokit.model.uncertainty import make_uncertainty, parameter_value, with_coefficients
from hydrokit.sysid.model import CHANNELS, force_table, stack_packs
from hydrokit.sysid.ship import SHIP_NOISE

#: the right-handed propeller's side force and the race's swirl, as a neutral rudder of 1.5° to
#: starboard (negative: hydrokit's positive rudder turns the ship to port); Esso Osaka's pond
#: model needed about 1° (issue #48)
NEUTRAL_DEG = -1.5
#: the model's superstructure (our numbers, a 3 m tanker model: A_F, A_L in m², L_oa in m) with
#: Blendermann's (1994) loaded tanker
WIND: dict[str, Any] = {
    "frontal_area": 0.06,
    "lateral_area": 0.4,
    "length": 3.0,
    "model": "blendermann1994",
    "vessel": "tanker_loaded",
    "s_L": 0.1,
}
#: the hull's yaw terms, made to turn in a tactical diameter of about 6 lengths (SHIP's own turn
#: in 17, which takes minutes to fly): N·s/rad·… SI as SHIP's ``terms``
HULL = {"N_ur": -300.0, "Y_ur": 60.0}
#: the fitted names, and the start of the fit relative to the truth
FREE = {
    "control_surfaces.rudder.lift_slope": 0.75,
    "control_surfaces.rudder.neutral_deflection_deg": 0.0,
    "terms.Y_uv": 0.7,
    "terms.N_ur": 1.3,
}
#: propeller speed, rev/s; approach speed, m/s
N_PROP, U0 = 20.0, 0.37
#: the runs' seed, the draws per turning circle, and the k of "within k σ"
SEED, DRAWS, K = 13, 24, 3.0


def wind_ship(**changes: Any) -> Any:
    """The race-rudder ship of :mod:`tests.simulate.test_sysid_propeller_rudder` with a neutral
    rudder and a wind-load model; ``changes`` replace top-level fields of its file."""
    from hydrokit.api import vehicle_from_dict

    d = copy.deepcopy(SHIP)
    d["control_surfaces"] = [{**copy.deepcopy(RACE_RUDDER), "neutral_deflection_deg": NEUTRAL_DEG}]
    d["terms"] = {k: v for k, v in SHIP["terms"].items() if "delta" not in k}
    d["terms"].update(HULL)
    d["wind"] = copy.deepcopy(WIND)
    d.update(changes)
    return vehicle_from_dict(d, "wind-ship")


def wind_ship_runs(
    truth: Any,
    n_runs: int,
    duration: float,
    seed: int,
    wind_speed: float = 2.5,
    dt: float = 0.01,
    noise: float = 1.0,
) -> list[RunLog]:
    """Zigzag-like runs of ``truth`` in a logged gusty wind (m/s; its direction turning slowly
    through a quarter of the compass), at a constant propeller speed, with the sensor noise of
    :data:`~hydrokit.sysid.ship.SHIP_NOISE` × ``noise`` at 10 Hz. The thrust is the propeller's
    curve at the true advance speed (six fixed-point passes, as
    :func:`hydrokit.sysid.ship.ship_runs` does); the wind acts through the vehicle's own
    wind model on the compiled RK4."""
    from hydrokit.model.dynamics import environment_table
    from hydrokit.simulate.compiled import no_drive, rk4_run

    rng = np.random.default_rng(seed)
    packs = stack_packs([truth])
    args = [packs[k][0] for k in ("Minv", "Mc", "DL", "DQ", "scal")]
    terms = (packs["t_dof"], packs["t_coef"][0], packs["t_kind"], packs["t_idx"])
    time = np.round(np.arange(0.0, duration + 1e-9, 0.1), 9)
    n_steps = int(round(duration / dt))
    rows = np.round(time / dt).astype(int)
    out = []
    for k in range(n_runs):
        delta = np.empty(time.size)
        t, sign = 0.0, float(rng.choice([-1.0, 1.0]))
        while t < duration + 1e-9:
            length = rng.uniform(3.0, 8.0)
            delta[(time >= t - 1e-9) & (time < t + length - 1e-9)] = sign * rng.uniform(0.3, 1.0) * math.radians(25)
            t += length
            sign = -sign
        phase = rng.uniform(0, 2 * math.pi, 3)
        speed = wind_speed * (1 + 0.2 * np.sin(2 * math.pi * time / 17 + phase[0]) + 0.1 * np.sin(time + phase[1]))
        direction = phase[2] + 0.5 * math.pi * time / duration
        env = {"wind_speed": speed, "wind_direction": direction}
        cur = environment_table(None, np.column_stack([time, speed, direction]))
        commands = {"prop": np.full(time.size, N_PROP)}
        x0 = np.zeros(12)
        x0[5], x0[6] = rng.uniform(-math.pi, math.pi), U0
        chans: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        states = np.zeros((time.size, 12))
        for _ in range(6):
            probe = RunLog(f"run{k + 1}", "", time, chans, commands, deflections={"rudder": delta})
            table = force_table(probe, truth.thrusters, dt, truth.surfaces.names)
            full = np.empty((n_steps + 1, 12))
            x = np.ascontiguousarray(x0)
            done = rk4_run(x, 0.0, dt, n_steps, 1, False, table, cur, (*args, *terms), no_drive(), full)
            assert done == n_steps, "the truth diverged"
            states = full[rows]
            chans = {c: (time, states[:, CHANNELS.index(c)]) for c in ("u", "v", "r")}
        logged = {
            c: (time, states[:, CHANNELS.index(c)] + noise * s * rng.standard_normal(time.size))
            for c, s in SHIP_NOISE.items()
        }
        out.append(RunLog(f"run{k + 1}", "", time, logged, commands, deflections={"rudder": delta}, environment=env))
    return out


def turn(vehicle: Any, side: float) -> Any:
    """A 35° turning circle (``side`` +1: rudder to port, −1: to starboard) at the propeller's
    speed, in still air, flown for 110 s after the execute: past the 180° that the advance and the
    tactical diameter need (the steady turn, at 540°, is not waited for)."""
    from hydrokit.manoeuvre import run as M

    return M.run_manoeuvre(
        vehicle,
        M.turning_circle(side * math.radians(35)),
        commands={"prop": N_PROP},
        nu0=(U0, 0, 0, 0, 0, 0),
        dt=0.2,
        duration=110.0,
    )


def identify_and_predict(seed: int, draws: int = DRAWS) -> tuple[Any, Any, dict[float, tuple[Any, Any]]]:
    """The truth, its fit from two 40 s runs (``seed``) and per side (+1, −1) the truth's turning
    circle and the fitted vehicle's with ``draws`` draws from the fit's covariance."""
    from hydrokit.manoeuvre.samples import add_intervals
    from hydrokit.sysid.fit import identify

    truth = wind_ship()
    runs = wind_ship_runs(truth, 2, 40.0, seed=seed)
    start = with_coefficients(truth, {n: (f * parameter_value(truth, n) if f else 0.0) for n, f in FREE.items()})
    res = identify(start, runs, list(FREE), dt=0.02, samples=0, check_step=False, window=None)
    v = res.vehicle
    unc = make_uncertainty(
        list(res.parameters), res.covariance, {}, "fit", surfaces=tuple(v.surfaces.names), thrusters=v.thruster_names
    )
    fitted = replace(v, uncertainty=unc)
    turns = {}
    for side in (1.0, -1.0):
        predicted = replace(turn(fitted, side), warnings=[])
        add_intervals(predicted, fitted, draws, seed, lambda veh, side=side: turn(veh, side))
        turns[side] = (turn(truth, side), predicted)
    return truth, res, turns


@pytest.mark.needs_jit(reason="two 40 s runs fitted by output error, then 52 turning circles")
def test_a_race_rudder_ship_in_wind_is_identified_within_sigma_and_its_turns_predicted_inside_the_interval() -> None:
    truth, res, turns = identify_and_predict(SEED)
    for name, value, sigma in zip(res.parameters, res.values, res.sigma):
        true = parameter_value(truth, name)
        small = 0.5 if name.endswith("_deg") else 0.2 * abs(true)
        assert 0 < sigma < small, (name, sigma, true)
        assert abs(value - true) < K * sigma, (name, value, sigma, true)
    for side, (true, predicted) in turns.items():
        for metric in ("advance", "tactical_diameter"):
            iv = predicted.intervals[metric]
            m = true.metrics[metric]
            assert iv["samples"] == DRAWS
            assert iv["low95"] < m < iv["high95"], (metric, side, iv, m)
            assert iv["high95"] - iv["low95"] < 0.3 * m, (metric, side, iv, m)
    # the right-handed propeller: the turn to starboard is the wider one, in the truth and the fit
    assert turns[-1.0][0].metrics["tactical_diameter"] > 1.05 * turns[1.0][0].metrics["tactical_diameter"]
    assert turns[-1.0][1].metrics["tactical_diameter"] > 1.05 * turns[1.0][1].metrics["tactical_diameter"]
