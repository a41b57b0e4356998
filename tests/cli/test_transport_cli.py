"""``hydrokit transport`` (issue #11): the frozen options and files, and bad assembly files
refused with one line naming the field, exit 2, nothing written."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from hydrokit.io.assembly import ASSEMBLIES_DIR

BASE = yaml.safe_load((ASSEMBLIES_DIR / "rehman_transport.yaml").read_text())


def _write(tmp_path, mutate):
    data = json.loads(json.dumps(BASE))
    mutate(data["parts"])
    p = tmp_path / "asm.yaml"
    p.write_text(yaml.safe_dump(data))
    return p


@pytest.mark.parametrize("model", ["rigid", "multibody", "independent"])
def test_transport_writes_the_contract_files(run_cli, tmp_path, model):
    out = tmp_path / "out"
    code, _, err = run_cli(
        "transport",
        "rehman_transport",
        "--duration",
        "2",
        "--dt",
        "0.01",
        "--model",
        model,
        "--rpm",
        "minerva-1.V1=1000",
        "--rpm",
        "minerva-2.V2=1000",
        "--force",
        "payload=0,0,-100,0,0,0",
        "--out",
        out,
        "--plots",
    )
    assert code == 0, err
    traj = (out / "trajectory.csv").read_text().splitlines()
    assert traj[0] == "time,x,y,z,phi,theta,psi,u,v,w,p,q,r"
    assert len(traj) == 1 + 201
    for part in ("payload", "manipulator-1", "manipulator-2", "minerva-1", "minerva-2"):
        assert (out / f"trajectory_{part}.csv").read_text().startswith("time,x,y,z,phi,theta,psi,u,v,w,p,q,r\n")
    loads = (out / "loads.csv").read_text().splitlines()
    assert loads[0] == "time,joint,fx,fy,fz,mx,my,mz"
    assert len(loads) == 1 + 201 * 4
    assert {line.split(",")[1] for line in loads[1:]} == {"manipulator-1", "manipulator-2", "minerva-1", "minerva-2"}
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["joints"]) == {"manipulator-1", "manipulator-2", "minerva-1", "minerva-2"}
    j = summary["joints"]["minerva-1"]
    col = np.array(
        [[float(v) for v in line.split(",")[2:5]] for line in loads[1:] if line.split(",")[1] == "minerva-1"]
    )
    assert j["max_force_N"] == pytest.approx(np.linalg.norm(col, axis=1).max(), rel=1e-6)
    for png in ("path.png", "separation.png", "loads.png"):
        assert (out / png).stat().st_size > 5000


BAD = [
    ("cycle", lambda ps: ps[0].update(parent="minerva-1", joint=[0, -1.5, 0]), "parts\\[0\\].parent.*cycle"),
    ("unknown parent", lambda ps: ps[3].update(parent="crane"), "parts\\[3\\].parent' = 'crane'"),
    ("far joint", lambda ps: ps[3].update(joint=[0, -9.0, 0]), "parts\\[3\\].joint' = \\[0.0, -9.0, 0.0\\]"),
    ("missing joint", lambda ps: ps[1].pop("joint"), "parts\\[1\\].joint': missing"),
    ("two roots", lambda ps: (ps[1].pop("parent"), ps[1].pop("joint")), "2 parts without a parent"),
    ("root joint", lambda ps: ps[0].update(joint=[0, 0, 0]), "parts\\[0\\].joint': the root part"),
    ("bad stiffness", lambda ps: ps[1].update(joint_stiffness=[1, 2, 3]), "parts\\[1\\].joint_stiffness"),
    ("negative stiffness", lambda ps: ps[1].update(joint_stiffness=[1, 1, 1, 1, 1, -1]), "expected positive"),
    ("self parent", lambda ps: ps[1].update(parent="manipulator-1"), "cannot be its own parent"),
    ("duplicate name", lambda ps: ps[2].update(name="manipulator-1"), "parts\\[2\\].name' = 'manipulator-1'"),
]


@pytest.mark.parametrize("label,mutate,match", BAD, ids=[b[0] for b in BAD])
def test_bad_assembly_is_one_line_exit_2_nothing_written(run_cli, tmp_path, label, mutate, match):
    import re

    p = _write(tmp_path, mutate)
    out = tmp_path / "out"
    code, stdout, err = run_cli("transport", p, "--duration", "1", "--dt", "0.01", "--out", out)
    assert code == 2
    assert "Traceback" not in err
    lines = [x for x in err.strip().splitlines() if x]
    assert len(lines) == 1 and re.search(match, lines[0]), err
    assert not out.exists()


@pytest.mark.parametrize(
    "args,match",
    [
        (["--rpm", "minerva-1.X=1000"], "thruster 'minerva-1.X': no such thruster"),
        (["--rpm", "minerva-1.V1"], "--rpm 'minerva-1.V1': expected PART.THRUSTER=RPM"),
        (["--rpm", "minerva-1.V1=fast"], "--rpm minerva-1.V1"),
        (["--force", "minerva-9=0,0,0,0,0,0"], "force on part 'minerva-9'"),
        (["--force", "payload=1,2"], "--force payload '1,2'"),
    ],
)
def test_bad_options_are_one_line_exit_2(run_cli, tmp_path, args, match):
    out = tmp_path / "out"
    code, _, err = run_cli("transport", "rehman_transport", "--duration", "1", "--dt", "0.01", *args, "--out", out)
    assert code == 2 and "Traceback" not in err
    assert match in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()
