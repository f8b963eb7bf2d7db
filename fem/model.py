"""The finite-element model of a (cracked) column: bodies, contact, collars, and its stable step.

The base is the column's bed (:mod:`colonna.fem.bed`): each base node's normal and tangential
spring is ``k_bed * t * l_trib`` (k_bed in N/m^3, thickness t, tributary length l_trib), a
physical stiffness held fixed when the mesh is refined (issue 38). What follows is the crack's.

Penalty stiffness (per contact node, N/m) is ``penalty_factor * E * t * l_trib / h``: the stiffness
of the adjacent element over the node's tributary length l_trib, h being that element's size normal
to the surface. With the default factor 1 the contact springs are as stiff as the stone next to
them, so they neither dominate the stable step nor let the faces sink visibly (penetration ~ strain
x h). The tangential penalty equals the normal one. Contact damping is a fraction ``damping`` of the
critical damping of each contact spring: at the base with its node's mass against the rigid ground,
2 zeta sqrt(k m); along the crack with the two faces' node masses in series, 2 zeta sqrt(k m1 m2 /
(m1 + m2)) (the pair's critical value, as LS-DYNA's contact damping). The crack may instead be
enforced exactly (``ContactSettings.enforcement = "lagrange"``: no penalty, damping nor filter).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import ArpackError, eigsh

from ..core.collar_law import LAW_SIZE, OUT_SIZE, state_size
from ..core.constants import STANDARD_GRAVITY
from ..core.errors import InputError, require_non_negative, require_positive, require_range
from ..meshes.column import ColumnMesh
from . import _kernels as K
from . import cohesive as cohesive_law
from .assembly import Stone, assemble
from .bed import DEFAULT as DEFAULT_BED
from .bed import Bed
from .partial_crack import (
    ALPHA,
    ETA,
    SOFTENING_FLOOR,
    CohesiveInterface,
    Crack,
    cracked_pairs,
    ligament_area,
    springs,
)

# how the crack's contact is enforced (ContactSettings.enforcement)
ENFORCEMENTS = ("penalty", "lagrange")


@dataclass(frozen=True)
class ContactSettings:
    """friction: Coulomb mu (base and crack); penalty_factor: scales the default penalty;
    penalty: a fixed penalty per unit contact area (N/m^3), overrides the factor;
    damping: fraction of critical damping of each contact spring;
    friction_filter: time constant (s) of the low-pass filter on the normal force that sets
    the friction cone (0: none). Without it, penalty contact with friction flutters near the
    slip limit (the contact's vibration modulates the cone); 1 ms is long against that
    vibration and short against the rocking; a closing contact starts at its full force;
    enforcement: the crack's contact, "lagrange" (the default: exact, forward-increment
    Lagrange multipliers with Coulomb friction, no penalty, damping nor filter;
    fem._kernels.crack_lagrange) or "penalty" (springs, the settings above). The base is
    penalty either way. The penalty along the crack does not converge within 3 % over its own
    settings on the uncollared column (docs/validation.md), the exact contact does, at the same
    cost per simulated second (docs/layout.md). With it, damping and friction_filter are the
    bed's only numerical settings: over damping 1-10 % and a filter of 0-2 ms the uncollared
    column's first swing moves by at most 1.6 % (replica medians, three meshes); an undamped
    bed (0) took another branch on one mesh (-4.2 %), so 0 is for energy-balance checks."""

    friction: float = 0.7
    penalty_factor: float = 1.0
    penalty: float | None = None
    damping: float = 0.05
    friction_filter: float = 1e-3
    enforcement: str = "lagrange"

    def __post_init__(self):
        # hard limits as in the study file's schema (studies.schema.Contact says why)
        require_non_negative("contact friction", self.friction)
        require_range(
            "contact friction_filter (s)",
            self.friction_filter,
            0.0,
            1.0,
            closed_low=True,
            closed_high=True,
        )
        require_range(
            "contact penalty_factor",
            self.penalty_factor,
            1e-3,
            1e3,
            closed_low=True,
            closed_high=True,
        )
        if self.penalty is not None:
            require_range(
                "contact penalty (N/m^3)",
                self.penalty,
                1e6,
                1e18,
                closed_low=True,
                closed_high=True,
            )
        require_range("contact damping", self.damping, 0.0, 1.0, closed_low=True)
        if self.enforcement not in ENFORCEMENTS:
            raise InputError(
                f"contact enforcement = {self.enforcement!r} must be one of "
                + ", ".join(repr(e) for e in ENFORCEMENTS)
            )


@dataclass
class Model:
    mesh: ColumnMesh
    stone: Stone
    thickness: float
    collars: tuple
    contact: ContactSettings
    g: float
    stiffness: sparse.csr_matrix = field(repr=False)
    mass: np.ndarray = field(repr=False)  # per dof
    gravity: np.ndarray = field(repr=False)
    X: np.ndarray = field(repr=False)  # reference positions, interleaved
    centroid_ref: np.ndarray = field(repr=False)  # (n_bodies, 2)
    base_nodes: np.ndarray = field(repr=False)
    base_kn: np.ndarray = field(repr=False)
    base_kt: np.ndarray = field(repr=False)
    base_cn: np.ndarray = field(repr=False)
    base_tributary: np.ndarray = field(repr=False)
    crack_passes: list = field(repr=False)  # [(slaves, masters, sign, kn, kt, cn)]
    collar_nodes: np.ndarray = field(repr=False)  # (n_collars, 6) int
    collar_props: np.ndarray = field(repr=False)  # (n_collars, 7 + LAW_SIZE), see _kernels
    top_load: float = 0.0  # N, on the capital (see build_model)
    bed: Bed = DEFAULT_BED  # the base's stiffness per unit area (see build_model)
    # a partial crack's intact mid-plane (fem.partial_crack; None: the crack is full-height)
    cohesive: CohesiveInterface | None = None

    @property
    def n_dofs(self) -> int:
        return self.X.size

    @property
    def collar_state_size(self) -> int:
        """Numbers per collar in the collars' plastic state (a row as long as the largest
        their laws need: colonna.core.collar_law)."""
        return state_size(self.collar_props[:, 7:])

    def collar_rest_state(self) -> np.ndarray:
        """The collars' plastic state at rest, (n_collars, collar_state_size), zeros."""
        return np.zeros((self.collar_nodes.shape[0], self.collar_state_size))

    @property
    def base_yield_force(self) -> np.ndarray:
        """Each base node's yield force (N): the bed's yield pressure x thickness x tributary
        length; inf on an elastic bed (fem.bed.Bed.yield_pressure None)."""
        pressure = self.bed.yield_pressure
        if pressure is None:
            return np.full(self.base_nodes.size, np.inf)
        return pressure * self.thickness * self.base_tributary

    @property
    def node_mass(self) -> np.ndarray:
        return self.mass[0::2]


