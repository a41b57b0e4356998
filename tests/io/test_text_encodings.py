"""Issue #32 class 3: every text reader takes UTF-8 (with or without a byte-order mark) and
UTF-16 with a BOM (little- or big-endian), as spreadsheets export them, and gives the same
result as the UTF-8 original; any other encoding is refused in one line naming the file and
the encoding found. The decoding lives once in :func:`hydrokit.io.yamlfile.decode_text`."""

from __future__ import annotations

import codecs
import dataclasses
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import hydrokit
from hydrokit.data import DATA_DIR
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import decode_text

UDROBOT = DATA_DIR / "campaigns" / "udrobot"
RIG = UDROBOT / "spring_x.yaml"
LAUNCH = UDROBOT / "spring_x" / "spring_x_L1_1.csv"
FORCES = DATA_DIR / "projects" / "udrobot" / "cfd_x.csv"
FORCE_TABLE = "time,X,Y,Z,K,M,N\n0,1,0,0,0,0,0\n1,2,0,0,0,0,0\n"

#: encodings a text file may come in, as bytes of its UTF-8 text
ENCODINGS: dict[str, Callable[[str], bytes]] = {
    "utf-8-bom": lambda s: codecs.BOM_UTF8 + s.encode("utf-8"),
    "utf-16-le-bom": lambda s: codecs.BOM_UTF16_LE + s.encode("utf-16-le"),
    "utf-16-be-bom": lambda s: codecs.BOM_UTF16_BE + s.encode("utf-16-be"),
}


def _rig() -> Any:
    return hydrokit.load_rig(RIG)


def _read(kind: str, path: Path) -> Any:
    """What each reader makes of ``path``, as something comparable with ``==``."""
    from hydrokit.io.forces import read_forces
    from hydrokit.io.geometry import load_geometry
    from hydrokit.io.launch import read_launch
    from hydrokit.io.mission import load_mission
    from hydrokit.io.project import load_project
    from hydrokit.io.rig import load_rig
    from hydrokit.io.table import read_table
    from hydrokit.io.thrusters import load_thrusters
    from hydrokit.io.trajectory import read_force_table
    from hydrokit.io.vehicle import load_vehicle

    if kind == "launch":
        la = read_launch(path, _rig())
        return (la.t.tolist(), la.y.tolist())
    if kind == "table":
        rec = read_table(path, _rig())
        return (rec.t.tolist(), rec.y.tolist())
    if kind == "forces":
        return tuple(a.tolist() for a in read_forces(path))
    if kind == "force-table":
        return read_force_table(path).tolist()
    if kind == "rig":
        return dataclasses.replace(load_rig(path), source="")
    if kind == "vehicle":
        return np.asarray(load_vehicle(path).M).tolist()
    if kind == "thrusters":
        return load_thrusters(path).names
    if kind == "mission":
        m = load_mission(path)
        return (m.name, m.vehicle, m.duration, m.gains)
    if kind == "geometry":
        return [gp.part.mass for gp in load_geometry(path).parts]
    if kind == "project":
        return load_project(path).name
    raise AssertionError(kind)


def _original(kind: str, tmp: Path) -> Path:
    """A valid UTF-8 input of ``kind`` in ``tmp`` (a copy of a bundled file where one exists)."""
    sources = {
        "launch": LAUNCH,
        "table": LAUNCH,
        "forces": FORCES,
        "rig": RIG,
        "vehicle": DATA_DIR / "vehicles" / "minerva.yaml",
        "thrusters": DATA_DIR / "vehicles" / "minerva.yaml",
        "geometry": DATA_DIR / "geometry" / "sphere.yaml",
    }
    if kind == "force-table":
        text = FORCE_TABLE
    elif kind == "mission":
        text = (DATA_DIR / "missions" / "minerva_square.yaml").read_text(encoding="utf-8")
    elif kind == "project":  # copied with the files it names, so its relative paths still resolve
        shutil.copytree(DATA_DIR / "projects" / "udrobot", tmp / "a" / "b" / "proj")
        (tmp / "a" / "campaigns").symlink_to(DATA_DIR / "campaigns")
        return tmp / "a" / "b" / "proj" / "project.yaml"
    else:
        text = sources[kind].read_text(encoding="utf-8")
    p = tmp / f"original-{kind}{'.yaml' if kind not in ('launch', 'table', 'forces', 'force-table') else '.csv'}"
    p.write_text(text, encoding="utf-8")
    return p


