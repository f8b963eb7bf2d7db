"""The Zhang & Makris validation (kind ``zhang-makris``): does the rigid solver reproduce the
literature? The block of Zhang & Makris (2001) that the source paper validates against (p = 2.14
rad/s, alpha = 0.25 rad, nu = 0.9, one-sine pulse): time histories at the paper's four
amplitudes, the amplitude boundaries of the overturning modes, and the overturning spectra of
both models with and without collars. It assesses no column.

``run`` (:mod:`.runner`) runs it into ``summary.json``; ``write_report`` (:mod:`.report`) writes
``index.html``; ``zhang_makris_validation`` is ``colonna validate``; ``mode_boundaries`` finds
the amplitudes where the overturning mode changes.
"""

from .report import write_report
from .runner import mode_boundaries, run, zhang_makris_validation

__all__ = ["mode_boundaries", "run", "write_report", "zhang_makris_validation"]
