"""Campaign statistics over many launches (SPEC §1.5).

Per coefficient: mean, standard deviation, a Student-t confidence interval of the mean, n,
and the launches rejected as outliers, plus the same statistics over every launch
(``without_rejection``), so a reader sees what the rule changed. Outlier rule (stated in every
summary): a launch is rejected when its value lies more than 3.5 scaled median absolute
deviations (1.4826·MAD, a robust σ) from the median of *its own amplitude group* (the launches
of one condition), applied only to groups of at least 5 launches and only when at least 4 of
the group remain — so a whole group is never rejected. Judged against the pooled campaign
instead, a group whose coefficient genuinely differs (K_Q at the smallest amplitude) was thrown
out as a block, and the interval came out narrower than the data support.
Amplitude groups are compared pairwise with the two-sided Mann–Whitney rank-sum test: z in
the normal approximation with the continuity correction and its p, which is what CELY2019
Tables 6, 8 and 9 report (U = 36 → z = 2.8022, p = 0.0051), plus the exact p of the
permutation distribution, which is the better figure for groups of six.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from hydrokit.errors import InputError
from hydrokit.identify.types import LaunchResult

SUMMARY_FIELDS = (
    "added_mass",
    "added_mass_coefficient",
    "linear_damping",
    "quadratic_damping",
    "drag_coefficient",
    "natural_frequency",
    "damping_ratio",
    "reynolds_max",
    "kc",
)
#: modified z-score threshold (Iglewicz & Hoaglin 1993: |M_i| > 3.5 flags an outlier)
OUTLIER_Z = 3.5
OUTLIER_RULE = (
    "modified z-score |x − median| / (1.4826 MAD) > 3.5 (Iglewicz–Hoaglin) within each amplitude group, "
    "applied when the group has ≥ 5 launches and ≥ 4 of them remain (a whole group is never rejected)"
)


def outliers(values: Sequence[float]) -> np.ndarray:
    """Which of one group's values the modified z-score rule rejects (boolean mask).

    M_i = |x_i − median| / (1.4826 MAD) > 3.5 (Iglewicz & Hoaglin 1993), applied only when the
    group has at least 5 values, MAD > 0 and at least 4 values remain; otherwise nothing is
    rejected (never the whole group).

    Parameters
    ----------
    values : sequence of float — finite values of one coefficient in one group (any unit)
    """
    x = np.asarray(values, float)
    bad = np.zeros(x.size, bool)
    if x.size < 5:
        return bad
    med = float(np.median(x))
    mad = 1.4826 * float(np.median(np.abs(x - med)))
    if mad > 0:
        flagged = np.abs(x - med) > OUTLIER_Z * mad
        if x.size - int(flagged.sum()) >= 4:
            bad = flagged
    return bad


def _statistics(x: np.ndarray, confidence: float) -> dict[str, Any]:
    """Mean, sample std, Student-t CI of the mean and n of ``x`` (its unit)."""
    from scipy import stats

    n = int(x.size)
    if n == 0:
        return {"mean": None, "std": None, "ci": [None, None], "n": 0}
    mean = float(np.mean(x))
    std = float(np.std(x, ddof=1)) if n > 1 else 0.0
    ci: list[float | None] = [None, None]
    if n > 1:
        half = float(stats.t.ppf(0.5 + confidence / 2, n - 1)) * std / math.sqrt(n)
        ci = [mean - half, mean + half]
    return {"mean": mean, "std": std, "ci": ci, "n": n}


def describe(
    values: Sequence[float | None],
    files: Sequence[str] | None = None,
    confidence: float = 0.95,
    groups: Sequence[str] | None = None,
) -> dict[str, Any]:
    """Mean, std, t-interval and outliers of one coefficient over launches.

    Each launch is judged by :func:`outliers` against the launches of its own group only; the
    statistics are then taken over all kept launches. ``without_rejection`` holds the same
    statistics over every launch.

    Parameters
    ----------
    values : sequence of float — one value per launch (None/NaN ignored), any unit
    files : sequence of str — launch names, for the rejected list
    confidence : float — confidence level of the interval (0–1)
    groups : sequence of str, optional — the group (condition, e.g. amplitude level) of each
        launch; None judges all launches as one group

    Returns
    -------
    dict — ``mean``, ``std``, ``ci``, ``n`` (outliers excluded), ``rejected`` (file names),
    ``rule``, ``confidence`` and ``without_rejection`` (``mean``, ``std``, ``ci``, ``n`` of all
    launches)
    """
    files = list(files) if files is not None else [str(i) for i in range(len(values))]
    labels = list(groups) if groups is not None else [""] * len(values)
    if not (len(files) == len(labels) == len(values)):
        raise InputError(
            f"describe: {len(values)} values, {len(files)} files and {len(labels)} groups; expected one of each per launch"
        )
    keep = [i for i, v in enumerate(values) if v is not None and math.isfinite(float(v))]
    x = np.array([float(values[i]) for i in keep])  # type: ignore[arg-type]
    bad = np.zeros(x.size, bool)
    group_of = [labels[i] for i in keep]
    for label in dict.fromkeys(group_of):
        idx = np.array([j for j, g in enumerate(group_of) if g == label])
        bad[idx] = outliers(x[idx])
    rejected = [files[keep[j]] for j in np.nonzero(bad)[0]]
    return {
        **_statistics(x[~bad], confidence),
        "rejected": rejected,
        "rule": OUTLIER_RULE,
        "confidence": confidence,
        "without_rejection": _statistics(x, confidence),
    }


def summarize(
    results: Sequence[LaunchResult],
    confidence: float = 0.95,
    groups: Mapping[str, Sequence[LaunchResult]] | None = None,
) -> dict[str, Any]:
    """Per-coefficient statistics over ``results`` (see :func:`describe`), outliers judged within
    each amplitude group (``groups``: label → launches; default :func:`group_by_amplitude`)."""
    if groups is None:
        groups = group_by_amplitude(results, angles=False)
    label_of = {id(r): label for label, members in groups.items() for r in members}
    labels = [label_of.get(id(r), "") for r in results]
    files = [r.file for r in results]
    out: dict[str, Any] = {}
    for name in SUMMARY_FIELDS:
        out[name] = describe([getattr(r, name) for r in results], files, confidence, labels)
    out["outlier_rule"] = OUTLIER_RULE
    return out


def consistency(values: Sequence[float | None], std_errors: Sequence[float | None]) -> dict[str, Any]:
    """Do repeats of one condition agree within their stated uncertainties?

    χ² = Σ (x_i − x̄_w)² / σ_i² about the inverse-variance weighted mean x̄_w, with n − 1
    degrees of freedom; p is the chance of a χ² at least this large if every σ_i were right
    (a small p: the repeats differ by more than their errors say). The Birge ratio
    √(χ²/(n − 1)) is the factor by which the errors would have to grow to explain the scatter.

    Parameters
    ----------
    values : the coefficient of each launch (any unit)
    std_errors : each launch's standard error (same unit); launches without one are skipped
    """
    from scipy import stats

    pairs = [
        (float(x), float(s))
        for x, s in zip(values, std_errors)
        if x is not None and s is not None and math.isfinite(x) and math.isfinite(s) and s > 0
    ]
    n = len(pairs)
    if n < 2:
        return {"n": n, "chi2": None, "dof": 0, "p": None, "birge_ratio": None, "weighted_mean": None}
    x = np.array([a for a, _ in pairs])
    w = 1.0 / np.array([b for _, b in pairs]) ** 2
    mean = float(np.sum(w * x) / np.sum(w))
    chi2 = float(np.sum(w * (x - mean) ** 2))
    dof = n - 1
    return {
        "n": n,
        "chi2": chi2,
        "dof": dof,
        "p": float(stats.chi2.sf(chi2, dof)),
        "birge_ratio": math.sqrt(chi2 / dof),
        "weighted_mean": mean,
    }


def amplitude_label(amplitude: float, rotational_units: bool) -> str:
    """A readable group label: mm for positions, degrees for angles."""
    return f"{math.degrees(amplitude):.3g}°" if rotational_units else f"{amplitude * 1e3:.3g} mm"


def group_by_amplitude(
    results: Sequence[LaunchResult], angles: bool, rel_tol: float = 0.15
) -> dict[str, list[LaunchResult]]:
    """Group launches whose initial amplitudes agree within ``rel_tol`` (nominal launch levels)."""
    order = sorted(results, key=lambda r: r.amplitude)
    groups: list[list[LaunchResult]] = []
    for r in order:
        if groups and abs(r.amplitude - groups[-1][0].amplitude) <= rel_tol * max(abs(groups[-1][0].amplitude), 1e-12):
            groups[-1].append(r)
        else:
            groups.append([r])
    return {
        f"L{i + 1} ({amplitude_label(float(np.mean([r.amplitude for r in g])), angles)})": g
        for i, g in enumerate(groups)
    }


def rank_sum(x: Sequence[float], y: Sequence[float], continuity: bool = True) -> dict[str, Any]:
    """Two-sided Mann–Whitney rank-sum test of two launch groups.

    Parameters
    ----------
    x, y : values of one coefficient in two groups (any unit, the same for both)
    continuity : bool — apply the continuity correction to z, as CELY2019 Tables 8–9 print
        (U = 36 of 6 × 6 → z = 2.8022, p = 0.0051); ``False`` gives the uncorrected z

    Returns
    -------
    dict — ``u`` (U of ``x``: pairs with x > y, ties ½), ``z`` = (U − n₁n₂/2 ∓ ½)/σ_U with the
    tie-corrected σ_U, ``p`` the two-sided normal p of that z (what the sources tabulate),
    ``p_exact`` the exact two-sided p from the permutation distribution (scipy, when there are no
    ties; None otherwise) — the better number for groups of six — and ``continuity``.
    """
    from scipy import stats

    xa, ya = np.asarray(x, float), np.asarray(y, float)
    n1, n2 = xa.size, ya.size
    u1 = float(stats.mannwhitneyu(xa, ya, alternative="two-sided", method="asymptotic").statistic)
    ranks = stats.rankdata(np.concatenate([xa, ya]))
    _, counts = np.unique(ranks, return_counts=True)
    n = n1 + n2
    tie = float(np.sum(counts**3 - counts)) / (n * (n - 1))
    sigma = math.sqrt(n1 * n2 / 12.0 * ((n + 1) - tie))
    d = u1 - n1 * n2 / 2.0
    if continuity:
        d = math.copysign(max(abs(d) - 0.5, 0.0), d)
    z = d / sigma if sigma > 0 else 0.0
    p_exact = None
    if np.all(counts == 1):
        p_exact = float(stats.mannwhitneyu(xa, ya, alternative="two-sided", method="exact").pvalue)
    return {"u": u1, "z": z, "p": z_to_p(z), "p_exact": p_exact, "continuity": continuity}


def z_to_p(z: float) -> float:
    """Two-sided p of a standard-normal z (as CELY2019 tabulates z next to p)."""
    from scipy import stats

    return float(2.0 * stats.norm.sf(abs(z)))


def rank_sum_pairs(groups: dict[str, Sequence[float]]) -> list[dict[str, Any]]:
    """Pairwise rank-sum tests between all groups (CELY2019 Tables 6, 8, 9)."""
    names = list(groups)
    out = []
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            a, b = groups[names[i]], groups[names[j]]
            if len(a) < 2 or len(b) < 2:
                continue
            out.append({"pair": [names[i], names[j]], **rank_sum(a, b)})
    return out
