"""Moved to :mod:`hydrokit.sysid.plan`; this name stays importable for one release (CHANGELOG.md)."""

import sys
from typing import TYPE_CHECKING

import hydrokit.sysid.plan as _moved

if TYPE_CHECKING:  # what a type checker sees here; at run time this name is the new module itself
    from hydrokit.sysid.plan import *  # noqa: F403

sys.modules[__name__] = _moved
