"""Every documented command runs as written (issue #49).

A fenced ``bash`` or ``sh`` block of README.md or docs/*.md that follows a marker line
``<!-- runnable -->`` is run by ``bash -euo pipefail`` and must exit 0. The marker convention
(directives, sandbox) is described in docs/architecture.md, "Runnable documentation"; in short::

    <!-- runnable -->
    <!-- runnable: skip "hydrokit cfd" replace "--duration 300" "--duration 5" -->
    <!-- runnable: setup "hydrokit sysid generate --out . --runs 3" needs simpleFoam slow -->

Directives (one or more marker lines right above the fence; their directives add up):

- ``skip "TEXT"``: leave out every command (a line with its ``\\`` continuation lines) whose text
  contains TEXT (synopses with ``[OPTION]`` placeholders, commands needing files we do not ship);
- ``replace "OLD" "NEW"``: substitute text in the block before it runs (shorter durations,
  fewer samples), so the marker itself says what differs from what a user types;
- ``setup "COMMAND"``: run COMMAND before the block (to make an input the page assumes);
- ``needs PROGRAM``: skip, naming PROGRAM, when it is not on PATH (OpenFOAM's ``simpleFoam``);
- ``slow``: the block carries the ``slow`` pytest marker;
- ``timeout SECONDS``: wall-clock limit of the block (default 900 s, a guard against a hang).

Every ``skip`` and ``replace`` must match something, so a marker cannot silently outlive its block.
Each page runs in its own temporary folder (cwd), with ``src`` (and ``.venv``) linked to the
repository's and ``hydrokit`` on PATH from the interpreter that runs pytest; its marked blocks run in
page order in that folder, so a later block can use an earlier block's output.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
MARKER = re.compile(r"^<!--\s*runnable(?::(?P<opts>.*?))?\s*-->\s*$")
FENCE = re.compile(r"^```(?P<lang>[\w+-]*)\s*$")
RUNNABLE_LANGUAGES = ("bash", "sh", "shell")
DEFAULT_TIMEOUT = 900.0  # s per block: a guard against a hang, not the time budget (loaded CI machines are slow)
TAIL = 3000  # characters of stderr/stdout shown on failure


@dataclass
class Block:
    """One marked code block: where it is, its text and its marker's directives."""

    page: Path
    ordinal: int  # 1-based among the page's fenced blocks
    line: int  # 1-based line of the opening fence
    code: str
    skip: list[str] = field(default_factory=list)
    replace: list[tuple[str, str]] = field(default_factory=list)
    setup: list[str] = field(default_factory=list)
    needs: list[str] = field(default_factory=list)
    slow: bool = False
    timeout: float = DEFAULT_TIMEOUT

    @property
    def name(self) -> str:
        return f"{self.page.relative_to(ROOT)}-{self.ordinal}"

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line} (code block {self.ordinal} of the page)"


_ARITY = {"skip": 1, "replace": 2, "setup": 1, "needs": 1, "slow": 0, "timeout": 1}


def _apply_directives(block: Block, text: str) -> None:
    """Add the directives of one marker line to ``block``; ValueError names a bad one."""
    try:
        tokens = shlex.split(text)
    except ValueError as exc:
        raise ValueError(f"marker {text!r}: {exc}") from None
    i = 0
    while i < len(tokens):
        word = tokens[i]
        if word not in _ARITY:
            raise ValueError(f"marker directive {word!r}; expected one of {', '.join(_ARITY)}")
        args = tokens[i + 1 : i + 1 + _ARITY[word]]
        if len(args) < _ARITY[word]:
            raise ValueError(f"marker directive {word!r} needs {_ARITY[word]} argument(s), got {args}")
        i += 1 + _ARITY[word]
        if word == "skip":
            block.skip.append(args[0])
        elif word == "replace":
            block.replace.append((args[0], args[1]))
        elif word == "setup":
            block.setup.append(args[0])
        elif word == "needs":
            block.needs.append(args[0])
        elif word == "slow":
            block.slow = True
        else:
            block.timeout = float(args[0])


