"""Closed-loop logs (issue #44 item 4): virtual dives flown under a depth/heading hold, what the
feedback does to identification, and the fit's warning when the commands follow the state."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.sysid.data import Hold, generate_runs, hidden_vehicle

HEAVE = ["added_mass.heave", "linear_damping.heave"]


@pytest.fixture(scope="module")
def truth() -> Any:
    import hydrokit

    return hidden_vehicle(hydrokit.load_vehicle("bluerov2-sysid"), 3)


@pytest.fixture(scope="module")
def short(truth: Any) -> tuple[Any, Any]:
    """8 s dives at 10 ms, open loop and under a depth/heading hold without dither."""
    open_loop = generate_runs(truth, 1, 8.0, seed=3, dt=0.01)[0]
    held = generate_runs(truth, 1, 8.0, seed=3, dt=0.01, hold=Hold(dither=0.0))[0]
    return open_loop, held


def test_closed_loop_dive_is_its_commands_replayed_and_holds_depth(truth: Any, short: Any) -> None:
    from hydrokit.sysid.data import _integrate
    from hydrokit.sysid.model import force_table, stack_packs

    open_loop, held = short
    # second method: the whole run's force table (rotor lag over the recorded commands)
    # integrated open loop from the same start gives the closed loop's states (the loop
    # integrated row by row from the rotor state at each row): equal to round-off
    dt = 0.01
    states = _integrate(stack_packs([truth]), held.truth[0], force_table(held, truth.thrusters, dt), dt, 800)
    np.testing.assert_allclose(states[::2], held.truth, atol=1e-9)
    # the hold keeps depth and heading: far less heave and yaw motion than the open-loop dive
    # flown on the same pilot multi-sines (by the hold's own figures ≥ 3×)
    for k in (2, 5):
        assert np.ptp(held.truth[:, k]) < np.ptp(open_loop.truth[:, k]) / 3
    # the held DOFs' commands follow the logged state: without dither, the heave force and yaw
    # moment of the commanded thrusts are the PD law on the latest depth/heading and DVL/gyro
    # samples, τ = −M ω² (y − y_0) − 2 ζ ω M ẏ (closed form; table curves inverted exactly)
    th = truth.thrusters
    tau = np.array([th.thrust(np.array([held.commands[n][k] for n in th.names])) for k in range(held.time.size)])
    tau = tau @ th.configuration_matrix().T
    hold = Hold()
    for dof, pos, rate in ((2, "z", "w"), (5, "psi", "r")):
        m = truth.M[dof, dof]
        y = _latest(held, pos)
        e = y - y[0] if pos == "z" else np.angle(np.exp(1j * (y - y[0])))
        law = -m * hold.bandwidth**2 * e - 2 * hold.damping * hold.bandwidth * m * _latest(held, rate)
        np.testing.assert_allclose(tau[:, dof], law, atol=1e-9 * np.max(np.abs(law)))


def _latest(run: Any, channel: str) -> np.ndarray:
    """The latest logged sample of ``channel`` at every row (what the autopilot saw)."""
    t, y = run.channels[channel]
    return y[np.searchsorted(t, run.time, side="right") - 1]


def test_feedback_is_detected_in_the_held_dive_only(truth: Any, short: Any) -> None:
    from hydrokit.sysid.fit import _feedback
    from hydrokit.sysid.smooth import Smoothed

    def ideal(run: Any) -> Smoothed:
        """A perfect smoother: the true states (the fit's own smoother is exercised by the fit
        below, with the JIT)."""
        return Smoothed(run.time, run.truth, np.zeros((run.time.size, 6)), np.ones(12, bool), {})

    open_loop, held = short
    runs = [open_loop, held]
    found = _feedback(runs, [ideal(r) for r in runs], truth.thrusters)
    # 40 DVL samples in 8 s: the depth hold's reaction to the DVL noise correlates with it at
    # |ρ| ≈ 0.9, 6× the 1/√n band; the open-loop dive's commands ignore the noise (|ρ|√n is
    # then standard normal: above 5 with probability 6e-7 per test)
    assert len(found) == 1 and found[0].startswith("dive1: the heave command follows the measured w")
    assert "feedback detected" in found[0] and "add a dither" in found[0]
    solo = _feedback([open_loop], [ideal(open_loop)], truth.thrusters)
    assert solo == []


def test_bad_holds() -> None:
    with pytest.raises(InputError, match=r"hold dofs \['surge'\]: expected some of heave, yaw"):
        Hold(dofs=("surge",))
    with pytest.raises(InputError, match=r"dither = 2: expected"):
        Hold(dither=2)


def test_bad_schedule_for_the_generator(truth: Any) -> None:
    with pytest.raises(InputError, match=r"commands: expected one column of ≥ 2 rows per thruster"):
        generate_runs(truth, 1, commands={"FR": np.zeros(1)})


@pytest.mark.needs_jit(reason="two output-error fits over 2 × 10 s of dives")
def test_a_hold_without_dither_inflates_sigma_and_is_warned(truth: Any) -> None:
    from hydrokit.sysid.fit import identify

    open_runs = generate_runs(truth, 2, 10.0, seed=11, dt=0.01)
    held_runs = generate_runs(truth, 2, 10.0, seed=11, dt=0.01, hold=Hold(dither=0.05))
    free = HEAVE
    a = identify(truth, open_runs, free, samples=0, check_step=False)
    b = identify(truth, held_runs, free, samples=0, check_step=False)
    # the depth hold removes the heave excitation: σ of heave added mass and damping grow
    # several-fold over the open-loop dives flown on the same pilot multi-sines (measured ×5–16
    # over three seeds)
    assert np.all(b.sigma > 2.5 * a.sigma), b.sigma / a.sigma
    # the fit says so: feedback detected in every held run, never in the open-loop ones
    assert sum("feedback detected" in w for w in b.warnings) >= 2
    assert not any("feedback detected" in w for w in a.warnings)
