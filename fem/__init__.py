"""colonna.fem: the 2D finite-element contact model of the (cracked) column.

Plane-stress halves in scikit-fem treated co-rotationally, penalty frictional contact at the base
and along the crack, collars as co-rotational frame elements, explicit central-difference time
stepping from the static gravity state (:mod:`colonna.fem.solver`). Study files build and run it
(:mod:`colonna.studies.fem_study`).
"""

from .assembly import Stone, assemble
from .model import ContactSettings, Model, build_model, stable_time_step
from .solver import FemResult, run, static_state

__all__ = [
    "ContactSettings",
    "FemResult",
    "Model",
    "Stone",
    "assemble",
    "build_model",
    "run",
    "stable_time_step",
    "static_state",
]
