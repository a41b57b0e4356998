"""Issue #32 acceptance: every command, given a file of random bytes in place of any one of its
inputs, ends in exactly one stderr line and exit 2 naming that file; given UTF-16 copies (with
a byte-order mark, as spreadsheets write them) of all its inputs, it gives its result (exit 0,
one stderr line). The commands are found by walking the click group, so a new command fails
:func:`test_every_command_is_covered` until it has an entry here. ``cfd`` needs OpenFOAM and
is covered by its own tests.
"""

from __future__ import annotations

import codecs
import random
from collections.abc import Callable
from pathlib import Path

import click
import pytest

from hydrokit.data import DATA_DIR

UDROBOT = DATA_DIR / "campaigns" / "udrobot"
ROV2 = DATA_DIR / "campaigns" / "rov2"
VEHICLE = DATA_DIR / "vehicles" / "minerva.yaml"
RANDOM = random.Random(32).randbytes(4096)
TRUTH = ["--added-mass", "0.3", "--linear-damping", "2", "--quadratic-damping", "5", "--amplitudes", "20"]
SKIPPED = {"cfd"}  # OpenFOAM; covered by tests/cfd
#: commands whose start lists their inputs on stderr (sysid: the runs, durations and channels)
TALKATIVE = {"sysid fit", "sysid compare"}

Files = dict[str, Path]
#: an input: a file to copy, or its text made from the paths of the other inputs
Source = Path | Callable[[Files], str]


def _mission(files: Files) -> str:
    text = (DATA_DIR / "missions" / "minerva_square.yaml").read_text(encoding="utf-8")
    return text.replace("vehicle: minerva\n", f"vehicle: {files['vehicle.yaml']}\n", 1)


def _assembly(files: Files) -> str:
    text = (DATA_DIR / "assemblies" / "rehman_transport.yaml").read_text(encoding="utf-8")
    return text.replace("vehicle: minerva-rehman", f"vehicle: {files['vehicle.yaml']}")


def _dive(files: Files) -> str:
    """A 1.5 s virtual dive of bluerov2-sysid (yaw, yaw rate, surge speed) as a run file."""
    import hydrokit
    from hydrokit.io.runlog import run_csv
    from hydrokit.sysid.data import generate_runs, hidden_vehicle

    base = hydrokit.load_vehicle("bluerov2-sysid")
    d = generate_runs(hidden_vehicle(base, 4), 1, 1.5, seed=4, dt=0.01)[0]
    return run_csv(d.time, {c: v for c, v in d.rows().items() if c in ("psi", "r", "u")}, d.commands)


def _project(files: Files) -> str:
    return (
        "name: tiny\nvehicle: base.yaml\nscale_ratio: 0.3\ngeometry: geometry.yaml\nchoose: tank\n"
        "campaigns:\n  - {dof: surge, rig: rig.yaml, launches: [l1.csv, l2.csv, l3.csv]}\n"
        "forces:\n  surge: {file: forces.csv, area: 0.444}\nuncertainty: {samples: 0, seed: 1}\n"
    )


