"""Click parameter types shared by every ``hydrokit`` command (issue #32 class 4).

A bare ``type=float`` takes ``nan`` and ``inf`` (and ``1e999``, which overflows to inf), so
``hydrokit scale --added-mass nan`` used to print "model nan → full scale nan". Every numeric
option uses :class:`Number` (one finite number, optionally in a physical range) or
:class:`Numbers` (comma-separated finite numbers, e.g. ``--force 30,0,3,0,0,3``); counts use
:class:`Count`. A bad value is refused while the command line is parsed, before any work, as one
line naming the option, the value and what was expected (exit 2).
"""

from __future__ import annotations

import math
from typing import Any

import click

from hydrokit.errors import InputError


def _shown(value: Any, limit: int = 80) -> str:
    r = repr(str(value))
    return r if len(r) <= limit else f"{r[: limit - 20]}…{r[-15:]} ({len(str(value))} characters)"


class OptionValueError(click.ClickException):
    """A bad option value: ``--dt 'nan': expected a finite number > 0 (s)`` — the house style of
    one line naming the option, the value and what was expected (exit 2, no usage hint: the
    line already says what to give)."""

    exit_code = 2

    def __init__(self, value: Any, expected: str, param: click.Parameter | None) -> None:
        opts = getattr(param, "opts", None) or ["value"]
        super().__init__(f"{'/'.join(opts)} {_shown(value)}: {expected}")


def _range_words(above: float | None, at_least: float | None, at_most: float | None) -> str:
    low = f" > {above:g}" if above is not None else f" ≥ {at_least:g}" if at_least is not None else ""
    return low + (f"{' and' if low else ''} ≤ {at_most:g}" if at_most is not None else "")


class Number(click.ParamType):
    """One finite number, optionally ``> above``, ``≥ at_least`` and ``≤ at_most``; ``unit`` is
    named in the message."""

    name = "float"

    def __init__(
        self,
        unit: str = "",
        *,
        above: float | None = None,
        at_least: float | None = None,
        at_most: float | None = None,
    ) -> None:
        self.unit, self.above, self.at_least, self.at_most = unit, above, at_least, at_most

    @property
    def expected(self) -> str:
        unit = f" ({self.unit})" if self.unit else ""
        return f"expected a finite number{_range_words(self.above, self.at_least, self.at_most)}{unit}"

    def ok(self, x: float) -> bool:
        return (
            math.isfinite(x)
            and (self.above is None or x > self.above)
            and (self.at_least is None or x >= self.at_least)
            and (self.at_most is None or x <= self.at_most)
        )

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> float:
        try:
            x = float(value) if not isinstance(value, bool) else math.nan
        except (TypeError, ValueError):
            x = math.nan
        if not self.ok(x):
            raise OptionValueError(value, self.expected, param)
        return x


class Numbers(click.ParamType):
    """Comma- (or semicolon-) separated finite numbers: exactly ``n`` when given, each
    positive or non-zero when asked; converted to a list of floats."""

    name = "list"

    def __init__(self, n: int | None = None, unit: str = "", *, positive: bool = False, nonzero: bool = False) -> None:
        self.n, self.unit, self.positive, self.nonzero = n, unit, positive, nonzero

    @property
    def expected(self) -> str:
        count = f"{self.n} " if self.n is not None else ""
        kind = "positive" if self.positive else "non-zero finite" if self.nonzero else "finite"
        return f"expected {count}comma-separated {kind} numbers" + (f" ({self.unit})" if self.unit else "")

    def parse(self, text: str) -> list[float] | None:
        """The numbers of ``text``, or None when it is not what this type takes."""
        try:
            vals = [float(x) for x in str(text).replace(";", ",").split(",")]
        except ValueError:
            return None
        ok = all(math.isfinite(v) and (v > 0 or not self.positive) and (v != 0 or not self.nonzero) for v in vals)
        return vals if ok and (self.n is None or len(vals) == self.n) else None

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> list[float]:
        if isinstance(value, list):  # already converted (a default given as a list)
            return value
        vals = self.parse(value)
        if vals is None:
            raise OptionValueError(value, self.expected, param)
        return vals


def floats(text: str, option: str, n: int | None = None, unit: str = "", positive: bool = False) -> list[float]:
    """:class:`Numbers` for a value that is not a whole option (``--force PART=fx,…``): the
    numbers, or an :class:`InputError` naming ``option``."""
    kind = Numbers(n, unit, positive=positive)
    vals = kind.parse(text)
    if vals is None:
        raise InputError(f"{option} {_shown(text)}: {kind.expected}")
    return vals


class Count(click.IntRange):
    """A whole number of things (launches, samples, generations, a seed) from ``at_least`` to
    ``at_most``."""

    def __init__(self, at_least: int = 1, at_most: int | None = None) -> None:
        super().__init__(at_least, at_most)

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        try:
            return super().convert(value, param, ctx)
        except click.BadParameter:
            span = f"from {self.min} to {self.max}" if self.max is not None else f"≥ {self.min}"
            raise OptionValueError(value, f"expected a whole number {span}", param) from None


#: the ranges most options need (a unit is added where the option has one)
FINITE = Number()
POSITIVE = Number(above=0)
NON_NEGATIVE = Number(at_least=0)
SECONDS = Number("s", above=0)
SEED = Count(0, 2**32 - 1)
