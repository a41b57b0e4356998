"""Mutation score of the physics packages (issue #13, "Trust"): does the suite notice a wrong line?

    python bench/mutation.py [--package core identify model estimate] [--sample N] [--seed S]
                             [--jobs J] [--scope suite|package] [--only TEXT …] [--list]
                             [--json FILE] [--previous FILE] [--trace FILE]

    # nightly: every mutant, the whole suite
    python bench/mutation.py --jobs 2 --json mutation.json
    # a quick estimate: 40 seeded mutants per package against the mirrored test folders
    python bench/mutation.py --sample 40 --scope package --jobs 2 --json before.json
    # after adding tests: the same mutants again, only the survivors rerun
    python bench/mutation.py --previous before.json --scope package --jobs 2

A small self-contained mutation runner: standard library and pytest only (mutmut and
cosmic-ray are not project dependencies; ``pip install mutmut`` and a ``[tool.mutmut]`` table
would do the same job, slower, as mutmut 3 reruns its own per-test statistics in a
``mutants/`` copy). For each module of ``src/hydrokit/{core,identify,model,estimate}`` it walks the
``ast`` and makes one-change mutants:

- arithmetic ``+ ↔ −``, ``* ↔ /``, ``** → *``, ``// → /``, ``% → *`` (also in ``+=`` …),
- comparisons ``< ↔ <=``, ``> ↔ >=``, ``== ↔ !=``, ``is ↔ is not``, ``in ↔ not in``,
- ``and ↔ or``, a dropped unary ``−`` or ``not``,
- numeric constants n → n + 1 (``True ↔ False``).

Strings, f-strings, docstrings, annotations and the arguments of ``raise`` are left alone (a
changed message is not a physics error). Each mutant is written into a private copy of the
project (one per job, so the working tree is never touched), and only the tests that reach the
mutated code run there, with ``-x`` and a timeout: a failing (or crashing) run kills the mutant,
a timeout counts as killed (reported apart), a green run is a survivor.

Which tests reach which code comes from one traced run of the unmutated tests (a
``sys.setprofile`` hook records, per test, the hydrokit functions it calls, and the test's
duration; no coverage package needed): a mutant inside a function runs the tests that called
that function; one at module level, or inside a numba-compiled function (invisible to the
hook), runs every test that called anything in its module or imports it. A mutant in a
function no test calls is reported as ``uncovered`` (a survivor) without running anything.
Tests that already fail unmutated are left out, with a warning.

Equivalent mutants (no input can tell them apart from the original) are excluded from the
score only through :data:`EQUIVALENT` below, each with its reason.

The score printed per package is killed / (mutants − equivalent), with a 95 % Wilson interval
when ``--sample`` draws a seeded random subset. The full run is a slow job (thousands of
mutants, hours on 2 cores): run it nightly, not in CI's 15 minutes. Issue #13 asks ≥ 90 %.
"""

from __future__ import annotations

import argparse
import ast
import copy
import json
import math
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("core", "identify", "model", "estimate")
#: --scope package: the mirrored test folders of each package (faster; core is exercised through
#: the model and estimate tests); --scope suite (default): the whole suite, as issue #13 counts
PACKAGE_TESTS = {
    "core": ("tests/core", "tests/model", "tests/estimate"),
    "identify": ("tests/identify",),
    "model": ("tests/model",),
    "estimate": ("tests/estimate",),
}
TESTS = dict.fromkeys(PACKAGES, ("tests",))
#: copied into each job's private tree (tests read docs/ and the bundled data under src/)
COPY = ("src", "tests", "docs", "bench", "pyproject.toml", "README.md")


#: (file relative to src/hydrokit, stripped source line, mutation) → why no test can kill it
def _alike(path: str, reason: str, *mutants: tuple[str, str]) -> dict[tuple[str, str, str], str]:
    """One reason for several mutants of a module, each given as (code, what)."""
    return {(path, code, what): reason for code, what in mutants}