def _tributary(coords: np.ndarray) -> np.ndarray:
    """Tributary lengths of sorted points on a line."""
    mid = 0.5 * (coords[1:] + coords[:-1])
    return np.diff(np.concatenate(([coords[0]], mid, [coords[-1]])))


def pair_damping(k, m1, m2, zeta):
    """Contact damping (N s/m): the fraction zeta of the critical damping of a spring k between
    two masses in series, c = 2 zeta sqrt(k m1 m2 / (m1 + m2)) (m2 = inf, a rigid ground: 2
    zeta sqrt(k m1))."""
    m1 = np.asarray(m1, dtype=float)
    m2 = np.asarray(m2, dtype=float)
    reduced = np.where(np.isinf(m2), m1, m1 * m2 / (m1 + np.where(np.isinf(m2), 0.0, m2)))
    return 2.0 * zeta * np.sqrt(k * reduced)


def _penalty(stone, thickness, contact, tributary, h):
    if contact.penalty is not None:
        return contact.penalty * thickness * tributary
    return contact.penalty_factor * stone.E * thickness * tributary / h


@dataclass(frozen=True)
class Loads:
    """The column's dead loads: ``g``, gravity (m/s^2), and ``top_load``, a vertical load on
    the capital (N, downward positive: the weight of what the column carries)."""

    g: float = STANDARD_GRAVITY
    top_load: float = 0.0


