"""Safe YAML reading with one-line errors that name the file and field.

Only :func:`yaml.safe_load` is ever used: files are untrusted.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import yaml

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


def read_text(path: str | os.PathLike[str], expected: str = "a UTF-8 text file") -> str:
    """A text file's content (UTF-8, BOM dropped), or one line naming the file and ``expected``."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError("no such file", str(p)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the file ({exc.__class__.__name__}); expected {expected}", str(p)) from None


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
        text = p.read_text(encoding="utf-8")
        if len(text) > MAX_YAML_BYTES:
            raise InputError(f"file of {len(text)} characters; expected a YAML file under {MAX_YAML_BYTES}", str(p))
        data = _load_bounded(text, str(p))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or "syntax error"
        raise InputError(f"not valid YAML{where}: {problem}", source=str(p)) from None
    except UnicodeDecodeError:
        raise InputError("not a UTF-8 text file", source=str(p)) from None
    except RecursionError:
        raise InputError("YAML nested too deeply; expected a document a few levels deep", source=str(p)) from None
    if not isinstance(data, dict):
        raise InputError(
            f"expected a mapping of fields at the top level, got {type(data).__name__}",
            source=str(p),
        )
    return data


def pydantic_error_line(exc: Any, source: str) -> InputError:
    """Turn a pydantic ``ValidationError`` into one :class:`InputError` line naming the field.

    Only the first error is reported (the user fixes one thing at a time) plus a count.
    """
    errors = exc.errors()
    first = errors[0]
    loc = ".".join(str(x) for x in first.get("loc", ())) or "(top level)"
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
