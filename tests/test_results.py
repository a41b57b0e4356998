"""Result objects: JSON-ready to_dict, plot on the caller's axes, notebook view, tables."""

from __future__ import annotations

import dataclasses
import json
import math
import sys

import numpy as np
import pytest

import hydrokit
from hydrokit.errors import InputError, MissingExtraError


@pytest.fixture(scope="module")
def results() -> dict[str, object]:
    from hydrokit.data import campaign_files, geometry_file

    rig_file, files = campaign_files("udrobot", "spring_x")
    return {
        "campaign": hydrokit.identify_campaign(rig_file, files[:6]),
        "trajectory": hydrokit.simulate("bluerov2-heavy", 2.0, 0.01, tau=[10, 0, 0, 0, 0, 0]),
        "batch": hydrokit.simulate_batch(["bluerov2-heavy"] * 3, 1.0, 0.01, tau=[10, 0, 0, 0, 0, 0], output_every=10),
        "mission": hydrokit.fly("minerva_square", duration=4.0),
        "estimate": hydrokit.estimate_geometry(geometry_file("sphere")),
        "forces": hydrokit.fit_forces([0.5, 1, 1.5, 2], [2.6, 10.1, 22.4, 40.2], 0.1, 1000.0),
        "allocation": hydrokit.allocate("minerva", [100, 0, 50, 0, 0, 10]),
    }


NAMES = ["campaign", "trajectory", "batch", "mission", "estimate", "forces", "allocation"]


@pytest.mark.parametrize("name", NAMES)
def test_to_dict_is_strict_json(results: dict[str, object], name: str) -> None:
    doc = results[name].to_dict()  # type: ignore[attr-defined]
    assert isinstance(doc, dict) and doc
    text = json.dumps(doc, allow_nan=False)  # raises on NaN/inf or numpy scalars
    assert json.loads(text) == doc


SPHERE_ADDED_MASS = 0.5 * 1025 * math.pi * 0.5**3 / 6  # kg: half the displaced mass, 0.5 m sphere in 1025 kg/m³

# per result, an array its plot must show (as a line's x or y data or a bar series' heights)
PLOTTED = {
    "campaign": lambda r: [x.added_mass for x in r.results],  # one marker per launch
    "trajectory": lambda r: r.eta[:, 0],  # the path: north against east
    "batch": lambda r: r.states[0, :, 0],  # one path per vehicle: north against east
    "mission": lambda r: r.run.eta[:, 0],  # the flown path
    "estimate": lambda r: [SPHERE_ADDED_MASS] * 3 + [0.0] * 3,  # the added-mass diagonal (closed form)
    "forces": lambda r: [2.6, 10.1, 22.4, 40.2],  # the measured forces
    "allocation": lambda r: r.thrust,  # one bar per thruster
}


def plotted_arrays(ax) -> list[np.ndarray]:  # noqa: ANN001
    out = []
    for line in ax.lines:
        out += [np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)]
    for bars in ax.containers:
        out.append(np.array([b.get_height() for b in bars], float))
    return out


@pytest.mark.parametrize("name", NAMES)
def test_plot_draws_on_the_given_axes(results: dict[str, object], name: str) -> None:
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    out = results[name].plot(ax=ax)  # type: ignore[attr-defined]
    assert out is ax
    want = np.asarray(PLOTTED[name](results[name]), float)
    drawn = plotted_arrays(ax)
    assert any(a.shape == want.shape and np.allclose(a, want, rtol=1e-9, atol=0) for a in drawn), (
        f"{name}.plot does not show {want}"
    )
    if name == "batch":
        assert len(ax.lines) == 3  # one line per vehicle


@pytest.mark.parametrize("name", NAMES)
def test_plot_without_axes_makes_a_figure(results: dict[str, object], name: str) -> None:
    import matplotlib

    before = matplotlib.get_backend()
    ax = results[name].plot()  # type: ignore[attr-defined]
    assert ax.figure is not None
    assert matplotlib.get_backend() == before


def campaign_cell(s: dict) -> str:
    """A campaign summary cell: mean to 5 digits ± std to 2 [interval ends to 4]."""
    return f"{s['mean']:.5g} ± {s['std']:.2g} [{s['ci'][0]:.4g}, {s['ci'][1]:.4g}]"


def g5(x: float) -> str:
    return f"{x:.5g}"


# per result, (label, shown value) rows its notebook table must hold: counts and sizes from the
# call that made it, closed forms where there is one, else the result's own number as 5 digits
REPR_ROWS = {
    "campaign": lambda r: [
        ("method", "output-error"),
        ("launches", "6"),
        # every fitted coefficient: mean ± std [confidence interval] of the six launches
        *[(f"{k} ({u})", campaign_cell(r.summary[k])) for k, u in (("added_mass", "kg"), ("linear_damping", "N s/m"))],
        # the bundled campaign is scaled to full size: those coefficients too
        ("quadratic_damping, full scale (N s^2/m^2)", g5(r.full_scale["quadratic_damping"])),
    ],
    "trajectory": lambda r: [
        ("samples", "201"),  # 2 s at 0.01 s, both ends
        ("final velocity (m/s, rad/s)", "[" + ", ".join(g5(round(v, 4)) for v in r.nu[-1]) + "]"),  # 4 decimals
    ],
    "batch": lambda r: [("vehicles", "3"), ("samples", "11")],  # 1 s at 0.01 s, every 10th
    "mission": lambda r: [("final time (s)", "4"), ("cross-track RMS (m)", g5(r.metrics["cross_track_rms"]))],
    "estimate": lambda r: [
        ("volume (m³)", g5(math.pi * 0.5**3 / 6)),
        (
            "added mass diagonal",
            f"[{g5(SPHERE_ADDED_MASS)}, {g5(SPHERE_ADDED_MASS)}, {g5(SPHERE_ADDED_MASS)}, 0, 0, 0]",
        ),
    ],
    "forces": lambda r: [("n", "4"), ("K_Q", g5(r.K_Q)), ("area", "0.1")],
    "allocation": lambda r: [
        ("thrust (N)", "[" + ", ".join(g5(round(f, 3)) for f in r.thrust) + "]"),  # to the mN
        ("not actuated", "pitch"),  # Minerva has no pitch actuator (SPEC §8 matrix)
    ],
}


