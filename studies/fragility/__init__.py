"""The fragility study (kind ``fragility``): how likely is each limit state of the column
(uplift, a rotation threshold, overturning, collar yield and fracture, toe crushing) at a given
intensity, over a suite of records? IDA or multiple-stripe analysis through the SDOF, the rigid
multibody model and the FEM, lognormal fits with bootstrap bands, and the likelihood-ratio test
whether the rigid and FEM data are one curve.

``run`` (:mod:`.runner`) runs the suite into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from it; ``colonna fragility`` (:mod:`.command`) runs the SDOF alone.
"""

from .runner import FEWER, defaults, fem_work, run


def write_report(out):
    """index.html of a fragility study (:func:`.report.write_report`; matplotlib is imported
    only here, so that the command line's parser, which reads this package, stays light)."""
    from .report import write_report as write

    return write(out)


__all__ = ["FEWER", "defaults", "fem_work", "run", "write_report"]