def build_model(
    mesh: ColumnMesh,
    stone: Stone,
    thickness: float,
    collars=(),
    contact: ContactSettings = ContactSettings(),
    loads: Loads = Loads(),
    bed: Bed = DEFAULT_BED,
    crack: tuple | Crack | None = None,
) -> Model:
    """Assemble bodies, contact pairs and collar elements.

    ``loads``: gravity and the dead load on the capital (:class:`Loads`).

    ``bed``: the base's stiffness per unit area (:class:`colonna.fem.bed.Bed`); each base
    node's spring is bed.stiffness x thickness x its tributary length, whatever the mesh
    (``contact``'s penalty settings are the crack's).

    ``loads.top_load`` (N): a vertical dead load on the capital, spread as a uniform pressure
    top_load / (width x thickness) over the top faces and lumped to the top nodes by their
    tributary lengths. It joins gravity in the constant load vector ``gravity``, so the
    energy balance counts its work as potential energy.

    ``crack`` (from, to) (m): the crack runs between these heights only, the rest of the
    mid-plane is intact stone (:mod:`colonna.fem.partial_crack`); None: the full height. A
    :class:`~colonna.fem.partial_crack.Crack` gives its extent and its depth, the fraction of
    the thickness it runs through, 0 < d <= 1: below 1 the crack's pairs keep a ligament
    (1 - d) of their area, and an extent of None runs the full height."""
    g, top_load = loads.g, loads.top_load
    require_positive("gravity g (m/s^2)", g)
    require_range(
        "column top_load (N)", top_load, 0.0, math.inf, closed_low=True, range_text="[0, inf)"
    )
    a = assemble(mesh, stone, thickness, g)
    if top_load > 0.0:
        p = mesh.points
        for body in range(mesh.n_bodies):
            nodes = mesh.body_nodes(body)
            top = nodes[np.abs(p[1, nodes] - mesh.height) <= 1e-9 * mesh.height]
            top = top[np.argsort(p[0, top])]
            a.gravity[2 * top + 1] -= top_load / mesh.width * _tributary(p[0, top])
    p = mesh.points
    X = p.T.ravel().copy()
    node_mass = a.lumped_mass[0::2]
    centroid_ref = np.zeros((mesh.n_bodies, 2))
    for b in range(mesh.n_bodies):
        on = mesh.node_body == b
        centroid_ref[b] = (p[:, on] * node_mass[on]).sum(axis=1) / node_mass[on].sum()

    # base: every body's base against the ground
    base_lists, kn, trib_all = [], [], []
    for nodes in mesh.base_nodes:
        trib = _tributary(p[0, nodes])
        base_lists.append(nodes)
        kn.append(bed.stiffness * thickness * trib)
        trib_all.append(trib)
    base_nodes = np.concatenate(base_lists)
    base_kn = np.concatenate(kn)
    base_cn = 2.0 * contact.damping * np.sqrt(base_kn * node_mass[base_nodes])

    # crack: node-to-segment both ways, half the penalty each; the damping a fraction of the
    # pair's critical value, the two faces' node masses in series
    passes = []
    if mesh.cracked:
        left, right = mesh.crack_nodes
        for slaves, masters, sign in ((right, left, 1.0), (left, right, -1.0)):
            trib = _tributary(p[1, slaves])
            h = np.abs(p[0, _node_beside(mesh, slaves)] - p[0, slaves])
            k = 0.5 * _penalty(stone, thickness, contact, trib, h)
            c = pair_damping(
                k,
                node_mass[slaves],
                node_mass[coincident_nodes(mesh, slaves, masters)],
                contact.damping,
            )
            passes.append((slaves.astype(np.int64), masters.astype(np.int64), sign, k, k.copy(), c))

    collar_nodes, collar_props = _collar_elements(mesh, collars)
    numbers = [a.lumped_mass, a.stiffness.data, base_kn, base_cn, collar_props]
    numbers += [q[3] for q in passes]
    if not (np.all(a.lumped_mass > 0.0) and all(np.all(np.isfinite(n)) for n in numbers)):
        raise InputError(
            f"the FEM model's masses and stiffnesses are not all finite and positive (stone E = "
            f"{stone.E:g} Pa, density = {stone.density:g} kg/m^3, thickness = {thickness:g} m, "
            "the contact penalty and the collars): an input is far outside its range"
        )
    return Model(
        mesh,
        stone,
        float(thickness),
        tuple(collars),
        contact,
        g,
        a.stiffness,
        a.lumped_mass,
        a.gravity,
        X,
        centroid_ref,
        base_nodes.astype(np.int64),
        base_kn,
        base_kn.copy(),
        base_cn,
        np.concatenate(trib_all),
        passes,
        collar_nodes,
        collar_props,
        float(top_load),
        bed,
        _cohesive_of(mesh, stone, thickness, crack if isinstance(crack, Crack) else Crack(crack)),
    )


