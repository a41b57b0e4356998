"""Standard manoeuvres (IMO MSC.137(76), ITTC 7.5-04-02-01) flown and measured, and trial replay.

``definitions`` (what to fly: :class:`~hydrokit.manoeuvre.definitions.Manoeuvre`, ``turning_circle``,
``zigzag`` …), ``run`` (the helm logics, the hold and the loop:
:func:`hydrokit.manoeuvre.run.run_manoeuvre`), ``laws`` (the helm and hold laws on plain floats),
``compiled`` (the same loop compiled with numba), ``result`` (a record measured into a
``ManoeuvreResult``), ``metrics`` (overshoots, advance, tactical diameter … measured on a track),
``criteria`` (the IMO §5.3 criteria) and ``samples`` (predictions with intervals over vehicles
drawn from the ``uncertainty:`` block); ``replay`` flies a model through a recorded trial's inputs
and measures both tracks with the same code.

The package object itself is callable: ``hydrokit.manoeuvre(vehicle, zigzag(a, b), …)`` is
:func:`hydrokit.api.manoeuvre`.
"""

from __future__ import annotations

from hydrokit._callable import make_callable

make_callable(__name__)
