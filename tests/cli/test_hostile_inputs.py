"""Bad and hostile input, class by class (issue #13 item 5; the table is docs/hostile-input.md).

Every class is answered with exit code 2 and one line on stderr naming the file, field or
option, or with a valid result; nothing new is left in the output folder. Multi-file outputs
are written as a set and a SIGTERM unwinds the command (exit 143, one line, no partial output).
Most cases run in-process through the real entry point (``run_cli``); the ones about the
process itself (stderr not a terminal, SIGTERM, a memory limit) run ``python -m hydrokit``.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError

MISSION = DATA_DIR / "missions" / "minerva_square.yaml"
VEHICLE = DATA_DIR / "vehicles" / "minerva.yaml"
HYDROKIT = [sys.executable, "-m", "hydrokit"]


def mission_file(path: Path, **changes: object) -> Path:
    """The bundled minerva_square mission with ``changes`` to its top-level fields."""
    doc = yaml.safe_load(MISSION.read_text())
    doc.update(changes)
    path.write_text(yaml.safe_dump(doc))
    return path


def vehicle_file(path: Path, old: str, new: str) -> Path:
    text = VEHICLE.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    return path


def alias_bomb(path: Path) -> Path:
    """Ten levels of nine aliases each: 1 KB that expands to 9**10 (3.5 billion) strings."""
    lines = ['l0: &l0 ["x","x","x","x","x","x","x","x","x"]']
    lines += [f"l{i}: &l{i} [" + ",".join([f"*l{i - 1}"] * 9) + "]" for i in range(1, 10)]
    path.write_text("\n".join(lines) + "\n")
    return path


def one_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, f"expected one stderr line, got {len(lines)}: {err[:500]!r}"
    return lines[0]


def files_in(folder: Path) -> list[str]:
    """Every entry under ``folder`` (hidden staging files included), or [] when it does not exist."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")) if folder.exists() else []


# --- bad input by class: (class, make(tmp) -> CLI arguments, words the one line must hold) ----
# the output folder is always tmp/out; it must not exist afterwards

CASES = {
    "yaml-alias-bomb": (
        lambda t: ["mission", alias_bomb(t / "bomb.yaml")],
        ["bomb.yaml", "alias", "expected"],
    ),
    "yaml-recursive-alias": (
        lambda t: ["mission", _write(t / "loop.yaml", "a: &a [*a]\n")],
        ["loop.yaml", "recursive"],
    ),
    "unbounded-echo-field": (
        lambda t: ["mission", mission_file(t / "m.yaml", dt="y" * 100_000)],
        ["m.yaml", "dt"],
    ),
    "unbounded-echo-option": (
        lambda t: ["mission", MISSION, "--duration", "9" * 100_000],
        ["--duration"],
    ),
    "unbounded-echo-path": (
        lambda t: ["mission", "z" * 100_000],
        ["zzz", "expected"],
    ),
    "nan-in-number": (
        lambda t: ["mission", mission_file(t / "m.yaml", dt=float("nan"))],
        ["m.yaml", "'dt'", "nan", "finite"],
    ),
    "inf-in-number": (
        lambda t: ["mission", mission_file(t / "m.yaml", duration=float("inf"))],
        ["m.yaml", "'duration'", "inf", "finite"],
    ),
    "bool-as-number": (
        lambda t: ["mission", mission_file(t / "m.yaml", duration=True)],
        ["m.yaml", "'duration'", "True", "number"],
    ),
    "bool-as-number-vehicle": (
        lambda t: [
            "mission",
            mission_file(t / "m.yaml", vehicle=str(vehicle_file(t / "v.yaml", "mass: 460", "mass: true"))),
        ],
        ["v.yaml", "'mass'", "True", "number"],
    ),
    "non-utf8-text": (
        lambda t: ["mission", _write(t / "m.yaml", b"name: caf\xe9\n" + MISSION.read_bytes())],
        ["m.yaml", "UTF-8"],
    ),
    "deep-nesting-recursion": (
        lambda t: ["mission", _write(t / "deep.yaml", "a: " + "[" * 100_000 + "]" * 100_000 + "\n")],
        ["deep.yaml", "nested", "expected"],
    ),
    "overflow-huge-number": (
        lambda t: ["mission", mission_file(t / "m.yaml", duration=1e308)],
        ["too large", "expected"],
    ),
    "float-overflow-to-inf": (
        lambda t: [
            "mission",
            mission_file(t / "m.yaml", vehicle=str(vehicle_file(t / "v.yaml", "mass: 460", "mass: 1.0e+400"))),
        ],
        ["v.yaml", "'mass'", "inf"],
    ),
    "negative-mass": (
        lambda t: [
            "mission",
            mission_file(t / "m.yaml", vehicle=str(vehicle_file(t / "v.yaml", "mass: 460", "mass: -460"))),
        ],
        ["v.yaml", "mass"],
    ),
    "usage-error": (
        lambda t: ["mission", MISSION, "--controller", "nope"],
        ["--controller", "nope", "--help"],
    ),
}


