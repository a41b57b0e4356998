"""Vehicles out: Gazebo (gz-sim) SDF and uuv_simulator parameters, and back for checking.

hydrokit works in body FRD (x forward, y right, z down) and world NED. Gazebo and
uuv_simulator use body FLU (x forward, y left, z up) and world ENU. The body change is the
reflection T = diag(1, −1, −1) on forces and on moments alike, so a 6×6 matrix becomes
T₆ M T₆ (T₆ = diag(1, −1, −1, 1, −1, −1)): diagonals are unchanged, an off-diagonal entry
changes sign when exactly one of its DOFs is sway, heave, pitch or yaw; vectors (CG, CB,
thruster positions and directions) have y and z negated. Both files say so in a comment.

Sign conventions of the targets:

- gz-sim ``Hydrodynamics`` system: SNAME derivatives. ``<xDotU>`` = X_u̇ = −M_A[0,0] (negative
  for a real added mass), cross terms ``<xDotV>`` …; linear damping ``<xU>`` = −D_L[0,0]
  (``<xV>`` … for cross terms), quadratic ``<xUabsU>`` = −d_Q (force X = xUabsU·|u|·u).
- uuv_simulator ``fossen`` model: ``added_mass`` = M_A (36 values, positive), ``linear_damping``
  and ``quadratic_damping`` = the negated diagonals (force −D ν with D = −lin − quad·|ν|).

What each target needs (:func:`export_checks`, run by :func:`hydrokit.export_vehicle` before
writing): M_RB + M_A symmetric positive definite and M_A positive semi-definite (½νᵀM_Aν is
the fluid's kinetic energy); for the engines that apply added mass as an explicit force
−M_A·a with the previous step's acceleration (gz-sim's Hydrodynamics ``*Dot*`` parameters,
uuv_simulator's fossen model) the step error is multiplied by −M_RB⁻¹M_A every step, so the
largest generalised eigenvalue ρ of M_A v = ρ M_RB v must be below 1 (refused at ρ ≥ 1,
warned above :data:`RATIO_WARN`; gz-sim issues #1923, #3246, uuv_simulator #181, #349). gz-sim's
``<fluid_added_mass>`` in the link's inertial (``added_mass="inertial"``, SDF 1.10, DART) is
integrated with the body's own mass and has no such limit.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

import numpy as np

from hydrokit.errors import InputError

T3 = np.diag([1.0, -1.0, -1.0])
T6 = np.diag([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
MOMENT = "xyzkmn"
#: SDF inertia tags and their entries of the 3×3 tensor
INERTIA_TAGS = {"ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2), "izz": (2, 2)}
VEL = "UVWPQR"
FRAME_NOTE = (
    "Converted by hydrokit from body FRD / world NED to body FLU / world ENU: y and z of every "
    "vector negated; 6x6 matrices as T M T with T = diag(1,-1,-1,1,-1,-1)."
)


#: ρ(M_RB⁻¹ M_A) above which an explicit added-mass force is warned about (the step error
#: shrinks by at most this factor per step, alternating in sign); at 1 it grows
RATIO_WARN = 0.5
#: the 21 entries of gz-sim's <fluid_added_mass> (upper triangle of M_A, FLU, positive)
FLUID_ADDED_MASS = [(a + b, i, j) for i, a in enumerate("xyzpqr") for j, b in enumerate("xyzpqr") if j >= i]
TARGETS = {"gazebo": "gz-sim", "uuv-simulator": "uuv_simulator", "python-control": "python-control"}


def added_mass_ratio(vehicle: Any) -> tuple[float, int]:
    """Largest ρ of M_A v = ρ M_RB v (dimensionless) and the DOF (0–5) its mode moves most.

    Notes
    -----
    An engine that applies −M_A·a_(n−1) while integrating M_RB a_n = F − M_A a_(n−1) carries an
    acceleration error e as e_n = −M_RB⁻¹ M_A e_(n−1): stable only for ρ < 1. With L Lᵀ = M_RB,
    ρ is the largest eigenvalue of the symmetric L⁻¹ M_A L⁻ᵀ.
    """
    L = np.linalg.cholesky(vehicle.M_RB)
    Li = np.linalg.inv(L)
    M_A = 0.5 * (vehicle.M_A + vehicle.M_A.T)
    w, V = np.linalg.eigh(Li @ M_A @ Li.T)
    mode = Li.T @ V[:, -1]
    scale = np.sqrt(np.diag(vehicle.M_RB))  # compare translations and rotations by their inertia
    return float(w[-1]), int(np.argmax(np.abs(mode) * scale))


def export_checks(vehicle: Any, target: str, added_mass: str = "plugin") -> list[str]:
    """Refuse (:class:`InputError`) what would crash or destabilise ``target``; the warnings.

    Parameters
    ----------
    vehicle : Vehicle
    target : str — "gazebo", "uuv-simulator" or "python-control"
    added_mass : str — gazebo only: "plugin" (the Hydrodynamics ``*Dot*`` parameters, an
        explicit force) or "inertial" (``<fluid_added_mass>``, integrated by DART)

    Returns
    -------
    list of str — one-line warnings (the number and the fix), also written into the file
    """
    from hydrokit.core.names import DOF_NAMES

    engine = TARGETS[target]
    M_A, M = np.asarray(vehicle.M_A, float), vehicle.M_RB + vehicle.M_A
    scale = max(float(np.abs(M).max()), 1e-300)
    for what, mat in (("M_RB + M_A", M), ("added_mass M_A", M_A), ("inertia", vehicle.inertia)):
        asym = float(np.abs(mat - mat.T).max())
        if asym > 1e-9 * scale:
            raise InputError(f"{what} is not symmetric (by {asym:.3g}); {engine} expects a symmetric matrix")
    low = float(np.linalg.eigvalsh(M).min())
    if low <= 0:
        raise InputError(
            f"M_RB + M_A has the eigenvalue {low:.4g}: not positive definite; {engine} cannot use it "
            "(expected positive mass and added-mass magnitudes, −X_udot > 0 …)"
        )
    out: list[str] = []
    if target == "python-control":
        return out
    low_a = float(np.linalg.eigvalsh(M_A).min())
    if low_a < -1e-9 * scale:
        raise InputError(
            f"added_mass M_A has the eigenvalue {low_a:.4g} (kg, kg m, kg m^2): not positive semi-definite, "
            f"which no fluid gives (½νᵀM_Aν is its kinetic energy) and {engine} turns into energy fed in; "
            "expected M_A ≥ 0 (check the signs: −X_udot > 0 …)"
        )
    rho, dof = added_mass_ratio(vehicle)
    explicit = target == "uuv-simulator" or added_mass == "plugin"
    if explicit and rho >= RATIO_WARN:
        fix = (
            "export with --added-mass inertial (gz-sim's <fluid_added_mass>, Garden or later with DART)"
            if target == "gazebo"
            else "lower <scaling_added_mass> (changes the physics) or use gz-sim: hydrokit export "
            "--format gazebo --added-mass inertial"
        )
        text = (
            f"added mass against rigid-body mass ρ(M_RB⁻¹ M_A) = {rho:.3g} (largest in {DOF_NAMES[dof]}): {engine} "
            f"applies −M_A·a of the previous step, which multiplies a step's error by −{rho:.3g} each step"
        )
        if rho >= 1:
            raise InputError(f"{text} — it goes unstable; expected ρ < 1, or {fix}")
        out.append(f"{text} (rings, above {RATIO_WARN:g}); {fix}")
    neg = [
        f"{name} {v:.4g}"
        for name, d in (("linear_damping", np.diag(vehicle.D_L)), ("quadratic_damping", vehicle.D_Q))
        for v in np.asarray(d, float)[np.asarray(d, float) < 0][:1]
    ]
    if neg:
        out.append(f"negative damping exported as given ({', '.join(neg)}): {engine} feeds energy in there")
    if target == "uuv-simulator":
        DL = to_flu(np.asarray(vehicle.D_L, float))
        off = np.abs(DL - np.diag(np.diag(DL)))
        if off.max() > 0:
            i, j = np.unravel_index(int(np.argmax(off)), off.shape)
            out.append(
                f"linear_damping off-diagonal entries dropped (the fossen model takes 6 diagonals), "
                f"largest [{i}][{j}] = {DL[i, j]:.4g} (FLU)"
            )
    omitted = _omitted(vehicle)
    if omitted:
        out.append(omitted.strip())
    return out


def _comment(text: str) -> Any:
    # "--" may not appear inside an XML comment (a vehicle name could hold it)
    return ET.Comment(text.replace("--", "- -"))


def to_flu(matrix: np.ndarray) -> np.ndarray:
    """A 6×6 (or 3×3) body matrix from FRD to FLU (its own inverse)."""
    T = T6 if matrix.shape[0] == 6 else T3
    return T @ matrix @ T


def _fmt(x: float) -> str:
    return f"{float(x) + 0.0:.12g}"  # + 0.0: no "-0"


def _vec(v: Any) -> str:
    return " ".join(_fmt(x) for x in np.asarray(v, float))


def _omitted(vehicle: Any) -> str | None:
    names = tuple(getattr(getattr(vehicle, "terms", None), "names", ()) or ())
    elements = tuple(e.name for e in getattr(vehicle, "drag_elements", ()) or ())
    parts = []
    if names:
        parts.append(
            f" {len(names)} general derivative term(s) of the vehicle file are not representable here and "
            f"are left out: {', '.join(names)} "
        )
    if elements:
        parts.append(
            f" {len(elements)} point drag element(s) (drag_elements) are not representable here and are "
            f"left out: {', '.join(elements)} "
        )
    return "".join(parts) or None


def _header(root: Any, vehicle: Any, notes: list[str] | None) -> None:
    """Comments: where the coefficients came from (when the vehicle file says) and the checks' warnings."""
    if vehicle.provenance:
        root.append(_comment(" provenance (from the vehicle file): " + " | ".join(vehicle.provenance) + " "))
    for note in notes or ():
        root.append(_comment(f" warning: {note} "))


