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


def gazebo_sdf(vehicle: Any, link: str = "base_link") -> str:
    """An SDF 1.9 model of ``vehicle`` for gz-sim: the base link's mass and inertia (about the
    CG, FLU), the Hydrodynamics system with every non-zero added-mass and damping entry, and
    one Thruster system (force commands, N) per thruster on its own joint."""
    name = vehicle.name or "vehicle"
    MA, DL = to_flu(vehicle.M_A), to_flu(vehicle.D_L)
    sdf = ET.Element("sdf", version="1.9")
    sdf.append(_comment(f" hydrokit export of '{name}'. {FRAME_NOTE} "))
    omitted = _omitted(vehicle)
    if omitted:
        sdf.append(_comment(omitted))
    model = ET.SubElement(sdf, "model", name=name)
    base = ET.SubElement(model, "link", name=link)
    inertial = ET.SubElement(base, "inertial")
    ET.SubElement(inertial, "pose").text = _vec(np.concatenate([T3 @ vehicle.r_g, np.zeros(3)]))
    ET.SubElement(inertial, "mass").text = _fmt(vehicle.mass)
    I = T3 @ vehicle.inertia @ T3
    inertia = ET.SubElement(inertial, "inertia")
    for tag, (i, j) in INERTIA_TAGS.items():
        ET.SubElement(inertia, tag).text = _fmt(I[i, j])
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
            if MA[i, j] != 0 or i == j:
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


def uuv_parameters(vehicle: Any, link: str = "base_link") -> str:
    """The uuv_simulator underwater-object plugin block (``fossen`` model, FLU) as URDF/xacro XML."""
    name = vehicle.name or "vehicle"
    root = ET.Element("gazebo")
    root.append(_comment(f" hydrokit export of '{name}' for uuv_simulator. {FRAME_NOTE} "))
    omitted = _omitted(vehicle)
    if omitted:
        root.append(_comment(omitted))
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
    for i in range(6):
        for j in range(6):
            e = hyd.find(f"{MOMENT[i]}Dot{VEL[j]}")
            MA[i, j] = -float(e.text) if e is not None and e.text else 0.0
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
