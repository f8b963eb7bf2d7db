"""Solid vs cracked (kind ``solid-vs-cracked``): what do the crack and the collars change? The
same column uncracked, cracked without collars and cracked with its collars, each through the
FEM and the rigid SDOF model under the study's ground motion.

``run`` (:mod:`.runner`) runs its variants into ``summary.json``; ``write_report``
(:mod:`.report`) writes ``index.html`` from what the run left on disk.
"""

from .report import write_report
from .runner import FEWER, fem_work, run

__all__ = ["FEWER", "fem_work", "run", "write_report"]