@pytest.mark.parametrize("name", NAMES)
def test_repr_html(results: dict[str, object], name: str) -> None:
    html = results[name]._repr_html_()  # type: ignore[attr-defined]
    assert html.startswith("<div><strong>") and html.endswith("</table></div>")
    for label, value in REPR_ROWS[name](results[name]):
        assert f"<tr><th style='text-align:left'>{label}</th><td>{value}</td></tr>" in html, (label, value, html)


def test_repr_html_escapes_user_text(results: dict[str, object]) -> None:
    run = results["mission"]
    evil = dataclasses.replace(run, mission=dataclasses.replace(run.mission, name="<script>x</script>"))  # type: ignore[arg-type]
    html = evil._repr_html_()
    assert "<script>" not in html
    assert "<tr><th style='text-align:left'>mission</th><td>&lt;script&gt;x&lt;/script&gt;</td></tr>" in html


def test_repr_html_title_is_escaped_once(results: dict[str, object]) -> None:
    run = results["mission"]
    evil = dataclasses.replace(run, mission=dataclasses.replace(run.mission, name="<script>x</script>"))  # type: ignore[arg-type]
    assert evil._repr_html_().startswith("<div><strong>MissionResult: &lt;script&gt;x&lt;/script&gt;</strong>")


def test_tables(results: dict[str, object]) -> None:
    pd = pytest.importorskip("pandas")
    camp = results["campaign"].to_dataframe()  # type: ignore[attr-defined]
    assert len(camp) == 6 and "added_mass" in camp.columns
    # the table holds the same numbers as the per-launch results (not a copy that could drift)
    assert camp["added_mass"].tolist() == [r.added_mass for r in results["campaign"].results]  # type: ignore[attr-defined]
    tr = results["trajectory"].to_dataframe()  # type: ignore[attr-defined]
    assert list(tr.columns)[:4] == ["time", "x", "y", "z"] and isinstance(tr, pd.DataFrame)
    alloc = results["allocation"].to_dataframe()  # type: ignore[attr-defined]
    assert np.allclose(alloc["thrust"], results["allocation"].thrust)  # type: ignore[attr-defined]
    from hydrokit._result import Result

    with pytest.raises(TypeError, match="Result has no tabular form"):
        Result().to_dataframe()


def test_missing_pandas_names_the_extra(results: dict[str, object], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(MissingExtraError, match=r"hydrokit\[pandas\]"):
        results["trajectory"].to_dataframe()  # type: ignore[attr-defined]


def test_allocation_document_matches_cli_contract(results: dict[str, object]) -> None:
    doc = results["allocation"].to_dict()  # type: ignore[attr-defined]
    assert set(doc) >= {
        "vehicle",
        "method",
        "thrusters",
        "tau",
        "configuration_matrix",
        "thrust",
        "thrust_limits",
        "command",
        "command_unit",
        "achieved_tau",
        "residual",
        "uncontrollable",
        "saturated",
        "warnings",
        "units",
    }
    # propeller speeds are shown in rpm at the edge: 60 × the rev/s the object holds
    a = results["allocation"]
    k = doc["command_unit"].index("rpm")
    assert doc["command"][k] == pytest.approx(60.0 * a.command[k])  # type: ignore[attr-defined]


def test_full_scale_values_follow_similitude(results: dict[str, object]) -> None:
    camp = results["campaign"]
    lam = 1.0 / camp.rig.scale  # type: ignore[attr-defined]
    # ENG2009 §II.D: added mass scales with λ³, translational damping with λ²
    assert camp.full_scale["added_mass"] == pytest.approx(camp.mean("added_mass") * lam**3)  # type: ignore[attr-defined]
    assert camp.full_scale["quadratic_damping"] == pytest.approx(camp.mean("quadratic_damping") * lam**2)  # type: ignore[attr-defined]


def test_fly_vehicle_needs_waypoints_and_thrusters() -> None:
    v = hydrokit.load_vehicle("minerva")
    with pytest.raises(InputError, match="waypoints"):
        hydrokit.fly(v)
    bare = dataclasses.replace(v, thrusters=None)
    gains = {"pid": {"speed": {"kp": 1}, "depth": {"kp": 1}, "heading": {"kp": 1}}}
    with pytest.raises(InputError, match="no thrusters"):
        hydrokit.fly(bare, waypoints=[[0, 0, 0], [5, 0, 0]], gains=gains, duration=1.0)
    with pytest.raises(InputError, match="expected 6 finite numbers"):
        hydrokit.allocate(v, [1, 2, 3])
