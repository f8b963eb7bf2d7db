"""Mesh convergence (kind ``mesh-convergence``): are the FEM's numbers converged on the study's
mesh? The FEM model on a sequence of meshes h, h/r, h/r^2, ...: peak rotation, collar stress and
toe stress on each, with the observed order and a Richardson estimate.

``run`` (:mod:`.runner`) runs its meshes into ``summary.json``; ``write_report`` (:mod:`.report`)
writes ``index.html`` from it; ``mesh_sizes`` gives the sizes of a study file's [convergence].
"""

from .report import write_report
from .runner import FEWER, fem_work, mesh_sizes, run

__all__ = ["FEWER", "fem_work", "mesh_sizes", "run", "write_report"]
