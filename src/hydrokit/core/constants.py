"""Physical constants the packages default to (SI).

Defaults only: every place that uses one takes the value from a file or an argument first.
"""

from __future__ import annotations

#: Sea water, kg/m³ — the density of the sources (SPEC §2.1: REHMAN Table 1 is reproduced with
#: 1025; SPEC §8) and of DNV-RP-C205; the fluid of any rig, vehicle or shape that names none.
SEAWATER_DENSITY = 1025.0

#: Gravitational acceleration, m/s² — the sources' rig files (ENG2009, CELY2019) use 9.81.
GRAVITY = 9.81
