"""Coefficients from geometry and from force-speed curves."""
