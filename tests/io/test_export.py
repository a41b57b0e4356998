"""Vehicles out (issue #12 item 7): Gazebo and uuv_simulator round trips in their own frame,
and the linearised model against closed forms and the nonlinear model."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest
import yaml

import hydrokit
from hydrokit.io.export import gazebo_sdf, read_gazebo_sdf, read_uuv_parameters, to_flu, uuv_parameters
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
    code, _, err = run_cli("export", "bluerov2-heavy", "--format", "gazebo", "--out", tmp_path / "b.sdf")
    assert code == 0, err
    back = read_gazebo_sdf((tmp_path / "b.sdf").read_text())
    v = hydrokit.load_vehicle("bluerov2-heavy")
    assert np.allclose(back["M_A"], v.M_A) and np.allclose(back["D_Q"], v.D_Q)