EQUIVALENT: dict[tuple[str, str, str], str] = {
    **{
        ("identify/rig_model.py", "nz = 2 + 2 * ns", what): (
            "the rig integrator's buffers grow past the 2 + 2 ns augmented states: the right-hand side "
            "writes and reads only those, the outputs copy only z[0], z[1] and z[2 + 2j] (j < ns), so the "
            "extra entries are integrated from unset scratch and never read"
        )
        for what in ("2 -> 3 [1]", "2 -> 3 [2]")
    },
    ("core/rigid_body.py", "M[0:3, 3:6] = -mass * S", "6 -> 7"): (
        "M is 6 × 6: numpy clips the slice 3:7 to 3:6, the same block"
    ),
    ("core/rigid_body.py", "H[0:3, 3:6] = skew(r).T", "6 -> 7"): (
        "H is 6 × 6: numpy clips the slice 3:7 to 3:6, the same block"
    ),
    ("core/drag.py", "P[:, 6:9] = P[:, 6:9] @ absR.T", "9 -> 10 [1]"): (
        "P has PACKED_WIDTH = 9 columns: numpy clips the slice 6:10 to 6:9, the same columns"
    ),
    (
        "identify/virtual_rig.py",
        "zero = rng.uniform(-0.5, 0.5) * self.resolution if self.random_zero else 0.0",
        "0.5 -> 1.5 [2]",
    ): (
        "the quantiser round((y + z)/r)·r − z is periodic in the zero z with period r: a zero uniform over "
        "two resolution steps gives the same output distribution as over one (only a seed-exact replay differs)"
    ),
    ("identify/estimators.py", "pk = [(tp, a) for tp, a in peaks if math.copysign(1.0, a) == sign]", "== -> !="): (
        "the loop runs over both signs and the rows are sorted by time after it: != takes the negative "
        "extremes first and the positive second, the same rows"
    ),
    ("identify/estimators.py", "shift = float(coef[-1]) / float(coef[0]) if coef[0] != 0 else 0.0", "0 -> 1 [2]"): (
        "coef[0] is the fitted ω² (1/s²): != 1 differs from != 0 only for a fit landing on exactly 0 or 1 "
        "to the last bit (probability 0 with any noise)"
    ),
    ("identify/estimators.py", "shift = float(coef[-1]) / float(coef[0]) if coef[0] != 0 else 0.0", "0.0 -> 1.0"): (
        "the else branch needs a fitted ω² of exactly 0.0 (probability 0 with any noise)"
    ),
    (
        "identify/estimators.py",
        "slow = acf is not None and acf >= 0.3 and acf_half is not None and acf_half > acf - 0.5",
        ">= -> >",
    ): ("differs only for an autocorrelation of exactly 0.3 to the last bit (probability 0): the verdict's edge"),
    **_alike(
        "identify/split.py",
        "a shortcut: a motion of fewer than MIN_SAMPLES = 20 samples after the hold (or of exactly 20) is "
        "refused a few lines on by trim_launch or check_record (too few samples after trimming, or not two "
        "cycles of decay in them), whose InputError the loop catches and skips just the same",
        ("if stop - b < MIN_SAMPLES:", "- -> +"),
        ("if stop - b < MIN_SAMPLES:", "< -> <="),
    ),
    ("identify/result.py", 'ci_txt = f" [{ci[0]:.4g}, {ci[1]:.4g}]" if ci[0] is not None else ""', "0 -> 1"): (
        "a summary's interval is (None, None) or two numbers: ci[1] is None exactly when ci[0] is"
    ),
    (
        "model/thrusters.py",
        "n = (lo * g_hi - hi * g_lo) / (g_hi - g_lo) if it < 20 else 0.5 * (lo + hi)",
        "< -> <=",
    ): (
        "the 21st step of the bracketed root search takes false position instead of bisection: both keep "
        "the sign-change bracket and stop at the same tolerance (1e-12 of f or of n_max)"
    ),
    (
        "model/allocation.py",
        "self.Q: Array | None = np.where(reach > 0, 1.0 / np.where(reach > 0, reach, 1.0), 1.0)",
        "> -> >= [1]",
    ): ("where reach == 0 the inner np.where already gives 1/1.0 = 1.0, the outer default"),
    **{
        ("model/control.py", code, op): (
            "with the error of this sense the new integral moves away from the limit's side (e ≥ 0: it does "
            "not decrease; e ≤ 0: it does not increase), so max/min with the previous value returns it "
            "unchanged: the clamp is a no-op for e = 0 and for the other sense alike"
        )
        for code, op in (
            ("if ki > 0 and raw > output_max and e < 0:", "0 -> 1 [2]"),
            ("elif ki > 0 and raw < output_min and e > 0:", "> -> >= [2]"),
        )
    },
    (
        "model/dynamics.py",
        "cor = coriolis_force(p.Mc, nr, symmetric=True)  # p.Mc was symmetrised once in pack()",
        "True -> False",
    ): ("p.Mc is exactly symmetric (pack() stores ½(M + Mᵀ)): symmetrising it again gives ½(a + a) = a bit for bit"),
    (
        "model/guidance.py",
        "if math.sqrt(b0 * b0 + b1 * b1 + b2 * b2) <= acceptance_radius or s >= 1.0:",
        ">= -> >",
    ): (
        "differs only when the projection on the leg lands on its end to the last bit (s = 1.0 exactly): probability 0"
    ),
    (
        "model/allocation.py",
        "self.thrust_scale = max(float(np.max(np.abs(np.concatenate([lo, hi])))), 1.0)",
        "1.0 -> 2.0",
    ): (
        "only sets the slack (1e-8 × scale) of the check that stage 2 kept stage 1's residual, which it does by "
        "construction (the fallback is the defensive 'pragma: no cover' branch): a slack of 1e-8 or 2e-8 N "
        "picks stage 2 all the same"
    ),
    ("model/thrusters.py", "if norm < 1e-12:", "< -> <="): (
        "differs only for a direction whose length is exactly 1e-12 to the last bit"
    ),
    (
        "estimate/composite.py",
        "DQ_out = np.diag(np.asarray(shifted, float) + _shifted_diagonal(_own_elements(parts), slice(6, 9))).copy()",
        "9 -> 10",
    ): ("the packed drag table has PACKED_WIDTH = 9 columns: numpy clips slice(6, 10) to 6:9"),
    **_alike(
        "estimate/shapes.py",
        "a table's last row (1e9, value) stands for the infinite ratio: _interp drops rows at or above 1e8 "
        "from the finite part and reads only that row's value, never its abscissa",
        (
            "CYL_TRANSVERSE_CA = ((1.2, 0.62), (2.5, 0.78), (5.0, 0.90), (9.0, 0.96), (1e9, 1.0))",
            "1000000000.0 -> 1000000001.0",
        ),
        ("(1e9, 1.0),", "1000000000.0 -> 1000000001.0"),
    ),
    (
        "estimate/geometry.py",
        '{"name": n, "position": r(row[0:3]), "linear": r(row[3:6]), "quadratic": r(row[6:9])}',
        "9 -> 10",
    ): ("row is a packed drag element of core.drag, PACKED_WIDTH = 9 entries: the slice 6:10 is 6:9"),
    (
        "model/allocation.py",
        "if _norm_diff(T @ g, target) <= _norm_diff(T @ f, target):",
        "<= -> <",
    ): (
        "differs only when a free thruster's exact KKT force lands on its limit to the last bit, a thruster "
        "the active-set test (within tol of the limit) has just called free: then f, within tol of the same "
        "point, is returned instead"
    ),
    ("estimate/mesh.py", 'vol = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0', "6.0 -> 7.0"): (
        "solid_inertia uses the tetrahedra's volumes only in ratios (centroid Σ V s / 4ΣV, inertia "
        "scaled by mass / ΣV): a common factor on every V cancels"
    ),
    ("core/rigid_body.py", "M[3:6, 0:3] = mass * S", "6 -> 7"): ("M is 6×6: the slice 3:7 is 3:6"),
    ("model/control.py", "if ki > 0 and raw > output_max and e < 0:", "0 -> 1 [1]"): (
        "with 0 ≤ e < 1 the branch runs too, but there the integral only grew (I + e dt ≥ I), and "
        "max(I + e dt, min(I, at_limit)) keeps it: the output is unchanged"
    ),
    ("identify/rig_model.py", "th = np.linspace(0.0, 2.0 * math.pi, 257)[:-1]", "2.0 -> 3.0"): (
        "every restoring shape is odd, so ρ(a cos θ) cos θ has period π: its mean over 256 even samples "
        "of [0, 3π) equals the mean over [0, 2π)"
    ),
    ("identify/preprocess.py", "if q0 * v0 > 0:", "* -> /"): (
        "q0/v0 > 0 iff q0 and v0 have one sign, as q0·v0 > 0; at v0 = 0 exactly (numpy floats: ±inf or "
        "nan) the branch may run, but its shift atan(0)/ω_d is zero"
    ),
    **_alike(
        "core/drag.py",
        "P is reshaped to (-1, PACKED_WIDTH) = 9 columns a few lines above: the slice 6:10 is 6:9",
        ("P[:, 6:9] = P[:, 6:9] @ absR.T", "9 -> 10 [1]"),
        ("P[:, 6:9] = P[:, 6:9] @ absR.T", "9 -> 10 [2]"),
    ),
    **_alike(
        "model/thrusters.py",
        "a clamp written as a conditional: where J equals the bound, both branches give the same value",
        ("J = j_lo if j_lo > J else J  # max(J, j_lo)", "> -> >="),
        ("J = j_hi if j_hi < J else J  # min(J, j_hi)", "< -> <="),
    ),
    ("identify/rig_model.py", "if abs(net) <= 1e-9 * max(rig.weight, rig.buoyancy, 1e-30) * r:", "<= -> <"): (
        "differs only when the net restoring moment is exactly 1e-9 of W·r to the last bit"
    ),
    (
        "identify/estimators.py",
        'np.array([w2, max(b, 0.0), max(g, 0.0), y[0] - facts["offset"], 0.0, facts["offset"]])',
        "0 -> 1",
    ): (
        "one starting point of the multi-start output-error search: q0 from the second sample (one "
        "sample step later) leads Levenberg–Marquardt to the same least-squares minimum (xtol 1e-12)"
    ),
    ("model/allocation.py", "Winv = np.diag(1.0 / w)", "1.0 -> 2.0"): (
        "W⁻¹ Tᵀ (T W⁻¹ Tᵀ)⁺ is unchanged when W⁻¹ is scaled: c W⁻¹ Tᵀ (c T W⁻¹ Tᵀ)⁺ = W⁻¹ Tᵀ (T W⁻¹ Tᵀ)⁺ "
        "(only the weights' ratios matter)"
    ),
    ("identify/rig_model.py", "LINEAR, SINE, POLYNOMIAL, TABLE = 0, 1, 2, 3", "3 -> 4"): (
        "TABLE is the fall-through of the compiled _restore (codes 0, 1, 2 are tested, anything else is "
        "the table): no code compares a shape code with 3"
    ),
    (
        "estimate/bem.py",
        "faces = mesh.faces if mesh.faces.shape[1] == 4 else np.column_stack([mesh.faces, mesh.faces[:, 2]])",
        "4 -> 5",
    ): (
        "quads then get a fifth column, and capytaine.Mesh keeps the first four columns of faces "
        "(checked with capytaine 3.0: Mesh(faces=[[0, 1, 2, 3, 2]]).faces == [[0, 1, 2, 3]])"
    ),
    ("estimate/mesh.py", "if _STL_HEADER + _STL_RECORD * count > size:", "> -> >="): (
        "equality was read as binary and returned a few lines above: here 84 + 50·count ≠ size"
    ),
    ("identify/preprocess.py", "elif a[0] - a[-2 if a.size % 2 == 0 else -1] <= 2.0 * band:", "drop unary - [1]"): (
        "the elif runs with fewer than 6 extremes left and j ≤ len(ext) − 4, so a.size is 4 or 5: "
        "the index is taken only for a.size = 4, where a[-2] and a[2] are the same element"
    ),
    **{
        ("identify/preprocess.py", "s = 1 if v > band else (-1 if v < -band else 0)", op): (
            f"differs only for a sample exactly on the band edge {edge}3σ (with real noise, probability 0; "
            "noise-free, an exact zero): it moves a crossing one sample earlier, and the period is taken "
            "between crossings of the same direction, where the shift cancels"
        )
        for op, edge in (("> -> >=", "+"), ("< -> <=", "−"))
    },
    ("estimate/composite.py", "DQ_out[:3] = elements[at_origin, 6:9].sum(axis=0)", "9 -> 10"): (
        "elements is the packed drag table of core.drag, PACKED_WIDTH = 9 columns: the slice 6:10 is 6:9"
    ),
    ("model/thrusters.py", "if g_hi <= 0.0:  # even the speed limit does not give f (forward)", "<= -> <"): (
        "g_hi == 0 exactly: the root search's first false-position step (lo·g_hi − hi·g_lo)/(g_hi − g_lo) "
        "is hi itself, where g = 0 meets the stopping test: the same speed limit is returned"
    ),
    ("identify/split.py", "a0 = max(a, b + 1 - max(5, int(round(min_hold / dt))))", "1 -> 2"): (
        "the stretch handed to the release detector starts one hold sample later: the release is found "
        "in the stretch's own samples (the last still one before the motion) and returned as a0 + i0, "
        "the same absolute index; the hold's level is a median of still samples, and one fewer moves it "
        "by a fraction of the noise, far inside the detector's 8 σ band"
    ),
    **_alike(
        "identify/damping.py",
        "the skip of a degenerate half cycle: successive extremes come from distinct half cycles of a "
        "strictly increasing time base (their parabola vertices stay within half a sample of distinct "
        "samples on either side of a crossing), and an extreme lying exactly on the refined rest value "
        "to the last bit has probability 0; the strict and non-strict tests differ only at those ties",
        ("if t2 <= t1 or a1 <= 0 or a2 <= 0:", "<= -> < [1]"),
        ("if t2 <= t1 or a1 <= 0 or a2 <= 0:", "<= -> < [2]"),
        ("if t2 <= t1 or a1 <= 0 or a2 <= 0:", "<= -> < [3]"),
    ),
    (
        "identify/estimators.py",
        "if rms > 3.0 * noise and rms > 1e-9 * max(1.0, float(np.max(np.abs(y)))):",
        "> -> >= [1]",
    ): (
        "differs only for an RMS residual of exactly 3 noise floors to the last bit (probability 0): the warning's edge"
    ),
    ("model/dynamics.py", "nu = x[7:13]", "13 -> 14"): (
        "the quaternion state is 13 long (position 3, quaternion 4, ν 6; solve_ivp and the fixed-step "
        "loops pass exactly that): numpy clips the slice 7:14 to 7:13"
    ),
    (
        "model/guidance.py",
        "if math.sqrt(b0 * b0 + b1 * b1 + b2 * b2) <= acceptance_radius or s >= 1.0:",
        "<= -> <",
    ): ("differs only for a distance to the waypoint of exactly the acceptance radius to the last bit (probability 0)"),
    ("model/thrusters.py", "if g_lo >= 0.0:  # (reverse)", ">= -> >"): (
        "g_lo == 0 exactly: the root search's first false-position step (lo·g_hi − hi·g_lo)/(g_hi − g_lo) "
        "is lo itself, where g = 0 meets the stopping test: the same reverse speed limit is returned"
    ),
    (
        "model/allocation.py",
        "self.Q: Array | None = np.where(reach > 0, 1.0 / np.where(reach > 0, reach, 1.0), 1.0)",
        "1.0 -> 2.0 [2]",
    ): ("the inner default only avoids 1/0 where reach == 0, and there the outer np.where takes its own 1.0"),
    (
        "model/allocation.py",
        "f2 = _clip_vec(bvls(A2, b2, lo_s, hi_s, 1e-12), lo, hi)",
        "1e-12 -> 1.000000000001",
    ): (
        "numerically equivalent, not exactly: BVLS's stopping tolerance only decides how far it refines "
        "the answer on its active set, and _polish then solves that set exactly; over 300 random "
        "6×(4–8) allocations with random limits the thrust moved by at most 3e-8 N (6e-10 of the limits)"
    ),
    ("estimate/mesh.py", "size = 0", "0 -> 1"): (
        "a placeholder for the type checker: size is read only by the MemoryError message, and every "
        "path to that handler runs p.stat() first (a failing stat raises OSError, handled apart)"
    ),
    ("core/rigid_body.py", "M[3:6, 3:6] = parallel_axis(I_cg, mass, r_g)", "6 -> 7 [2]"): (
        "M is 6×6: numpy clips the slice 3:7 to 3:6, the same block"
    ),
    (
        "model/allocation.py",
        "self.Q: Array | None = np.where(reach > 0, 1.0 / np.where(reach > 0, reach, 1.0), 1.0)",
        "> -> >= [2]",
    ): (
        "where reach == 0 the inner np.where then yields 1/0 = inf, but the outer np.where takes its own "
        "1.0 there: the weights are the same (numpy's divide warning is the only difference)"
    ),
    (
        "estimate/mesh.py",
        "if 80 <= size < _STL_HEADER:  # meshio reads a count from any file of 80 bytes or more",
        "< -> <=",
    ): (
        "an ASCII STL of exactly 84 bytes is refused either way (the smallest facet, 'solid', 'facet "
        "normal', 'outer loop', three 'vertex' lines and the end keywords, takes over 100 bytes): only "
        "the wording of the one-line error differs, and messages are not mutated"
    ),
    ("identify/tare.py", "if not (alpha < 0 and math.isfinite(alpha)):", "< -> <="): (
        "differs only for a fitted α of exactly 0.0 to the last bit (probability 0 with any noise)"
    ),
    (
        "identify/estimators.py",
        "cov = 2 * best.cost / max(1, t.size - x.size) * np.linalg.inv(J.T @ J)",
        "1 -> 2",
    ): (
        "the floor of the degrees of freedom: a fitted record has at least MIN_SAMPLES = 20 samples and "
        "the extended fit at most 9 parameters, so n − p ≥ 11 and max(1, n − p) = max(2, n − p)"
    ),
    ("identify/preprocess.py", "big = np.nonzero(np.abs(y[i0:] - eq) > floor)[0]", "> -> >="): (
        "differs only for a sample exactly 4 noise σ from the rest value to the last bit (σ is a scaled "
        "MAD, or step/√12 for a quantised sensor whose samples sit whole steps from a median: never "
        "exactly 4σ); probability 0"
    ),
    (
        "identify/estimators.py",
        "if math.sqrt(2 * best.cost / t.size) <= 2.0 * noise:  # noise ≥ 1e-12 (set above)",
        "<= -> <",
    ): (
        "the multi-start's early stop: differs only for an RMS residual of exactly 2 noise floors to the "
        "last bit (probability 0), and then one more start is tried, whose fit replaces the best only "
        "if its cost is lower"
    ),
    (
        "identify/estimators.py",
        "if ratio is not None and ratio <= 2.0 and (acf is None or abs(acf) < 0.3):",
        "<= -> <",
    ): (
        "differs only for a residual of exactly twice the noise floor to the last bit (probability 0): the verdict's edge"
    ),
    (
        "identify/estimators.py",
        "if ratio is not None and ratio <= 2.0 and (acf is None or abs(acf) < 0.3):",
        "< -> <=",
    ): (
        "differs only for a residual autocorrelation at one period of exactly ±0.3 to the last bit "
        "(probability 0): the verdict's other edge"
    ),
    (
        "identify/estimators.py",
        "s = 1 if z[i] > band else (-1 if z[i] < -band else 0)",
        "1 -> 2 [1]",
    ): (
        "the half-cycle state above the band becomes 2 instead of 1: it is only compared with the next "
        "state (2 ≠ −1, ≠ 0 as 1 was) and multiplies the half cycle before argmax, which a positive "
        "factor does not move"
    ),
    ("identify/preprocess.py", "s = 1 if v > band else (-1 if v < -band else 0)", "1 -> 2 [1]"): (
        "the state above the band becomes 2 instead of 1: it is only compared with the next state "
        "(2 ≠ −1, ≠ 0 as 1 was), so the same crossings are recorded"
    ),
    ("identify/preprocess.py", "if not coef[1] < -3.0 * se:", "< -> <="): (
        "differs only when the amplitude trend's slope is exactly −3 standard errors to the last bit "
        "(probability 0): the edge of the 'still decaying' test"
    ),
    ("model/allocation.py", "active[i] = f[i] <= lo[i] + tol[i] or f[i] >= hi[i] - tol[i]", ">= -> >"): (
        "differs only for a thrust exactly tol below its upper limit to the last bit (tol ≥ 1e-7 N, "
        "and a clipped thrust sits at the limit itself): probability 0"
    ),
    ("model/thrusters.py", "fwd = f > 0", "> -> >="): (
        "f = 0 returned 0.0 two lines above, so f ≥ 0 and f > 0 agree on every f that reaches this line"
    ),
    (
        "identify/estimators.py",
        'starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))',
        "- -> +",
    ): (
        "a start value only: the response is nearly linear in q0, so Levenberg–Marquardt corrects a "
        "start of y0 + offset in one step (measured: the same fit about a rest value 20 times the "
        "amplitude, 10 evaluations instead of 11; tests/identify/test_floating_rig.py)"
    ),
    (
        "identify/tare.py",
        "if not np.all(np.isfinite(bread)) or np.linalg.cond(HtH) > 1e14:",
        "100000000000000.0 -> 100000000000001.0",
    ): (
        "differs only for a condition number between 1e14 and 1e14 + 1 (one part in 1e14): the edge "
        "of 'too ill-conditioned to invert'"
    ),
    ("identify/rig_model.py", "if x >= xe:  # linear beyond the last knot", ">= -> >"): (
        "at x = xe exactly the last Hermite piece gives the last knot's value y1 = par[2n] and slope "
        "d1/h = par[3n], the same value and slope as the linear extension"
    ),
    **_alike(
        "model/thrusters.py",
        "the ideal curve and the thrust table ignore the advance speed (the same thrust at any inflow), "
        "so its default is never read",
        ("def thrust(self, command: float, advance_speed: float = 0.0) -> float:  # any inflow", "0.0 -> 1.0"),
        ("def command(self, thrust: float, advance_speed: float = 0.0) -> float:  # any inflow", "0.0 -> 1.0"),
    ),
    ("model/thrusters.py", "if abs(g) <= 1e-12 * abs(f) or hi - lo <= 1e-12 * n_max:", "<= -> < [1]"): (
        "differs only when the thrust error is exactly 1e-12 of the target to the last bit (f ≠ 0 here, "
        "so g = 0 passes both): probability 0"
    ),
    **_alike(
        "model/thrusters.py",
        "n = 0 returned 0.0 above, and this branch needs |va| ≥ 1e6 |n D| > 0: neither va nor n is zero "
        "here, so > 0 and ≥ 0 agree",
        ("J = j_hi if (va > 0) == (n > 0) else j_lo", "> -> >= [1]"),
        ("J = j_hi if (va > 0) == (n > 0) else j_lo", "> -> >= [2]"),
    ),
    ("model/thrusters.py", "_BISECTION_STEPS = 80", "80 -> 81"): (
        "an iteration cap never reached: after 20 false-position steps plain bisection halves a bracket "
        "of width ≤ n_max, so it is below 1e-12 n_max (the stop test) within 40 more steps, by step 61"
    ),
    ("identify/preprocess.py", "s = 1 if z[i] > band else (-1 if z[i] < -band else 0)", "1 -> 2 [1]"): (
        "the half-cycle state above the band becomes 2 instead of 1: it is only compared with the next "
        "state (2 ≠ −1, ≠ 0 as 1 was) and multiplies the half cycle before argmax, which a positive "
        "factor does not move"
    ),
    ("identify/rig_model.py", "if m > 2:", "> -> >="): (
        "m is 2 (no sensitivities) or more than 2; with m = 2 the mutant also fills the derivative "
        "buffers' sensitivity entries, but the RK4 updates and the outputs read only the first m entries"
    ),
    ("identify/rig_model.py", "if m > 2:", "2 -> 3"): (
        "m is 2 (no sensitivities) or 2 + 2 (nfree + 2) ≥ 12 with them: m > 3 is false and true for the same two values"
    ),
    ("identify/split.py", "a0 = max(a, b + 1 - max(5, int(round(min_hold / dt))))", "+ -> -"): (
        "the window starts two samples earlier but never before the still run's start a (a still run "
        "is at least that long): both windows hold only samples of the same still hold, within the "
        "stillness threshold, ahead of the same release"
    ),
    (
        "identify/estimators.py",
        "slow = acf is not None and acf >= 0.3 and acf_half is not None and acf_half > acf - 0.5",
        "> -> >=",
    ): (
        "differs only when the half-period autocorrelation is exactly 0.5 below the full-period one to "
        "the last bit (probability 0): the edge between 'model error' and 'drift'"
    ),
    ("identify/estimators.py", "if best is None or sol.cost < best.cost:", "< -> <="): (
        "a later restart replaces the best one only at exactly the same cost to the last bit: two "
        "least-squares minima of the same residual with equal cost and different parameters do not occur "
        "in floating point (and a tie at the same point changes nothing)"
    ),
    ("identify/estimators.py", "if math.degrees(est.amplitude_) > last:", "> -> >="): (
        "differs only when the fitted launch amplitude equals the GZ table's last angle to the last bit; "
        "there the righting arm is the table's own end value either way (no extrapolation happens), so "
        "the warning's absence or presence at that single float is immaterial"
    ),
    # the advance-ratio guard of propeller_thrust
    **_alike(
        "model/thrusters.py",
        "for 1e6 < |J| ≤ 1000001 both branches give the same range end: the first clamps J = V_a/(nD) to "
        "hi or lo, the other picks hi or lo from the same signs",
        ("if abs(nD) * 1e6 > abs(va):", "1000000.0 -> 1000001.0"),
    ),
    **_alike(
        "model/thrusters.py",
        "at |n D|·1e6 = |V_a| exactly |J| = 1e6, far outside any K_T range: the clamped J of the first "
        "branch and the sign-only J of the other are the same range end",
        ("if abs(nD) * 1e6 > abs(va):", "> -> >="),
    ),
    ("model/thrusters.py", "k = kt_forward if n > 0 else kt_reverse", "> -> >="): (
        "n = 0 returned two lines above, so n ≥ 0 and n > 0 pick the same curve"
    ),
    ("identify/estimators.py", "p0 = np.zeros(6)", "6 -> 7"): (
        "p0 is read only at the fitted indices `free` (all below 6): a seventh zero is never read"
    ),
    ("identify/preprocess.py", "tt, aa = times[j:n] - times[j], amps[j:n]", "- -> +"): (
        "the times shift by the constant 2·times[j]; the regression has a constant column, so only the "
        "intercept moves: the slope and its standard error (the only things read) are unchanged"
    ),
    (
        "estimate/composite.py",
        "has_drag = np.any(np.diag(DQ) != 0) or np.asarray(p.drag_elements).size > 0",
        "0 -> 1 [2]",
    ): ("drag_elements is an (n, 9) array: its size is 0 or at least 9, so size > 1 and size > 0 agree"),
    **_alike(
        "estimate/shapes.py",
        "the shape tables' rows are finite ratios up to 100 and the 1e9 row of the infinite-ratio limit: no "
        "row lies at or near 1e8, where < and ≤ (or the bound 1e8 + 1) would part",
        ("finite = [(a, b) for a, b in table if a < 1e8]", "< -> <="),
        ("finite = [(a, b) for a, b in table if a < 1e8]", "100000000.0 -> 100000001.0"),
    ),
    (
        "identify/split.py",
        "if nxt > b + 1 and float(np.max(np.abs(y[b + 1 : nxt] - level))) > big:",
        "+ -> - [2]",
    ): (
        "the slice gains samples b − 1 and b, the still run's own last samples: they lie within the "
        "stillness threshold of its median, below big (≥ 20 σ, and ≥ 2 % of the range), so they never "
        "decide whether the largest excursion exceeds big"
    ),
    ("identify/estimators.py", "tf = np.linspace(t[0], t[-1], max(2000, 4 * t.size))", "1 -> 2"): (
        "equivalent in effect (not exactly): the grid for the fitted response's peak speed ends one "
        "sample early; a free decay peaks in its first cycle, so only the grid points move, which changes "
        "the sampled maximum (Re, KC) by the grid's own resolution (measured on an 8 s closed-form decay: "
        "1.5e-6 relative at 200 Hz, 4e-5 at 20 Hz)"
    ),
    ("identify/preprocess.py", "s = 1 if z[i] > band else (-1 if z[i] < -band else 0)", "1 -> 2 [2]"): (
        "the half-cycle state below the band becomes −2 instead of −1: it is only compared with the next "
        "state (−2 ≠ 1, ≠ 0 as −1 was) and multiplies the half cycle before argmax, which a positive "
        "factor (2) does not move"
    ),
    **_alike(
        "model/allocation.py",
        "a thrust exactly at a limit ± its tolerance (1e-6 of the limit), to the last bit: the allocator "
        "puts thrusts at the limit itself (inside the band either way) or away from it, never on the "
        "band's edge except by coincidence",
        (
            "return [n for n, x, a, b, t in zip(names, f, lo, hi, tol) if x >= b - t or x <= a + t]",
            "<= -> <",
        ),
        (
            "return [n for n, x, a, b, t in zip(names, f, lo, hi, tol) if x >= b - t or x <= a + t]",
            ">= -> >",
        ),
    ),
    (
        "identify/design.py",
        "_, v, J = simulate_normalised(t, w2, b, g, amplitude, 0.0, c.sine, 4, True, restoring=c.restoring)",
        "4 -> 5",
    ): (
        "equivalent in effect (not exactly): five RK4 substeps per sample instead of four change the "
        "bound by the integrator's error, measured 2e-5 relative at 20 Hz on the spring rig (an "
        "independent scipy bound agrees with either to 1e-4; tests/identify/test_campaign_design.py)"
    ),
    ("identify/result.py", "for row, f in zip(rows, fitted, strict=True):", "True -> False"): (
        "a guard only: both lists come from equivalent_damping at the same amplitudes, one row each, so "
        "they are always the same length and zip never stops early"
    ),
    (
        "identify/estimators.py",
        "s = 1 if z[i] > band else (-1 if z[i] < -band else 0)",
        "> -> >=",
    ): (
        "differs only for a sample exactly on the hysteresis band (10 noise σ, at least 1e-15) to the last "
        "bit: a coincidence of probability 0 for measured or simulated records"
    ),
    ("estimate/mesh.py", 'vol = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0', "/ -> *"): (
        "a common factor (36) on every tetrahedron's volume: the centroid divides by the total and the "
        "inertia is scaled by mass / total, so the factor cancels in both (only rounding differs)"
    ),
    ("model/dynamics.py", "if elements.shape[0]:", "0 -> 1"): (
        "a shortcut: shape[1] is always 9, so the mutant always calls drag_wrench, which returns the zero "
        "wrench for no elements (its own shortcut, excused in core/drag.py)"
    ),
    ("identify/preprocess.py", "s = 1 if z[i] > band else (-1 if z[i] < -band else 0)", "< -> <="): (
        "differs only for a sample exactly on the hysteresis band (3 noise σ) to the last bit: a "
        "coincidence of probability 0 for measured or simulated records"
    ),
    ("identify/split.py", "flag = rng[: y.size - w + 1] <= thr", "<= -> <"): (
        "differs only for a window whose range equals the stillness threshold max(8 σ, 1e-6 of the range) "
        "to the last bit, σ itself estimated from the record: a tie of probability 0"
    ),
    ("identify/split.py", "near = np.nonzero(np.abs(motion - centre) <= band)[0]", "<= -> <"): (
        "differs only for a sample exactly band (4 σ or 2 % of the hold's height, both estimated) from the "
        "motion's median, to the last bit: a tie of probability 0"
    ),
    (
        "identify/split.py",
        "if nxt > b + 1 and float(np.max(np.abs(y[b + 1 : nxt] - level))) > big:",
        "> -> >= [2]",
    ): ("differs only for an excursion exactly big (20 σ or 2 % of the range) to the last bit: probability 0"),
    **_alike(
        "identify/split.py",
        "the hold's level is the median of its still run (samples a..b, at least 5, all within 8 σ of one "
        "another); dropping its last two samples or adding the first one after it moves the median by one "
        "order statistic, a fraction of σ, against a decision threshold of at least 20 σ (here) and a rest "
        "band of 2 % of the hold's height (there), which is itself at most a few σ off: equivalent in effect",
        ("level = float(np.median(y[a : b + 1]))", "+ -> -"),
        ("level = float(np.median(y[a : b + 1]))", "1 -> 2"),
        ("band = max(4.0 * sigma, 0.02 * abs(float(np.median(y[a : b + 1])) - centre))", "+ -> -"),
        ("band = max(4.0 * sigma, 0.02 * abs(float(np.median(y[a : b + 1])) - centre))", "1 -> 2"),
    ),
    **_alike(
        "identify/split.py",
        "equivalent in effect: the motion tested after a still run grows by the next still run (whose "
        "samples stay within 8 σ of where that motion ended) or, for the last-but-one run, by the last run "
        "and what follows; only a still run in a decay's tail followed by a small disturbance and then a "
        "slow drift of more than 20 σ could newly pass as a candidate, and such a candidate is refused "
        "as a launch by check_record; the launch before it would end at that still run, where its decay "
        "is already inside the noise band the end detector stops at",
        ("nxt = runs[k + 1][0] if k + 1 < len(runs) else y.size", "0 -> 1"),
        ("nxt = runs[k + 1][0] if k + 1 < len(runs) else y.size", "1 -> 2 [2]"),
    ),
    (
        "identify/split.py",
        "if nxt > b + 1 and float(np.max(np.abs(y[b + 1 : nxt] - level))) > big:",
        "1 -> 2 [1]",
    ): (
        "nxt = b + 2 exactly when one sample separates two still runs: a one-sample glitch (every window "
        "holding it is unstill). Taking that run as a candidate (original) or not (mutant) gives the same "
        "launches: its stretch ends at the next candidate; if that is the run right after the glitch the "
        "stretch has 2 < MIN_SAMPLES samples and is skipped, else it holds the glitch, a still run and a "
        "motion that did not make that run a candidate, which check_record refuses as a decay (the "
        "glitch test in test_mutants_identify.py shows the launch after it unchanged)"
    ),
    ("identify/split.py", "a0 = max(a, b + 1 - max(5, int(round(min_hold / dt))))", "5 -> 6"): (
        "only for min_hold under 5.5 samples: the release detector's stretch starts one hold sample "
        "earlier, inside the same still run (at least 5 samples, and a ≤ a0 either way); as for "
        "'1 -> 2' on this line, the release is found at the same absolute index"
    ),
    ("identify/tare.py", "if np.max(np.abs(np.diff(t) - dt)) > 0.05 * dt:", "> -> >="): (
        "differs only for a largest step deviation of exactly 5 % of the mean step to the last bit: a tie"
    ),
    ("identify/tare.py", "if not np.all(np.isfinite(bread)) or np.linalg.cond(HtH) > 1e14:", "> -> >="): (
        "differs only for a condition number of exactly 1e14 to the last bit: a tie"
    ),
    ("identify/tare.py", "se = np.sqrt(np.clip(np.diag(cov)[:3], 0.0, None))", "3 -> 4"): (
        "se gains the first rest term's error, but only se[0], se[1], se[2] are read (α, β, γ)"
    ),
    (
        "identify/tare.py",
        "for _ in range(3):  # the bias depends (weakly) on the coefficients: a few fixed-point steps",
        "3 -> 4",
    ): (
        "equivalent in effect (measured): a fourth fixed-point step moves α, β, γ by 1e-12 relative at "
        "0.05° noise and by 7e-5 of β (under 1e-3 of its standard error) at 0.5° noise and 30 fps: the "
        "iteration has converged after three"
    ),
    ("identify/estimators.py", "x = np.linspace(0.0, float(a), 201)", "0.0 -> 1.0"): (
        "R(a) is only used as a difference R(a1) − R(a2) (the energy lost in a half cycle, damping.py) or "
        "beside a fitted intercept E_0 (equation-error's energy balance): a lower limit of 1 instead of 0 "
        "subtracts the same ∫₀¹ ρ from every R, up to the trapezoid rule's error (h² ρ''/12 with h = a/200: "
        "~1e-6 of R)"
    ),
    ("identify/estimators.py", "x = np.linspace(0.0, float(a), 201)", "201 -> 202"): (
        "equivalent in effect: 201 instead of 200 trapezoid intervals changes the quadrature error "
        "(~1e-6 of R for a cubic or table shape at 0.4 rad) by 1 %, i.e. ~1e-8 of the damping value"
    ),
    ("identify/campaign.py", "groups = group_by_amplitude(results, angles=False)", "False -> True"): (
        "the labels only key the groups inside summarize (never shown): mm or ° text, each prefixed with "
        "its own L1, L2 …, gives the same partition of the launches"
    ),
    (
        "identify/campaign.py",
        "if groups and abs(r.amplitude - groups[-1][0].amplitude) <= rel_tol * max(abs(groups[-1][0].amplitude), 1e-12):",
        "<= -> <",
    ): ("differs only for two measured amplitudes exactly rel_tol (15 %) apart to the last bit: a tie"),
    ("identify/virtual_rig.py", "if self.noise_std > 0:", "> -> >="): (
        "equivalent in distribution: a noise-free sensor then adds N(0, 0) draws, i.e. zeros; only the "
        "random stream moves on, so a random quantisation zero drawn after them is another uniform draw"
    ),
    ("identify/virtual_rig.py", "out += rng.normal(0.0, self.noise_std, out.shape)", "+ -> -"): (
        "equivalent in distribution: subtracting zero-mean Gaussian noise is adding it (the noise test "
        "checks its mean and std)"
    ),
    **_alike(
        "identify/virtual_rig.py",
        "equivalent in distribution: only the quantisation grid's offset modulo one resolution step "
        "matters (readings are rounded to the grid and shifted back); a uniform offset over [−1.5, 0.5] "
        "steps (two whole steps) is uniform modulo a step, and u/resolution for u uniform in ±½ spans "
        "thousands of steps, equally uniform modulo one to within a step's fraction",
        ("zero = rng.uniform(-0.5, 0.5) * self.resolution if self.random_zero else 0.0", "0.5 -> 1.5 [1]"),
        ("zero = rng.uniform(-0.5, 0.5) * self.resolution if self.random_zero else 0.0", "* -> /"),
    ),
    (
        "identify/virtual_rig.py",
        "a0 = float(amplitude) * (1.0 + amplitude_jitter * rng.standard_normal()) if amplitude_jitter else float(amplitude)",
        "+ -> -",
    ): (
        "equivalent in distribution: A (1 − j z) and A (1 + j z) are the same Gaussian for a standard "
        "normal z (the jitter test checks that distribution)"
    ),
    (
        "identify/virtual_rig.py",
        "q, _, _ = simulate_normalised(t_run, w2, b, g, a0, v0, c.sine, 8, restoring=c.restoring)",
        "8 -> 9",
    ): (
        "equivalent in effect: the truth integrated with 9 instead of 8 RK4 steps per sample; the global "
        "error, ∝ (ω Δt / 8)⁴, is ~1e-8 of the amplitude already (ω = 7 rad/s at 100 Hz), far below any "
        "sensor's noise or resolution"
    ),
    ("identify/preprocess.py", "sel = np.nonzero((t >= lo) & (t <= hi))[0]", "<= -> <"): (
        "differs only for a sample exactly at hi = c0 − 0.1 T (a crossing time less a tenth of a period "
        "measured from the extremes) to the last bit: a tie of probability 0"
    ),
    **_alike(
        "identify/estimators.py",
        "sign only orders the replay's times (argsort of sign · t): any positive factor gives the same order",
        ("for mask, sign in ((fwd, 1.0), (~fwd, -1.0)):", "1.0 -> 2.0 [1]"),
        ("for mask, sign in ((fwd, 1.0), (~fwd, -1.0)):", "1.0 -> 2.0 [2]"),
    ),
    **_alike(
        "identify/estimators.py",
        "equivalent in effect: the replay (plots, residuals after the fit) with 5 instead of 4 RK4 steps "
        "per sample; its global error, ∝ (ω Δt / 4)⁴, is ~1e-7 of the amplitude at ω Δt = 0.07 and "
        "only shrinks, far below any sensor's noise",
        ("qq, vv, _ = simulate_extended(grid, ext, self.q0_, self.v0_, shape, 4)", "4 -> 5"),
        ("qq, vv, _ = simulate_normalised(grid, w2, b, g, self.q0_, self.v0_, sine, 4, restoring=shape)", "4 -> 5"),
    ),
    ("identify/estimators.py", "tu = np.arange(t[0], t[-1], dt)", "0 -> 1"): (
        "equivalent in effect: the even grid for jittered stamps starts at the second stamp instead of "
        "the first; the rig equation is autonomous and equation-error fits it sample by sample, so the "
        "record one step shorter gives the same coefficients to within its own noise"
    ),
    (
        "identify/preprocess.py",
        "cands = sel[(t[sel] > lo + 0.05 * period) & (t[sel] < c0 - 0.15 * period)]",
        "> -> >=",
    ): (
        "differs only for a sample exactly 5 % of a measured period after the window's start, to the last "
        "bit: a tie of probability 0"
    ),
    ("identify/estimators.py", "tf = np.linspace(t[0], t[-1], max(2000, 4 * t.size))", "2000 -> 2001"): (
        "equivalent in effect, as '1 -> 2' on this line: one grid point more for the fitted response's "
        "peak speed moves only the grid points, so the sampled maximum (Re, KC) changes by the grid's "
        "own resolution (under 1e-5 relative)"
    ),
    ("identify/preprocess.py", "if last > 1.2 * first + band:", "> -> >="): (
        "differs only for a last-third peak exactly 1.2 times the first third's plus the band, to the last "
        "bit: a tie of probability 0"
    ),
    ("identify/preprocess.py", "post = s >= 0", ">= -> >"): (
        "only the sample at s = 0 (the candidate release itself) changes sides, and there both models "
        "give the same regressor row [1, 0, 0, 0]: the hand's quadratic (1, s, s²) and the free response "
        "(q_a = 1, q_b = 0, 1 − q_a = 0) join with the same position and rate"
    ),
    ("identify/estimators.py", "if m_a < 0:", "< -> <="): (
        "differs only for a fitted added mass of exactly 0 to the last bit (m_a = A − m from a "
        "least-squares ω²): a tie of probability 0"
    ),
    ("identify/preprocess.py", "sp = np.where(post, s, 0.0)", "0.0 -> 1.0"): (
        "sp only feeds the free-response columns q_a, q_b, 1 − q_a, which every row before the join "
        "replaces by the hand's (1, s, s², 0) through np.where(pre, …): the value put there for s < 0 "
        "(0 to keep exp from overflowing, or 1) is never used"
    ),
    ("model/thrusters.py", "kt = 0.0 if kt < 0.0 else kt  # max(kt, 0.0), NaN kept", "< -> <="): (
        "differs only for kt exactly ±0.0: the mutant returns +0.0 where the original keeps kt, a zero "
        "either way, so the thrust loss · kt · ρ D⁴ |n| n is zero either way"
    ),
    (
        "identify/preprocess.py",
        "still = np.nonzero(np.abs(z[s0 : s1 + 1] - z[k0]) <= 0.02 * abs(float(z[k0])))[0]",
        "<= -> <",
    ): ("differs only for a sample exactly 2 % of the extreme from it, to the last bit: a tie"),
    **_alike(
        "identify/preprocess.py",
        "the release half cycle's last sample (or the next half cycle's first) sits at the hysteresis band "
        "or beyond it on the other side, far from the extreme (band ≤ max(4 σ, 1 % of the peak) against an "
        "extreme that starts the decay): never within 2 % of the extreme, so it is never a hold sample",
        ("still = np.nonzero(np.abs(z[s0 : s1 + 1] - z[k0]) <= 0.02 * abs(float(z[k0])))[0]", "+ -> -"),
        ("still = np.nonzero(np.abs(z[s0 : s1 + 1] - z[k0]) <= 0.02 * abs(float(z[k0])))[0]", "1 -> 2"),
    ),
    ("identify/preprocess.py", "first = next((j for j, a in enumerate(amps) if a <= hi), None)", "<= -> <"): (
        "differs only for a measured extreme exactly equal to the window's HI to the last bit: a tie"
    ),
    **_alike(
        "identify/estimators.py",
        "start values of output-error's generic start (ζ, K_Q, q0 and v0), used after the "
        "equation-error and log-decrement starts: Levenberg–Marquardt reaches the same minimum from "
        "either (measured with both other starts failing, 4 launches × 3 damping/restoring models: "
        "coefficients within 1.2e-6 of each other, a few evaluations more or less; "
        "tests/identify/test_mutants_identify.py checks the generic start alone)",
        ('starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))', "* -> / [2]"),
        (
            'starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))',
            "0.0 -> 1.0 [1]",
        ),
        (
            'starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))',
            "0.0 -> 1.0 [2]",
        ),
        ('starts.append(np.array([w * w, 0.1 * w, 0.0, y[0] - facts["offset"], 0.0, facts["offset"]]))', "0 -> 1"),
    ),
    **_alike(
        "model/thrusters.py",
        "the root search's bracket-width stop: differs only for a bracket exactly 1e-12 n_max wide to the "
        "last bit (probability 0), and then one more step stays inside the same bracket",
        ("if abs(g) <= 1e-12 * abs(f) or hi - lo <= 1e-12 * n_max:", "<= -> < [2]"),
    ),
    ("model/allocation.py", "self.scale = scale = max(float(np.linalg.norm(T, 2)), 1e-300)", "1e-300 -> 1.0"): (
        "a configuration matrix of unit thrust directions has ‖T‖₂ ≥ 1, so both give ‖T‖₂; for a T scaled "
        "down 100 or 1000 times (Python API) only the stage-2 penalty's weight changes, and _polish solves "
        "the active set exactly: the thrusts of 150 random saturating demands agreed to 7e-10 N"
    ),
    ("model/allocation.py", "active[i] = f[i] <= lo[i] + tol[i] or f[i] >= hi[i] - tol[i]", "<= -> <"): (
        "f equals lo + tol (a limit plus 1e-7 of it) only by coincidence to the last bit: f at the limit "
        "itself (clipped) passes both; probability 0 otherwise"
    ),
    ("model/allocation.py", "g[i] = lo[i] if f[i] <= lo[i] + tol[i] else hi[i]", "<= -> <"): (
        "f equals lo + tol (a limit plus 1e-7 of it) only by coincidence to the last bit: f at the limit "
        "itself (clipped) passes both; probability 0 otherwise"
    ),
    **_alike(
        "model/allocation.py",
        "a thrust exactly a limit plus 1e-9 of it, to the last bit: probability 0 (a thrust at the limit "
        "itself is tested, and passes both)",
        (
            "over = [n for n, x, a, b in zip(names, f, lo, hi) if x > b + 1e-9 * abs(b) or x < a - 1e-9 * abs(a)]",
            "> -> >=",
        ),
        (
            "over = [n for n, x, a, b in zip(names, f, lo, hi) if x > b + 1e-9 * abs(b) or x < a - 1e-9 * abs(a)]",
            "< -> <=",
        ),
    ),
    **_alike(
        "model/allocation.py",
        "what stands in for a missing (infinite) limit in the tolerance's scale: the tolerance is "
        "1e-6 · max(scale, 1.0) just below, so 0 and 1 give the same",
        (
            "scale = np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)), np.abs(np.where(np.isfinite(hi), hi, 0.0)))",
            "0.0 -> 1.0 [1]",
        ),
        (
            "scale = np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)), np.abs(np.where(np.isfinite(hi), hi, 0.0)))",
            "0.0 -> 1.0 [2]",
        ),
    ),
    ("identify/estimators.py", "dof = max(1, H.shape[0] - H.shape[1])", "1 -> 2 [1]"): (
        "a guard that never binds: a launch has at least MIN_SAMPLES = 20 samples, the Savitzky–Golay "
        "edges take at most a third of them at the coarsest sampling a 2-cycle launch allows, so H has "
        "13 or more rows against at most 6 columns (dof ≥ 7)"
    ),
    ("identify/estimators.py", "shift = float(coef[-1]) / float(coef[0]) if coef[0] != 0 else 0.0", "0 -> 1 [3]"): (
        "coef[0] is the fitted ω² (rad²/s²) of a least-squares fit to measured accelerations: exactly "
        "1.0 or exactly 0.0 to the last bit only by coincidence (probability 0)"
    ),
    ("identify/estimators.py", "if len(peaks) >= 3:", "3 -> 4"): (
        "with exactly three extremes (signs alternate: one per half cycle) only one same-sign pair "
        "exists, so the estimator refuses the record a few lines below ('fewer than two cycles') "
        "whether or not the rest value was refined from them"
    ),
    ("identify/preprocess.py", "k = start + int(np.argmax(z[start:i] * state))", "* -> /"): (
        "state is +1 or −1 here (a half cycle is only closed from a nonzero state), and z / ±1 is z · ±1 exactly"
    ),
    ("model/terms.py", "-np.ones((0, MAX_FACTORS, 3), np.int64),", "drop unary -"): (
        "the empty term set's index array has no elements (0 rows), so −1 or +1 fills nothing"
    ),
    ("model/terms.py", "for m, i in enumerate(f.indices[:3]):", "3 -> 4"): (
        "a factor has at most three indices (the parser refuses a norm of more, every other factor "
        "has one), so [:3] and [:4] take all of them"
    ),
    ("identify/estimators.py", "if terms > 1:", "1 -> 2"): (
        "restoring_terms is 1, 3 or 5 (the estimator refuses anything else when it is made), and "
        "> 1 and > 2 split those alike"
    ),
    ("estimate/mesh.py", "data = f.read(MAX_MESH_BYTES + 1)", "1 -> 2"): (
        "reading one or two bytes past the limit decides alike: len(data) > MAX_MESH_BYTES exactly when "
        "the file holds more than MAX_MESH_BYTES bytes"
    ),
    ("estimate/shapes.py", "if x <= finite[-1][0] or len(finite) == len(table):", "<= -> <"): (
        "at the last finite row itself both branches give that row's value: np.interp returns b0, the "
        "reciprocal form b1 + (b0 − b1)·a0/a0 (to the rounding of one subtraction)"
    ),
    ("estimate/composite.py", "a = np.abs(P[:, 0:3]) ** 3", "3 -> 4 [1]"): (
        "a slice end past the three position columns adds a fourth column of a that no line reads "
        "(a[:, 0], a[:, 1], a[:, 2] only)"
    ),
    ("estimate/composite.py", "Q = P[:, 6:9]", "9 -> 10"): (
        "P has PACKED_WIDTH = 9 columns: the slices 6:9 and 6:10 are the same three"
    ),
    (
        "estimate/mesh.py",
        "key = np.round(mesh.vertices / max(1e-12, float(np.ptp(mesh.vertices))) * 1e9).astype(np.int64)",
        "1000000000.0 -> 1000000001.0",
    ): (
        "a merge grid of 1/(1e9 + 1) instead of 1/1e9 of the extent splits or joins two vertices only "
        "when they straddle a rounding boundary within 1e-18 of the extent"
    ),
    (
        "estimate/mesh.py",
        "if size >= _STL_HEADER and (_STL_HEADER + _STL_RECORD * _stl_count(data)) % 2**32 == size:",
        ">= -> >",
    ): (
        "at exactly 84 bytes the wrap needs 50·count ≡ 0 (mod 2³²): count 0 or 2³¹, whose bytes 80–83 "
        "end in 0x00 or 0x80; text reaches here with no NUL in its first KiB, and a copy without blank "
        "lines ends in '\\n' (0x0a)"
    ),
    (
        "estimate/composite.py",
        "at_origin = np.all(elements[:, 0:3] == 0, axis=1) & np.all(elements[:, 3:6] == 0, axis=1)",
        "3 -> 4 [1]",
    ): (
        "0:4 adds column 3, which the second test (3:6) requires to be zero as well: the conjunction "
        "covers columns 0–5 either way"
    ),
    ("model/control.py", "if ki > 0 and raw > output_max and e < 0:", "> -> >= [2]"): (
        "at raw = output_max the integral already puts the output at the limit: at_limit equals it "
        "(to the rounding of one division), and max(I, min(I_prev, I)) = I"
    ),
    ("model/control.py", "elif ki > 0 and raw < output_min and e > 0:", "< -> <="): (
        "at raw = output_min the integral already puts the output at the limit: at_limit equals it "
        "(to the rounding of one division), and min(I, max(I_prev, I)) = I"
    ),
    ("model/control.py", "if ki > 0 and raw > output_max and e < 0:", "< -> <="): (
        "at e = 0 the integral is the previous one (inside ±bound, as every update leaves it), so "
        "max(I, min(I, at_limit)) = I: the branch changes nothing"
    ),
    ("model/control.py", "cth = cth if abs(cth) > 1e-9 else math.copysign(1e-9, cth)", "> -> >="): (
        "at |cos θ| = 1e-9 exactly both branches give cos θ itself: copysign(1e-9, cth) = cth"
    ),
    ("model/allocation.py", "_STAGE2_WEIGHT = 1e5", "100000.0 -> 100001.0"): (
        "a weight of 1e5 + 1 instead of 1e5 moves the achieved τ off the stage-1 optimum by |f|/W², "
        "about 1e-10 of the thrust scale either way (its comment)"
    ),
    (
        "identify/preprocess.py",
        "if per.size and np.max(np.abs(per / np.median(per) - 1.0)) > 0.15:",
        "> -> >=",
    ): ("a period exactly 15 % off the median, to the last bit, from sample times: the two tests split only there"),
    ("identify/preprocess.py", "if c0 - t[0] < 0.3 * period:", "< -> <="): (
        "the release half cycle's end exactly 0.3 median periods after the first sample, to the last "
        "bit: the two tests split only there"
    ),
    (
        "model/allocation.py",
        "if math.sqrt(q2) <= math.sqrt(q1) + 1e-8 * thrust_scale * q_max:",
        "<= -> <",
    ): ("stage 2 losing exactly the tolerance, to the last bit: the two tests split only there"),
    (
        "model/thrusters.py",
        "return (0.0,) * (4 - len(coeffs)) + tuple(coeffs) if len(coeffs) <= 4 else tuple(coeffs)",
        "<= -> <",
    ): ("four coefficients padded with (0.0,) * 0 are the same tuple as tuple(coeffs)"),
    ("identify/estimators.py", "if len(peaks) >= 3:", ">= -> >"): (
        "three alternating peaks (+ − + or − + −) hold one same-sign pair, one row, so the fit refuses "
        "'fewer than two cycles' either way: the shift (p1 p3 − p2²)/(p1 + p3 − 2 p2) lies strictly "
        "between the middle peak and the smaller outer one, so no peak changes sign"
    ),
    ("model/thrusters.py", "loss = loss_forward if n > 0 else loss_reverse", "> -> >="): (
        "n = 0 returns 0.0 before this line, so n > 0 and n >= 0 pick the same loss"
    ),
    ("identify/estimators.py", "restarts: int = 3,", "3 -> 4"): (
        "_starts gives at most three starts (equation-error, log-decrement, the period's guess): "
        "starts[: 1 + 3] and starts[: 1 + 4] are the same list"
    ),
    ("model/thrusters.py", "if g < 0.0:", "< -> <="): (
        "in both root searches g = 0 meets the |g| <= tolerance test on the line before (a tolerance of "
        "at least 0) and breaks out first"
    ),
    ("model/thrusters.py", "u, v, w, p, q, r = (float(x) for x in np.asarray(nu, dtype=float)[:6])", "6 -> 7"): (
        "every caller passes the six-component ν of a state (x[6:12], nu, nu_r): nu[:6] and nu[:7] are the same six"
    ),
    (
        "model/thrusters.py",
        "curves: tuple[ThrustCurve, ...] = field(init=False, repr=False, compare=False)",
        "False -> True [3]",
    ): (
        "the curves are the thrusters' own curve objects, which comparing the thrusters already "
        "compares: two sets equal by their thrusters have equal curves"
    ),
    ("identify/estimators.py", "if c.sine and est.amplitude_ > math.radians(20):", "> -> >="): (
        "a fitted launch amplitude of exactly 20°, to the last bit: the two tests split only there"
    ),
    (
        "model/thrusters.py",
        "return (0.0,) * (4 - len(coeffs)) + tuple(coeffs) if len(coeffs) <= 4 else tuple(coeffs)",
        "4 -> 5 [2]",
    ): ("five coefficients padded with (0.0,) * -1 = () are the same tuple as tuple(coeffs)"),
    ("identify/preprocess.py", "i = int(np.clip(np.searchsorted(t, time), 0, t.size - 1))", "0 -> 1"): (
        "a time at or before t[0] (searchsorted 0) then starts at i = 1, and the next line steps back: "
        "time − t0 ≤ 0 < t1 − time gives index 0 either way (one sample: the clip's upper end 0 wins)"
    ),
    ("identify/rig_model.py", "m = nz if want_jac else 2", "2 -> 3"): (
        "without the Jacobian a third integrated state is ∂q/∂ω², which neither q nor v reads (their "
        "derivatives use z[0] and z[1] only) and which is not copied out: q and v are bit for bit the same"
    ),
    (
        "identify/preprocess.py",
        "if den > 0:  # c_0 is the least of the three, so the vertex is within half a step: |d| ≤ ½",
        "> -> >=",
    ): (
        "c_0 is the least of the three costs, so den = c_m − 2 c_0 + c_p ≥ 0; > and >= split only at "
        "three equal costs to the last bit (a flat parabola, no vertex)"
    ),
    ("identify/estimators.py", "fwd = tt >= 0", ">= -> >"): (
        "a sample at t0 exactly is then replayed by the backward pass instead of the forward one: a grid "
        "step of zero length, which returns the initial state (q0, v0) bit for bit either way"
    ),
}

