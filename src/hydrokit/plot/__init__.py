"""Figures. The only layer that imports matplotlib (always the Agg backend)."""
