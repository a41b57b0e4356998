"""Memory budget of a run: refuse up front, before allocating, arrays the machine cannot hold.

A run's recorded arrays are sized from the duration, the step and the output step before the
first step is taken; :func:`check_memory` compares that size with the memory still available,
so a run of terabytes is refused in a millisecond with a line saying what to change, rather
than failing in ``np.empty`` (or, worse, after the machine has started to swap).
"""

from __future__ import annotations

import os

from hydrokit.errors import InputError

_GB = 1e9


def available_bytes() -> int | None:
    """Memory this process can still take, bytes, or None when the system does not say.

    The smaller of the memory the kernel can give without swapping (``MemAvailable`` in
    ``/proc/meminfo`` on Linux, else the free physical pages) and what an address-space
    limit (``ulimit -v``, ``RLIMIT_AS``) leaves above the process's current size.

    Returns
    -------
    int or None
        Bytes.
    """
    figures = [n for n in (_meminfo_available(), _address_space_left()) if n is not None]
    return min(figures) if figures else None


def check_memory(n_bytes: float, what: str) -> None:
    """Refuse a run whose arrays would need more memory than is available.

    Parameters
    ----------
    n_bytes : float
        Size of the arrays about to be allocated, bytes.
    what : str
        What they hold, named in the message (``the recorded trajectory (2e10 rows)``).

    Raises
    ------
    InputError
        ``this run would need X GB of memory for <what>, more than the Y GB available; expected …``.
        Nothing is checked when the available memory is unknown.
    """
    avail = available_bytes()
    if avail is not None and n_bytes > avail:
        raise InputError(
            f"this run would need {n_bytes / _GB:.3g} GB of memory for {what}, more than the "
            f"{avail / _GB:.3g} GB available; expected a shorter duration, a larger output step or fewer samples"
        )


def _meminfo_available() -> int | None:
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024  # kB
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def _address_space_left() -> int | None:
    try:
        import resource
    except ImportError:  # not POSIX
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY or soft < 0:
        return None
    used = 0
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    used = int(line.split()[1]) * 1024  # kB
                    break
    except (OSError, ValueError, IndexError):
        pass
    return max(0, soft - used)
