"""Vehicles out (issue #12 item 7): Gazebo and uuv_simulator round trips in their own frame,
and the linearised model against closed forms and the nonlinear model."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.io.export import (
    added_mass_ratio,
    export_checks,
    gazebo_sdf,
    read_gazebo_sdf,
    read_uuv_parameters,
    to_flu,
    uuv_parameters,
)
from hydrokit.io.vehicle import resolve_vehicle


def coupled_vehicle():
    """Minerva with off-diagonal added mass and linear damping and a CG below the origin, so
    that every sign of the FRD → FLU change is exercised."""
    doc = yaml.safe_load(resolve_vehicle("minerva").read_text())
    MA = np.diag(doc["added_mass"]).astype(float)
    MA[0, 4] = MA[4, 0] = 12.0  # surge–pitch: one index in {w, q, r} → sign flips in FLU
    MA[1, 5] = MA[5, 1] = -7.0  # sway–yaw: both flip → unchanged
    DL = np.diag(doc["linear_damping"]).astype(float)
    DL[2, 4] = 3.0
    doc.update(added_mass=MA.tolist(), linear_damping=DL.tolist(), center_of_gravity=[0.01, 0.02, 0.05])
    doc["name"] = "coupled--test <&>"
    return hydrokit.vehicle_from_dict(doc)


def test_flu_change_of_frame_flips_exactly_the_mixed_entries():
    M = np.arange(36.0).reshape(6, 6)
    F = to_flu(M)
    flip = np.array([1, -1, -1, 1, -1, -1])
    assert np.array_equal(F, M * np.outer(flip, flip))
    assert np.array_equal(to_flu(F), M)  # its own inverse


def test_gazebo_round_trip_returns_the_vehicle_matrices():
    v = coupled_vehicle()
    text = gazebo_sdf(v)
    ET.fromstring(text)  # well-formed despite "--", "<" and "&" in the name
    back = read_gazebo_sdf(text)
    for key, mine in (("M_A", v.M_A), ("D_L", v.D_L), ("D_Q", v.D_Q), ("inertia", v.inertia), ("r_g", v.r_g)):
        assert np.allclose(back[key], mine, rtol=1e-11, atol=1e-12), key
    assert back["mass"] == v.mass


def test_gazebo_values_are_sname_derivatives_in_flu():
    v = coupled_vehicle()
    hyd = ET.fromstring(gazebo_sdf(v)).find(".//plugin[@name='gz::sim::systems::Hydrodynamics']")
    # X_udot = −m_a (negative), X_q̇ in FLU = −(−12) because w/q/r flip sign once
    assert float(hyd.findtext("xDotU")) == -v.M_A[0, 0]
    assert float(hyd.findtext("xDotQ")) == pytest.approx(12.0)
    assert float(hyd.findtext("yDotR")) == pytest.approx(7.0)  # both flip: −(−7)
    assert float(hyd.findtext("xUabsU")) == -v.D_Q[0]
    assert float(hyd.findtext("zQ")) == pytest.approx(-3.0)  # heave and pitch both flip: −(3)
    pose = [float(x) for x in ET.fromstring(gazebo_sdf(v)).findtext(".//link/inertial/pose").split()]
    assert pose[:3] == [0.01, -0.02, -0.05]  # CG 5 cm below the origin is z = −0.05 in FLU
    thrusters = ET.fromstring(gazebo_sdf(v)).findall(".//plugin[@name='gz::sim::systems::Thruster']")
    assert len(thrusters) == len(v.thrusters)


def test_uuv_round_trip_and_signs():
    v = coupled_vehicle()
    text = uuv_parameters(v)
    back = read_uuv_parameters(text)
    assert np.allclose(back["M_A"], v.M_A, rtol=1e-11)
    assert np.allclose(back["D_Q"], v.D_Q, rtol=1e-11)
    assert np.allclose(np.diag(back["D_L"]), np.diag(v.D_L), rtol=1e-11)
    assert "off-diagonal terms the fossen model does not take" in text  # D_L[2, 4] is dropped, said so
    hm = ET.fromstring(text).find(".//hydrodynamic_model")
    assert float(hm.findtext("quadratic_damping").split()[0]) == -v.D_Q[0]  # uuv: negated diagonal


def decoupled_vehicle():
    doc = yaml.safe_load(resolve_vehicle("minerva").read_text())
    doc.update(center_of_gravity=[0, 0, 0], center_of_buoyancy=[0, 0, 0])
    doc["volume"] = doc["mass"] / doc["fluid"]["density"]
    return hydrokit.vehicle_from_dict(doc)


def test_linearised_surge_pole_is_the_closed_form():
    v = decoupled_vehicle()
    u0 = 0.6
    lin = hydrokit.linearize(v, trim=[u0, 0, 0, 0, 0, 0])
    m = v.mass + v.M_A[0, 0]
    # m u̇ = τ − d_L u − d_Q |u| u → ∂u̇/∂u = −(d_L + 2 d_Q u0)/m, and τ0 = d_L u0 + d_Q u0²
    assert lin.A[6, 6] == pytest.approx(-(v.D_L[0, 0] + 2 * v.D_Q[0] * u0) / m, rel=1e-6)
    assert lin.tau0[0] == pytest.approx(v.D_L[0, 0] * u0 + v.D_Q[0] * u0**2, rel=1e-9)
    assert lin.B[6, 0] == pytest.approx(1 / m, rel=1e-6)
    assert lin.A[0, 6] == pytest.approx(1.0, abs=1e-9)  # ẋ = u at zero attitude
    # at zero speed the yaw pole is −d_L,r / (I_z + N_ṙ)
    lin0 = hydrokit.linearize(v)
    Iz = v.inertia[2, 2] + v.M_A[5, 5]
    assert np.any(np.isclose(lin0.eigenvalues.real, -v.D_L[5, 5] / Iz, rtol=1e-5))


def test_linear_model_follows_the_nonlinear_one_for_a_small_push():
    v = hydrokit.load_vehicle("minerva")
    u0 = 0.5
    lin = hydrokit.linearize(v, trim=[u0, 0, 0, 0, 0, 0])
    dtau = np.array([2.0, 1.0, 0.5, 0.0, 0.0, 0.3])  # small against τ0 (≈ 88 N surge)
    t, dx = lin.response(dtau, duration=5.0, dt=0.01)
    traj = hydrokit.simulate(v, 5.0, 0.01, tau=lin.tau0 + dtau, nu0=[u0, 0, 0, 0, 0, 0])
    nu_nl = traj.nu[-1] - lin.x0[6:]
    # the linear deviation is first order in δτ: agreement to a few % of the deviation itself
    assert np.allclose(dx[-1, 6:], nu_nl, atol=0.05 * np.abs(nu_nl).max())
    assert np.abs(nu_nl).max() > 1e-3  # the push does something


def test_python_control_export_loads_without_pickle(tmp_path, run_cli):
    code, _, err = run_cli(
        "export", "minerva", "--format", "python-control", "--out", tmp_path / "m.npz", "--trim", "0.5,0,0,0,0,0"
    )
    assert code == 0, err
    with np.load(tmp_path / "m.npz", allow_pickle=False) as z:
        A, B = z["A"], z["B"]
        assert list(z["inputs"]) == ["X", "Y", "Z", "K", "M", "N"]
    lin = hydrokit.linearize("minerva", trim=[0.5, 0, 0, 0, 0, 0])
    assert np.array_equal(A, lin.A) and np.array_equal(B, lin.B)
    control = pytest.importorskip("control")
    ss = lin.to_statespace()
    assert isinstance(ss, control.StateSpace)
    assert np.allclose(np.sort_complex(ss.poles()), np.sort_complex(lin.eigenvalues))


def test_export_bad_input_is_one_line(tmp_path, run_cli):
    code, _, err = run_cli(
        "export", "minerva", "--format", "python-control", "--out", tmp_path / "m.npz", "--trim", "1,2"
    )
    assert code == 2
    assert err.splitlines() == ["error: --trim '1,2': expected 6 comma-separated finite numbers (m/s and rad/s)"]
    assert not (tmp_path / "m.npz").exists()
    with pytest.raises(hydrokit.InputError, match="format"):
        hydrokit.export_vehicle("minerva", "openfoam")


def test_gazebo_file_via_cli(tmp_path, run_cli):
    # the BlueROV2's heave added mass is 1.38 times its mass: only the <fluid_added_mass> route takes it
    args = ("--format", "gazebo", "--out", tmp_path / "b.sdf", "--added-mass", "inertial")
    code, _, err = run_cli("export", "bluerov2-heavy", *args)
    assert code == 0, err
    back = read_gazebo_sdf((tmp_path / "b.sdf").read_text())
    v = hydrokit.load_vehicle("bluerov2-heavy")
    assert np.allclose(back["M_A"], v.M_A) and np.allclose(back["D_Q"], v.D_Q)


# --- what each target needs (issue 32 class 7) --------------------------------------------------


def vehicle_with(name: str = "minerva", **fields):
    doc = yaml.safe_load(resolve_vehicle(name).read_text())
    doc.update(fields)
    return hydrokit.vehicle_from_dict(doc, f"{name}.yaml")


def test_the_added_mass_ratio_is_the_growth_of_an_explicit_added_mass_force():
    """Second method: iterate what gz-sim and uuv_simulator do, M_RB a_n = F − M_A a_(n−1); an
    acceleration error grows or shrinks by ρ(M_RB⁻¹ M_A) per step (power iteration)."""
    for name in ("bluerov2-heavy", "minerva", "udrobot", "lingyun"):
        v = hydrokit.load_vehicle(name)
        rho, _ = added_mass_ratio(v)
        step = -np.linalg.solve(v.M_RB, v.M_A)
        e = np.ones(6)
        for _ in range(400):
            e_next = step @ step @ e  # two steps: the sign alternates
            growth = math.sqrt(np.linalg.norm(e_next) / np.linalg.norm(e))
            e = e_next / np.linalg.norm(e_next)
        assert growth == pytest.approx(rho, rel=1e-6), name
    assert added_mass_ratio(hydrokit.load_vehicle("bluerov2-heavy"))[0] > 1 > added_mass_ratio(v)[0]


@pytest.mark.parametrize(
    ("fmt", "extra", "code_says"),
    [
        ("gazebo", (), (2, "ρ(M_RB⁻¹ M_A) = 1.38 (largest in heave): gz-sim applies −M_A·a")),
        ("uuv-simulator", (), (2, "ρ(M_RB⁻¹ M_A) = 1.38 (largest in heave): uuv_simulator applies −M_A·a")),
        ("gazebo", ("--added-mass", "inertial"), (0, "")),
        ("python-control", (), (0, "")),
    ],
    ids=["gazebo-plugin", "uuv", "gazebo-inertial", "python-control"],
)
def test_an_added_mass_larger_than_the_mass_is_refused_where_it_is_applied_explicitly(
    run_cli, tmp_path, fmt, extra, code_says
):
    out = tmp_path / "o"
    code, _, err = run_cli("export", "bluerov2-heavy", "--format", fmt, "--out", out, *extra)
    assert code == code_says[0], err
    if code == 2:
        line = err.strip()
        assert "\n" not in line and code_says[1] in line and "goes unstable" in line, line
        assert "--added-mass inertial" in line  # the fix
        assert not out.exists()
    else:
        assert out.stat().st_size > 0 and "unstable" not in err


@pytest.mark.parametrize("fmt", ["gazebo", "uuv-simulator"])
def test_an_added_mass_close_to_the_mass_is_warned_in_words_and_in_the_file(run_cli, tmp_path, fmt):
    code, _, err = run_cli("export", "udrobot", "--format", fmt, "--out", tmp_path / "o.xml")
    assert code == 0, err
    warned = [line for line in err.splitlines() if line.startswith("warning: added mass against rigid-body mass")]
    assert len(warned) == 1 and "= 0.964 (largest in surge)" in warned[0] and "rings" in warned[0], err
    assert "warning: added mass against rigid-body mass" in (tmp_path / "o.xml").read_text()


def test_the_inertial_route_writes_fluid_added_mass_and_no_explicit_terms():
    v = coupled_vehicle()
    text = gazebo_sdf(v, added_mass="inertial")
    root = ET.fromstring(text)
    assert root.get("version") == "1.10"
    hyd = root.find(".//plugin[@name='gz::sim::systems::Hydrodynamics']")
    assert not [e.tag for e in hyd if "Dot" in e.tag]
    fam = root.find(".//link/inertial/fluid_added_mass")
    assert len(fam) == 21 and float(fam.findtext("xx")) == v.M_A[0, 0]
    assert float(fam.findtext("xq")) == pytest.approx(-12.0)  # surge–pitch flips once in FLU
    assert np.allclose(read_gazebo_sdf(text)["M_A"], v.M_A, rtol=1e-11, atol=1e-12)


def test_added_mass_that_no_fluid_gives_is_refused_for_the_simulators():
    # −293 kg of surge added mass: M_RB + M_A stays positive definite (hydrokit flies it, warned)
    v = vehicle_with(added_mass=[-293, 302, 326, 52, 52, 57])
    for fmt in ("gazebo", "uuv-simulator"):
        with pytest.raises(hydrokit.InputError, match=r"M_A has the eigenvalue -293 .*not positive semi-definite"):
            hydrokit.export_vehicle(v, fmt, added_mass="inertial")
    assert hydrokit.export_vehicle(v, "python-control")  # a linear model of what hydrokit flies


@pytest.mark.parametrize("fmt", ["gazebo", "uuv-simulator", "python-control"])
def test_matrices_no_engine_can_integrate_are_refused_for_every_target(fmt):
    from dataclasses import replace

    v = hydrokit.load_vehicle("minerva")
    bad = np.diag([-500.0, 302, 326, 52, 52, 57])  # −40 kg in surge, less still with the CG's pitch coupling
    low = np.linalg.eigvalsh(v.M_RB + bad).min()
    assert low < -40
    with pytest.raises(hydrokit.InputError, match=rf"M_RB \+ M_A has the eigenvalue {low:.4g}: not positive definite"):
        hydrokit.export_vehicle(replace(v, M_A=bad), fmt, added_mass="inertial")
    skew = np.diag(v.M_A).copy()
    skew = np.diag(skew)
    skew[0, 5] = 3.0
    with pytest.raises(hydrokit.InputError, match=r"M_RB \+ M_A is not symmetric \(by 3\)"):
        hydrokit.export_vehicle(replace(v, M_A=skew), fmt, added_mass="inertial")


def test_provenance_of_a_run_vehicle_goes_into_every_export(tmp_path):
    doc = yaml.safe_load(resolve_vehicle("udrobot").read_text())
    doc["project"] = {
        "name": "tank-2026",
        "virtual_data": False,
        "sources": {"surge": {"added_mass": "tank", "linear_damping": "cfd", "quadratic_damping": "geometry"}},
    }
    v = hydrokit.vehicle_from_dict(doc)
    says = "surge: added_mass tank, linear_damping cfd, quadratic_damping geometry"
    for fmt in ("gazebo", "uuv-simulator"):
        text = hydrokit.export_vehicle(v, fmt, added_mass="inertial").decode()
        comments = [c for c in text.split("<!--")[1:] if c.lstrip().startswith("provenance")]
        assert len(comments) == 1 and "project tank-2026" in comments[0] and says in comments[0], fmt
    (tmp_path / "v.npz").write_bytes(hydrokit.export_vehicle(v, "python-control"))
    with np.load(tmp_path / "v.npz", allow_pickle=False) as z:
        assert says in list(z["provenance"])
    # a vehicle file that says nothing of its sources gets no provenance comment
    assert "provenance" not in hydrokit.export_vehicle("udrobot", "gazebo").decode()


def test_negative_damping_allowed_by_the_file_is_exported_with_a_warning():
    v = hydrokit.vehicle_from_dict(
        yaml.safe_load(resolve_vehicle("udrobot").read_text())
        | {"quadratic_damping": [-5, 17.4666, 55.7484, 1, 1, 1], "allow_negative_damping": True}
    )
    notes = export_checks(v, "uuv-simulator")
    assert any(n.startswith("negative damping exported as given (quadratic_damping -5)") for n in notes), notes