def _cohesive_of(
    mesh: ColumnMesh, stone: Stone, thickness: float, crack: Crack
) -> CohesiveInterface | None:
    """The cohesive interface of a crack, or None for today's through crack of full height (no
    interface at all: extent None and depth 1)."""
    depth = require_range(
        "column crack_depth (fraction of the thickness)", crack.depth, 0.0, 1.0, closed_high=True
    )
    if crack.extent is None and depth >= 1.0:
        return None
    extent = (0.0, mesh.height) if crack.extent is None else crack.extent
    return _cohesive(mesh, stone, thickness, extent, depth)


def _cohesive(
    mesh: ColumnMesh, stone: Stone, thickness: float, crack, depth: float = 1.0
) -> CohesiveInterface:
    """The mid-plane's node pairs with the cohesive law on the part outside ``crack``, and on
    the crack's ligament where it runs through ``depth`` < 1 of the thickness
    (fem.partial_crack), checked: the crack within the column; the penalty stiff enough that
    the law's peak comes well before its full damage (fem.partial_crack.SOFTENING_FLOOR)."""
    if not mesh.cracked:
        raise InputError("column crack needs a cracked column (a mesh of two halves)")
    low, high = (float(c) for c in crack)
    if not 0.0 <= low <= high <= mesh.height * (1.0 + 1e-12):
        raise InputError(
            f"column crack = [{low:g}, {high:g}] m is outside the allowed range: "
            f"0 <= from <= to <= {mesh.height:g} m (the column height)"
        )
    p = mesh.points
    left, right = (nodes.astype(np.int64) for nodes in mesh.crack_nodes)
    partner = coincident_nodes(mesh, left, right)
    heights = p[1, left]
    h = np.minimum(
        np.abs(p[0, _node_beside(mesh, left)] - p[0, left]),
        np.abs(p[0, _node_beside(mesh, partner)] - p[0, partner]),
    )
    # K = alpha E / h, and on elements too wide for the law at least SOFTENING_FLOOR times
    # f_t^2 / (2 G_f): its softening branch then at least half its separation (delta_0 <=
    # delta_f / 2), where at f_t^2 / (2 G_f) the peak would come at full damage
    floor = SOFTENING_FLOOR * stone.ft**2 / (2.0 * stone.Gf)
    K_pair = np.maximum(
        np.asarray(cohesive_law.penalty_stiffness(stone.E, h, ALPHA), dtype=float), floor
    )
    on_crack = cracked_pairs(heights, (low, high), mesh.height)
    # a through crack's pairs are broken; a part-depth crack's keep their ligament, intact
    damage0 = np.where(on_crack, 1.0, 0.0) if depth >= 1.0 else np.zeros(heights.size)
    law = np.array([stone.ft, stone.ft, stone.Gf, stone.Gf, ETA])
    cohesive_law.check_parameters(
        float(np.min(K_pair)), stone.ft, stone.ft, stone.Gf, stone.Gf, ETA, 0.0
    )
    return CohesiveInterface(
        left,
        partner.astype(np.int64),
        heights,
        _tributary(heights),
        ligament_area(thickness * _tributary(heights), on_crack, depth),
        K_pair,
        law,
        damage0,
        (low, high),
        float(depth),
        on_crack if depth < 1.0 else np.zeros(heights.size, dtype=bool),
    )


def _node_above(mesh: ColumnMesh, nodes: np.ndarray) -> np.ndarray:
    """For base nodes: the node directly above (sharing an element edge)."""
    return _neighbour(mesh, nodes, axis=1)


def _node_beside(mesh: ColumnMesh, nodes: np.ndarray) -> np.ndarray:
    """For crack-face nodes: the nearest node inward along x."""
    return _neighbour(mesh, nodes, axis=0)


