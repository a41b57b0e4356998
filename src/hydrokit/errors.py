"""The project's exceptions.

Every user-facing error is one line naming the file, field or column, the bad value and
what was expected. The CLI turns :class:`HydrokitError` into that line on stderr and exit
code 2, with no traceback. Recoverable oddities are *warnings recorded in results*, not
exceptions.
"""

from __future__ import annotations


class HydrokitError(ValueError):
    """Base of all errors hydrokit raises on bad input or impossible requests."""


class InputError(HydrokitError):
    """Bad user input: a file, field, column or option value that cannot be used.

    Parameters
    ----------
    message : str
        What is wrong: name the value and what was expected.
    source : str, optional
        The file (and field or column) the value came from; prefixed as ``source: message``.
    """

    def __init__(self, message: str, source: str | None = None):
        self.source = source
        self.detail = message
        text = f"{source}: {message}" if source else message
        # one line, always
        super().__init__(" ".join(text.split()))


class SimulationError(HydrokitError):
    """A simulation that cannot go on (e.g. the state became non-finite at time t)."""


class MissingExtraError(HydrokitError, ImportError):
    """An optional dependency is not installed; the message says which extra to install."""

    def __init__(self, package: str, extra: str):
        self.package, self.extra = package, extra
        super().__init__(f"this feature needs the optional package '{package}': pip install 'hydrokit[{extra}]'")

    def __reduce__(self) -> tuple[type, tuple[str, str]]:
        # rebuilt from its two arguments when a worker process sends it back (Dask pickles errors)
        return (type(self), (self.package, self.extra))
