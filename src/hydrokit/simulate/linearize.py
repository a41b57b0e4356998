"""The vehicle model linearised at a trim state, for controller design (python-control).

State x = [η; ν] (x, y, z m NED; φ, θ, ψ rad; u, v, w m/s; p, q, r rad/s), input δτ (N, N·m)
about the trim force τ₀ that holds the trim velocity steady at zero attitude:
ẋ = f(x, τ₀ + δτ) ≈ f(x₀, τ₀) + A (x − x₀) + B δτ. A and B are central differences of the
compiled right-hand side (:func:`hydrokit.simulate.compiled.make_dynamics`, the model every
simulation uses); C = I (all states measured), D = 0. At a non-zero trim speed η drifts
(ẋ₀ ≠ 0 in the position rows): the linear model describes deviations from that motion.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, html_table, jsonable
from hydrokit.core.names import FORCE_SYMBOLS, STATE_COLUMNS
from hydrokit.errors import InputError, MissingExtraError

STATES: tuple[str, ...] = STATE_COLUMNS[1:]
INPUTS: tuple[str, ...] = FORCE_SYMBOLS


@dataclass
class Linearization(Result):
    """A, B, C, D of the model about ``x0`` with trim force ``tau0`` (SI; see module docstring).

    Attributes
    ----------
    A : (12, 12) — 1/s and mixed units of ∂ẋ/∂x
    B : (12, 6) — ∂ẋ/∂τ, 1/kg and 1/(kg·m²) blocks
    C : (12, 12) identity; D : (12, 6) zeros
    x0 : (12,) trim state; tau0 : (6,) trim force, N and N·m
    vehicle : str — the vehicle's name
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    x0: np.ndarray
    tau0: np.ndarray
    vehicle: str = ""
    step: float = 1e-6
    states: tuple[str, ...] = field(default=STATES)
    inputs: tuple[str, ...] = field(default=INPUTS)

    @property
    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of A (1/s), sorted by real part."""
        ev = np.linalg.eigvals(self.A)
        return ev[np.argsort(ev.real)]

    def to_statespace(self) -> Any:
        """A ``control.StateSpace`` (needs ``pip install 'hydrokit[control]'``)."""
        try:
            import control
        except ImportError:
            raise MissingExtraError("control", "control") from None
        return control.ss(
            self.A,
            self.B,
            self.C,
            self.D,
            states=list(self.states),
            inputs=list(self.inputs),
            outputs=list(self.states),
        )

    def response(self, dtau: Any, duration: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """Deviation of the state from the trim motion for a constant δτ (N, N·m) held from t = 0:
        exact discretisation (matrix exponential) of the linear model. Returns (t s, (n, 12))."""
        from scipy.linalg import expm

        n = int(round(duration / dt)) + 1
        m = np.zeros((18, 18))
        m[:12, :12] = self.A * dt
        m[:12, 12:] = self.B * dt
        e = expm(m)
        Ad, Bd = e[:12, :12], e[:12, 12:]
        u = np.asarray(dtau, float)
        x = np.zeros((n, 12))
        for k in range(1, n):
            x[k] = Ad @ x[k - 1] + Bd @ u
        return np.arange(n) * dt, x

    def to_dict(self) -> dict[str, Any]:
        return jsonable(
            {
                "vehicle": self.vehicle,
                "states": list(self.states),
                "inputs": list(self.inputs),
                "x0": self.x0,
                "tau0": self.tau0,
                "A": self.A,
                "B": self.B,
                "C": self.C,
                "D": self.D,
                "eigenvalues_real": self.eigenvalues.real,
                "eigenvalues_imag": self.eigenvalues.imag,
                "step": self.step,
            }
        )

    def summary_rows(self) -> list[tuple[str, Any]]:
        ev = self.eigenvalues
        return [
            ("vehicle", self.vehicle),
            ("trim ν (m/s, rad/s)", [round(float(v), 6) for v in self.x0[6:]]),
            ("trim τ (N, N·m)", [round(float(v), 6) for v in self.tau0]),
            (
                "slowest stable eigenvalue (1/s)",
                float(ev.real[ev.real < -1e-9].max()) if np.any(ev.real < -1e-9) else None,
            ),
        ]

    def _repr_html_(self) -> str:
        return html_table(f"Linearization: {self.vehicle}", self.summary_rows())

    def npz_arrays(self) -> dict[str, np.ndarray]:
        """Arrays for ``numpy.savez`` (plain float and text arrays: loads with allow_pickle=False)."""
        return {
            "A": self.A,
            "B": self.B,
            "C": self.C,
            "D": self.D,
            "x0": self.x0,
            "tau0": self.tau0,
            "states": np.array(self.states),
            "inputs": np.array(self.inputs),
        }


#: largest trim velocity linearised about, m/s and rad/s
MAX_TRIM = 1e3


def linearize(vehicle: Any, trim: Any = (0, 0, 0, 0, 0, 0), step: float = 1e-6) -> Linearization:
    """Linearise ``vehicle`` about the body velocity ``trim`` at zero attitude and position.

    Parameters
    ----------
    vehicle : Vehicle
    trim : 6 floats — ν₀ = u, v, w (m/s), p, q, r (rad/s)
    step : float — relative central-difference step (scaled by max(1, |x|)), –

    Returns
    -------
    Linearization
    """
    from hydrokit.simulate.compiled import make_dynamics

    nu0 = np.asarray(trim, float)
    if nu0.shape != (6,) or not np.all(np.isfinite(nu0)):
        raise InputError(f"--trim = {trim!r}: expected 6 finite numbers u,v,w (m/s), p,q,r (rad/s)")
    if np.abs(nu0).max() > MAX_TRIM:
        k = int(np.argmax(np.abs(nu0)))
        unit = "m/s" if k < 3 else "rad/s"
        raise InputError(
            f"--trim {'uvwpqr'[k]} = {nu0[k]:.4g} {unit}: expected |{'uvwpqr'[k]}| ≤ {MAX_TRIM:g} {unit} (faster than anything moves in water; the unit force of B would vanish in round-off)"
        )
    if not (np.isfinite(step) and 0 < step < 1e-2):
        raise InputError(f"step = {step}: expected a small positive relative step (e.g. 1e-6)")
    f = make_dynamics(vehicle)
    x0 = np.concatenate([np.zeros(6), nu0])
    zero = np.zeros(6)
    # f is affine in τ: ν̇ = M⁻¹ (τ − n(x)); the trim force zeroes ν̇
    with np.errstate(all="ignore"):  # non-finite forces (a huge trim) are refused below, in words
        B_nu = np.column_stack([f(0.0, x0, np.eye(6)[j])[6:] - f(0.0, x0, zero)[6:] for j in range(6)])
        try:
            tau0 = -np.linalg.solve(B_nu, f(0.0, x0, zero)[6:])
        except np.linalg.LinAlgError:  # non-finite or singular: refused below
            tau0 = np.full(6, np.nan)
        A = np.zeros((12, 12))
        for j in range(12):
            h = step * max(1.0, abs(x0[j]))
            dx = np.zeros(12)
            dx[j] = h
            A[:, j] = (f(0.0, x0 + dx, tau0) - f(0.0, x0 - dx, tau0)) / (2 * h)
        B = np.zeros((12, 6))
        for j in range(6):
            h = step * max(1.0, abs(tau0[j]))
            dt = np.zeros(6)
            dt[j] = h
            B[:, j] = (f(0.0, x0, tau0 + dt) - f(0.0, x0, tau0 - dt)) / (2 * h)
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B)) and np.all(np.isfinite(tau0))):
        # a trim so fast that the damping forces (∝ ν²) leave the float range
        raise InputError(
            f"--trim {', '.join(f'{x:.4g}' for x in nu0)}: the model's forces at this velocity are not finite "
            "numbers; expected a trim velocity of a realistic size (m/s, rad/s)"
        )
    return Linearization(A, B, np.eye(12), np.zeros((12, 6)), x0, tau0, getattr(vehicle, "name", ""), step)
