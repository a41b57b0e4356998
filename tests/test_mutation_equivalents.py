"""bench/mutation.py's EQUIVALENT list stays honest: every entry names a mutant the runner makes.

An entry whose code line was edited away would match nothing and hide nothing, but it would
also no longer say what it excuses; a typo in one would leave its mutant counted as a
survivor while the reader believes it excused.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _runner():
    spec = importlib.util.spec_from_file_location("mutation_runner", ROOT / "bench" / "mutation.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_every_equivalent_entry_names_a_mutant_and_gives_a_reason():
    runner = _runner()
    keys = {m.key for m in runner.all_mutants(list(runner.PACKAGES))}
    stale = [k for k in runner.EQUIVALENT if k not in keys]
    assert not stale, f"EQUIVALENT entries that match no mutant: {stale}"
    assert all(len(reason) > 20 for reason in runner.EQUIVALENT.values())


def test_an_inferred_reshape_size_keeps_its_sign_mutant_only():
    # reshape(-1) and reshape(-2) are the same call to numpy, so the runner does not make the
    # 1 -> 2 mutant; dropping the minus (reshape(1), a different shape) is still made
    runner = _runner()
    path = ROOT / "src" / "hydrokit" / "model" / "guidance.py"
    code = "s = np.asarray(self.speeds, dtype=float).reshape(-1)"
    assert code in path.read_text()
    whats = {m.key[2] for m in runner.module_mutants(path, "model") if m.key[1] == code}
    assert "drop unary -" in whats
    assert not any(w.startswith("1 -> ") for w in whats)


def test_a_default_value_belongs_to_the_scope_that_defines_its_function():
    # ThrustCurve.command is abstract: its body never runs, but its default advance_speed = 0.0 is
    # evaluated when the class is made. Its mutant must be tested by the tests that import the
    # module (scope 0), not by the (no) tests that run the body; a body line keeps its function
    runner = _runner()
    path = ROOT / "src" / "hydrokit" / "model" / "thrusters.py"
    lines = path.read_text().splitlines()
    mutants = runner.module_mutants(path, "model")
    line = next(
        i for i, s in enumerate(lines, 1) if "def command(self, thrust: float, advance_speed: float = 0.0)" in s
    )
    assert {m.scope for m in mutants if m.line == line} == {0}
    body = next(i for i, s in enumerate(lines, 1) if "if g_hi <= 0.0:  # even the speed limit" in s)
    assert all(m.scope > 0 for m in mutants if m.line == body)
