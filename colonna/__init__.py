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
>>> colonna.rock(block, colonna.Motion(pulse), model="linear").mode
'safe'
"""

from __future__ import annotations

import os as _os
from typing import TYPE_CHECKING

from .core import lazy_exports

# In the source tree the subpackages sit beside this folder (rigid/, fem/, ...); installed, they
# sit inside it. Let ``colonna.rigid`` resolve in both.
_here = _os.path.dirname(_os.path.abspath(__file__))
_root = _os.path.dirname(_here)
if not _os.path.isdir(_os.path.join(_here, "rigid")) and _os.path.isfile(
    _os.path.join(_root, "rigid", "__init__.py")
):
    __path__.append(_root)  # noqa: F821 (the package's own search path)

# The public names, each imported from its module on first use (PEP 562), so that ``import
# colonna`` loads neither numba (and compiles nothing) nor scikit-fem, pydantic, scipy or
# matplotlib: name -> the module (relative to this package) that defines it.
_PUBLIC = {
    "Block": ".rigid.block",
    "Collar": ".core.collar",
    "ColonnaError": ".core.errors",
    "FemSettings": ".fem.settings",
    "FemStart": ".fem.settings",
    "HarmonicPulse": ".core.ground",
    "InputError": ".core.errors",
    "Motion": ".core.motion",
    "MultibodyContact": ".rigid.multibody",
    "MultibodyResult": ".rigid.multibody",
    "MultibodySettings": ".rigid.multibody",
    "NumericalFailure": ".core.errors",
    "Record": ".core.ground",
    "Release": ".core.motion",
    "Replicas": ".fem.settings",
    "RockingResult": ".rigid.solve",
    "SdofSettings": ".rigid.solve",
    "Spectrum": ".rigid.spectrum",
    "StaleResultsError": ".core.errors",
    "housner_restitution": ".rigid.block",
    "multibody_spectrum": ".rigid.multibody",
    "overturning_spectrum": ".rigid.spectrum",
    "pulse_from_ratios": ".rigid.block",
    "read_collars": ".studies.schema",
    "read_record": ".core.ground",
    "rock": ".rigid.solve",
    "rock_multibody": ".rigid.multibody",
}
_SUBPACKAGES = ("core", "fem", "meshes", "rigid", "studies")

__all__ = [
    "Block",
    "Collar",
    "ColonnaError",
    "FemSettings",
    "FemStart",
    "HarmonicPulse",
    "InputError",
    "Motion",
    "MultibodyContact",
    "MultibodyResult",
    "MultibodySettings",
    "NumericalFailure",
    "Record",
    "Release",
    "Replicas",
    "RockingResult",
    "SdofSettings",
    "Spectrum",
    "StaleResultsError",
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

if TYPE_CHECKING:  # what the names are, for type checkers (nothing is imported at run time)
    from .core.collar import Collar
    from .core.errors import ColonnaError, InputError, NumericalFailure, StaleResultsError
    from .core.ground import HarmonicPulse, Record, read_record
    from .core.motion import Motion, Release
    from .fem.settings import FemSettings, FemStart, Replicas
    from .rigid.block import Block, housner_restitution, pulse_from_ratios
    from .rigid.multibody import (
        MultibodyContact,
        MultibodyResult,
        MultibodySettings,
        multibody_spectrum,
        rock_multibody,
    )
    from .rigid.solve import RockingResult, SdofSettings, rock
    from .rigid.spectrum import Spectrum, overturning_spectrum
    from .studies.schema import read_collars

    __version__: str


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("colonna")
    except PackageNotFoundError:  # running from a source tree that is not installed
        return "0+unknown"


_getattr, __dir__ = lazy_exports(globals(), _PUBLIC, _SUBPACKAGES)


def __getattr__(name: str) -> object:
    """A public name (or a subpackage) imported on first use, then kept in the package."""
    if name == "__version__":
        globals()[name] = _version()
        return globals()[name]
    return _getattr(name)
