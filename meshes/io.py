"""Mesh and field I/O through meshio: VTU and XDMF out (ParaView), gmsh ``.msh`` in."""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path

import meshio
import numpy as np

from ..core.errors import InputError
from .column import ColumnMesh, from_arrays


def to_meshio(
    mesh: ColumnMesh, point_data: dict | None = None, cell_data: dict | None = None
) -> meshio.Mesh:
    """meshio mesh with 3D points (z = 0), the body id as cell data, and any fields given
    (point arrays of shape (n_nodes,) or (n_nodes, k), cell arrays of shape (n_cells, ...))."""
    points = np.vstack((mesh.points, np.zeros(mesh.n_nodes))).T
    cdata = {"body": [mesh.cell_body.astype(np.int32)]}
    for name, values in (cell_data or {}).items():
        cdata[name] = [np.asarray(values)]
    pdata = {}
    for name, values in (point_data or {}).items():
        values = np.asarray(values)
        if values.ndim == 2 and values.shape[1] == 2:  # vectors: pad to 3D for ParaView
            values = np.hstack((values, np.zeros((values.shape[0], 1))))
        pdata[name] = values
    return meshio.Mesh(
        points, [("quad", mesh.cells.T.astype(np.int64))], point_data=pdata, cell_data=cdata
    )


def write(
    path, mesh: ColumnMesh, point_data: dict | None = None, cell_data: dict | None = None
) -> None:
    """Write a mesh and fields; the format follows the extension (.vtu, .xdmf, .msh, ...)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part" + path.suffix)
    kwargs = {"binary": True, "compression": "zlib"} if path.suffix == ".vtu" else {}
    meshio.write(tmp, to_meshio(mesh, point_data, cell_data), **kwargs)
    os.replace(tmp, path)


def read(path) -> ColumnMesh:
    """Read a quadrilateral column mesh (gmsh .msh 2.2/4.x, VTU, ...) and classify it."""
    path = Path(path)
    try:
        with contextlib.redirect_stderr(io.StringIO()):  # meshio prints before it exits
            m = meshio.read(path)
    except (OSError, meshio.ReadError) as exc:
        raise InputError(f"mesh file {path} cannot be read: {exc}") from None
    except SystemExit:  # meshio exits instead of raising when no reader fits the file
        raise InputError(
            f"mesh file {path} cannot be read: not a mesh meshio knows "
            "(gmsh .msh 2.2/4.x, VTU, ...)"
        ) from None
    except (ValueError, KeyError, IndexError, UnicodeDecodeError) as exc:
        raise InputError(f"mesh file {path} cannot be read: malformed ({exc})") from None
    quads = [block.data for block in m.cells if block.type == "quad"]
    if not quads:
        raise InputError(f"mesh file {path} has no quadrilateral cells")
    cells = np.vstack(quads).T
    used = np.unique(cells)
    remap = -np.ones(m.points.shape[0], dtype=np.int64)
    remap[used] = np.arange(used.size)
    return from_arrays(m.points[used, :2].T, remap[cells])


def write_time_series(path, mesh: ColumnMesh, times, point_fields) -> None:
    """XDMF time series. ``point_fields`` is a callable k -> dict of point arrays for output k.

    Data are stored inline (XML), so no HDF5 library is needed; meshio's writer still runs from
    the target folder, since with HDF5 it would drop its .h5 file in the working directory."""
    path = Path(path).resolve()
    path.parent.mkdir(parents=True, exist_ok=True)
    here = Path.cwd()
    m = to_meshio(mesh)
    try:
        os.chdir(path.parent)
        with meshio.xdmf.TimeSeriesWriter(path.name, data_format="XML") as writer:
            writer.write_points_cells(m.points, m.cells)
            for k, t in enumerate(times):
                fields = {}
                for name, values in point_fields(k).items():
                    values = np.asarray(values)
                    if values.ndim == 2 and values.shape[1] == 2:
                        values = np.hstack((values, np.zeros((values.shape[0], 1))))
                    fields[name] = values
                writer.write_data(float(t), point_data=fields)
    finally:
        os.chdir(here)
