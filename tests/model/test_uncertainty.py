"""The ``uncertainty:`` block of a vehicle file: read into the vehicle, checked, sampled (issue 32,
class 8), and written by ``hydrokit run`` for every chosen coefficient with a σ."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.vehicle import parse_vehicle

BASE = DATA_DIR / "projects" / "udrobot" / "base.yaml"
COV = [[0.0025, 1.2e-4, 0.021], [1.2e-4, 0.0092, -0.047], [0.021, -0.047, 2.78]]
PARAMS = ["added_mass.surge", "linear_damping.surge", "quadratic_damping.surge"]


def doc_with(block: dict) -> dict:
    doc = yaml.safe_load(BASE.read_text())
    doc["uncertainty"] = block
    return doc


def run_block() -> dict:
    """A block as ``hydrokit run`` writes it: σ per coefficient and the covariance of the tank's."""
    s = np.sqrt(np.diag(COV))
    return {
        "description": "standard errors",
        "added_mass": [s[0], 0, 0, 0, 0, 0],
        "linear_damping": [s[1], 0, 0, 0, 0, 0],
        "quadratic_damping": [s[2], 0.5, 0, 0, 0, 0],  # sway's K_Q from a CFD fit: σ, no covariance row
        "parameters": list(PARAMS),
        "covariance": COV,
    }


def test_the_block_is_read_into_the_vehicle_with_every_sigma():
    v = parse_vehicle(doc_with(run_block()), "v.yaml")
    u = v.uncertainty
    assert u.parameters == (*PARAMS, "quadratic_damping.sway")
    assert np.array_equal(u.covariance[:3, :3], np.asarray(COV))
    # the σ the covariance does not hold is sampled too, independent of the rest
    assert u.covariance[3, 3] == 0.25 and not u.covariance[3, :3].any()
    assert u.std[1] == pytest.approx(math.sqrt(0.0092), rel=1e-15)


def test_a_vehicle_without_the_block_or_with_only_zeros_has_no_uncertainty():
    assert parse_vehicle(doc_with(None), "v.yaml").uncertainty is None  # type: ignore[arg-type]
    assert parse_vehicle(doc_with({"added_mass": [0] * 6}), "v.yaml").uncertainty is None


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ({"parameters": ["added_mass.hover", *PARAMS[1:]]}, r"'uncertainty\.parameters\[0\]' = 'added_mass\.hover'"),
        ({"parameters": [PARAMS[0], PARAMS[0], PARAMS[2]]}, "names 'added_mass.surge' twice"),
        ({"covariance": [[1.0, 0.0], [0.0, 1.0]]}, r"shape \(2, 2\); expected a 3×3 matrix"),
        ({"covariance": [[0.0025, 1e-3, 0], [0, 0.0092, 0], [0, 0, 2.78]]}, "not symmetric"),
        ({"covariance": [[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]]}, "smallest eigenvalue -1; expected a positive"),
        ({"linear_damping": [0.2, 0, 0, 0, 0, 0]}, r"'uncertainty\.linear_damping' = 0\.2 for surge: the covariance"),
        ({"added_mass": [-0.05, 0, 0, 0, 0, 0]}, r"expected 6 standard errors ≥ 0"),
        ({"samples": 50}, r"unknown key\(s\) \['samples'\]"),
        ({"covariance": [[".nan", 0, 0], [0, 1, 0], [0, 0, 1]]}, "expected a 3×3 matrix of finite numbers"),
    ],
)
def test_a_bad_block_is_one_line_naming_the_field(change, says):
    block = run_block() | change
    if "added_mass" in change and change["added_mass"][0] < 0:
        block["covariance"] = COV
    with pytest.raises(InputError, match=says):
        parse_vehicle(doc_with(block), "v.yaml")


def test_drawn_vehicles_have_the_stated_covariance_about_their_own_values():
    v = parse_vehicle(doc_with(run_block()), "v.yaml")
    vehicles, values, clipped = v.uncertainty.sample_vehicles(v, 20000, seed=3)
    assert clipped == 0  # all means are many σ above zero
    # the sample covariance of 20 000 draws is the stated one within 3 % on the diagonal
    # (relative sd √(2/n) = 1 %) and 0.03 in correlation (sd 1/√n = 0.007)
    sample = np.cov(values, rowvar=False)
    stated = v.uncertainty.covariance
    assert np.diag(sample) == pytest.approx(np.diag(stated), rel=0.03)
    corr = lambda c: c / np.sqrt(np.outer(np.diag(c), np.diag(c)))  # noqa: E731
    assert np.abs(corr(sample) - corr(stated)).max() < 0.03
    assert values.mean(axis=0) == pytest.approx([v.M_A[0, 0], v.D_L[0, 0], v.D_Q[0], v.D_Q[1]], rel=1e-3)
    # the drawn values are in the vehicles, the rest untouched
    k = 17
    assert vehicles[k].M_A[0, 0] == values[k, 0] and vehicles[k].D_L[0, 0] == values[k, 1]
    assert vehicles[k].D_Q[1] == values[k, 3] and vehicles[k].D_Q[2] == v.D_Q[2]
    assert np.array_equal(vehicles[k].M_A[1:, 1:], v.M_A[1:, 1:])
    # one seeded generator: the same seed gives the same vehicles
    assert np.array_equal(v.uncertainty.sample_vehicles(v, 5, seed=3)[1], values[:5])


def test_the_run_samples_every_chosen_coefficient_with_a_sigma_whatever_its_source():
    from hydrokit.pipeline.compare import vehicle_document

    base = yaml.safe_load(BASE.read_text())
    chosen = {
        d: {
            c: {"value": 1.0, "source": "base", "se": None}
            for c in ("added_mass", "linear_damping", "quadratic_damping")
        }
        for d in ("surge", "sway", "heave", "roll", "pitch", "yaw")
    }
    chosen["surge"]["added_mass"] = {"value": 10.0, "source": "tank", "se": 0.05}
    chosen["surge"]["quadratic_damping"] = {"value": 43.0, "source": "cfd", "se": 0.4}
    chosen["heave"]["linear_damping"] = {"value": 3.0, "source": "cfd", "se": 0.2}
    tank = {"surge": {"covariance": [[0.0025, 0, 0], [0, 9, 0], [0, 0, 16]]}}
    project = SimpleNamespace(name="p", virtual=True)
    unc = vehicle_document(base, chosen, tank, project)["uncertainty"]  # type: ignore[arg-type]
    # before: only the tank's added_mass.surge was sampled; the CFD fit's σ stopped at the file
    assert unc["parameters"] == ["added_mass.surge", "quadratic_damping.surge", "linear_damping.heave"]
    assert np.allclose(unc["covariance"], np.diag([0.0025, 0.16, 0.04]), rtol=1e-12)
