"""Moved to :mod:`hydrokit.manoeuvre.replay`; this name stays importable for one release (CHANGELOG.md)."""

import sys
from typing import TYPE_CHECKING

import hydrokit.manoeuvre.replay as _moved

if TYPE_CHECKING:  # what a type checker sees here; at run time this name is the new module itself
    from hydrokit.manoeuvre.replay import *  # noqa: F403

sys.modules[__name__] = _moved
