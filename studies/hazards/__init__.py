"""Example hazard curves (colonna.core.hazard): each file says its source, or that it is
illustrative, in its # lines."""