def _neighbour(mesh: ColumnMesh, nodes: np.ndarray, axis: int) -> np.ndarray:
    cells = mesh.cells
    p = mesh.points
    out = np.empty_like(nodes)
    for k, i in enumerate(nodes):
        touching = cells[:, np.any(cells == i, axis=0)]
        cand = np.unique(touching[touching != i])
        other = 1 - axis
        aligned = cand[np.abs(p[other, cand] - p[other, i]) < 1e-9 * (1.0 + abs(p[other, i]))]
        if aligned.size == 0:
            aligned = cand
        out[k] = aligned[np.argmin(np.abs(p[axis, aligned] - p[axis, i]))]
    return out


def _collar_elements(mesh: ColumnMesh, collars):
    nodes = np.zeros((len(collars), 6), dtype=np.int64)
    props = np.zeros((len(collars), 7 + LAW_SIZE))
    if not collars:
        return nodes, props
    faces = mesh.outer_nodes  # left and right outer faces (of one body if solid)
    p = mesh.points
    for c, collar in enumerate(collars):
        if not 0.0 < collar.y <= mesh.height:
            raise InputError(
                f"collar {c + 1} y = {collar.y:g} m is outside the column height "
                f"(0, {mesh.height:g}]"
            )
        row = []
        for face in faces:
            k = int(np.argmin(np.abs(p[1, face] - collar.y)))
            below = face[max(k - 1, 0)]
            above = face[min(k + 1, face.size - 1)]
            row += [face[k], below, above]
        nodes[c] = row
        chord = p[:, row[3]] - p[:, row[0]]
        L0 = float(np.hypot(*chord))
        L = collar.length if collar.length is not None else L0
        ea_l = collar.E * collar.area / L
        # bending stiffness scaled so that the lateral stiffness is 12 E I / L^3 over the chord
        ei_l = collar.E * collar.second_moment * (L0 / L) ** 3 / L0
        angles = []
        for side in range(2):
            below, above = row[1 + 3 * side], row[2 + 3 * side]
            angles.append(math.atan2(p[1, above] - p[1, below], p[0, above] - p[0, below]))
        props[c] = (
            ea_l,
            ei_l,
            collar.pretension,
            L0,
            math.atan2(chord[1], chord[0]),
            angles[0],
            angles[1],
            *collar.law(),
        )
    return nodes, props


# ------------------------------------------------------------------------------------------
# linearised stiffness and the stable time step
# ------------------------------------------------------------------------------------------


def base_stiffness(model: Model, tangential_scale: float = 1.0) -> sparse.csr_matrix:
    """Linearised stiffness of the base springs (all closed, ground frame): kn on each base
    node's vertical dof, ``tangential_scale`` * kt on its horizontal one."""
    n = model.n_dofs
    rows = np.concatenate([2 * model.base_nodes + 1, 2 * model.base_nodes])
    vals = np.concatenate([model.base_kn, tangential_scale * model.base_kt])
    return sparse.csr_matrix((vals, (rows, rows)), shape=(n, n))


def crack_stiffness(model: Model, tangential_scale: float = 1.0) -> sparse.csr_matrix:
    """Linearised stiffness of the crack springs in the reference configuration (faces
    coincident, all closed); the tangential springs scaled by ``tangential_scale``."""
    n = model.n_dofs
    rows, cols, vals = [], [], []
    for slaves, masters, _sign, knn, ktt, _ in model.crack_passes:
        partners = coincident_nodes(model.mesh, slaves, masters)
        for dof, k in ((0, knn), (1, tangential_scale * ktt)):
            i, j = 2 * slaves + dof, 2 * partners + dof
            rows += [i, j, i, j]
            cols += [i, j, j, i]
            vals += [k, k, -k, -k]
    if not rows:
        return sparse.csr_matrix((n, n))
    return sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )


def contact_stiffness(model: Model, tangential_scale: float = 1.0) -> sparse.csr_matrix:
    """Linearised stiffness of the contact springs in the reference configuration (all closed);
    the tangential springs scaled by ``tangential_scale``."""
    return base_stiffness(model, tangential_scale) + crack_stiffness(model, tangential_scale)