def gazebo_sdf(
    vehicle: Any, link: str = "base_link", added_mass: str = "plugin", notes: list[str] | None = None
) -> str:
    """An SDF model of ``vehicle`` for gz-sim: the base link's mass and inertia (about the CG,
    FLU), the Hydrodynamics system with every non-zero damping entry and, with ``added_mass``
    "plugin" (SDF 1.9), the added mass as its ``*Dot*`` parameters — or, with "inertial"
    (SDF 1.10), as the link's ``<fluid_added_mass>`` — and one Thruster system (force
    commands, N) per thruster on its own joint. ``notes`` are written as comments."""
    if added_mass not in ("plugin", "inertial"):
        raise InputError(f"added_mass = {added_mass!r}: expected plugin or inertial")
    name = vehicle.name or "vehicle"
    MA, DL = to_flu(vehicle.M_A), to_flu(vehicle.D_L)
    inertial_route = added_mass == "inertial"
    sdf = ET.Element("sdf", version="1.10" if inertial_route else "1.9")
    sdf.append(_comment(f" hydrokit export of '{name}'. {FRAME_NOTE} "))
    omitted = _omitted(vehicle)
    if omitted:
        sdf.append(_comment(omitted))
    _header(sdf, vehicle, notes)
    model = ET.SubElement(sdf, "model", name=name)
    base = ET.SubElement(model, "link", name=link)
    inertial = ET.SubElement(base, "inertial")
    ET.SubElement(inertial, "pose").text = _vec(np.concatenate([T3 @ vehicle.r_g, np.zeros(3)]))
    ET.SubElement(inertial, "mass").text = _fmt(vehicle.mass)
    I = T3 @ vehicle.inertia @ T3
    inertia = ET.SubElement(inertial, "inertia")
    for tag, (i, j) in INERTIA_TAGS.items():
        ET.SubElement(inertia, tag).text = _fmt(I[i, j])
    if inertial_route:
        inertial.append(_comment(" added mass (FLU, positive) integrated with the body: gz-sim Garden or later, DART "))
        fam = ET.SubElement(inertial, "fluid_added_mass")
        for tag, i, j in FLUID_ADDED_MASS:
            ET.SubElement(fam, tag).text = _fmt(MA[i, j])
    base.append(
        _comment(
            f" buoyancy: volume {_fmt(vehicle.volume)} m^3, fluid density {_fmt(vehicle.density)} kg/m^3, "
            f"centre of buoyancy {_vec(T3 @ vehicle.r_b)} m (FLU); give the link a collision of that volume "
            "and add the world Buoyancy system "
        )
    )
    hyd = ET.SubElement(model, "plugin", filename="gz-sim-hydrodynamics-system", name="gz::sim::systems::Hydrodynamics")
    ET.SubElement(hyd, "link_name").text = link
    ET.SubElement(hyd, "water_density").text = _fmt(vehicle.density)
    for i in range(6):
        for j in range(6):
            if not inertial_route and (MA[i, j] != 0 or i == j):
                ET.SubElement(hyd, f"{MOMENT[i]}Dot{VEL[j]}").text = _fmt(-MA[i, j])
            if DL[i, j] != 0 or i == j:
                ET.SubElement(hyd, f"{MOMENT[i]}{VEL[j]}").text = _fmt(-DL[i, j])
        ET.SubElement(hyd, f"{MOMENT[i]}{VEL[i]}abs{VEL[i]}").text = _fmt(-vehicle.D_Q[i])
    for t in vehicle.thrusters.thrusters if vehicle.thrusters is not None else ():
        tl = ET.SubElement(model, "link", name=f"thruster_{t.name}")
        pos = T3 @ np.asarray(t.position, float)
        ET.SubElement(tl, "pose").text = _vec(np.concatenate([pos, np.zeros(3)]))
        joint = ET.SubElement(model, "joint", name=f"thruster_{t.name}_joint", type="revolute")
        ET.SubElement(joint, "parent").text = link
        ET.SubElement(joint, "child").text = f"thruster_{t.name}"
        axis = ET.SubElement(joint, "axis")
        ET.SubElement(axis, "xyz").text = _vec(T3 @ np.asarray(t.direction, float))
        plug = ET.SubElement(model, "plugin", filename="gz-sim-thruster-system", name="gz::sim::systems::Thruster")
        ET.SubElement(plug, "namespace").text = name
        ET.SubElement(plug, "joint_name").text = f"thruster_{t.name}_joint"
        ET.SubElement(plug, "fluid_density").text = _fmt(vehicle.density)
        ET.SubElement(plug, "max_thrust_cmd").text = _fmt(t.max_thrust)
        ET.SubElement(plug, "min_thrust_cmd").text = _fmt(t.min_thrust if t.min_thrust is not None else -t.max_thrust)
        if t.diameter and t.kt_forward:
            # gz: thrust = coefficient · ρ · D⁴ · ω|ω| with ω in rad/s; K_T(J = 0) is per (rev/s)²
            ET.SubElement(plug, "propeller_diameter").text = _fmt(t.diameter)
            kt0 = float(t.kt_forward[-1]) * t.thrust_loss_forward
            ET.SubElement(plug, "thrust_coefficient").text = _fmt(kt0 / (2 * np.pi) ** 2)
        plug.append(_comment(f" rotor time constant {_fmt(t.time_constant)} s in hydrokit "))
    ET.indent(sdf)
    return '<?xml version="1.0"?>\n' + ET.tostring(sdf, encoding="unicode") + "\n"


