"""The CLI entry point's contract: help works, bad input is one line and exit code 2."""

from __future__ import annotations

import subprocess
import sys

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
    "mission",
    "rig",
    "run",
    "scale",
    "simulate",
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
