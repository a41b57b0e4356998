"""Profile of a body of revolution for ``hydrokit cfd``: a CSV with columns ``x`` and ``r``.

x (m) runs from the nose along the axis, r (m) is the radius, r = 0 at the nose and the tail;
``#`` comment lines and a header (``x,r``, any case, other columns ignored) are required, so a
file of other numbers is not read as a hull by mistake. Values are checked by
:func:`hydrokit.cfd.body.check_profile` (closed, increasing x, r ≥ 0).
"""

from __future__ import annotations

import os

import numpy as np

from hydrokit.io.forces import read_columns


def read_profile(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """(x, r) arrays in m from a profile CSV."""
    return read_columns(path, ("x", "r"), "x (m, from the nose) and r (m, the radius)")
