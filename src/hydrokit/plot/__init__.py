"""Figures. The only layer that imports matplotlib. It builds Figure objects and never selects
a backend (see ``_mpl``); results hand off to it from their ``plot(ax=None)`` methods."""
