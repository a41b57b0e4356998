"""Standard manoeuvres (IMO MSC.137(76), ITTC 7.5-04-02-01) flown and measured, and trial replay.

``run`` (the manoeuvre definitions, the helm logics and the loop: :func:`hydrokit.manoeuvre.run.run_manoeuvre`)
uses ``laws`` (the helm and hold laws on plain floats), ``compiled`` (the same loop compiled with
numba), ``metrics`` (overshoots, advance, tactical diameter … measured on a track) and
``samples`` (the recorded channels); ``replay`` flies a model through a recorded trial's inputs
and measures both tracks with the same code.

The package object itself is callable: ``hydrokit.manoeuvre(vehicle, zigzag(a, b), …)`` is
:func:`hydrokit.api.manoeuvre`. The old names ``hydrokit.simulate.manoeuvre*`` and
``hydrokit.simulate.replay`` are the same modules, kept for one release.
"""

from __future__ import annotations

from hydrokit._callable import make_callable

make_callable(__name__)
