"""Free rocking (kind ``free-rocking``): how much energy does the column lose at impact? The
column, released from rest at a few tilts with no ground motion, rocks freely; the velocity
ratio at every impact of the FEM and of the rigid multibody model, beside Housner's
1 - 1.5 sin^2(alpha), and what the FEM's value depends on (contact damping, mesh).

``run`` (:mod:`.runner`) runs its cases into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from what the run left on disk; ``with_defaults`` and ``as_run`` give a
study file's tables with this kind's own defaults.
"""

from .report import write_report
from .runner import FEWER, defaults, fem_work, run

__all__ = ["FEWER", "defaults", "fem_work", "run", "write_report"]
