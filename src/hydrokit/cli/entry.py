"""The ``hydrokit`` program's entry point (console script and ``python -m hydrokit``)."""

from __future__ import annotations

import os
import sys

from hydrokit.cli.main import main


def entry() -> None:
    """The ``hydrokit`` program: ``sys.exit(main())``, except after a termination signal.

    An interrupted command has already removed what it staged and printed its one line; the
    process then ends at once with 128 + N, skipping the interpreter's teardown. Native
    libraries stopped mid-work (numba/LLVM compiling when SIGTERM landed) crashed there now and
    then, and the exit code became −11 (SIGSEGV) instead of 143.
    """
    code = main()
    if code > 128:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)
