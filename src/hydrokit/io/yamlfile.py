"""Safe YAML reading with one-line errors that name the file and field.

Only :func:`yaml.safe_load` is ever used: files are untrusted.
"""

from __future__ import annotations

import codecs
import difflib
import math
import os
import typing
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import yaml

from hydrokit.core.validate import cut
from hydrokit.errors import InputError

#: largest YAML file read (characters) and most nodes once aliases are expanded: hydrokit's
#: files are a few thousand nodes; an alias bomb of 1 KB expands to billions
MAX_YAML_BYTES = 20_000_000
MAX_YAML_NODES = 2_000_000


def _expanded_nodes(node: yaml.Node, memo: dict[int, int], active: set[int], source: str) -> int:
    """Nodes of ``node`` with every alias expanded (memoised, so linear in the file's size);
    a node that contains itself (a recursive alias) is refused."""
    key = id(node)
    if key in active:
        raise InputError("a YAML alias refers to a block that contains it (recursive); expected a tree", source)
    if key in memo:
        return memo[key]
    active.add(key)
    total = 1
    if isinstance(node, yaml.SequenceNode):
        total += sum(_expanded_nodes(n, memo, active, source) for n in node.value)
    elif isinstance(node, yaml.MappingNode):
        total += sum(
            _expanded_nodes(k, memo, active, source) + _expanded_nodes(v, memo, active, source) for k, v in node.value
        )
    active.discard(key)
    memo[key] = min(total, MAX_YAML_NODES + 1)
    return memo[key]


def _load_bounded(text: str, source: str) -> Any:
    """``yaml.safe_load`` that first checks the document's size with aliases expanded."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        n = _expanded_nodes(node, {}, set(), source)
        if n > MAX_YAML_NODES:
            raise InputError(
                f"YAML aliases expand to more than {MAX_YAML_NODES} nodes (an alias bomb?); "
                "expected a plain document (anchors and aliases only for small repeated blocks)",
                source,
            )
        return loader.construct_document(node)
    finally:
        loader.dispose()


#: the encodings a text file may come in (spreadsheets export UTF-16 with a mark)
ACCEPTED_ENCODINGS = "UTF-8 (with or without a byte-order mark) or UTF-16 with a byte-order mark"
_MARKS = (
    (codecs.BOM_UTF8, "utf-8", "UTF-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le", "UTF-16"),
    (codecs.BOM_UTF16_BE, "utf-16-be", "UTF-16"),
)


def decode_text(data: bytes, source: str, what: str = "a text file") -> str:
    """The text of a file's bytes: UTF-8 with or without a byte-order mark, or UTF-16 (LE or
    BE) with one; the mark is dropped.

    Raises
    ------
    InputError
        One line naming ``source``, the encoding found (UTF-32, UTF-16 without a mark, an 8-bit
        code page such as Latin-1, binary data) and the encodings accepted.
    """
    if data.startswith((codecs.BOM_UTF32_LE, codecs.BOM_UTF32_BE)):  # before UTF-16: FF FE 00 00
        found = "UTF-32 (its byte-order mark)"
    else:
        mark, codec, name = next((m for m in _MARKS if data.startswith(m[0])), (b"", "utf-8", ""))
        try:
            text = data[len(mark) :].decode(codec)
        except UnicodeDecodeError as exc:
            at = f"{exc.reason} at byte {exc.start + len(mark)}"
            found = f"a {name} byte-order mark, then bytes that are not {name} ({at})" if mark else _guess(data, at)
        else:
            if "\x00" not in text:
                return text
            found = _guess(data, f"a NUL character at character {text.index(chr(0))}")
    raise InputError(f"not readable text: found {found}; expected {what} in {ACCEPTED_ENCODINGS}", source)


def _guess(data: bytes, where: str) -> str:
    """What undecodable bytes without a byte-order mark most likely are (for the message)."""
    head = data[:4096]
    even, odd = head[0::2], head[1::2]
    if len(head) >= 4 and (even.count(0) > 0.4 * len(even) or odd.count(0) > 0.4 * len(odd)):
        return f"UTF-16 without a byte-order mark ({where})"
    controls = sum(b < 9 or 13 < b < 32 for b in head)
    if controls == 0:
        return f"an 8-bit encoding such as Latin-1 or Windows-1252, not UTF-8 ({where})"
    return f"binary data, not text ({where}; {controls} control byte(s) in the first {len(head)})"


def read_text(path: str | os.PathLike[str], what: str = "a text file") -> str:
    """A text file's content (see :func:`decode_text` for the encodings), or one line naming
    the file and ``what`` it should be."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise InputError("no such file", str(p)) from None
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror or exc}); expected {what}", str(p)) from None
    return decode_text(data, str(p), what)


