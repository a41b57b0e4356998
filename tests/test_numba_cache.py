"""Every numba kernel caches its compiled code on disk (``cache=True``): the CLI and a notebook
start without recompiling (README, "Keep the CLI quick to start"). The cache is keyed on the
source of every law a kernel reaches (hydrokit/_numba.py, issue #50): a changed law is seen by
the next process, never by touching a file by hand."""

from __future__ import annotations

import importlib
import json
import os
import pkgutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import hydrokit

#: kernels still on numba's plain cache while calling a compiled function of another file (so a
#: change there is not seen by their cache): each is to move onto ``hydrokit._numba.njit``
#: when its module is next touched. The set only shrinks: an entry that no longer applies fails.
PENDING: set[str] = set()


def _kernels() -> dict:
    from numba.core.dispatcher import Dispatcher

    kernels = {}
    for mod in pkgutil.walk_packages(hydrokit.__path__, "hydrokit."):
        if mod.name.endswith("__main__"):  # runs the CLI
            continue
        try:
            module = importlib.import_module(mod.name)
        except ImportError:  # an optional extra (capytaine, cv2 …) that is not installed
            continue
        for name, obj in vars(module).items():
            if isinstance(obj, Dispatcher) and obj.py_func.__module__ == mod.name:
                kernels[f"{mod.name}.{name}"] = obj
    return kernels


def _reached_files(disp, seen=None) -> set[str]:  # noqa: ANN001
    """Source files of the compiled functions a kernel reaches (its own excluded)."""
    from numba.core.dispatcher import Dispatcher

    from hydrokit._numba import referenced

    seen = set() if seen is None else seen
    files: set[str] = set()
    for _, value in referenced(disp.py_func):
        if isinstance(value, Dispatcher) and id(value) not in seen:
            seen.add(id(value))
            files.add(value.py_func.__code__.co_filename)
            files |= _reached_files(value, seen)
    return files - {disp.py_func.__code__.co_filename}


@pytest.mark.needs_jit(reason="without the JIT there are no compiled kernels to cache")
def test_every_compiled_kernel_caches_to_disk():
    from numba.core.caching import FunctionCache

    from hydrokit._numba import LawCache

    kernels = _kernels()
    # the rig integrators, the vehicle RK4, the closed loop and the transport kernels at least
    assert len(kernels) >= 20, sorted(kernels)
    assert {k for k, d in kernels.items() if not isinstance(d._cache, FunctionCache)} == set()
    # a kernel reaching compiled code of another file needs its cache keyed on that file's source
    stale = {k for k, d in kernels.items() if not isinstance(d._cache, LawCache) and _reached_files(d)}
    assert stale == PENDING
    # the closed loop and the laws compiled from model/ (compile_law) are keyed so
    from hydrokit.simulate import compiled

    assert isinstance(kernels["hydrokit.simulate.compiled_loop._loop"]._cache, LawCache)
    assert isinstance(compiled._terms._cache, LawCache)
    assert isinstance(compiled.steer_surfaces_compiled._cache, LawCache)


_LAW = """
LIMIT = 1.0


def law(x):
    return {gain} * x
"""

_KERNELS = """
import json
import sys

import numba

from hydrokit._numba import njit
from hydrokit.simulate.compiled import compile_law
from lawpkg import laws

_law = compile_law(laws.law)


@njit
def caller(x):
    return _law(x) + 1.0


@numba.njit(cache=True)
def plain_caller(x):
    return _law(x) + 1.0


def stats(d):
    return [sum(d.stats.cache_hits.values()), sum(d.stats.cache_misses.values())]


out = {"caller": caller(3.0), "plain": plain_caller(3.0), "caller_stats": stats(caller), "law_stats": stats(_law)}
json.dump(out, sys.stdout)
"""


def _fresh_process(root: Path) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(root / "cache"), PYTHONPATH=str(root))
    env.pop("NUMBA_DISABLE_JIT", None)
    run = subprocess.run(
        [sys.executable, "-c", "import lawpkg.kernels"], env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


@pytest.mark.needs_jit(reason="the disk cache of compiled code is what is tested")
def test_a_changed_law_is_seen_by_the_next_process_and_an_unchanged_one_hits(tmp_path):
    pkg = tmp_path / "lawpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "kernels.py").write_text(textwrap.dedent(_KERNELS))
    laws = pkg / "laws.py"
    laws.write_text(_LAW.format(gain="2.0"))

    first = _fresh_process(tmp_path)
    assert first["caller"] == 2.0 * 3.0 + 1.0
    assert first["caller_stats"] == [0, 1]  # compiled and saved
    # nothing changed: the next process loads both from disk, compiles nothing
    second = _fresh_process(tmp_path)
    assert second["caller"] == first["caller"]
    assert second["caller_stats"] == [1, 0]
    assert second["law_stats"][1] == 0  # the law inside it is not compiled again either

    # the law changes in another file, same size and possibly the same time stamp
    stat = laws.stat()
    laws.write_text(_LAW.format(gain="3.0"))
    os.utime(laws, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    third = _fresh_process(tmp_path)
    assert third["caller"] == 3.0 * 3.0 + 1.0
    assert third["caller_stats"] == [0, 1]
    # numba's own cache (keyed on the caller's file only) keeps the old law inside the caller:
    # what LawCache is for. Should numba ever track callees itself, this fails and LawCache can go.
    assert third["plain"] == first["caller"]
    # and the new entry hits in turn
    assert _fresh_process(tmp_path)["caller_stats"] == [1, 0]