BINOP = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.Pow: ast.Mult}
BINOP.update({ast.FloorDiv: ast.Div, ast.Mod: ast.Mult})
CMPOP = {ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt, ast.Eq: ast.NotEq}
CMPOP.update({ast.NotEq: ast.Eq, ast.Is: ast.IsNot, ast.IsNot: ast.Is, ast.In: ast.NotIn, ast.NotIn: ast.In})
SYMBOL = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**", ast.FloorDiv: "//", ast.Mod: "%"}
SYMBOL.update({ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="})
SYMBOL.update({ast.Is: "is", ast.IsNot: "is not", ast.In: "in", ast.NotIn: "not in", ast.And: "and", ast.Or: "or"})


@dataclass
class Mutant:
    package: str
    path: str  # relative to src/hydrokit
    line: int
    what: str  # e.g. "+ -> -"
    code: str  # the original source line, stripped
    start: int  # byte span of the replaced node in the file
    end: int
    new: str  # replacement source text
    scope: int = 0  # first line of the enclosing function's code object (0: module level or compiled)
    status: str = "pending"  # killed, timeout, survived, uncovered, equivalent, error
    seconds: float = 0.0
    killer: str = ""

    @property
    def key(self) -> tuple[str, str, str]:
        return (self.path, self.code, self.what)

    def label(self) -> str:
        return f"{self.path}:{self.line}: {self.what}   | {self.code}"


def _skipped_nodes(tree: ast.AST) -> set[int]:
    """ids of nodes never mutated: docstrings, f-strings, annotations, raise arguments, and the size
    of an inferred (negative) ``reshape`` dimension (numpy reads −1 and −2 alike)."""
    skip: set[int] = set()

    def drop(node: ast.AST | None) -> None:
        if node is not None:
            skip.update(id(n) for n in ast.walk(node))

    for node in ast.walk(tree):
        if isinstance(node, (ast.JoinedStr, ast.Raise, ast.Assert)):
            drop(node)
        elif isinstance(node, ast.AnnAssign):
            drop(node.annotation)
        elif isinstance(node, ast.arg):
            drop(node.annotation)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            drop(node.returns)
        elif isinstance(node, ast.keyword) and node.arg == "stacklevel":
            drop(node.value)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "reshape":
            for a in node.args:
                if isinstance(a, ast.UnaryOp) and isinstance(a.op, ast.USub):
                    drop(a.operand)  # the sign stays mutable: reshape(1) is a different shape
        elif isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            drop(node)
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                drop(first)
    return skip


def _jitted(tree: ast.AST) -> set[str]:
    """Names of functions compiled by numba: ``@njit`` … or ``numba.njit(...)(f)``."""

    def is_jit(f: ast.AST) -> bool:
        f = f.func if isinstance(f, ast.Call) else f
        name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
        return name in ("jit", "njit")

    names = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and any(is_jit(d) for d in node.decorator_list):
            names.add(node.name)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Call) and is_jit(node.func):
            names.update(a.id for a in node.args if isinstance(a, ast.Name))
    return names


def _scopes(tree: ast.AST) -> dict[int, int]:
    """id(node) → co_firstlineno of the innermost enclosing function (0 at module level, in a
    class body, or in a numba-compiled function, whose calls a profiler cannot see). A function's
    decorators and default values belong to the scope that defines it: they run once, at the
    ``def``, even when the body never does (an abstract method's default)."""
    jitted = _jitted(tree)
    out: dict[int, int] = {}

    def visit(node: ast.AST, scope: int, compiled: bool) -> None:
        for child in ast.iter_child_nodes(node):
            s, c = scope, compiled
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                c = compiled or child.name in jitted
                # the code object starts at the first decorator
                s = 0 if c else min([child.lineno] + [d.lineno for d in child.decorator_list])
            out[id(child)] = s
            visit(child, s, c)
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                # decorators and default values run where the def statement runs, not in the body
                a = child.args
                for o in [*getattr(child, "decorator_list", ()), *a.defaults, *(d for d in a.kw_defaults if d)]:
                    out[id(o)] = scope
                    visit(o, scope, compiled)

    visit(tree, 0, False)
    return out


def _variants(node: ast.AST) -> list[tuple[str, ast.AST]]:
    """(description, mutated copy of ``node``) for every single change this runner knows."""
    out: list[tuple[str, ast.AST]] = []
    if isinstance(node, (ast.BinOp, ast.AugAssign)) and type(node.op) in BINOP:
        m = copy.deepcopy(node)
        m.op = BINOP[type(node.op)]()
        out.append((f"{SYMBOL[type(node.op)]} -> {SYMBOL[type(m.op)]}", m))
    elif isinstance(node, ast.Compare):
        for i, op in enumerate(node.ops):
            if type(op) in CMPOP:
                m = copy.deepcopy(node)
                m.ops[i] = CMPOP[type(op)]()
                out.append((f"{SYMBOL[type(op)]} -> {SYMBOL[type(m.ops[i])]}", m))
    elif isinstance(node, ast.BoolOp):
        m = copy.deepcopy(node)
        m.op = ast.Or() if isinstance(node.op, ast.And) else ast.And()
        out.append((f"{SYMBOL[type(node.op)]} -> {SYMBOL[type(m.op)]}", m))
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.Not)):
        out.append(("drop unary -" if isinstance(node.op, ast.USub) else "drop not", copy.deepcopy(node.operand)))
    elif isinstance(node, ast.Constant) and type(node.value) in (bool, int, float):
        v = node.value
        new = (not v) if isinstance(v, bool) else v + 1
        out.append((f"{v!r} -> {new!r}", ast.Constant(new)))
    return out


