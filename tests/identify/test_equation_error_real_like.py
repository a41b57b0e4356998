"""Equation error on a roll decay shaped like the KVLCC2 model-test records.

The property of those records that broke it: besides the decay, the angle carries a third
harmonic of about 0.1 % of the amplitude, in quadrature (fitted against the output-error
model's phase on runs 21337/21338/21340: 8e-4 to 1.2e-3 of the amplitude, 0.01° at 10°, under
the 0.005° quantisation step once the roll is small). The output error does not see it; the
equation error's waveform fit, where a harmonic k weighs k² times its share of the angle in q̈,
read B_e(5°) 19–20 % high, and bench/real_decay.py printed nan for it (it did not ask for it).

The truth is the damping the decay is generated with: (I + I_a) φ̈ + B1 φ̇ + B2 |φ̇| φ̇ + C44 φ = 0
integrated by SciPy's DOP853 (not hydrokit's integrator), and B_e(a) = B1 + 8/(3π) ω0 a B2,
the equivalent linearisation of the quadratic term (ω0 = √(C44 / (I + I_a))).
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp
from scipy.signal import hilbert

from hydrokit.identify.result import fit_launch
from hydrokit.identify.types import Launch
from hydrokit.io.launch import launch_csv
from hydrokit.io.rig import parse_rig

DATA = Path(__file__).parent / "data" / "kvlcc2_roll_rig.yaml"
BENCH = Path(__file__).resolve().parents[2] / "bench" / "real_decay.py"
RIG_DOC = yaml.safe_load(DATA.read_text())
FS = 100.0  # Hz, as the model-test records
STEP = math.radians(0.005)  # rad, their quantisation step
I_A, B1, B2 = 19.0, 0.63, 14.3  # kg·m², N·m·s/rad, N·m·s²/rad²: about what output error reads on 21337
HARMONIC = 1e-3  # third harmonic, in quadrature, relative to the amplitude
AT = math.radians(5.0)  # rad


def _c44_inertia() -> tuple[float, float]:
    """C44 = ρ g ∇ GM (N·m/rad) and I + I_a (kg·m²) from the rig file's numbers, by hand."""
    body, fluid = RIG_DOC["body"], RIG_DOC["fluid"]
    c44 = fluid["density"] * RIG_DOC["gravity"] * body["volume"] * RIG_DOC["floating"]["gm"]
    return c44, body["inertia"] + I_A


def _true_equivalent(a: float) -> float:
    c44, inertia = _c44_inertia()
    return B1 + 8.0 / (3.0 * math.pi) * math.sqrt(c44 / inertia) * a * B2


def _decay(duration: float, heel: float = math.radians(10.0)) -> tuple[np.ndarray, np.ndarray]:
    """Free decay from rest at ``heel`` (rad), sampled at FS for ``duration`` s."""
    c44, inertia = _c44_inertia()

    def rhs(_t: float, x: np.ndarray) -> list[float]:
        phi, rate = x
        return [rate, -(B1 * rate + B2 * abs(rate) * rate + c44 * phi) / inertia]

    t = np.arange(int(duration * FS)) / FS
    sol = solve_ivp(rhs, (0.0, t[-1]), [heel, 0.0], method="DOP853", t_eval=t, rtol=1e-11, atol=1e-13)
    return t, sol.y[0]


def _real_like(phi: np.ndarray, harmonic: float) -> np.ndarray:
    """The decay with a quadrature third harmonic of ``harmonic`` × its amplitude, quantised."""
    analytic = hilbert(phi)
    amplitude, phase = np.abs(analytic), np.angle(analytic)
    return np.round((phi - harmonic * amplitude * np.sin(3.0 * phase)) / STEP) * STEP


def _rig():
    return parse_rig(RIG_DOC, "kvlcc2_roll_rig.yaml")


def _equation_error(y: np.ndarray, t: np.ndarray):
    item = fit_launch(_rig(), Launch(t, y, "real-like.csv"), "equation-error", equivalent_at=[AT])
    return item.result


def test_a_clean_quantised_decay_keeps_the_waveform_damping() -> None:
    # no harmonic: the model is exact, the waveform's damping passes the energy check and B_e(5°)
    # is the truth within 1 % (measured −0.25 %: the quantisation and the differentiator)
    t, phi = _decay(66.0)
    res = _equation_error(_real_like(phi, 0.0), t)
    assert res.extra["equivalent_damping"][0]["value"] == pytest.approx(_true_equivalent(AT), rel=0.01)
    assert not [w for w in res.warnings if "energy balance" in w]


def test_a_third_harmonic_of_a_thousandth_does_not_move_the_equivalent_damping() -> None:
    # the KVLCC2 property: before the energy check the waveform fit read B_e(5°) 44 % high here;
    # the energy balance gives the truth within 2 % (measured +0.07 %), and the warning says why
    t, phi = _decay(66.0)
    res = _equation_error(_real_like(phi, HARMONIC), t)
    row = res.extra["equivalent_damping"][0]
    assert row["value"] == pytest.approx(_true_equivalent(AT), rel=0.02)
    assert row["std_error"] is not None and 0.0 < row["std_error"] < 0.05 * row["value"]
    [warning] = [w for w in res.warnings if "energy balance" in w]
    assert warning.startswith("equation-error: the in-cycle waveform's damping is")
    # the natural period is the restoring's, untouched by the harmonic: within 0.1 %
    c44, inertia = _c44_inertia()
    assert res.natural_frequency == pytest.approx(math.sqrt(c44 / inertia), rel=1e-3)


def _bench():
    spec = importlib.util.spec_from_file_location("real_decay", BENCH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_bench_prints_the_equation_error_equivalent_damping(tmp_path: Path, monkeypatch, capsys) -> None:  # noqa: ANN001
    # a whole record as a tank exports it (2 s at rest, held at 10° for 2 s, released at 4 s): the
    # equation-error row carries a number, the truth within 2 %, not nan
    bench = _bench()
    real = importlib.util.find_spec
    monkeypatch.setattr(
        bench.importlib.util,
        "find_spec",
        lambda name, *a: None if name in ("Snoopy", "rolldecayestimators") else real(name, *a),
    )
    t_free, phi = _decay(66.0)
    free = _real_like(phi, HARMONIC)
    rest = np.zeros(int(2 * FS))
    held = np.full(int(2 * FS), free[0])
    y = np.concatenate([rest, held, free])
    t = np.arange(y.size) / FS
    rig_path, csv = tmp_path / "roll.yaml", tmp_path / "decay.csv"
    rig_path.write_text(yaml.safe_dump(RIG_DOC))
    csv.write_text(launch_csv(t, y, "angle"))
    monkeypatch.setattr(sys, "argv", ["real_decay.py", str(rig_path), str(csv), "--methods", "equation-error"])
    bench.main()
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("equation-error"))
    assert " error:" not in row
    assert float(row.split()[4]) == pytest.approx(_true_equivalent(AT), rel=0.02)
