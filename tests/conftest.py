"""Shared fixtures.

``run_cli(*args)`` runs the ``hydrokit`` command in-process through the real entry point
(:func:`hydrokit.cli.main.main`, with its error handling) and returns (exit_code, stdout, stderr).

Headless-Chromium checks for the self-contained HTML reports (see the "Headless Chromium" section
below; these are fixtures because, with ``--import-mode=importlib``, helper modules under tests/
are not importable by test modules):

``require_chromium`` -- path of the Chromium binary; skips the test when none is installed.
``open_in_chromium(html_path, screenshot, width=1280, height=2400)`` -- load a local HTML file
    (file:// only, network blocked) and return a :class:`BrowserPage` (``.dom``, ``.console``,
    ``.errors``, ``.screenshot``, ``.images``, ``.text(tag)``). Skips when Chromium is absent.
``figures_ok(page)`` -- list of problems (empty when fine): every ``<img>`` is an inline data URI
    that decodes to a non-empty, non-blank image, and the screenshot is a non-blank PNG.
"""

from __future__ import annotations

import base64
import binascii
import io
import os
import re
import shutil
import signal
import subprocess
import tempfile
import urllib.parse
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import settings

# CI runs the same examples every time (reproducible); locally hypothesis explores freely
settings.register_profile("ci", derandomize=True, deadline=None)
if os.environ.get("CI"):
    settings.load_profile("ci")

REFERENCE = Path(__file__).parent / "reference"

# --- Without the JIT (.ci/coverage) -------------------------------------------------------------
#
# .ci/coverage runs the compiled kernels' tests with NUMBA_DISABLE_JIT=1 so that line coverage sees
# the kernels' bodies (anyone may run any test so); they then run as plain Python, 50-500x slower.
# Tests whose cost is a long compiled loop (and whose assertions depend on its length, so it
# cannot simply be shortened) carry
# ``@pytest.mark.needs_jit(reason=...)`` and are skipped there; .ci/run still runs them compiled.
JIT_OFF = os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0")
NEEDS_JIT_REASON = "NUMBA_DISABLE_JIT is set: too slow as interpreted Python (runs in the JIT suite)"


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "needs_jit(reason): skipped under NUMBA_DISABLE_JIT=1 (a long compiled loop; see tests/conftest.py)"
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if not JIT_OFF:
        return
    for item in items:
        mark = item.get_closest_marker("needs_jit")
        if mark is not None:
            why = mark.kwargs.get("reason") or (mark.args[0] if mark.args else "")
            item.add_marker(pytest.mark.skip(reason=f"{NEEDS_JIT_REASON}; {why}" if why else NEEDS_JIT_REASON))


@pytest.fixture
def run_cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., tuple[int, str, str]]:
    from hydrokit.cli.main import main

    def _run(*args: object) -> tuple[int, str, str]:
        capsys.readouterr()
        code = main([str(a) for a in args])
        out, err = capsys.readouterr()
        return code, out, err

    return _run


@pytest.fixture(scope="session")
def published() -> dict:
    """Numbers printed in the source works (copied from the project's spec; see SPEC.md)."""
    return yaml.safe_load((REFERENCE / "published_results.yaml").read_text())


@pytest.fixture(scope="session")
def lingyun_reference() -> dict:
    """LI2021 Table 1 and Table 4 as printed."""
    return yaml.safe_load((REFERENCE / "li2021_lingyun.yaml").read_text())


# --- Headless Chromium ------------------------------------------------------------------------
#
# Usage in a report test (all three are fixtures; request them as arguments):
#
#     def test_my_report(tmp_path, open_in_chromium, figures_ok):
#         page = open_in_chromium(tmp_path / "report.html", tmp_path / "report.png")
#         assert page.errors == [], page.console
#         assert figures_ok(page) == []
#
# Chromium runs twice per page (one ``--screenshot``, one ``--dump-dom``), each with a fresh
# ``--user-data-dir`` and a hard time limit, with DNS and proxying pointed at nothing so a report
# that tries to fetch anything from the network gets an error instead.

CHROMIUM_SKIP_REASON = "headless Chromium not found (apt-get install -y chromium); the report's browser test needs it"
CHROMIUM_TIMEOUT = 60.0  # seconds per Chromium run; a hung browser fails the test instead of hanging it
CHROMIUM_FLAGS = (
    "--headless=new",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--allow-file-access-from-files",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
    "--disable-sync",
    "--disable-background-networking",
    "--disable-component-update",
    # no network: every host name fails to resolve and every non-loopback request goes to a dead proxy
    "--host-resolver-rules=MAP * ~NOTFOUND",
    "--proxy-server=127.0.0.1:9",
    # console messages (console.log/warn/error and uncaught exceptions) are written to stderr
    "--enable-logging=stderr",
    "--v=0",
)
_CONSOLE_LINE = re.compile(r"^\[[^\]]*:CONSOLE[^\]]*\]\s?(?P<message>.*)$")
_ERROR_WORDS = re.compile(r"uncaught|error|exception|failed", re.IGNORECASE)
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