def module_mutants(path: Path, package: str) -> list[Mutant]:
    """All mutants of one module, with byte spans into its UTF-8 source."""
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    starts = [0]
    for ln in lines[:-1]:
        starts.append(starts[-1] + len(ln) + 1)
    tree = ast.parse(raw)
    skip = _skipped_nodes(tree)
    rel = path.relative_to(ROOT / "src" / "hydrokit").as_posix()
    scope = _scopes(tree)
    out = []
    for node in ast.walk(tree):
        if id(node) in skip or not hasattr(node, "end_lineno"):
            continue
        for what, mutated in _variants(node):
            a = starts[node.lineno - 1] + node.col_offset
            b = starts[node.end_lineno - 1] + node.end_col_offset
            text = ast.unparse(mutated)
            new = text if isinstance(node, ast.stmt) else f"({text})"
            code = lines[node.lineno - 1].decode().strip()
            out.append(Mutant(package, rel, node.lineno, what, code, a, b, new, scope.get(id(node), 0)))
    out.sort(key=lambda m: (m.line, m.start, m.what))
    # the same change twice on one line (three `3 -> 4` in a slice) gets its ordinal: [1], [2] …
    count: dict[tuple[int, str], int] = {}
    for m in out:
        count[(m.line, m.what)] = count.get((m.line, m.what), 0) + 1
    seen: dict[tuple[int, str], int] = {}
    for m in out:
        if count[(m.line, m.what)] > 1:
            seen[(m.line, m.what)] = seen.get((m.line, m.what), 0) + 1
            m.what += f" [{seen[(m.line, m.what)]}]"
    return out


