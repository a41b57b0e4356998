"""Readers that survive any file (issue #13 item 4): random bytes, truncations, wrong types,
NaN/inf, huge numbers, YAML alias bombs and python tags. The only outcomes are a result or one
``InputError`` line — never another exception. Examples are bounded so the suite stays fast
(60 per reader); the longer run sets ``HYDROKIT_FUZZ_EXAMPLES``, e.g.
``HYDROKIT_FUZZ_EXAMPLES=2000 .venv/bin/python -m pytest tests/io/test_fuzz_readers.py``."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError

FUZZ = settings(
    max_examples=int(os.environ.get("HYDROKIT_FUZZ_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)

# values a careless or hostile file holds where a number, list or mapping is expected
NASTY = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=8),
    st.dictionaries(st.text(max_size=8), st.integers(), max_size=3),
)


def _readers():
    from hydrokit.api import load_geometry, load_mission, load_rig, load_vehicle
    from hydrokit.io.project import load_project
    from hydrokit.io.thrusters import load_thrusters

    return {
        "rig": (load_rig, DATA_DIR / "campaigns" / "udrobot" / "spring_x.yaml"),
        "vehicle": (load_vehicle, DATA_DIR / "vehicles" / "minerva.yaml"),
        "thrusters": (load_thrusters, DATA_DIR / "vehicles" / "bluerov2-heavy.yaml"),
        "mission": (load_mission, DATA_DIR / "missions" / "minerva_square.yaml"),
        "geometry": (load_geometry, DATA_DIR / "geometry" / "sphere.yaml"),
        "project": (load_project, DATA_DIR / "projects" / "rov2" / "project.yaml"),
    }


def _survives(fn, path: Path) -> str:
    """ "result" or "error" (a one-line InputError); any other exception fails the test."""
    try:
        out = fn(path)
    except InputError as exc:
        assert "\n" not in str(exc)
        assert len(str(exc)) < 2000, "a message must not echo unbounded input"
        return "error"
    assert out is not None
    return "result"


@pytest.mark.parametrize("kind", ["rig", "vehicle", "thrusters", "mission", "geometry", "project"])
def test_field_values_of_any_type_give_a_result_or_one_line(kind, tmp_path):
    fn, original = _readers()[kind]
    doc = yaml.safe_load(original.read_text())
    keys = sorted(doc)

    outcomes: list[str] = []

    @FUZZ
    @given(key=st.sampled_from(keys), value=NASTY)
    def run(key, value):
        bad = dict(doc)
        bad[key] = value
        path = tmp_path / original.name  # same folder layout is not needed: paths that go missing are errors too
        path.write_text(yaml.safe_dump(bad))
        outcomes.append(_survives(fn, path))

    run()
    # and every field emptied, deterministically: random draws can miss the one required field
    # (a thrusters file reads only `thrusters:`, 1 of its 13 keys)
    for key in keys:
        path = tmp_path / original.name
        path.write_text(yaml.safe_dump({**doc, key: None}))
        outcomes.append(_survives(fn, path))
    # nonsense in a required field must be refused: a reader that accepted everything would fail here
    assert "error" in outcomes


@pytest.mark.parametrize("kind", ["rig", "vehicle", "mission", "geometry"])
@FUZZ
@given(data=st.binary(max_size=300))
def test_random_bytes_and_truncations(kind, data, tmp_path_factory):
    fn, original = _readers()[kind]
    folder = tmp_path_factory.mktemp(kind)
    (folder / "junk.yaml").write_bytes(data)
    # 300 random bytes are never a valid file of this kind: only a one-line error is right
    assert _survives(fn, folder / "junk.yaml") == "error"
    text = original.read_bytes()
    cut = len(data) % max(1, len(text))
    (folder / "cut.yaml").write_bytes(text[:cut])
    assert _survives(fn, folder / "cut.yaml") in ("result", "error")
    assert _survives(fn, original) == "result"  # the untouched file still reads


def test_alias_bomb_is_refused_quickly(tmp_path):
    from hydrokit.api import load_vehicle

    text = 'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]\n'
    prev = "a"
    for c in "bcdefghi":  # 9^9 ≈ 387 million strings once expanded, from 342 bytes
        text += f"{c}: &{c} [" + ",".join(["*" + prev] * 9) + "]\n"
        prev = c
    (tmp_path / "bomb.yaml").write_text(text)
    with pytest.raises(InputError, match="alias"):
        load_vehicle(tmp_path / "bomb.yaml")


def test_small_anchors_still_work_and_recursion_is_refused(tmp_path):
    from hydrokit.io.yamlfile import read_yaml

    (tmp_path / "ok.yaml").write_text("t: &t {command: [0, 1], thrust: [0, 5]}\nu: *t\n")
    assert read_yaml(tmp_path / "ok.yaml")["u"] == {"command": [0, 1], "thrust": [0, 5]}
    (tmp_path / "loop.yaml").write_text("x: &x [*x]\n")
    with pytest.raises(InputError, match="recursive"):
        read_yaml(tmp_path / "loop.yaml")
    (tmp_path / "deep.yaml").write_text("a: " + "[" * 20000 + "]" * 20000 + "\n")
    with pytest.raises(InputError, match="nested too deeply"):
        read_yaml(tmp_path / "deep.yaml")


def test_python_tags_are_not_constructed(tmp_path):
    from hydrokit.io.yamlfile import read_yaml

    marker = tmp_path / "pwned"
    (tmp_path / "tag.yaml").write_text(f'a: !!python/object/apply:os.system ["touch {marker}"]\n')
    with pytest.raises(InputError, match="not valid YAML"):
        read_yaml(tmp_path / "tag.yaml")
    assert not marker.exists()


@FUZZ
@given(
    rows=st.lists(
        st.tuples(st.floats(allow_nan=True, allow_infinity=True), st.floats(allow_nan=True, allow_infinity=True)),
        max_size=30,
    ),
    header=st.sampled_from(["time,position", "time,angle", "t,x", "time;position", ""]),
)
def test_launch_csv_of_any_content(rows, header, tmp_path_factory):
    from hydrokit.api import load_rig
    from hydrokit.io.launch import read_launch

    rig = load_rig(DATA_DIR / "campaigns" / "udrobot" / "spring_x.yaml")
    folder = tmp_path_factory.mktemp("launch")
    text = header + "\n" + "\n".join(f"{a!r},{b!r}" for a, b in rows) + "\n"
    (folder / "l.csv").write_text(text)
    try:
        launch = read_launch(folder / "l.csv", rig)
    except InputError as exc:
        assert "\n" not in str(exc)
        return
    assert all(math.isfinite(v) for v in launch.t) and all(math.isfinite(v) for v in launch.y)


@FUZZ
@given(data=st.binary(max_size=400))
def test_meshes_of_any_bytes(data, tmp_path_factory):
    from hydrokit.estimate.mesh import read_mesh

    folder = tmp_path_factory.mktemp("mesh")
    for name in ("m.stl", "m.obj"):
        (folder / name).write_bytes(data)
        try:
            read_mesh(folder / name)
        except InputError as exc:
            assert "\n" not in str(exc)
        (folder / name).write_bytes(b"solid " + data)  # the ASCII STL path (and 'solid' junk as OBJ)
        _survives(read_mesh, folder / name)


def _tetrahedron_files(folder: Path) -> dict[str, bytes]:
    """The corner tetrahedron of the unit cube (volume 1/6 m³) written by meshio's own writers."""
    import meshio

    points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    cells = [("triangle", [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])]
    out = {}
    for name, options in (("ascii.stl", {}), ("binary.stl", {"binary": True}), ("tet.obj", {})):
        meshio.write_points_cells(folder / name, points, cells, **options)
        out[name] = (folder / name).read_bytes()
    return out


