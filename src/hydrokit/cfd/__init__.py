"""The computational half: hydrokit drives OpenFOAM as a virtual tow tank and rotating arm.

``body`` (what the flow meets) → ``case`` (a body, a flow, settings → OpenFOAM files) → ``mesh3d``
(snappyHexMesh around a surface) or ``wedge`` (a structured axisymmetric mesh) → ``foam`` (running
programs: captured output, timeout, clean-up) → ``history`` (force histories judged for
convergence) and ``gci`` (Richardson/GCI) → ``run`` (one case, cached) → ``sweep`` (cases on the
executor, fitted with :mod:`hydrokit.estimate.forces` and :mod:`hydrokit.estimate.derivatives`).
OpenFOAM and foamlib are imported only when a case is built or run.
"""
