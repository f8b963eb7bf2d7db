"""colonna.rigid: Housner rocking of a solid or cracked stone column held by steel collars.

Solvers: :func:`rock` (time history), :func:`overturning_spectrum` (:mod:`rigid.spectrum`), the
multibody contact model (:mod:`rigid.multibody`); collar design: :mod:`rigid.design`. The ground
motions, the collar description and the input errors are the shared core's (:mod:`colonna.core`),
re-exported here so that a rigid analysis needs one import.
"""

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
from .block import Block, housner_restitution, pulse_from_ratios
from .solve import RockingResult, rock

__all__ = [
    "Block",
    "Collar",
    "HarmonicPulse",
    "InputError",
    "NoMotion",
    "Record",
    "RockingResult",
    "cosine_pulse",
    "housner_restitution",
    "pulse_from_ratios",
    "read_peer_at2",
    "read_record",
    "read_two_column",
    "rock",
    "sine_pulse",
]
