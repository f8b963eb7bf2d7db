"""pyvista renders of a FEM run: the deformed halves coloured by the minimum principal stress at
key instants, and an animated GIF of the rocking (frames assembled with Pillow).

The camera looks at the xy plane in parallel projection, fitted to the column and the ground
line, and each image is then trimmed to what is drawn (a few pixels of margin kept)."""

from __future__ import annotations

import contextlib
import json
import os
import sys
from pathlib import Path

import numpy as np

MAGNIFY = 1.0  # rocking displacements are large already: drawn true to scale
WINDOW = (360, 640)  # render window, px (width, height): a column is tall
MARGIN = 8  # px of background kept around what is drawn
BACKGROUND = (255, 255, 255)
# what the renders' colour is: the stone's minimum principal stress per element (not the toe
# stress of the answers, which is the base contact pressure averaged over the toe window)
BAR_TITLE = "min principal stress sigma_3 (MPa)"


@contextlib.contextmanager
def _no_display_fallback_warning():
    """Without an X display (Linux, DISPLAY unset) VTK tries X first, warns "bad X server
    connection" and falls back to EGL or OSMesa. Only that warning is silenced, while the
    window is made: VTK errors still print, and a failed render still raises."""
    if not sys.platform.startswith("linux") or os.environ.get("DISPLAY"):
        yield
        return
    from vtkmodules.vtkCommonCore import vtkLogger

    before = vtkLogger.GetCurrentVerbosityCutoff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    try:
        yield
    finally:
        vtkLogger.SetStderrVerbosity(before)


def _plotter():
    import pyvista as pv

    pv.OFF_SCREEN = True
    with _no_display_fallback_warning():
        p = pv.Plotter(off_screen=True, window_size=WINDOW)
    p.background_color = BACKGROUND
    return p


def _fit(p, bounds, bottom: float = 0.0, top: float = 0.0, pad: float = 0.04) -> None:
    """Parallel camera on the xy plane with the box bounds = (x0, x1, y0, y1) (m) filling the
    window between the fractions ``bottom`` and ``1 - top`` of its height (the rest is left for
    a colour bar or a label)."""
    x0, x1, y0, y1 = bounds
    width, height = WINDOW
    free = 1.0 - bottom - top
    half = (1.0 + pad) * max((y1 - y0) / (2.0 * free), (x1 - x0) * height / (2.0 * width))
    cx = 0.5 * (x0 + x1)
    cy = 0.5 * (y0 + y1) - (bottom + 0.5 * free - 0.5) * 2.0 * half
    cam = p.camera
    cam.parallel_projection = True
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 10.0 * half)
    cam.up = (0.0, 1.0, 0.0)
    cam.parallel_scale = half  # half the visible height (m)
    p.renderer.ResetCameraClippingRange()


def _drawn_box(img: np.ndarray) -> tuple[int, int, int, int]:
    """(row0, row1, col0, col1) of the pixels that are not background, with MARGIN around."""
    drawn = np.any(np.abs(img[..., :3].astype(int) - BACKGROUND) > 6, axis=2)
    rows, cols = np.nonzero(drawn.any(axis=1))[0], np.nonzero(drawn.any(axis=0))[0]
    if rows.size == 0:
        return 0, img.shape[0], 0, img.shape[1]
    return (
        max(rows[0] - MARGIN, 0),
        min(rows[-1] + 1 + MARGIN, img.shape[0]),
        max(cols[0] - MARGIN, 0),
        min(cols[-1] + 1 + MARGIN, img.shape[1]),
    )


def _ground(x0: float, x1: float, reach: float):
    """The ground line under the column, ``reach`` (m) beyond its footprint on each side."""
    import pyvista as pv

    return pv.Line((x0 - reach, 0.0, 0.0), (x1 + reach, 0.0, 0.0))


def render_snapshots(out: Path, n_frames: int = 24) -> list[tuple[str, str]]:
    """Render the FEM snapshots of ``out/cases/fem`` into ``out/figures``: (file, caption) of
    each image. When the run ended at its peak rotation (it stopped as the column overturned)
    the peak and the end are one frame, drawn once."""
    import meshio

    out = Path(out)
    fem = out / "cases" / "fem"
    meshes = {
        name: meshio.read(fem / f"fields_{name}.vtu")
        for name in ("initial", "peak_rotation", "final")
    }
    same_end = np.array_equal(
        meshes["peak_rotation"].point_data["displacement"],
        meshes["final"].point_data["displacement"],
    )
    snaps = [("initial", "at rest under gravity")]
    if same_end and _overturned(fem):
        snaps.append(
            (
                "peak_rotation",
                "at the overturning stop, the end of the run: its largest rotation is where "
                "the overturning rule stopped it (a stopping convention, not a peak; the "
                "deformed-column figure shows the largest rotation before overturning)",
            )
        )
    elif same_end:
        snaps.append(("peak_rotation", "at peak rotation, which is also the end of the run"))
    else:
        snaps += [("peak_rotation", "at peak rotation"), ("final", "at the end of the run")]
    images = []
    for name, caption in snaps:
        png = f"render_{name}.png"
        _snapshot(meshes[name], out / "figures" / png)
        images.append(
            (
                png,
                f"Deformed halves {caption}, drawn true to scale (displacements not "
                "magnified), coloured by the stone's minimum principal "
                "stress sigma_3 per element (MPa, compression negative): a stress in the "
                "stone, not the toe stress of the answers (the base contact pressure "
                "averaged over the toe window)",
            )
        )
    images.append(_gif(out, fem, n_frames))
    return images


