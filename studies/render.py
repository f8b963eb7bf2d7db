"""pyvista renders of a FEM run: the deformed halves coloured by the minimum principal stress at
key instants, and an animated GIF of the rocking (frames assembled with Pillow)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

MAGNIFY = 1.0        # rocking displacements are large already: drawn true to scale


def _plotter():
    import pyvista as pv
    pv.OFF_SCREEN = True
    return pv.Plotter(off_screen=True, window_size=(360, 640))


def render_snapshots(out: Path, n_frames: int = 24) -> list[tuple[str, str]]:
    import meshio
    import pyvista as pv

    out = Path(out)
    fem = out / "cases" / "fem"
    images = []
    snaps = [("fields_initial.vtu", "at rest under gravity"),
             ("fields_peak_rotation.vtu", "at peak rotation"),
             ("fields_final.vtu", "at the end of the run")]
    for name, caption in snaps:
        m = meshio.read(fem / name)
        grid = pv.from_meshio(m)
        grid.points = grid.points + MAGNIFY * grid.point_data["displacement"]
        grid.cell_data["stress_MPa"] = grid.cell_data["sigma_min_principal"] / 1e6
        p = _plotter()
        p.add_mesh(grid, scalars="stress_MPa", cmap="viridis", show_edges=False,
                   scalar_bar_args={"title": "min principal stress (MPa)", "fmt": "%.2f",
                                    "n_labels": 3})
        p.add_mesh(pv.Line((-1.0, 0.0, 0.0), (1.0, 0.0, 0.0)), color="k", line_width=2)
        p.view_xy()
        png = f"render_{name.replace('fields_', '').replace('.vtu', '')}.png"
        p.screenshot(str(out / "figures" / png))
        p.close()
        images.append((png, f"Deformed halves {caption}, coloured by the minimum principal "
                            "stress (compression negative)"))
    images.append(_gif(out, fem, n_frames))
    return images


def _gif(out: Path, fem: Path, n_frames: int) -> tuple[str, str]:
    import meshio
    import pyvista as pv
    from PIL import Image

    with meshio.xdmf.TimeSeriesReader(fem / "fields.xdmf") as reader:
        points, cells = reader.read_points_cells()
        n = reader.num_steps
        frames = []
        bounds = None
        for k in np.unique(np.linspace(0, n - 1, n_frames).astype(int)):
            t, point_data, _ = reader.read_data(int(k))
            grid = pv.from_meshio(meshio.Mesh(points + point_data["displacement"], cells))
            p = _plotter()
            p.add_mesh(grid, color="#c9b79c", show_edges=True, edge_color="#777777")
            p.add_mesh(pv.Line((-1.5, 0.0, 0.0), (1.5, 0.0, 0.0)), color="k", line_width=2)
            p.add_text(f"t = {t:.2f} s", font_size=10)
            p.view_xy()
            if bounds is None:
                p.camera.zoom(0.8)
                bounds = p.camera.position, p.camera.focal_point, p.camera.up
            else:
                p.camera.position, p.camera.focal_point, p.camera.up = bounds
            frames.append(Image.fromarray(p.screenshot(return_img=True)))
            p.close()
    name = "rocking.gif"
    frames[0].save(out / "figures" / name, save_all=True, append_images=frames[1:],
                   duration=120, loop=0)
    return name, "The rocking, frame by frame (true scale)"
