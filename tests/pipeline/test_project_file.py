"""Project files (issue #10 contract): every bad field is one line naming it, nothing is run."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.project import bundled_projects, load_project

CAMPAIGN = DATA_DIR / "campaigns" / "udrobot"
BASE = DATA_DIR / "projects" / "udrobot" / "base.yaml"


def write_project(tmp_path: Path, **overrides: object) -> Path:
    """A small valid project in tmp_path (two spring launches, the bundled base vehicle)."""
    (tmp_path / "launches").mkdir(exist_ok=True)
    for name in ("spring_x_L1_1.csv", "spring_x_L4_1.csv"):
        shutil.copy(CAMPAIGN / "spring_x" / name, tmp_path / "launches" / name)
    shutil.copy(CAMPAIGN / "spring_x.yaml", tmp_path / "spring_x.yaml")
    shutil.copy(BASE, tmp_path / "base.yaml")
    doc: dict[str, object] = {
        "name": "tiny",
        "vehicle": "base.yaml",
        "scale_ratio": 0.3,
        "campaigns": [{"dof": "surge", "rig": "spring_x.yaml", "launches": "launches/*.csv"}],
    }
    doc.update(overrides)
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_bundled_projects_load_with_their_globs_expanded():
    assert {"udrobot", "rov2"} <= set(bundled_projects())
    p = load_project("udrobot")
    assert [c.dof for c in p.campaigns] == ["surge", "sway", "heave"]
    # 4 amplitudes × 6 launches per campaign (the bundled README)
    assert [len(c.launches) for c in p.campaigns] == [24, 24, 24]
    assert p.campaigns[0].scale_ratio == 0.3 and p.campaigns[1].scale_ratio == p.scale_ratio == 0.22
    assert p.choose == dict.fromkeys(("surge", "sway", "heave", "roll", "pitch", "yaw"), "tank")
    assert all(f.is_file() for f in p.input_files())


def test_a_minimal_project_takes_the_defaults(tmp_path):
    p = load_project(write_project(tmp_path))
    c = p.campaigns[0]
    assert c.method == "output-error" and c.scale_ratio == 0.3 and len(c.launches) == 2
    assert (p.samples, p.seed, p.mission, p.geometry) == (200, 1, None, None)


def test_choose_per_dof_with_a_default(tmp_path):
    p = load_project(write_project(tmp_path, choose={"surge": "cfd", "default": "geometry"}))
    assert p.choose["surge"] == "cfd" and p.choose["heave"] == "geometry"


@pytest.mark.parametrize(
    ("override", "field", "value"),
    [
        (
            {"campaigns": [{"dof": "hover", "rig": "spring_x.yaml", "launches": "launches/*.csv"}]},
            "campaigns[0].dof",
            "hover",
        ),
        (
            {"campaigns": [{"dof": "surge", "rig": "nope.yaml", "launches": "launches/*.csv"}]},
            "campaigns[0].rig",
            "nope.yaml",
        ),
        (
            {"campaigns": [{"dof": "surge", "rig": "spring_x.yaml", "launches": "none/*.csv"}]},
            "campaigns[0].launches",
            "none/*.csv",
        ),
        (
            {"campaigns": [{"dof": "surge", "rig": "spring_x.yaml", "launches": ["launches/gone.csv"]}]},
            "campaigns[0].launches",
            "gone.csv",
        ),
        (
            {"campaigns": [{"dof": "surge", "rig": "spring_x.yaml", "launches": "launches/*.csv", "method": "magic"}]},
            "campaigns[0].method",
            "magic",
        ),
        ({"choose": "oracle"}, "choose", "oracle"),
        ({"choose": {"hover": "tank"}}, "choose.hover", ""),
        ({"forces": {"surge": "missing.csv"}}, "forces.surge", "missing.csv"),
        ({"mission": "missing.yaml"}, "mission", "missing.yaml"),
        ({"scale_ratio": -1}, "scale_ratio", "-1"),
        ({"vehicle": "gone.yaml"}, "vehicle", "gone.yaml"),
    ],
)
def test_bad_fields_are_named_in_one_line(tmp_path, override, field, value):
    path = write_project(tmp_path, **override)
    with pytest.raises(InputError) as exc:
        load_project(path)
    msg = str(exc.value)
    assert "\n" not in msg and str(path) in msg and f"'{field}'" in msg and value in msg


def test_two_campaigns_for_one_dof_are_refused(tmp_path):
    camp = {"dof": "surge", "rig": "spring_x.yaml", "launches": "launches/*.csv"}
    with pytest.raises(InputError, match=r"campaigns\[1\]\.dof.*already identified by campaigns\[0\]"):
        load_project(write_project(tmp_path, campaigns=[camp, camp]))


def test_unknown_project_names_the_bundled_ones():
    with pytest.raises(InputError, match="udrobot"):
        load_project("no-such-project")