@FUZZ
@given(
    name=st.sampled_from(["ascii.stl", "binary.stl", "tet.obj"]),
    keep=st.floats(min_value=0.0, max_value=1.0),
    edits=st.lists(st.tuples(st.floats(min_value=0.0, max_value=1.0), st.binary(min_size=1, max_size=4)), max_size=4),
)
def test_meshes_cut_or_overwritten_anywhere(name, keep, edits, tmp_path_factory):
    # a valid file truncated at any point and with a few bytes overwritten: a mesh whose
    # vertices are finite and whose faces exist, or one InputError line
    from hydrokit.estimate.mesh import read_mesh

    folder = tmp_path_factory.mktemp("mesh")
    good = _tetrahedron_files(folder)
    assert read_mesh(folder / name).volume() == pytest.approx(1 / 6, rel=1e-6)
    data = bytearray(good[name][: round(keep * len(good[name]))])
    for where, new in edits:
        at = round(where * len(data))
        data[at : at + len(new)] = new
    (folder / name).write_bytes(bytes(data))
    try:
        mesh = read_mesh(folder / name)
    except InputError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 2000
        assert str(exc).startswith(str(folder / name))
        return
    assert mesh.vertices.shape[1] == 3 and all(math.isfinite(v) for v in mesh.vertices.ravel())
    assert 0 <= mesh.faces.min() and mesh.faces.max() < len(mesh.vertices)


@FUZZ
@given(rows=st.lists(st.tuples(NASTY, NASTY), max_size=12))
def test_force_curves_of_any_content(rows, tmp_path_factory):
    from hydrokit.io.forces import read_forces

    folder = tmp_path_factory.mktemp("forces")
    (folder / "f.csv").write_text("speed,force\n" + "\n".join(f"{a},{b}" for a, b in rows) + "\n")
    try:
        read_forces(folder / "f.csv")
    except InputError as exc:
        assert "\n" not in str(exc)
