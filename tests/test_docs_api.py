"""docs/api.md is executed, so the walk-through cannot rot; the top-level API contract."""

from __future__ import annotations

import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "api.md"


def test_docs_api_walkthrough_runs_and_keeps_the_backend() -> None:
    import matplotlib
    import matplotlib.pyplot as plt

    backend = matplotlib.get_backend()
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) >= 5
    ns: dict[str, object] = {}
    try:
        for code in blocks:
            exec(compile(code, str(DOC), "exec"), ns)  # our own documentation, not user input
    finally:
        plt.close("all")
    assert matplotlib.get_backend() == backend
    # the walk-through really identified, estimated, simulated and flew
    campaign = ns["campaign"]
    # kg; the campaign's truth (its README: CELY2019 Table 7 x axis, k/ω_n² − m = 0.2866), to 2 %:
    # 8 virtual launches with 2 ms sensor lag, 0.41 mm quantisation and a hand push (measured −0.45 %)
    assert campaign.mean("added_mass") == pytest.approx(0.2866, rel=0.02)
    assert ns["own"].metrics["final_time"] <= 40.0
    # a heavier vehicle accelerates more slowly under the same thrust
    b = ns["batch"]
    assert b.states[1, 1, 6] < b.states[0, 1, 6]


def test_import_is_light() -> None:
    code = (
        "import sys, time; t = time.perf_counter(); import hydrokit; dt = time.perf_counter() - t; "
        "heavy = [m for m in ('numba', 'matplotlib', 'scipy') if m in sys.modules]; print(dt, heavy)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split(" ", 1)
    assert out[1].strip() == "[]", f"import hydrokit loaded {out[1]}"


def test_top_level_names_and_signatures() -> None:
    import hydrokit

    expected = {
        "load_vehicle": ["name_or_path"],
        "load_rig": ["path"],
        "load_mission": ["name_or_path"],
        "load_geometry": ["path"],
        "read_launch": ["path", "rig"],
        "simulate": ["vehicle", "duration", "dt", "tau"],
        "simulate_batch": ["vehicles", "duration", "dt", "tau"],
        "fly": ["mission_or_vehicle"],
        "identify_campaign": ["rig", "launches_or_paths", "method"],
        "estimate_geometry": ["geometry", "bem"],
        "fit_forces": ["speed", "force", "area", "density"],
        "allocate": ["vehicle", "tau", "method"],
    }
    for name, params in expected.items():
        sig = inspect.signature(getattr(hydrokit, name))
        assert list(sig.parameters)[: len(params)] == params, name
    assert inspect.signature(hydrokit.identify_campaign).parameters["method"].default == "output-error"
    assert inspect.signature(hydrokit.allocate).parameters["method"].default == "constrained"
    assert inspect.signature(hydrokit.estimate_geometry).parameters["bem"].default is False
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        hydrokit.nonexistent  # noqa: B018


def test_api_docstring_examples() -> None:
    import doctest

    import hydrokit.api

    res = doctest.testmod(hydrokit.api, optionflags=doctest.ELLIPSIS)
    assert res.attempted >= 8 and res.failed == 0


def test_simulate_is_both_the_function_and_the_subpackage() -> None:
    """``hydrokit.simulate(...)`` runs a simulation, and ``import hydrokit.simulate.x as y``
    still imports the subpackage module (the two share a name)."""
    code = (
        "import hydrokit.simulate.closed_loop as cl; import hydrokit; "
        "tr = hydrokit.simulate('bluerov2-heavy', 0.5, 0.01, tau=[5, 0, 0, 0, 0, 0]); "
        "print(cl.__name__, type(tr).__name__, tr.nu[-1, 0] > 0)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["hydrokit.simulate.closed_loop", "Trajectory", "True"]
