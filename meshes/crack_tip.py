"""Quadrilateral meshes of a single-edge-cracked strip, graded geometrically toward the crack tip.

The strip is ``width`` W wide (x in [0, W]) with an edge crack of length ``a`` along y = 0 from
x = 0 to the tip at x = a. The half model (``full=False``) is y in [0, H], H = ``half_height``:
the crack face is its free edge y = 0, x < a, the ligament (x >= a on y = 0) its symmetry line.
The full model (``full=True``) is y in [-H, H]; the nodes of the crack faces are *split* (one
node above and one below at each x < a, same coordinates, different indices), the ligament's and
the tip's are shared: the mesh the column's partial crack will need.

Grading: the node columns cluster toward x = a from both sides and the node rows toward y = 0,
each interval ``growth`` times the one nearer the tip, the first ``tip_size``: the elements at the
tip are squares of side ``tip_size``. ``refine`` bisects every interval that many times (nested
meshes, the tip element halved each time) for a convergence study.

>>> m = edge_crack_mesh(1.0, 0.4, 1.5, tip_size=0.01, refine=0)
>>> bool(np.isclose(m.points[0, m.tip], 0.4)), m.points[1, m.tip].item()
(True, 0.0)
>>> bool(np.all(m.points[0, m.crack_upper] < 0.4)), m.crack_lower is None
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError, require_positive, require_range


@dataclass
class CrackTipMesh:
    """Nodes (2, n), counter-clockwise quadrilaterals (4, n_cells) and the node sets of the
    edge-cracked strip. ``crack_upper`` / ``crack_lower``: the crack-face nodes sorted by their
    distance behind the tip, nearest first (``crack_lower`` is None for the half model);
    ``ligament``: the nodes on y = 0 with x >= a (tip included); ``top`` / ``bottom``: the loaded
    edges y = H and y = -H (``bottom`` None for the half model)."""

    points: np.ndarray = field(repr=False)
    cells: np.ndarray = field(repr=False)
    width: float
    crack_length: float
    half_height: float
    tip: int
    crack_upper: np.ndarray = field(repr=False)
    crack_lower: np.ndarray | None = field(repr=False)
    ligament: np.ndarray = field(repr=False)
    top: np.ndarray = field(repr=False)
    bottom: np.ndarray | None = field(repr=False)

    @property
    def tip_element_size(self) -> float:
        """The shortest element edge (the tip elements' side), m."""
        p = self.points[:, self.cells]
        return float(np.linalg.norm(p - np.roll(p, -1, axis=1), axis=0).min())

    def to_skfem(self):
        from skfem import MeshQuad

        return MeshQuad(np.ascontiguousarray(self.points), np.ascontiguousarray(self.cells))


def geometric_intervals(length: float, first: float, growth: float) -> np.ndarray:
    """Node offsets 0 = s_0 < ... < s_n = ``length``: intervals first, first q, first q^2, ...,
    n the fewest that reach ``length`` with q = ``growth``, then q <= ``growth`` solved so that
    they end on ``length`` exactly (the first interval stays ``first``; uniform intervals where
    n of them would overshoot).

    >>> geometric_intervals(1.0, 0.25, 1.0).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    n, reach, step = 1, first, first
    while reach < length * (1.0 - 1e-12):
        step *= growth
        reach += step
        n += 1
    if n * first >= length * (1.0 - 1e-12):
        return np.linspace(0.0, length, n + 1)
    lo, hi = 1.0, growth  # sum first q^k, k < n, rises with q: bisect it onto length
    for _ in range(200):
        q = 0.5 * (lo + hi)
        if first * np.sum(q ** np.arange(n)) < length:
            lo = q
        else:
            hi = q
    s = np.concatenate([[0.0], np.cumsum(first * q ** np.arange(n))])
    s[-1] = length
    return s


def _bisect(coords: np.ndarray, times: int) -> np.ndarray:
    for _ in range(times):
        mid = 0.5 * (coords[:-1] + coords[1:])
        coords = np.sort(np.concatenate([coords, mid]))
    return coords


def edge_crack_mesh(
    width: float,
    crack_length: float,
    half_height: float,
    *,
    tip_size: float | None = None,
    growth: float = 1.25,
    refine: int = 0,
    full: bool = False,
) -> CrackTipMesh:
    """The edge-cracked strip's mesh (module docstring). ``tip_size`` defaults to a / 50."""
    require_positive("strip width W (m)", width)
    require_range("crack length a / W", crack_length / width, 0.0, 1.0, range_text="(0, 1)")
    require_positive("strip half-height H (m)", half_height)
    a = crack_length
    h0 = a / 50.0 if tip_size is None else require_positive("tip element size (m)", tip_size)
    if h0 >= min(a, width - a, half_height):
        raise InputError(
            f"tip element size = {h0:g} m is not allowed: it must be smaller than the crack "
            f"length, the ligament and the half-height ({min(a, width - a, half_height):g} m)"
        )
    require_range("mesh growth ratio", growth, 1.0, 2.0, closed_low=True, closed_high=True)
    if not (isinstance(refine, int) and 0 <= refine <= 6):
        raise InputError(f"mesh refine = {refine!r} is not allowed: an integer in 0..6")

    x = np.concatenate(
        [
            a - geometric_intervals(a, h0, growth)[::-1],
            a + geometric_intervals(width - a, h0, growth)[1:],
        ]
    )
    y = geometric_intervals(half_height, h0, growth)
    x, y = _bisect(x, refine), _bisect(y, refine)
    x[0], x[-1] = 0.0, width  # exact edges
    nx, ny = x.size, y.size
    X, Y = np.meshgrid(x, y, indexing="xy")  # (ny, nx), row j is y[j]
    idx = np.arange(nx * ny).reshape(ny, nx)
    points = np.vstack([X.ravel(), Y.ravel()])
    cells = np.vstack(
        [idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()]
    )
    i_tip = int(np.argmin(np.abs(x - a)))
    x[i_tip] = points[0, idx[0, i_tip]] = a
    behind = idx[0, :i_tip][::-1]  # crack face, nearest the tip first
    ligament = idx[0, i_tip:]
    top = idx[-1, :]
    if not full:
        return CrackTipMesh(
            points,
            cells,
            width,
            a,
            half_height,
            int(idx[0, i_tip]),
            behind,
            None,
            ligament,
            top,
            None,
        )

    # mirror the rows y > 0 to y < 0; row 0 of the mirror is the lower crack face (new nodes
    # for x < a) and the ligament (the same nodes as above)
    n = points.shape[1]
    lower = np.empty((ny, nx), dtype=np.int64)
    lower[1:, :] = n + np.arange((ny - 1) * nx).reshape(ny - 1, nx)
    n_lower_rows = (ny - 1) * nx
    lower[0, i_tip:] = idx[0, i_tip:]
    lower[0, :i_tip] = n + n_lower_rows + np.arange(i_tip)
    mirror = np.vstack([X[1:].ravel(), -Y[1:].ravel()])
    face = np.vstack([x[:i_tip], np.zeros(i_tip)])
    points = np.hstack([points, mirror, face])
    # counter-clockwise below the crack plane: the mirror reverses orientation, so walk it back
    cells_low = np.vstack(
        [
            lower[1:, :-1].ravel(),
            lower[1:, 1:].ravel(),
            lower[:-1, 1:].ravel(),
            lower[:-1, :-1].ravel(),
        ]
    )
    cells = np.hstack([cells, cells_low])
    return CrackTipMesh(
        points,
        cells,
        width,
        a,
        half_height,
        int(idx[0, i_tip]),
        behind,
        lower[0, :i_tip][::-1].copy(),
        ligament,
        top,
        lower[-1, :].copy(),
    )


def tip_element_count(mesh: CrackTipMesh) -> int:
    """Elements with a corner at the tip (2 in the half model, 4 in the full one)."""
    return int(np.count_nonzero(np.any(mesh.cells == mesh.tip, axis=0)))


__all__ = ["CrackTipMesh", "edge_crack_mesh", "geometric_intervals", "tip_element_count"]
