"""Matplotlib set-up shared by the plot modules: Agg backend, PNG bytes out."""

from __future__ import annotations

import io
from typing import Any


def pyplot() -> Any:
    """Import pyplot with the non-interactive Agg backend (headless, CI-safe)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def to_png(fig: Any, dpi: int = 110) -> bytes:
    """Render a figure to PNG bytes and close it."""
    plt = pyplot()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()


def save_png(fig: Any, path: Any, dpi: int = 110) -> None:
    """Write a figure to ``path`` as PNG, whole or not at all, and close it."""
    from hydrokit._atomic import write_bytes

    write_bytes(path, to_png(fig, dpi=dpi))