def read_yaml(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a YAML mapping from ``path``.

    Raises
    ------
    InputError
        The file is missing, is not valid YAML, or its top level is not a mapping.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError("file not found", source=str(p))
    try:
        text = read_text(p, "a YAML file")
        if len(text) > MAX_YAML_BYTES:
            raise InputError(f"file of {len(text)} characters; expected a YAML file under {MAX_YAML_BYTES}", str(p))
        data = _load_bounded(text, str(p))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or "syntax error"
        raise InputError(f"not valid YAML{where}: {problem}", source=str(p)) from None
    except RecursionError:
        raise InputError("YAML nested too deeply; expected a document a few levels deep", source=str(p)) from None
    if not isinstance(data, dict):
        raise InputError(
            f"expected a mapping of fields at the top level, got {type(data).__name__}",
            source=str(p),
        )
    return data


def unknown_key_line(field: str, key: str, accepted: Iterable[str], source: str, more: int = 0) -> InputError:
    """One line for an unknown key: the field (``parts[0].diamter``), the accepted keys and,
    for a near miss, the key it probably meant."""
    names = sorted(set(accepted))
    near = difflib.get_close_matches(key, names, n=1)
    hint = f" (did you mean '{near[0]}'?)" if near else ""
    others = f" and {more} more unknown" if more else ""
    return InputError(f"unknown field '{cut(field)}'{others}{hint}; expected one of {', '.join(names)}", source)


def check_keys(data: Mapping[Any, Any], accepted: Iterable[str], where: str, source: str) -> None:
    """Refuse a key of ``data`` (the mapping at field ``where``, "" for the top level) that is
    not in ``accepted``: a misspelt key must not be read as "not given"."""
    names = set(accepted)
    unknown = [str(k) for k in data if str(k) not in names]
    if unknown:
        field = f"{where}.{unknown[0]}" if where else unknown[0]
        raise unknown_key_line(field, unknown[0], names, source, len(unknown) - 1)


def _fields_at(model: Any, loc: tuple[Any, ...]) -> list[str]:
    """The field names of the pydantic model met at ``loc`` (list indices and union tags skipped)."""
    from pydantic import BaseModel

    def inner(tp: Any) -> Any:
        if isinstance(tp, type) and issubclass(tp, BaseModel):
            return tp
        return next((m for m in map(inner, typing.get_args(tp)) if m is not None), None)

    for part in loc:
        field = model.model_fields.get(part) if isinstance(part, str) else None
        sub = inner(field.annotation) if field is not None else None
        model = sub or model
    return list(model.model_fields)


def pydantic_error_line(exc: Any, source: str, model: Any = None) -> InputError:
    """Turn a pydantic ``ValidationError`` into one :class:`InputError` line naming the field.

    Only the first error is reported (the user fixes one thing at a time) plus a count. With
    ``model`` (the validated class), an unknown key is named with the keys accepted there.
    """
    errors = exc.errors()
    first = errors[0]
    loc = ".".join(str(x) for x in first.get("loc", ())) or "(top level)"
    if first.get("type") == "extra_forbidden" and model is not None:
        path = tuple(first["loc"])
        field = "".join(f"[{x}]" if isinstance(x, int) else f".{x}" for x in path).lstrip(".")
        more = sum(e.get("type") == "extra_forbidden" for e in errors) - 1
        return unknown_key_line(field, str(path[-1]), _fields_at(model, path[:-1]), source, more)
    value = first.get("input")
    msg = first.get("msg", "invalid value")
    if isinstance(value, dict):
        shown = "a mapping"
    elif isinstance(value, float) and math.isnan(value):
        shown = "nan"
    else:
        shown = repr(value)
        if len(shown) > 60:
            shown = shown[:57] + "..."
    more = f" (and {len(errors) - 1} more problem(s))" if len(errors) > 1 else ""
    return InputError(f"field '{loc}' = {shown}: {msg}{more}", source=source)
