"""Names shared by every layer: degrees of freedom, state and force columns, coefficients.

One definition of each list, so a file format, a table and a plot can never disagree on the
order of the six degrees of freedom (SNAME 1950: surge, sway, heave, roll, pitch, yaw).
"""

from __future__ import annotations

#: the six degrees of freedom, in the order of τ = [X Y Z K M N] and ν = [u v w p q r]
DOF_NAMES: tuple[str, ...] = ("surge", "sway", "heave", "roll", "pitch", "yaw")
#: SNAME force/moment symbols, one per DOF (X Y Z in N, K M N in N·m)
FORCE_SYMBOLS: tuple[str, ...] = ("X", "Y", "Z", "K", "M", "N")
#: body velocity symbols, one per DOF (u v w in m/s, p q r in rad/s)
VELOCITY_SYMBOLS: tuple[str, ...] = ("u", "v", "w", "p", "q", "r")
#: NED position and Euler-angle symbols of η (x y z in m, φ θ ψ in rad)
POSE_SYMBOLS: tuple[str, ...] = ("x", "y", "z", "phi", "theta", "psi")
#: columns of a trajectory table and CSV: time (s), η, ν
STATE_COLUMNS: tuple[str, ...] = ("time", *POSE_SYMBOLS, *VELOCITY_SYMBOLS)
#: columns of a force table and CSV: time (s), τ
FORCE_COLUMNS: tuple[str, ...] = ("time", *FORCE_SYMBOLS)
#: the three coefficients identified per degree of freedom, in the order of a fitted parameter
#: vector and its covariance: added mass m_a (kg; kg·m² for a rotation), linear damping K_L
#: (N·s/m; N·m·s/rad) and quadratic damping K_Q (N·s²/m²; N·m·s²/rad²). The keys of a rig fit,
#: of a campaign summary and of a vehicle file's ``uncertainty:`` block.
COEFFICIENTS: tuple[str, ...] = ("added_mass", "linear_damping", "quadratic_damping")