def _write(path: Path, data: str | bytes) -> Path:
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data)
    return path


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input_is_one_line_exit_2_and_nothing_written(run_cli, tmp_path, case):
    make, words = CASES[case]
    out = tmp_path / "out"
    code, _, err = run_cli(*make(tmp_path), "--out", out)
    line = one_line(err)
    assert code == 2, line
    assert line.startswith("error: "), line
    for w in words:
        assert w in line, f"{w!r} not in {line!r}"
    assert len(line) <= 700, "a message must not echo unbounded input"
    assert files_in(out) == []


def test_huge_integer_field_is_refused(run_cli, tmp_path):
    # 10**30 would reach numba as a Python int (an internal error); bounded by the step count instead
    code, _, err = run_cli("mission", mission_file(tmp_path / "m.yaml", output_every=10**30), "--out", tmp_path / "o")
    line = one_line(err)
    assert code == 2 and "m.yaml" in line and "'output_every'" in line, line
    assert str(10**30) in line and "from 1 to 4000" in line, line  # 200 s / 0.05 s
    assert files_in(tmp_path / "o") == []


# --- signs: negative damping refused unless the file allows it; other oddities said ---------------

NEGATIVE_DAMPING = [
    ("quadratic_damping", "quadratic_damping: [292,", "quadratic_damping: [-292,", "[-292.0,"),
    ("linear_damping", "linear_damping: [29,", "linear_damping: [-29,", "[-29.0,"),
]


@pytest.mark.parametrize(("field", "old", "new", "says"), NEGATIVE_DAMPING)
@pytest.mark.parametrize("command", ["simulate", "mission"])
def test_negative_damping_is_refused_unless_the_file_allows_it(run_cli, tmp_path, field, old, new, says, command):
    """Issue 32 class 6: it was warned and flown (exit 0); the warning's text is now the refusal."""
    veh = vehicle_file(tmp_path / "v.yaml", old, new)
    args = ["--out", tmp_path / "o.csv"] if command == "simulate" else ["--out", tmp_path / "o"]
    target = veh if command == "simulate" else mission_file(tmp_path / "m.yaml", vehicle=str(veh))
    code, _, err = run_cli(command, target, *args, "--duration", 1)
    line = one_line(err)
    assert code == 2, line
    assert line.startswith(f"error: {veh}: field '{field}': {field} has negative"), line
    assert says in line and "energy is fed in" in line and "allow_negative_damping: true" in line, line
    assert not (tmp_path / "o.csv").exists() and not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("field", "old", "new", "says"),
    [
        *NEGATIVE_DAMPING,
        # 460 kg - 293 kg leaves M_RB + M_A positive definite: flies, said
        ("added_mass", "added_mass: [293,", "added_mass: [-293,", "[-293.0,"),
    ],
)
def test_a_negative_entry_that_still_flies_is_warned_about(run_cli, tmp_path, field, old, new, says):
    # negative damping flies only when the file says it is intended
    veh = vehicle_file(tmp_path / "v.yaml", old, new)
    if "damping" in field:
        veh.write_text(veh.read_text() + "\nallow_negative_damping: true\n")
    code, _, err = run_cli("simulate", veh, "--out", tmp_path / "o.csv", "--duration", 1)
    assert code == 0, err
    assert (tmp_path / "o.csv").read_text().startswith("time,")
    warned = [line for line in err.splitlines() if line.startswith(f"warning: {field} has negative")]
    assert len(warned) == 1 and says in warned[0], err


def test_the_bundled_vehicle_flies_without_a_sign_warning(run_cli, tmp_path):
    code, _, err = run_cli("simulate", VEHICLE, "--out", tmp_path / "o.csv", "--duration", 1)
    assert code == 0, err
    assert "negative" not in err, err