def scan(page: Path, text: str | None = None) -> tuple[list[Block], list[str]]:
    """The marked blocks of ``page`` (or of ``text`` as if it were that page) and the problems
    with its markers (as messages)."""
    lines = (page.read_text(encoding="utf-8") if text is None else text).splitlines()
    rel = page.relative_to(ROOT)
    blocks: list[Block] = []
    problems: list[str] = []
    markers: list[tuple[int, str]] = []  # (line number, directives) awaiting their fence
    ordinal = 0
    i = 0
    while i < len(lines):
        line = lines[i]
        marker = MARKER.match(line)
        fence = FENCE.match(line)
        if marker:
            markers.append((i + 1, marker.group("opts") or ""))
        elif fence:
            ordinal += 1
            end = i + 1
            while end < len(lines) and not lines[end].startswith("```"):
                end += 1
            if markers:
                if fence.group("lang") not in RUNNABLE_LANGUAGES:
                    problems.append(f"{rel}:{markers[0][0]}: marker above a {fence.group('lang') or 'plain'} block")
                else:
                    block = Block(page, ordinal, i + 1, "\n".join(lines[i + 1 : end]))
                    try:
                        for _, opts in markers:
                            _apply_directives(block, opts)
                        prepare(block)  # every skip and replace must match
                    except ValueError as exc:
                        problems.append(f"{rel}:{markers[0][0]}: {exc}")
                    else:
                        blocks.append(block)
            markers = []
            i = end
        elif markers and line.strip():
            problems.append(f"{rel}:{markers[0][0]}: marker not directly above a code block")
            markers = []
        i += 1
    if markers:
        problems.append(f"{rel}:{markers[0][0]}: marker not directly above a code block")
    return blocks, problems


def commands(code: str) -> list[str]:
    """The block's commands: each line joined with its backslash continuation lines."""
    out: list[str] = []
    current: list[str] = []
    for line in code.splitlines():
        current.append(line)
        if not line.rstrip().endswith("\\"):
            out.append("\n".join(current))
            current = []
    if current:
        out.append("\n".join(current))
    return out


def prepare(block: Block) -> str:
    """The script that runs: setup commands, then the block without skipped commands, replaced."""
    kept = commands(block.code)
    for text in block.skip:
        hits = [c for c in kept if text in c and not c.lstrip().startswith("#")]
        if not hits:
            raise ValueError(f"skip {text!r} matches no command of the block")
        kept = [c for c in kept if c not in hits]
    script = "\n".join(kept)
    for old, new in block.replace:
        if old not in script:
            raise ValueError(f"replace {old!r} matches nothing in the commands that run")
        script = script.replace(old, new)
    return "\n".join([*block.setup, script])


def _collect() -> tuple[list[Block], list[str]]:
    blocks: list[Block] = []
    problems: list[str] = []
    for page in PAGES:
        b, p = scan(page)
        blocks += b
        problems += p
    return blocks, problems


BLOCKS, PROBLEMS = _collect()


def test_markers_are_well_formed() -> None:
    assert PROBLEMS == []


def test_the_readme_and_the_guides_have_runnable_blocks() -> None:
    pages = {b.page.name for b in BLOCKS}
    assert "README.md" in pages
    # README's sysid example runs on the dives that `hydrokit sysid generate` writes
    readme = "\n".join(prepare(b) for b in BLOCKS if b.page.name == "README.md")
    assert re.search(r"^hydrokit sysid (?!plan|generate)", readme, flags=re.M), readme
    assert len(pages) >= 8, sorted(pages)


def test_scan_reads_the_directives() -> None:
    page = ROOT / "docs" / "probe.md"  # not a file: scan() reads the text given
    text = (
        '<!-- runnable: skip "hydrokit cfd" replace "--duration 300" "--duration 5" -->\n'
        "<!-- runnable: needs simpleFoam slow timeout 20 -->\n"
        "```bash\nhydrokit cfd x \\\n  --out y\nhydrokit simulate v --duration 300\n```\n"
        "<!-- runnable -->\n\ntext\n"
    )
    blocks, problems = scan(page, text)
    assert len(blocks) == 1
    assert prepare(blocks[0]) == "hydrokit simulate v --duration 5"
    assert (blocks[0].needs, blocks[0].slow, blocks[0].timeout) == (["simpleFoam"], True, 20.0)
    assert problems == ["docs/probe.md:8: marker not directly above a code block"]
    stale = '<!-- runnable: skip "nothing" -->\n```bash\nhydrokit demo --out d\n```\n'
    assert scan(page, stale)[1] == ["docs/probe.md:1: skip 'nothing' matches no command of the block"]
    assert scan(page, "<!-- runnable: bogus -->\n```bash\nls\n```\n")[1] == [
        "docs/probe.md:1: marker directive 'bogus'; expected one of skip, replace, setup, needs, slow, timeout"
    ]
    assert scan(page, "<!-- runnable -->\n```yaml\na: 1\n```\n")[1] == ["docs/probe.md:1: marker above a yaml block"]


