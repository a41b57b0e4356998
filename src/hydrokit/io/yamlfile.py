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
        data = yaml.safe_load(p.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or "syntax error"
        raise InputError(f"not valid YAML{where}: {problem}", source=str(p)) from None
    except UnicodeDecodeError:
        raise InputError("not a UTF-8 text file", source=str(p)) from None
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
