"""One launch as fitted: the trimmed record, its result and the fitted estimator.

Kept apart from :mod:`hydrokit.identify.result` so the figures (:mod:`hydrokit.plot.identify`,
:mod:`hydrokit.plot.adequacy`) read a fit without importing the campaign result, whose ``plot``
method hands off to them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from hydrokit.identify.types import Launch, LaunchResult

__all__ = ["IdentifiedLaunch", "predict"]


@dataclass
class IdentifiedLaunch:
    """One launch: the trimmed record, its result and the fitted estimator (``predict(t)``).

    ``prediction`` (m or rad at the launch's own sample times) stands in for the estimator when
    the fit ran elsewhere (a worker process) and only its numbers came back.
    """

    launch: Launch
    result: LaunchResult
    estimator: Any
    prediction: np.ndarray | None = None


def predict(item: IdentifiedLaunch) -> np.ndarray:
    """The fitted signal of one launch at its own sample times (m or rad)."""
    if item.prediction is not None:
        return np.asarray(item.prediction, float)
    return np.asarray(item.estimator.predict(np.asarray(item.launch.t, float)))