#: command → (its inputs by file name, the command line given the inputs' paths)
CALLS: dict[str, tuple[dict[str, Source], Callable[[Files], list[object]]]] = {
    "allocate": ({"vehicle.yaml": VEHICLE}, lambda f: ["allocate", f["vehicle.yaml"], "--tau", "10,0,0,0,0,0"]),
    "demo": ({}, lambda f: []),  # no input file: the bundled campaigns only
    "estimate": (
        {"geometry.yaml": DATA_DIR / "geometry" / "sphere.yaml"},
        lambda f: ["estimate", f["geometry.yaml"], "--out", "e.yaml"],
    ),
    "export": (
        {"vehicle.yaml": VEHICLE},
        lambda f: ["export", f["vehicle.yaml"], "--format", "python-control", "--out", "x.npz"],
    ),
    "fit-forces": (
        {"forces.csv": DATA_DIR / "projects" / "udrobot" / "cfd_x.csv"},
        lambda f: ["fit-forces", f["forces.csv"], "--area", "0.05", "--density", "1000"],
    ),
    "identify": (
        {"rig.yaml": UDROBOT / "spring_x.yaml", "launch.csv": UDROBOT / "spring_x" / "spring_x_L1_1.csv"},
        lambda f: ["identify", f["rig.yaml"], f["launch.csv"], "--json", "i.json", "--method", "equation-error"],
    ),
    "ingest": (
        {"rig.yaml": UDROBOT / "spring_x.yaml", "record.csv": UDROBOT / "spring_x" / "spring_x_L1_1.csv"},
        lambda f: ["ingest", f["record.csv"], "--rig", f["rig.yaml"], "--out", "ing"],
    ),
    "manoeuvre": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "mariner.yaml"},
        lambda f: [
            "manoeuvre",
            f["vehicle.yaml"],
            "--turning-circle",
            "35",
            "--force",
            "727000,0,0,0,0,0",
            "--initial-velocity",
            "7.7,0,0,0,0,0",
            "--dt",
            "0.5",
            "--no-plots",
            "--out",
            "mm",
        ],  # fmt: skip
    ),
    "mission": (
        {"vehicle.yaml": VEHICLE, "mission.yaml": _mission},
        lambda f: ["mission", f["mission.yaml"], "--duration", "1", "--no-plots", "--out", "m"],
    ),
    "rig plan": (
        {"rig.yaml": UDROBOT / "spring_x.yaml"},
        lambda f: ["rig", "plan", f["rig.yaml"], *TRUTH, "--duration", "2"],
    ),
    "rig simulate": (
        {"rig.yaml": UDROBOT / "spring_x.yaml"},
        lambda f: ["rig", "simulate", f["rig.yaml"], *TRUTH, "--duration", "2", "--launches", "1", "--out", "rs"],
    ),
    "run": (
        {
            "base.yaml": DATA_DIR / "projects" / "rov2" / "base.yaml",
            "geometry.yaml": DATA_DIR / "projects" / "rov2" / "geometry.yaml",
            "forces.csv": DATA_DIR / "projects" / "rov2" / "cfx_surge.csv",
            "rig.yaml": ROV2 / "pendulum_surge.yaml",
            **{f"l{k}.csv": ROV2 / "surge" / f"surge_L{k}_1.csv" for k in (1, 2, 3)},
            "project.yaml": _project,
        },
        lambda f: ["run", f["project.yaml"], "--workers", "1", "--quiet", "--out", "r"],
    ),
    "scale": ({}, lambda f: []),  # numbers only: tests/cli/test_numeric_options.py
    "simulate": (
        {"vehicle.yaml": VEHICLE, "force.csv": lambda f: "time,X,Y,Z,K,M,N\n0,10,0,0,0,0,0\n1,20,0,0,0,0,0\n"},
        lambda f: ["simulate", f["vehicle.yaml"], "--duration", "1", "--force-csv", f["force.csv"], "--out", "s.csv"],
    ),
    "transport": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "minerva-rehman.yaml", "assembly.yaml": _assembly},
        lambda f: ["transport", f["assembly.yaml"], "--duration", "0.05", "--dt", "0.01", "--out", "tr"],
    ),
    "sysid fit": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "bluerov2-sysid.yaml", "dive.csv": _dive},
        lambda f: [
            "sysid",
            "fit",
            f["dive.csv"],
            "--vehicle",
            f["vehicle.yaml"],
            "--free",
            "added_mass.yaw",
            "--out",
            "fit",
            "--samples",
            "2",
            "--workers",
            "1",
            "--dt",
            "0.02",
        ],  # fmt: skip
    ),
    "sysid compare": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "bluerov2-sysid.yaml", "dive.csv": _dive, "held.csv": _dive},
        lambda f: [
            "sysid",
            "compare",
            f["dive.csv"],
            "--holdout",
            f["held.csv"],
            "--candidate",
            f"a={f['vehicle.yaml']}",
            "--free",
            "added_mass.yaw",
            "--candidate",
            f"b={f['vehicle.yaml']}",
            "--free",
            "added_mass.yaw,linear_damping.yaw",
            "--out",
            "cmp",
            "--workers",
            "1",
            "--dt",
            "0.02",
            "--window",
            "none",
        ],  # fmt: skip
    ),
    "sysid generate": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "bluerov2-sysid.yaml"},
        lambda f: [
            "sysid",
            "generate",
            "--vehicle",
            f["vehicle.yaml"],
            "--out",
            "g",
            "--runs",
            "1",
            "--duration",
            "1",
        ],
    ),
    "sysid plan": (
        {"vehicle.yaml": DATA_DIR / "vehicles" / "bluerov2-sysid.yaml"},
        lambda f: [
            "sysid",
            "plan",
            f["vehicle.yaml"],
            "--free",
            "added_mass.yaw",
            "--duration",
            "2",
            "--channels",
            "r",
            "--evaluations",
            "2",
            "--dt",
            "0.05",
            "--out",
            "p",
        ],  # fmt: skip
    ),
    "tune": (
        {"vehicle.yaml": VEHICLE, "mission.yaml": _mission},
        lambda f: [
            "tune",
            f["mission.yaml"],
            "--controller",
            "pid",
            "--maxiter",
            "1",
            "--popsize",
            "1",
            "--duration",
            "1",
            "--workers",
            "1",
            "--out",
            "t",
        ],  # fmt: skip
    ),
}


