"""The solver's stop signal and a finished run's judgement read OpenFOAM's force files with their
pressure and viscous parts (no OpenFOAM needed: the files are written here)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrokit.cfd.body import profile_body
from hydrokit.cfd.case import Case, Flow, Settings
from hydrokit.cfd.run import judged, loads_and_parts, settled


def _wedge_case() -> Case:
    t = np.linspace(0.0, np.pi, 31)
    body = profile_body(0.5 * (1 - np.cos(t)) - 0.5, np.r_[0.0, 0.5 * np.sin(t[1:-1]), 0.0], "sphere profile")
    case = Case(body, Flow(1.0), Settings(density=1.0, viscosity=1e-3, window=100, min_iterations=100, tolerance=5e-4))
    assert case.path == "wedge"
    return case


def _write(post: Path, pressure: np.ndarray, viscous: np.ndarray) -> None:
    """force.dat and moment.dat in OpenFOAM v1912's layout, the parts along the profile's x."""
    d = post / "0"
    d.mkdir(parents=True)
    lines = ["# Force", "# Time (total_x total_y total_z) (pressure_x ...) (viscous_x ...)"]
    for i, (p, v) in enumerate(zip(pressure, viscous, strict=True), start=1):
        lines.append(f"{i}\t({p + v:.12e} 0 0)\t({p:.12e} 0 0)\t({v:.12e} 0 0)")
    (d / "force.dat").write_text("\n".join(lines) + "\n")
    (d / "moment.dat").write_text("\n".join(lines).replace("Force", "Moment") + "\n")


def test_a_wedge_history_whose_parts_trade_does_not_stop_the_solver(tmp_path):
    case = _wedge_case()
    it = np.arange(600, dtype=float)
    # the wedge's 5° sector: 1/72 of the body's force, along the profile's x (aft: X = −F_x)
    trading, flat = tmp_path / "trading", tmp_path / "flat"
    _write(trading, (0.1 + 1e-5 * it) / 72, (0.9 - 1e-5 * it) / 72)  # 1 mN per window against |F| 1 N
    _write(flat, np.full(600, 0.1) / 72, np.full(600, 0.9) / 72)

    _, values, parts = loads_and_parts(case, trading)
    assert values[:, 0] == pytest.approx(-1.0) and not np.any(values[:, 1:])  # × 72, SNAME sign
    assert parts[-1, 0] == pytest.approx(-(0.1 + 1e-5 * 599)) and parts[-1, 3] == pytest.approx(-(0.9 - 1e-5 * 599))
    assert parts[:, 0] + parts[:, 3] == pytest.approx(values[:, 0])

    assert not settled(case, trading)  # the total is flat; its parts are not
    assert settled(case, flat)
    assert judged(case, values, parts).status == "not converged"
    assert judged(case, values, None).status == "converged"  # the total alone would have passed
    _, v_flat, p_flat = loads_and_parts(case, flat)
    assert judged(case, v_flat, p_flat).status == "converged"


def test_a_history_without_parts_is_judged_on_its_total(tmp_path):
    case = _wedge_case()
    d = tmp_path / "post" / "0"
    d.mkdir(parents=True)
    rows = "\n".join(f"{i}\t(0.01 0 0)" for i in range(1, 301))  # an older layout: totals only
    (d / "force.dat").write_text(rows + "\n")
    (d / "moment.dat").write_text(rows + "\n")
    _, values, parts = loads_and_parts(case, tmp_path / "post")
    assert parts is None and values[:, 0] == pytest.approx(-0.72)
    assert settled(case, tmp_path / "post")
