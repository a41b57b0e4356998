"""Identification from logs: a vehicle's coefficients fitted to its own free-running runs.

``fit`` (the whole-run output-error and equation-error fits, :func:`hydrokit.sysid.fit.identify`)
uses ``model`` (the free parameters and the batch of simulated runs), ``lm`` (projected
Levenberg–Marquardt), ``smooth`` (the smoother and the equation-error kernels), ``stats``
(whiteness, sandwich covariance, correlation), ``window`` (the windowed fit of long logs);
``compare`` judges fits on held-out runs, ``plan`` designs an experiment, ``data`` generates
virtual dives, ``ship`` the surface-ship variant of the force table.

The package object itself is callable: ``hydrokit.sysid(runs, vehicle, free, …)`` is
:func:`hydrokit.api.sysid`.
"""

from __future__ import annotations

from hydrokit._callable import make_callable

make_callable(__name__)
