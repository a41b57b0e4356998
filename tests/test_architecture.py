"""The layer rules of docs/architecture.md, enforced on the source tree.

A module may import hydrokit modules of its own layer package or of a lower rank only;
sibling layers of equal rank (identify, estimate, model) may not import each other.
``core`` may import only the standard library and numpy; only ``plot`` imports matplotlib,
never pyplot and never ``matplotlib.use``. ``io`` imports nothing from ``simulate`` (it only
reads and writes files). One exception, by design: a result's ``plot`` method hands off to
``hydrokit.plot`` with an import inside that method (STYLE: results have ``.plot(ax=None)``).

No import circles between modules either, counting the imports inside functions (a circle
hidden behind a function-local import is still a circle: neither module can be read, tested
or moved without the other).
"""

from __future__ import annotations

import ast
import sys
from collections.abc import Iterable
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "hydrokit"

# package -> rank. Base modules (hydrokit/errors.py, hydrokit/_atomic.py) are rank -1.
RANK = {
    "core": 0,
    "identify": 1,
    "estimate": 1,
    "model": 1,
    "simulate": 2,
    "cfd": 2,
    "sysid": 3,
    "manoeuvre": 3,
    "io": 4,
    "plot": 5,
    "api": 6,
    "pipeline": 7,
    "report": 8,
    "cli": 9,
}
BASE = {"errors", "_atomic", "_callable", "_result", "_parallel", "_quiet", "_numba", "data", "__init__", "__main__"}
SYSID_MODULES = ("compare", "data", "lm", "model", "plan", "ship", "smooth", "stats", "window")
MANOEUVRE_MODULES = ("laws", "compiled", "metrics", "samples")
#: imports a rank would allow but the layer's job forbids: (importer, imported)
FORBIDDEN = {("io", "simulate"), ("io", "sysid"), ("io", "manoeuvre"), ("plot", "io"), ("plot", "api")}
#: the one upward edge by design: the simulate, sysid and manoeuvre package objects are callable as
#: hydrokit.api.simulate, .sysid, .manoeuvre (so each API name and its subpackage can share a name)
ALLOWED = {("hydrokit._callable", "hydrokit.api")}
#: old name → new home of the modules moved out of simulate/ (issue #50: rooms named after what
#: users do, and the numba cache down to a base module); their shims were kept for one release and
#: are gone (CHANGELOG.md, Removed)
REMOVED = {
    "hydrokit.simulate.sysid": "hydrokit.sysid.fit",
    **{f"hydrokit.simulate.sysid_{n}": f"hydrokit.sysid.{n}" for n in SYSID_MODULES},
    "hydrokit.simulate.manoeuvre": "hydrokit.manoeuvre.run",
    **{f"hydrokit.simulate.manoeuvre_{n}": f"hydrokit.manoeuvre.{n}" for n in MANOEUVRE_MODULES},
    "hydrokit.simulate.replay": "hydrokit.manoeuvre.replay",
    "hydrokit.simulate._cache": "hydrokit._numba",
}
#: import circles that exist today and are being taken apart elsewhere: module sets. The list
#: only shrinks — an entry that no longer is a circle fails. (Empty since issue #50: the windowed
#: fit's circle with the whole-run fit went with hydrokit.sysid.problem.)
KNOWN_CYCLES: set[frozenset[str]] = set()
#: most lines a CLI module may have (the CLI is a thin layer: parse → call the API → write)
CLI_MAX_LINES = 150