def test_negative_added_mass_that_leaves_no_positive_mass_is_refused(run_cli, tmp_path):
    # X_udot magnitudes below -mass make M = M_RB + M_A indefinite: refused, naming the field
    veh = vehicle_file(tmp_path / "v.yaml", "added_mass: [293,", "added_mass: [-2930,")
    code, _, err = run_cli("simulate", veh, "--out", tmp_path / "o.csv", "--duration", 1)
    line = one_line(err.strip())
    assert code == 2 and "added_mass" in line and "positive definite" in line, line
    assert not (tmp_path / "o.csv").exists()


# --- JSON outputs are strict JSON (null, never NaN/Infinity) -----------------------------------


def _strict(text: str) -> object:
    def refuse(name: str) -> object:
        raise AssertionError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_metrics_json_is_strict_even_when_nothing_is_reached(run_cli, tmp_path):
    # 1 s of a 200 s square: no waypoint reached, so the waypoint times are missing values
    code, _, err = run_cli("mission", MISSION, "--out", tmp_path / "o", "--duration", 1, "--no-plots")
    assert code == 0, err
    doc = _strict((tmp_path / "o" / "metrics.json").read_text())
    times = doc["controllers"]["PID"]["waypoint_times"]  # type: ignore[index]
    assert times and all(t is None for t in times)


# --- output paths: checked before the computation, OS errors one line --------------------------


def _never(*args, **kwargs):
    raise AssertionError("the computation started before the output path was checked")


def _udrobot_spring() -> list[object]:
    from hydrokit.data import campaign_files

    rig, launches = campaign_files("udrobot", "spring_x")
    return [rig, launches[0]]


RIG_TRUTH = ["--added-mass", "1", "--linear-damping", "1", "--quadratic-damping", "1", "--amplitudes", "10"]
# (command line with BAD for the unusable path, the function that would compute, the option named)
CHECKED_FIRST = {
    "transport": (
        ["transport", "rehman_transport", "--duration", "1", "--dt", "0.01", "--out", "BAD"],
        "hydrokit.api.transport",
        "--out",
    ),
    "identify-json": (["identify", *_udrobot_spring(), "--json", "BAD"], "hydrokit.api.identify_campaign", "--json"),
    "identify-plots": (
        ["identify", *_udrobot_spring(), "--json", "ok.json", "--plots", "BAD"],
        "hydrokit.api.identify_campaign",
        "--plots",
    ),
    "identify-report": (
        ["identify", *_udrobot_spring(), "--json", "ok.json", "--report", "BAD"],
        "hydrokit.api.identify_campaign",
        "--report",
    ),
    "demo": (["demo", "--out", "BAD"], "hydrokit.api.identify_campaign", "--out"),
    "rig-simulate": (
        ["rig", "simulate", _udrobot_spring()[0], *RIG_TRUTH, "--out", "BAD"],
        "hydrokit.identify.virtual_rig.simulate_launch",
        "--out",
    ),
    "simulate-out": (["simulate", "minerva", "--out", "BAD"], "hydrokit.simulate.driver.simulate", "--out"),
    "simulate-plots": (
        ["simulate", "minerva", "--out", "ok.csv", "--plots", "BAD"],
        "hydrokit.simulate.driver.simulate",
        "--plots",
    ),
}


@pytest.mark.parametrize("case", sorted(CHECKED_FIRST))
def test_output_path_is_checked_before_computing(run_cli, tmp_path, monkeypatch, case):
    import importlib

    args, target, option = CHECKED_FIRST[case]
    module, name = target.rsplit(".", 1)
    monkeypatch.setattr(importlib.import_module(module), name, _never)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("not a folder")
    code, _, err = run_cli(*[tmp_path / "file" / "sub" if a == "BAD" else a for a in args])
    line = one_line(err)
    assert code == 2 and line.startswith(f"error: {option}") and "is a file" in line, line
    assert files_in(tmp_path) == ["file"]


def test_transport_leaves_no_folder_when_its_write_fails(run_cli, tmp_path, monkeypatch):
    from hydrokit import _atomic

    def disk_full(files):
        raise OSError(28, "No space left on device", str(next(iter(files))))

    monkeypatch.setattr(_atomic, "write_files", disk_full)
    out = tmp_path / "new" / "out"
    code, _, err = run_cli("transport", "rehman_transport", "--duration", "0.2", "--dt", "0.01", "--out", out)
    line = one_line(err)
    assert code == 2 and "No space left" in line and "nothing was written" in line, line
    assert files_in(tmp_path) == []  # neither 'new' nor 'new/out' was made


