"""colonna.meshes: quadrilateral meshes of the solid or cracked column, and mesh I/O via meshio.

Not implemented yet (issue 3).
"""
