"""CFD pieces that need no OpenFOAM: flows, bodies, profiles, derivatives, sweeps assembled from outcomes."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import curve_fit

from hydrokit.cfd.body import box, check_profile, geometry_body, mesh_body, profile_body, projected_area, revolve
from hydrokit.cfd.case import Case, Flow, Settings
from hydrokit.cfd.sweep import SweepSpec, assemble, make_cases
from hydrokit.errors import InputError
from hydrokit.estimate.derivatives import fit_derivatives, linear_at
from hydrokit.estimate.forces import fit_forces
from hydrokit.estimate.mesh import SurfaceMesh, check_mesh


def _spheroid(a: float = 0.5, b: float = 0.1, n: int = 81) -> tuple[np.ndarray, np.ndarray]:
    t = np.linspace(0.0, np.pi, n)
    x, r = a * (1 - np.cos(t)), b * np.sin(t)
    r[0] = r[-1] = 0.0
    return x, r


def test_flow_velocity_follows_the_drift_and_attack_definitions():
    f = Flow(2.0, drift=math.radians(10), attack=math.radians(-5))
    u, v, w = f.velocity()
    assert math.hypot(u, v, w) == pytest.approx(2.0, rel=1e-14)
    assert math.atan2(v, u) == pytest.approx(math.radians(10), rel=1e-14)  # β = atan2(v, u)
    assert math.atan2(w, u) == pytest.approx(math.radians(-5), rel=1e-14)  # α = atan2(w, u)
    assert list(Flow(1.5, axis="z").velocity()) == [0.0, 0.0, 1.5]


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"speed": 0.0}, "expected a positive finite speed"),
        ({"speed": math.nan}, "expected a positive finite speed"),
        ({"speed": 1.0, "drift": math.radians(90)}, r"drift angle = 90°: expected \|angle\| < 90°"),
        ({"speed": 1.0, "attack": math.radians(-95)}, r"attack angle = -95°"),
        ({"speed": 1.0, "axis": "w"}, "expected x, y or z"),
        ({"speed": 1.0, "axis": "y", "drift": 0.1}, "takes no drift"),
    ],
)
def test_a_flow_no_tow_tank_can_run_is_refused(kw, match):
    with pytest.raises(InputError, match=match):
        Flow(**kw)


def test_settings_refuse_unknown_models_and_grids_and_choose_laminar_below_2000():
    s = Settings()
    assert s.model(1999.0) == "laminar" and s.model(2000.0) == "kOmegaSST"
    assert Settings(turbulence="kEpsilon").model(10.0) == "kEpsilon"
    with pytest.raises(InputError, match="expected auto, laminar, kOmegaSST or kEpsilon"):
        Settings(turbulence="LES")
    with pytest.raises(InputError, match="expected 1, 2 or 3"):
        Settings(grid=4)
    with pytest.raises(InputError, match="viscosity = -1"):
        Settings(viscosity=-1.0)


def test_the_cache_key_changes_with_every_input_that_changes_the_result():
    body = profile_body(*_spheroid())
    base = Case(body, Flow(1.0), Settings())
    assert base.key() == Case(body, Flow(1.0), Settings(timeout=5.0)).key()  # the timeout changes nothing
    others = [
        Case(body, Flow(1.1), Settings()),
        Case(body, Flow(1.0, drift=0.1), Settings()),
        Case(body, Flow(1.0), Settings(grid=2)),
        Case(body, Flow(1.0), Settings(density=1000.0)),
        Case(profile_body(*_spheroid(b=0.11)), Flow(1.0), Settings()),
        Case(body, Flow(1.0), Settings(y_plus=50.0)),
    ]
    assert len({c.key() for c in others} | {base.key()}) == 7
    assert base.path == "wedge" and others[1].path == "3d"
    # the path taken is what counts: auto going 3-D is the 3-D case, forcing 3-D is another case
    assert others[1].key() == Case(body, Flow(1.0, drift=0.1), Settings(path="3d")).key()
    assert base.key() != Case(body, Flow(1.0), Settings(path="3d")).key()


def test_profile_refusals_name_the_row_and_value():
    x, r = _spheroid()
    check_profile(x, r)
    bad = r.copy()
    bad[7] = -0.01
    with pytest.raises(InputError, match=r"column 'r' = -0.01 m at row 8: expected a radius r >= 0"):
        check_profile(x, bad)
    open_tail = r.copy()
    open_tail[-1] = 0.05
    with pytest.raises(InputError, match="expected a closed body"):
        check_profile(x, open_tail)
    back = x.copy()
    back[5] = back[4]
    with pytest.raises(InputError, match="at row 6: expected x increasing"):
        check_profile(back, r)
    with pytest.raises(InputError, match="expected at least 5 points"):
        check_profile(x[:3], r[:3])


def test_a_revolved_profile_is_a_closed_outward_surface_of_the_right_volume_and_shadow():
    x, r = _spheroid(0.5, 0.1, 121)
    tri = revolve(np.column_stack([x, r]), segments=96)
    mesh = SurfaceMesh(tri.reshape(-1, 3), np.arange(tri.shape[0] * 3).reshape(-1, 3))
    check_mesh(mesh)  # closed (after merging coincident vertices) and outward
    # prolate spheroid: V = 4/3 π a b²; frontal shadow π b², side shadow π a b
    assert mesh.volume() == pytest.approx(4 / 3 * math.pi * 0.5 * 0.01, rel=2e-3)
    assert projected_area(tri, 0) == pytest.approx(math.pi * 0.01, rel=0.01)
    assert projected_area(tri, 2) == pytest.approx(math.pi * 0.5 * 0.1, rel=0.01)
    body = profile_body(x, r)
    assert body.length == pytest.approx(1.0) and body.area == pytest.approx(math.pi * 0.01)


def test_a_geometry_file_becomes_one_surface_per_part_in_the_common_frame():
    from hydrokit.api import load_geometry
    from hydrokit.data import geometry_file

    geo = load_geometry(geometry_file("sphere"))
    body = geometry_body(geo)
    assert len(body.surfaces()) == len(geo.parts) == 1
    d = 0.5  # the bundled sphere: 0.5 m diameter
    assert body.length == pytest.approx(d, rel=1e-3)
    assert body.area == pytest.approx(math.pi * d * d / 4, rel=0.015)
    t = box(2.0, 1.0, 0.5)
    m = SurfaceMesh(t.reshape(-1, 3), np.arange(36).reshape(-1, 3))
    check_mesh(m)
    assert m.volume() == pytest.approx(1.0)


def test_derivatives_recover_known_coefficients_and_their_weighted_standard_errors():
    rng = np.random.default_rng(3)
    U, rho, L = 1.5, 1025.0, 1.2
    beta = np.radians([-12, -8, -4, 0, 4, 8, 12])
    u, v = U * np.cos(beta), U * np.sin(beta)
    nu = np.zeros((len(beta), 6))
    nu[:, 0], nu[:, 1] = u, v
    Y_uv, Y_vv = -40.0, -150.0
    sd = np.full(len(beta), 0.2)
    Y = Y_uv * u * v + Y_vv * v * np.abs(v) + rng.normal(0, 0.2, len(beta))
    loads = np.zeros_like(nu)
    loads[:, 1] = Y
    sigma = np.zeros_like(nu)
    sigma[:, 1] = sd
    d = {x.name: x for x in fit_derivatives(nu, loads, sigma, {"Y": ["uv", "v|v|"]}, density=rho, length=L)}
    # second method: scipy's curve_fit with the same σ
    popt, pcov = curve_fit(lambda X, a, b: a * X[0] * X[1] + b * X[1] * np.abs(X[1]), (u, v), Y, sigma=sd)
    # curve_fit iterates to its own tolerance (~1e-8): 1e-6 is tight against a wrong weighting
    assert d["Y_uv"].value == pytest.approx(popt[0], rel=1e-6)
    assert d["Y_v|v|"].value == pytest.approx(popt[1], rel=1e-6)
    # curve_fit scales by the residual variance; hydrokit takes the larger of that and σ as given
    s2 = max(1.0, float(np.sum(((Y - (popt[0] * u * v + popt[1] * v * np.abs(v))) / sd) ** 2)) / 5)
    ref = np.sqrt(np.diag(pcov) / (np.sum(((Y - (popt[0] * u * v + popt[1] * v * np.abs(v))) / sd) ** 2) / 5) * s2)
    assert d["Y_uv"].se == pytest.approx(ref[0], rel=1e-5)
    assert d["Y_uv"].k == 2 and d["Y_uv"].nondimensional == pytest.approx(d["Y_uv"].value / (0.5 * rho * L**2))
    name, Yv, *_ = linear_at(d["Y_uv"], U, rho, L)
    assert name == "Y_v" and Yv == pytest.approx(d["Y_uv"].value * U)


def test_a_moment_of_a_rate_scales_with_a_higher_power_of_length():
    nu = np.zeros((4, 6))
    nu[:, 0] = 1.0
    nu[:, 5] = [-0.2, -0.1, 0.1, 0.2]
    loads = np.zeros_like(nu)
    loads[:, 5] = -7.0 * nu[:, 0] * nu[:, 5]
    d = fit_derivatives(nu, loads, np.zeros_like(nu), {"N": ["ur"]}, density=1000.0, length=2.0)
    assert d[0].name == "N_ur" and d[0].value == pytest.approx(-7.0)
    assert d[0].k == 4 and d[0].nondimensional == pytest.approx(-7.0 / (0.5 * 1000 * 2.0**4))


def test_weighted_force_fit_matches_curve_fit_with_sigma():
    U = np.array([0.5, 1.0, 1.5, 2.0, 2.5])
    F = 2.0 * U + 30.0 * U * U + np.array([0.05, -0.2, 0.3, -0.6, 1.0])
    sd = np.array([0.05, 0.1, 0.2, 0.4, 0.8])
    fit = fit_forces(U, F, area=0.1, density=1000.0, sigma=sd)
    popt, _ = curve_fit(lambda u, a, b: a * u + b * u * np.abs(u), U, F, sigma=sd)
    assert [fit.K_L, fit.K_Q] == pytest.approx(list(popt), rel=1e-9)
    plain = fit_forces(U, F, area=0.1, density=1000.0)
    assert plain.K_L != pytest.approx(fit.K_L, rel=1e-3)  # the weights matter
    with pytest.raises(InputError, match="expected standard deviations >= 0"):
        fit_forces(U, F, 0.1, 1000.0, sigma=-sd)


def _outcome(case: Case, X: float, Y: float = 0.0, N: float = 0.0, status: str = "converged") -> dict:
    from dataclasses import asdict

    return {
        "label": case.label,
        "status": status,
        "flow": asdict(case.flow),
        "settings": asdict(case.settings),
        "forces": [X, Y, 0.0, 0.0, 0.0, N],
        "std": [0.01] * 6,
    }


def test_a_sweep_is_assembled_into_rows_fits_and_derivatives():
    body = profile_body(*_spheroid())
    spec = SweepSpec((0.5, 1.0, 1.5, 2.0), drifts=tuple(np.radians([-6, 6])))
    cases = make_cases(body, spec, Settings())
    # 4 speeds + 2 drift angles at the reference speed 2.0 (the straight 2.0 case is shared)
    assert len(cases) == 6
    # one mesh family for the whole sweep: a wedge at β = 0 beside 3-D angles would bias X_vv
    assert {c.path for c in cases} == {"3d"}
    assert {c.path for c in make_cases(body, SweepSpec((0.5, 1.0, 1.5)), Settings())} == {"wedge"}
    K_Q, Y_uv, N_uv = 20.0, -30.0, -12.0
    outs = []
    for c in cases:
        u, v, _ = c.flow.velocity()
        outs.append(_outcome(c, -K_Q * u * u, Y_uv * u * v, N_uv * u * v))
    res = assemble(body, spec, Settings(), outs)
    assert res.fits["x"].K_Q == pytest.approx(K_Q, rel=1e-6) and abs(res.fits["x"].K_L) < 1e-6
    names = {d.name: d.value for d in res.derivatives}
    assert names["Y_uv"] == pytest.approx(Y_uv, rel=1e-6) and names["N_uv"] == pytest.approx(N_uv, rel=1e-6)
    coef = res.coefficients()
    assert coef["terms"]["X_u|u|"] == pytest.approx(-K_Q, rel=1e-6)  # resistance opposes u
    assert coef["linear_derivatives"]["Y_v"]["value"] == pytest.approx(Y_uv * 2.0, rel=1e-6)
    head = res.forces_csv().splitlines()[0]
    assert head.startswith("case,speed,drift_deg,attack_deg,yaw_rate,pitch_rate,X,Y,Z,K,M,N,X_std")
    assert res.resistance_csv().splitlines()[0] == "speed,force,force_std"


def test_a_failed_case_leaves_its_row_empty_and_the_others_are_fitted():
    body = profile_body(*_spheroid())
    spec = SweepSpec((0.5, 1.0, 1.5, 2.0))
    cases = make_cases(body, spec, Settings())
    outs = [_outcome(c, -10 * c.flow.speed**2) for c in cases]
    outs[1] = {**outs[1], "status": "failed", "reason": "simpleFoam failed (exit 1): diverged"}
    res = assemble(body, spec, Settings(), outs)
    assert len(res.failed) == 1 and any("diverged" in w for w in res.warnings)
    row = [r for r in res.rows if r["status"] == "failed"][0]
    assert math.isnan(row["X"])
    assert res.fits["x"].n == 3 and res.fits["x"].K_Q == pytest.approx(10.0, rel=1e-6)
    assert ",failed" in res.forces_csv()


def test_a_3d_grid_study_whose_levels_carry_different_layer_stacks_says_so():
    from hydrokit.cfd.mesh3d import layer_plan

    body = _myring_3d(50.0).body
    spec = SweepSpec((0.5, 1.0, 1.5), grids=3)
    base = Settings(density=1000.0, viscosity=1e-6, turbulence="kOmegaSST", path="3d", surface_level=4)
    cases = make_cases(body, spec, base)
    # the stack laid for y⁺ 50 fits in fewer layers as the surface cells shrink by √2 per grid
    layers: dict[float, dict[int, int]] = {}
    for c in cases:
        n = layer_plan(replace(c, settings=replace(c.settings, y_plus=50.0)))[0]
        layers.setdefault(c.flow.speed, {})[c.settings.grid] = n
    assert all(by_grid[1] > by_grid[3] for by_grid in layers.values())
    for y_plus, expected in ((50.0, True), (0.0, False)):
        outs = []
        for c in cases:
            c = replace(c, settings=replace(c.settings, y_plus=y_plus))
            o = _outcome(c, -10 * c.flow.speed**2 * (1 + 0.01 / c.settings.grid))
            o["prism_layers"] = layer_plan(c)[0]
            outs.append(o)
        res = assemble(body, spec, base, outs)
        said = [w for w in res.warnings if "prism layers" in w]
        assert bool(said) is expected
        if expected:  # one line per flow, naming its own three stacks
            assert len(said) == 3
            for speed, n in layers.items():
                assert any(w.startswith(f"U{speed:g}_") and f"{n[1]} / {n[2]} / {n[3]} prism layers" in w for w in said)


def test_the_bundled_bodies_are_the_shapes_their_files_describe():
    from hydrokit.api import load_cfd_body

    myring = load_cfd_body("myring")
    x, r = myring.profile[:, 0], myring.profile[:, 1]
    a, b, c, d, theta = 0.191, 0.654, 0.541, 0.191, math.radians(25)
    assert myring.length == pytest.approx(a + b + c, abs=1e-6)
    # Myring (1976), n = 2: nose ellipse, parallel middle, cubic tail closing with slope tan θ
    s = x[x > a + b] - a - b
    tail = d / 2 - (3 * d / (2 * c * c) - math.tan(theta) / c) * s**2 + (d / c**3 - math.tan(theta) / c**2) * s**3
    assert r[x > a + b] == pytest.approx(np.maximum(tail, 0.0), abs=2e-6)
    nose = x <= a
    assert r[nose] == pytest.approx(d / 2 * np.sqrt(np.clip(1 - ((x[nose] - a) / a) ** 2, 0, None)), abs=2e-6)
    assert myring.area == pytest.approx(math.pi * (d / 2) ** 2, rel=1e-6)
    lingyun = load_cfd_body("lingyun")  # LI2021's L × B × H block
    assert lingyun.length == pytest.approx(1.25) and lingyun.area == pytest.approx(0.47 * 0.93, rel=0.01)
    with pytest.raises(InputError, match="bundled: lingyun, myring"):
        load_cfd_body("remus")


def test_a_slender_body_is_refined_until_its_diameter_is_resolved_like_a_spheres():
    from hydrokit.api import load_cfd_body
    from hydrokit.cfd.mesh3d import surface_level
    from hydrokit.estimate.bem import shape_mesh

    m = shape_mesh("sphere", 24, diameter=1.0)
    from hydrokit.cfd.body import mesh_body

    sphere = Case(mesh_body(m.vertices[m.triangles()], "s"), Flow(1.0), Settings(surface_level=4))
    myring = Case(load_cfd_body("myring"), Flow(1.0, drift=0.1), Settings(surface_level=4))
    assert surface_level(sphere) == 4
    # L/d = 1.386/0.191 = 7.26: round(log2) = 3 more halvings, so the surface cell is a 32nd of d
    assert surface_level(myring) == 7


def test_the_progress_reader_finds_running_cases_and_their_iteration(tmp_path):
    from hydrokit.cfd.case import foam_file
    from hydrokit.cfd.run import running_iterations

    run = tmp_path / "run-abc123"
    foam_file(run / "system" / "controlDict", {"application": "simpleFoam", "endTime": 1500})
    dat = run / "postProcessing" / "forces" / "0" / "force.dat"
    dat.parent.mkdir(parents=True)
    dat.write_text("# Force\n# Time (total)\n1\t(-1 0 0)\n2\t(-1 0 0)\n37\t(-1 0 0)\n38\t(-1 0")
    (tmp_path / "run-def456").mkdir()  # just made: nothing written yet
    assert running_iterations(tmp_path) == {"abc123": (38, 1500), "def456": (0, 0)}


def test_stop_now_rewrites_only_stop_at_and_the_field_files_parse_back(tmp_path):
    import foamlib

    from hydrokit.cfd.case import write_case
    from hydrokit.cfd.foam import stop_now

    case = Case(mesh_body(box(1.0, 0.5, 0.4), "b"), Flow(1.0), Settings())
    write_case(case, tmp_path, {})
    before = foamlib.FoamFile.loads((tmp_path / "system" / "controlDict").read_bytes())
    stop_now(tmp_path)
    after = foamlib.FoamFile.loads((tmp_path / "system" / "controlDict").read_bytes(), include_header=True)
    assert after["stopAt"] == "writeNow" and before["stopAt"] != "writeNow"
    assert {k: v for k, v in after.items() if k not in ("stopAt", "FoamFile")} == {
        k: v for k, v in before.items() if k != "stopAt"
    }
    assert after["FoamFile"]["object"] == "controlDict"
    assert not list((tmp_path / "system").glob(".*tmp"))
    u = foamlib.FoamFile.loads((tmp_path / "0" / "U").read_bytes(), include_header=True)
    assert u["FoamFile"]["class"] == "volVectorField"
    assert list(u["internalField"]) == pytest.approx([-1.0, 0.0, 0.0])  # the body moves +x: water comes at it
    assert "farfield" in u["boundaryField"]


def test_capture_bands_refine_every_cell_the_body_touches_down_to_the_surface_level():
    from hydrokit.cfd.mesh3d import capture_bands

    h = 0.7
    bands = capture_bands(h, 3)
    assert [b[1] for b in bands] == [3, 2, 1]  # finest first, as snappyHexMesh reads them
    for dist, k in bands:
        # a level-(k−1) cell touched by the body has its centre within √3/2 of its size of the
        # surface: the band of level k must reach that far
        assert dist >= math.sqrt(3) / 2 * h / 2 ** (k - 1)
        assert dist <= 2.0 * h / 2**k * 1.0001  # and no further than two cells of its level
    from hydrokit.api import load_cfd_body
    from hydrokit.cfd.mesh3d import mesh_dicts, surface_level

    case = Case(load_cfd_body("myring"), Flow(1.0), Settings())

    regions = mesh_dicts(case)["snappyHexMeshDict"]["castellatedMeshControls"]["refinementRegions"]
    assert regions["body"] == {"mode": "distance", "levels": capture_bands(case.body.length / 2, surface_level(case))}


def test_openfoam_runs_without_the_malloc_trim_setting_of_dask_workers(monkeypatch, tmp_path):
    # Dask's nanny exports MALLOC_TRIM_THRESHOLD_=65536; under it simpleFoam ran at half speed
    from hydrokit.cfd.foam import OpenFOAM

    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")
    monkeypatch.setenv("FOAM_SIGFPE", "1")
    monkeypatch.setenv("HYDROKIT_PROBE", "kept")
    env = OpenFOAM(tmp_path / "bin", tmp_path).env()
    assert "MALLOC_TRIM_THRESHOLD_" not in env and "FOAM_SIGFPE" not in env
    assert env["HYDROKIT_PROBE"] == "kept" and env["WM_PROJECT_DIR"] == str(tmp_path)


def test_a_laminar_case_keeps_the_key_it_had_before_y_plus_the_inflow_and_end_level_existed():
    # cached laminar sweeps stay valid: the key is the hash of the inputs it had before;
    # a turbulent case's key holds the inflow turbulence (its default changed: such cases rerun)
    import hashlib
    import json
    from dataclasses import asdict

    from hydrokit.cfd.case import CASE_FORMAT

    new = (
        "timeout",
        "processes",
        "y_plus",
        "inflow_intensity",
        "inflow_viscosity_ratio",
        "end_level",
        "turbulence_order",
    )
    body = profile_body(*_spheroid())
    case = Case(body, Flow(1.2, drift=0.05), Settings(density=1000.0, turbulence="laminar"))
    old = {k: v for k, v in asdict(case.settings).items() if k not in new}
    old["path"] = "3d"
    data = {"format": CASE_FORMAT, "body": case.body.digest(), "flow": asdict(case.flow), "settings": old}
    assert case.key() == hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]
    laminar = Settings(turbulence="laminar", inflow_intensity=0.05)
    assert Case(body, Flow(1.0), laminar).key() == Case(body, Flow(1.0), Settings(turbulence="laminar")).key()
    turbulent = [
        Settings(turbulence="kOmegaSST", **kw)
        for kw in ({}, {"inflow_intensity": 0.005}, {"inflow_viscosity_ratio": 1.0})
    ]
    assert len({Case(body, Flow(1.0), t).key() for t in turbulent}) == 3


def test_the_inflow_turbulence_follows_its_settings():
    from hydrokit.cfd.case import inflow

    body = profile_body(*_spheroid())
    s = Settings(viscosity=1e-6, inflow_intensity=0.02, inflow_viscosity_ratio=5.0)
    t = inflow(Case(body, Flow(2.0), s))
    k = 1.5 * (0.02 * 2.0) ** 2  # k = 3/2 (I U)², ν_t = 5 ν = k/ω = 0.09 k²/ε
    assert t["k"] == pytest.approx(k) and t["omega"] == pytest.approx(k / 5e-6)
    assert t["epsilon"] == pytest.approx(0.09 * k * k / 5e-6)
    default = inflow(Case(body, Flow(1.0), Settings(viscosity=1e-6)))
    assert default["k"] == pytest.approx(1.5e-4) and default["omega"] == pytest.approx(15.0)  # 1 %, ν_t/ν 10
    for bad in ({"inflow_intensity": 0.0}, {"inflow_intensity": 0.8}, {"inflow_viscosity_ratio": float("inf")}):
        with pytest.raises(InputError, match=f"{next(iter(bad))} = .*: expected a number above 0"):
            Settings(**bad)


@pytest.mark.parametrize("bad", [-1.0, float("nan"), 1e4, True, "50"])
def test_a_target_y_plus_outside_0_to_1000_is_refused(bad):
    with pytest.raises(InputError, match=r"y_plus = .*: expected 0 \(each path's default\) or a target y⁺"):
        Settings(y_plus=bad)


def _myring_3d(y_plus: float, re: float = 1e6, **kw) -> Case:
    from hydrokit.api import load_cfd_body

    body = load_cfd_body("myring")
    s = Settings(density=1000.0, viscosity=1e-6, turbulence="kOmegaSST", path="3d", y_plus=y_plus, **kw)
    return Case(body, Flow(re * 1e-6 / body.length), s)


def _layers(case: Case) -> dict:
    from hydrokit.cfd.mesh3d import mesh_dicts

    return mesh_dicts(case)["snappyHexMeshDict"]["addLayersControls"]


def test_layers_laid_from_a_target_y_plus_span_the_turbulent_boundary_layer():
    # first layer: Δy = y⁺ ν / u_τ, u_τ = U √(C_f/2), C_f = 0.026 Re^(-1/7) (White eq. 7.45);
    # layers growing by 1.2 until they reach δ = 0.37 L Re^(-1/5) at the tail (White eq. 7.41),
    # on surface cells coarse enough (level 1 + 3: 43 mm) to hold the whole stack
    case = _myring_3d(50.0, surface_level=1, layers=3)
    U, nu, L = case.flow.speed, 1e-6, case.body.length
    dy = 50.0 * nu / (U * math.sqrt(0.026 * 1e6 ** (-1 / 7) / 2))
    delta = 0.37 * L * 1e6**-0.2
    c = _layers(case)
    assert c["relativeSizes"] is False and "finalLayerThickness" not in c
    assert c["firstLayerThickness"] == pytest.approx(dy, rel=1e-9)
    assert c["minThickness"] == pytest.approx(0.1 * dy) and c["expansionRatio"] == 1.2
    n = c["layers"]['"body.*"']["nSurfaceLayers"]
    total = lambda k: dy * (1.2**k - 1) / 0.2  # noqa: E731 -- k layers growing by 1.2
    assert total(n - 1) < delta <= total(n)
    assert n == 9  # 50 at Re 1e6 on the bundled Myring: Δy 1.63 mm, δ 32.4 mm


def test_prism_layers_from_a_target_y_plus_fit_together_in_two_surface_cells():
    # nine layers (34 mm) in the 11 mm cells of surface level 3 stayed off the Myring's aft 13 %;
    # one cell's worth (four layers at level 3, one at level 5) left the friction 3–16 % low
    from hydrokit.cfd.mesh3d import cell_size, surface_level

    for level, expected in ((3, 7), (4, 4), (5, 2)):
        case = _myring_3d(50.0, surface_level=level, layers=3)
        c = _layers(case)
        n, dy = c["layers"]['"body.*"']["nSurfaceLayers"], c["firstLayerThickness"]
        cell = cell_size(case) / 2 ** surface_level(case)
        total = lambda k, dy=dy: dy * (1.2**k - 1) / 0.2  # noqa: E731 -- k layers growing by 1.2
        assert total(n) <= 2 * cell < total(n + 1)
        # level 3: 21.0 mm of layers in 2 × 10.8 mm (eight: 26.9 mm); level 4: 8.7 in 2 × 5.4 mm
        assert n == expected


def test_layers_from_a_small_y_plus_stop_at_20_or_two_surface_cells_and_default_stays_relative():
    from hydrokit.cfd.mesh3d import cell_size, surface_level

    fine = _layers(_myring_3d(1.0, surface_level=3))
    assert fine["layers"]['"body.*"']["nSurfaceLayers"] == 20  # y⁺ 1 would need 29 to reach δ
    for y_plus, level in ((30.0, 3), (300.0, 3), (100.0, 1)):
        case = _myring_3d(y_plus, surface_level=level)
        c = _layers(case)
        n = c["layers"]['"body.*"']["nSurfaceLayers"]
        surface_cell = cell_size(case) / 2 ** surface_level(case)
        stack = c["firstLayerThickness"] * (1.2**n - 1) / 0.2
        assert n >= 1 and stack <= max(2 * surface_cell, c["firstLayerThickness"])
    default = _layers(_myring_3d(0.0, layers=4))
    assert default["relativeSizes"] is True and default["finalLayerThickness"] == 0.5
    assert default["layers"]['"body.*"']["nSurfaceLayers"] == 4 and "firstLayerThickness" not in default


def test_the_ends_are_the_triangles_in_the_fore_and_aft_tenth_and_refined_end_level_more():
    from hydrokit.cfd.mesh3d import cell_size, end_triangles, estimate_cells, mesh_dicts, surface_level

    case = _myring_3d(50.0, surface_level=3, end_level=2)
    tri = np.concatenate(case.body.surfaces())
    x = tri[:, :, 0].mean(axis=1)
    lo, hi = x.min(), x.max()
    ends = end_triangles(case)
    ex = ends[:, :, 0].mean(axis=1)
    L = case.body.length  # the profile's bounding box: its length along x
    nose, tail = ex > hi - 0.2 * L, ex < lo + 0.2 * L
    assert nose.any() and tail.any() and (nose | tail).all()
    assert ex[nose].min() >= case.body.bounds()[1][0] - 0.1 * L and ex[tail].max() <= case.body.bounds()[0][0] + 0.1 * L
    inner = (x > case.body.bounds()[0][0] + 0.1 * L) & (x < case.body.bounds()[1][0] - 0.1 * L)
    assert len(ends) == len(tri) - inner.sum()  # every triangle is either an end or mid-body
    snappy = mesh_dicts(case)["snappyHexMeshDict"]
    geo, regions = snappy["geometry"], snappy["castellatedMeshControls"]["refinementRegions"]
    assert geo["ends.stl"] == {"type": "triSurfaceMesh", "name": "ends"}
    h, lvl = cell_size(case), surface_level(case)
    # level k within one level-(k−1) cell of the ends, as the capture bands around the body
    assert regions["ends"] == {
        "mode": "distance",
        "levels": [[2 * h / 2 ** (lvl + 2), lvl + 2], [2 * h / 2 ** (lvl + 1), lvl + 1]],
    }
    assert "ends" not in snappy["castellatedMeshControls"]["refinementSurfaces"]  # no wall patch of its own
    plain = _myring_3d(50.0, surface_level=3)
    plain_snappy = mesh_dicts(plain)["snappyHexMeshDict"]
    assert (
        "ends.stl" not in plain_snappy["geometry"]
        and "ends" not in plain_snappy["castellatedMeshControls"]["refinementRegions"]
    )
    assert estimate_cells(plain) < estimate_cells(_myring_3d(50.0, surface_level=3, end_level=1)) < estimate_cells(case)


@pytest.mark.parametrize("bad", [-1, 4, 1.0, True])
def test_an_end_level_outside_0_to_3_is_refused(bad):
    with pytest.raises(InputError, match=r"end_level = .*: expected a whole number from 0 to 3"):
        Settings(end_level=bad)


def test_end_level_changes_the_key_of_a_3d_case_only():
    three_d = _myring_3d(0.0)
    wedge = Case(three_d.body, three_d.flow, Settings(viscosity=1e-6, turbulence="kOmegaSST"))
    assert wedge.path == "wedge"
    with_ends = lambda c: Case(c.body, c.flow, Settings(**{**c.settings.__dict__, "end_level": 1}))  # noqa: E731
    assert with_ends(three_d).key() != three_d.key()
    assert with_ends(wedge).key() == wedge.key()
    # the layer stack laid from a target y⁺ changed: those 3-D cases are redone, the wedge's kept
    import hashlib
    import json
    from dataclasses import asdict

    from hydrokit.cfd.case import CASE_FORMAT

    def before(case: Case) -> str:  # the key as it was computed until the layer stack was capped
        skip = ("timeout", "processes", "end_level", "turbulence_order")
        settings = {k: v for k, v in asdict(case.settings).items() if k not in skip}
        data = {"format": CASE_FORMAT, "body": case.body.digest(), "flow": asdict(case.flow)}
        data["settings"] = {**settings, "path": case.path}
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]

    y50 = _myring_3d(50.0)
    wedge50 = Case(y50.body, y50.flow, Settings(**{**y50.settings.__dict__, "path": "auto"}))
    assert y50.key() != before(y50) and wedge50.key() == before(wedge50)


def test_the_wedge_lays_its_first_cell_for_the_target_y_plus(monkeypatch):
    from hydrokit.cfd import run, wedge

    seen = []
    real = wedge.blockmesh_dict
    held = []
    monkeypatch.setattr(
        wedge,
        "blockmesh_dict",
        lambda *a, **kw: seen.append(kw["first_cell"]) or held.append(kw["hold_first_cell"]) or real(*a, **kw),
    )
    for y_plus in (0.0, 1.0, 30.0):
        case = _myring_3d(y_plus)
        case = Case(case.body, case.flow, Settings(**{**case.settings.__dict__, "path": "auto"}))
        assert case.path == "wedge"
        run._mesh_dicts(case)
    U, nu = 1e6 * 1e-6 / case.body.length, 1e-6
    u_tau = U * math.sqrt(0.026 * 1e6 ** (-1 / 7) / 2)
    # default: y⁺ 1 but at most a twentieth of the laminar layer (0.25 L/√Re = 0.35 mm here)
    assert seen[0] == pytest.approx(min(nu / u_tau, 0.25 * case.body.length / 1e3))
    assert seen[1] == pytest.approx(nu / u_tau) and seen[2] == pytest.approx(30 * nu / u_tau)
    # an asked-for y⁺ is held on the finer grid levels; the default one refines with the grid
    assert held == [False, True, True]


def test_a_held_first_cell_changes_the_key_of_finer_wedge_levels_only():
    base = _myring_3d(50.0)
    at = lambda grid, y_plus: Case(  # noqa: E731
        base.body, base.flow, Settings(**{**base.settings.__dict__, "path": "auto", "grid": grid, "y_plus": y_plus})
    )
    import hashlib
    import json
    from dataclasses import asdict

    from hydrokit.cfd.case import CASE_FORMAT

    def before(case: Case) -> str:  # the key as it was computed until the first cell was held
        skip = ("timeout", "processes", "end_level", "turbulence_order")
        settings = {k: v for k, v in asdict(case.settings).items() if k not in skip}
        settings = {k: v for k, v in settings.items() if not (k == "y_plus" and v == 0)}
        data = {"format": CASE_FORMAT, "body": case.body.digest(), "flow": asdict(case.flow)}
        data["settings"] = {**settings, "path": case.path}
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]

    assert at(1, 50.0).path == "wedge"
    # level 1 is the same mesh, and the default y⁺ still refines with the grid: their keys stay
    assert at(1, 50.0).key() == before(at(1, 50.0))
    assert at(2, 0.0).key() == before(at(2, 0.0)) and at(3, 0.0).key() == before(at(3, 0.0))
    # finer levels at an asked-for y⁺ have a new mesh: computed anew
    assert at(2, 50.0).key() != before(at(2, 50.0)) and at(3, 50.0).key() != before(at(3, 50.0))


def test_the_cli_options_reach_the_settings_in_si():
    import click

    from hydrokit.cli._cfd_options import _OPTIONS, sweep_inputs

    opts = {}
    for flags, kw in _OPTIONS:
        name = flags[-1] if not flags[-1].startswith("--") else flags[0][2:].replace("-", "_")
        default = kw.get("default")
        opts[name] = (
            kw["type"].convert(default, None, None)
            if isinstance(kw.get("type"), click.ParamType) and default is not None
            else default
        )
    # the CLI's defaults are the library's (written twice: the CLI does not import numpy to start)
    defaults, _ = sweep_inputs(dict(opts))
    lib = Settings()
    for name in ("density", "viscosity", "turbulence", "y_plus", "inflow_intensity", "inflow_viscosity_ratio"):
        assert getattr(defaults, name) == getattr(lib, name), name
    opts |= {"y_plus": 40.0, "drift": [5.0], "surface_level": 3, "inflow_intensity": 0.02}
    settings, spec = sweep_inputs(opts)
    assert settings.y_plus == 40.0 and settings.surface_level == 3
    assert settings.inflow_intensity == 0.02 and settings.inflow_viscosity_ratio == 10.0
    assert settings.base_cells == 2 and settings.max_iterations == 1500 and settings.density == 1025.0
    assert settings.timeout == 3600.0 and settings.processes == 1 and settings.turbulence == "auto"
    assert spec.speeds == (0.5, 1.0, 1.5, 2.0) and spec.axes == ("x",) and spec.grids == 1
    assert spec.drifts == pytest.approx((math.radians(5.0),))
    assert Settings().y_plus == 0.0  # the default: each path its own wall resolution


@pytest.mark.parametrize("bad", [0, 3, 2.0, True])
def test_a_turbulence_order_other_than_1_or_2_is_refused(bad):
    with pytest.raises(InputError, match=r"turbulence_order = .*: expected a whole number from 1 to 2"):
        Settings(turbulence_order=bad)


def test_turbulence_order_2_changes_the_key_of_a_turbulent_case_only():
    # order 1 (the default) keeps every key computed before the setting existed (the key tests
    # above); order 2 is another answer for a turbulent case and none for a laminar one
    turbulent = _myring_3d(0.0)
    second = Case(turbulent.body, turbulent.flow, replace(turbulent.settings, turbulence_order=2))
    assert second.key() != turbulent.key()
    laminar = Settings(turbulence="laminar")
    assert (
        Case(turbulent.body, turbulent.flow, replace(laminar, turbulence_order=2)).key()
        == Case(turbulent.body, turbulent.flow, laminar).key()
    )


def test_the_second_stage_continues_with_second_order_k_and_omega(tmp_path):
    from hydrokit.cfd.case import _schemes, foamlib, write_second_stage

    FoamFile = foamlib().FoamFile  # noqa: N806 -- foamlib's class
    first = _schemes("kOmegaSST")
    assert first["divSchemes"]["div(phi,k)"] == ("bounded", "Gauss", "upwind")
    assert first["divSchemes"]["div(phi,omega)"] == ("bounded", "Gauss", "upwind")
    assert "limitedGrad" not in first["gradSchemes"]
    case = Case(_myring_3d(0.0).body, _myring_3d(0.0).flow, Settings(turbulence="kOmegaSST", max_iterations=700))
    (tmp_path / "system").mkdir()
    write_second_stage(case, tmp_path, 365)
    schemes = FoamFile(tmp_path / "system" / "fvSchemes")
    for q in ("k", "omega", "epsilon"):
        assert list(schemes["divSchemes"][f"div(phi,{q})"]) == ["bounded", "Gauss", "linearUpwind", "limitedGrad"]
    assert list(schemes["gradSchemes"]["limitedGrad"]) == ["cellLimited", "Gauss", "linear", 1]
    # the velocity's own scheme is the first stage's: only the turbulence changes order
    assert list(schemes["divSchemes"]["div(phi,U)"]) == list(first["divSchemes"]["div(phi,U)"])
    control = FoamFile(tmp_path / "system" / "controlDict")
    assert control["startFrom"] == "latestTime" and control["stopAt"] == "endTime"
    assert control["endTime"] == 365 + 700 and control["writeInterval"] == 365 + 700
    assert "forces" in control["functions"]


def test_a_turbulent_grid_study_that_does_not_converge_points_to_second_order_turbulence():
    body = profile_body(*_spheroid())
    spec = SweepSpec((0.5, 1.0, 1.5), grids=3)
    # each finer grid moves the drag further (the Myring wedge's first-order triplets): "diverging"
    drop = {1: 1.000, 2: 0.996, 3: 0.990}
    for model, order, expected in (("kOmegaSST", 1, True), ("kOmegaSST", 2, False), ("laminar", 1, False)):
        base = Settings(turbulence=model, turbulence_order=order)
        outs = []
        for c in make_cases(body, spec, base):
            o = _outcome(c, -10 * c.flow.speed**2 * drop[c.settings.grid])
            o["model"] = c.model
            outs.append(o)
        res = assemble(body, spec, base, outs)
        assert all(r["X_convergence"] == "diverging" for r in res.rows)
        said = [w for w in res.warnings if "--turbulence-order 2" in w]
        assert len(said) == (3 if expected else 0), (model, order, said)


def _triplet(fine_to_coarse: dict[str, tuple[float, float, float]]) -> tuple[list, list]:
    """Outcomes of a Myring-like wedge triplet (one speed) whose resistance has the given
    pressure and viscous parts (N) on grids 3, 2, 1."""
    body = profile_body(*_spheroid())
    spec = SweepSpec((1.0,), grids=3)
    base = Settings(turbulence="kOmegaSST", turbulence_order=2)
    outs = []
    for c in make_cases(body, spec, base):
        i = 3 - c.settings.grid
        p, v = fine_to_coarse["pressure"][i], fine_to_coarse["viscous"][i]
        o = _outcome(c, -(p + v))
        o["force_parts"] = {"pressure": [-p, 0.0, 0.0], "viscous": [-v, 0.0, 0.0]}
        outs.append(o)
    return outs, assemble(body, spec, base, outs).rows


def test_a_sum_of_parts_converging_at_their_own_rates_is_studied_part_by_part():
    from hydrokit.cfd.gci import grid_study

    # the Myring wedge at Re_L 1e6, second-order k and ω (bench/cfd.py body, 2026-11-28)
    friction, pressure = (0.7858, 0.7800, 0.7714), (0.0879, 0.0887, 0.0938)
    outs, rows = _triplet({"pressure": pressure, "viscous": friction})
    (row,) = rows
    assert row["X_convergence"] == "diverging"  # 0.8737 / 0.8687 / 0.8652: the steps grow
    assert row["X_parts_convergence"] == "monotonic"
    # each part by Richardson with a constant ratio √2: p = ln(ε32/ε21) / ln √2, GCI = F_s |ε21| / (r^p − 1)
    expected_gci, expected_ext = 0.0, 0.0
    for s1, s2, s3 in (friction, pressure):
        e21, e32 = s2 - s1, s3 - s2
        order = math.log(e32 / e21) / math.log(math.sqrt(2.0))
        fs = 1.25 if abs(order / 2 - 1) <= 0.1 else 3.0
        expected_gci += fs * abs(e21) / (math.sqrt(2.0) ** order - 1)
        expected_ext += s1 - e21 / (math.sqrt(2.0) ** order - 1)
    # SNAME signs: the loads are −(p + v), so the extrapolation is too
    assert row["X_parts_extrapolated"] == pytest.approx(-expected_ext, rel=1e-9)
    assert row["X_parts_gci"] == pytest.approx(expected_gci, rel=1e-9)
    # the friction's slow convergence (p 1.1, F_s 3) makes the parts' GCI the wider here: 4 %
    # against the total's "diverging" 3 max|ε| = 1.7 % — the cancellation hid it
    assert row["X_parts_gci"] > row["X_gci"]
    assert grid_study(*(-f for f in friction), math.sqrt(2.0)).kind == "monotonic"
    res = assemble(profile_body(*_spheroid()), SweepSpec((1.0,), grids=3), Settings(turbulence="kOmegaSST"), outs)
    said = [w for w in res.warnings if "X_parts_gci" in w]
    assert len(said) == 1 and "each converge monotonically" in said[0] and f"{-expected_ext:.6g} N" in said[0]


def test_the_parts_study_is_as_good_as_its_worst_part_and_reaches_forces_csv():
    # friction oscillating over the grids: no extrapolation from the parts, and the kind says so
    outs, rows = _triplet({"pressure": (0.0879, 0.0887, 0.0938), "viscous": (0.780, 0.786, 0.771)})
    (row,) = rows
    assert row["X_parts_convergence"] == "oscillatory" and math.isnan(row["X_parts_extrapolated"])
    # an oscillating part's U is half its range (the pressure part's own GCI is checked above)
    assert row["X_parts_gci"] == pytest.approx(0.5 * (0.786 - 0.771) + _pressure_gci(), rel=1e-9)
    res = assemble(profile_body(*_spheroid()), SweepSpec((1.0,), grids=3), Settings(turbulence="kOmegaSST"), outs)
    head = res.forces_csv().splitlines()[0].split(",")
    assert head[-5:] == ["X_parts_gci", "Y_parts_gci", "Z_parts_gci", "axis", "status"]
    # cases cached before the parts were recorded: no parts columns, no error
    bare = [{k: v for k, v in o.items() if k != "force_parts"} for o in outs]
    res = assemble(profile_body(*_spheroid()), SweepSpec((1.0,), grids=3), Settings(turbulence="kOmegaSST"), bare)
    assert "X_parts_gci" not in res.rows[0] and "X_parts_gci" not in res.forces_csv()


def _pressure_gci() -> float:
    from hydrokit.cfd.gci import grid_study

    return grid_study(0.0879, 0.0887, 0.0938, math.sqrt(2.0)).gci


def test_a_rotating_arm_case_limits_the_absolute_velocitys_gradient_as_straight_flow_does(tmp_path):
    # SRFSimpleFoam solves for Urel but builds its turbulence model on U = Urel + Ω × r: the
    # model's production and wall functions and the forces' viscous stress take grad(U). Left to
    # the unlimited default, the Myring's friction on the arm was 2.8 % under straight flow at
    # every radius down to Ω → 0 (surface level 4, 2026-11-28); limited, +0.01 %
    from hydrokit.cfd.case import foamlib, write_case

    FoamFile = foamlib().FoamFile  # noqa: N806 -- foamlib's class
    straight = _myring_3d(0.0)
    arm = Case(straight.body, Flow(straight.flow.speed, yaw_rate=0.05), straight.settings)
    grads = {}
    for name, case in (("straight", straight), ("arm", arm)):
        write_case(case, tmp_path / name, {})
        grads[name] = FoamFile(tmp_path / name / "system" / "fvSchemes")["gradSchemes"]
    limited = ["cellLimited", "Gauss", "linear", 1]
    assert list(grads["straight"]["grad(U)"]) == limited
    assert list(grads["arm"]["grad(U)"]) == limited  # the turbulence model's, absolute velocity
    assert list(grads["arm"]["grad(Urel)"]) == limited  # the momentum equation's
    assert FoamFile(tmp_path / "arm" / "system" / "controlDict")["application"] == "SRFSimpleFoam"
    # arm cases computed before the fix are redone, straight ones keep their keys
    import hashlib
    import json
    from dataclasses import asdict

    from hydrokit.cfd.case import CASE_FORMAT

    def before(case: Case) -> str:  # the key as it was computed until grad(U) was limited on the arm
        skip = ("timeout", "processes", "y_plus", "end_level", "turbulence_order")
        settings = {k: v for k, v in asdict(case.settings).items() if k not in skip}
        data = {"format": CASE_FORMAT, "body": case.body.digest(), "flow": asdict(case.flow)}
        data["settings"] = {**settings, "path": case.path}
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]

    assert straight.key() == before(straight)
    assert arm.key() != before(arm)
