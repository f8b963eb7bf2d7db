"""Crack extent (kind ``crack-extent``, issue 51): how much of the paper's full-crack hypothesis
does this column need? The study's column through the FEM with its crack running over 0, 1/4,
1/2, 3/4 and the whole of its height (from the top down, or from the base up where the study's
[column] crack starts at the base) and over its own extent (the column as found), the rest of
the mid-plane intact stone that can crack; beside them its two rigid limits, the solid column
and the fully split one with its collars (the SDOF models).

``run`` (:mod:`.runner`) runs its variants into ``summary.json``; ``write_report``
(:mod:`.report`) writes ``index.html`` from what the run left on disk.
"""

from .report import write_report
from .runner import FEWER, fem_work, run

__all__ = ["FEWER", "fem_work", "run", "write_report"]
