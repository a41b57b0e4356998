"""Integrators and simulation drivers; they live outside the models.

The package object itself is callable: ``hydrokit.simulate(vehicle, duration, dt, tau=…)``
is :func:`hydrokit.api.simulate`, so the top-level API name and this subpackage can share the
name ``simulate`` without one hiding the other (``import hydrokit.simulate.driver`` and
``hydrokit.simulate(...)`` both work).
"""

from __future__ import annotations

import sys
import types
from typing import Any


class _CallablePackage(types.ModuleType):
    """A module whose call is :func:`hydrokit.api.simulate` (imported on first call)."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        from hydrokit.api import simulate

        return simulate(*args, **kwargs)

    @property
    def __signature__(self) -> Any:
        import inspect

        from hydrokit.api import simulate

        return inspect.signature(simulate)


sys.modules[__name__].__class__ = _CallablePackage
