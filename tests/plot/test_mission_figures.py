"""Mission figures: every plan view drawn as a chart (east across, north up), and the Monte
Carlo bands visible (under the lines, at a scale where their width shows)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from matplotlib.collections import PolyCollection

from hydrokit.plot._mpl import to_png
from hydrokit.plot.mission import envelope_figure, fleet_axes, mission_axes, path_figure

#: a path that goes 10 m north and only 2 m east: a swapped plan view shows it lying down
WAYPOINTS = np.array([[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], [10.0, 2.0, 1.5]])


def _run(offset: float = 0.0) -> SimpleNamespace:
    s = np.linspace(0.0, 1.0, 200)
    north = np.interp(s, [0, 0.8, 1], WAYPOINTS[:, 0]) + offset
    east = np.interp(s, [0, 0.8, 1], WAYPOINTS[:, 1]) + 0.1 * np.sin(8 * s)
    depth = np.interp(s, [0, 0.8, 1], WAYPOINTS[:, 2])
    eta = np.column_stack([north, east, depth, 0 * s, 0 * s, 0 * s])
    return SimpleNamespace(eta=eta, path=SimpleNamespace(points=WAYPOINTS), time=60 * s)


def _plan_views(fig):
    """Axes with a north axis and an east axis, whichever way round."""
    pairs = [(a, {a.get_xlabel().split(" ")[0], a.get_ylabel().split(" ")[0]}) for a in fig.axes]
    return [a for a, words in pairs if words == {"north", "east"}]


def _check_chart(ax) -> None:
    assert ax.get_xlabel().startswith("east") and ax.get_ylabel().startswith("north"), (
        ax.get_xlabel(),
        ax.get_ylabel(),
    )
    # the data agree with the labels: the planned path's horizontal extent is the east one (2 m)
    planned = next(line for line in ax.lines if line.get_label() == "planned")
    x, y = np.asarray(planned.get_xdata(), float), np.asarray(planned.get_ydata(), float)
    np.testing.assert_allclose([np.ptp(x), np.ptp(y)], [2.0, 10.0])


def _envelope_inputs(spread: float):
    grid = np.linspace(0.0, 60.0, 120)
    nom = np.column_stack([np.interp(grid, [0, 48, 60], WAYPOINTS[:, k]) for k in range(3)])
    widen = spread * grid / grid[-1]
    env = {
        "p5": nom - widen[:, None],
        "p95": nom + widen[:, None],
        "min": nom - 2 * widen[:, None],
        "max": nom + 2 * widen[:, None],
        "sample_paths": np.stack([nom + f * widen[:, None] for f in (-1.0, 0.0, 1.0)]),
    }
    return grid, {"PID": env}, {"PID": nom}, {"PID": nom + 0.5 * widen[:, None]}


def test_every_mission_plan_view_has_east_across_and_north_up():
    runs = {"PID": _run(), "S-plane": _run(0.2)}
    figs = [path_figure(runs), envelope_figure(WAYPOINTS, *_envelope_inputs(0.05)[:3])]
    axes = [v for f in figs for v in _plan_views(f) if v.name != "3d"]
    axes.append(mission_axes(_run()))
    axes.append(fleet_axes(WAYPOINTS, np.stack([_run().eta, _run(0.1).eta]), np.array([0.1, 0.2])))
    assert len(axes) == 4
    for ax in axes:
        _check_chart(ax)
    three_d = next(a for a in path_figure(runs).axes if a.name == "3d")
    assert three_d.get_xlabel().startswith("east") and three_d.get_ylabel().startswith("north")


def test_monte_carlo_bands_are_under_the_lines_and_visible():
    """A 5 cm spread along a 10 m path: each band must be drawn beneath every line of its
    axes, in a colour that shows (alpha ≥ 0.3 for the 5–95 % band), and in some panel the band
    must take a visible share (≥ 20 %) of the panel's height at the end of the run."""
    grid, envs, nominal, truth = _envelope_inputs(0.05)
    fig = envelope_figure(WAYPOINTS, grid, envs, nominal, truth)
    to_png(fig, 90)
    shares = []
    for ax in fig.axes:
        bands = [c for c in ax.collections if isinstance(c, PolyCollection)]
        if not bands:
            continue
        lines = [line for line in ax.lines if line.get_visible()]
        assert max(b.get_zorder() for b in bands) < min(line.get_zorder() for line in lines)
        assert max(b.get_alpha() for b in bands) >= 0.3
        y0, y1 = sorted(ax.get_ylim())
        for b in bands:
            ext = b.get_paths()[0].vertices[:, 1]
            shares.append((ext.max() - ext.min()) / (y1 - y0))
    assert shares and max(shares) >= 0.2, shares


def test_the_transport_path_is_drawn_as_a_chart_too():
    from hydrokit.plot.transport import path_axes

    eta = _run().eta[:, :3]
    ax = path_axes(SimpleNamespace(parts={"A": eta}, assembly=eta, model="rigid"))
    assert ax.get_xlabel().startswith("east") and ax.get_ylabel().startswith("north")
    x, y, _ = ax.lines[0].get_data_3d()
    np.testing.assert_allclose(x, eta[:, 1])
    np.testing.assert_allclose(y, eta[:, 0])
