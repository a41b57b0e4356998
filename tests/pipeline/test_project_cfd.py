"""A project's ``cfd:`` section: parsed and checked like every field; computed with OpenFOAM into the CFD column."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from hydrokit.errors import InputError
from hydrokit.io.project import load_project, parse_project

UDROBOT = Path(__file__).resolve().parents[2] / "src" / "hydrokit" / "data" / "projects" / "udrobot"
TINY = {
    "base_cells": 2,
    "surface_level": 2,
    "layers": 0,
    "upstream": 2.0,
    "downstream": 4.0,
    "lateral": 2.0,
    "min_iterations": 50,
    "window": 30,
    "tolerance": 5e-3,
    "max_iterations": 400,
}


def _project(tmp_path: Path, cfd: dict, forces: dict | None = None) -> dict:
    (tmp_path / "sphere.yaml").write_text(
        "name: s\ngravity: 9.81\nfluid: {density: 1.0}\nparts:\n  - {name: ball, shape: sphere, diameter: 1.0, mass: 0.5}\n"
    )
    data = yaml.safe_load((UDROBOT / "project.yaml").read_text())
    for c in data["campaigns"]:
        c["rig"] = str((UDROBOT / c["rig"]).resolve())
        c["launches"] = str((UDROBOT / c["launches"]).resolve())
    data["vehicle"] = str(UDROBOT / data["vehicle"])
    data["mission"] = str(UDROBOT / data["mission"])
    data["geometry"] = str(tmp_path / "sphere.yaml")
    data["forces"] = forces or {}
    data["cfd"] = cfd
    return data


@pytest.mark.parametrize(
    ("cfd", "forces", "match"),
    [
        ({"speeds": [1, 2, 3], "dofs": ["yaw"]}, None, r"field 'cfd.dofs\[0\]' = 'yaw': expected surge, sway or heave"),
        ({"speeds": [1, 2]}, None, "cfd.speeds"),
        ({"speeds": [1, 2, -3]}, None, r"cfd.speeds\[2\]' = -3"),
        ({"speeds": [1, 2, 3], "wind": 1}, None, "wind"),
        ({"speeds": [1, 2, 3], "dofs": ["heave"], "area": {"surge": 0.1}}, None, "cfd.area.surge"),
        ({"speeds": [1, 2, 3], "dofs": ["surge"]}, {"surge": str(UDROBOT / "cfd_x.csv")}, "one CFD source per DOF"),
        ({"speeds": [1, 2, 3], "body": "nope.stl"}, None, "cfd.body"),
    ],
)
def test_a_bad_cfd_section_is_one_line_naming_the_field(tmp_path, cfd, forces, match):
    data = _project(tmp_path, cfd, forces)
    with pytest.raises(InputError, match=match) as info:
        parse_project(data, tmp_path / "project.yaml")
    assert "\n" not in str(info.value)


def test_the_bundled_udrobot_cfd_project_reads_and_names_its_body():
    p = load_project("udrobot_cfd")
    assert p.cfd is not None and p.cfd.dofs == ("surge", "heave")
    assert p.cfd.body.name == "geometry.yaml" and p.cfd.area == {"surge": 0.0495, "heave": 0.0906}
    assert p.cfd.body in p.input_files()  # an edit of the body invalidates the run's cache


def test_bad_cfd_settings_are_refused_before_openfoam_is_looked_for(tmp_path):
    from hydrokit.pipeline.compare import cfd_sweep_inputs

    data = _project(tmp_path, {"speeds": [1, 2, 3], "settings": {"colour": "red"}})
    p = parse_project(data, tmp_path / "project.yaml")
    with pytest.raises(InputError, match="field 'cfd.settings'"):
        cfd_sweep_inputs(p, 1000.0)
    data = _project(tmp_path, {"speeds": [1, 2, 3], "turbulence": "LES"})
    with pytest.raises(InputError, match="field 'cfd'.*turbulence = 'LES'"):
        cfd_sweep_inputs(parse_project(data, tmp_path / "project.yaml"), 1000.0)


@pytest.mark.cfd
@pytest.mark.skipif(shutil.which("simpleFoam") is None, reason="OpenFOAM is not installed")
def test_the_cfd_column_is_computed_from_the_body(tmp_path):
    from hydrokit.pipeline.compare import computed_cfd_sources

    speeds = [0.5, 1.0, 1.5]
    data = _project(tmp_path, {"speeds": speeds, "density": 1.0, "viscosity": 0.02, "settings": TINY})
    p = parse_project(data, tmp_path / "project.yaml")
    done: list[int] = []
    out = computed_cfd_sources(p, 1000.0, tmp_path / "cache", progress=done.append)
    assert done == [1, 1, 1]  # the main job's bar advances per case, not once for the sweep
    surge = out["surge"]
    # independent: the Chin fit of the drag the Clift-Grace-Weber curve gives at Re = U D / ν
    U = np.array(speeds)
    re = U * 1.0 / 0.02
    drag = 0.5 * 1.0 * U**2 * (math.pi / 4) * 24 / re * (1 + 0.1935 * re**0.6305)
    X = np.column_stack([U, U * U])
    k_l, k_q = np.linalg.lstsq(X, drag, rcond=None)[0]
    force = lambda a, b: a * U + b * U * U  # noqa: E731
    assert force(surge["linear_damping"], surge["quadratic_damping"]) == pytest.approx(force(k_l, k_q), rel=0.12)
    assert surge["se"]["quadratic_damping"] > 0 and surge["points"] == 3
    assert surge["computed"].startswith("OpenFOAM (3 cases, 0 failed)")


def test_the_bundled_lingyun_project_carries_li2021_table_4_into_its_truth_and_base_vehicle():
    from hydrokit.io.project import check_inputs
    from hydrokit.io.vehicle import load_vehicle
    from hydrokit.pipeline.compare import cfd_sweep_inputs

    p = load_project("lingyun")
    check_inputs(p)
    # LI2021 Table 4 (non-dimensional): X'_udot, Y'_vdot, Z'_wdot; X'_uu (read as u|u|), Y'_v|v|,
    # Z'_w√(v²+w²); model scale 1:5 (L = 0.25 m) in the tank's fresh water
    dot = {"surge": 5.8589e-02, "sway": 3.8083e-01, "heave": 1.1718e-01}
    quad = {"surge": 1.35758e-01, "sway": 7.85474e-01, "heave": 1.3851717}
    for c in p.campaigns:
        q = 0.5 * 998.2
        assert c.truth["added_mass"] == pytest.approx(dot[c.dof] * q * 0.25**3, rel=1e-5)
        assert c.truth["quadratic_damping"] == pytest.approx(quad[c.dof] * q * 0.25**2, rel=1e-5)
    # the base vehicle holds the same terms at full scale (sea water, L = 1.25 m) in its
    # diagonals and no longer among its terms, so the tank's values replace them, not add to them
    v = load_vehicle(p.vehicle)
    q = 0.5 * 1025.9
    for i, dof in enumerate(("surge", "sway", "heave")):
        assert v.M_A[i, i] == pytest.approx(dot[dof] * q * 1.25**3, rel=1e-5)
        assert v.D_Q[i] == pytest.approx(quad[dof] * q * 1.25**2, rel=1e-5)
    names = set(v.terms.names)
    assert not names & {"X_udot", "Y_vdot", "Z_wdot", "X_u|u|", "Y_v|v|", "Y_|v|v", "Z_w*sqrt(v^2+w^2)"}
    assert {"X_vv", "M_pp", "Y_wr"} <= names
    body, settings, sweep, cases = cfd_sweep_inputs(p, 1025.9)
    assert body.length == pytest.approx(1.25) and settings.density == 1025.9
    assert len(cases) == 12 and {c.flow.axis for c in cases} == {"x", "y", "z"}


@pytest.mark.skipif(shutil.which("simpleFoam") is None, reason="OpenFOAM is not installed")
def test_the_main_jobs_cfd_bar_counts_cases_and_names_the_reynolds_span(tmp_path, monkeypatch):
    import hydrokit.pipeline.compare as compare
    from hydrokit.pipeline.cache import StepCache
    from hydrokit.pipeline.steps import Runner

    data = _project(tmp_path, {"speeds": [0.5, 1.0, 1.5], "density": 1.0, "viscosity": 0.02, "settings": TINY})
    (tmp_path / "project.yaml").write_text(yaml.safe_dump(data))
    p = load_project(tmp_path / "project.yaml")
    bars: dict[str, list[int]] = {}

    def progress(label: str, total: int):  # noqa: ANN202
        bars[label] = [total, 0]
        return lambda n: bars[label].__setitem__(1, bars[label][1] + n)

    def fake(project, density, cache_dir, mapper=None, progress=None):  # noqa: ANN001, ANN202
        for _ in range(3):  # what run_sweep does as each case finishes
            progress(1)
        return {}

    monkeypatch.setattr(compare, "computed_cfd_sources", fake)
    runner = Runner(p, StepCache(tmp_path / "c"), None, progress, bem=False, samples=0)
    runner.others({})
    (label,) = [k for k in bars if k.startswith("CFD")]
    # Re_L = U L / ν with the unit sphere: 0.5 / 0.02 = 25 to 1.5 / 0.02 = 75
    assert "3 cases" in label and "Re_L 25–75" in label
    assert bars[label] == [3, 3]  # a bar of 3 cases, full when the sweep is done
