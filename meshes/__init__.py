"""colonna.meshes: quadrilateral meshes of the solid or cracked column (the crack faces keep
distinct nodes), and mesh I/O through meshio (:mod:`colonna.meshes.io`)."""

from .column import ColumnMesh, column_mesh, from_arrays

__all__ = ["ColumnMesh", "column_mesh", "from_arrays"]
