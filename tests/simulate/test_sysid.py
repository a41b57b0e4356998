"""System identification from free-running logs (issue #44): recovery on generated dives,
the thruster force history, the statistics and the bad inputs."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.sysid.data import HIDDEN, generate_runs, hidden_vehicle
from hydrokit.sysid.model import force_table, free_parameters, values_of, with_values


@pytest.fixture(scope="module")
def base() -> Any:
    import hydrokit

    return hydrokit.load_vehicle("bluerov2-sysid")


@pytest.fixture(scope="module")
def dives(base: Any) -> tuple[Any, list[Any]]:
    truth = hidden_vehicle(base, 2)
    return truth, generate_runs(truth, 3, 12.0, seed=5)


@pytest.fixture(scope="module")
def short(base: Any) -> list[Any]:
    """Two 3 s dives integrated at 10 ms: cheap enough for the uncompiled suite."""
    return generate_runs(hidden_vehicle(base, 2), 2, 3.0, seed=5, dt=0.01)


@pytest.mark.needs_jit(reason="an output-error fit of 12 parameters over 2 × 12 s of dives")
def test_output_error_recovers_truth_and_agrees_with_equation_error(base: Any, dives: Any) -> None:
    from hydrokit.sysid.fit import identify

    truth, runs = dives
    res = identify(base, runs[:2], list(HIDDEN), holdout=runs[2:], samples=0, check_step=False)
    _, params = free_parameters(truth, HIDDEN)
    true = values_of(truth, params)
    # the generating truth within 4 σ (σ from the Fisher information with the coloured-residual
    # sandwich; 12 parameters at 4 σ fail by chance with probability < 1e-3)
    assert np.all(np.abs(res.values - true) < 4 * res.sigma), (res.values - true) / res.sigma
    # every coefficient identifiable from these dives: σ under 10 % of its value
    assert np.all(res.sigma < 0.1 * np.abs(res.values))
    # the independent equation-error fit (smoothed states, least squares on the equations of
    # motion) agrees within 4 combined σ
    ee, ee_sd = res.equation_error["values"], res.equation_error["sigma"]
    assert np.all(np.abs(res.values - ee) < 4 * np.hypot(res.sigma, ee_sd))
    # the held-out dive is predicted open loop: angular rates within 20 % of their spread
    held = next(r for r in res.runs if r["holdout"])
    assert held["channels"]["r"]["nrmse"] < 0.2
    # the noise levels found are the generator's σ (yaw-rate gyro 0.005 rad/s, DVL 0.01 m/s)
    assert res.noise["r"] == pytest.approx(0.005, rel=0.15)
    assert res.noise["u"] == pytest.approx(0.01, rel=0.25)


@pytest.mark.needs_jit(reason="an output-error fit and its check at half the step")
def test_halving_the_step_moves_no_estimate_by_a_tenth_of_sigma(base: Any, dives: Any) -> None:
    from hydrokit.sysid.fit import identify

    truth, runs = dives
    res = identify(base, runs[:1], ["added_mass.yaw", "quadratic_damping.yaw"], samples=5, dt=0.01)
    assert res.step_check < 0.1
    assert len(res.predictions) == 1 and res.predictions[0]["channels"]["r"]["low"].shape == (601,)


@pytest.mark.needs_jit(reason="three output-error fits of 2 parameters over a 12 s dive")
def test_the_step_check_predicts_what_a_fit_at_half_the_step_gives(base: Any, dives: Any) -> None:
    """The check (residuals at dt/2 with the fit's Jacobian at dt, one Gauss–Newton step) against a
    second method: the fit done again at dt/2. At a coarse step the two agree on how far the
    estimates move, and the fit warns."""
    from hydrokit.sysid.fit import identify

    _, runs = dives
    free = ["added_mass.yaw", "quadratic_damping.yaw"]
    coarse = identify(base, runs[:1], free, samples=0, dt=0.1)
    fine = identify(base, runs[:1], free, samples=0, dt=0.05, check_step=False)
    moved = float(np.max(np.abs(fine.values - coarse.values) / coarse.sigma))
    assert moved > 0.1, "a 0.1 s step must matter for this check to mean anything"
    assert coarse.step_check == pytest.approx(moved, rel=0.25)
    assert any("use a smaller dt" in w for w in coarse.warnings)


def test_force_table_holds_commands_and_follows_rotor_lag(base: Any) -> None:
    # one thruster stepped from 0 to command 0.5 at t = 0.1 s: the thrust follows the table
    # curve of the lagged command c(t) = 0.5 (1 − e^{−(t − 0.1)/τ}) (closed form of τ ċ = c* − c)
    th = base.thrusters
    t = np.round(np.arange(0.0, 0.6, 0.02), 6)
    cmd = {n: np.zeros(t.size) for n in th.names}
    cmd["FR"][t >= 0.1] = 0.5

    class Run:
        name = "step"
        time = t
        channels: dict[str, Any] = {}
        commands = cmd
        thrusts: dict[str, Any] = {}

    tab = force_table(Run(), th, 0.01)
    tc = th.time_constants[0]
    for tq in (0.1, 0.15, 0.3, 0.55):
        c = 0.5 * (1 - np.exp(-(tq - 0.1) / tc))
        f = th.curves[0].thrust(c)
        expect = th.configuration_matrix()[:, 0] * f
        got = np.array([np.interp(tq, tab[:, 0], tab[:, 1 + j]) for j in range(6)])
        np.testing.assert_allclose(got, expect, atol=1e-9)  # nodes at every RK4 stage: exact

    class Measured(Run):
        commands = {n: v for n, v in cmd.items() if n != "FR"}
        thrusts = {"FR": np.where(t >= 0.1, 10.0, 0.0)}

    tab = force_table(Measured(), th, 0.01)
    X = lambda tq: np.interp(tq, tab[:, 0], tab[:, 1])  # noqa: E731
    # held thrust: the old value up to the row, the new one right after (zero-order hold)
    T0 = th.configuration_matrix()[0, 0]
    assert X(0.1) == pytest.approx(0.0) and X(0.1 + 1e-6) == pytest.approx(10.0 * T0)


def test_free_names_terms_and_values_round_trip(base: Any) -> None:
    v, params = free_parameters(base, ["added_mass.surge", "terms.N_r|r|", "terms.Y_vdot", "linear_damping.yaw"])
    assert [p.kind for p in params] == ["added_mass", "term", "accel", "linear_damping"]
    assert "N_r|r|" in v.terms.names  # absent term added at 0
    np.testing.assert_allclose(values_of(v, params), [base.M_A[0, 0], 0.0, -base.M_A[1, 1], base.D_L[5, 5]])
    w = with_values(v, params, [1.0, -2.0, -3.0, 4.0])
    np.testing.assert_allclose(values_of(w, params), [1.0, -2.0, -3.0, 4.0])
    assert w.M_A[1, 1] == 3.0 and w.terms.coef[v.terms.names.index("N_r|r|")] == -2.0
    for bad, match in (
        ("added_mass.swirl", r"free parameter 'added_mass.swirl' does not exist"),
        ("terms.Q_uu", r"term 'Q_uu'"),
    ):
        with pytest.raises(InputError, match=match):
            free_parameters(base, [bad])
    with pytest.raises(InputError, match=r"named twice"):
        free_parameters(base, ["added_mass.surge", "added_mass.surge"])
    with pytest.raises(InputError, match=r"no free parameter"):
        free_parameters(base, [])


def test_smoother_gives_rate_and_noise_of_a_multirate_channel() -> None:
    from hydrokit.sysid.smooth import smooth_run

    # heave velocity sampled at 5 Hz with σ = 0.01 m/s: the smoother's value and derivative
    # against the closed form w = 0.2 sin t, ẇ = 0.2 cos t
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 20.0, 0.2)

    class Run:
        name = "sine"
        time = t
        channels = {"w": (t, 0.2 * np.sin(t) + 0.01 * rng.standard_normal(t.size))}

    sm = smooth_run(Run(), dt=0.05)
    inner = (sm.time > 2) & (sm.time < 18)
    assert np.sqrt(np.mean((sm.states[inner, 8] - 0.2 * np.sin(sm.time[inner])) ** 2)) < 0.006  # < σ: smoothed
    assert np.sqrt(np.mean((sm.nu_dot[inner, 2] - 0.2 * np.cos(sm.time[inner])) ** 2)) < 0.02
    assert sm.noise["w"] == pytest.approx(0.01, rel=0.3)  # 100 samples: ±30 % covers the estimate
    assert sm.known[8] and not sm.known[6]


def test_sandwich_is_fisher_for_white_and_long_run_variance_for_ar1() -> None:
    from hydrokit.sysid.stats import condition_number, correlation, sandwich, whiteness

    # estimating a mean from n residuals: white unit noise → variance 1/n (Fisher); AR(1) noise
    # with coefficient φ → the long-run variance (1 + φ)/(1 − φ) / n (closed form)
    rng = np.random.default_rng(1)
    n = 20000
    A = np.ones((n, 1))
    white = rng.standard_normal(n)
    assert sandwich(A, white, [(0, n)])[0, 0] * n == pytest.approx(1.0, rel=0.05)
    phi = 0.8
    from scipy.signal import lfilter

    e = lfilter([np.sqrt(1 - phi**2)], [1.0, -phi], white)
    var = sandwich(A, e, [(0, n)])[0, 0] * n
    assert var == pytest.approx((1 + phi) / (1 - phi), rel=0.25)  # Bartlett taper: a few % low
    assert whiteness(white)["outside"] < 0.2 and whiteness(e)["lag1"] == pytest.approx(phi, abs=0.03)
    c = correlation(np.array([[4.0, 2.0], [2.0, 9.0]]))
    assert c[0, 1] == pytest.approx(2.0 / 6.0)
    assert condition_number(np.diag([1.0, 100.0])) == pytest.approx(1.0)  # unit-free: scaled first


def test_bad_inputs_of_identify(base: Any, short: Any) -> None:
    from hydrokit.sysid.fit import identify

    runs = short
    with pytest.raises(InputError, match=r"free parameter 'damping.surge' does not exist"):
        identify(base, runs[:1], ["damping.surge"])
    with pytest.raises(InputError, match=r"method 'magic'"):
        identify(base, runs[:1], ["added_mass.surge"], method="magic")
    with pytest.raises(InputError, match=r"no training run"):
        identify(base, [], ["added_mass.surge"])
    from dataclasses import replace

    with pytest.raises(InputError, match=r"has no thrusters"):
        identify(replace(base, thrusters=None), runs[:1], ["added_mass.surge"])
    t = runs[0].time[:3]

    class Tiny:
        name = "tiny"
        time = t
        channels = {"u": (t, np.zeros(3))}
        commands = {n: np.zeros(3) for n in base.thrusters.names}
        thrusts: dict[str, Any] = {}

    with pytest.raises(InputError, match=r"3 samples for 2 parameters and 1 initial states; expected more samples"):
        identify(base, [Tiny()], ["added_mass.surge", "linear_damping.surge"])


def test_divergent_fit_names_the_parameter_that_ran_away(base: Any, short: Any, monkeypatch: Any) -> None:
    from hydrokit.sysid import fit as sysid

    def run_away(problem: Any, z: np.ndarray, scale: np.ndarray, *_: Any) -> Any:
        z = z.copy()
        z[1] = 1e9
        raise sysid._Diverged(z)

    monkeypatch.setattr(sysid, "_lm", run_away)
    runs = short
    short = [_cut(runs[0], 2.0)]
    with pytest.raises(InputError, match=r"diverged: linear_damping.surge ran away to 1e\+09"):
        sysid.identify(base, short, ["added_mass.surge", "linear_damping.surge"], samples=0, check_step=False)


def _cut(run: Any, seconds: float, only: tuple[str, ...] = ()) -> Any:
    """The first ``seconds`` of a generated dive (a short case the uncompiled tests can afford),
    with only the channels ``only`` (default: all)."""
    from dataclasses import replace

    keep = run.time <= seconds
    chans = {c: (t[t <= seconds], y[t <= seconds]) for c, (t, y) in run.channels.items() if not only or c in only}
    return replace(run, time=run.time[keep], channels=chans, commands={k: v[keep] for k, v in run.commands.items()})


def test_short_fit_result_outputs(base: Any, short: Any, tmp_path: Any) -> None:
    """A one-parameter fit over 2 s (cheap without the JIT): the result's views and files."""
    import yaml

    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.vehicle import resolve_vehicle
    from hydrokit.io.yamlfile import read_yaml
    from hydrokit.report.sysid import output_files
    from hydrokit.sysid.fit import identify

    runs = short
    res = identify(
        base,
        [_cut(runs[0], 2.0, ("psi", "r", "u"))],
        ["added_mass.yaw"],
        holdout=[_cut(runs[1], 1.0, ("r",))],
        dt=0.02,
        samples=3,
        max_iter=2,
        check_step=False,
    )
    d = res.to_dict()
    assert d["parameters"][0]["name"] == "added_mass.yaw" and d["parameters"][0]["unit"] == "kg·m²"
    assert "<table>" in res._repr_html_() and res.table()[0][0] == "parameter"
    lo, hi = res.interval()[0]
    assert lo < res.values[0] < hi
    ax = res.plot()
    assert ax.get_xlabel() == "time (s)"
    files = output_files(res, read_yaml(resolve_vehicle("bluerov2-sysid")), str(tmp_path))
    doc = yaml.safe_load(files[str(tmp_path / "vehicle.yaml")])
    v = vehicle_from_dict(doc, "identified")
    assert v.M_A[5, 5] == pytest.approx(res.values[0])
    assert v.uncertainty.parameters == ("added_mass.yaw",)
    assert v.uncertainty.covariance[0, 0] == pytest.approx(res.sigma[0] ** 2)
    assert "held out" in files[str(tmp_path / "report.html")]
    assert files[str(tmp_path / "predictions.csv")].startswith("run,holdout,channel,time")


def test_equation_error_method_and_terms(base: Any, short: Any) -> None:
    from hydrokit.report.sysid import vehicle_document
    from hydrokit.sysid.fit import identify

    runs = short
    free = ["terms.N_r|r|", "terms.Z_wdot"]
    res = identify(base, [_cut(runs[0], 2.0)], free, method="equation-error", dt=0.02, samples=0, bounds=False)
    assert res.method == "equation-error"
    np.testing.assert_allclose(res.values, res.equation_error["values"])
    # bounded (the default): N_r|r| projected onto ≤ 0 (a positive one feeds energy in), Z_wdot free
    held = identify(base, [_cut(runs[0], 2.0)], free, method="equation-error", dt=0.02, samples=0)
    ee = np.asarray(held.equation_error["values"])
    np.testing.assert_allclose(held.values, [min(ee[0], 0.0), ee[1]])
    doc = vehicle_document(
        res, {"name": "b", "added_mass": [1, 2, 3, 4, 5, 6], "linear_damping": [0] * 6, "quadratic_damping": [0] * 6}
    )
    assert doc["terms"]["N_r|r|"]["value"] == pytest.approx(res.values[0])
    # Z_wdot: M_A[2, 2] = file added mass − term, and the identified entry is −value
    assert doc["terms"]["Z_wdot"]["value"] == pytest.approx(3 + res.values[1])
    assert doc["uncertainty"]["parameters"] == ["terms.N_r|r|", "terms.Z_wdot"]


def test_identifiability_messages_name_pairs_and_what_separates_them(base: Any) -> None:
    from hydrokit.sysid.fit import _messages
    from hydrokit.sysid.smooth import Smoothed

    names = [
        "added_mass.surge",
        "linear_damping.surge",
        "added_mass.sway",
        "linear_damping.yaw",
        "quadratic_damping.yaw",
    ]
    _, params = free_parameters(base, names)
    corr = np.eye(5)
    corr[0, 1] = corr[1, 0] = 0.97  # mass and damping of one DOF
    corr[0, 2] = corr[2, 0] = 0.99  # two added masses (Munk moment)
    corr[3, 4] = corr[4, 3] = -0.98  # linear and quadratic of one DOF
    corr[1, 3] = corr[3, 1] = 0.96  # two DOFs
    states = np.zeros((10, 12))
    states[:, 11] = np.linspace(-0.4, 0.3, 10)
    sm = Smoothed(np.arange(10.0), states, np.zeros((10, 6)), np.ones(12, bool), {})
    values = np.array([5.0, -1.0, 6.0, 0.5, 1.0])
    sigma = np.array([0.1, 0.2, 0.1, 0.6, 0.1])
    text = "\n".join(_messages(names, params, values, sigma, corr, [sm]))
    assert (
        "added_mass.surge and linear_damping.surge move together (ρ = +0.970): these runs hold little surge acceleration"
        in text
    )
    assert "the rotation fixes their difference (Munk moment)" in text
    assert "these runs reach only |r| ≤ 0.4; fly yaw over a wider speed range" in text
    assert "excite surge and yaw separately" in text
    assert "linear_damping.yaw = 0.5 with σ = 0.6 > |value|: not identifiable from these runs" in text
    assert "linear_damping.surge = -1 N·s/m is below its physical bound 0 (reported as fitted, not clipped)" in text