def all_mutants(packages: list[str]) -> list[Mutant]:
    out = []
    for pkg in packages:
        for path in sorted((ROOT / "src" / "hydrokit" / pkg).glob("*.py")):
            out += module_mutants(path, pkg)
    for m in out:
        if m.key in EQUIVALENT:
            m.status = "equivalent"
    return out


TRACE_PLUGIN = '''"""pytest plugin written by bench/mutation.py: the hydrokit functions each test calls."""
import json, os, sys, threading, time

import pytest

_SRC = os.environ["MUTATION_TRACE_SRC"]
_calls = set()
_tests = {}
_failed = set()
_files = {}


def _profile(frame, event, arg):
    if event == "call" and frame.f_code.co_filename.startswith(_SRC):
        _calls.add((frame.f_code.co_filename[len(_SRC):], frame.f_code.co_firstlineno))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _calls.clear()
    t0 = time.perf_counter()
    sys.setprofile(_profile)
    threading.setprofile(_profile)
    yield
    sys.setprofile(None)
    threading.setprofile(None)
    calls = sorted(f"{f.replace(os.sep, '/')}:{n}" for f, n in _calls)
    _tests[item.nodeid] = {"seconds": time.perf_counter() - t0, "calls": calls}


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    # what a test file calls while it is imported (module-level tables, parametrize lists)
    # counts for each of its tests
    if not isinstance(collector, pytest.Module):
        yield
        return
    _calls.clear()
    sys.setprofile(_profile)
    yield
    sys.setprofile(None)
    _files[collector.nodeid] = sorted(f"{f.replace(os.sep, '/')}:{n}" for f, n in _calls)


def pytest_runtest_logreport(report):
    if report.failed:
        _failed.add(report.nodeid)


def pytest_sessionfinish(session):
    with open(os.environ["MUTATION_TRACE_OUT"], "w") as f:
        for nodeid, entry in _tests.items():
            entry["calls"] = sorted(set(entry["calls"]) | set(_files.get(nodeid.split("::")[0], ())))
        json.dump({"tests": _tests, "failed": sorted(_failed)}, f)
'''


