"""Quadrilateral meshes of a solid or cracked column.

The column is ``width`` (= 4b) wide and ``height`` (= 2h) tall, standing on y = 0 with its axis at
x = 0. A cracked column is two bodies, x in [-width/2, 0] and [0, width/2], whose crack-face nodes
are *distinct* (same coordinates, different indices): scikit-fem's ``Mesh.__add__`` would merge them
and weld the crack shut, so the arrays are stacked by hand.

Grading: each body's columns of nodes cluster toward its two vertical edges (the rocking toes are
the base corners), its rows toward the base; ``grading`` in [0, 1) sets how strongly (0: uniform).
Rows can be pinned at given heights (the collars) so that attachment points are nodes.

Toe refinement: the element columns within ``toe_zone`` of a body's vertical edges and the rows
within ``toe_zone`` of the base are each split into ``toe_refinement`` equal parts, so that the
base corners (the rocking toes, outer and at the crack) are refined that many times in both
directions while the rest of the column keeps its size: a local h-refinement for the toe stress.

Toe grading: with ``toe_size`` the intervals within ``toe_zone`` of a base corner are first
replaced by equal ones of about ``toe_size``, then by a geometric progression growing by
``TOE_GROWTH`` per element until it meets the column's own size (in x toward both vertical
edges, in y from the base): the contact zone of a toe pivoting on its bed, a few millimetres
long, is then crossed by several elements (:func:`colonna.fem.bed.resolving_toe_size` gives
the size that resolves it).
``toe_refinement`` then splits the graded intervals as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError, require_positive, require_range


@dataclass
class ColumnMesh:
    """Nodes, quadrilaterals (counter-clockwise) and the node sets the model needs."""

    points: np.ndarray = field(repr=False)  # (2, n_nodes), m
    cells: np.ndarray = field(repr=False)  # (4, n_cells)
    cell_body: np.ndarray = field(repr=False)  # (n_cells,) 0: left (or solid), 1: right
    node_body: np.ndarray = field(repr=False)  # (n_nodes,)
    width: float
    height: float
    cracked: bool
    base_nodes: list = field(repr=False)  # per body, sorted by x
    outer_nodes: list = field(repr=False)  # per body: its outer face, sorted by y
    crack_nodes: list = field(repr=False)  # per body: its crack face, sorted by y ([] solid)

    @property
    def n_bodies(self) -> int:
        return 2 if self.cracked else 1

    @property
    def n_nodes(self) -> int:
        return self.points.shape[1]

    def body_nodes(self, body: int) -> np.ndarray:
        return np.nonzero(self.node_body == body)[0]

    def min_edge_length(self) -> float:
        p = self.points[:, self.cells]
        edges = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=0)
        return float(edges.min())

    def outer_node_at(self, body: int, y: float) -> int:
        """The outer-face node of ``body`` nearest to height y."""
        nodes = self.outer_nodes[body]
        return int(nodes[np.argmin(np.abs(self.points[1, nodes] - y))])

    def to_skfem(self):
        from skfem import MeshQuad

        # contiguous arrays: scikit-fem copies others and logs a warning for each large mesh
        return MeshQuad(np.ascontiguousarray(self.points), np.ascontiguousarray(self.cells))


def _graded(n: int, grading: float, both_ends: bool) -> np.ndarray:
    """n + 1 values in [0, 1], clustered toward 0 (and 1 if both_ends)."""
    s = np.linspace(0.0, 1.0, n + 1)
    clustered = 0.5 * (1.0 - np.cos(math.pi * s)) if both_ends else s**2
    return (1.0 - grading) * s + grading * clustered


def _split(coords: np.ndarray, near, parts: int) -> np.ndarray:
    """The node coordinates with every interval for which ``near(lo, hi)`` holds divided into
    ``parts`` equal intervals."""
    out = [coords[:1]]
    for lo, hi in zip(coords[:-1], coords[1:]):
        n = parts if near(lo, hi) else 1
        out.append(lo + (hi - lo) * np.arange(1, n + 1) / n)
    return np.concatenate(out)


TOE_GROWTH = 1.3  # largest ratio of neighbouring element sizes in a graded toe zone


def _grade_ends(coords: np.ndarray, zone: float, size: float, low: bool, high: bool):
    """``coords`` (sorted) with the intervals within ``zone`` of the low (and high) end replaced
    by intervals of about ``size``, then a geometric progression growing by ``TOE_GROWTH`` per
    interval, carried on until it meets an original interval within ``TOE_GROWTH`` of its last
    one; the progression is stretched evenly to end on that original node."""

    def graded(c: np.ndarray) -> np.ndarray:  # from the low end of c
        fine = c[0] + np.linspace(0.0, zone, max(1, math.ceil(zone / size - 1e-9)) + 1)
        steps: list[float] = []
        k = int(np.searchsorted(c, fine[-1], side="right"))  # first original node past it
        while k < c.size:
            step = (steps[-1] if steps else fine[-1] - fine[-2]) * TOE_GROWTH
            reach = fine[-1] + sum(steps)
            while k < c.size and c[k] <= reach + step:
                k += 1
            if k >= c.size or c[k] - c[k - 1] <= step * TOE_GROWTH:
                break
            steps.append(step)
        end = c[k - 1]
        if steps:
            grown = fine[-1] + np.cumsum(steps)
            grown = fine[-1] + (grown - fine[-1]) * (end - fine[-1]) / (grown[-1] - fine[-1])
            return np.concatenate((fine, grown[:-1], c[k - 1 :]))
        return np.concatenate((fine[:-1], c[k - 1 :])) if end > fine[-1] else fine

    if low:
        coords = graded(coords)
    if high:
        coords = -graded(-coords[::-1])[::-1]
    return coords


MAX_NODES = 200_000  # an explicit run on more would take days (the step shrinks with the size)


def _require_node_count(n_nodes: int, size: float, area: float) -> None:
    """An InputError where a mesh would have more than MAX_NODES nodes, before it is built."""
    if n_nodes > MAX_NODES:
        smallest = math.sqrt(area / MAX_NODES)
        raise InputError(
            f"mesh size = {size:g} m gives {n_nodes:,} nodes on this column: at most "
            f"{MAX_NODES:,} (a size of at least about {smallest:.2g} m here)"
        )


@dataclass(frozen=True)
class ToeGrading:
    """How the mesh is refined at the base corners: ``refinement``, how many times the
    elements within ``zone`` (m) of a base corner are split in x and in y (1: none); ``size``
    (m), the element size at the base corners, graded geometrically within ``zone`` (None: no
    toe grading; see the module)."""

    refinement: int = 1
    zone: float = 0.0
    size: float | None = None


NO_TOE_GRADING = ToeGrading()


def column_mesh(
    width: float,
    height: float,
    size: float,
    *,
    cracked: bool = True,
    grading: float = 0.5,
    pinned_heights=(),
    toe: ToeGrading = NO_TOE_GRADING,
) -> ColumnMesh:
    """Structured, graded quadrilateral mesh of the column.

    size: target element size (m), at most the width of one body; grading in [0, 1);
    pinned_heights: heights (m) at which a row of nodes is placed exactly (collar positions);
    toe: the refinement and grading at the base corners (:class:`ToeGrading`).
    """
    if not isinstance(toe, ToeGrading):
        raise InputError(f"toe = {toe!r} is not a colonna.meshes.ToeGrading")
    toe_refinement, toe_zone, toe_size = toe.refinement, toe.zone, toe.size
    require_positive("column width (m)", width)
    require_positive("column height (m)", height)
    body_width = 0.5 * width if cracked else width
    require_range(
        "mesh size (m)",
        size,
        0.0,
        body_width,
        closed_high=True,
        range_text=f"(0, {body_width:g}] (the width of one body)",
    )
    require_range("mesh grading", grading, 0.0, 1.0, closed_low=True)
    n_x = max(2, math.ceil(body_width / size))
    n_y = max(2, math.ceil(height / size))
    n_bodies = 2 if cracked else 1
    _require_node_count(n_bodies * (n_x + 1) * (n_y + 1), size, n_bodies * body_width * height)
    ys = height * _graded(n_y, grading, both_ends=False)
    for y_pin in pinned_heights:
        require_range("pinned height (m)", y_pin, 0.0, height, closed_high=True)
        k = int(np.argmin(np.abs(ys[1:] - y_pin))) + 1  # never move the base row
        ys[k] = y_pin
    if np.any(np.diff(ys) <= 0.0):
        raise InputError(
            "mesh size is too coarse for the pinned (collar) heights: two collars "
            "fall on the same row of nodes; use a smaller [mesh] size"
        )
    xs = body_width * _graded(n_x, grading, both_ends=True)
    if (
        isinstance(toe_refinement, bool)
        or not isinstance(toe_refinement, (int, np.integer))
        or not 1 <= toe_refinement <= 64
    ):
        raise InputError(f"mesh toe_refinement = {toe_refinement!r} must be an integer in [1, 64]")
    if toe_size is not None:
        require_positive("mesh toe_zone (m)", toe_zone)
        require_range("mesh toe_size (m)", toe_size, 0.0, toe_zone, closed_high=True)
        zone = max(toe_zone, toe_size)
        ys = _grade_ends(ys, zone, toe_size, low=True, high=False)
        xs = _grade_ends(xs, zone, toe_size, low=True, high=True)
        for y_pin in pinned_heights:  # a collar's row must stay a row of nodes
            if not np.any(np.abs(ys - y_pin) <= 1e-12 * height):
                raise InputError(
                    f"mesh toe_size = {toe_size:g} m with toe_zone = {toe_zone:g} m grades the "
                    f"rows past the pinned (collar) height {y_pin:g} m: use a smaller toe_zone"
                )
        _require_node_count(n_bodies * xs.size * ys.size, size, n_bodies * body_width * height)
    if toe_refinement > 1:
        require_positive("mesh toe_zone (m)", toe_zone)
        ys = _split(ys, lambda lo, hi: lo < toe_zone, toe_refinement)
        xs = _split(xs, lambda lo, hi: lo < toe_zone or hi > body_width - toe_zone, toe_refinement)
    _require_node_count(n_bodies * xs.size * ys.size, size, n_bodies * body_width * height)
    offsets = [-0.5 * width, 0.0] if cracked else [-0.5 * width]

    points, cells, cell_body, node_body = [], [], [], []
    base_nodes: list = []
    outer_nodes: list = []
    crack_nodes: list = []
    start = 0
    for body, x0 in enumerate(offsets):
        X, Y = np.meshgrid(x0 + xs, ys)  # (n_y+1, n_x+1), row-major in y
        idx = start + np.arange(X.size).reshape(X.shape)
        points.append(np.vstack((X.ravel(), Y.ravel())))
        quads = np.vstack(
            (idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel())
        )
        cells.append(quads)
        cell_body.append(np.full(quads.shape[1], body))
        node_body.append(np.full(X.size, body))
        base_nodes.append(idx[0, :].copy())
        _sort_faces(body, cracked, idx[:, 0].copy(), idx[:, -1].copy(), outer_nodes, crack_nodes)
        start += X.size
    return ColumnMesh(
        np.hstack(points),
        np.hstack(cells),
        np.concatenate(cell_body),
        np.concatenate(node_body),
        float(width),
        float(height),
        bool(cracked),
        base_nodes,
        outer_nodes,
        crack_nodes,
    )


def _sort_faces(body, cracked, left_edge, right_edge, outer, crack) -> None:
    """Append a body's vertical edges to the outer-face and crack-face lists."""
    if not cracked:
        outer.extend([left_edge, right_edge])
    elif body == 0:
        outer.append(left_edge)
        crack.append(right_edge)
    else:
        outer.append(right_edge)
        crack.append(left_edge)


