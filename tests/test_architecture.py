"""The layer rules of docs/architecture.md, enforced on the source tree.

A module may import hydrokit modules of its own layer package or of a lower rank only;
sibling layers of equal rank (identify, estimate, model) may not import each other.
``core`` may import only the standard library and numpy; only ``plot`` imports matplotlib.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "hydrokit"

# package -> rank. Base modules (hydrokit/errors.py, hydrokit/_atomic.py) are rank -1.
RANK = {
    "core": 0,
    "identify": 1, "estimate": 1, "model": 1,
    "simulate": 2,
    "io": 3, "plot": 3,
    "report": 4,
    "cli": 5,
}
BASE = {"errors", "_atomic", "__init__", "__main__"}


def _layer(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "hydrokit" or len(parts) < 2:
        return None
    return parts[1]


def _module_name(path: Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    mod = _module_name(path)
    pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
    out: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.extend(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")
                base = base[: len(base) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.append(name)
            if node.module is None or node.level:
                out.extend(f"{name}.{a.name}" for a in node.names)
    return out


def _modules() -> list[Path]:
    return sorted(p for p in SRC.rglob("*.py"))


def test_every_layer_package_exists() -> None:
    for name in RANK:
        assert (SRC / name / "__init__.py").is_file(), name


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_layer_rules(path: Path) -> None:
    own = _layer(_module_name(path))
    if own is None or own in BASE:
        return
    own_rank = RANK[own]
    for imp in _imports(path):
        top = imp.split(".")[0]
        if own == "core" and top not in ("hydrokit", "numpy", "__future__"):
            assert top in sys.stdlib_module_names, f"core must use numpy only, imports {imp}"
        if top == "matplotlib":
            assert own == "plot", f"only plot/ may import matplotlib ({imp})"
        layer = _layer(imp)
        if layer is None or layer in BASE or layer == own:
            continue
        assert layer in RANK, f"unknown hydrokit package {imp}"
        assert RANK[layer] < own_rank, f"{own} (rank {own_rank}) must not import {imp} (rank {RANK[layer]})"


def test_checker_catches_a_violation(tmp_path: Path) -> None:
    """The rule itself can fail: a core module importing simulate is caught."""
    bad = SRC / "core" / "_tmp_violation_probe.py"
    bad.write_text("from hydrokit.simulate import x\n")
    try:
        with pytest.raises(AssertionError, match="must not import"):
            test_layer_rules(bad)
    finally:
        bad.unlink()
