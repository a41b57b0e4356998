"""Mesh files through meshio (issue #13): the same closed box as ASCII STL, binary STL and OBJ
gives the same mesh and the closed-form volume a·b·c; hostile files (lying headers, oversize,
NaN vertices, missing vertices, junk) give one InputError line naming the file."""

from __future__ import annotations

import os
import struct
import time

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.estimate import mesh as mesh_module
from hydrokit.estimate.mesh import check_mesh, read_mesh

A, B, C = 2.0, 3.0, 5.0  # box edges, m (float32-exact, so binary STL loses nothing)
ORIGIN = np.array([1.0, -2.0, 0.5])  # m
# unit-cube corners and its outward quads (counter-clockwise seen from outside), 0-based
CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]


def box_vertices() -> np.ndarray:
    """The 8 corners of the a×b×c box, m."""
    return ORIGIN + np.array(CORNERS, float) * [A, B, C]


def box_triangles() -> np.ndarray:
    """(12, 3, 3) outward triangles of the box, m."""
    v = box_vertices()
    return np.array([[v[q[0]], v[q[i]], v[q[i + 1]]] for q in QUADS for i in (1, 2)])


def stl_ascii(tris: np.ndarray) -> bytes:
    facets = "".join(
        "facet normal 0 0 0\n outer loop\n"
        + "".join(f"  vertex {x!r} {y!r} {z!r}\n" for x, y, z in np.asarray(t, float).tolist())
        + " endloop\nendfacet\n"
        for t in tris
    )
    return f"solid box\n{facets}endsolid box\n".encode()


def stl_binary(tris: np.ndarray, count: int | None = None) -> bytes:
    """Binary STL; ``count`` overrides the header's triangle count (a lying header)."""
    out = bytearray(b"box".ljust(80, b" ") + struct.pack("<I", len(tris) if count is None else count))
    for t in tris:
        out += struct.pack("<12fH", 0, 0, 0, *np.asarray(t, float).ravel(), 0)
    return bytes(out)


