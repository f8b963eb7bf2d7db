"""Transfer of a displacement and velocity state from one mesh of the column to another.

Each body's fields are interpolated with the bilinear shape functions of the source mesh at
the reference positions of the target mesh's nodes of the same body (scikit-fem's
``Basis.probes``), body by body so that the two faces of the crack, which share coordinates,
stay apart. Bilinear interpolation reproduces any field linear in x and y exactly: rigid
translations, small rotations and uniform strains pass unchanged, so a column moving almost
rigidly (rocking between impacts) is handed over with only the source mesh's discretisation
of its elastic strains.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from skfem import Basis, ElementQuad1, MeshQuad

from ..core.errors import InputError
from ..meshes.column import ColumnMesh


def interpolation_matrices(source: ColumnMesh, target: ColumnMesh) -> list:
    """Per body b: (target node indices, sparse P, source node indices) with
    field_target[targets] = P @ field_source[sources] for a nodal scalar field."""
    if source.n_bodies != target.n_bodies:
        raise InputError(
            f"transfer: the source mesh has {source.n_bodies} bodies and the "
            f"target {target.n_bodies}"
        )
    for name in ("width", "height"):
        a, b = getattr(source, name), getattr(target, name)
        if abs(a - b) > 1e-9 * max(a, b):
            raise InputError(f"transfer: the meshes differ in {name} ({a:g} m, {b:g} m)")
    out = []
    for body in range(source.n_bodies):
        cells = source.cells[:, source.cell_body == body]
        used = np.unique(cells)
        local = np.full(source.n_nodes, -1)
        local[used] = np.arange(used.size)
        mesh = MeshQuad(
            np.ascontiguousarray(source.points[:, used]), np.ascontiguousarray(local[cells])
        )
        basis = Basis(mesh, ElementQuad1())
        targets = target.body_nodes(body)
        # keep the probes strictly inside the body's bounding box (round-off on the faces)
        lo, hi = mesh.p.min(axis=1, keepdims=True), mesh.p.max(axis=1, keepdims=True)
        span = hi - lo
        points = np.clip(target.points[:, targets], lo + 1e-12 * span, hi - 1e-12 * span)
        out.append((targets, basis.probes(points), used))
    return out


def transfer_state(
    source: ColumnMesh, target: ColumnMesh, displacement: np.ndarray, velocity: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Positions x and velocities v (flat, 2 per node) of the ``target`` mesh's nodes from the
    nodal ``displacement`` and ``velocity`` (n_nodes, 2) of the ``source`` mesh."""
    u = np.asarray(displacement, dtype=float).reshape(-1, 2)
    vel = np.asarray(velocity, dtype=float).reshape(-1, 2)
    if u.shape[0] != source.n_nodes or vel.shape[0] != source.n_nodes:
        raise InputError(
            f"transfer: displacement and velocity need {source.n_nodes} rows (one per source node)"
        )
    u_t = np.zeros((target.n_nodes, 2))
    v_t = np.zeros((target.n_nodes, 2))
    for targets, P, sources in interpolation_matrices(source, target):
        u_t[targets] = P @ u[sources]
        v_t[targets] = P @ vel[sources]
    return (target.points.T + u_t).ravel(), v_t.ravel()


def _traction_transfer(coords_s, force_s, coords_t, tributary_s, tributary_t):
    """Nodal forces on a line turned into tractions (N/m) by the source tributary lengths,
    interpolated linearly to the target nodes and turned back into forces."""
    return np.interp(coords_t, coords_s, force_s / tributary_s) * tributary_t


def transfer_contact(source, target, state: dict) -> dict:
    """The contact state of the ``source`` model (a ``contact_frames`` entry: tangential forces
    base_ft, crack_ft and filtered normal forces base_fc, crack_fc, N per node) carried to the
    ``target`` model (both :class:`colonna.fem.model.Model`) as tractions along the base of
    each body and along each crack pass's face, so that a restart keeps the friction that was
    holding the column (reset to zero, a sticking crack slips for a moment), and the bed's
    plastic indentation (m) where it has one, interpolated as a depth."""
    from .model import _tributary

    body_s = source.mesh.node_body[source.base_nodes]
    body_t = target.mesh.node_body[target.base_nodes]
    xs, xt = source.mesh.points[0, source.base_nodes], target.mesh.points[0, target.base_nodes]
    out: dict[str, Any] = {}
    for key in ("base_ft", "base_fc"):
        force = np.asarray(state[key], dtype=float)
        carried = np.zeros(target.base_nodes.size)
        for body in range(target.mesh.n_bodies):
            s, t = body_s == body, body_t == body
            carried[t] = _traction_transfer(
                xs[s], force[s], xt[t], source.base_tributary[s], target.base_tributary[t]
            )
        out[key] = carried
    for key in ("crack_ft", "crack_fc"):
        out[key] = []
        for pass_s, pass_t, force in zip(source.crack_passes, target.crack_passes, state[key]):
            ys = source.mesh.points[1, pass_s[0]]
            yt = target.mesh.points[1, pass_t[0]]
            out[key].append(
                _traction_transfer(
                    ys, np.asarray(force, dtype=float), yt, _tributary(ys), _tributary(yt)
                )
            )
    if state.get("base_indentation") is not None:  # the bed's indentation (m): a depth
        depth = np.asarray(state["base_indentation"], dtype=float)
        carried = np.zeros(target.base_nodes.size)
        for body in range(target.mesh.n_bodies):
            s, t = body_s == body, body_t == body
            carried[t] = np.interp(xt[t], xs[s], depth[s])
        out["base_indentation"] = carried
    if "collar_state" in state:  # the same collars on both meshes
        out["collar_state"] = np.array(state["collar_state"], dtype=float)
    if state.get("cohesive_damage") is not None and target.cohesive is not None:
        out["cohesive_damage"] = transfer_damage(source, target, state["cohesive_damage"])
    return out


def transfer_damage(source, target, damage) -> np.ndarray:
    """A partial crack's pair damage (fem.partial_crack) carried from the ``source`` model's
    mid-plane pairs to the ``target``'s by height: a target pair takes the damage of the
    source pair at its height, and one between two source pairs the smaller of theirs (a pair
    is broken only between broken ones: the crack grows no further than it had)."""
    ys, yt = source.cohesive.heights, target.cohesive.heights
    damage = np.asarray(damage, dtype=float)
    above = np.clip(np.searchsorted(ys, yt - 1e-12 * target.mesh.height), 0, ys.size - 1)
    below = np.clip(above - 1, 0, ys.size - 1)
    at = np.abs(ys[above] - yt) <= 1e-9 * target.mesh.height
    return np.where(at, damage[above], np.minimum(damage[above], damage[below]))