KINDS = ["launch", "table", "forces", "force-table", "rig", "vehicle", "thrusters", "mission", "geometry", "project"]


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
@pytest.mark.parametrize("kind", KINDS)
def test_every_reader_takes_utf8_with_bom_and_utf16_with_bom(tmp_path, kind, encoding):
    original = _original(kind, tmp_path)
    copy = original.with_name(f"{encoding}-{original.name}")
    copy.write_bytes(ENCODINGS[encoding](original.read_text(encoding="utf-8")))
    assert _read(kind, copy) == _read(kind, original)


REFUSED = {
    "utf-16-le-without-bom": (lambda s: s.encode("utf-16-le"), "UTF-16 without a byte-order mark"),
    "utf-16-be-without-bom": (lambda s: s.encode("utf-16-be"), "UTF-16 without a byte-order mark"),
    "utf-32-le-bom": (lambda s: codecs.BOM_UTF32_LE + s.encode("utf-32-le"), "UTF-32"),
    "utf-32-be-bom": (lambda s: codecs.BOM_UTF32_BE + s.encode("utf-32-be"), "UTF-32"),
    "latin-1": (lambda s: "# café\n".encode("latin-1") + s.encode("utf-8"), "Latin-1"),
    "binary": (lambda s: bytes(range(256)) * 4, "binary"),
    "utf-16-bom-then-odd-byte": (lambda s: codecs.BOM_UTF16_LE + s.encode("utf-16-le") + b"\x00", "UTF-16"),
}


@pytest.mark.parametrize("case", sorted(REFUSED))
@pytest.mark.parametrize("kind", ["launch", "forces", "force-table", "vehicle", "rig", "geometry"])
def test_other_encodings_are_refused_naming_the_file_and_the_encoding(tmp_path, kind, case):
    encode, found = REFUSED[case]
    original = _original(kind, tmp_path)
    bad = original.with_name(f"bad-{original.name}")
    bad.write_bytes(encode(original.read_text(encoding="utf-8")))
    with pytest.raises(InputError, match=r"bad-original") as info:
        _read(kind, bad)
    msg = str(info.value)
    assert found in msg, msg
    assert "UTF-8 (with or without a byte-order mark) or UTF-16 with a byte-order mark" in msg, msg
    assert "\n" not in msg


@pytest.mark.parametrize(
    ("data", "text"),
    [
        (b"a,b\n1,2\n", "a,b\n1,2\n"),
        (codecs.BOM_UTF8 + "é\n".encode(), "é\n"),
        (codecs.BOM_UTF16_LE + "é\n".encode("utf-16-le"), "é\n"),
        (codecs.BOM_UTF16_BE + "é\n".encode("utf-16-be"), "é\n"),
        (b"", ""),
    ],
    ids=["utf-8", "utf-8-bom", "utf-16-le-bom", "utf-16-be-bom", "empty"],
)
def test_decode_text_drops_the_mark_and_keeps_the_text(data, text):
    assert decode_text(data, "f.csv") == text


def test_a_nul_byte_in_utf8_text_is_refused_as_binary():
    # NUL is valid UTF-8 but no text file holds one: it is binary data or UTF-16 without a mark
    with pytest.raises(InputError, match=r"f\.csv: .*NUL"):
        decode_text(b"time,position\n0,\x001\n", "f.csv")
