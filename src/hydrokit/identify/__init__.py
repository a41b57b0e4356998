"""Free-decay identification: rig models (spring, pendulum, torsion) and estimators."""
