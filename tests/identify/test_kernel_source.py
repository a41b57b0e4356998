"""The compiled rig integrators against their own Python source run by the interpreter.

numba does not check array bounds: a kernel that loops one state too far reads and writes past
its buffers and usually still returns plausible numbers. The same source run as Python raises
IndexError on the first such access, so running it uncompiled (on a short record: it is slow)
and comparing with the compiled result catches both an out-of-bounds loop and any difference
between the two paths (the no-numba fallback uses the Python source).
"""

from __future__ import annotations

import numpy as np
import pytest

import hydrokit.identify.rig_model as rm

SHAPES = {
    "linear": rm.Restoring(),
    "sine": rm.Restoring(rm.SINE),
    "polynomial": rm.Restoring.polynomial(1.0, -0.4, 0.05),
    "table": rm.Restoring.table([0.0, 0.2, 0.4, 0.7], [0.0, 0.19, 0.33, 0.42])[0],
}


@pytest.fixture
def interpreted(monkeypatch):
    """The kernels' helpers as plain Python (the kernels look them up as module globals), patched
    once the compiled kernel is built: compiled while patched (a cold cache, e.g. a fresh clone or
    .ci/run's generic-CPU pass), numba would meet a Python function for its callee and fail."""
    for shape in SHAPES.values():
        rm.simulate_normalised(np.linspace(0.0, 0.1, 3), 4.0, 0.2, 1.5, 0.3, restoring=shape, jacobian=True)
    monkeypatch.setattr(rm, "_restore", rm._restore_py)
    monkeypatch.setattr(rm, "_deriv", rm._deriv_py)


@pytest.mark.parametrize("jacobian", [False, True])
@pytest.mark.parametrize("name", list(SHAPES))
def test_compiled_rig_integrator_equals_its_python_source(interpreted, name, jacobian):
    shape = SHAPES[name]
    t = np.linspace(0.0, 3.0, 40)
    p = np.array([4.0, 0.2, 1.5, 0.0, 0.0, 0.0])
    q, v, J = rm._integrate_py(t, 0.3, -0.1, p, rm.NORMALISED_PARAMETERS, shape.kind, shape.array(), 3, jacobian)
    qc, vc, Jc = rm.simulate_normalised(t, 4.0, 0.2, 1.5, 0.3, -0.1, substeps=3, jacobian=jacobian, restoring=shape)
    np.testing.assert_allclose(qc, q, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(vc, v, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(Jc, J, rtol=1e-12, atol=1e-15)
    assert np.any(J[1:] != 0) == jacobian  # (row 0 holds the seeds ∂q0/∂q0 = 1)


@pytest.mark.parametrize("jacobian", [False, True])
@pytest.mark.parametrize("name", ["linear", "table"])
def test_compiled_extended_integrator_equals_its_python_source(interpreted, name, jacobian):
    shape = SHAPES[name]
    t = np.linspace(0.0, 3.0, 40)
    p = np.array([4.0, 0.2, 1.5, 0.3, -0.2, 0.05])
    q, v, J = rm._integrate_py(t, 0.3, -0.1, p, rm.EXTENDED_PARAMETERS, shape.kind, shape.array(), 3, jacobian)
    qc, vc, Jc = rm.simulate_extended(t, p, 0.3, -0.1, restoring=shape, substeps=3, jacobian=jacobian)
    np.testing.assert_allclose(qc, q, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(vc, v, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(Jc, J, rtol=1e-12, atol=1e-15)
    assert np.any(J[1:] != 0) == jacobian  # (row 0 holds the seeds ∂q0/∂q0 = 1)


def test_the_extended_integrator_without_extra_terms_is_the_normalised_one():
    # d = a3 = a5 = 0 leaves q̈ = −ω² q − b q̇ − g |q̇| q̇: both integrators, released from rest
    # by default, give the same record
    t = np.linspace(0.0, 5.0, 300)
    q, v, _ = rm.simulate_extended(t, [4.0, 0.2, 1.5, 0.0, 0.0, 0.0], 0.3)
    qn, vn, _ = rm.simulate_normalised(t, 4.0, 0.2, 1.5, 0.3)
    assert v[0] == 0.0
    np.testing.assert_allclose(q, qn, rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(v, vn, rtol=1e-10, atol=1e-13)
