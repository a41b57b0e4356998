"""Shared fixtures.

``run_cli(*args)`` runs the ``hydrokit`` command in-process through the real entry point
(:func:`hydrokit.cli.main.main`, with its error handling) and returns (exit_code, stdout, stderr).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml
from hypothesis import settings

# CI runs the same examples every time (reproducible); locally hypothesis explores freely
settings.register_profile("ci", derandomize=True, deadline=None)
if os.environ.get("CI"):
    settings.load_profile("ci")

REFERENCE = Path(__file__).parent / "reference"


@pytest.fixture
def run_cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., tuple[int, str, str]]:
    from hydrokit.cli.main import main

    def _run(*args: object) -> tuple[int, str, str]:
        capsys.readouterr()
        code = main([str(a) for a in args])
        out, err = capsys.readouterr()
        return code, out, err

    return _run


@pytest.fixture(scope="session")
def published() -> dict:
    """Numbers printed in the source works (copied from the project's spec; see SPEC.md)."""
    return yaml.safe_load((REFERENCE / "published_results.yaml").read_text())


@pytest.fixture(scope="session")
def lingyun_reference() -> dict:
    """LI2021 Table 1 and Table 4 as printed."""
    return yaml.safe_load((REFERENCE / "li2021_lingyun.yaml").read_text())
