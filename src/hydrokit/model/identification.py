"""What a fit claims of a vehicle it wrote (issue #48): the ``identification:`` block of a
vehicle file.

``hydrokit sysid fit`` (and ``sysid compare``) write the block with the fit's verdict — does the
identified model describe the runs — its reasons, the held-out NRMSE per channel, the runs, the
tool and the date (:func:`hydrokit.io.vehicle.identified_vehicle_document`). A vehicle whose block
says ``does not fit`` still loads and flies, but every result that flies it leads its warnings
with :meth:`Identification.warning`, and ``--strict`` refuses it. A file without the block
(hand-written, or the block deleted by hand) makes no claim.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: the verdicts a block may hold
VERDICTS = ("fits", "does not fit")
#: the text every "does not fit" warning carries (the reports find their banner by it)
UNFIT_MARK = 'its identification says "does not fit"'
#: how much of the first reason a warning quotes, characters
REASON_CHARS = 200


@dataclass(frozen=True)
class Identification:
    """The ``identification:`` block of a vehicle file.

    Attributes
    ----------
    verdict : str — ``fits`` or ``does not fit``
    reasons : tuple of str — the verdict's reasons, plain sentences
    holdout_nrmse : dict — held-out run → channel → NRMSE (–, RMS residual over the channel's
        standard deviation); empty when no run was held out
    runs : tuple of str — the fitted runs (file stems); holdout : tuple of str — the held-out ones
    method : str — ``output-error`` or ``equation-error`` ("" when not said)
    tool : str — what wrote the block (``hydrokit sysid 0.1.0``)
    date : str — when, ISO 8601 (UTC)
    """

    verdict: str
    reasons: tuple[str, ...] = ()
    holdout_nrmse: dict[str, dict[str, float]] = field(default_factory=dict)
    runs: tuple[str, ...] = ()
    holdout: tuple[str, ...] = ()
    method: str = ""
    tool: str = ""
    date: str = ""

    @property
    def fits(self) -> bool:
        """True when the fit said the model describes the runs."""
        return self.verdict == "fits"

    def warning(self, source: str) -> str | None:
        """The one-line warning of a vehicle that does not fit (None when it fits).

        Parameters
        ----------
        source : str — the vehicle file's path (named in the text)

        Returns
        -------
        str or None — ``FILE: its identification says "does not fit" (first reason): the
        predictions below are not trustworthy``
        """
        if self.fits:
            return None
        return f"{source}: {UNFIT_MARK}{self.why}: the predictions below are not trustworthy"

    @property
    def why(self) -> str:
        """The first reason in brackets, shortened to about :data:`REASON_CHARS` characters at a
        word (the whole reasons are in the file), or "" when the block gives none."""
        if not self.reasons:
            return ""
        text = " ".join(self.reasons[0].split()).rstrip(".")
        if len(text) > REASON_CHARS:
            text = text[:REASON_CHARS].rsplit(" ", 1)[0] + " …"
        return f" ({text})"


def is_unfit_warning(text: str) -> bool:
    """True when ``text`` is the warning of a vehicle whose identification does not fit."""
    return UNFIT_MARK in text
