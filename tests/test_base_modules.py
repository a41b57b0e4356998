"""Atomic writes and one-line errors: the base every output and error goes through."""

from __future__ import annotations

from pathlib import Path

import pytest

from hydrokit._atomic import atomic_path, write_text
from hydrokit.errors import InputError
from hydrokit.io.yamlfile import read_yaml


def test_atomic_write_leaves_old_file_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.json"
    write_text(target, "old")
    with pytest.raises(RuntimeError, match="boom"):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


def test_input_error_is_one_line() -> None:
    err = InputError("bad value\n  expected   positive", source="rig.yaml: body.mass")
    assert "\n" not in str(err)
    assert str(err).startswith("rig.yaml: body.mass: bad value")


def test_read_yaml_errors_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="missing.yaml: file not found"):
        read_yaml(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("a: [1, 2\n")
    with pytest.raises(InputError, match=r"bad.yaml: not valid YAML \(line"):
        read_yaml(bad)
    scalar = tmp_path / "scalar.yaml"
    scalar.write_text("3\n")
    with pytest.raises(InputError, match="expected a mapping"):
        read_yaml(scalar)


def test_read_yaml_refuses_python_tags(tmp_path: Path) -> None:
    evil = tmp_path / "evil.yaml"
    evil.write_text("x: !!python/object/apply:os.system ['echo hi']\n")
    with pytest.raises(InputError, match="not valid YAML"):
        read_yaml(evil)