def coincident_nodes(mesh: ColumnMesh, slaves: np.ndarray, masters: np.ndarray) -> np.ndarray:
    """For each node of one crack face, the node of the other face at the same height."""
    y = mesh.points[1]
    return masters[np.argmin(np.abs(y[slaves][:, None] - y[masters][None, :]), axis=1)]


def collar_stiffness(model: Model, h: float = 1e-7) -> sparse.csr_matrix:
    """Linearised collar stiffness at the reference configuration (central differences)."""
    n = model.n_dofs
    if model.collar_nodes.shape[0] == 0:
        return sparse.csr_matrix((n, n))
    dofs = np.unique(
        np.concatenate([2 * model.collar_nodes.ravel(), 2 * model.collar_nodes.ravel() + 1])
    )
    x = model.X.copy()
    out = np.zeros((model.collar_nodes.shape[0], OUT_SIZE))
    state = model.collar_rest_state()
    cols = []
    step = h * model.mesh.width
    for d in dofs:
        fp, fm = np.zeros(n), np.zeros(n)
        x[d] += step
        K.collar_forces(x, model.collar_nodes, model.collar_props, out, fp, state, False)
        x[d] -= 2 * step
        K.collar_forces(x, model.collar_nodes, model.collar_props, out, fm, state, False)
        x[d] += step
        cols.append(-(fp - fm)[dofs] / (2 * step))
    local = np.array(cols).T
    local = 0.5 * (local + local.T)
    i, j = np.meshgrid(dofs, dofs, indexing="ij")
    return sparse.csr_matrix((local.ravel(), (i.ravel(), j.ravel())), shape=(n, n))


def max_frequency(stiffness: sparse.spmatrix, mass: np.ndarray) -> float:
    """Highest circular frequency sqrt(lambda_max(M^-1 K)) with lumped mass (rad/s), rounded up
    to six significant digits (well inside the step's safety factor)."""
    if stiffness.count_nonzero() == 0:  # no springs of that kind (a solid column, no collars)
        return 0.0
    scale = sparse.diags(1.0 / np.sqrt(mass))
    A = (scale @ stiffness @ scale).tocsr()
    if not np.all(np.isfinite(A.data)):
        raise InputError(
            "the FEM model's stiffness over its mass overflows (an input far outside its range: "
            "the stone's E or density, the thickness, the contact penalty, a collar)"
        )
    # a fixed start vector keeps dt reproducible to the last digit (rocking is chaotic)
    try:
        lam = eigsh(
            A, k=1, which="LA", return_eigenvectors=False, tol=1e-8, v0=np.ones(A.shape[0])
        )[0]
    except ArpackError as exc:
        if A.shape[0] <= 4000:  # a small model (a few springs on many dofs): solve it densely
            lam = float(np.linalg.eigvalsh(A.toarray())[-1])
            return _round_up(math.sqrt(max(lam, 0.0)), 6)
        raise InputError(
            f"the stable time step cannot be found ({exc.__class__.__name__}): an input is far "
            "outside its range (the stone's E or density, the thickness, the contact penalty, a "
            "collar)"
        ) from None
    # ARPACK's last digits vary from call to call (BLAS kernels follow the arrays' memory
    # alignment): rounded up to six significant digits, the frequency (so the step, and every
    # run) is the same each time, and stays an upper bound
    return _round_up(math.sqrt(max(lam, 0.0)), 6)


def _round_up(value: float, digits: int) -> float:
    """The smallest number of `digits` significant digits at or above a positive value."""
    if value <= 0.0:
        return 0.0
    quantum = 10.0 ** (math.floor(math.log10(value)) - digits + 1)
    return math.ceil(value / quantum) * quantum


@dataclass(frozen=True)
class StableStep:
    """Critical steps (s): 2 / omega_max of the stone alone; the linear bound 2 / omega_max with
    every contact spring closed and the collars; and the contact onset limit
    ``CONTACT_ONSET_LIMIT`` / omega_c of the stiffest contact spring on its nodes. The step used
    is safety * min(linear, onset) * (sqrt(1 + xi^2) - xi), contact damping xi."""

    critical_elastic: float
    critical_linear: float
    safety: float
    damping: float
    critical_contact: float = math.inf

    @property
    def critical(self) -> float:
        """The critical step the run's step is a fraction of: the smaller of the linear bound
        and the contact onset limit."""
        return min(self.critical_linear, self.critical_contact)

    @property
    def dt(self) -> float:
        xi = self.damping
        return self.safety * self.critical * (math.sqrt(1.0 + xi * xi) - xi)

    @property
    def contact_reduction(self) -> float:
        """critical / critical_elastic: how much contact and collars shorten the step."""
        return self.critical / self.critical_elastic


