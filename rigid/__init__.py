"""colonna.rigid: Housner rocking of a solid or cracked stone column held by steel collars.

The block, ground motion and collar descriptions are plain frozen dataclasses shared with the
finite-element model (``fem``). Solvers: :func:`rock` (time history) and
:func:`overturning_spectrum`; collar design: :mod:`rigid.design`.
"""

from .block import Block, housner_restitution
from .collars import Collar
from .ground import (HarmonicPulse, NoMotion, Record, cosine_pulse, pulse_from_ratios, read_peer_at2,
                     read_record, read_two_column, sine_pulse)
from .solve import RockingResult, rock
from .validation import InputError

__all__ = ["Block", "Collar", "HarmonicPulse", "InputError", "NoMotion", "Record",
           "RockingResult",
           "cosine_pulse", "housner_restitution", "pulse_from_ratios",
           "read_peer_at2", "read_record", "read_two_column", "rock", "sine_pulse"]