def _overturned(fem: Path) -> bool:
    """Whether the FEM run of ``fem`` (its summary.json) stopped as the column overturned."""
    try:
        return bool(json.loads((fem / "summary.json").read_text()).get("overturned"))
    except (OSError, ValueError, AttributeError):
        return False


def _snapshot(m, path: Path) -> None:
    import pyvista as pv
    from PIL import Image

    grid = pv.from_meshio(m)
    grid.points = grid.points + MAGNIFY * grid.point_data["displacement"]
    grid.cell_data["stress_MPa"] = grid.cell_data["sigma_min_principal"] / 1e6
    x0, x1, y0, y1 = grid.bounds[:4]
    reach = 0.1 * (y1 - y0)
    p = _plotter()
    p.add_mesh(
        grid,
        scalars="stress_MPa",
        cmap="viridis",
        show_edges=False,
        scalar_bar_args={
            "title": "",  # drawn below the bar (BAR_TITLE): VTK puts it over its tick labels
            "fmt": "%.2f",
            "n_labels": 3,
            "position_x": 0.2,
            "position_y": 0.045,
            "width": 0.6,
            "height": 0.05,
            "label_font_size": 14,
        },
    )
    # the bar's tick labels above it, its title below it: apart whatever the numbers' widths
    p.add_text(BAR_TITLE, position=(0.2 * WINDOW[0], 4), font_size=8, color="k", name="bar_title")
    p.add_mesh(_ground(x0, x1, reach), color="k", line_width=2)
    _fit(p, (x0 - reach, x1 + reach, min(y0, 0.0), y1), bottom=0.16)
    img = p.screenshot(return_img=True)
    p.close()
    r0, r1, c0, c1 = _drawn_box(img)
    Image.fromarray(img[r0:r1, c0:c1]).save(path)


def _gif(out: Path, fem: Path, n_frames: int) -> tuple[str, str]:
    import meshio
    import pyvista as pv
    from PIL import Image

    with meshio.xdmf.TimeSeriesReader(fem / "fields.xdmf") as reader:
        points, cells = reader.read_points_cells()
        n = reader.num_steps
        steps = []
        for k in np.unique(np.linspace(0, n - 1, n_frames).astype(int)):
            t, point_data, _ = reader.read_data(int(k))
            steps.append((t, points + point_data["displacement"]))
    # one camera for every frame: the box around the column in all of them
    lo = np.min([x.min(axis=0) for _, x in steps], axis=0)
    hi = np.max([x.max(axis=0) for _, x in steps], axis=0)
    reach = 0.1 * (hi[1] - lo[1])
    ground = _ground(lo[0], hi[0], reach)
    # one window for every frame: the mesh's points and the time label change, the rest stays
    # (a window per frame cost two thirds of the time in making windows and first renders)
    grid = pv.from_meshio(meshio.Mesh(steps[0][1], cells))
    p = _plotter()
    p.add_mesh(grid, color="#c9b79c", show_edges=True, edge_color="#777777")
    p.add_mesh(ground, color="k", line_width=2)
    _fit(p, (lo[0] - reach, hi[0] + reach, min(lo[1], 0.0), hi[1]), top=0.06)
    shots = []
    for t, x in steps:
        grid.points = x
        p.add_text(f"t = {t:.2f} s", position="upper_edge", font_size=10, name="time")
        shots.append(p.screenshot(return_img=True))
    p.close()
    boxes = np.array([_drawn_box(img) for img in shots])
    r0, c0 = boxes[:, [0, 2]].min(axis=0)
    r1, c1 = boxes[:, [1, 3]].max(axis=0)
    frames = [Image.fromarray(img[r0:r1, c0:c1]) for img in shots]
    name = "rocking.gif"
    frames[0].save(
        out / "figures" / name, save_all=True, append_images=frames[1:], duration=120, loop=0
    )
    return name, "The rocking, frame by frame (true scale)"
