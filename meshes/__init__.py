"""colonna.meshes: quadrilateral meshes of the solid or cracked column (the crack faces keep
distinct nodes), and mesh I/O through meshio (:mod:`colonna.meshes.io`)."""

from typing import TYPE_CHECKING

from ..core import lazy_exports

# name -> the module that defines it, imported on first use (:func:`colonna.core.lazy_exports`)
_PUBLIC = {
    "ColumnMesh": ".column",
    "ToeGrading": ".column",
    "column_mesh": ".column",
    "from_arrays": ".column",
}

if TYPE_CHECKING:  # what the names are, for type checkers (nothing is imported at run time)
    from .column import ColumnMesh, ToeGrading, column_mesh, from_arrays

__getattr__, __dir__ = lazy_exports(globals(), _PUBLIC)

__all__ = ["ColumnMesh", "ToeGrading", "column_mesh", "from_arrays"]