def test_simulate_writes_its_csv_and_plots_as_a_set(run_cli, tmp_path):
    (tmp_path / "plots" / "path.png").mkdir(parents=True)  # a folder where the set puts a file
    code, _, err = run_cli(
        "simulate", "minerva", "--duration", "0.2", "--out", tmp_path / "o.csv", "--plots", tmp_path / "plots"
    )
    line = one_line(err)
    assert code == 2 and "path.png" in line and "nothing was written" in line, line
    assert files_in(tmp_path) == ["plots", "plots/path.png"]  # no CSV, no states.png


def test_output_folder_is_checked_before_the_search_starts(run_cli, tmp_path, monkeypatch):
    import hydrokit.simulate.tune as tune_module

    def never(*args, **kwargs):
        raise AssertionError("the search started before the output folder was checked")

    monkeypatch.setattr(tune_module, "tune_gains", never)
    (tmp_path / "file").write_text("not a folder")
    code, _, err = run_cli("tune", MISSION, "--controller", "pid", "--out", tmp_path / "file" / "sub")
    line = one_line(err)
    assert code == 2 and "--out" in line and "is a file" in line, line


@pytest.mark.parametrize(
    ("make_out", "words"),
    [
        (lambda t: _write(t / "file", "x") / "sub", ["--out", "is a file"]),
        (lambda t: t / ("a" * 300), ["longer than", "bytes"]),
        (lambda t: Path("/proc/hydrokit-out"), ["cannot create files", "/proc"]),
    ],
    ids=["parent-is-a-file", "name-too-long", "cannot-create"],
)
def test_unusable_output_folder_is_one_line(run_cli, tmp_path, make_out, words):
    if words[-1] == "/proc" and not Path("/proc/self").exists():
        pytest.skip("needs Linux /proc")
    out = make_out(tmp_path)
    code, _, err = run_cli("mission", MISSION, "--out", out, "--duration", 1, "--no-plots")
    line = one_line(err)
    assert code == 2, line
    for w in words:
        assert w in line, line
    assert len(line) <= 700


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="permissions do not bind root")
def test_unwritable_output_folder_is_one_line(run_cli, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        code, _, err = run_cli("mission", MISSION, "--out", locked / "o", "--duration", 1, "--no-plots")
    finally:
        locked.chmod(0o755)
    line = one_line(err)
    assert code == 2 and "cannot create files" in line, line


# --- relative paths in a file resolve from that file's folder ----------------------------------


def test_vehicle_path_in_a_mission_resolves_from_the_mission_folder(run_cli, tmp_path, monkeypatch):
    (tmp_path / "vehicles").mkdir()
    (tmp_path / "vehicles" / "mine.yaml").write_text(VEHICLE.read_text())
    (tmp_path / "missions").mkdir()
    mis = mission_file(tmp_path / "missions" / "m.yaml", vehicle="../vehicles/mine.yaml")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # ../vehicles/mine.yaml does not exist from here
    code, _, err = run_cli("mission", mis, "--out", "o", "--duration", 1, "--no-plots")
    assert code == 0, err
    doc = _strict((elsewhere / "o" / "metrics.json").read_text())
    assert Path(doc["vehicle"]).resolve() == (tmp_path / "vehicles" / "mine.yaml").resolve()  # type: ignore[index]


# --- multi-file outputs are written as a set ---------------------------------------------------


def test_a_set_that_cannot_be_completed_leaves_the_old_files(run_cli, tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    (out / "metrics.json").write_text("old metrics\n")
    (out / "trajectory.csv").write_text("old trajectory\n")
    (out / "tracking.png").mkdir()  # a folder where the set puts a file: found before any move
    code, _, err = run_cli("mission", MISSION, "--out", out, "--duration", 1)
    line = one_line(err)
    assert code == 2 and "tracking.png" in line and "nothing was written" in line, line
    assert (out / "metrics.json").read_text() == "old metrics\n"
    assert (out / "trajectory.csv").read_text() == "old trajectory\n"
    assert files_in(out) == ["metrics.json", "tracking.png", "trajectory.csv"]


def test_a_failed_move_puts_the_old_files_back(tmp_path, monkeypatch):
    from hydrokit import _atomic

    (tmp_path / "a.txt").write_text("old a")
    real = os.replace
    calls = []

    def flaky(src, dst):
        calls.append(dst)
        if len(calls) == 2:
            raise OSError(28, "No space left on device", str(dst))
        real(src, dst)

    monkeypatch.setattr(os, "replace", flaky)
    with pytest.raises(OSError, match="No space left"):
        _atomic.write_files({tmp_path / "a.txt": b"new a", tmp_path / "sub" / "b.txt": b"new b"})
    monkeypatch.setattr(os, "replace", real)
    assert calls[0] == tmp_path / "a.txt"  # the first move happened, then was undone
    assert (tmp_path / "a.txt").read_text() == "old a"
    assert files_in(tmp_path) == ["a.txt"]  # no staged file, no backup, no new folder


def test_a_signal_during_the_moves_is_held_until_the_set_is_complete(tmp_path, monkeypatch):
    from hydrokit import _atomic

    real = os.replace
    sent = []

    def replace_then_signal(src, dst):
        real(src, dst)
        if not sent:
            sent.append(dst)
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.05)  # the handler runs here if it is going to

    monkeypatch.setattr(os, "replace", replace_then_signal)
    files = {tmp_path / f"{k}.txt": f"new {k}".encode() for k in "abc"}
    with _atomic.interrupt_on_signals(), pytest.raises(_atomic.Interrupted) as info:
        _atomic.write_files(files)
    assert sent and info.value.written
    assert [p.read_text() for p in files] == ["new a", "new b", "new c"]
    assert files_in(tmp_path) == ["a.txt", "b.txt", "c.txt"]


def test_staged_dir_leaves_the_target_untouched_on_failure(tmp_path):
    from hydrokit._atomic import staged_dir

    new = tmp_path / "new" / "run"
    with pytest.raises(RuntimeError, match="boom"), staged_dir(new) as stage:
        (stage / "report.html").write_text("half")
        raise RuntimeError("boom")
    assert files_in(tmp_path) == []  # not even the parent folder is left behind

    old = tmp_path / "old"
    old.mkdir()
    (old / "report.html").write_text("old report")
    (old / "notes.txt").write_text("the user's")
    with staged_dir(old) as stage:
        (stage / "report.html").write_text("new report")
        (stage / "mission").mkdir()
        (stage / "mission" / "pid.csv").write_text("t\n")
    assert (old / "report.html").read_text() == "new report"
    assert files_in(old) == ["mission", "mission/pid.csv", "notes.txt", "report.html"]
    assert files_in(tmp_path) == ["old", "old/mission", "old/mission/pid.csv", "old/notes.txt", "old/report.html"]


# --- the process: stderr not a terminal, SIGTERM, a memory limit -------------------------------


def _run(args: list[object], cwd: Path, **kw: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*HYDROKIT, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=120, check=False, **kw
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        pytest.param(
            ["mission", "no-such-mission", "--out", "o"],
            "error: no such file or bundled mission 'no-such-mission' (bundled: lingyun_path, minerva_square)",
            id="mission-missing-file",
        ),
        pytest.param(
            ["mission", MISSION],
            "error: Missing option '--out'. (see 'hydrokit mission --help')",
            id="usage-missing-option",
        ),
        pytest.param(
            ["simulate", "minerva", "--duration", "0.2", "--out", "file/x.csv"],
            "error: --out 'file/x.csv': its folder 'file' is a file; expected a folder that exists or can be "
            "created, and that accepts new files",
            id="simulate-unusable-out",
        ),
        pytest.param(
            ["simulate", "minerva", "--duration", "0.2", "--out", "x.csv", "--plots", "p"],
            "error: cannot write 'p/states.png': is a folder; expected a file (or nothing); nothing was written",
            id="simulate-unwritable-after-the-run",  # its progress bar has run: it must print nothing
        ),
    ],
)
def test_stderr_is_one_line_when_not_a_terminal(tmp_path, args, message):
    (tmp_path / "file").write_text("x")
    (tmp_path / "p" / "states.png").mkdir(parents=True)  # found only when the set is written
    res = _run(args, tmp_path)
    assert res.returncode == 2, res.stderr
    assert res.stderr.splitlines() == [message], res.stderr
    assert files_in(tmp_path) == ["file", "p", "p/states.png"]  # no x.csv, no o/


