"""The JSON result document of ``hydrokit identify`` (issue #2 format).

``{"launches": [...], "summary": {...}, "pairwise": [...], "rig": {...}, "method": ...}``;
each launch object holds every :class:`hydrokit.identify.types.LaunchResult` field plus
``notes`` (what reading and trimming did). The document is
:meth:`hydrokit.identify.result.CampaignResult.to_dict`; this module only writes it.
"""

from __future__ import annotations

import json
from typing import Any


def dumps(doc: dict[str, Any]) -> str:
    """JSON text (strict: NaN/inf must already be ``None``, as ``to_dict()`` gives)."""
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"
