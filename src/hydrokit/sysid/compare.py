"""Model structures compared (issue #48 item 5): several candidate vehicle files, each with its
own free parameters, fitted on the same runs and ranked by what they predict.

Eight plausible term structures can span −12…+20 % in a manoeuvre's tactical diameter: the
structure, not the data, then decides the answer. Each candidate is fitted by
:func:`hydrokit.sysid.fit.identify` on the same training runs and judged by

1. **Held-out error** — the NRMSE (RMS error / standard deviation of the measured channel) of
   the open-loop prediction of the held-out runs, per channel that moves (standard deviation
   above 3 sensor-noise σ, :data:`hydrokit.sysid.stats.MOVING`), averaged over held-out
   runs; the score is its mean over those channels.
2. **An information criterion** on the training residuals. The output-error likelihood with
   Gaussian residuals of one unknown variance per channel, maximised over that variance, is
   −2 ln L = Σ_c N_c (ln 2π σ̂_c² + 1) with σ̂_c² the mean squared residual of channel c.
   Residuals sampled at 50 Hz are not independent, so N_c is replaced by an effective count:
   per residual series (one channel of one run) N_eff = N (1 − ρ₁)/(1 + ρ₁), the variance
   inflation of the mean of an AR(1) series with lag-1 autocorrelation ρ₁ (clipped to
   [0, 0.99]; Bayley & Hammersley 1946, J. R. Stat. Soc. Suppl. 8, "The effective number of
   independent observations in an autocorrelated time series"). So that every candidate is
   weighed on one footing, the fraction N_eff/N of each channel is taken from the best-fitting
   candidate (lowest −2 ln L at the full count) — its residuals are closest to the sensors'
   own colour — and applied to all. Then AIC = −2 ln L + 2k and BIC = −2 ln L + k ln N_eff
   (Akaike 1974; Schwarz 1978), k = the candidate's free parameters (the initial states of the
   runs are estimated for every candidate alike and cancel in the differences).
3. **The verdict** of each fit (:func:`hydrokit.sysid.stats.verdict`).

**Which to keep.** The candidates whose held-out error is within :data:`EQUIVALENT` (5 %) of
the lowest predict equally; of those, the one with the lowest BIC is kept (a needed parameter
lowers it, a useless one costs ln N_eff). The ranking lists the equally-predicting candidates
by BIC, then the others by held-out error.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hydrokit._result import Result, jsonable
from hydrokit.errors import InputError
from hydrokit.model.vehicle import Vehicle
from hydrokit.sysid.fit import SysidResult, identify
from hydrokit.sysid.model import RunData
from hydrokit.sysid.stats import whiteness

#: held-out errors within this fraction of the lowest are said to predict equally
EQUIVALENT = 0.05
#: the lag-1 autocorrelation used for the effective sample count is clipped to [0, RHO_MAX]
RHO_MAX = 0.99
#: a candidate's name becomes a folder name in the outputs
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


@dataclass(frozen=True)
class Candidate:
    """One model structure to fit.

    name : str — a short label (letters, digits, ``._-``), also the folder of its outputs
    vehicle : Vehicle with thrusters — the base (every coefficient not free keeps its value)
    free : tuple of str — its free parameters (``added_mass.yaw``, ``terms.N_r|r|`` …)
    runs, holdout : training and held-out runs, read with this vehicle's thruster and surface
        names (the same files for every candidate)
    source : str — where the vehicle came from (a file or bundled name), for the report
    """

    name: str
    vehicle: Vehicle
    free: tuple[str, ...]
    runs: Sequence[RunData]
    holdout: Sequence[RunData]
    source: str = ""


@dataclass(frozen=True)
class Scored:
    """A fitted candidate and its scores.

    name, source : str; free : tuple of str; k : int — free parameters
    result : SysidResult — the fit
    heldout_nrmse : dict — moving channel → held-out NRMSE (mean over held-out runs, unit-free)
    heldout : float — mean of ``heldout_nrmse`` (unit-free)
    information : dict — ``n`` (training samples), ``n_eff`` (effective samples),
        ``minus_2_log_likelihood``, ``aic``, ``bic`` (unit-free)
    """

    name: str
    source: str
    free: tuple[str, ...]
    k: int
    result: SysidResult
    heldout_nrmse: dict[str, float]
    heldout: float
    information: dict[str, float]

    @property
    def aic(self) -> float:
        return float(self.information["aic"])

    @property
    def bic(self) -> float:
        return float(self.information["bic"])

    @property
    def verdict(self) -> dict[str, Any]:
        v = getattr(self.result, "verdict", None) or {}
        return {"fits": bool(v.get("fits", True)), "reasons": list(v.get("reasons", []))}


@dataclass(frozen=True)
class Comparison(Result):
    """Candidates fitted on the same runs, ranked (module docstring).

    candidates : tuple of Scored — in the order given
    ranking : tuple of str — names, the one to keep first
    keep : str — the name of the one to keep
    recommendation : str — which to keep and why, in one sentence
    notes : tuple of str — caveats (e.g. candidates fitted on different windows)
    effective : dict — channel → N_eff / N used for every candidate (unit-free)
    reference : str — the candidate whose residuals gave ``effective`` (the best-fitting)
    """

    candidates: tuple[Scored, ...]
    ranking: tuple[str, ...]
    keep: str
    recommendation: str
    notes: tuple[str, ...] = ()
    effective: dict[str, float] = field(default_factory=dict)
    reference: str = ""

    def by_name(self, name: str) -> Scored:
        """The scored candidate called ``name``."""
        for c in self.candidates:
            if c.name == name:
                return c
        raise KeyError(name)

    def to_dict(self) -> dict[str, Any]:
        """compare.json: candidates (name, vehicle, free, k, aic, bic, heldout_nrmse, verdict,
        parameters), ranking, keep, recommendation, notes, effective_samples (the fraction N_eff/N
        per channel and the candidate it came from) (SI)."""
        cands = []
        for c in self.candidates:
            r = c.result
            cands.append(
                {
                    "name": c.name,
                    "vehicle": c.source,
                    "free": list(c.free),
                    "k": c.k,
                    "aic": c.aic,
                    "bic": c.bic,
                    "heldout_nrmse": c.heldout_nrmse,
                    "heldout_nrmse_mean": c.heldout,
                    "samples": c.information["n"],
                    "effective_samples": c.information["n_eff"],
                    "minus_2_log_likelihood": c.information["minus_2_log_likelihood"],
                    "verdict": c.verdict,
                    "parameters": [
                        {"name": n, "unit": u, "value": v, "sigma": s}
                        for n, u, v, s in zip(r.parameters, r.units, r.values, r.sigma)
                    ],
                }
            )
        return jsonable(
            {
                "candidates": cands,
                "ranking": list(self.ranking),
                "keep": self.keep,
                "recommendation": self.recommendation,
                "notes": list(self.notes),
                "effective_samples": {"from": self.reference, "fraction": self.effective},
            }
        )

    def table(self) -> tuple[list[str], list[list[Any]]]:
        cols = ["rank", "candidate", "k", "held-out NRMSE", "AIC", "BIC", "verdict"]
        rows = []
        for i, n in enumerate(self.ranking, 1):
            c = self.by_name(n)
            rows.append([i, n, c.k, c.heldout, c.aic, c.bic, "fits" if c.verdict["fits"] else "does not fit"])
        return cols, rows

    def summary_rows(self) -> list[tuple[str, Any]]:
        return [("keep", self.keep), ("why", self.recommendation), ("ranking", ", ".join(self.ranking))]

    def plot(self, ax: Any = None) -> Any:
        """Held-out NRMSE per channel, one bar per candidate (or on ``ax``); returns the axes."""
        from hydrokit.plot.sysid_compare import heldout_axes

        return heldout_axes([c.name for c in self.candidates], [c.heldout_nrmse for c in self.candidates], ax)


# ------------------------------------------------------------------------------ the scores
def training_residuals(result: SysidResult) -> list[tuple[str, str, np.ndarray]]:
    """(run, channel, measured − simulated) of every fitted (not held-out) series, SI."""
    out = []
    for p in result.predictions:
        if p["holdout"]:
            continue
        for c, d in p["channels"].items():
            e = np.asarray(d["measured"], float) - np.asarray(d["simulated"], float)
            out.append((str(p["name"]), str(c), e))
    return out


def effective_fraction(series: Sequence[tuple[str, str, np.ndarray]]) -> dict[str, float]:
    """Channel → N_eff / N over its series, N_eff = N (1 − ρ₁)/(1 + ρ₁) per series (ρ₁ the
    lag-1 autocorrelation of its residuals, clipped to [0, :data:`RHO_MAX`]; a series too short
    for :func:`~hydrokit.sysid.stats.whiteness` counts whole)."""
    n: dict[str, float] = {}
    eff: dict[str, float] = {}
    for _, c, e in series:
        rho = whiteness(e)["lag1"]
        rho = min(max(rho, 0.0), RHO_MAX) if math.isfinite(rho) else 0.0
        n[c] = n.get(c, 0.0) + e.size
        eff[c] = eff.get(c, 0.0) + e.size * (1 - rho) / (1 + rho)
    return {c: eff[c] / n[c] for c in n if n[c] > 0}


def information(
    series: Sequence[tuple[str, str, np.ndarray]], k: int, fraction: Mapping[str, float] | None = None
) -> dict[str, float]:
    """AIC and BIC of a fit from its training residuals (module docstring, step 2).

    Parameters
    ----------
    series : (run, channel, residual) — residuals in SI, one series per channel of each run
    k : int — free parameters of the model (count)
    fraction : channel → N_eff / N (:func:`effective_fraction`); None: every sample counts

    Returns
    -------
    dict — ``n``, ``n_eff`` (samples), ``minus_2_log_likelihood``, ``aic``, ``bic`` (unit-free)
    """
    sq: dict[str, float] = {}
    n: dict[str, int] = {}
    for _, c, e in series:
        sq[c] = sq.get(c, 0.0) + float(np.sum(e**2))
        n[c] = n.get(c, 0) + int(e.size)
    m2ll = 0.0
    n_eff = 0.0
    for c in n:
        var = max(sq[c] / n[c], 1e-300)
        ne = n[c] * (1.0 if fraction is None else float(fraction.get(c, 1.0)))
        m2ll += ne * (math.log(2 * math.pi * var) + 1)
        n_eff += ne
    return {
        "n": float(sum(n.values())),
        "n_eff": n_eff,
        "minus_2_log_likelihood": m2ll,
        "aic": m2ll + 2 * k,
        "bic": m2ll + k * math.log(max(n_eff, 1.0)),
    }


def heldout_nrmse(result: SysidResult) -> dict[str, float]:
    """Moving channel → NRMSE of the open-loop prediction, mean over the held-out runs (unit-free;
    a channel that moves in no held-out run is left out)."""
    acc: dict[str, list[float]] = {}
    for row in result.runs:
        if not row["holdout"]:
            continue
        for c, d in row["channels"].items():
            v = float(d.get("nrmse", float("nan")))
            if d.get("moving") and math.isfinite(v):
                acc.setdefault(c, []).append(v)
    return {c: float(np.mean(v)) for c, v in acc.items()}


# ------------------------------------------------------------------------------ the choice
def _num(x: float) -> str:
    return f"{x:.2g}" if abs(x) < 1 else f"{x:.3g}"


def _params(n: int) -> str:
    return f"{n} parameter{'s' if n != 1 else ''}"


def choose(scores: Sequence[Scored], equivalent: float = EQUIVALENT) -> tuple[tuple[str, ...], str, str]:
    """Ranking, the one to keep and the sentence that says why (module docstring).

    Parameters
    ----------
    scores : two or more scored candidates
    equivalent : float — held-out errors within this fraction of the lowest predict equally

    Returns
    -------
    (ranking names, kept name, sentence)
    """
    if len(scores) < 2:
        raise InputError(f"{len(scores)} candidate(s): expected two or more to compare")
    best_err = min(s.heldout for s in scores)
    tie = [s for s in scores if s.heldout <= best_err * (1 + equivalent)]
    rest = [s for s in scores if s not in tie]
    tie.sort(key=lambda s: (s.bic, s.k))
    rest.sort(key=lambda s: (s.heldout, s.bic))
    ranked = [*tie, *rest]
    keep = ranked[0]
    low_bic = min(scores, key=lambda s: s.bic)
    if len(tie) == 1:
        other = ranked[1]
        text = (
            f"Keep {keep.name}: lowest held-out error ({_num(keep.heldout)} vs {_num(other.heldout)} for {other.name})"
        )
        if low_bic is keep:
            second = min((s for s in scores if s is not keep), key=lambda s: s.bic)
            text += f" and lowest BIC (ΔBIC {second.bic - keep.bic:.0f} to {second.name})"
        else:
            text += (
                f", although {low_bic.name} has a lower BIC (by {keep.bic - low_bic.bic:.0f}): its closer fit to "
                "the training runs does not carry over to the held-out runs"
            )
        if other.k > keep.k:
            n = other.k - keep.k
            text += f"; {other.name}'s extra " + ("parameter does" if n == 1 else f"{n} parameters do") + " not pay"
        elif other.k < keep.k:
            n = keep.k - other.k
            text += "; its extra " + ("parameter pays" if n == 1 else f"{n} parameters pay")
    else:
        others = [s for s in tie if s is not keep]
        names = ", ".join(s.name for s in tie[:-1]) + f" and {tie[-1].name}"
        errs = " vs ".join(_num(s.heldout) for s in tie)
        head = f"{names} predict equally (held-out within {100 * equivalent:.0f} %: {errs})"
        simplest = min(s.k for s in tie)
        nxt = others[0]
        if keep.k == simplest and any(s.k > keep.k for s in others):
            text = (
                f"{head}: keep the simpler {keep.name} ({_params(keep.k)}; ΔBIC {nxt.bic - keep.bic:.0f} to {nxt.name})"
            )
        elif keep.k > simplest:
            simple = min(others, key=lambda s: (s.k, s.bic))
            text = (
                f"{head}: keep {keep.name}: its extra {_params(keep.k - simple.k)} "
                + ("pays" if keep.k - simple.k == 1 else "pay")
                + " on the training runs "
                f"(ΔBIC {simple.bic - keep.bic:.0f} to {simple.name})"
            )
        else:
            text = f"{head}: keep {keep.name}, lowest BIC (ΔBIC {nxt.bic - keep.bic:.0f} to {nxt.name})"
        if low_bic not in tie:
            text += (
                f"; {low_bic.name} has a lower BIC (by {keep.bic - low_bic.bic:.0f}) but predicts the held-out runs "
                f"worse ({_num(low_bic.heldout)}): its closer fit to the training runs does not carry over"
            )
    if not keep.verdict["fits"]:
        text += f"; but even {keep.name} does not describe the runs (its verdict): try another structure"
    return tuple(s.name for s in ranked), keep.name, text + "."


# ------------------------------------------------------------------------------ the fits
def check_candidates(names: Sequence[str]) -> None:
    """Two or more candidates with distinct names usable as folder names.

    Raises
    ------
    InputError
        One line naming the bad or repeated name, or the count.
    """
    if len(names) < 2:
        raise InputError(f"--candidate: {len(names)} given; expected two or more candidates to compare")
    seen: set[str] = set()
    for n in names:
        if not NAME.match(n):
            raise InputError(f"--candidate: name {n!r}: expected letters, digits, '.', '_' or '-' (a folder name)")
        if n in seen:
            raise InputError(f"--candidate: name {n!r} given twice; expected distinct names (NAME=VEHICLE)")
        seen.add(n)


def compare(
    candidates: Sequence[Candidate],
    progress: Callable[[str, int, float], None] | None = None,
    equivalent: float = EQUIVALENT,
    **identify_options: Any,
) -> Comparison:
    """Fit every candidate on its runs and rank them (module docstring).

    Parameters
    ----------
    candidates : two or more :class:`Candidate` (the same run files, each read for its vehicle)
    progress : callable(candidate name, iteration, cost) — after every accepted iteration
    equivalent : float — held-out errors within this fraction of the lowest predict equally
    identify_options : passed to :func:`hydrokit.sysid.fit.identify` (``method``, ``dt``
        in s, ``window``, ``samples``, ``workers`` …)

    Raises
    ------
    InputError
        Fewer than two candidates, a repeated name, no held-out run, or a fit that fails (the
        message names the candidate).
    """
    check_candidates([c.name for c in candidates])
    for c in candidates:
        if not c.holdout:
            raise InputError("--holdout: no held-out run; expected at least one (candidates are ranked by it)")
    fits: list[tuple[Candidate, SysidResult]] = []
    for c in candidates:
        step = None if progress is None else (lambda it, cost, _n=c.name: progress(_n, it, cost))
        try:
            res = identify(c.vehicle, c.runs, c.free, c.holdout, progress=step, **identify_options)
        except InputError as exc:
            raise InputError(f"candidate {c.name}: {exc}") from None
        fits.append((c, res))
    series = [training_residuals(r) for _, r in fits]
    raw = [information(s, len(c.free)) for s, (c, _) in zip(series, fits)]
    ref = int(np.argmin([r["minus_2_log_likelihood"] for r in raw]))
    fraction = effective_fraction(series[ref])
    scores = []
    for (c, res), s in zip(fits, series):
        held = heldout_nrmse(res)
        scores.append(
            Scored(
                name=c.name,
                source=c.source,
                free=tuple(res.parameters),
                k=len(res.parameters),
                result=res,
                heldout_nrmse=held,
                heldout=float(np.mean(list(held.values()))) if held else float("nan"),
                information=information(s, len(res.parameters), fraction),
            )
        )
    notes = []
    if any(not math.isfinite(s.heldout) for s in scores):
        raise InputError(
            "--holdout: no channel of the held-out runs moves above its sensor noise; expected a run that does"
        )
    shapes = {tuple((r, ch, e.size) for r, ch, e in s) for s in series}
    if len(shapes) > 1:
        notes.append(
            "the candidates were fitted on different windows (--window auto windows only a fit that drifts): their "
            "AIC and BIC weigh different residual series; give --window S (or none) to compare them on one footing"
        )
    ranking, keep, sentence = choose(scores, equivalent)
    return Comparison(tuple(scores), ranking, keep, sentence, tuple(notes), fraction, fits[ref][0].name)


__all__ = [
    "EQUIVALENT",
    "Candidate",
    "Comparison",
    "Scored",
    "check_candidates",
    "choose",
    "compare",
    "effective_fraction",
    "heldout_nrmse",
    "information",
    "training_residuals",
]