class _DomParser(HTMLParser):
    """Collects the attributes of every ``<img>`` and the text of every element, by tag."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.images: list[dict[str, str | None]] = []
        self.texts: dict[str, list[str]] = {}
        self._open: list[tuple[str, list[str]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "img":
            self.images.append(dict(attrs))
        elif tag not in {"br", "hr", "meta", "link", "input", "source", "col", "area", "base", "wbr"}:
            self._open.append((tag, []))

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "img":
            self.images.append(dict(attrs))

    def handle_endtag(self, tag: str) -> None:
        # close up to the most recent matching start tag (tolerates unclosed <p>, <li>, ...)
        for i in range(len(self._open) - 1, -1, -1):
            if self._open[i][0] == tag:
                for name, parts in reversed(self._open[i:]):
                    self.texts.setdefault(name, []).append(" ".join("".join(parts).split()))
                del self._open[i:]
                return

    def handle_data(self, data: str) -> None:
        for _, parts in self._open:
            parts.append(data)


@dataclass(frozen=True)
class BrowserPage:
    """What headless Chromium made of a local HTML file.

    ``dom``: the serialized DOM after scripts ran (``--dump-dom``).
    ``console``: console messages Chromium logged while loading the page, in order, e.g.
        ``'"Uncaught ReferenceError: f is not defined", source: file:///.../report.html (12)'``.
        Chromium's stderr log tags console.log/warn/error alike, so the level is not available.
    ``screenshot``: the PNG screenshot of the first ``width`` x ``height`` CSS pixels.
    ``url``: the file:// URL that was loaded.
    """

    dom: str
    console: list[str]
    screenshot: Path
    url: str
    _parsed: _DomParser = field(repr=False, compare=False)

    @property
    def errors(self) -> list[str]:
        """Console messages that look like errors: uncaught exceptions, or mentioning error/exception/failed."""
        return [m for m in self.console if _ERROR_WORDS.search(m)]

    @property
    def images(self) -> list[dict[str, str | None]]:
        """Attributes of every ``<img>`` in the DOM, in document order (e.g. ``img["src"]``, ``img["alt"]``)."""
        return self._parsed.images

    def text(self, tag: str) -> list[str]:
        """Whitespace-normalized text content of every ``<tag>`` element in the DOM, e.g. ``page.text("h1")``."""
        return list(self._parsed.texts.get(tag.lower(), []))


def _chromium_binary() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _run_chromium(args: list[str], what: str) -> subprocess.CompletedProcess[str]:
    """Run Chromium in its own process group; on timeout kill the whole group and fail the test."""
    proc = subprocess.Popen(
        args,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        errors="replace",
        start_new_session=True,
    )
    try:
        out, err = proc.communicate(timeout=CHROMIUM_TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"headless Chromium hung for more than {CHROMIUM_TIMEOUT:.0f} s ({what})", pytrace=False)
    finally:
        # renderer/GPU helpers that outlived the browser process
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    if proc.returncode != 0:
        tail = "\n".join(err.splitlines()[-20:])
        pytest.fail(f"headless Chromium exited with {proc.returncode} ({what}):\n{tail}", pytrace=False)
    return subprocess.CompletedProcess(args, proc.returncode, out, err)


def _open_in_chromium(
    binary: str, html_path: Path, screenshot: Path, width: int = 1280, height: int = 2400
) -> BrowserPage:
    html_path = Path(html_path).resolve()
    if not html_path.is_file():
        pytest.fail(f"no HTML file at {html_path}", pytrace=False)
    screenshot = Path(screenshot).resolve()
    screenshot.parent.mkdir(parents=True, exist_ok=True)
    screenshot.unlink(missing_ok=True)
    url = html_path.as_uri()
    with tempfile.TemporaryDirectory(prefix="chromium-profile-", ignore_cleanup_errors=True) as profile:

        def run(*extra: str, what: str) -> subprocess.CompletedProcess[str]:
            user_data = Path(profile) / what.replace(" ", "-")
            flags = [*CHROMIUM_FLAGS, f"--user-data-dir={user_data}", f"--window-size={width},{height}"]
            return _run_chromium([binary, *flags, *extra, url], what)

        run(f"--screenshot={screenshot}", what="screenshot")
        dumped = run("--dump-dom", what="dump dom")
    if not screenshot.is_file() or screenshot.stat().st_size == 0:
        pytest.fail(f"headless Chromium wrote no screenshot to {screenshot}", pytrace=False)
    if screenshot.read_bytes()[:8] != _PNG_SIGNATURE:
        pytest.fail(f"the screenshot {screenshot} is not a PNG", pytrace=False)
    console = []
    for line in dumped.stderr.splitlines():
        match = _CONSOLE_LINE.match(line)
        if match:
            console.append(match["message"])
        elif "Uncaught" in line:
            console.append(line.strip())
    parsed = _DomParser()
    parsed.feed(dumped.stdout)
    parsed.close()
    return BrowserPage(dom=dumped.stdout, console=console, screenshot=screenshot, url=url, _parsed=parsed)


def _decode_data_uri(src: str) -> tuple[str, bytes]:
    """(media type, payload) of a ``data:`` URI; raises ValueError when malformed."""
    header, sep, payload = src[len("data:") :].partition(",")
    if not sep:
        raise ValueError("no ',' in the data URI")
    params = header.split(";")
    media = params[0].strip().lower() or "text/plain"
    if "base64" in (p.strip().lower() for p in params[1:]):
        try:
            return media, base64.b64decode(urllib.parse.unquote(payload), validate=True)
        except binascii.Error as e:
            raise ValueError(f"bad base64 ({e})") from e
    return media, urllib.parse.unquote_to_bytes(payload)


def _image_problem(media: str, data: bytes) -> str | None:
    """Why the embedded image is unusable, or None when it decodes to a non-empty, non-blank picture."""
    if not data:
        return "empty payload"
    if media == "image/svg+xml":
        try:
            root = ET.fromstring(data)
        except ET.ParseError as e:
            return f"SVG does not parse ({e})"
        return None if root.tag.rsplit("}", 1)[-1] == "svg" else f"SVG root is <{root.tag}>, not <svg>"
    from PIL import Image  # matplotlib's own dependency

    try:
        with Image.open(io.BytesIO(data)) as im:
            im.load()
            if im.width == 0 or im.height == 0:
                return f"decodes to a {im.width}x{im.height} image"
            extrema = im.convert("RGBA").getextrema()
    except Exception as e:  # any decoder error is the finding
        return f"does not decode as {media} ({type(e).__name__}: {e})"
    if all(lo == hi for lo, hi in extrema):
        return "is a single colour (blank figure)"
    return None


def _screenshot_problem(path: Path) -> str | None:
    import matplotlib.image

    if not path.is_file() or path.stat().st_size == 0:
        return f"screenshot {path} is missing or empty"
    if path.read_bytes()[:8] != _PNG_SIGNATURE:
        return f"screenshot {path} is not a PNG"
    pixels = np.asarray(matplotlib.image.imread(path), dtype=float)
    flat = pixels.reshape(-1, pixels.shape[-1]) if pixels.ndim == 3 else pixels.reshape(-1, 1)
    if flat.size == 0:
        return f"screenshot {path} has no pixels"
    if np.all(flat == flat[0]) or float(flat.std()) < 1e-3:
        return f"screenshot {path} is blank (one colour): the page rendered nothing"
    return None


def _figures_ok(page: BrowserPage) -> list[str]:
    problems = []
    for i, img in enumerate(page.images, start=1):
        label = f"<img> #{i}" + (f" ({img['alt']!r})" if img.get("alt") else "")
        src = (img.get("src") or "").strip()
        if not src:
            problems.append(f"{label} has no src")
            continue
        if not src.lower().startswith("data:"):
            problems.append(f"{label} is not embedded (src={src[:80]!r}); a self-contained report inlines figures")
            continue
        try:
            media, data = _decode_data_uri(src)
        except ValueError as e:
            problems.append(f"{label}: malformed data URI: {e}")
            continue
        problem = _image_problem(media, data)
        if problem:
            problems.append(f"{label} {problem}")
    screenshot = _screenshot_problem(page.screenshot)
    if screenshot:
        problems.append(screenshot)
    return problems


@pytest.fixture
def require_chromium() -> str:
    """Path of the headless-Chromium binary (``chromium`` or ``chromium-browser``); skips the test when absent."""
    binary = _chromium_binary()
    if binary is None:
        pytest.skip(CHROMIUM_SKIP_REASON)
    return binary


@pytest.fixture
def open_in_chromium(require_chromium: str) -> Callable[..., BrowserPage]:
    """``open_in_chromium(html_path, screenshot, width=1280, height=2400) -> BrowserPage``.

    Loads ``html_path`` (a local file, as a file:// URL; the network is blocked) in headless Chromium
    with a ``width`` x ``height`` window, writes the PNG screenshot to ``screenshot`` and returns the DOM
    after scripts ran and the console messages. Fails the test (not hangs) if Chromium takes more than
    60 s or exits non-zero; skips it when Chromium is not installed.
    """

    def _open(html_path: Path, screenshot: Path, width: int = 1280, height: int = 2400) -> BrowserPage:
        return _open_in_chromium(require_chromium, html_path, screenshot, width, height)

    return _open


@pytest.fixture
def figures_ok() -> Callable[[BrowserPage], list[str]]:
    """``figures_ok(page) -> list[str]``: the problems found, empty when every figure is fine.

    Checks every ``<img>`` in ``page.dom``: it must be an inline ``data:`` URI (the reports are
    self-contained) whose payload decodes (PNG/JPEG/GIF/WebP with Pillow, SVG as XML) to a non-empty
    image that is not a single colour; and the page screenshot must be a PNG that is not one colour.
    """
    return _figures_ok
