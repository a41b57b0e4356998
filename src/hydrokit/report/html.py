"""Building blocks for self-contained HTML reports.

All user-supplied text goes through :func:`esc`; figures are embedded as base64 PNG so a
report is one file that can be mailed or archived.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Sequence

CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2rem auto;
max-width:1300px;color:#1b1f24;line-height:1.45;padding:0 1rem}
h1{border-bottom:3px solid #0b5394;padding-bottom:.3rem}
h2{color:#0b5394;margin-top:2rem}
table{border-collapse:collapse;margin:.6rem 0 1.2rem;font-size:.92rem;display:block;max-width:100%;overflow-x:auto}
th,td{border:1px solid #c8ced6;padding:.25rem .55rem;text-align:right}
th{background:#eef3f9} td.l,th.l{text-align:left}
.warn{background:#fff4e5;border-left:4px solid #e69138;padding:.4rem .8rem;margin:.3rem 0}
.note{color:#555;font-size:.9rem}
figure{margin:1rem 0} figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:.88rem;color:#444}
"""


def esc(text: object) -> str:
    """Escape any value for HTML text or attribute context."""
    return html.escape(str(text), quote=True)


def fmt(x: object, digits: int = 4) -> str:
    """Format a number for a table (significant digits); None/NaN as an en dash."""
    if x is None:
        return "–"
    if isinstance(x, (int,)) and not isinstance(x, bool):
        return str(x)
    try:
        v = float(x)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return esc(x)
    if v != v:
        return "–"
    return f"{v:.{digits}g}"


def table(header: Sequence[str], rows: Iterable[Sequence[object]], left_cols: int = 1) -> str:
    """An HTML table; cells that are not already-formatted strings are formatted by :func:`fmt`.

    The first ``left_cols`` columns are left-aligned (labels). String cells are escaped.
    """
    out = ["<table><thead><tr>"]
    for i, h in enumerate(header):
        cls = ' class="l"' if i < left_cols else ""
        out.append(f"<th{cls}>{esc(h)}</th>")
    out.append("</tr></thead><tbody>")
    for row in rows:
        out.append("<tr>")
        for i, cell in enumerate(row):
            cls = ' class="l"' if i < left_cols else ""
            text = esc(cell) if isinstance(cell, str) else fmt(cell)
            out.append(f"<td{cls}>{text}</td>")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def figure(png: bytes, caption: str = "") -> str:
    """Embed PNG bytes as a figure with an escaped caption."""
    data = base64.b64encode(png).decode("ascii")
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    return f'<figure><img alt="{esc(caption)}" src="data:image/png;base64,{data}">{cap}</figure>'


def warnings_block(messages: Iterable[str]) -> str:
    """Each warning in its own highlighted paragraph (escaped)."""
    return "".join(f'<p class="warn">{esc(m)}</p>' for m in messages)


def page(title: str, body_parts: Iterable[str]) -> str:
    """A whole HTML document with inline CSS; ``body_parts`` are already-safe HTML fragments."""
    body = "\n".join(body_parts)
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{esc(title)}</title><style>{CSS}</style></head>"
        f"<body><h1>{esc(title)}</h1>\n{body}\n</body></html>\n"
    )
