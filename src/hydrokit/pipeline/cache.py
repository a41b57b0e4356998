"""Step cache of ``hydrokit run``: each step's output stored as JSON under the hash of its inputs.

A step's key is the SHA-256 of everything it reads — file bytes, options, the outputs of the
steps before it — and of hydrokit's own source, so a re-run skips exactly what is up to date and redoes
what changed. Entries are plain JSON (never pickle) written atomically; a failed step leaves the
entries of the steps before it in place.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from pathlib import Path
from typing import Any

from hydrokit._atomic import write_bytes

#: bump when a step's output layout changes, so old entries are not read back
CACHE_FORMAT = 1


def file_digest(path: str | os.PathLike[str]) -> str:
    """SHA-256 (hex) of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """SHA-256 of hydrokit's own source files: a changed or upgraded hydrokit redoes the steps
    (a version number alone misses a developer's edits)."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def digest(*parts: Any) -> str:
    """SHA-256 (hex) of JSON-serialisable parts (sorted keys; paths as text), the cache format
    and the code fingerprint."""
    text = json.dumps([CACHE_FORMAT, code_fingerprint(), *parts], sort_keys=True, default=str, allow_nan=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


class StepCache:
    """JSON entries ``DIR/<step>-<key16>.json``; ``force`` ignores (and overwrites) old entries.

    Parameters
    ----------
    directory : folder of the entries (created on the first store)
    force : bool — recompute every step
    """

    def __init__(self, directory: str | os.PathLike[str], force: bool = False):
        self.directory = Path(directory)
        self.force = force
        self.hits: list[str] = []

    def _path(self, step: str, key: str) -> Path:
        safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in step)
        return self.directory / f"{safe}-{key[:16]}.json"

    def load(self, step: str, key: str) -> Any | None:
        """The stored output of ``step`` for ``key``, or None (missing, forced, or unreadable)."""
        if self.force:
            return None
        path = self._path(step, key)
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(doc, dict) or doc.get("key") != key:
            return None
        self.hits.append(step)
        return doc.get("output")

    def store(self, step: str, key: str, output: Any) -> None:
        """Store ``output`` (JSON-serialisable) for ``step``; older entries of the step are removed."""
        path = self._path(step, key)
        text = json.dumps({"step": step, "key": key, "output": output}, allow_nan=False)
        write_bytes(path, text.encode("utf-8"))
        for old in self.directory.glob(f"{path.name.rsplit('-', 1)[0]}-*.json"):
            if old != path and len(old.stem) == len(path.stem):
                old.unlink(missing_ok=True)
