"""The sources' arithmetic (issue #2 acceptance), numbers from SPEC tables as cited."""

from __future__ import annotations

import pytest

from hydrokit.identify.campaign import rank_sum, rank_sum_pairs, z_to_p
from hydrokit.identify.rig_model import rig_constants
from hydrokit.identify.scaling import SCALING_ASSUMPTIONS, scale_coefficients, scale_factor
from hydrokit.identify.tare import air_tare
from hydrokit.identify.types import Rig


def test_eng2009_air_test_effective_length(published):
    air = published["eng2009"]["air_test"]
    # ENG2009 §IV.A: α = −25.128 → r = −g/α = 0.3904 m (against 0.39 m measured)
    tare = air_tare(air["alpha"], air["beta"], air["gamma"], mass=1.0, gravity=9.81)
    assert tare.effective_length == pytest.approx(air["r_fit"], abs=5e-5)


def test_cely2019_table7_added_mass_via_S2(published):
    spring = published["cely2019"]["spring_rig"]
    wn = published["cely2019"]["table7_spring"]["omega_n"]
    rig = Rig(
        test="spring",
        axis="surge",
        gravity=9.81,
        density=998.2,
        kinematic_viscosity=1e-6,
        mass=spring["mass"],
        volume=spring["volume_mm3"] * 1e-9,
        reference_area=0.01,
        reference_length=0.1,
        stiffness=spring["stiffness"],
    )
    c = rig_constants(rig)
    m_a = [c.from_normalised(w * w, 0.0, 0.0)[0] for w in wn]
    # SPEC §1.1: k/ω_n² − m = 0.287, 0.068, 0.398 kg
    assert m_a == pytest.approx([0.287, 0.068, 0.398], abs=6e-4)


def test_eng2009_scaling(published):
    lam = scale_factor(published["eng2009"]["scale"])
    full = scale_coefficients({"added_mass": 0.58, "quadratic_damping": 9.5439, "linear_damping": 1.5515}, lam)
    assert full["added_mass"] == pytest.approx(21.48, abs=0.005)  # ENG2009 Table III
    assert full["quadratic_damping"] == pytest.approx(106.04, abs=0.005)  # Table IV
    assert full["linear_damping"] == pytest.approx(17.24, abs=0.005)
    assert lam**5 == pytest.approx(published["eng2009"]["scaling"]["rotational_drag"], abs=0.01)
    assert any("Reynolds" in a for a in SCALING_ASSUMPTIONS)


def test_rank_sum_z_to_p_cely2019(published):
    p, z = published["cely2019"]["table6_spring_added_mass_pairs"]["1-2"][0]
    # CELY2019 Table 6, pair L1–L2, x axis: z = −1.286 ↔ p = 0.198 (two-sided normal)
    assert z_to_p(z) == pytest.approx(p, abs=5e-4)


def test_rank_sum_against_hand_count():
    # x all below y: U = 0 (scipy reports U of x); n1 = n2 = 6: z = (0 − 18)/√(36·13/12) = −2.882
    r = rank_sum([1, 2, 3, 4, 5, 6], [7, 8, 9, 10, 11, 12], continuity=False)
    assert r["u"] == 0
    assert r["z"] == pytest.approx(-18 / (36 * 13 / 12) ** 0.5, rel=1e-12)
    assert r["p"] == pytest.approx(z_to_p(r["z"]), rel=1e-9)
    # exact: U = 0 is the single most extreme of C(12, 6) = 924 orderings, two-sided p = 2/924
    assert r["p_exact"] == pytest.approx(2 / 924, rel=1e-12)


def test_rank_sum_with_continuity_reproduces_cely2019_tables_8_9():
    # CELY2019 Tables 8–9 print U = 36 → z = 2.8022, p = 0.0051 and U = 17 → z = −0.080, p = 0.9362
    # for 6 × 6 launches: the normal approximation with the continuity correction,
    # z = (U − 18 ∓ ½)/√39.
    r = rank_sum([7, 8, 9, 10, 11, 12], [1, 2, 3, 4, 5, 6])
    assert r["u"] == 36
    assert r["z"] == pytest.approx(2.8022, abs=5e-5)
    assert r["p"] == pytest.approx(0.0051, abs=5e-5)
    x, y = [1, 2, 6, 8, 9, 12], [3, 4, 5, 7, 10, 11]  # pairs with x > y: 0+0+3+4+4+6 = 17
    r = rank_sum(x, y)
    assert r["u"] == sum(a > b for a in x for b in y) == 17
    assert r["z"] == pytest.approx(-0.080, abs=5e-4)
    assert r["p"] == pytest.approx(0.9362, abs=5e-5)
    # without the correction the same data give z = −1/√39 = −0.160
    assert rank_sum(x, y, continuity=False)["z"] == pytest.approx(-1 / 39**0.5, rel=1e-12)


def test_rank_sum_pairs_tests_every_pair_once_and_skips_single_launch_groups():
    # CELY2019 Tables 8–9 compare every pair of amplitude groups: 3 groups give 3 tests, in
    # order, each the same as rank_sum on the pair; a group of one launch cannot be ranked
    groups = {"10 mm": [7, 8, 9, 10, 11, 12], "20 mm": [1, 2, 3, 4, 5, 6], "30 mm": [1, 2, 6, 8, 9, 12]}
    rows = rank_sum_pairs({**groups, "40 mm": [5.0]})
    assert [r["pair"] for r in rows] == [["10 mm", "20 mm"], ["10 mm", "30 mm"], ["20 mm", "30 mm"]]
    for r in rows:
        a, b = r["pair"]
        assert r["u"] == rank_sum(groups[a], groups[b])["u"]
    assert rows[0]["u"] == 36  # Table 8's U for wholly separated groups


@pytest.mark.parametrize("ratio", [0, -0.3, float("inf"), float("nan"), "0.3", None])
def test_scale_ratio_must_be_a_positive_finite_number(ratio):
    from hydrokit.errors import InputError

    with pytest.raises(InputError, match=r"scale ratio = .*: expected a positive model/full-size length ratio"):
        scale_factor(ratio)  # type: ignore[arg-type]
    assert scale_factor(0.25) == 4.0  # λ = full/model


@pytest.mark.parametrize("continuity", [False, True])
def test_rank_sum_with_ties_matches_scipys_tie_corrected_normal_p(continuity):
    # tied values shrink σ_U by the tie term Σ(c³ − c)/(n(n − 1)); scipy's asymptotic
    # Mann–Whitney p applies the same correction (and the same ½ continuity step): a second
    # method. Here the ties are heavy (groups of 2 and 3), so a wrong tie term moves p visibly
    from scipy import stats

    x, y = [1.0, 2.0, 2.0, 3.0, 3.0, 3.0], [2.0, 3.0, 4.0, 4.0, 5.0, 5.0]
    r = rank_sum(x, y, continuity=continuity)
    ref = stats.mannwhitneyu(x, y, alternative="two-sided", method="asymptotic", use_continuity=continuity)
    assert r["u"] == float(ref.statistic)
    assert r["p"] == pytest.approx(float(ref.pvalue), rel=1e-10)
    assert r["p_exact"] is None  # no exact distribution with ties
