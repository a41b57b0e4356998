"""Floating-body rig (issue #16 item 1): parsing, bad input, closed-form acceptance, CLI end to end.

(I + I_a) φ̈ + B1 φ̇ + B2 |φ̇| φ̇ + C(φ) = 0 with C = ρ g ∇ GM (roll, pitch), ρ g A_wp (heave),
C1 φ + C3 φ³ + C5 φ⁵ or ρ g ∇ GZ(φ).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.identify.estimators import identify_launch
from hydrokit.identify.preprocess import trim_launch
from hydrokit.identify.rig_model import rig_constants, simulate_extended, simulate_rig
from hydrokit.identify.types import Rig, rig_document
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch
from hydrokit.io.rig import parse_rig

RHO, G, VOL = 1000.0, 9.81, 0.1
BODY = {"mass": 100.0, "volume": VOL, "reference_area": 0.5, "reference_length": 1.0, "inertia": 8.0}


def doc(axis: str, floating: dict[str, Any] | None, **body: float) -> dict[str, Any]:
    d: dict[str, Any] = {
        "test": "floating",
        "axis": axis,
        "gravity": G,
        "fluid": {"density": RHO, "kinematic_viscosity": 1.0e-6},
        "body": {**BODY, **body},
    }
    if floating is not None:
        d["floating"] = floating
    return d


def rig_of(axis: str, floating: dict[str, Any], **body: float) -> Rig:
    return parse_rig(doc(axis, floating, **body), "float.yaml")


# -- parsing ---------------------------------------------------------------------------------


@pytest.mark.parametrize("gm", [-0.3, 0.0, math.inf, math.nan])
def test_a_floating_rig_without_positive_finite_restoring_is_refused(gm: float) -> None:
    # the file reader refuses these first; a Rig built in Python meets the same rule where the
    # constants are made: C1 = ρ g V GM must be positive and finite. A small C1 (0.5 N·m/rad) is fine
    import dataclasses

    rig = dataclasses.replace(rig_of("roll", {"gm": 0.3}), floating=("gm", gm))
    with pytest.raises(InputError, match=r"floating restoring C1 = .*: expected a positive number"):
        rig_constants(rig)
    small = dataclasses.replace(rig, floating=("restoring", (0.5, 0.0, 0.0)))
    assert rig_constants(small).S == 0.5
    # built in Python with neither a floating section nor a stiffness: no restoring at all
    bare = dataclasses.replace(rig, floating=None, stiffness=None)
    with pytest.raises(InputError, match=r"floating restoring C1 = 0.0: expected a positive number"):
        rig_constants(bare)
    assert rig_constants(dataclasses.replace(bare, stiffness=0.7)).S == 0.7


def test_a_torsion_rig_document_reads_back() -> None:
    import dataclasses

    # the JSON's rig section of a torsion rig: its stiffness under 'torsion', no floating section
    torsion = Rig("torsion", "pitch", G, RHO, 1e-6, 100.0, VOL, 0.5, 1.0, inertia=8.0, stiffness=123.0)
    doc_ = rig_document(torsion)
    assert doc_["torsion"] == {"stiffness": 123.0} and "floating" not in doc_
    assert parse_rig(doc_, "torsion.yaml") == dataclasses.replace(torsion, source="torsion.yaml")
    # an air tare with only one of its two terms is written (and read back) too, and a wall distance and a model scale
    for tare in (
        {"tare_linear_damping": 0.3},
        {"tare_quadratic_damping": 0.2},
        {"wall_distance": 0.45},
        {"scale": 0.3},
    ):
        tared = dataclasses.replace(torsion, source="torsion.yaml", **tare)
        assert parse_rig(rig_document(tared), "torsion.yaml") == tared


def test_a_restoring_shape_is_immutable() -> None:
    # shared by the compiled kernels' parameter packing and the parallel fits: frozen
    import dataclasses

    from hydrokit.identify.rig_model import Restoring

    shape = Restoring.polynomial(300.0, -200.0, 50.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        shape.kind = 0  # type: ignore[misc]


def test_parse_gm_is_the_torsion_model() -> None:
    rig = rig_of("pitch", {"gm": 0.3})
    C = RHO * G * VOL * 0.3
    assert rig.test == "floating" and rig.rotational and not rig.translational_signal
    assert rig.stiffness == pytest.approx(C)
    assert rig.floating == ("gm", 0.3)
    c = rig_constants(rig)
    assert (c.S, c.base_inertia, c.restoring.kind if c.restoring else 0) == (pytest.approx(C), 8.0, 0)
    torsion = Rig("torsion", "pitch", G, RHO, 1e-6, 100.0, VOL, 0.5, 1.0, inertia=8.0, stiffness=C)
    t = np.linspace(0.0, 10.0, 501)
    a = simulate_rig(rig, t, 2.0, 1.0, 3.0, 0.2)
    b = simulate_rig(torsion, t, 2.0, 1.0, 3.0, 0.2)
    np.testing.assert_array_equal(a, b)


def test_parse_waterplane_area_is_the_spring_model() -> None:
    rig = rig_of("heave", {"waterplane_area": 0.2})
    assert not rig.rotational and rig.translational_signal
    c = rig_constants(rig)
    assert c.S == pytest.approx(RHO * G * 0.2)
    assert c.base_inertia == 100.0  # heave: body.mass
    spring = Rig("spring", "heave", G, RHO, 1e-6, 100.0, VOL, 0.5, 1.0, stiffness=RHO * G * 0.2)
    t = np.linspace(0.0, 10.0, 501)
    np.testing.assert_array_equal(simulate_rig(rig, t, 50, 10, 200, 0.05), simulate_rig(spring, t, 50, 10, 200, 0.05))


def test_parse_restoring_polynomial_and_gz() -> None:
    lin = rig_of("roll", {"restoring": [300.0, 0.0, 0.0]})
    assert rig_constants(lin).restoring.kind == 0  # type: ignore[union-attr]  # C3 = C5 = 0: linear
    short = rig_of("heave", {"restoring": [2000.0]})
    assert short.floating == ("restoring", (2000.0, 0.0, 0.0))
    quint = rig_of("roll", {"restoring": [300.0, -200.0, 50.0]})
    c = rig_constants(quint)
    q = np.array([-0.4, 0.1, 0.3])
    np.testing.assert_allclose(c.S * c.shape(q), 300 * q - 200 * q**3 + 50 * q**5, rtol=1e-12)
    np.testing.assert_allclose(c.S * c.shape.slope(q), 300 - 600 * q**2 + 250 * q**4, rtol=1e-12)
    table = [[0, 0], [10, 0.05], [20, 0.09], [30, 0.11], [40, 0.10]]
    gz = rig_of("roll", {"gz": table})
    c = rig_constants(gz)
    gm0 = 0.05 / math.radians(10)
    assert c.S == pytest.approx(RHO * G * VOL * gm0)
    angles = np.radians([0.0, 10.0, 20.0, 30.0, 40.0, -20.0])
    np.testing.assert_allclose(c.S * c.shape(angles), RHO * G * VOL * np.array([0, 0.05, 0.09, 0.11, 0.10, -0.09]))
    for r in (rig_of("pitch", {"gm": 0.3}), short, quint, gz):
        assert parse_rig(rig_document(r), "float.yaml") == r  # the JSON's rig reads back


BAD = {
    "gm zero": (doc("roll", {"gm": 0.0}), "floating.gm"),
    "gm negative": (doc("pitch", {"gm": -0.1}), "floating.gm"),
    "waterplane area zero": (doc("heave", {"waterplane_area": 0.0}), "floating.waterplane_area"),
    "waterplane area negative": (doc("heave", {"waterplane_area": -1.0}), "floating.waterplane_area"),
    "gz not starting at zero angle": (doc("roll", {"gz": [[5, 0.0], [10, 0.05]]}), "floating.gz"),
    "gz not starting at zero arm": (doc("roll", {"gz": [[0, 0.01], [10, 0.05]]}), "floating.gz"),
    "gz angles not increasing": (doc("roll", {"gz": [[0, 0], [20, 0.09], [10, 0.05]]}), "floating.gz"),
    "gz one row": (doc("roll", {"gz": [[0, 0]]}), "floating.gz"),
    "gz bad row": (doc("roll", {"gz": [[0, 0, 1], [10, 0.05, 1]]}), "floating.gz"),
    "two restorings": (doc("roll", {"gm": 0.3, "gz": [[0, 0], [10, 0.05]]}), "field 'floating'"),
    "gm for heave": (doc("heave", {"gm": 0.3}), "floating.gm"),
    "waterplane area for roll": (doc("roll", {"waterplane_area": 0.2}), "floating.waterplane_area"),
    "gz for heave": (doc("heave", {"gz": [[0, 0], [10, 0.05]]}), "floating.gz"),
    "restoring C1 not positive": (doc("roll", {"restoring": [0.0, 1.0, 0.0]}), "floating.restoring"),
    "restoring too long": (doc("roll", {"restoring": [1.0, 0.0, 0.0, 0.0]}), "floating.restoring"),
    "no restoring": (doc("roll", None), "field 'floating'"),
    "empty floating": (doc("roll", {}), "field 'floating'"),
    "surge axis": (doc("surge", {"gm": 0.3}), "field 'axis'"),
    "roll without inertia": (doc("roll", {"gm": 0.3}, inertia=0.0), "body.inertia"),
    "floating on a spring rig": (
        {**doc("heave", {"waterplane_area": 0.2}), "test": "spring", "spring": {"stiffness": 10.0}},
        "field 'floating'",
    ),
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_floating_rig_names_the_field(name: str) -> None:
    data, field = BAD[name]
    with pytest.raises(InputError) as exc:
        parse_rig(data, "float.yaml")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("float.yaml: ")
    assert field in msg, msg


@pytest.mark.parametrize("floating", [{"restoring": [300.0, -200.0, 50.0]}, {"gz": [[0, 0], [10, 0.05], [25, 0.1]]}])
def test_nonlinear_restoring_sensitivities_match_finite_differences(floating: dict[str, Any]) -> None:
    from hydrokit.identify.rig_model import simulate_normalised

    shape = rig_constants(rig_of("roll", floating)).shape
    t = np.linspace(0.0, 6.0, 301)
    p = np.array([30.0, 0.1, 0.3, 0.6, 0.2])  # ω², b, g, q0, v0: out past the table's last row
    _, _, J = simulate_normalised(t, *p[:3], p[3], p[4], False, 8, True, restoring=shape)
    for k in range(5):
        h = 1e-6 * max(1.0, abs(p[k]))
        up, dn = p.copy(), p.copy()
        up[k] += h
        dn[k] -= h
        qu, _, _ = simulate_normalised(t, *up[:3], up[3], up[4], False, 8, restoring=shape)
        qd, _, _ = simulate_normalised(t, *dn[:3], dn[3], dn[4], False, 8, restoring=shape)
        np.testing.assert_allclose(J[:, k], (qu - qd) / (2 * h), atol=2e-5 * np.max(np.abs(J[:, k])) + 1e-9)


# -- closed-form acceptance on generated data --------------------------------------------------


def _fit_launches(rig: Rig, truth: tuple[float, float, float], amplitudes, sensor, duration, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    for a in amplitudes:
        L = simulate_launch(rig, *truth, a, duration, sensor, rng, file=f"a{a:g}")
        out.append(identify_launch(rig, trim_launch(L)))
    return out


def _check(results, rig: Rig, truth, c_closed: float, base: float, tol: float = 0.03) -> float:
    """Every launch: ω0 within 0.5 % of √(C/(I + I_a)), coefficients within ``tol``; worst ω0 error."""
    ma, b1, b2 = truth
    w0 = math.sqrt(c_closed / (base + ma))
    worst = 0.0
    for r in results:
        assert not r.warnings, r.warnings
        err = abs(r.natural_frequency / w0 - 1.0)
        worst = max(worst, err)
        assert err < 0.005, (r.file, r.natural_frequency, w0)
        assert r.added_mass == pytest.approx(ma, rel=tol)
        assert r.linear_damping == pytest.approx(b1, rel=tol)
        assert r.quadratic_damping == pytest.approx(b2, rel=tol)
        assert r.extra["restoring_stiffness"] == pytest.approx(c_closed)
        assert r.extra["total_inertia"] == pytest.approx(c_closed / r.natural_frequency**2)
    return worst


def test_heave_waterplane_area_recovers_closed_form() -> None:
    awp = 0.2
    rig = rig_of("heave", {"waterplane_area": awp}, mass=50.0)
    truth = (25.0, 10.0, 200.0)  # kg, N·s/m, N·s²/m²
    sensor = SensorModel(50.0, 0.2e-3, 0.0, 1.0, "heave probe 0.2 mm")
    res = _fit_launches(rig, truth, (0.03, 0.05, 0.08), sensor, 20.0)
    worst = _check(res, rig, truth, RHO * G * awp, 50.0)
    assert worst < 0.005


def test_pitch_gm_recovers_closed_form() -> None:
    gm = 0.3
    rig = rig_of("pitch", {"gm": gm})
    truth = (2.0, 1.0, 3.0)  # kg·m², N·m·s/rad, N·m·s²/rad²
    sensor = SensorModel(50.0, math.radians(0.02), 0.0, 1.0, "IMU 0.02°")
    res = _fit_launches(rig, truth, np.radians([5.0, 10.0, 15.0]), sensor, 30.0)
    assert len(res) == 3
    assert _check(res, rig, truth, RHO * G * VOL * gm, 8.0) < 0.005  # ω0 = √(ρ g ∇ GM / (I + I_a))


def test_quintic_restoring_is_recovered_only_with_the_matching_rig() -> None:
    coef = [300.0, -200.0, 50.0]  # N·m/rad, N·m/rad³, N·m/rad⁵: softening roll restoring
    rig = rig_of("roll", {"restoring": coef})
    truth = (2.0, 1.0, 3.0)
    sensor = SensorModel(50.0, math.radians(0.02), 0.0, 1.0, "IMU 0.02°")
    L = simulate_launch(rig, *truth, math.radians(25.0), 30.0, sensor, 3)
    r = identify_launch(rig, trim_launch(L))
    assert not r.warnings, r.warnings
    assert r.natural_frequency == pytest.approx(math.sqrt(300.0 / 10.0), rel=0.005)  # ω0 of C1
    for got, want in zip((r.added_mass, r.linear_damping, r.quadratic_damping), truth):
        assert got == pytest.approx(want, rel=0.03)
    # the same record fitted as a linear restoring (C1 only) misreads the softening as inertia
    lin = identify_launch(rig_of("roll", {"restoring": coef[:1]}), trim_launch(L))
    assert abs(lin.added_mass / truth[0] - 1.0) > 0.04
    assert lin.rms_residual > 3.0 * r.rms_residual


def test_gz_curve_restoring_is_recovered() -> None:
    table = [[0, 0], [10, 0.05], [20, 0.09], [30, 0.11], [40, 0.10]]
    rig = rig_of("roll", {"gz": table})
    truth = (2.0, 1.0, 3.0)
    sensor = SensorModel(50.0, math.radians(0.02), 0.0, 1.0, "IMU 0.02°")
    L = simulate_launch(rig, *truth, math.radians(30.0), 40.0, sensor, 4)
    r = identify_launch(rig, trim_launch(L))
    assert not r.warnings, r.warnings
    for got, want in zip((r.added_mass, r.linear_damping, r.quadratic_damping), truth):
        assert got == pytest.approx(want, rel=0.03)
    short = rig_of("roll", {"gz": table[:3]})  # the table ends at 20°, the launch starts at 30°
    assert any("beyond the GZ table" in w for w in identify_launch(short, trim_launch(L)).warnings)


@pytest.mark.parametrize("method", ["equation-error", "log-decrement"])
def test_other_methods_use_the_nonlinear_restoring(method: str) -> None:
    rig = rig_of("roll", {"restoring": [300.0, -200.0, 50.0]})
    L = simulate_launch(rig, 2.0, 1.0, 3.0, math.radians(25.0), 30.0, SensorModel(50.0), 0)
    r = identify_launch(rig, trim_launch(L), method)
    assert r.added_mass == pytest.approx(2.0, rel=0.03)


# -- CLI ---------------------------------------------------------------------------------------


def _write(path: Path, data: dict[str, Any]) -> Path:
    path.write_text(yaml.safe_dump(data))
    return path


def test_cli_floating_heave_end_to_end(run_cli, tmp_path: Path) -> None:
    rig_path = _write(tmp_path / "float.yaml", doc("heave", {"waterplane_area": 0.2}, mass=50.0))
    code, _, err = run_cli(
        "rig", "simulate", rig_path, "--added-mass", 25, "--linear-damping", 10, "--quadratic-damping", 200,
        "--amplitudes", "40,60", "--launches", 2, "--noise", 0.2, "--resolution", 0, "--out", tmp_path / "launches",
    )  # fmt: skip
    assert code == 0, err
    files = sorted((tmp_path / "launches").glob("*.csv"))
    assert len(files) == 4 and "position" in files[0].read_text()
    out = tmp_path / "out.json"
    code, _, err = run_cli("identify", rig_path, *files, "--json", out)
    assert code == 0, err
    d = json.loads(out.read_text())
    assert d["rig"]["floating"] == {"waterplane_area": 0.2}
    assert d["units"]["added_mass"] == "kg" and d["units"]["amplitude"] == "m"
    w0 = math.sqrt(RHO * G * 0.2 / 75.0)
    for L in d["launches"]:
        assert L["natural_frequency"] == pytest.approx(w0, rel=0.005)
        assert L["added_mass"] == pytest.approx(25.0, rel=0.03)
        assert {"linear_damping", "quadratic_damping", "std_error"} <= set(L)


def test_cli_floating_pitch_and_bad_rig(run_cli, tmp_path: Path) -> None:
    rig_path = _write(tmp_path / "float.yaml", doc("pitch", {"gm": 0.3}))
    rig = parse_rig(doc("pitch", {"gm": 0.3}), "x")
    L = simulate_launch(rig, 2.0, 1.0, 3.0, math.radians(10), 30.0, SensorModel.imu(50.0, 0.02), 0)
    f = tmp_path / "pitch.csv"
    f.write_text("time,angle_deg\n" + "\n".join(f"{a:.4f},{math.degrees(b):.6f}" for a, b in zip(L.t, L.y)) + "\n")
    out = tmp_path / "p.json"
    code, _, err = run_cli("identify", rig_path, f, "--json", out)
    assert code == 0, err
    launch = json.loads(out.read_text())["launches"][0]
    assert launch["added_mass"] == pytest.approx(2.0, rel=0.03)
    assert json.loads(out.read_text())["units"]["added_mass"] == "kg m^2"
    bad = _write(tmp_path / "bad.yaml", doc("pitch", {"gm": -0.3}))
    code, _, err = run_cli("identify", bad, f, "--json", tmp_path / "bad.json")
    assert code == 2
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "floating.gm" in lines[0] and "Traceback" not in err
    assert not (tmp_path / "bad.json").exists()


# -- optional fits: --damping-model cubic, --restoring-terms 3|5 ---------------------------------


def _extended_launch(rig: Rig, truth: dict[str, float], a0: float, seed: int, duration: float = 30.0):
    """A launch whose truth has cubic damping B3 q̇³ and restoring corrections C3 q³ + C5 q⁵."""
    from hydrokit.identify.rig_model import simulate_extended
    from hydrokit.identify.types import Launch

    c = rig_constants(rig)
    A, S = c.inertia(truth["I_a"]), c.S
    p = [S / A, truth["B1"] / A, truth["B2"] / A, truth.get("B3", 0.0) / A]
    p += [truth.get("C3", 0.0) / S, truth.get("C5", 0.0) / S]
    t = np.arange(int(duration * 50) + 1) / 50.0
    q, _, _ = simulate_extended(t, p, a0, 0.0, c.restoring, 8)
    y = np.concatenate([np.full(50, a0), q]) + np.random.default_rng(seed).normal(0, math.radians(0.02), 50 + t.size)
    return trim_launch(Launch(np.arange(y.size) / 50.0, y, f"ext{seed}"))


def test_cubic_damping_model_recovers_b3() -> None:
    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0}, math.radians(15), 0)
    r = identify_launch(rig, L, damping_model="cubic")
    assert not r.warnings, r.warnings
    assert (r.added_mass, r.linear_damping, r.quadratic_damping) == (
        pytest.approx(2.0, rel=0.01),
        pytest.approx(1.0, rel=0.03),
        pytest.approx(3.0, rel=0.03),
    )
    assert r.extra["cubic_damping"] == pytest.approx(5.0, rel=0.03)
    # the restoring was not extended (one term): no restoring correction is reported
    assert (r.extra["damping_model"], r.extra["restoring_terms"]) == ("cubic", 1)
    assert "restoring_correction" not in r.extra
    assert 0 < r.std_error["cubic_damping"] < 0.1  # type: ignore[operator]
    quad = identify_launch(rig, L)  # the quadratic model lacks B3: biased, and says so
    assert abs(quad.linear_damping - 1.0) > 0.3 and quad.warnings


def test_cubic_damping_standard_error_is_the_delta_method_of_the_fit_covariance() -> None:
    # B3 = d·S/ω² from the fitted (ω², d); its standard error must be √(gᵀ Σ g) with g the
    # gradient of that map, here by central differences (a second method) over the estimator's
    # own covariance of (ω², b, g, d)
    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0}, math.radians(15), 1)
    r, est = identify_launch(rig, L, damping_model="cubic", return_estimator=True)
    S = est.constants_.S
    w2, d = est.ext_[0], est.ext_[3]

    def b3(w2_: float, d_: float) -> float:
        return d_ * S / w2_

    h_w, h_d = 1e-6 * w2, 1e-6 * abs(d)
    g = np.zeros(4)
    g[0] = (b3(w2 + h_w, d) - b3(w2 - h_w, d)) / (2 * h_w)
    g[3] = (b3(w2, d + h_d) - b3(w2, d - h_d)) / (2 * h_d)
    assert r.extra["cubic_damping"] == pytest.approx(b3(w2, d), rel=1e-12)
    assert r.std_error["cubic_damping"] == pytest.approx(math.sqrt(g @ est.pcov4_ @ g), rel=1e-6)


def test_restoring_terms_recover_c3_and_c5() -> None:
    rig = rig_of("pitch", {"gm": 0.3})
    truth = {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "C3": -200.0, "C5": 50.0}
    L = _extended_launch(rig, truth, math.radians(30), 1)
    r5 = identify_launch(rig, L, restoring_terms=5)
    assert not r5.warnings, r5.warnings
    corr = r5.extra["restoring_correction"]
    assert corr["C3"] == pytest.approx(-200.0, rel=0.03)
    assert abs(corr["C5"] - 50.0) < 3.0 * corr["std_error"]["C5"]
    for got, want in zip((r5.added_mass, r5.linear_damping, r5.quadratic_damping), (2.0, 1.0, 3.0)):
        assert got == pytest.approx(want, rel=0.01)
    # three terms: C3 alone is reported (with its standard error), no C5
    r3 = identify_launch(rig, L, restoring_terms=3)
    assert set(r3.extra["restoring_correction"]) == {"C3", "std_error"}
    assert set(r3.extra["restoring_correction"]["std_error"]) == {"C3"}
    r1 = identify_launch(rig, L)  # the rig's linear restoring alone misreads the softening
    assert abs(r1.added_mass / 2.0 - 1.0) > 0.05 and r1.warnings


def test_linear_damping_model_holds_b2_at_zero() -> None:
    rig = rig_of("heave", {"waterplane_area": 0.2}, mass=50.0)
    L = simulate_launch(rig, 25.0, 40.0, 0.0, 0.05, 20.0, SensorModel(50.0, 0.2e-3, 0.0, 1.0), 0)
    r = identify_launch(rig, trim_launch(L), damping_model="linear")
    assert r.linear_damping == pytest.approx(40.0, rel=0.02)
    assert r.quadratic_damping == 0.0 and r.std_error["quadratic_damping"] is None


def test_optional_fits_reject_what_they_cannot_do(pendulum_rig: Rig) -> None:
    rig = rig_of("pitch", {"gm": 0.3})
    L = trim_launch(simulate_launch(rig, 2.0, 1.0, 3.0, 0.2, 20.0, SensorModel(50.0), 0))
    with pytest.raises(InputError, match="--method output-error"):
        identify_launch(rig, L, "equation-error", damping_model="cubic")
    with pytest.raises(InputError, match="not to the pendulum"):
        identify_launch(pendulum_rig, L, restoring_terms=3)
    with pytest.raises(InputError, match="--restoring-terms"):
        identify_launch(rig, L, restoring_terms=4)
    # the model-free damping curve, called directly, refuses the pendulum by name too
    from hydrokit.identify.damping import damping_curve

    _, est = identify_launch(rig, L, return_estimator=True)
    assert damping_curve(L.t, L.y, est, rig)  # the pitch rig gets its curve
    with pytest.raises(InputError, match=r"^the damping curve applies to .* not to the pendulum"):
        damping_curve(L.t, L.y, est, pendulum_rig)


def test_cli_optional_fits(run_cli, tmp_path: Path) -> None:
    rig_path = _write(tmp_path / "float.yaml", doc("pitch", {"gm": 0.3}))
    rig = parse_rig(doc("pitch", {"gm": 0.3}), "x")
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0, "C3": -200.0}, math.radians(25), 2)
    f = tmp_path / "ext.csv"
    f.write_text("time,angle\n" + "\n".join(f"{a:.4f},{b:.8f}" for a, b in zip(L.t, L.y)) + "\n")
    out = tmp_path / "ext.json"
    code, _, err = run_cli(
        "identify", rig_path, f, "--json", out, "--damping-model", "cubic", "--restoring-terms", "3"
    )  # fmt: skip
    assert code == 0, err
    launch = json.loads(out.read_text())["launches"][0]
    assert launch["damping_model"] == "cubic" and launch["restoring_terms"] == 3
    assert launch["cubic_damping"] == pytest.approx(5.0, rel=0.05)
    assert launch["restoring_correction"]["C3"] == pytest.approx(-200.0, rel=0.03)
    assert launch["std_error"]["cubic_damping"] > 0
    code, _, err = run_cli(
        "identify", rig_path, f, "--json", tmp_path / "x.json", "--method", "log-decrement", "--damping-model", "cubic"
    )  # fmt: skip
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--method output-error" in err


def test_roll_speed_re_and_kc_use_the_tip_of_the_body() -> None:
    # a rotating body's speed for Re and KC is its tip's, L_ref/2 from the axis: from the
    # record's own finite differences, u_max = (L/2)·max|φ̇| (L = 1.6 m, so L/2 and 1/(2L) differ)
    L = 1.6
    rig = rig_of("pitch", {"gm": 0.3}, reference_length=L)
    launch = simulate_launch(rig, 2.0, 1.0, 3.0, math.radians(10.0), 20.0, SensorModel(200.0, 0, 0, 0), rng=0)
    res = identify_launch(rig, trim_launch(launch), "output-error")
    t, y = np.asarray(launch.t), np.asarray(launch.y)
    rate = float(np.max(np.abs(np.gradient(y, t))))  # rad/s
    u = res.extra["speed_max"]
    assert u == pytest.approx(0.5 * L * rate, rel=0.01)
    assert res.reynolds_max == pytest.approx(u * L / 1.0e-6, rel=1e-9)
    assert res.kc == pytest.approx(u * res.extra["period"] / L, rel=1e-9)


def test_extended_fit_formal_covariance_is_curve_fits() -> None:
    # a second method: scipy's curve_fit on the same model (the extended ODE, free ω², b, g, d,
    # q0, v0, rest), started at the estimate, gives s² (JᵀJ)⁻¹ with s² = SSR/(n − p). A short
    # record (n ≈ 200, p = 7) makes the degrees of freedom matter: n + p would be 7 % off
    from scipy.optimize import curve_fit

    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0}, math.radians(15), 2, duration=4.0)
    _, est = identify_launch(rig, L, damping_model="cubic", return_estimator=True)
    t, y = np.asarray(L.t, float), np.asarray(L.y, float)
    shape, sub = est.constants_.restoring, est.substeps

    def model(tt: np.ndarray, w2: float, b: float, g: float, d: float, q0: float, v0: float, c: float) -> np.ndarray:
        q, _, _ = simulate_extended(tt, [w2, b, g, d, 0.0, 0.0], q0, v0, shape, sub)
        return q + c

    x = [*est.ext_[:4], est.q0_, est.v0_, est.offset_]
    popt, pcov = curve_fit(model, t, y, p0=x, xtol=1e-14, ftol=1e-14)
    assert popt[:4] == pytest.approx(x[:4], rel=1e-5)
    np.testing.assert_allclose(est.pcov4_formal_, pcov[:4, :4], rtol=1e-3, atol=1e-3 * np.abs(pcov[:4, :4]).max())
    # the stated (cycle-jackknife) covariance keeps d's own variance, never below the formal one
    assert est.pcov4_[3, 3] >= est.pcov4_formal_[3, 3] > 0


def test_equivalent_damping_on_a_disturbed_record_keeps_the_cubic_terms_jackknife_variance() -> None:
    # a 0.2° disturbance at 0.37 Hz that no damping law models: the residual is not the sensor's
    # noise, so the stated covariance is the cycle jackknife, which is never below the formal one
    # (estimators.py). B_e(a) = A(b + K2 ω a g + K3 ω² a² d) then carries d's jackknife variance:
    # at 0.25 rad the K3 a² term dominates, and a covariance that dropped d's row would fall
    # under the formal error
    from hydrokit.identify.damping import equivalent_damping
    from hydrokit.identify.types import Launch

    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0}, math.radians(15), 3, duration=20.0)
    t = np.asarray(L.t, float)
    y = np.asarray(L.y, float) + math.radians(0.2) * np.sin(2 * math.pi * 0.37 * t)
    _, est = identify_launch(rig, Launch(t, y, "disturbed"), damping_model="cubic", return_estimator=True)
    assert not est.adequacy_["verdict"].startswith("adequate")
    np.testing.assert_array_equal(est.pcov4_[:3, :3], est.pcov_)
    # second method: the gradient of B_e over (ω², b, g, d) by central differences, over the
    # jackknife 6×6 covariance the derived coefficients (B3, C3, C5) are stated with
    jackknife = est._derived_[1][:4, :4]
    S = est.constants_.S

    def b_e(p: np.ndarray, a: float) -> float:
        w2, b, g, d = p
        return S / w2 * (b + 8 / (3 * math.pi) * math.sqrt(w2) * a * g + 0.75 * w2 * a * a * d)

    p0 = np.asarray(est.ext_[:4], float)
    for entry in equivalent_damping(est, rig, [0.1, 0.25]):
        a = entry["amplitude"]
        grad = np.zeros(4)
        for i in range(4):
            h = np.zeros(4)
            h[i] = 1e-6 * max(abs(p0[i]), 1e-3)
            grad[i] = (b_e(p0 + h, a) - b_e(p0 - h, a)) / (2 * h[i])
        assert entry["std_error"] == pytest.approx(math.sqrt(grad @ jackknife @ grad), rel=1e-5)
        assert entry["std_error"] >= entry["std_error_formal"] > 0, entry
    # B3 = d·S/ω² is stated over the same covariance as m_a, K_L, K_Q: the public pcov4_, here
    # the jackknife, not the formal one the fit also keeps
    r = identify_launch(rig, Launch(t, y, "disturbed"), damping_model="cubic")
    w2, d = p0[0], p0[3]
    g = np.array([-d * S / w2**2, 0.0, 0.0, S / w2])
    assert r.std_error["cubic_damping"] == pytest.approx(math.sqrt(g @ est.pcov4_ @ g), rel=1e-6)
    assert r.std_error["cubic_damping"] > 1.2 * math.sqrt(g @ est.pcov4_formal_ @ g)


def test_heave_speed_for_re_and_kc_is_the_records_own_rate() -> None:
    # a heaving body moves as a whole: u_max = max|ż| (no lever arm), Re = u L/ν
    rig = rig_of("heave", {"waterplane_area": 0.05}, reference_length=0.4)
    launch = simulate_launch(rig, 2.0, 1.0, 3.0, 0.05, 20.0, SensorModel(200.0, 0, 0, 0), rng=0)
    res = identify_launch(rig, trim_launch(launch), "output-error")
    t, y = np.asarray(launch.t), np.asarray(launch.y)
    rate = float(np.max(np.abs(np.gradient(y, t))))  # m/s
    assert res.extra["speed_max"] == pytest.approx(rate, rel=0.01)
    assert res.reynolds_max == pytest.approx(rate * 0.4 / 1.0e-6, rel=0.01)


@pytest.mark.parametrize("damping_model", ["quadratic", "cubic"])
def test_a_fit_at_the_noise_floor_tries_no_other_start(monkeypatch, damping_model) -> None:
    # docs/identify.md (output-error): "restarts when the residual is above twice the noise
    # floor": a clean launch of the fitted model is explained by the first start, so the
    # least-squares solver runs once, for the quadratic and for the extended (cubic) fit alike
    import scipy.optimize

    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0, "B3": 5.0 * (damping_model == "cubic")}, 0.26, 4)
    calls = []
    real = scipy.optimize.least_squares
    monkeypatch.setattr(scipy.optimize, "least_squares", lambda *a, **k: calls.append(1) or real(*a, **k))
    r, est = identify_launch(rig, L, damping_model=damping_model, return_estimator=True)
    assert est.rms_residual_ <= 2.0 * est.noise_
    assert len(calls) == 1
    assert r.added_mass == pytest.approx(2.0, rel=0.01)


def test_a_fit_above_twice_the_noise_floor_tries_the_other_starts(monkeypatch) -> None:
    # the other side of the restart rule: a 3.7 Hz ripple of 0.08° (no rig model has it) leaves
    # a residual between 2 and 3 noise floors, so every start (equation error, log decrement,
    # period) is tried
    import scipy.optimize

    from hydrokit.identify.types import Launch

    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0}, 0.26, 4)
    t = np.asarray(L.t, float)
    y = np.asarray(L.y, float) + math.radians(0.08) * np.sin(2 * math.pi * 3.7 * t)
    calls = []
    real = scipy.optimize.least_squares
    monkeypatch.setattr(scipy.optimize, "least_squares", lambda *a, **k: calls.append(1) or real(*a, **k))
    _, est = identify_launch(rig, Launch(t, y, "ripple"), return_estimator=True)
    assert 2.0 < est.rms_residual_ / est.noise_ < 3.0
    assert len(calls) == 3
    # restarts = extra starts after the first (docstring): 0 → one solve, 1 → two
    for restarts in (0, 1):
        for model in ("quadratic", "cubic"):
            calls.clear()
            identify_launch(rig, Launch(t, y, "ripple"), restarts=restarts, damping_model=model)
            assert len(calls) == 1 + restarts, model


def test_the_period_start_alone_fits_a_launch_about_a_distant_rest_value(monkeypatch) -> None:
    # when neither equation error nor the log decrement gives a start, the output-error fit
    # starts from the period alone (released at y[0], resting at the measured offset) and must
    # still find the coefficients, here about a rest value 20 times the amplitude
    from hydrokit.identify.estimators import EquationErrorEstimator, LogDecrementEstimator
    from hydrokit.identify.types import Launch

    def refuse(self, t, y, facts):  # noqa: ANN001, ANN202
        raise InputError("no start from this method")

    monkeypatch.setattr(EquationErrorEstimator, "_fit", refuse)
    monkeypatch.setattr(LogDecrementEstimator, "_fit", refuse)
    rig = rig_of("pitch", {"gm": 0.3})
    L = _extended_launch(rig, {"I_a": 2.0, "B1": 1.0, "B2": 3.0}, 0.1, 5)
    r = identify_launch(rig, Launch(L.t, np.asarray(L.y) + 2.0, "offset"), restarts=0)
    assert r.added_mass == pytest.approx(2.0, rel=0.01)
    assert r.linear_damping == pytest.approx(1.0, rel=0.1)


@pytest.mark.parametrize(("rms", "peak", "warned"), [(1.5e-9, 0.5, True), (1.5e-9, 2.0, False), (4e-9, 2.0, True)])
def test_residual_warning_floor_is_a_billionth_of_the_larger_of_one_and_the_peak(rms, peak, warned) -> None:
    # docs/identify.md, adequacy: warned above 3× the noise floor and above 1e-9 × max(1, |y|max)
    # (noise-free here, floored at 1e-12 as the fits do, so the 1e-9 floor decides)
    from hydrokit.identify.estimators import OutputErrorEstimator

    est = OutputErrorEstimator(rig_of("pitch", {"gm": 0.3}))
    est.warnings_ = []
    est._warn_residual(rms, 1e-12, np.array([0.0, -peak, 0.3 * peak]))  # the fits floor the noise at 1e-12
    assert bool(est.warnings_) is warned


def test_a_floating_rig_built_with_only_its_linear_restoring_is_written_as_floating() -> None:
    # a Rig made in Python for a roll decay may give C1 as its stiffness and no file spec: its
    # document is a floating rig with restoring [C1] (once written as a torsion rig), which reads
    # back to the same restoring constants
    import dataclasses

    bare = Rig("floating", "roll", G, RHO, 1e-6, 100.0, VOL, 0.5, 1.0, inertia=8.0, stiffness=123.0)
    doc_ = rig_document(bare)
    assert doc_["floating"] == {"restoring": [123.0]} and "torsion" not in doc_
    back = parse_rig(doc_, "float.yaml")
    assert back == dataclasses.replace(bare, source="float.yaml", floating=("restoring", (123.0, 0.0, 0.0)))
    assert rig_constants(back).S == rig_constants(bare).S == 123.0
