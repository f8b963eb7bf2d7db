"""The collar-layout study kind: the lightest collar layout of a catalogue that meets a target
risk of overturning at the site (:mod:`.runner`), and its report (:mod:`.report`)."""

from ..fragility.runner import defaults  # the same: [ground] is the suite's records
from .runner import FEWER, expected_work, fem_work, run

__all__ = ["FEWER", "defaults", "expected_work", "fem_work", "run", "write_report"]


def write_report(out):
    """The study's report (index.html) from its summary.json."""
    from .report import write_report as write

    return write(out)
