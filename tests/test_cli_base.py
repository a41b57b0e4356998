"""The CLI entry point's contract: help works, bad input is one line and exit code 2."""

from __future__ import annotations

import subprocess
import sys

import pytest

# every command (README "Quick start" and "More commands"; tune in docs/control.md), in the
# sorted order click lists them
COMMANDS = [
    "allocate",
    "cfd",
    "demo",
    "estimate",
    "export",
    "fit-forces",
    "identify",
    "ingest",
    "manoeuvre",
    "mission",
    "rig",
    "run",
    "scale",
    "simulate",
    "sysid",
    "transport",
    "tune",
]


def test_help_lists_commands(run_cli) -> None:
    code, out, _ = run_cli("--help")
    assert code == 0
    # the first word of each row of the Commands section (continuation lines are indented deeper)
    section = out.split("Commands:\n", 1)[1].splitlines()
    listed = [line.split()[0] for line in section if line.startswith("  ") and not line.startswith("   ")]
    assert listed == COMMANDS
    # each listed name resolves to its command (a registry entry pointing at a missing module
    # would be listed yet answer "No such command")
    for name in COMMANDS:
        code, out, err = run_cli(name, "--help")
        assert code == 0, (name, err)
        assert out.startswith(f"Usage: hydrokit {name} [OPTIONS]"), (name, out[:200])


def test_unknown_command_exits_2(run_cli) -> None:
    code, out, err = run_cli("no-such-command")
    assert code == 2
    assert err.splitlines() == ["error: No such command 'no-such-command'. (see 'hydrokit --help')"]
    assert out == ""


def test_help_does_not_import_heavy_modules() -> None:
    code = (
        "import sys; from hydrokit.cli.main import main; "
        "rc = main(['--help']); "
        "heavy = [m for m in ('scipy', 'numba', 'matplotlib') if m in sys.modules]; "
        "print(heavy); sys.exit(rc)"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert res.returncode == 0
    assert res.stdout.strip().endswith("[]"), res.stdout


@pytest.mark.parametrize(("code", "ends"), [(143, "os._exit"), (130, "os._exit"), (2, "sys.exit"), (0, "sys.exit")])
def test_an_interrupted_program_ends_without_interpreter_teardown(monkeypatch, code, ends) -> None:
    # after a signal the outputs are already cleaned up; teardown is where an interrupted numba
    # compile crashed (exit −11 instead of 143). Plain exits keep the normal path (atexit etc.)
    import hydrokit.cli.entry as m

    calls: list[tuple[str, int]] = []

    def ending(name: str):
        def end(c: int) -> None:
            calls.append((name, c))
            raise SystemExit(c)  # neither returns

        return end

    monkeypatch.setattr(m, "main", lambda: code)
    monkeypatch.setattr(m.os, "_exit", ending("os._exit"))
    monkeypatch.setattr(m.sys, "exit", ending("sys.exit"))
    with pytest.raises(SystemExit):
        m.entry()
    assert calls == [(ends, code)]
