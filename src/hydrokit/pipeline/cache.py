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


# -- the run folder's own files --------------------------------------------------------------
#
# The report and the files beside it are cached like a step: OUT/.cache/report.json holds the
# key of the run that wrote them (every input file's hash, the options, hydrokit's source) and
# the SHA-256 of each file as written. A re-run whose key matches, with every file still as
# written, renders and writes nothing.

#: the stamp of the run folder's files, in OUT/.cache
STAMP = "report.json"


def run_key(digests: dict[str, str], bem: bool, samples: int) -> str:
    """Key of a whole run: the input files' SHA-256 (path → hex, as ``Runner.digests``), the
    options that change its outputs (``bem``; ``samples``: Monte Carlo count), the cache format
    and hydrokit's source. Workers and the scheduler change how, not what, and are left out."""
    files = sorted((os.path.abspath(path), sha) for path, sha in digests.items())
    return digest("run", files, bool(bem), int(samples))


def project_key(project: Any, bem: bool = False, samples: int | None = None) -> str:
    """:func:`run_key` of a parsed :class:`hydrokit.io.project.Project` (its input files hashed
    now; ``samples`` None = the project's)."""
    digests = {str(p): file_digest(p) for p in project.input_files()}
    return run_key(digests, bem, project.samples if samples is None else samples)


def outputs_current(out_dir: str | os.PathLike[str], key: str) -> bool:
    """True when ``out_dir`` holds the files of the run with ``key``, each byte for byte as
    that run wrote it (see :func:`record_outputs`)."""
    out = Path(out_dir)
    try:
        stamp = json.loads((out / ".cache" / STAMP).read_text(encoding="utf-8"))
        files = stamp["files"]
        if stamp.get("key") != key or not isinstance(files, dict) or not files:
            return False
        return all(file_digest(out / name) == sha for name, sha in files.items())
    except (OSError, ValueError, KeyError, TypeError):
        return False


def record_outputs(out_dir: str | os.PathLike[str], key: str, names: list[str]) -> None:
    """Write the stamp of the files ``names`` (relative to ``out_dir``) of the run with ``key``."""
    out = Path(out_dir)
    doc = {"key": key, "files": {name: file_digest(out / name) for name in names}}
    write_bytes(out / ".cache" / STAMP, (json.dumps(doc, indent=1, sort_keys=True) + "\n").encode("utf-8"))
