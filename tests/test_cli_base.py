"""The CLI entry point's contract: help works, bad input is one line and exit code 2."""

from __future__ import annotations

import subprocess
import sys


def test_help_lists_commands(run_cli) -> None:
    code, out, _ = run_cli("--help")
    assert code == 0
    for name in ("identify", "simulate", "allocate", "estimate", "demo"):
        assert name in out


def test_unknown_command_exits_2(run_cli) -> None:
    code, _, err = run_cli("no-such-command")
    assert code == 2
    assert "no-such-command" in err


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
