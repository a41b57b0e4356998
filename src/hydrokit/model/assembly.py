"""Assemblies: rigid parts joined in a tree (issue #11, REHMAN's two-HAUV payload transport).

An :class:`Assembly` is what an assembly file describes (read by
:func:`hydrokit.io.assembly.load_assembly`): parts in a common frame, each but one (the root)
joined to a parent at a joint point. It carries every body the three transport models need, all
as :class:`~hydrokit.model.vehicle.Vehicle` objects so the one vehicle model (and its compiled
copy) serves them all:

- ``composite`` — the whole assembly as one rigid body about the common origin (``rigid``);
- ``subtrees[i]`` — part i and everything beyond it, about the common origin: the Newton–Euler
  balance of this body gives the load at part i's joint;
- ``bodies[i]`` — part i alone about its own origin, in axes parallel to the common axes
  (``multibody``);
- ``groups[g]`` — a child subtree of the root plus an equal share of the root part, about the
  common origin (``independent``: REHMAN's separate bodies, each vehicle with its manipulator
  and half the payload).

Thrusters of vehicle parts are collected in common axes about the common origin and named
``PART.THRUSTER``; ``thruster_part[k]`` is the part that carries thruster k.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hydrokit.errors import InputError
from hydrokit.model.thrusters import ThrusterSet
from hydrokit.model.vehicle import Vehicle

Array = NDArray[np.float64]

#: the three transport models
MODELS = ("rigid", "multibody", "independent")


@dataclass(frozen=True)
class Assembly:
    """Parts joined in a tree (SI; common frame = the assembly's body frame at rest).

    Attributes
    ----------
    name : str
    part_names : tuple of str — in file order
    parents : tuple of int — index of each part's parent, −1 for the root
    positions : (n, 3) — part origins in the common frame, m
    rotations : (n, 3, 3) — part axes → common axes
    joints : (n, 3) — joint point of each part with its parent, common frame, m (root: its origin)
    joint_stiffness : (n, 6) — N/m (3), N·m/rad (3), the joined-bodies model's springs
    joint_damping : (n, 6) — N·s/m (3), N·m·s/rad (3)
    composite, subtrees, bodies, groups : see the module docstring
    group_parts : tuple of tuple of int — the parts of each group (the root in every one)
    thrusters : ThrusterSet or None — all thrusters, common axes about the common origin
    thruster_part : tuple of int — the part that carries each thruster
    source : str — the file it came from
    """

    name: str
    part_names: tuple[str, ...]
    parents: tuple[int, ...]
    positions: Array
    rotations: Array
    joints: Array
    joint_stiffness: Array
    joint_damping: Array
    composite: Vehicle
    subtrees: tuple[Vehicle, ...]
    bodies: tuple[Vehicle, ...]
    groups: tuple[Vehicle, ...]
    group_parts: tuple[tuple[int, ...], ...]
    thrusters: ThrusterSet | None
    thruster_part: tuple[int, ...]
    source: str = ""

    @property
    def root(self) -> int:
        """Index of the part without a parent."""
        return self.parents.index(-1)

    @property
    def joint_parts(self) -> tuple[int, ...]:
        """Indices of the parts that hang on a joint (all but the root), file order."""
        return tuple(i for i, p in enumerate(self.parents) if p >= 0)

    def subtree(self, i: int) -> tuple[int, ...]:
        """Part i and every part beyond it (indices, file order)."""
        return subtree_of(self.parents, i)

    def part_index(self, name: str, what: str = "part") -> int:
        """Index of the part called ``name`` (InputError naming the choices otherwise)."""
        if name not in self.part_names:
            raise InputError(f"{what} '{name}': no such part (parts: {', '.join(self.part_names)})", self.source)
        return self.part_names.index(name)

    def thruster_index(self, name: str) -> int:
        """Index of thruster ``PART.THRUSTER`` (InputError naming the choices otherwise)."""
        names = self.thrusters.names if self.thrusters is not None else []
        if name not in names:
            listed = ", ".join(names) if names else "none: no vehicle part carries thrusters"
            raise InputError(f"thruster '{name}': no such thruster (thrusters: {listed})", self.source)
        return names.index(name)


def subtree_of(parents: tuple[int, ...] | list[int], i: int) -> tuple[int, ...]:
    """Part i and its descendants in a parent list (−1 = root), file order."""
    out = {i}
    changed = True
    while changed:
        changed = False
        for k, p in enumerate(parents):
            if p in out and k not in out:
                out.add(k)
                changed = True
    return tuple(sorted(out))


def check_tree(names: list[str], parents: list[str | None], source: str = "") -> list[int]:
    """Parent indices of a parts list, validated: names unique, one root, known parents, no
    cycle. Errors name the field ``parts[k].parent``."""
    seen: dict[str, int] = {}
    for k, n in enumerate(names):
        if n in seen:
            raise InputError(
                f"field 'parts[{k}].name' = '{n}': already used by parts[{seen[n]}]; expected unique names", source
            )
        seen[n] = k
    idx: list[int] = []
    for k, p in enumerate(parents):
        if p is None:
            idx.append(-1)
            continue
        if p not in seen:
            raise InputError(
                f"field 'parts[{k}].parent' = '{p}': no such part; expected one of {', '.join(names)}", source
            )
        if seen[p] == k:
            raise InputError(f"field 'parts[{k}].parent' = '{p}': a part cannot be its own parent", source)
        idx.append(seen[p])
    for k in range(len(idx)):  # walk up from every part: a cycle never reaches the root
        path = [k]
        j = idx[k]
        while j >= 0:
            if j in path:
                cyc = " → ".join(names[m] for m in path[path.index(j) :] + [j])
                raise InputError(
                    f"field 'parts[{k}].parent': the parents form a cycle ({cyc}); expected a tree", source
                )
            path.append(j)
            j = idx[j]
    roots = [k for k, p in enumerate(idx) if p < 0]
    if len(roots) != 1:
        listed = ", ".join(names[k] for k in roots)
        raise InputError(
            f"field 'parts[].parent': {len(roots)} parts without a parent ({listed}); expected exactly one root", source
        )
    return idx


def joint_mobility(parent: Vehicle, child: Vehicle, a_parent: Array, a_child: Array) -> Array:
    """6×6 mobility at a joint point: H(a_p) M_p⁻¹ H(a_p)ᵀ + H(a_c) M_c⁻¹ H(a_c)ᵀ (m/s per N·s),
    the relative acceleration of the two bodies' joint points per unit joint wrench (both
    bodies' axes parallel to the common axes at rest; a_* the joint point from each origin, m).
    Its inverse diagonal is the mass each joint DOF moves; eigenvalues of G·K are the joint's
    squared natural frequencies."""
    from hydrokit.core.rigid_body import shift_matrix

    G = np.zeros((6, 6))
    for body, a in ((parent, a_parent), (child, a_child)):
        H = shift_matrix(a)
        G += H @ np.linalg.inv(body.M) @ H.T
    return G


def check_model(model: str) -> str:
    """``model`` if it is one of :data:`MODELS`."""
    if model not in MODELS:
        raise InputError(f"model = {model!r}: expected one of {', '.join(MODELS)}")
    return model