def select_tests(m: Mutant, tests: dict, failed: set[str], worker: Worker) -> list[str]:
    """Node ids (in run order) of the passing tests of ``m.package`` that reach the mutated code."""
    dirs = tuple(d + "/" for d in TESTS[m.package])
    mine = [t for t in tests if t.startswith(dirs) and t not in failed]
    if m.scope:
        key = f"{m.path}:{m.scope}"
        return [t for t in mine if key in tests[t]["calls"]]
    prefix = m.path + ":"
    importers = set(worker.tests_for(m.package, m.path, direct_only=True))
    return [t for t in mine if t.split("::")[0] in importers or any(c.startswith(prefix) for c in tests[t]["calls"])]


class Worker:
    """A private copy of the project in which one mutant at a time is applied and tested."""

    def __init__(self, base: Path, k: int) -> None:
        self.root = base / f"job{k}"
        for name in COPY:
            src = ROOT / name
            if src.is_dir():
                shutil.copytree(src, self.root / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
            elif src.exists():
                self.root.mkdir(parents=True, exist_ok=True)
                shutil.copy2(src, self.root / name)
        self.stamp = time.time_ns()
        self.proc: subprocess.Popen | None = None

    def stop(self) -> None:
        """Kill a pytest still running (its own process group)."""
        if self.proc is not None and self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)

    def _touch(self, f: Path) -> None:
        # a fresh, strictly increasing mtime: numba's cache index never mistakes a mutant for the original
        self.stamp += 2_000_000_000
        os.utime(f, ns=(self.stamp, self.stamp))

    def trace(self, packages: list[str]) -> dict:
        """Run the packages' tests once, unmutated, recording which functions each test calls."""
        (self.root / "_mutation_trace.py").write_text(TRACE_PLUGIN)
        out = self.root / "trace.json"
        files = sorted({f for p in packages for f in self.tests_for(p)})
        env = {"MUTATION_TRACE_SRC": str(self.root / "src" / "hydrokit") + os.sep, "MUTATION_TRACE_OUT": str(out)}
        status, _, dt = self.pytest(files, 4 * 3600, ["-p", "_mutation_trace"], stop=False, extra_env=env)
        data = json.loads(out.read_text())
        data["seconds"] = dt
        return data

    def tests_for(self, package: str, path: str = "", direct_only: bool = False) -> list[str]:
        """The package's test files, those importing the module ``path`` (relative to src/hydrokit)
        first (or only those, with ``direct_only``)."""
        module = "hydrokit." + path[:-3].replace("/", ".") if path else "-"
        pkg, name = module.rsplit(".", 1) if path else ("-", "-")
        files = sorted(p for d in TESTS[package] for p in (self.root / d).rglob("test_*.py"))

        def direct(p: Path) -> bool:
            text = p.read_text(encoding="utf-8")
            return module in text or f"from {pkg} import {name}" in text

        if direct_only:
            files = [p for p in files if direct(p)]
        files.sort(key=lambda p: not direct(p))  # stable: direct importers first
        return [str(p.relative_to(self.root)) for p in files]

    def pytest(
        self,
        tests: list[str],
        timeout: float,
        options: tuple[str, ...] | list[str] = (),
        stop: bool = True,
        extra_env: dict[str, str] | None = None,
    ) -> tuple[str, str, float]:
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(self.root / "src"), str(self.root)]))
        env.update(PYTHONDONTWRITEBYTECODE="1", NUMBA_CACHE_DIR=str(self.root / ".numba_cache"), **(extra_env or {}))
        # in-process (-n 0, not pyproject's xdist workers): its own plugin traces the tests
        cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--no-header", "-n", "0", *options]
        cmd += ["-x"] if stop else []
        cmd += ["--", *tests]  # node ids, a few thousand at most: well inside the argv limit
        t0 = time.perf_counter()
        proc = self.proc = subprocess.Popen(
            cmd, cwd=self.root, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True
        )
        try:
            out, _ = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return "timeout", "", time.perf_counter() - t0
        dt = time.perf_counter() - t0
        text = out.decode(errors="replace")
        failed = next((ln.split(" ")[1] for ln in text.splitlines() if ln.startswith(("FAILED", "ERROR "))), "")
        if proc.returncode == 0:
            return "survived", "", dt
        if proc.returncode in (1, 2):  # test failure, or a collection error (an import broke)
            return "killed", failed, dt
        if proc.returncode == 4 and "found no collectors" in text:  # the mutant broke a test module's import
            return "killed", "collection: " + failed, dt
        if proc.returncode < 0 or "Fatal Python error" in text:  # the test run crashed (a segfault in numba
            # code given a wrong-shaped array): CI goes red just the same
            return "killed", f"crashed (exit {proc.returncode}): " + failed, dt
        return "error", text[-500:], dt

    def run(self, m: Mutant, tests: list[str], timeout: float) -> None:
        f = self.root / "src" / "hydrokit" / m.path
        original = f.read_bytes()
        try:
            f.write_bytes(original[: m.start] + m.new.encode() + original[m.end :])
            self._touch(f)
            m.status, m.killer, m.seconds = self.pytest(tests, timeout)
        finally:
            f.write_bytes(original)
            self._touch(f)


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    if n == 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (c - h, c + h)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--package", nargs="+", choices=PACKAGES, default=list(PACKAGES))
    ap.add_argument("--sample", type=int, default=0, help="random mutants per package (0 = all)")
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("--jobs", type=int, default=1, help="mutants tested at once (each in its own copy)")
    ap.add_argument("--only", nargs="+", default=[], help="keep mutants whose label contains one of these texts")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument(
        "--target", type=float, default=90.0, help="kill rate (%%) each package must reach; exit 1 below it"
    )
    ap.add_argument("--json", type=Path, help="write every mutant's outcome to this file")
    ap.add_argument("--scope", choices=("suite", "package"), default="suite", help="tests that may kill a mutant")
    ap.add_argument(
        "--previous", type=Path, help="a --json file: keep its killed and timed-out mutants, rerun the rest"
    )
    ap.add_argument(
        "--trace", type=Path, help="reuse this traced run if it exists, else save it there (stale once tests change)"
    )
    args = ap.parse_args(argv)

    if args.scope == "package":
        TESTS.update(PACKAGE_TESTS)
    mutants = all_mutants(args.package)
    generated = {p: sum(m.package == p for m in mutants) for p in args.package}
    if args.only:
        mutants = [m for m in mutants if any(s in m.label() for s in args.only)]
    before: dict[tuple[str, str, str], dict] = {}
    if args.previous:  # the same mutants as that run (a source edit since may have removed some)
        previous = json.loads(args.previous.read_text())
        by_key: dict[tuple[str, str, str], list[Mutant]] = {}
        for m in mutants:
            by_key.setdefault(m.key, []).append(m)
        chosen = []
        for d in previous:  # the same line text may recur: take the nearest to the old line number
            cands = [m for m in by_key.get((d["path"], d["code"], d["what"]), []) if m not in chosen]
            if cands:
                chosen.append(min(cands, key=lambda m: abs(m.line - d["line"])))
                before[chosen[-1].key] = d
        if len(chosen) < len(previous):
            print(f"{len(previous) - len(chosen)} mutants of {args.previous} no longer exist (source changed)")
        mutants = chosen
    elif args.sample:
        rng = random.Random(args.seed)
        picked = []
        for p in args.package:
            pool = [m for m in mutants if m.package == p]
            picked += rng.sample(pool, min(args.sample, len(pool)))
        mutants = picked
    if args.list:
        for m in mutants:
            print(m.label(), "->", m.new)
        print(f"{len(mutants)} mutants", {p: generated[p] for p in args.package})
        return 0

    if before:
        for m in mutants:
            d = before.get(m.key)
            if m.status == "pending" and d and d["status"] in ("killed", "timeout") and d["line"] == m.line:
                m.status, m.killer, m.seconds = d["status"], d["killer"], d["seconds"]
    todo = [m for m in mutants if m.status == "pending"]
    t_start = time.perf_counter()
    base = Path(tempfile.mkdtemp(prefix="hydrokit-mutation-"))
    # a kill (SIGTERM) unwinds through the finally below: no stray pytest, no temp copies left
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    workers: list[Worker] = []
    try:
        workers += [Worker(base, k) for k in range(max(1, args.jobs))]
        if args.trace and args.trace.exists():
            trace = json.loads(args.trace.read_text())
        else:
            trace = workers[0].trace(sorted({m.package for m in todo}))
            if args.trace:
                args.trace.write_text(json.dumps(trace))
        tests, failed = trace["tests"], set(trace["failed"])
        print(f"traced {len(tests)} tests in {trace['seconds']:.0f} s", flush=True)
        if failed:
            print(f"left out, failing unmutated: {', '.join(sorted(failed))}", file=sys.stderr)
        plan = {}
        for m in todo:
            sel = select_tests(m, tests, failed, workers[0])
            if sel:
                plan[id(m)] = (sel, 60.0 + 3.0 * sum(tests[t]["seconds"] for t in sel))
            else:
                m.status = "uncovered"
        free = list(workers)
        lock = threading.Lock()
        done = [0]
        queue = [m for m in todo if id(m) in plan]

        def one(m: Mutant) -> None:
            with lock:
                w = free.pop()
            try:
                w.run(m, *plan[id(m)])
            finally:
                with lock:
                    free.append(w)
                    done[0] += 1
                    tail = f" ({m.killer})" if m.killer else ""
                    print(f"[{done[0]}/{len(queue)}] {m.status:9s} {m.seconds:6.1f} s  {m.label()}{tail}", flush=True)

        pool = ThreadPoolExecutor(max_workers=len(workers))
        try:
            list(pool.map(one, queue))
        finally:
            pool.shutdown(wait=False, cancel_futures=True)
    finally:
        for w in workers:
            w.stop()
        shutil.rmtree(base, ignore_errors=True)
    wall = time.perf_counter() - t_start

    sample = f"sample of {args.sample} per package, seed {args.seed}" if args.sample else "all mutants"
    print(f"\nmutation score ({sample}; tests: {args.scope}; {wall / 60:.1f} min, {args.jobs} job(s))")
    print(
        f"{'package':10s} {'generated':>9s} {'tested':>6s} {'killed':>6s} {'timeout':>7s} {'survived':>8s} "
        f"{'uncovered':>9s} {'equiv':>5s} {'error':>5s}  kill rate"
    )
    below = []
    for p in args.package:
        ms = [m for m in mutants if m.package == p]
        n = {
            s: sum(m.status == s for m in ms)
            for s in ("killed", "timeout", "survived", "uncovered", "equivalent", "error")
        }
        k = n["killed"] + n["timeout"]
        denom = k + n["survived"] + n["uncovered"] + n["error"]
        lo, hi = wilson(k, denom)
        rate = f"{100 * k / denom:5.1f} %  (95 % CI {100 * lo:.0f}–{100 * hi:.0f} %)" if denom else "  n/a"
        if denom and 100 * k / denom < args.target:
            below.append(p)
        print(
            f"{p:10s} {generated[p]:9d} {len(ms):6d} {n['killed']:6d} {n['timeout']:7d} {n['survived']:8d} "
            f"{n['uncovered']:9d} {n['equivalent']:5d} {n['error']:5d}  {rate}"
        )
    survivors = [m for m in mutants if m.status in ("survived", "uncovered", "error")]
    if survivors:
        print("\nsurvivors (add a test, or an EQUIVALENT entry with its reason):")
        for m in survivors:
            print(f"  {m.status:9s} {m.label()}  ->  {m.new}")
    if args.json:
        args.json.write_text(json.dumps([asdict(m) for m in mutants], indent=1, ensure_ascii=False))
    verdict = (
        f"below the {args.target:g} % target: {', '.join(below)}" if below else f"every package ≥ {args.target:g} %"
    )
    print(f"\n{verdict}")
    return 1 if below else 0


if __name__ == "__main__":
    raise SystemExit(main())