def from_arrays(points: np.ndarray, cells: np.ndarray, *, tol: float = 1e-9) -> ColumnMesh:
    """Classify an arbitrary quadrilateral mesh of the column (for example one read from gmsh).

    Bodies are the connected components of the cells (two for a cracked column, whose crack
    nodes are not shared); base, outer and crack faces are found from the bounding box.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    points = np.asarray(points, dtype=float)[:2]
    cells = np.asarray(cells, dtype=np.int64)
    if cells.shape[0] != 4:
        raise InputError("the mesh must be made of quadrilaterals (4 nodes per cell)")
    n = points.shape[1]
    i = np.repeat(cells, 4, axis=0).ravel()
    j = np.tile(cells, (4, 1)).ravel()
    n_comp, label = connected_components(
        coo_matrix((np.ones(i.size), (i, j)), shape=(n, n)), directed=False
    )
    used = np.unique(cells)
    comps = np.unique(label[used])
    if comps.size not in (1, 2):
        raise InputError(
            f"the mesh has {comps.size} separate bodies: a column has 1 (solid) or 2 (cracked)"
        )
    # order bodies left to right
    centres = [points[0, label == c].mean() for c in comps]
    order = comps[np.argsort(centres)]
    node_body = np.full(n, -1)
    for b, c in enumerate(order):
        node_body[label == c] = b
    x_min, x_max = points[0, used].min(), points[0, used].max()
    width, height = x_max - x_min, points[1, used].max()
    if abs(points[1, used].min()) > tol * max(1.0, height):
        raise InputError("the column base must lie on y = 0")
    scale = tol * max(width, height)
    base: list = []
    outer: list = []
    crack: list = []
    for b in range(comps.size):
        nodes = np.nonzero(node_body == b)[0]
        on_base = nodes[np.abs(points[1, nodes]) <= scale]
        base.append(on_base[np.argsort(points[0, on_base])])
        bx_min, bx_max = points[0, nodes].min(), points[0, nodes].max()
        left = nodes[np.abs(points[0, nodes] - bx_min) <= scale]
        right = nodes[np.abs(points[0, nodes] - bx_max) <= scale]
        left, right = left[np.argsort(points[1, left])], right[np.argsort(points[1, right])]
        _sort_faces(b, comps.size == 2, left, right, outer, crack)
    # counter-clockwise orientation
    p = points[:, cells]
    area2 = (p[0, 1] - p[0, 0]) * (p[1, 2] - p[1, 0]) - (p[0, 2] - p[0, 0]) * (p[1, 1] - p[1, 0])
    cells = np.where(area2 < 0.0, cells[::-1], cells)
    return ColumnMesh(
        points,
        cells,
        node_body[cells[0]],
        node_body,
        float(width),
        float(height),
        comps.size == 2,
        base,
        outer,
        crack,
    )