# omega_c dt of the stiffest closing contact spring above which a run's energy balance fails:
# a spring that closes between two steps starts at the penetration it reached in the step, not
# at zero, and gives its node the energy 1/2 k d^2 that no force took from it, of order
# (omega_c dt)^2 of the node's kinetic energy at each landing. Measured (docs/physics.md, "The
# stable step"): the default column's halves on a lead bed, meshes 0.225 and 0.1125 m, fail at
# omega_c dt = 1.57 and 1.61 and close their balance to 2e-3 at 1.38 and 1.43, while the linear
# bound allowed 1.66; 1.4 is the limit taken, and safety 0.9 with 5 % damping steps at 1.2.
CONTACT_ONSET_LIMIT = 1.4


def contact_frequency(model: Model) -> float:
    """Top circular frequency (rad/s) of the contact springs alone, all closed, on the lumped
    masses: the Gershgorin bound sqrt(max_i sum_j |S_ij| / sqrt(m_i m_j)) of M^-1/2 S M^-1/2,
    S the base's springs k t l_trib (and the crack's, with penalty enforcement): for a base
    node k t l_trib / m_node. 0 without contact springs."""
    springs = base_stiffness(model)
    if model.contact.enforcement == "penalty":
        springs = springs + crack_stiffness(model)
    springs = sparse.csr_matrix(springs)
    if springs.nnz == 0:
        return 0.0
    scale = sparse.diags(1.0 / np.sqrt(model.mass))
    rows = abs(scale @ springs @ scale).sum(axis=1)
    return _round_up(math.sqrt(float(rows.max())), 6)


def stable_time_step(model: Model, safety: float = 0.9) -> StableStep:
    """Stable step from omega_max^2 <= lambda_max(stone + base) + lambda_max(crack + collars).

    The base springs are isotropic (kn = kt, each k I on one node, anchored to the ground), so
    the spectrum of stone plus base is invariant under any rotation of each body, and losing
    springs (a lifted or sliding node) only lowers it: its upright value with all base nodes
    closed bounds every configuration. The crack springs and collars join the bodies to each
    other, and the halves turn apart; Weyl's inequality adds their top eigenvalue. The exact
    top frequency of the upright column is not enough: once a half rocks onto a toe, its
    rotated stiffness and the springs between the halves line up differently and the sum can
    exceed it. (With kn != kt the base joins the crack and collars in the second term.) The
    intact pairs of a partial crack (:func:`colonna.fem.partial_crack.springs`, undamaged:
    damage only softens them) join the second term too.

    A linear bound is not enough where contact springs dominate (a lead or stiff stone bed,
    coarse meshes): a spring that closes between steps is not the linear system's, and the
    step is also held below ``CONTACT_ONSET_LIMIT`` / omega_c (:func:`contact_frequency`)."""
    require_range("run safety (time-step safety factor)", safety, 0.0, 1.0, closed_high=True)
    w_el = max_frequency(model.stiffness, model.mass)
    # exact crack contact has no springs, and no step limit of its own
    between = collar_stiffness(model) + springs(model.cohesive, model.n_dofs)
    if model.contact.enforcement == "penalty":
        between = between + crack_stiffness(model)
    if np.array_equal(model.base_kn, model.base_kt):
        bodies = model.stiffness + base_stiffness(model)
    else:
        bodies, between = model.stiffness, between + base_stiffness(model)
    w_bound = math.sqrt(
        max_frequency(bodies, model.mass) ** 2 + max_frequency(between, model.mass) ** 2
    )
    w_contact = contact_frequency(model)
    onset = CONTACT_ONSET_LIMIT / w_contact if w_contact > 0.0 else math.inf
    return StableStep(2.0 / w_el, 2.0 / w_bound, safety, model.contact.damping, onset)
