"""Moved to :mod:`hydrokit._numba` (a base module, so that identify can key its caches too); this
name stays importable as the same module."""

import sys
from typing import TYPE_CHECKING

import hydrokit._numba as _moved

if TYPE_CHECKING:  # what a type checker sees here; at run time this name is the new module itself
    from hydrokit._numba import *  # noqa: F403

sys.modules[__name__] = _moved