# --- running the blocks -------------------------------------------------------------------------


@dataclass
class PageRun:
    """A page's sandbox folder and which of its marked blocks have run (and how)."""

    folder: Path
    done: dict[int, subprocess.CompletedProcess[str] | str] = field(default_factory=dict)


def _sandbox(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "src").symlink_to(ROOT / "src", target_is_directory=True)
    if sys.prefix != sys.base_prefix:  # pytest runs in a venv: `.venv/bin/...` as the docs write it
        (folder / ".venv").symlink_to(Path(sys.prefix), target_is_directory=True)
    return folder


def _run(block: Block, folder: Path) -> subprocess.CompletedProcess[str] | str:
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    env["MPLBACKEND"] = "Agg"
    # the failing command is named last on stderr (set -e exits right after the ERR trap)
    script = f"trap 'echo \"documented command failed (exit $?): $BASH_COMMAND\" >&2' ERR\n{prepare(block)}"
    # own session: a timeout ends bash and every hydrokit process it started
    proc = subprocess.Popen(
        ["bash", "-euo", "pipefail", "-c", script],
        cwd=folder,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        out, err = proc.communicate(timeout=block.timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        return f"timed out after {block.timeout:g} s\n--- stderr (tail)\n{err[-TAIL:]}"
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


def _failed(result: subprocess.CompletedProcess[str] | str) -> bool:
    return isinstance(result, str) or result.returncode != 0


def test_a_failing_command_is_named_and_a_hung_block_is_ended(tmp_path: Path) -> None:
    page = ROOT / "docs" / "probe.md"  # not a file: the blocks are built here
    failing = Block(page, 1, 1, "true\nls no-such-file \\\n  --color=never\necho never reached")
    result = _run(failing, tmp_path)
    assert isinstance(result, subprocess.CompletedProcess) and result.returncode != 0
    assert result.stderr.strip().splitlines()[-1].startswith("documented command failed (exit 2): ls no-such-file")
    assert "never reached" not in result.stdout
    hung = Block(page, 2, 1, "echo started >&2\nsleep 30 & wait", timeout=1.0)
    started = time.monotonic()
    message = _run(hung, tmp_path)
    assert isinstance(message, str) and message.startswith("timed out after 1 s") and "started" in message
    assert time.monotonic() - started < 20.0  # killed with its children, not waited for


@pytest.fixture(scope="module")
def page_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[Path, PageRun]:
    root = tmp_path_factory.mktemp("docs-commands")
    return {p: PageRun(_sandbox(root / p.stem)) for p in PAGES}


def _params() -> list[object]:
    out = []
    for b in BLOCKS:
        marks = [
            pytest.mark.needs_jit(reason="runs the documented commands as subprocesses, which add no coverage"),
        ]
        if b.slow:
            marks.append(pytest.mark.slow)
        out.append(pytest.param(b, id=b.name, marks=marks))
    return out


@pytest.mark.parametrize("block", _params())
def test_documented_command_runs(block: Block, page_runs: dict[Path, PageRun]) -> None:
    missing = [p for p in block.needs if shutil.which(p) is None]
    if missing:
        pytest.skip(f"{block.where} needs {', '.join(missing)} (not on PATH)")
    state = page_runs[block.page]
    # the page's earlier blocks first (they may make this block's inputs), once each
    earlier = [b for b in BLOCKS if b.page == block.page and b.ordinal < block.ordinal]
    for b in earlier:
        if b.ordinal not in state.done and not b.slow and not [p for p in b.needs if shutil.which(p) is None]:
            state.done[b.ordinal] = _run(b, state.folder)
    result = _run(block, state.folder)
    state.done[block.ordinal] = result
    if _failed(result):
        before = [b.where for b in earlier if b.ordinal in state.done and _failed(state.done[b.ordinal])]
        detail = (
            result
            if isinstance(result, str)
            else f"exit {result.returncode}\n--- stderr (tail)\n{result.stderr[-TAIL:]}\n"
            f"--- stdout (tail)\n{result.stdout[-TAIL:]}"
        )
        pytest.fail(
            f"{block.where} failed in {state.folder}: {detail}\n--- script\n{prepare(block)}"
            + (f"\n(earlier blocks of the page that failed: {'; '.join(before)})" if before else ""),
            pytrace=False,
        )
    assert isinstance(result, subprocess.CompletedProcess) and result.returncode == 0
