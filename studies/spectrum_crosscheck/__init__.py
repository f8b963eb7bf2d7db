"""The spectrum cross-check (kind ``spectrum-crosscheck``): over which pulses is the rigid-body
assumption good enough? One column, a grid of pulses Omega/p x a_p/a_uplift (or of a record's
time scale and amplitude), each run through the FEM, the rigid multibody model and the paper's
SDOF model: each model's overturning map, where they agree, and their overturning boundaries.

``run`` (:mod:`.runner`) runs its grid into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from it; ``grid_of`` and ``parse_grid_size`` give its grid of pulses.
"""

from .report import write_report
from .runner import FEWER, fem_work, grid_of, parse_grid_size, run


def parse_option(name: str, text: str):
    """Its option of ``colonna study`` (studies/kinds.py: ``options``) from the command line:
    --grid NxM, the grid's counts (:func:`.runner.parse_grid_size`)."""
    return parse_grid_size(text)


__all__ = ["FEWER", "fem_work", "grid_of", "parse_grid_size", "parse_option", "run", "write_report"]
