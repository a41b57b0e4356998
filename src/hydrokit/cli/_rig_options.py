"""Options shared by ``hydrokit rig simulate`` and ``rig plan``: true coefficients, amplitudes
and the sensor model, converted from the CLI's units (mm, degrees, Hz) to SI at this edge."""

from __future__ import annotations

import math
from typing import Any

import click

from hydrokit.cli._types import FINITE, NON_NEGATIVE, SECONDS, Number, Numbers
from hydrokit.errors import InputError


def _sensor(rig_obj: Any, sample_rate: float | None, noise: float | None, resolution: float | None, hold: float) -> Any:
    from hydrokit.identify.virtual_rig import SensorModel

    if rig_obj.translational_signal:
        base = SensorModel.encoder(hold_time=hold)
        noise_si = 0.0 if noise is None else noise * 1e-3
        res_si = base.resolution if resolution is None else resolution * 1e-3
    else:
        base = SensorModel.imu(hold_time=hold)
        noise_si = base.noise_std if noise is None else math.radians(noise)
        res_si = 0.0 if resolution is None else math.radians(resolution)
    rate = base.sample_rate if sample_rate is None else sample_rate
    unit = "mm" if rig_obj.translational_signal else "°"
    name = f"{rate:g} Hz, noise {noise_si * (1e3 if unit == 'mm' else 180 / math.pi):.3g} {unit}, step {res_si * (1e3 if unit == 'mm' else 180 / math.pi):.3g} {unit}"
    return SensorModel(rate, noise_si, res_si, hold, name)


_COMMON = [
    *(
        click.option(
            f"--{name}",
            type=NON_NEGATIVE,
            required=True,
            help=f"True {sym}, {unit} ({rot} torsion, floating roll/pitch).",
        )
        for name, sym, unit, rot in (
            ("added-mass", "added mass m_a", "kg", "kg·m²"),
            ("linear-damping", "K_L", "N·s/m", "N·m·s/rad"),
            ("quadratic-damping", "K_Q", "N·s²/m²", "N·m·s²/rad²"),
        )
    ),
    click.option(
        "--amplitudes",
        type=Numbers(unit="mm or degrees", nonzero=True),
        required=True,
        help="Release displacements, comma-separated: mm (spring, floating heave) or degrees (otherwise).",
    ),
    click.option("--duration", type=SECONDS, default=20.0, show_default=True, help="Recorded time after release, s."),
    click.option("--sample-rate", type=Number("Hz", above=0), help="Sensor sample rate, Hz (default 100)."),
    click.option(
        "--noise", type=NON_NEGATIVE, help="Sensor noise std: mm (spring, default 0) or degrees (default 0.05)."
    ),
    click.option(
        "--resolution", type=NON_NEGATIVE, help="Sensor step: mm (spring, default 1/2.45 = 0.408) or degrees (0)."
    ),
]


def _common(f):  # noqa: ANN001, ANN202
    for opt in reversed(_COMMON):
        f = opt(f)
    return f


def _amplitudes(vals: list[float], rig_obj: Any) -> list[float]:
    return [v * 1e-3 for v in vals] if rig_obj.translational_signal else [math.radians(v) for v in vals]


_TRIM = [
    click.option(
        "--start",
        "--release",
        "release",
        type=FINITE,
        default=None,
        help="Start of free motion (release) in every launch, s in the file's time base "
        "(default: detected after any forced motion, at the first extreme of the free decay).",
    ),
    click.option("--end", type=FINITE, default=None, help="Last useful time in every launch, s (default: detected)."),
    click.option(
        "--detrend",
        type=click.Choice(["none", "mean", "linear"]),
        default="mean",
        show_default=True,
        help="Remove a constant (mean) or straight drifting (linear) rest value from each launch (no unit).",
    ),
    click.option(
        "--amplitude-window",
        default=None,
        metavar="HI,LO",
        help="Fit only while the amplitude is inside the window: from the first extreme ≤ HI until the "
        "amplitude falls below LO; degrees as 20deg,3.5deg or SI (m or rad).",
    ),
    click.option(
        "--equivalent-at",
        default=None,
        metavar="A[,A...]",
        help="Add the equivalent linear damping B_e at these amplitudes with its standard error: "
        "degrees as 5deg or SI (m or rad). Spring, torsion and floating rigs.",
    ),
    click.option(
        "--equivalent-model",
        type=click.Choice(["cubic", "fitted"]),
        default="cubic",
        show_default=True,
        help="Damping model B_e comes from (output-error): a cubic-damping fit of the same record, "
        "which bends with the damping curve, or the fitted --damping-model (biased wherever the "
        "curve bends; its value stays in the JSON as value_fitted_model).",
    ),
]


def trim_options(f):  # noqa: ANN001, ANN201
    """``hydrokit identify``'s record options: --start, --end, --detrend, --amplitude-window,
    --equivalent-at, --equivalent-model."""
    for opt in reversed(_TRIM):
        f = opt(f)
    return f


def trim_settings(
    rig_obj: Any, window_text: str | None, equivalent_text: str | None
) -> tuple[tuple[float, float] | None, tuple[float, ...]]:
    """--amplitude-window and --equivalent-at in SI (m or rad)."""
    from hydrokit.identify.preprocess import parse_amplitude

    tr = bool(rig_obj.translational_signal)
    window = None
    if window_text is not None:
        parts = window_text.split(",")
        if len(parts) != 2:
            raise InputError(f"--amplitude-window {window_text!r}: expected HI,LO such as 20deg,3.5deg")
        hi, lo = (parse_amplitude(p, tr, "--amplitude-window") for p in parts)
        if not hi > lo:
            raise InputError(f"--amplitude-window {window_text!r}: expected HI > LO")
        window = (hi, lo)
    amps: tuple[float, ...] = ()
    if equivalent_text is not None:
        amps = tuple(parse_amplitude(p, tr, "--equivalent-at") for p in equivalent_text.split(","))
    return window, amps