def uuv_parameters(vehicle: Any, link: str = "base_link", notes: list[str] | None = None) -> str:
    """The uuv_simulator underwater-object plugin block (``fossen`` model, FLU) as URDF/xacro XML;
    ``notes`` are written as comments."""
    name = vehicle.name or "vehicle"
    root = ET.Element("gazebo")
    root.append(_comment(f" hydrokit export of '{name}' for uuv_simulator. {FRAME_NOTE} "))
    omitted = _omitted(vehicle)
    if omitted:
        root.append(_comment(omitted))
    _header(root, vehicle, notes)
    off = to_flu(vehicle.D_L) - np.diag(np.diag(to_flu(vehicle.D_L)))
    if np.any(off != 0):
        root.append(_comment(" linear damping has off-diagonal terms the fossen model does not take: dropped "))
    plug = ET.SubElement(root, "plugin", name="uuv_plugin", filename="libuuv_underwater_object_ros_plugin.so")
    ET.SubElement(plug, "fluid_density").text = _fmt(vehicle.density)
    ET.SubElement(plug, "flow_velocity_topic").text = "hydrodynamics/current_velocity"
    ET.SubElement(plug, "debug").text = "0"
    lk = ET.SubElement(plug, "link", name=link)
    ET.SubElement(lk, "neutrally_buoyant").text = "0"
    ET.SubElement(lk, "volume").text = _fmt(vehicle.volume)
    ET.SubElement(lk, "center_of_buoyancy").text = _vec(T3 @ vehicle.r_b)
    hm = ET.SubElement(lk, "hydrodynamic_model")
    ET.SubElement(hm, "type").text = "fossen"
    ET.SubElement(hm, "added_mass").text = _vec(to_flu(vehicle.M_A).ravel())
    ET.SubElement(hm, "linear_damping").text = _vec(-np.diag(to_flu(vehicle.D_L)))
    ET.SubElement(hm, "quadratic_damping").text = _vec(-np.asarray(vehicle.D_Q, float))
    inert = ET.SubElement(root, "inertial_of", link=link)
    ET.SubElement(inert, "mass").text = _fmt(vehicle.mass)
    ET.SubElement(inert, "origin").text = _vec(T3 @ vehicle.r_g)
    I = T3 @ vehicle.inertia @ T3
    ET.SubElement(inert, "inertia").text = _vec([I[0, 0], I[0, 1], I[0, 2], I[1, 1], I[1, 2], I[2, 2]])
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _numbers(text: str | None, what: str, n: int) -> np.ndarray:
    try:
        v = np.array([float(x) for x in (text or "").split()])
    except ValueError:
        raise InputError(f"{what} = {text!r}: expected {n} numbers") from None
    if v.size != n:
        raise InputError(f"{what}: {v.size} numbers; expected {n}")
    return v


