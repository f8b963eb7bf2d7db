"""The shared core: what the physics packages share and nothing that depends on them.

* :mod:`colonna.core.errors`      input errors and range checks (one line: field and range);
* :mod:`colonna.core.constants`   g and the steel defaults;
* :mod:`colonna.core.ground`      ground motions (pulses, records, no motion): one protocol,
  ``acceleration(t)``, ``end_time``, ``peak_acceleration``;
* :mod:`colonna.core.collar`      the collar description (section, steel, axial law's data);
* :mod:`colonna.core.collar_law`  the collars' compiled frame element (local law and axial
  plasticity), used by the FEM's and the multibody model's collars;
* :mod:`colonna.core.tables`      the compiled evaluation of the ground-motion tables.

``rigid``, ``fem``, ``meshes`` and ``studies`` import from here; this package imports none of them.
"""
