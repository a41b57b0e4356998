"""A package that is also the API function of its name.

``hydrokit.simulate(...)``, ``hydrokit.sysid(...)`` and ``hydrokit.manoeuvre(...)`` are
:func:`hydrokit.api.simulate`, :func:`hydrokit.api.sysid` and :func:`hydrokit.api.manoeuvre`,
while ``hydrokit.simulate``, ``hydrokit.sysid`` and ``hydrokit.manoeuvre`` are also the packages
holding their code. Importing a submodule (``import hydrokit.sysid.fit``) sets the package as the
attribute of ``hydrokit``; making the package object itself callable keeps both uses working,
whichever comes first.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any


class CallablePackage(types.ModuleType):
    """A package whose call is the function of the same name in :mod:`hydrokit.api` (imported on
    first call)."""

    def _api_function(self) -> Any:  # noqa: ANN401
        return getattr(importlib.import_module("hydrokit.api"), self.__name__.rpartition(".")[2])

    def __call__(self, *args: Any, **kwargs: Any) -> Any:  # noqa: ANN401
        return self._api_function()(*args, **kwargs)

    @property
    def __signature__(self) -> Any:  # noqa: ANN401
        import inspect

        return inspect.signature(self._api_function())


def make_callable(name: str) -> None:
    """Turn the already imported package ``name`` into a :class:`CallablePackage`."""
    sys.modules[name].__class__ = CallablePackage
