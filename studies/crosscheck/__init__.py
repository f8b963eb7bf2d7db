"""The cross-check (kind ``cross-check``): is the rigid-body assumption good enough for this
column? One column and one ground motion through the 2D FEM contact model and the rigid models
(the rigid multibody reference, the paper's SDOF half block with collars, the whole column as
one block), side by side: rotations, impacts, overturning, energy lost at impact, and whether
the collars yield or break and the toe crushes, with a verdict.

``run`` (:mod:`.runner`) runs its cases into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from what the run left on disk.
"""

from .report import write_report
from .runner import FEWER, expected_work, fem_work, run

__all__ = ["FEWER", "expected_work", "fem_work", "run", "write_report"]
