"""The collar design (kind ``collar-design``): do the collars yield, and which collars does the
column need? The corrected design chart (paper Eq. 22-24) over slenderness and pulse, the design
numbers of the study's collar section at its pulse's peak, the check of the chosen collars
against the collar stress of the FEM run, and the thinnest plastic band that never yields or
that yields but holds (rigid multibody trials).

``run`` (:mod:`.runner`) runs its cases into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from what the run left on disk.
"""

from .report import write_report
from .runner import FEWER, fem_work, run

__all__ = ["FEWER", "fem_work", "run", "write_report"]
