"""The sysid figures as a reader sees them in the reports (embedded at 70 dpi): readable text,
cell numbers that contrast with their cells, angles wrapped without vertical strokes, channels
in the natural order."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.colors import to_rgba
from matplotlib.text import Text

from hydrokit.plot._mpl import to_png
from hydrokit.plot.sysid import correlation_figure, residual_figure, run_figure

#: the reports embed these figures at 70 dpi (pipeline/sysid.py) and 80 dpi (report/sysid.py)
REPORT_DPI = 70
#: smallest text a reader reads without zooming (px); 10 px is the usual floor for figure text
MIN_PX = 10.0
NATURAL = ["x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r"]


def _prediction(name: str = "dive1", holdout: bool = False) -> dict:
    t = np.linspace(0.0, 30.0, 1500)
    chans = {}
    for k, c in enumerate(sorted(NATURAL)):  # alphabetical on purpose: the figure must reorder
        y = 0.1 * np.sin(0.3 * t + k)
        if c == "psi":
            y = -0.5 * t  # turns round to −15 rad, as a yawing dive does
        chans[c] = {"time": t, "measured": y + 0.01, "simulated": y, "low": y - 0.05, "high": y + 0.05}
    return {"name": name, "holdout": holdout, "channels": chans}


def _texts(fig) -> list[Text]:
    to_png(fig, REPORT_DPI)  # tick labels exist only once drawn
    return [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]


def _luminance(rgb) -> float:
    # WCAG 2.1 relative luminance, written out here from the standard (not the module's helper)
    def lin(c: float) -> float:
        return c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4

    r, g, b = (lin(c) for c in rgb[:3])
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def _contrast(a, b) -> float:
    la, lb = sorted((_luminance(a), _luminance(b)), reverse=True)
    return (la + 0.05) / (lb + 0.05)


@pytest.mark.parametrize(
    "make",
    [
        lambda: run_figure(_prediction()),
        lambda: residual_figure([_prediction(), _prediction("dive3", True)]),
        lambda: correlation_figure([f"p{i}" for i in range(8)], np.eye(8) * 2 - 1),
    ],
    ids=["run", "residual", "correlation"],
)
def test_every_text_is_readable_at_the_report_dpi(make):
    fig = make()
    small = [(t.get_text(), t.get_fontsize() * REPORT_DPI / 72) for t in _texts(fig)]
    small = [(s, px) for s, px in small if px < MIN_PX]
    assert not small, f"text under {MIN_PX} px at {REPORT_DPI} dpi: {small[:5]}"


def test_correlation_numbers_contrast_with_their_cells():
    n = 7
    corr = np.array([[np.cos(np.pi * (i - j) / (n - 1)) for j in range(n)] for i in range(n)])
    corr[0, -1] = corr[-1, 0] = -1.0  # the darkest blue and (diagonal) the darkest red
    fig = correlation_figure([f"p{i}" for i in range(n)], corr)
    ax = fig.axes[0]
    im = ax.images[0]
    cells = [t for t in ax.texts]
    assert len(cells) == n * n
    worst = min(
        _contrast(
            to_rgba(t.get_color()), im.cmap(im.norm(corr[round(t.get_position()[1]), round(t.get_position()[0])]))
        )
        for t in cells
    )
    # WCAG 2.1 AA asks 4.5:1 for normal text
    assert worst >= 4.5, f"a cell number has contrast {worst:.2f}:1 with its cell"


def test_angles_are_wrapped_and_never_drawn_across_the_wrap():
    fig = run_figure(_prediction())
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("ψ"))
    for line in ax.lines:
        y = np.asarray(line.get_ydata(), float)
        assert np.all(y > -np.pi - 1e-12) and np.all(y <= np.pi + 1e-12), line.get_label()
        if line.get_linestyle() not in ("None", ""):
            assert np.max(np.abs(np.diff(y)), initial=0.0) < np.pi, f"{line.get_label()}: a stroke across the wrap"
    measured = next(line for line in ax.lines if line.get_label() == "measured")
    # the wrapped angle is the unwrapped one modulo 2π: same sine and cosine
    y = np.asarray(measured.get_ydata(), float)
    t = np.asarray(measured.get_xdata(), float)
    np.testing.assert_allclose(np.cos(y), np.cos(-0.5 * t + 0.01), atol=1e-9)
    np.testing.assert_allclose(np.sin(y), np.sin(-0.5 * t + 0.01), atol=1e-9)


def test_channels_are_in_the_natural_order():
    names = ["x", "y", "z", "φ", "θ", "ψ", "u", "v", "w", "p", "q", "r"]
    fig = run_figure(_prediction())
    assert [a.get_ylabel().split(" ")[0] for a in fig.axes] == names
    fig = residual_figure([_prediction()])
    assert [a.get_ylabel().split(" ")[0] for a in fig.axes] == names


def test_every_axis_says_its_unit():
    figs = [run_figure(_prediction()), residual_figure([_prediction()])]
    for fig in figs:
        for ax in fig.axes:
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                if label:
                    assert "(" in label and label.endswith(")"), label
