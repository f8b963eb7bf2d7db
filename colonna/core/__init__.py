"""The shared core: what the physics packages share and nothing that depends on them.

* :mod:`colonna.core.errors`      the errors by kind (input, stale results, numerical failure)
  and the range checks (one line: field and range);
* :mod:`colonna.core.constants`   g and the steel defaults;
* :mod:`colonna.core.ground`      ground motions (pulses, records, no motion): one protocol,
  ``acceleration(t)``, ``end_time``, ``peak_acceleration``;
* :mod:`colonna.core.collar`      the collar description (section, steel, axial law's data);
* :mod:`colonna.core.collar_law`  the collars' compiled frame element (local law and axial
  plasticity), used by the FEM's and the multibody model's collars;
* :mod:`colonna.core.tables`      the compiled evaluation of the ground-motion tables;
* :mod:`colonna.core.esm`         ESM ASCII records (the Engineering Strong-Motion database);
* :mod:`colonna.core.suite`       record suites (a folder or a TOML list, scale and SHA-256);
* :mod:`colonna.core.synthetic`   seeded near-fault records (M&P 2003 pulse, R&DK 2008 noise);
* :mod:`colonna.core.intensity`   intensity measures (PGA ... Arias, CAV, D5-95, Sa(T), rocking);
* :mod:`colonna.core.fragility`   lognormal fragility fits (Baker 2015), bootstrap, LR test.

``rigid``, ``fem``, ``meshes`` and ``studies`` import from here; this package imports none of them.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable


def lazy_exports(
    namespace: dict, names: dict[str, str], subpackages: tuple[str, ...] = ()
) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` (PEP 562) of a package whose public names are imported
    on first use, so that importing the package loads none of its modules' dependencies (numba,
    scikit-fem, ...). ``namespace``: the package's ``globals()``; ``names``: public name -> the
    module that defines it, relative to the package (``".solve"``, ``"..core.errors"``);
    ``subpackages``: its subpackages, also imported on first use. A name, once imported, is kept
    in the package, so its next use does not come here."""
    package = namespace["__name__"]

    def __getattr__(name: str) -> object:
        if name in names:
            value = getattr(importlib.import_module(names[name], package), name)
        elif name in subpackages:
            value = importlib.import_module(f".{name}", package)
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted({*namespace, *names, *subpackages})

    return __getattr__, __dir__
