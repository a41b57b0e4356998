"""hydrokit: free-decay identification, coefficient estimation, 6-DOF models and control
for underwater vehicles.

The top-level names below are imported lazily (on first use), so ``import hydrokit`` is quick
and loads neither numpy's heavy friends nor matplotlib, scipy or numba:

>>> import hydrokit
>>> sorted(hydrokit.__all__)[:4]
['HydrokitError', 'InputError', '__version__', 'allocate']

Layers (see docs/architecture.md): core -> identify / estimate / model -> simulate ->
sysid / manoeuvre -> io -> plot -> api -> report -> cli. Units are SI and radians everywhere inside the package.
A walk-through of the whole chain is in docs/api.md.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from hydrokit.errors import HydrokitError, InputError

__version__ = "0.1.0"

#: public name -> module that defines it (imported on first attribute access)
_LAZY = {
    "load_vehicle": "hydrokit.api",
    "load_rig": "hydrokit.api",
    "load_mission": "hydrokit.api",
    "load_geometry": "hydrokit.api",
    "read_launch": "hydrokit.api",
    "simulate": "hydrokit",  # the subpackage hydrokit.simulate, callable as hydrokit.api.simulate
    "simulate_batch": "hydrokit.api",
    "fly": "hydrokit.api",
    "fly_batch": "hydrokit.api",
    "identify_campaign": "hydrokit.api",
    "estimate_geometry": "hydrokit.api",
    "fit_forces": "hydrokit.api",
    "cfd": "hydrokit.api",
    "load_cfd_body": "hydrokit.api",
    "allocate": "hydrokit.api",
    "vehicle_from_dict": "hydrokit.api",
    "linearize": "hydrokit.api",
    "export_vehicle": "hydrokit.api",
    "load_assembly": "hydrokit.api",
    "transport": "hydrokit.api",
    "manoeuvre": "hydrokit",  # the subpackage hydrokit.manoeuvre, callable as hydrokit.api.manoeuvre
    "sysid": "hydrokit",  # the subpackage hydrokit.sysid, callable as hydrokit.api.sysid
    "load_project": "hydrokit.io.project",
    "run_project": "hydrokit.pipeline",
    "RunResult": "hydrokit.pipeline.result",
    "Vehicle": "hydrokit.model.vehicle",
    "Rig": "hydrokit.identify.types",
    "Launch": "hydrokit.identify.types",
    "Mission": "hydrokit.model.mission",
    "Trajectory": "hydrokit.simulate.driver",
    "BatchTrajectory": "hydrokit.simulate.batch",
    "MissionResult": "hydrokit.simulate.mission",
    "FleetResult": "hydrokit.simulate.fleet",
    "CampaignResult": "hydrokit.identify.result",
    "Estimate": "hydrokit.estimate.geometry",
    "ForceFit": "hydrokit.estimate.forces",
    "CFDResult": "hydrokit.cfd.sweep",
    "Allocation": "hydrokit.model.allocation",
    "Assembly": "hydrokit.model.assembly",
    "TransportResult": "hydrokit.simulate.transport",
}

__all__ = ["HydrokitError", "InputError", "__version__", *_LAZY]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from hydrokit.api import (
        allocate,
        cfd,
        estimate_geometry,
        export_vehicle,
        fit_forces,
        fly,
        fly_batch,
        identify_campaign,
        linearize,
        load_cfd_body,
        load_geometry,
        load_mission,
        load_rig,
        load_vehicle,
        read_launch,
        simulate,
        simulate_batch,
        vehicle_from_dict,
    )
    from hydrokit.cfd.sweep import CFDResult
    from hydrokit.io.project import load_project
    from hydrokit.pipeline import run_project
    from hydrokit.pipeline.result import RunResult


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'hydrokit' has no attribute {name!r}")
    import importlib

    value = (
        importlib.import_module(f"hydrokit.{name}")
        if module == "hydrokit"
        else getattr(importlib.import_module(module), name)
    )
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