def _layer(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "hydrokit" or len(parts) < 2:
        return None
    return parts[1]


def _module_name(path: Path, src: Path = SRC) -> str:
    rel = path.relative_to(src.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _plot_method_nodes(tree: ast.AST) -> set[int]:
    """ids of the import nodes inside functions named ``plot`` (the result hand-off)."""
    ids: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and node.name == "plot":
            ids.update(id(n) for n in ast.walk(node) if isinstance(n, (ast.Import, ast.ImportFrom)))
    return ids


def _imports(path: Path, *, skip_plot_handoff: bool = False) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    mod = _module_name(path)
    pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
    handoff = _plot_method_nodes(tree) if skip_plot_handoff else set()
    out: list[str] = []
    for node in ast.walk(tree):
        if id(node) in handoff:
            name = getattr(node, "module", None) or ""
            if name.startswith("hydrokit.plot"):
                continue
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


def _import_graph(paths: Iterable[Path], src: Path = SRC) -> dict[str, set[str]]:
    """module → the hydrokit modules it imports anywhere in its body (functions included).

    ``from a.b import c`` points at the module ``a.b.c`` when there is one, else at ``a.b``; an
    import inside a ``plot`` method of ``hydrokit.plot`` (the result hand-off) and the
    :data:`ALLOWED` edges are left out, as in the layer rules.
    """
    paths = list(paths)
    known = {_module_name(p, src) for p in paths}

    def resolve(name: str) -> str | None:
        while name and name not in known:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {}
    for path in paths:
        mod = _module_name(path, src)
        pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
        tree = ast.parse(path.read_text(encoding="utf-8"))
        handoff = _plot_method_nodes(tree)
        targets: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = pkg.split(".")
                    base = base[: len(base) - node.level + 1]
                    name = ".".join(base + ([node.module] if node.module else []))
                else:
                    name = node.module or ""
                names = [f"{name}.{a.name}" if f"{name}.{a.name}" in known else name for a in node.names]
            else:
                continue
            if id(node) in handoff and all(n.startswith("hydrokit.plot") for n in names):
                continue
            targets.update(t for t in map(resolve, names) if t is not None and t != mod)
        graph[mod] = {t for t in targets if (mod, t) not in ALLOWED}
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One shortest circle per strongly connected group of ``graph`` (Tarjan), each as the
    modules in import order with the first repeated at the end; sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[set[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.add(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(group)

    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 10 * len(graph) + 100))
    try:
        for v in sorted(graph):
            if v not in index:
                visit(v)
    finally:
        sys.setrecursionlimit(limit)

    out = []
    for group in groups:
        start = min(group)
        # breadth-first from start back to start, inside the group: the shortest circle through it
        prev: dict[str, str] = {}
        frontier = [start]
        while frontier and start not in prev:
            nxt = []
            for v in frontier:
                for w in sorted(graph[v] & group):
                    if w not in prev:
                        prev[w] = v
                        nxt.append(w)
            frontier = nxt
        path = [start]
        v = prev[start]
        while v != start:
            path.append(v)
            v = prev[v]
        out.append([start, *reversed(path[1:]), start])
    return sorted(out)


def test_every_layer_package_exists() -> None:
    for name in RANK:
        assert (SRC / name / "__init__.py").is_file() or (SRC / f"{name}.py").is_file(), name


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_layer_rules(path: Path) -> None:
    own = _layer(_module_name(path))
    if own is None or own in BASE:
        return
    assert own in RANK, f"{path}: hydrokit.{own} is neither a layer of docs/architecture.md nor a base module"
    own_rank = RANK[own]
    for imp in _imports(path, skip_plot_handoff=True):
        if (_module_name(path), imp) in ALLOWED:
            continue
        top = imp.split(".")[0]
        if own == "core" and top not in ("hydrokit", "numpy", "__future__"):
            assert top in sys.stdlib_module_names, f"core must use numpy only, imports {imp}"
        if top == "matplotlib":
            assert own == "plot", f"only plot/ may import matplotlib ({imp})"
            assert imp != "matplotlib.pyplot", f"{path.name}: plot/ builds Figure objects, never pyplot"
        layer = _layer(imp)
        if layer is None or layer in BASE or layer == own:
            continue
        assert layer in RANK, f"unknown hydrokit package {imp}"
        assert RANK[layer] < own_rank, f"{own} (rank {own_rank}) must not import {imp} (rank {RANK[layer]})"
        assert (own, layer) not in FORBIDDEN, f"{own} must not import {imp} ({own} only does its own job)"


def test_no_import_cycles() -> None:
    """No two modules import each other, directly or round a circle, function-local imports included."""
    graph = _import_graph(_modules())
    found = [c for c in _cycles(graph) if frozenset(c) not in KNOWN_CYCLES]
    assert not found, "import circles (move the shared piece to the lower module or a new small one): " + "; ".join(
        " → ".join(c) for c in found
    )


def test_known_cycles_still_exist() -> None:
    """An entry of KNOWN_CYCLES that is no longer a circle is removed, so the list only shrinks."""
    groups = {frozenset(c) for c in _cycles(_import_graph(_modules()))}
    stale = [sorted(k) for k in KNOWN_CYCLES if k not in groups]
    assert not stale, f"no longer circles, delete them from KNOWN_CYCLES: {stale}"


def test_cycle_finder_sees_function_local_imports(tmp_path: Path) -> None:
    """The circle test can fail: two probe modules that import each other only inside functions
    are named as a circle; a plot-method hand-off is not counted."""
    pkg = tmp_path / "hydrokit" / "io"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def f():\n    from hydrokit.io.b import g\n")
    (pkg / "b.py").write_text("def g():\n    from hydrokit.io import a\n")
    (pkg / "c.py").write_text("def plot(ax=None):\n    from hydrokit.plot import d\n")
    plot = tmp_path / "hydrokit" / "plot"
    plot.mkdir()
    (plot / "__init__.py").write_text("")
    (plot / "d.py").write_text("from hydrokit.io.c import x\n")
    src = tmp_path / "hydrokit"
    graph = _import_graph(sorted(src.rglob("*.py")), src)
    assert _cycles(graph) == [["hydrokit.io.a", "hydrokit.io.b", "hydrokit.io.a"]]


#: names that are one table each, defined in one module and imported everywhere else (issue #50)
ONE_TABLE = {"COEFFICIENTS": "hydrokit.core.names"}


def test_one_table_of_names() -> None:
    """``COEFFICIENTS`` is assigned in one module only; the others import it."""
    where: dict[str, list[str]] = {name: [] for name in ONE_TABLE}
    for path in _modules():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets = (
                node.targets
                if isinstance(node, ast.Assign)
                else [node.target]
                if isinstance(node, ast.AnnAssign)
                else []
            )
            for t in targets:
                if isinstance(t, ast.Name) and t.id in where:
                    where[t.id].append(_module_name(path))
    assert where == {name: [mod] for name, mod in ONE_TABLE.items()}, where


def test_no_backend_switch() -> None:
    """No module selects a matplotlib backend (a notebook's inline backend must survive)."""
    for path in _modules():
        text = path.read_text(encoding="utf-8")
        assert "matplotlib.use(" not in text, f"{path}: calls matplotlib.use"


@pytest.mark.parametrize("path", sorted((SRC / "cli").glob("*.py")), ids=lambda p: p.name)
def test_cli_modules_are_thin(path: Path) -> None:
    n = len(path.read_text(encoding="utf-8").splitlines())
    assert n <= CLI_MAX_LINES, f"{path.name} has {n} lines; move logic to the library (limit {CLI_MAX_LINES})"


def test_plot_handoff_is_the_only_exception(tmp_path: Path) -> None:
    """An upward import outside a ``plot`` method is still caught, inside one it is allowed."""
    probe = SRC / "simulate" / "_tmp_handoff_probe.py"
    probe.write_text(
        "def plot(ax=None):\n    from hydrokit.plot.vehicle import path_axes\n\n"
        "def other():\n    from hydrokit.plot.vehicle import path_axes\n"
    )
    try:
        with pytest.raises(AssertionError, match="must not import hydrokit.plot.vehicle"):
            test_layer_rules(probe)
        probe.write_text("def plot(ax=None):\n    from hydrokit.plot.vehicle import path_axes\n")
        test_layer_rules(probe)
    finally:
        probe.unlink()


def test_checker_catches_a_violation(tmp_path: Path) -> None:
    """The rule itself can fail: core importing simulate, io importing simulate are caught."""
    for layer, line in (
        ("core", "from hydrokit.simulate import x\n"),
        ("io", "from hydrokit.simulate.driver import x\n"),
    ):
        bad = SRC / layer / "_tmp_violation_probe.py"
        bad.write_text(line)
        try:
            with pytest.raises(AssertionError, match="must not import"):
                test_layer_rules(bad)
        finally:
            bad.unlink()


@pytest.mark.parametrize("old", sorted(REMOVED))
def test_removed_module_name_is_gone(old: str) -> None:
    """The old name of a moved module no longer imports (its one-release shim is gone); its new
    home does."""
    import importlib
    import re

    with pytest.raises(ModuleNotFoundError, match=re.escape(repr(old))):
        importlib.import_module(old)
    assert importlib.import_module(REMOVED[old]).__name__ == REMOVED[old]


def test_no_compatibility_shims_left() -> None:
    """No module in src/ is a shim that re-exports a moved module under an old name."""
    shims = [str(p.relative_to(SRC)) for p in _modules() if "Moved to :mod:" in p.read_text(encoding="utf-8")]
    assert shims == []


def test_packages_named_like_api_functions_stay_callable() -> None:
    """``hydrokit.sysid`` and ``hydrokit.manoeuvre`` are packages and the API functions of their
    names, whichever is reached first (a fresh interpreter: the submodule import comes first)."""
    import subprocess

    code = (
        "import inspect, hydrokit.sysid.fit, hydrokit.manoeuvre.run, hydrokit.simulate.driver, hydrokit, hydrokit.api\n"
        "for n in ('sysid', 'manoeuvre', 'simulate'):\n"
        "    p = getattr(hydrokit, n)\n"
        "    assert callable(p) and hasattr(p, '__path__'), n\n"
        "    assert inspect.signature(p) == inspect.signature(getattr(hydrokit.api, n)), n\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "ok", out.stderr[-2000:]
