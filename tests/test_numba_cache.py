"""Every numba kernel caches its compiled code on disk (``cache=True``): the CLI and a notebook
start without recompiling (README, "Keep the CLI quick to start")."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import hydrokit


@pytest.mark.needs_jit(reason="without the JIT there are no compiled kernels to cache")
def test_every_compiled_kernel_caches_to_disk():
    from numba.core.dispatcher import Dispatcher

    kernels = {}
    for mod in pkgutil.walk_packages(hydrokit.__path__, "hydrokit."):
        if mod.name.endswith("__main__"):  # runs the CLI
            continue
        try:
            module = importlib.import_module(mod.name)
        except ImportError:  # an optional extra (capytaine, cv2 …) that is not installed
            continue
        for name, obj in vars(module).items():
            if isinstance(obj, Dispatcher) and obj.py_func.__module__ == mod.name:
                kernels[f"{mod.name}.{name}"] = type(obj._cache).__name__
    # the rig integrators, the vehicle RK4, the closed loop and the transport kernels at least
    assert len(kernels) >= 20, sorted(kernels)
    assert {k for k, cache in kernels.items() if cache != "FunctionCache"} == set()
