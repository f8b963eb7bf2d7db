"""The fragility study (kind ``fragility``): how likely is each limit state of the column
(uplift, a rotation threshold, overturning, collar yield and fracture, toe crushing) at a given
intensity, over a suite of records? IDA or multiple-stripe analysis through the SDOF, the rigid
multibody model and the FEM, lognormal fits with bootstrap bands, and the likelihood-ratio test
whether the rigid and FEM data are one curve.

``run`` (:mod:`.runner`) runs the suite into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from it.
"""

from .report import write_report
from .runner import FEWER, defaults, fem_work, run

__all__ = ["FEWER", "defaults", "fem_work", "run", "write_report"]
