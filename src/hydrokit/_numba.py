"""numba's on-disk cache, keyed on the source of every law a kernel depends on (issue #50), and
``compile_law``: a base module, importable by every layer (identify compiles core's RK4 laws with it).

numba keys a cached function on its own source file's time stamp and size only. A kernel that
calls a law compiled from another file (``compile_law`` of a law in model/ or core/, or another
kernel) holds that law's machine code in its own cache entry, so after a change to the law's file
a fresh process would keep running the old law. :class:`LawCache` adds to numba's stamp a hash of
what the kernel's compiled code is made of: the source text of the kernel's file and, through
every compiled function it names (globals, module attributes, closure cells), the source text of
their files, transitively, and the values of the global constants numba freezes into the code.
Nothing is touched by hand: change a law and every kernel built on it recompiles in the next
process; change nothing and the cache hits.

The hash is computed when the kernel is first loaded or saved (its callees are all defined by
then), once per process; files are read and hashed once each (a few ms for the whole package).
The cache file's name also carries a short hash of *which* compiled functions the kernel names,
so one law compiled twice with different callees (``compile_law(f, g=a)`` and
``compile_law(f, g=b)``) keeps two entries instead of loading the other's code.
"""

from __future__ import annotations

import hashlib
import os
import types
from collections.abc import Callable
from typing import Any

import numba
import numpy as np
from numba.core.caching import FunctionCache
from numba.core.dispatcher import Dispatcher

_FILE_HASH: dict[str, str] = {}
#: id → (the dispatcher, kept alive so that its id is never reused; its hashes)
_DEPS: dict[int, tuple[Dispatcher, tuple[str, str]]] = {}


def _file_hash(path: str) -> str:
    """sha256 of a source file's bytes ('' when it cannot be read: numba's own stamp remains)."""
    h = _FILE_HASH.get(path)
    if h is None:
        try:
            with open(path, "rb") as fh:
                h = hashlib.sha256(fh.read()).hexdigest()
        except OSError:
            h = ""
        _FILE_HASH[path] = h
    return h