def _commands() -> list[str]:
    """Every leaf command of the ``hydrokit`` group, as typed ("rig simulate")."""
    from hydrokit.cli.main import cli

    ctx = click.Context(cli)
    found: list[str] = []

    def walk(group: click.Group, prefix: str) -> None:
        for name in group.list_commands(ctx):
            cmd = group.get_command(ctx, name)
            if isinstance(cmd, click.Group):
                walk(cmd, f"{prefix}{name} ")
            elif cmd is not None:
                found.append(f"{prefix}{name}")

    walk(cli, "")
    return found


def test_every_command_is_covered():
    assert sorted(set(_commands()) - SKIPPED) == sorted(CALLS)


def _materialise(tmp: Path, inputs: dict[str, Source], encode: Callable[[str, str], bytes]) -> Files:
    """Every input written to ``tmp`` through ``encode(name, text)``: copies first, then the
    files whose text names them."""
    files = {name: tmp / name for name in inputs}
    for name, src in sorted(inputs.items(), key=lambda kv: callable(kv[1])):
        text = src(files) if callable(src) else src.read_text(encoding="utf-8")
        files[name].write_bytes(encode(name, text))
    return files


RANDOM_CASES = [(cmd, name) for cmd, (inputs, _) in sorted(CALLS.items()) for name in inputs]


@pytest.mark.parametrize(("command", "name"), RANDOM_CASES, ids=[f"{c}-{n}" for c, n in RANDOM_CASES])
def test_random_bytes_in_any_input_is_one_line_naming_the_file(run_cli, tmp_path, monkeypatch, command, name):
    monkeypatch.chdir(tmp_path)
    inputs, args = CALLS[command]
    files = _materialise(tmp_path, inputs, lambda n, text: RANDOM if n == name else text.encode("utf-8"))
    code, _, err = run_cli(*args(files))
    lines = err.splitlines()
    assert len(lines) == 1, err[:800]
    assert code == 2 and lines[0].startswith("error: ") and name in lines[0], lines[0]


UTF16 = [cmd for cmd, (inputs, _) in sorted(CALLS.items()) if inputs]


@pytest.mark.parametrize("command", UTF16)
def test_utf16_copies_of_every_input_give_the_result(run_cli, tmp_path, monkeypatch, command):
    monkeypatch.chdir(tmp_path)
    inputs, args = CALLS[command]
    files = _materialise(tmp_path, inputs, lambda n, text: codecs.BOM_UTF16_LE + text.encode("utf-16-le"))
    assert all(f.read_bytes()[:2] == codecs.BOM_UTF16_LE for f in files.values())
    code, _, err = run_cli(*args(files))
    lines = err.splitlines()
    assert code == 0, err[:800]
    if command in TALKATIVE:  # lists its inputs first (issue #44), then notes, then what it wrote
        assert lines[-1].startswith("wrote") and not any(ln.startswith(("error", "internal error")) for ln in lines)
    else:
        assert len(lines) <= 1 and not err.startswith(("error", "internal error")), err[:800]