def obj_text(vertices: np.ndarray, faces: list[tuple[int, ...]]) -> str:
    """OBJ with 1-based indices."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def test_ascii_and_binary_stl_of_a_box_give_the_same_mesh_and_volume_abc(tmp_path):
    (tmp_path / "a.stl").write_bytes(stl_ascii(box_triangles()))
    (tmp_path / "b.stl").write_bytes(stl_binary(box_triangles()))
    ascii_mesh, binary_mesh = read_mesh(tmp_path / "a.stl"), read_mesh(tmp_path / "b.stl")
    np.testing.assert_array_equal(ascii_mesh.vertices, binary_mesh.vertices)
    np.testing.assert_array_equal(ascii_mesh.faces, binary_mesh.faces)
    assert ascii_mesh.vertices.shape == (8, 3) and ascii_mesh.faces.shape == (12, 3)  # corners merged
    assert ascii_mesh.volume() == pytest.approx(A * B * C, rel=1e-12)
    assert binary_mesh.volume() == pytest.approx(A * B * C, rel=1e-12)
    assert binary_mesh.source.endswith("b.stl")
    check_mesh(binary_mesh)  # closed, outward


def test_obj_with_quads_gives_the_same_box(tmp_path):
    path = tmp_path / "box.obj"
    path.write_text(obj_text(box_vertices(), QUADS))
    mesh = read_mesh(path)
    assert mesh.faces.shape == (6, 4)  # quads kept as quads
    assert mesh.volume() == pytest.approx(A * B * C, rel=1e-12)
    check_mesh(mesh)
    # the same faces counted back from the last vertex (-8 is the first of 8)
    back = obj_text(box_vertices(), []) + "".join("f " + " ".join(str(i - 8) for i in q) + "\n" for q in QUADS)
    (tmp_path / "back.obj").write_text(back)
    np.testing.assert_array_equal(read_mesh(tmp_path / "back.obj").faces, mesh.faces)


def test_obj_polygons_are_fanned_and_mixed_with_quads(tmp_path):
    # a prism on the pentagon (0,0) (2,0) (2,1) (1,2) (0,1), area 2 + 1 = 3 m², height 4 m:
    # volume 12 m³. Caps are pentagons (fanned into 3 triangles), sides are quads.
    pent = [(0, 0), (2, 0), (2, 1), (1, 2), (0, 1)]
    v = np.array([(x, y, z) for z in (0.0, 4.0) for x, y in pent])
    faces = [(4, 3, 2, 1, 0), (5, 6, 7, 8, 9)] + [(i, (i + 1) % 5, (i + 1) % 5 + 5, i + 5) for i in range(5)]
    (tmp_path / "prism.obj").write_text(obj_text(v, faces))
    mesh = read_mesh(tmp_path / "prism.obj")
    assert mesh.faces.shape == (2 * 3 + 5, 4)  # fans padded to quads that repeat a corner
    assert len(mesh.triangles()) == 2 * 3 + 5 * 2
    assert mesh.volume() == pytest.approx(12.0, rel=1e-12)
    check_mesh(mesh)


@pytest.mark.parametrize(
    ("count", "match"),
    [
        (13, r"announces 13 triangles but is truncated: its 684 bytes hold 12\)"),  # whole triangles, not 12.0
        (10**9, "announces 1000000000"),
        (11, "announces 11 triangles but 50 bytes follow them"),
        (1, "announces 1 triangle but 550 bytes follow them"),  # one, in the singular
    ],
)
def test_binary_stl_whose_header_lies_is_refused_before_parsing(tmp_path, monkeypatch, count, match):
    import meshio

    calls: list[object] = []
    monkeypatch.setattr(meshio.stl, "read", lambda *a: calls.append(a))
    path = tmp_path / "hull.stl"
    path.write_bytes(stl_binary(box_triangles(), count=count))
    with pytest.raises(InputError, match=match) as err:
        read_mesh(path)
    assert str(err.value).startswith(f"{path}: not a readable STL (")
    assert str(err.value).endswith("expected ASCII or binary STL")
    assert calls == []  # meshio never saw the file


def test_binary_stl_whose_header_starts_with_solid_is_still_checked_as_binary(tmp_path, monkeypatch):
    # some CAD exporters start the 80-byte binary header with "solid" too; the zero bytes of the
    # triangle records give it away, so a lying count is refused as binary, not parsed as text
    import meshio

    calls: list[object] = []
    monkeypatch.setattr(meshio.stl, "read", lambda *a: calls.append(a))
    data = stl_binary(box_triangles(), count=13)
    path = tmp_path / "hull.stl"
    path.write_bytes(b"solid hull".ljust(80, b" ") + data[80:])
    with pytest.raises(InputError, match="announces 13 triangles but is truncated: its 684 bytes hold 12"):
        read_mesh(path)
    assert calls == []


def _printable_cp1252(b: int) -> bool:
    try:
        ch = bytes([b]).decode("cp1252")
    except UnicodeDecodeError:
        return False
    return ch.isprintable() and not ch.isspace()


def test_text_whose_bytes_80_to_83_wrap_to_the_file_size_is_not_read_as_binary(tmp_path, capfd):
    # meshio computes 84 + 50·count in uint32: text can match the size modulo 2³² and would be
    # read as ~1.7e9 binary triangles (an 80 GiB allocation). Craft such a text file.
    inverse = pow(25, -1, 2**31)
    body = stl_ascii(box_triangles()).split(b"\n", 1)[1]
    for pad in range(0, 4000, 2):
        rest = b"\n" + body[:-1] + b" " * pad + b"\n"  # pad spaces: not a blank line
        half = len(rest) // 2
        choices = [half * inverse % 2**31, half * inverse % 2**31 + 2**31] if len(rest) % 2 == 0 else []
        # count bytes that are printable text (Windows-1252: an odd multiple needs bytes above
        # 0x7F), and 84 + 50·count an odd multiple of 2³² above the size: then it differs from
        # the size modulo 2³³, so only the 32-bit wrap explains the match
        good = [
            n
            for n in choices
            if all(_printable_cp1252(b) for b in n.to_bytes(4, "little"))
            and (84 + 50 * n - (84 + len(rest))) // 2**32 % 2 == 1
        ]
        if good:
            data = b"solid box".ljust(80, b" ") + good[0].to_bytes(4, "little") + rest
            break
    assert (84 + 50 * good[0]) % 2**32 == len(data) and (84 + 50 * good[0]) % 2**33 != len(data)
    path = tmp_path / "wrap.stl"
    path.write_bytes(data)
    with pytest.raises(InputError, match=f"binary count of {good[0]} triangles that matches the size modulo"):
        read_mesh(path)
    assert capfd.readouterr().err == ""  # no numpy overflow warning on stderr
    # the same text with an ordinary header line reads as the box
    path.write_bytes(b"solid box\n" + rest[1:])
    assert read_mesh(path).volume() == pytest.approx(A * B * C, rel=1e-12)


def test_a_file_over_the_size_bound_is_refused_before_parsing(tmp_path, monkeypatch):
    import meshio

    calls: list[object] = []
    monkeypatch.setattr(meshio.obj, "read", lambda *a: calls.append(a))
    monkeypatch.setattr(mesh_module, "MAX_MESH_BYTES", 100)
    path = tmp_path / "big.obj"
    path.write_text(obj_text(box_vertices(), QUADS))
    assert path.stat().st_size > 100
    with pytest.raises(
        InputError, match=r"big\.obj: the file has [0-9,]+ bytes \(.* MB\), more than the 100 bytes a mesh may have"
    ):
        read_mesh(path)
    assert calls == []


def test_the_bounded_read_keeps_a_file_of_exactly_the_bound_and_refuses_one_byte_more(tmp_path, monkeypatch):
    # the read after the size check takes one byte more than the bound, so a file that grew in
    # between is caught; a file of exactly the bound is read whole
    monkeypatch.setattr(mesh_module, "MAX_MESH_BYTES", 100)
    path = tmp_path / "m.obj"
    path.write_bytes(b"#" * 100)
    assert mesh_module._bounded_bytes(path) == b"#" * 100
    path.write_bytes(b"#" * 101)
    with pytest.raises(InputError, match=r"m\.obj: the file has grown past 0\.0001 MB while being read"):
        mesh_module._bounded_bytes(path)


@pytest.mark.parametrize("fmt", ["ascii", "binary", "obj"])
@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_vertex_is_refused(tmp_path, fmt, bad):
    tris = box_triangles()
    tris[3, 1, 2] = bad
    v = box_vertices()
    v[5, 0] = bad
    path = tmp_path / ("hull.obj" if fmt == "obj" else "hull.stl")
    data = {
        "ascii": lambda: stl_ascii(tris),
        "binary": lambda: stl_binary(tris),
        "obj": lambda: obj_text(v, QUADS).encode(),
    }
    path.write_bytes(data[fmt]())
    with pytest.raises(InputError, match=r"1 vertex\(es\) not finite, e\.g\. \(.*(nan|inf).*\); expected finite x y z"):
        read_mesh(path)


def test_a_far_vertex_is_refused(tmp_path):
    v = box_vertices()
    v[2, 1] = 1e300  # finite, but its volume terms would overflow
    (tmp_path / "far.obj").write_text(obj_text(v, QUADS))
    with pytest.raises(InputError, match=r"far\.obj: a vertex coordinate is 1e\+300 m"):
        read_mesh(tmp_path / "far.obj")
    # the bound is ±10⁹ m (docs/hostile-input.md): on it a box still reads, half a metre past it not
    v[2, 1] = 1e9
    (tmp_path / "edge.obj").write_text(obj_text(v, QUADS))
    assert float(np.abs(read_mesh(tmp_path / "edge.obj").vertices).max()) == 1e9
    v[2, 1] = 1e9 + 0.5
    (tmp_path / "past.obj").write_text(obj_text(v, QUADS))
    with pytest.raises(InputError, match=r"past\.obj: a vertex coordinate is 1e\+09 m, beyond ±1e\+09 m"):
        read_mesh(tmp_path / "past.obj")


@pytest.mark.parametrize(
    ("face", "match"),
    [
        ("f 1 2 9", "refers to vertex 9 but the file has 8"),
        ("f 0 1 2", "vertex 0 or counts back"),
        ("f -1 -2 -9", "counts back past the first"),
        ("f 1 2", "a face with 2 corner"),
        ("f 1 2 " + "9" * 30, "a face index is not a vertex number"),
    ],
)
def test_faces_that_refer_to_missing_vertices_are_refused(tmp_path, face, match):
    (tmp_path / "m.obj").write_text(obj_text(box_vertices(), QUADS) + face + "\n")
    with pytest.raises(InputError, match=match) as err:
        read_mesh(tmp_path / "m.obj")
    assert str(err.value).startswith(str(tmp_path / "m.obj"))


@pytest.mark.parametrize(
    ("name", "data", "match"),
    [
        ("empty.obj", b"", "no vertices in the OBJ file"),
        ("points.obj", b"v 0 0 0\nv 1 0 0\n", "no faces in the OBJ file"),
        ("empty.stl", b"solid x\nendsolid x\n", "no vertices in the STL file"),
        ("short.stl", b"\x00" * 50, "50 bytes: shorter than a binary header"),
        ("zero.stl", b"\x00" * 84, "no vertices in the STL file"),
        ("words.obj", b"v 1 2 three\n", r"not a readable OBJ \(ValueError: could not convert"),
        ("mesh.ply", b"ply\n", r"mesh format '\.ply': expected \.stl or \.obj"),
    ],
)
def test_empty_and_wrong_files_are_one_line(tmp_path, name, data, match):
    (tmp_path / name).write_bytes(data)
    with pytest.raises(InputError, match=match) as err:
        read_mesh(tmp_path / name)
    assert "\n" not in str(err.value) and str(err.value).startswith(str(tmp_path / name))


def test_messages_do_not_echo_a_long_token(tmp_path):
    (tmp_path / "long.obj").write_bytes(b"v " + b"x" * 100_000 + b" 0 0\n")
    with pytest.raises(InputError, match="100049 characters") as err:
        read_mesh(tmp_path / "long.obj")
    assert len(str(err.value)) < 400


def test_ascii_stl_with_blank_lines_and_crlf_still_reads(tmp_path):
    # meshio alone fails on a blank line after the last vertex ("cannot reshape … shape (0)")
    text = stl_ascii(box_triangles()).replace(b"endsolid", b"\n  \nendsolid") + b"\n\n \n"
    (tmp_path / "blank.stl").write_bytes(text)
    (tmp_path / "crlf.stl").write_bytes(text.replace(b"\n", b"\r\n"))
    for name in ("blank.stl", "crlf.stl"):
        assert read_mesh(tmp_path / name).volume() == pytest.approx(A * B * C, rel=1e-12)


def test_any_parser_failure_is_an_input_error_but_an_interrupt_is_not(tmp_path, monkeypatch):
    import meshio

    (tmp_path / "box.obj").write_text(obj_text(box_vertices(), QUADS))

    def boom(exc):
        def read(*_):
            raise exc

        return read

    for exc, match in [
        (MemoryError(), "not enough memory to read this"),
        (IndexError("list index out of range"), r"not a readable OBJ \(IndexError: list index out of range\)"),
        (struct.error("unpack requires a buffer"), r"\(error: unpack requires a buffer\)"),
        (SystemExit(1), r"not a readable OBJ \(SystemExit: 1\)"),
    ]:
        monkeypatch.setattr(meshio.obj, "read", boom(exc))
        with pytest.raises(InputError, match=match):
            read_mesh(tmp_path / "box.obj")
    monkeypatch.setattr(meshio.obj, "read", boom(KeyboardInterrupt()))
    with pytest.raises(KeyboardInterrupt):
        read_mesh(tmp_path / "box.obj")


@pytest.mark.parametrize(
    "data",
    [
        b"solid x\n" + b"1 " * 1_500_000,  # one 3 MB line of numbers
        b"solid x\n" + b"\n" * 3_000_000,  # 3 MB of blank lines (the blank-line copy path)
        b"solid x\n" + bytes(range(33, 127)) * 30_000,  # 2.8 MB of printable junk, no newline
        (b"solid x\n" + stl_ascii(box_triangles())[10:] * 3000)[:-40],  # 3000 boxes, cut mid-vertex
    ],
    ids=["numbers", "blank-lines", "junk", "truncated"],
)
@pytest.mark.parametrize("name", ["m.stl", "m.obj"])
def test_large_junk_and_truncations_end_quickly(tmp_path, data, name):
    (tmp_path / name).write_bytes(data)
    start = time.perf_counter()
    try:
        mesh = read_mesh(tmp_path / name)
    except InputError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 400
    else:
        assert np.isfinite(mesh.vertices).all() and mesh.faces.max() < len(mesh.vertices)
    assert time.perf_counter() - start < 30.0  # linear readers: about a second on a slow machine


def test_random_bytes_give_an_input_error(tmp_path):
    rng = np.random.default_rng(13)
    for k in range(40):
        data = rng.bytes(int(rng.integers(0, 5000)))
        for name in (f"r{k}.stl", f"r{k}.obj"):
            (tmp_path / name).write_bytes(data if k % 2 else b"solid " + data)
            with pytest.raises(InputError) as err:
                read_mesh(tmp_path / name)
            assert "\n" not in str(err.value) and os.fspath(tmp_path / name) in str(err.value)


@pytest.mark.parametrize("size", [80, 83])
def test_text_of_80_to_83_bytes_is_too_short_for_a_facet(tmp_path, size):
    # meshio reads a binary count from any file of 80 bytes or more: such short text is refused first
    path = tmp_path / "short.stl"
    path.write_bytes(b"solid x".ljust(size, b" "))
    with pytest.raises(InputError) as err:
        read_mesh(path)
    assert str(err.value).startswith(f"{path}: not a readable STL ({size} bytes of text: too short for a facet); ")


def test_the_size_bound_is_200_megabytes(tmp_path):
    # MAX_MESH_BYTES's documented 200 MB: one byte more is refused by its size alone (a sparse
    # file: nothing is written to disk, and nothing is read)
    path = tmp_path / "huge.stl"
    with open(path, "wb") as f:
        f.truncate(200_000_001)
    with pytest.raises(InputError, match=r"has 200,000,001 bytes \(200 MB\), more than the 200,000,000 bytes"):
        read_mesh(path)


def test_an_ascii_stl_facet_of_two_vertices_is_refused_in_words(tmp_path):
    # meshio's ASCII reader raises a ReadError without a message for a facet that is not one
    # 'facet normal' line and three 'vertex' lines: the error says that instead of nothing
    path = tmp_path / "two.stl"
    path.write_text(
        "solid x\nfacet normal 0 0 0\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n endloop\nendfacet\nendsolid x\n"
    )
    with pytest.raises(
        InputError, match=r"\(ReadError: the facets are not each one 'facet normal' line and three 'vertex' lines\)"
    ):
        read_mesh(path)


@pytest.mark.parametrize("quad", [[0, 1, 2, 2], [0, 1, 2, 0], [0, 1, 1, 2]])
def test_a_quad_repeating_a_corner_is_one_triangle(quad):
    # a quad face that repeats any of its corners is a triangle: its second half is degenerate
    # (two equal corners) and left out, whichever corners they are
    from hydrokit.estimate.mesh import SurfaceMesh

    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    tri = SurfaceMesh(v, np.array([quad])).triangles()
    assert tri.shape == (1, 3) and sorted(tri[0].tolist()) == [0, 1, 2]


@pytest.mark.parametrize(("blanks", "reads"), [(1019, True), (1020, False)])
def test_text_is_told_from_binary_by_its_first_kib(tmp_path, blanks, reads):
    # the first 1024 bytes (mesh._STL_SNIFF) decide: 'solid' must begin within them. 1019 blanks
    # leave 'solid' whole in the first KiB; 1020 cut it to 'soli', and the file is judged binary
    # (whose header cannot match this size)
    path = tmp_path / "box.stl"
    path.write_bytes(b" " * blanks + stl_ascii(box_triangles()))
    if reads:
        assert read_mesh(path).volume() == pytest.approx(A * B * C, rel=1e-12)
    else:
        with pytest.raises(InputError, match="binary header announces"):
            read_mesh(path)


def test_digest_ignores_sub_nanometre_round_off_but_not_a_nanometre():
    # the BEM cache key rounds vertices to 1e-9 m: 0.4 nm of re-export round-off keeps the key,
    # a 2 nm move changes it, and so does a different face list
    from hydrokit.estimate.mesh import SurfaceMesh

    v, f = box_vertices(), np.array(QUADS)
    key = SurfaceMesh(v, f).digest()
    assert SurfaceMesh(v + 4e-10, f).digest() == key
    assert SurfaceMesh(v + 2e-9, f).digest() != key
    assert SurfaceMesh(v, f[:, ::-1]).digest() != key
    assert len(key) == 64 and int(key, 16) >= 0  # SHA-256 hex


def test_check_mesh_of_no_faces_says_so():
    from hydrokit.estimate.mesh import SurfaceMesh

    with pytest.raises(InputError, match="the mesh has no faces"):
        check_mesh(SurfaceMesh(box_vertices(), np.zeros((0, 3), np.int64), "empty.obj"))


def test_a_mesh_of_exactly_the_size_bound_is_read(tmp_path, monkeypatch):
    # the bound is "at most MAX_MESH_BYTES": a box OBJ padded to exactly the bound reads, one
    # byte more is refused by size
    text = obj_text(box_vertices(), QUADS).encode()
    bound = len(text) + 10
    monkeypatch.setattr(mesh_module, "MAX_MESH_BYTES", bound)
    path = tmp_path / "box.obj"
    path.write_bytes(text + b"#" * 9 + b"\n")
    assert path.stat().st_size == bound
    assert read_mesh(path).volume() == pytest.approx(A * B * C, rel=1e-12)
    path.write_bytes(text + b"#" * 10 + b"\n")
    with pytest.raises(InputError, match=f"more than the {bound:,} bytes a mesh may have"):
        read_mesh(path)


def test_a_bare_84_byte_header_is_a_header_not_a_short_file(tmp_path):
    # 84 bytes is a whole binary header: one announcing a triangle is truncated (0 follow), not
    # "shorter than a binary header"; 83 bytes are
    path = tmp_path / "h.stl"
    path.write_bytes(stl_binary(box_triangles()[:1])[:84])
    with pytest.raises(InputError, match=r"announces 1 triangle but is truncated: its 84 bytes hold 0\)"):
        read_mesh(path)
    path.write_bytes(stl_binary(box_triangles()[:1])[:83])
    with pytest.raises(InputError, match="83 bytes: shorter than a binary header"):
        read_mesh(path)


def test_a_relative_index_of_a_non_ascii_digit_is_not_a_number(tmp_path):
    # Python's int() reads '٣' (ARABIC-INDIC DIGIT THREE) as 3; an OBJ index is ASCII digits, so
    # 'f -٣ -2 -1' is refused, while the same face with '-3' reads
    tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -{} -2 -1\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n"
    path = tmp_path / "t.obj"
    path.write_text(tetra.format("3"), encoding="utf-8")
    assert read_mesh(path).faces.shape == (4, 3)
    path.write_text(tetra.format("\u0663"), encoding="utf-8")
    with pytest.raises(InputError, match="t.obj: a face refers to vertex"):
        read_mesh(path)


@pytest.mark.parametrize("extra", [" 1", " 0.5 0.2 0.9"])
def test_obj_vertices_with_a_weight_or_colours_keep_x_y_z(tmp_path, extra):
    # 'v x y z w' and 'v x y z r g b' are both written by exporters: the hull keeps x, y, z (m)
    v = box_vertices()
    lines = [ln + extra if ln.startswith("v ") else ln for ln in obj_text(v, QUADS).splitlines()]
    path = tmp_path / "box.obj"
    path.write_text("\n".join(lines) + "\n")
    m = read_mesh(path)
    assert m.vertices.shape == (8, 3)
    np.testing.assert_array_equal(m.vertices, v)
    assert m.volume() == pytest.approx(A * B * C, rel=1e-12)


def test_a_flat_block_of_indices_is_cells_of_one_corner():
    # meshio keeps cells as (k, corners); a flat block of k indices is k one-corner cells (points)
    with pytest.raises(InputError, match=r"x\.obj: a face with 1 corner\(s\); expected 3 or more"):
        mesh_module._corners(np.array([0, 1, 2]), 4, "x.obj")
    with pytest.raises(InputError, match=r"a face with 2 corner\(s\)"):
        mesh_module._corners(np.array([[0, 1], [1, 2]]), 4, "x.obj")