def _names(code: types.CodeType) -> set[str]:
    """Global and attribute names a code object (and the code nested in it) refers to."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _names(const)
    return names


def _constant(value: Any) -> str | None:  # noqa: ANN401
    """A stable text of a value numba would freeze into the code, or None for anything else."""
    if isinstance(value, (bool, int, float, complex, str, bytes)):
        return repr(value)
    if isinstance(value, tuple) and all(_constant(v) is not None for v in value):
        return repr(value)
    if isinstance(value, np.ndarray):
        return f"{value.dtype}{value.shape}" + hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()
    return None


def referenced(func: Callable[..., Any]) -> list[tuple[str, Any]]:
    """(name, value) of what a function's code names: its globals (and the attributes it reads of
    a module it names, ``mod.law``) and its closure cells."""
    code = func.__code__
    names = sorted(_names(code))
    scope = func.__globals__
    values: list[tuple[str, Any]] = []
    for name in names:
        if name not in scope:
            continue
        value = scope[name]
        if isinstance(value, types.ModuleType):  # ``mod.law`` or ``mod.CONSTANT``
            attrs = ((f"{name}.{n}", getattr(value, n)) for n in names if hasattr(value, n))
            values.extend(a for a in attrs if not isinstance(a[1], types.ModuleType))
        else:
            values.append((name, value))
    for cell in func.__closure__ or ():
        try:
            values.append(("<cell>", cell.cell_contents))
        except ValueError:  # an empty cell
            continue
    return values


def dependencies(disp: Dispatcher) -> tuple[str, str]:
    """(source hash, binding hash) of a compiled function: the source hash folds in the text of
    its file and of every compiled function it reaches, and the constants it reads; the binding
    hash only which compiled functions it calls by which name."""
    key = id(disp)
    if key in _DEPS:
        return _DEPS[key][1]
    _DEPS[key] = (disp, ("", ""))  # a recursion (a kernel reaching itself) adds nothing twice
    code = disp.py_func.__code__
    src = hashlib.sha256(_file_hash(code.co_filename).encode())
    src.update(code.co_code)
    binding = hashlib.sha256()
    for name, value in referenced(disp.py_func):
        if isinstance(value, Dispatcher):
            dep_src, _ = dependencies(value)
            src.update(f"{name}:{dep_src}".encode())
            binding.update(f"{name}={value.py_func.__module__}.{value.py_func.__qualname__};".encode())
            continue
        text = _constant(value)
        if text is not None:
            src.update(f"{name}={text};".encode())
    _DEPS[key] = (disp, (src.hexdigest(), binding.hexdigest()[:8]))
    return _DEPS[key][1]


class LawCache(FunctionCache):
    """numba's ``FunctionCache`` with the stamp of :func:`dependencies` added to the source file's
    own (time, size) stamp, and the binding hash added to the file name."""

    def __init__(self, py_func: types.FunctionType, dispatcher: Dispatcher) -> None:
        super().__init__(py_func)
        self._dispatcher = dispatcher
        self._keyed = False

    def _key(self) -> None:
        if self._keyed:
            return
        self._keyed = True
        src, binding = dependencies(self._dispatcher)
        cf = self._cache_file
        cf._source_stamp = (cf._source_stamp, src)
        base = cf._index_name[: -len(".nbi")] + "-" + binding
        cf._index_name = f"{base}.nbi"
        cf._index_path = os.path.join(cf._cache_path, cf._index_name)
        cf._data_name_pattern = f"{base}.{{number:d}}.nbc"

    def load_overload(self, sig: Any, target_context: Any) -> Any:  # noqa: ANN401
        self._key()
        return super().load_overload(sig, target_context)

    def save_overload(self, sig: Any, data: Any) -> None:  # noqa: ANN401
        self._key()
        super().save_overload(sig, data)


def njit(func: Callable[..., Any] | None = None, **options: Any) -> Any:  # noqa: ANN401
    """``numba.njit(cache=True, **options)`` with the cache keyed by :class:`LawCache`; use as
    ``@njit`` or ``@njit(inline="always")``."""

    def wrap(f: Callable[..., Any]) -> Dispatcher:
        disp = numba.njit(**options)(f)
        if isinstance(disp, Dispatcher):  # NUMBA_DISABLE_JIT=1 hands back the Python function
            disp._cache = LawCache(disp.py_func, disp)  # type: ignore[attr-defined]  # enable_caching, keyed
        return disp

    return wrap if func is None else wrap(func)


#: ``numba.njit`` for kernels that allocate nothing: compiled without numba's reference
#: counting, which otherwise updates every array argument's count atomically on entry and exit
#: (with ~60 array arguments per closed-loop step this was a fifth of the step). Such a kernel
#: may call only kernels of the same kind (numba passes the setting on to callees, and
#: allocation needs it), so code that allocates stays in ordinary ``njit`` kernels. Both cache
#: on disk keyed on the source of every law they reach (:class:`LawCache`).
njit_noalloc = njit(_nrt=False)


def compile_law(func, *, allocates=False, **callees):  # noqa: ANN001, ANN003, ANN201
    """``njit_noalloc`` of a law written once on plain floats in core/ or model/, with the laws it
    calls (``callees``: name → their compiled dispatchers) bound in its globals — numba calls
    only compiled functions, the Python original keeps calling the Python ones. Not a copy: the
    same code object. Its disk cache is keyed on the law's source and its callees' (transitively),
    so a changed law is recompiled in the next process (:class:`LawCache`).

    ``allocates=True`` compiles with numba's reference counting (``njit``) for a law that creates
    arrays (the bounded least squares of the constrained allocation); its callees must be
    compiled the same way, and only such kernels may call it."""
    scope = dict(func.__globals__)
    scope.update(callees)
    bound = types.FunctionType(func.__code__, scope, func.__name__, func.__defaults__, func.__closure__)
    bound.__module__, bound.__qualname__, bound.__doc__ = func.__module__, func.__qualname__, func.__doc__
    return njit(bound) if allocates else njit_noalloc(bound)
