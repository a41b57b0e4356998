"""Matplotlib set-up shared by the plot modules: object-oriented figures, PNG bytes out.

Figures are built as :class:`matplotlib.figure.Figure` objects, never through pyplot's
global state, and this package never selects a backend: a notebook keeps its inline backend
and a caller's figures are never closed or switched. PNG rendering uses the Agg canvas
explicitly, which works under any backend (and with none chosen).
"""

from __future__ import annotations

import io
from typing import Any


def new_figure(figsize: tuple[float, float] = (6.4, 4.8), **kwargs: Any) -> Any:
    """A new :class:`matplotlib.figure.Figure` not registered with pyplot (no backend needed)."""
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, **kwargs)


def axes_or_new(ax: Any = None, figsize: tuple[float, float] = (6.4, 4.8), **kwargs: Any) -> Any:
    """``ax`` itself, or the single axes of a new figure (``kwargs`` go to ``add_subplot``)."""
    if ax is not None:
        return ax
    return new_figure(figsize).add_subplot(1, 1, 1, **kwargs)


def to_png(fig: Any, dpi: int = 110) -> bytes:
    """Render a figure to PNG bytes with the Agg canvas (the figure is left as it was)."""
    buf = io.BytesIO()
    # savefig picks a PNG-capable canvas for the call only; no backend is switched
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    return buf.getvalue()
