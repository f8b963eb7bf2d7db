"""colonna.fem: the 2D finite-element contact model of the (cracked) column.

Plane-stress halves in scikit-fem treated co-rotationally, penalty frictional contact at the base
and along the crack, collars as co-rotational frame elements, explicit central-difference time
stepping from the static gravity state (:mod:`colonna.fem.solver`); a run's files are written by
:mod:`colonna.fem.output`. Studies build and run it through their gateway to the models
(:mod:`colonna.studies.models`).
"""

from typing import TYPE_CHECKING

from ..core import lazy_exports

# name -> the module that defines it, imported on first use (:func:`colonna.core.lazy_exports`):
# ``import colonna.fem`` loads neither scikit-fem nor numba until the model is asked for
_PUBLIC = {
    "ContactSettings": ".model",
    "FemResult": ".solver",
    "FemSettings": ".settings",
    "FemStart": ".settings",
    "Loads": ".model",
    "Model": ".model",
    "Replicas": ".settings",
    "Stone": ".assembly",
    "assemble": ".assembly",
    "build_model": ".model",
    "run": ".solver",
    "stable_time_step": ".model",
    "static_state": ".solver",
}

if TYPE_CHECKING:  # what the names are, for type checkers (nothing is imported at run time)
    from .assembly import Stone, assemble
    from .model import ContactSettings, Loads, Model, build_model, stable_time_step
    from .settings import FemSettings, FemStart, Replicas
    from .solver import FemResult, run, static_state

__getattr__, __dir__ = lazy_exports(globals(), _PUBLIC)

__all__ = [
    "ContactSettings",
    "FemResult",
    "FemSettings",
    "FemStart",
    "Loads",
    "Model",
    "Replicas",
    "Stone",
    "assemble",
    "build_model",
    "run",
    "stable_time_step",
    "static_state",
]
