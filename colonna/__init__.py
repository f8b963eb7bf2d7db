"""colonna: seismic assessment of cracked stone columns held by steel collars.

The subpackages keep their own folders at the repository root and install under this name:

* :mod:`colonna.rigid`   rocking of rigid blocks: the SDOF Housner models (solid or cracked with
  collar springs), spectra, collar design, and the rigid multibody contact model;
* :mod:`colonna.fem`     the 2D finite-element contact model (scikit-fem, explicit dynamics);
* :mod:`colonna.meshes`  column meshes and mesh I/O (meshio);
* :mod:`colonna.studies` study files, the command line and the HTML reports.

The names below are the public API.

>>> import colonna
>>> block = colonna.Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
>>> pulse = colonna.pulse_from_ratios(block, "sine", 5.0, 3.0, "linear")
>>> colonna.rock(block, pulse, model="linear").mode
'safe'
"""

from __future__ import annotations

import os as _os

# In the source tree the subpackages sit beside this folder (rigid/, fem/, ...); installed, they
# sit inside it. Let ``colonna.rigid`` resolve in both.
_here = _os.path.dirname(_os.path.abspath(__file__))
_root = _os.path.dirname(_here)
if not _os.path.isdir(_os.path.join(_here, "rigid")) and _os.path.isfile(
    _os.path.join(_root, "rigid", "__init__.py")
):
    __path__.append(_root)  # noqa: F821 (the package's own search path)

from .rigid import (  # noqa: E402
    Block,
    Collar,
    HarmonicPulse,
    InputError,
    Record,
    RockingResult,
    housner_restitution,
    pulse_from_ratios,
    read_record,
    rock,
)
from .rigid.multibody import MultibodyResult, multibody_spectrum, rock_multibody  # noqa: E402
from .rigid.spectrum import Spectrum, overturning_spectrum  # noqa: E402
from .studies.schema import read_collars  # noqa: E402

try:
    from importlib.metadata import PackageNotFoundError, version

    __version__ = version("colonna")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

__all__ = [
    "Block",
    "Collar",
    "HarmonicPulse",
    "InputError",
    "MultibodyResult",
    "Record",
    "RockingResult",
    "Spectrum",
    "__version__",
    "housner_restitution",
    "multibody_spectrum",
    "overturning_spectrum",
    "pulse_from_ratios",
    "read_collars",
    "read_record",
    "rock",
    "rock_multibody",
]
