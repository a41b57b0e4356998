"""``terms.<term>`` parameters in a vehicle file's ``uncertainty:`` block (issue #44): read,
checked, drawn (the term's SI coefficient perturbed, its sign kept) and written back by
``hydrokit sysid`` with the full covariance."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.vehicle import parse_vehicle
from hydrokit.model.uncertainty import Uncertainty, parameter_value, with_coefficients

BASE = DATA_DIR / "vehicles" / "bluerov2-sysid.yaml"
PARAMS = ["added_mass.surge", "terms.N_r|r|", "terms.Z_wdot"]
#: σ 0.2 kg, 0.4 N·m·s²/rad², 0.05 kg; ρ(added_mass.surge, N_r|r|) = −0.6
COV = [[0.04, -0.048, 0.0], [-0.048, 0.16, 0.0], [0.0, 0.0, 0.0025]]


def doc_with(block: dict[str, Any] | None, terms: dict[str, Any] | None = None) -> dict[str, Any]:
    doc = yaml.safe_load(BASE.read_text())
    doc.pop("thrusters")
    doc["terms"] = {"N_r|r|": -0.3} if terms is None else terms
    doc["uncertainty"] = block
    return doc


def block(**change: Any) -> dict[str, Any]:
    return {"added_mass": [0.2, 0, 0, 0, 0, 0], "parameters": list(PARAMS), "covariance": COV} | change


def test_a_term_parameter_is_read_and_names_the_terms_si_coefficient():
    v = parse_vehicle(doc_with(block()), "v.yaml")
    assert v.uncertainty.parameters == tuple(PARAMS)
    np.testing.assert_array_equal(v.uncertainty.covariance, COV)
    # a velocity term: its coefficient as the file states it; an acceleration term: −M_A[dof, acc]
    # (SNAME: Z_wdot = −M_A[2, 2] = −18.68 kg from the file's added_mass; Y_rdot = −M_A[1, 5] = 0)
    assert parameter_value(v, "terms.N_r|r|") == -0.3
    assert parameter_value(v, "terms.Z_wdot") == -18.68
    assert parameter_value(v, "terms.Y_rdot") == 0.0
    w = with_coefficients(v, {"terms.N_r|r|": -0.9, "terms.Y_rdot": -0.25, "linear_damping.yaw": 2.0})
    assert w.terms.coef.tolist() == [-0.9] and v.terms.coef.tolist() == [-0.3]  # the original untouched
    assert w.M_A[1, 5] == 0.25 and w.D_L[5, 5] == 2.0 and w.M_A[0, 0] == v.M_A[0, 0]


def test_drawn_samples_perturb_the_term_with_the_stated_covariance_and_keep_its_sign():
    v = parse_vehicle(doc_with(block()), "v.yaml")
    vehicles, values, clipped = v.uncertainty.sample_vehicles(v, 20000, seed=5)
    # N_r|r| = −0.3 ± 0.4: about 23 % of the draws are positive (Φ(−0.75)); a term keeps its
    # sign, so nothing of it is clipped; surge added mass 6.36 ± 0.2 is 30 σ from zero
    assert clipped == 0
    assert np.mean(values[:, 1] > 0) == pytest.approx(0.2266, abs=0.01)  # binomial sd 0.003
    # sample mean and covariance of 20 000 draws against the stated ones: the mean within 4 sd
    # (sd σ/√n), the variances within 3 % (relative sd √(2/n) = 1 %), ρ within 0.03 (sd 0.006)
    mean = [v.M_A[0, 0], -0.3, -v.M_A[2, 2]]
    sd = np.sqrt(np.diag(COV))
    assert np.all(np.abs(values.mean(axis=0) - mean) < 4 * sd / np.sqrt(20000))
    sample = np.cov(values, rowvar=False)
    assert np.diag(sample) == pytest.approx(np.diag(COV), rel=0.03)
    assert sample[0, 1] / np.sqrt(sample[0, 0] * sample[1, 1]) == pytest.approx(-0.6, abs=0.03)
    # the drawn values are in the vehicles, nothing else changed
    k = 11
    assert vehicles[k].terms.coef[0] == values[k, 1] and vehicles[k].M_A[2, 2] == -values[k, 2]
    assert vehicles[k].M_A[0, 0] == values[k, 0] and np.array_equal(vehicles[k].D_Q, v.D_Q)


def test_only_diagonal_coefficients_are_clipped_at_zero():
    u = Uncertainty(("linear_damping.surge", "terms.X_u|u|"), np.diag([1.0, 1.0]))
    values, clipped = u.draw(np.array([0.0, 0.0]), 4000, seed=2)
    # both means at 0: half of each column drawn below zero; only the damping is set to 0
    assert clipped == int(np.sum(values[:, 0] == 0.0))
    assert clipped == pytest.approx(2000, abs=200)  # binomial sd 32
    assert np.mean(values[:, 1] < 0) == pytest.approx(0.5, abs=0.05)


@pytest.mark.parametrize(
    ("change", "says"),
    [
        (
            {"parameters": ["added_mass.surge", "terms.N_vv", "terms.Z_wdot"]},
            r"'uncertainty\.parameters\[1\]' = 'terms\.N_vv': the vehicle has no such term",
        ),
        (
            {"parameters": ["added_mass.surge", "terms.X_udot", "terms.Z_wdot"]},
            r"names 'terms\.X_udot' twice \(as 'added_mass\.surge'\)",
        ),
        (
            {"parameters": ["added_mass.surge", "terms.N_|r|r", "terms.N_r|r|"]},
            r"names 'terms\.N_r\|r\|' twice \(as 'terms\.N_\|r\|r'\)",
        ),
        (
            {"parameters": ["added_mass.surge", "terms.Q_uu", "terms.Z_wdot"]},
            r"'uncertainty\.parameters\[1\]' = 'terms\.Q_uu'",
        ),
        (
            {"parameters": ["added_mass.surge", "terms.", "terms.Z_wdot"]},
            r"'uncertainty\.parameters\[1\]' = 'terms\.': expected",
        ),
    ],
)
def test_a_bad_term_parameter_is_one_line_naming_the_field(change, says):
    with pytest.raises(InputError, match=says):
        parse_vehicle(doc_with(block(**change)), "v.yaml")


def test_a_term_spelt_otherwise_in_the_file_is_the_same_term():
    v = parse_vehicle(doc_with(block(), terms={"N_|r|r": -0.3}), "v.yaml")
    assert parameter_value(v, "terms.N_r|r|") == -0.3
    with pytest.raises(InputError, match=r"parameter 'terms\.N_vv': the vehicle 'bluerov2-sysid' has no such term"):
        parameter_value(v, "terms.N_vv")


def test_sysid_writes_every_free_parameter_and_the_file_reads_it_back():
    """Round trip: an identification with two terms → vehicle.yaml → the vehicle file reader."""
    from hydrokit.report.sysid import vehicle_document

    base = yaml.safe_load(BASE.read_text())
    base["added_mass"] = np.diag(base["added_mass"]).tolist()  # as a matrix: M_A[2, 2] = 18.68 kg
    base["terms"] = {"N_|r|r": -0.5}  # the free N_r|r| spelt otherwise
    names = ("linear_damping.yaw", "terms.N_r|r|", "terms.Z_wdot")
    values = np.array([0.6, -1.2, -15.0])
    cov = np.array([[1e-4, -2e-4, 0.0], [-2e-4, 9e-4, 1e-5], [0.0, 1e-5, 4e-4]])
    result = SimpleNamespace(
        parameters=names,
        values=values,
        covariance=cov,
        method="output-error",
        runs=[{"name": "dive1", "holdout": False}],
    )
    doc = vehicle_document(result, base)  # type: ignore[arg-type]
    v = parse_vehicle(yaml.safe_load(yaml.safe_dump(doc)), "vehicle.yaml")
    assert v.uncertainty.parameters == names
    np.testing.assert_allclose(v.uncertainty.covariance, cov, rtol=1e-15)
    assert doc["uncertainty"]["linear_damping"][5] == pytest.approx(0.01)
    # each identified value is what the read vehicle holds: N_r|r| replaced (not added twice),
    # Z_wdot written as the file term that, with the file's M_A[2, 2] = 18.68, gives 15 kg
    assert list(doc["terms"]) == ["N_|r|r", "Z_wdot"]
    assert doc["terms"]["Z_wdot"]["value"] == pytest.approx(18.68 - 15.0)
    for name, value in zip(names, values):
        assert parameter_value(v, name) == pytest.approx(value, rel=1e-12)
    assert v.M_A[2, 2] == pytest.approx(15.0, rel=1e-12)


def test_simulate_samples_draws_the_term_from_the_file():
    from hydrokit.simulate.samples import simulate_samples

    v = parse_vehicle(doc_with(block()), "v.yaml")
    # a yaw moment spins the vehicle: N_r|r| brakes it, so the drawn terms spread the yaw rate
    runs = simulate_samples(v, 3, 4, duration=0.5, dt=0.05, tau=[0, 0, 0, 0, 0, 2.0])
    assert runs.parameters == tuple(PARAMS)
    np.testing.assert_array_equal(runs.values, v.uncertainty.sample_vehicles(v, 3, 4)[1])
    r_end = runs.states[:, -1, 11]
    assert np.all(np.isfinite(r_end)) and np.ptp(r_end) > 0
