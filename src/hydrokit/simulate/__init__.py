"""Integrators and simulation drivers; they live outside the models.

The package object itself is callable: ``hydrokit.simulate(vehicle, duration, dt, tau=…)``
is :func:`hydrokit.api.simulate`, so the top-level API name and this subpackage can share the
name ``simulate`` without one hiding the other (``import hydrokit.simulate.driver`` and
``hydrokit.simulate(...)`` both work).

Identification from logs lives in :mod:`hydrokit.sysid` and the standard manoeuvres and trial
replay in :mod:`hydrokit.manoeuvre` (issue #50); their old names here (``hydrokit.simulate.sysid``,
``hydrokit.simulate.manoeuvre`` …) were removed one release later (CHANGELOG.md).
"""

from __future__ import annotations

from hydrokit._callable import make_callable

make_callable(__name__)
