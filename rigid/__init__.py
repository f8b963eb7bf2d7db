"""colonna.rigid: Housner rocking of a solid or cracked stone column held by steel collars.

Solvers: :func:`rock` (time history), :func:`overturning_spectrum` (:mod:`rigid.spectrum`), the
multibody contact model (:mod:`rigid.multibody`); collar design: :mod:`rigid.design`. The ground
motions, the collar description and the input errors are the shared core's (:mod:`colonna.core`),
re-exported here so that a rigid analysis needs one import.
"""

from typing import TYPE_CHECKING

from ..core import lazy_exports

# name -> the module that defines it, imported on first use (:func:`colonna.core.lazy_exports`):
# ``import colonna.rigid`` loads no numba or scipy until a solver is asked for
_PUBLIC = {
    "Block": ".block",
    "Collar": "..core.collar",
    "HarmonicPulse": "..core.ground",
    "InputError": "..core.errors",
    "Motion": "..core.motion",
    "NoMotion": "..core.ground",
    "Record": "..core.ground",
    "Release": "..core.motion",
    "RockingResult": ".solve",
    "SdofSettings": ".solve",
    "cosine_pulse": "..core.ground",
    "housner_restitution": ".block",
    "pulse_from_ratios": ".block",
    "read_peer_at2": "..core.ground",
    "read_record": "..core.ground",
    "read_two_column": "..core.ground",
    "rock": ".solve",
    "sine_pulse": "..core.ground",
}

if TYPE_CHECKING:  # what the names are, for type checkers (nothing is imported at run time)
    from ..core.collar import Collar
    from ..core.errors import InputError
    from ..core.ground import (
        HarmonicPulse,
        NoMotion,
        Record,
        cosine_pulse,
        read_peer_at2,
        read_record,
        read_two_column,
        sine_pulse,
    )
    from ..core.motion import Motion, Release
    from .block import Block, housner_restitution, pulse_from_ratios
    from .solve import RockingResult, SdofSettings, rock

__getattr__, __dir__ = lazy_exports(globals(), _PUBLIC)

__all__ = [
    "Block",
    "Collar",
    "HarmonicPulse",
    "InputError",
    "Motion",
    "NoMotion",
    "Record",
    "Release",
    "RockingResult",
    "SdofSettings",
    "cosine_pulse",
    "housner_restitution",
    "pulse_from_ratios",
    "read_peer_at2",
    "read_record",
    "read_two_column",
    "rock",
    "sine_pulse",
]
