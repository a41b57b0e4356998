"""What every public result object shares: JSON, a table, a notebook view.

A result is a dataclass of one layer (``Trajectory`` in ``simulate``, ``CampaignResult`` in
``identify`` …) that mixes in :class:`Result`. It then has

- ``to_dict()`` — JSON-ready (numbers, lists, strings, ``None`` for NaN/inf): what the CLI
  writes;
- ``to_dataframe()`` — a pandas table where the result is tabular (``hydrokit[pandas]``);
- ``_repr_html_()`` — a small table of its headline numbers for notebooks (text escaped);
- ``plot(ax=None)`` — defined by each class; it hands off to ``hydrokit.plot`` lazily, draws
  on the given axes (or a new :class:`matplotlib.figure.Figure`) and returns the axes.

This module is a base module (like ``hydrokit.errors``): every layer may import it, and it
imports nothing heavy.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from typing import Any

from hydrokit.errors import MissingExtraError


def jsonable(obj: Any) -> Any:
    """``obj`` with arrays as lists, tuples as lists, keys as str and NaN/inf as ``None``."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if hasattr(obj, "to_dict") and not isinstance(obj, type):
        return jsonable(obj.to_dict())
    if hasattr(obj, "tolist"):  # numpy arrays and numpy scalars
        return jsonable(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def pandas() -> Any:
    """Import pandas or raise a one-line error naming the extra to install."""
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError("pandas", "pandas") from None
    return pd


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "–" if not math.isfinite(value) else f"{value:.5g}"
    if value is None:
        return "–"
    if isinstance(value, (list, tuple)):
        if len(value) > 8:
            return f"[{len(value)} values]"
        return "[" + ", ".join(_cell(v) for v in value) + "]"
    return str(value)


def html_table(title: str, rows: Sequence[tuple[str, Any]]) -> str:
    """A two-column HTML table (name, value) under a heading; all text escaped."""
    body = "".join(
        f"<tr><th style='text-align:left'>{html.escape(str(k))}</th><td>{html.escape(_cell(v))}</td></tr>"
        for k, v in rows
    )
    return f"<div><strong>{html.escape(title)}</strong><table>{body}</table></div>"


class Result:
    """Mixin of the public result dataclasses (see the module docstring)."""

    def to_dict(self) -> dict[str, Any]:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def summary_rows(self) -> list[tuple[str, Any]]:
        """(name, value) pairs of the headline numbers; default: the scalar fields of to_dict."""
        return [(k, v) for k, v in self.to_dict().items() if not isinstance(v, (dict, list))]

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """(columns, rows) of the tabular part; results without one raise TypeError."""
        raise TypeError(f"{type(self).__name__} has no tabular form")

    def to_dataframe(self) -> Any:
        """The tabular part as a :class:`pandas.DataFrame` (needs ``hydrokit[pandas]``)."""
        columns, rows = self.table()
        return pandas().DataFrame(rows, columns=columns)

    def _repr_html_(self) -> str:
        return html_table(type(self).__name__, self.summary_rows())