def _wait_for_handler(proc: subprocess.Popen[str], timeout: float = 60.0) -> None:
    """Wait until the process catches SIGTERM (hydrokit's handler is installed), via /proc."""
    status = Path(f"/proc/{proc.pid}/status")
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        caught = next((ln for ln in status.read_text().splitlines() if ln.startswith("SigCgt:")), "SigCgt: 0")
        if int(caught.split()[1], 16) & (1 << (signal.SIGTERM - 1)):
            return
        time.sleep(0.05)
    raise AssertionError("hydrokit never installed its SIGTERM handler")


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs Linux /proc to see the handler")
@pytest.mark.parametrize("existing", [False, True], ids=["new-folder", "folder-with-old-files"])
def test_sigterm_leaves_no_partial_output(tmp_path, existing):
    out = tmp_path / "o"
    if existing:
        out.mkdir()
        (out / "metrics.json").write_text("old metrics\n")
    before = {p: p.read_bytes() for p in out.rglob("*")} if existing else {}
    # 3000 s of the square in the reference Python loop: ~10 s of work, stopped after ~1 s
    proc = subprocess.Popen(
        [*HYDROKIT, "mission", str(MISSION), "--out", str(out), "--loop", "python", "--duration", "3000"],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        _wait_for_handler(proc)
        time.sleep(1.0)  # inside the closed-loop run
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill() if proc.poll() is None else None
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert one_line(err) == "interrupted (SIGTERM); no output written"
    assert {p: p.read_bytes() for p in out.rglob("*")} == before
    assert files_in(tmp_path) == (["o", "o/metrics.json"] if existing else [])


@pytest.mark.skipif(os.name != "posix", reason="resource limits are POSIX")
def test_a_run_larger_than_memory_is_refused_up_front(tmp_path):
    import resource

    def limit() -> None:  # 4 GB of address space: the machine as the run sees it
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    start = time.monotonic()
    # 1e9 s at dt = 0.05 s: 2e10 steps, terabytes of trajectory
    res = _run(["mission", MISSION, "--out", "o", "--duration", "1e9", "--no-plots"], tmp_path, preexec_fn=limit)
    line = one_line(res.stderr)
    assert res.returncode == 2 and "memory" in line, line
    assert time.monotonic() - start < 60, "refused only after running for a long time"
    assert files_in(tmp_path) == []


# --- memory: a run larger than the machine is refused before its arrays are made ---------------


def test_budget_reads_the_available_memory():
    from hydrokit.simulate.budget import available_bytes, check_memory

    avail = available_bytes()
    if avail is None:
        pytest.skip("the system does not say how much memory is available")
    assert avail > 0
    check_memory(1000, "a few numbers")  # fits: no error
    with pytest.raises(InputError, match=r"would need .* GB of memory for everything, more than the .* GB available"):
        check_memory(avail * 2 + 1e9, "everything")


def test_a_run_larger_than_the_available_memory_is_refused_before_allocating(run_cli, tmp_path, monkeypatch):
    import hydrokit.simulate.budget as budget
    import hydrokit.simulate.compiled_loop as compiled_loop

    monkeypatch.setattr(budget, "available_bytes", lambda: 50_000_000)  # a 50 MB machine
    monkeypatch.setattr(compiled_loop, "_loop", _never)
    # 10⁵ s at 0.05 s, every 2nd step: 10⁶ rows of 345 bytes (11 arrays, 5 thrusters)
    code, _, err = run_cli("mission", MISSION, "--out", tmp_path / "o", "--duration", "1e5", "--no-plots")
    line = one_line(err)
    assert code == 2 and "would need 0.345 GB of memory for the recorded trajectory (1000001 rows)" in line, line
    assert "more than the 0.05 GB available" in line and "expected a shorter duration" in line, line
    assert files_in(tmp_path) == []


def test_fleet_paths_larger_than_the_available_memory_are_refused_before_flying(monkeypatch):
    import hydrokit.simulate.budget as budget
    import hydrokit.simulate.compiled_loop as compiled_loop
    from hydrokit import load_mission, load_vehicle  # the API's: the vehicle with its thrusters
    from hydrokit.simulate.fleet import fly_fleet

    mission = load_mission(MISSION)
    monkeypatch.setattr(budget, "available_bytes", lambda: 1_000_000)
    monkeypatch.setattr(compiled_loop, "_fleet", _never)
    with pytest.raises(InputError, match=r"paths of 8 copies \(4001 points each\), more than the 0.001 GB"):
        fly_fleet(mission, load_vehicle(mission.vehicle), n=8, paths_every=1)