def read_gazebo_sdf(text: str) -> dict[str, Any]:
    """Matrices back in hydrokit's FRD convention from a :func:`gazebo_sdf` document (a check)."""
    root = ET.fromstring(text)
    hyd = root.find(".//plugin[@name='gz::sim::systems::Hydrodynamics']")
    if hyd is None:
        raise InputError("no gz::sim::systems::Hydrodynamics plugin in the SDF")
    MA, DL, DQ = np.zeros((6, 6)), np.zeros((6, 6)), np.zeros(6)
    fam = root.find(".//link/inertial/fluid_added_mass")
    for tag, i, j in FLUID_ADDED_MASS if fam is not None else ():
        MA[i, j] = MA[j, i] = float(fam.findtext(tag) or 0)  # type: ignore[union-attr]
    for i in range(6):
        for j in range(6):
            e = hyd.find(f"{MOMENT[i]}Dot{VEL[j]}")
            MA[i, j] = -float(e.text) if e is not None and e.text else MA[i, j]
            e = hyd.find(f"{MOMENT[i]}{VEL[j]}")
            DL[i, j] = -float(e.text) if e is not None and e.text else 0.0
        e = hyd.find(f"{MOMENT[i]}{VEL[i]}abs{VEL[i]}")
        DQ[i] = -float(e.text) if e is not None and e.text else 0.0
    inertial = root.find(".//link/inertial")
    assert inertial is not None
    I = np.zeros((3, 3))
    for tag, (i, j) in INERTIA_TAGS.items():
        I[i, j] = I[j, i] = float(inertial.findtext(f"inertia/{tag}") or 0)
    return {
        "M_A": to_flu(MA),
        "D_L": to_flu(DL),
        "D_Q": DQ,
        "mass": float(inertial.findtext("mass") or "nan"),
        "inertia": T3 @ I @ T3,
        "r_g": T3 @ _numbers(inertial.findtext("pose"), "inertial pose", 6)[:3],
    }


def read_uuv_parameters(text: str) -> dict[str, Any]:
    """Matrices back in hydrokit's FRD convention from a :func:`uuv_parameters` document."""
    root = ET.fromstring(text)
    hm = root.find(".//hydrodynamic_model")
    lk = root.find(".//plugin/link")
    if hm is None or lk is None:
        raise InputError("no hydrodynamic_model in the uuv_simulator block")
    return {
        "M_A": to_flu(_numbers(hm.findtext("added_mass"), "added_mass", 36).reshape(6, 6)),
        "D_L": np.diag(-_numbers(hm.findtext("linear_damping"), "linear_damping", 6)),
        "D_Q": -_numbers(hm.findtext("quadratic_damping"), "quadratic_damping", 6),
        "volume": float(lk.findtext("volume") or "nan"),
        "r_b": T3 @ _numbers(lk.findtext("center_of_buoyancy"), "center_of_buoyancy", 3),
    }
