"""Compiled (numba) kernels of the rigid multibody contact model. Private: use
:mod:`rigid.multibody`.

State: per body the centroid (x, y) and the counter-clockwise angle phi, and their velocities,
in the ground frame (the ground acceleration acts as the body force -m ug''). Reported rotations
follow the paper (theta = -phi: positive tipping toward +x).

Time stepping is Moreau-Jean's midpoint scheme at the velocity-impulse level (Moreau 1988, Jean
1999; the scheme of Siconos and LMGC90):

    q_m     = q_k + h/2 v_k                  contacts detected at q_m (gap <= 0: active; a
                                             crack contact also within g h^2 and closing)
    M (v_k+1 - v_k) = h f(q_m, t_m) + G^T P  smooth forces: gravity, ground, collars
    q_k+1   = q_m + h/2 v_k+1

with, for every active contact, Newton's impact law U_N+ + e_n U_N- >= 0 complementary to the
normal impulse P_N >= 0, and Coulomb friction |P_T| <= mu P_N with P_T opposing the sliding
velocity U_T+ (zero velocity while it sticks). The per-step problem is solved by non-smooth
Gauss-Seidel over the contacts, each local 2 x 2 problem exactly (open, stick, slip +/-).

Energy bookkeeping is exact for this scheme: kinetic energy changes by the work of the smooth
forces at q_m over q_k+1 - q_k plus the impulses' work P . (U+ + U-) / 2, which is the energy that
impacts and friction dissipate.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit, prange

from ..core.collar_law import FIBRE, LAW_KIND, OUT_SIZE, RECORDED, frame_local_law
from ..core.fibre import STRESS as FIBRE_STRESS
from ..core.jit_cache import ensure_fresh
from ..core.tables import table_value

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)

N_RECORDED = len(RECORDED)  # plastic-state entries per collar in a history row
N_COLLAR_COLS = OUT_SIZE + N_RECORDED
"""Columns per collar in a history row: collar_forces' outputs at that time (OUT_SIZE), then
its plastic state's RECORDED entries."""

GROUND_NONE = 0
GROUND_HARMONIC = 1
GROUND_RECORD = 2

# statuses
FINISHED = 0  # ran to the requested duration
OVERTURNED = 1
SETTLED = 2  # early exit: after the ground motion the energy is below every barrier
UNSTABLE = 3  # non-finite state or energy out of bounds

# why it overturned
OVER_NONE = 0
OVER_HALF_PI = 1  # a body rotated past pi/2
OVER_COLUMN = 2  # the column's centre of mass past an outer toe, moving outward
OVER_HALF = 3  # a free half's centre of mass past its outer toe, moving outward
# why an UNSTABLE run stopped (simulate's reason then): the state or the energy left its bounds,
# or a collar's law returned no answer (NaN: a fibre section whose iteration did not converge)
UNSTABLE_STATE = 10
UNSTABLE_COLLAR = 11

CONTACT_BASE = 0
CONTACT_CRACK = 1

# output columns, per row: t, then per body x, y, phi, vx, vy, omega, then the tallies
OUT_T = 0
N_BODY_COLS = 6
# after the body columns: kinetic, gravity, collar, dissipated, external work, crack normal
# force, crack tangential force (N_TAIL columns), then per body its base normal and
# tangential force, then per collar its N_COLLAR_COLS (outputs and recorded plastic state)
N_TAIL = 7


@njit(cache=True)
def history_columns(n_bodies, n_collars):
    """The width of a history row (``out``'s second dimension) for n_bodies and n_collars: the
    layout _write_row writes."""
    return 1 + N_BODY_COLS * n_bodies + N_TAIL + 2 * n_bodies + N_COLLAR_COLS * n_collars


# The kernels' arguments travel in bundles (named tuples, which numba compiles as records of
# arrays and numbers), as the FEM's do (fem._kernels): what describes the column (Bodies,
# Contacts, Collars), the ground (Ground), the run (Settings), and what a step reads and
# updates besides the positions and velocities (Scratch, StepState).

Bodies = namedtuple("Bodies", ["mass", "inertia", "minv", "half", "g"])
"""mass (n_bodies,) kg; inertia (n_bodies,) kg m^2, centroidal; minv (3 n_bodies,): the inverse
mass of each dof (1/m, 1/m, 1/J per body); half (n_bodies, 3): half width, half height (m) and
dead load at the top's centre (N); g (m/s^2). Make it with :func:`bodies`."""

Contacts = namedtuple("Contacts", ["a", "b", "pt", "face", "mu", "kind"])
"""The candidate contacts: point pt[c] (body frame) of body a[c] against the ground (b[c] < 0)
or against the face face[c] = (local x, outward sign, half length) of body b[c]; friction
coefficient mu[c]; kind[c]: CONTACT_BASE or CONTACT_CRACK."""

Collars = namedtuple("Collars", ["a", "b", "r", "props", "limits", "state_size"])
"""The collar elements (collar_forces' col_a, col_b, col_r, props), limits[c] = (A, W, f_y,
H or -1) of each (MultibodyColumn.col_limits) and the numbers per collar in their plastic
state (MultibodyColumn.collar_state_size: as many as the largest of their laws needs)."""

Ground = namedtuple("Ground", ["kind", "params", "times", "values", "end"])
"""The ground motion: kind (GROUND_NONE, GROUND_HARMONIC, GROUND_RECORD); params = (amplitude,
omega, phase, duration, rows of the horizontal record, 1 if vertical rows follow); the tables
(times, values) of colonna.core.ground.kernel_tables; end (s): when the ground is still."""

Settings = namedtuple(
    "Settings",
    [
        "h",
        "n_steps",
        "refine",
        "e_n",
        "out_every",
        "free_halves",
        "barrier",
        "early_exit",
        "impact_tol",
        "energy_scale",
        "tol",
        "max_iter",
        "outcome_only",
        "stop_decided",
        "impacts_needed",
        "touching_scale",
    ],
    defaults=(False, False, True, 1.0),
)
"""The run (see :func:`simulate`): step h (s), n_steps of it, refine (substeps of a step in which
a contact closes), Newton's e_n, a history row every out_every steps, free_halves, barrier (J),
early_exit, impact_tol (rad), energy_scale (J), the contact solver's tolerance tol and
max_iter sweeps, and outcome_only (False by default: a run for its outcome, without history:
the steps of a column at rest skipped, the contacts' active-set solve by Gaussian elimination
after FAST_GS_ITERATIONS sweeps; see :func:`simulate`) and stop_decided (False by default;
with outcome_only: the run stops once no answer can change, :func:`_decided`) and
impacts_needed (True by default: the stop keeps the impact count exact; False where the
caller does not use it, as the fragility's limit states do not) and touching_scale (1 by
default: a crack contact within g h^2 of touching and closing is active, h the step's own;
(h_0 / h)^2 keeps the tolerance of a step h_0 at a longer step h)."""

REST_VELOCITY = 1e-9  # m/s: a body at rest moves slower than this at every point (measured:
# 1e-11 from the contact solver's tolerance while resting under a record)

Scratch = namedtuple(
    "Scratch",
    [
        "qm",
        "f",
        "vfree",
        "vnew",
        "bvec",
        "umin",
        "P",
        "mu_act",
        "G",
        "W",
        "act",
        "n_base",
        "col_out",
        "col_state",
        "trig",
        "impulse_sum",
        "as_status",
        "as_sign",
        "as_A",
        "as_rhs",
        "as_x",
        "as_lu",
    ],
)
"""A step's work arrays (:func:`new_scratch`): midpoint positions, forces, free and new
velocities, the active contacts' free and pre-step velocities, impulses, friction, rows G,
Delassus matrix W, candidates act and base contacts per body; and the collars' outputs and
plastic states (col_out, col_state: collar_forces' out and state, kept across steps); trig (per
body the cosine and sine of its angle at the configuration whose contact rows are built,
:func:`_body_trig`), impulse_sum (G^T P per dof) and the active-set solve's work arrays (as_*:
:func:`_active_set_work`)."""

StepState = namedtuple(
    "StepState",
    ["P_prev", "was_active", "pivot_side", "armed", "tallies", "forces", "impacts"],
)
"""What a step reads and updates besides q and v (:func:`new_step_state`): the last impulses of
each candidate and whether it was active, each body's pivot side and whether an impact is
armed, tallies = (dissipated energy, external work, impacts, max solver iterations), forces =
(crack normal, crack tangential, then per body base normal and tangential), and the impacts
table."""


def bodies(mass, inertia, half, g) -> Bodies:
    """The :class:`Bodies` bundle of bodies of these masses, inertias and half sizes."""
    mass = np.ascontiguousarray(mass, dtype=float)
    inertia = np.ascontiguousarray(inertia, dtype=float)
    minv = np.empty(3 * mass.size)
    minv[0::3] = 1.0 / mass
    minv[1::3] = 1.0 / mass
    minv[2::3] = 1.0 / inertia
    return Bodies(mass, inertia, minv, np.ascontiguousarray(half, dtype=float), float(g))


@njit(cache=True)
def new_scratch(n_bodies, n_contacts, n_collars, collar_state_size):
    """The work arrays of a step (:class:`Scratch`), collars' state at rest (collar_state_size
    numbers per collar)."""
    n_dof = 3 * n_bodies
    return Scratch(
        np.empty(n_dof),
        np.empty(n_dof),
        np.empty(n_dof),
        np.empty(n_dof),
        np.zeros(2 * n_contacts),
        np.zeros(2 * n_contacts),
        np.zeros(2 * n_contacts),
        np.zeros(n_contacts),
        np.zeros((2 * n_contacts, n_dof)),
        np.zeros((2 * n_contacts, 2 * n_contacts)),
        np.zeros(n_contacts, dtype=np.int64),
        np.zeros(n_bodies, dtype=np.int64),
        np.zeros((n_collars, OUT_SIZE)),
        np.zeros((n_collars, collar_state_size)),
        np.zeros((n_bodies, 2)),
        np.zeros(n_dof),
        np.zeros(n_contacts, dtype=np.int64),
        np.ones(n_contacts),
        np.zeros((2 * n_contacts, 2 * n_contacts)),
        np.zeros(2 * n_contacts),
        np.zeros(2 * n_contacts),
        np.zeros((2 * n_contacts, 2 * n_contacts + 1)),
    )


@njit(cache=True)
def new_step_state(n_bodies, n_contacts, impacts):
    """The contact state of bodies at rest (:class:`StepState`), no contact active yet, the
    impacts written to ``impacts`` (rows (t, body, theta' before, theta' after))."""
    return StepState(
        np.zeros((n_contacts, 2)),
        np.zeros(n_contacts, dtype=np.bool_),
        np.zeros(n_bodies, dtype=np.int64),
        np.zeros(n_bodies, dtype=np.bool_),
        np.zeros(4),
        np.zeros(2 + 2 * n_bodies),
        impacts,
    )


@njit(cache=True)
def ground_acceleration(t, ground):
    """Horizontal ground acceleration (m/s^2): harmonic ground.params = (amplitude, omega,
    phase, duration, ...) or a record: the first params[4] rows of the tables, linear
    interpolation, zero outside."""
    gpar = ground.params
    if ground.kind == GROUND_HARMONIC:
        if 0.0 <= t <= gpar[3]:
            return gpar[0] * math.sin(gpar[1] * t + gpar[2])
        return 0.0
    if ground.kind == GROUND_RECORD:
        n = int(gpar[4])
        return table_value(t, ground.times[:n], ground.values[:n])
    return 0.0


@njit(cache=True)
def vertical_acceleration(t, ground):
    """Vertical ground acceleration (m/s^2, upward positive): with params[5] = 1, the rows of
    the tables after the first params[4], linear interpolation, zero outside."""
    gpar = ground.params
    if gpar[5] == 0.0:
        return 0.0
    n = int(gpar[4])
    return table_value(t, ground.times[n:], ground.values[n:])


@njit(cache=True, inline="always")
def _world_trig(q, body, lx, ly, c, s):
    """World position of the body-fixed point (lx, ly) (relative to the centroid), c and s the
    cosine and sine of the body's angle (:func:`_body_trig`)."""
    return q[3 * body] + c * lx - s * ly, q[3 * body + 1] + s * lx + c * ly


@njit(cache=True, inline="always")
def _body_trig(q, trig):
    """trig[i] = (cos phi_i, sin phi_i) of every body i at q: what _contact_row reads."""
    for i in range(trig.shape[0]):
        trig[i, 0] = math.cos(q[3 * i + 2])
        trig[i, 1] = math.sin(q[3 * i + 2])


@njit(cache=True)
def collar_forces(q, col_a, col_b, col_r, props, f, out, state, commit):
    """Co-rotational Euler-Bernoulli frame elements between body-fixed attachment points (the
    FEM's collar element with rigid end sections), elastic or elastoplastic (N and M).

    col_r[c] = (x1, y1, x2, y2): attachment points in the frames of bodies col_a[c], col_b[c];
    props[c] = (EA/L, EI'/L0, pretension, L0, chord angle at rest, then the law row of
    colonna.core.collar.Collar.law). Adds the generalised forces -dU/dq to f (if f.size) and
    writes out[c] = (N, M1, M2, elastic energy, plastic strain, extreme-fibre strain, end
    rotations th1, th2 relative to the chord). Plasticity and fracture as the FEM's
    (colonna.core.collar_law.frame_local_law): state[c] = (plastic elongation, accumulated
    plastic strain, plastic work, hinge rotations, largest fibre strain, fractured), updated
    with commit. Returns the elastic energy U (J); the plastic work of a committed call is
    added to state[c, 2]. The cosine and sine of an end's body angle are computed once for the
    collars in a row that share that body (the column's collars all join the same two)."""
    energy = 0.0
    body_a = -1
    body_b = -1
    ca = sa = cb = sb = 0.0
    for c in range(col_a.size):
        a = col_a[c]
        b = col_b[c]
        if a != body_a:
            body_a = a
            ca = math.cos(q[3 * a + 2])
            sa = math.sin(q[3 * a + 2])
        if b != body_b:
            body_b = b
            cb = math.cos(q[3 * b + 2])
            sb = math.sin(q[3 * b + 2])
        x1, y1 = _world_trig(q, a, col_r[c, 0], col_r[c, 1], ca, sa)
        x2, y2 = _world_trig(q, b, col_r[c, 2], col_r[c, 3], cb, sb)
        dx = x2 - x1
        dy = y2 - y1
        length = math.sqrt(dx * dx + dy * dy)
        beta = math.atan2(dy, dx) - props[c, 4]
        th1 = q[3 * a + 2] - beta
        th2 = q[3 * b + 2] - beta
        N, M1, M2, e, plastic_strain, fibre = frame_local_law(
            length - props[c, 3],
            th1,
            th2,
            props[c, 0],
            props[c, 1],
            props[c, 2],
            props[c, 5:],
            state,
            c,
            commit,
        )
        out[c, 5] = fibre
        out[c, 6] = th1
        out[c, 7] = th2
        out[c, 4] = plastic_strain
        out[c, 0] = N
        out[c, 1] = M1
        out[c, 2] = M2
        out[c, 3] = e
        energy += e
        if f.size == 0:
            continue
        ex = dx / length
        ey = dy / length
        shear = (M1 + M2) / length
        # force on end 1: N e - shear n, n = (-ey, ex); on end 2 the opposite
        f1x = N * ex + shear * ey
        f1y = N * ey - shear * ex
        r1x = x1 - q[3 * a]
        r1y = y1 - q[3 * a + 1]
        r2x = x2 - q[3 * b]
        r2y = y2 - q[3 * b + 1]
        f[3 * a] += f1x
        f[3 * a + 1] += f1y
        f[3 * a + 2] += r1x * f1y - r1y * f1x - M1
        f[3 * b] -= f1x
        f[3 * b + 1] -= f1y
        f[3 * b + 2] += -(r2x * f1y - r2y * f1x) - M2
    return energy


@njit(cache=True, inline="always")
def _contact_row(q, trig, c, cand_a, cand_b, cand_pt, cand_face, G, j, n_dof):
    """Gap of candidate contact c at q and, if it is on its face, its velocity rows
    G[2j] (normal) and G[2j+1] (tangential). trig: the bodies' cosines and sines at q
    (:func:`_body_trig`). Returns (gap, on_face)."""
    a = cand_a[c]
    b = cand_b[c]
    px, py = _world_trig(q, a, cand_pt[c, 0], cand_pt[c, 1], trig[a, 0], trig[a, 1])
    if b < 0:  # the ground y = 0
        nx = 0.0
        ny = 1.0
        gap = py
        on_face = True
    else:  # a face of body b: local x = face_x, outward sign
        cb = trig[b, 0]
        sb = trig[b, 1]
        rx = px - q[3 * b]
        ry = py - q[3 * b + 1]
        lx = cb * rx + sb * ry
        ly = -sb * rx + cb * ry
        sign = cand_face[c, 1]
        gap = (lx - cand_face[c, 0]) * sign
        on_face = abs(ly) <= cand_face[c, 2] * (1.0 + 1e-9)
        nx = sign * cb
        ny = sign * sb
    if not on_face:
        return gap, False
    tx = ny
    ty = -nx
    for k in range(n_dof):
        G[2 * j, k] = 0.0
        G[2 * j + 1, k] = 0.0
    rax = px - q[3 * a]
    ray = py - q[3 * a + 1]
    G[2 * j, 3 * a] = nx
    G[2 * j, 3 * a + 1] = ny
    G[2 * j, 3 * a + 2] = rax * ny - ray * nx
    G[2 * j + 1, 3 * a] = tx
    G[2 * j + 1, 3 * a + 1] = ty
    G[2 * j + 1, 3 * a + 2] = rax * ty - ray * tx
    if b >= 0:
        rbx = px - q[3 * b]
        rby = py - q[3 * b + 1]
        G[2 * j, 3 * b] = -nx
        G[2 * j, 3 * b + 1] = -ny
        G[2 * j, 3 * b + 2] = -(rbx * ny - rby * nx)
        G[2 * j + 1, 3 * b] = -tx
        G[2 * j + 1, 3 * b + 1] = -ty
        G[2 * j + 1, 3 * b + 2] = -(rbx * ty - rby * tx)
    return gap, True


@njit(cache=True, inline="always")
def _normal_velocity(G, j, v):
    un = 0.0
    for k in range(v.size):
        un += G[2 * j, k] * v[k]
    return un


@njit(cache=True)
def local_coulomb(wnn, wnt, wtn, wtt, rn, rt, mu):
    """Exact solution of one contact's problem U = W P + r with 0 <= U_N _|_ P_N >= 0 and
    Coulomb's law in the plane: open, sticking (U_T = 0, |P_T| <= mu P_N) or sliding
    (P_T = -mu P_N sgn U_T). Returns (P_N, P_T)."""
    if rn >= 0.0:
        return 0.0, 0.0
    if mu <= 0.0:
        return -rn / wnn, 0.0
    det = wnn * wtt - wnt * wtn
    if det > 0.0:
        pn = (-rn * wtt + rt * wnt) / det
        pt = (-rt * wnn + rn * wtn) / det
        if pn >= 0.0 and abs(pt) <= mu * pn:
            return pn, pt
    best_pn = -rn / wnn
    best_pt = 0.0
    for s in (1.0, -1.0):
        denom = wnn - s * mu * wnt
        if denom <= 0.0:
            continue
        pn = -rn / denom
        ut = (wtn - s * mu * wtt) * pn + rt
        if s * ut >= 0.0:
            return pn, -s * mu * pn
    return best_pn, best_pt


@njit(cache=True)
def _solve_contacts(W, bvec, P, mu, n_act, tol, max_iter):
    """Non-smooth Gauss-Seidel over the active contacts. Returns the iterations used."""
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 (it: the count returned)
        change = 0.0
        size = 0.0
        for j in range(n_act):
            rn = bvec[2 * j]
            rt = bvec[2 * j + 1]
            for k in range(2 * n_act):
                rn += W[2 * j, k] * P[k]
                rt += W[2 * j + 1, k] * P[k]
            pn0 = P[2 * j]
            pt0 = P[2 * j + 1]
            rn -= W[2 * j, 2 * j] * pn0 + W[2 * j, 2 * j + 1] * pt0
            rt -= W[2 * j + 1, 2 * j] * pn0 + W[2 * j + 1, 2 * j + 1] * pt0
            pn, pt = local_coulomb(
                W[2 * j, 2 * j],
                W[2 * j, 2 * j + 1],
                W[2 * j + 1, 2 * j],
                W[2 * j + 1, 2 * j + 1],
                rn,
                rt,
                mu[j],
            )
            change = max(change, abs(pn - pn0), abs(pt - pt0))
            size = max(size, abs(pn))
            P[2 * j] = pn
            P[2 * j + 1] = pt
        if change <= tol * size or size == 0.0:
            break
    return it


GS_ITERATIONS = 100  # Gauss-Seidel sweeps before the exact active-set solve
FAST_GS_ITERATIONS = 5  # the same with outcome_only, whose active-set solve is cheap


@njit(cache=True)
def _gauss_solve(A, rhs, x, lu):
    """x = A^-1 rhs by Gaussian elimination with partial pivoting (lu: work, n x n+1); False
    where a pivot falls below 1e-13 of A's largest entry (then lstsq)."""
    n = rhs.size
    big = 0.0
    for i in range(n):
        for j in range(n):
            lu[i, j] = A[i, j]
            big = max(big, abs(A[i, j]))
        lu[i, n] = rhs[i]
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(lu[i, k]) > abs(lu[p, k]):
                p = i
        if abs(lu[p, k]) <= 1e-13 * big:
            return False
        if p != k:
            for j in range(k, n + 1):
                lu[k, j], lu[p, j] = lu[p, j], lu[k, j]
        for i in range(k + 1, n):
            f = lu[i, k] / lu[k, k]
            if f != 0.0:  # column k below the pivot is read no more: left as it is
                for j in range(k + 1, n + 1):
                    lu[i, j] -= f * lu[k, j]
    for i in range(n - 1, -1, -1):
        acc = lu[i, n]
        for j in range(i + 1, n):
            acc -= lu[i, j] * x[j]
        x[i] = acc / lu[i, i]
    return True


@njit(cache=True)
def _active_set(W, bvec, P, mu, n_act, gauss=False):
    """:func:`_active_set_work` with work arrays of its own."""
    m2 = 2 * n_act
    return _active_set_work(
        W,
        bvec,
        P,
        mu,
        n_act,
        gauss,
        np.zeros(n_act, dtype=np.int64),
        np.ones(n_act),
        np.zeros((m2, m2)),
        np.zeros(m2),
        np.zeros(m2),
        np.zeros((m2, m2 + 1)),
    )


@njit(cache=True)
def _active_set_work(W, bvec, P, mu, n_act, gauss, status, sign, A, rhs, x, lu):
    """The contact problem solved exactly from the Gauss-Seidel iterate P (in place).

    With more contact rows than degrees of freedom (4 active contacts of 2 bodies: 8 rows, 6
    dof) the Delassus matrix W is singular, the impulses are not unique, and Gauss-Seidel
    moves along that null space only slowly: its velocities can stay off by 1e-4 after
    hundreds of sweeps, which then builds up step by step. The velocities are unique, and
    this finds them: each contact is open (P = 0), sticking (U = 0) or sliding (U_N = 0,
    P_T = -s mu P_N), its status taken from P; the equations of that status are solved with
    W + eps I (eps = 1e-9 of W's largest diagonal term, which makes the impulses unique and
    moves the velocities by 1e-9 of them); the contact that most violates its status's
    conditions (U_N >= 0 when open; P_N >= 0 and |P_T| <= mu P_N when sticking; P_N >= 0 and
    sliding in the direction s when sliding) changes status, and again, until none does.
    Returns False (P unchanged) if that does not settle within 4 n + 10 changes. ``gauss``:
    each status's equations by Gaussian elimination (:func:`_gauss_solve`; lstsq where a pivot
    vanishes), the same solution to round-off and 20-50 times cheaper than lstsq's SVD.
    Work arrays (any contents, at least this size: Scratch's as_*): status and sign (n_act), A
    (2 n_act square), rhs and x (2 n_act), lu (2 n_act x 2 n_act + 1)."""
    m2 = 2 * n_act
    A = A[:m2, :m2]
    rhs = rhs[:m2]
    x = x[:m2]
    lu = lu[:m2, : m2 + 1]
    eps = 0.0
    scale_u = 0.0
    for r in range(m2):
        eps = max(eps, W[r, r])
        scale_u = max(scale_u, abs(bvec[r]))
    eps *= 1e-9
    if scale_u == 0.0:
        scale_u = 1e-300
    # status: 0 open, 1 sticking, 2 sliding (in the direction sign)
    for j in range(n_act):
        pn = P[2 * j]
        pt = P[2 * j + 1]
        sign[j] = 1.0
        if pn <= 0.0:
            status[j] = 0
        elif abs(pt) < mu[j] * pn * (1.0 - 1e-6):
            status[j] = 1
        else:
            status[j] = 2
            sign[j] = -1.0 if pt > 0.0 else 1.0
    for _ in range(4 * n_act + 10):
        A[:, :] = 0.0
        rhs[:] = 0.0
        for j in range(n_act):
            n_row = 2 * j
            t_row = 2 * j + 1
            if status[j] == 0:
                A[n_row, n_row] = 1.0
                A[t_row, t_row] = 1.0
                continue
            for k in range(m2):
                A[n_row, k] = W[n_row, k]
            A[n_row, n_row] += eps
            rhs[n_row] = -bvec[n_row]
            if status[j] == 1:
                for k in range(m2):
                    A[t_row, k] = W[t_row, k]
                A[t_row, t_row] += eps
                rhs[t_row] = -bvec[t_row]
            else:
                A[t_row, t_row] = 1.0
                A[t_row, n_row] = sign[j] * mu[j]
        if not (gauss and _gauss_solve(A, rhs, x, lu)):
            x[:] = np.linalg.lstsq(A, rhs)[0]
        scale_p = 1e-300
        for r in range(m2):
            scale_p = max(scale_p, abs(x[r]))
        worst = -1
        worst_v = 1e-10
        for j in range(n_act):
            pn = x[2 * j]
            pt = x[2 * j + 1]
            un = bvec[2 * j] + eps * pn
            ut = bvec[2 * j + 1] + eps * pt
            for k in range(m2):
                un += W[2 * j, k] * x[k]
                ut += W[2 * j + 1, k] * x[k]
            if status[j] == 0:
                v = -un / scale_u
            elif status[j] == 1:
                v = max(-pn, abs(pt) - mu[j] * pn) / scale_p
            else:
                v = max(-pn / scale_p, -sign[j] * ut / scale_u)
            if v > worst_v:
                worst = j
                worst_v = v
        if worst < 0:
            for r in range(m2):
                P[r] = x[r]
            return True
        j = worst
        pn = x[2 * j]
        pt = x[2 * j + 1]
        if status[j] == 0:
            status[j] = 1
        elif status[j] == 1:
            if abs(pt) > mu[j] * pn and not (pn < 0.0 and abs(pt) < -mu[j] * pn):
                status[j] = 2
                sign[j] = -1.0 if pt > 0.0 else 1.0
            else:
                status[j] = 0
        else:
            status[j] = 0 if pn < 0.0 else 1
    return False


@njit(cache=True)
def _contact_problem(G, minv, vfree, v, act, cand_a, cand_b, n_act, nb, bvec, umin, W):
    """The active contacts' problem U = W P + b: the rows' free velocities bvec = G vfree,
    their velocities before the step umin = G v, and the Delassus matrix W = G M^-1 G^T.
    Each sum runs over the dofs in order and leaves out the rows' zero entries (the dofs of
    the bodies a contact does not touch), whose terms are exact zeros: the same numbers as the
    full products."""
    m2 = 2 * n_act
    for r in range(m2):
        cr = act[r // 2]
        ar = cand_a[cr]
        br = cand_b[cr]
        acc = 0.0
        acc_minus = 0.0
        for i in range(nb):
            if i == ar or i == br:
                for k in range(3 * i, 3 * i + 3):
                    acc += G[r, k] * vfree[k]
                    acc_minus += G[r, k] * v[k]
        bvec[r] = acc
        umin[r] = acc_minus
        for s in range(r, m2):
            cs = act[s // 2]
            as_ = cand_a[cs]
            bs = cand_b[cs]
            w = 0.0
            for i in range(nb):
                if (i == ar or i == br) and (i == as_ or i == bs):
                    for k in range(3 * i, 3 * i + 3):
                        w += G[r, k] * minv[k] * G[s, k]
            W[r, s] = w
            W[s, r] = w


@njit(cache=True)
def _step(t, h, q, v, bodies, contacts, collars, ground, settings, scratch, state):
    """One Moreau-Jean step of size h from time t; q, v and the contact state (``state``, a
    :class:`StepState`) updated in place; ``settings``: its e_n, impact_tol, tol and max_iter.

    state.tallies = (dissipated energy, external work, impacts, max solver iterations);
    state.forces = (crack normal, crack tangential, then per body base normal and tangential),
    mean over the step (N); with settings.outcome_only (no histories) the dissipated energy and
    the forces are not kept. Returns True if a contact closed in this step: open in the last
    step, closed at this one's midpoint or end, approaching faster than gravity alone makes it
    in a few steps (4 g h; slower closures are a resting contact settling back after the
    midpoint scheme's O(h^2) lift of a pivot)."""
    mass, minv, half, g = bodies.mass, bodies.minv, bodies.half, bodies.g
    cand_a, cand_b, cand_pt, cand_face = contacts.a, contacts.b, contacts.pt, contacts.face
    cand_mu, cand_kind = contacts.mu, contacts.kind
    col_a, col_b, col_r, col_props = collars.a, collars.b, collars.r, collars.props
    e_n, impact_tol = settings.e_n, settings.impact_tol
    qm, f, vfree, vnew, bvec, umin, P, mu_act, G, W, act, n_base, col_out, col_state = scratch[:14]
    trig, impulse_sum = scratch.trig, scratch.impulse_sum
    outcome_only = settings.outcome_only
    P_prev, was_active, pivot_side, armed, tallies, forces, impacts = state
    nb = mass.size
    n_dof = 3 * nb
    nc = cand_a.size
    tm = t + 0.5 * h
    ag = ground_acceleration(tm, ground)
    av = vertical_acceleration(tm, ground)
    for k in range(n_dof):
        qm[k] = q[k] + 0.5 * h * v[k]
        f[k] = 0.0
    for i in range(nb):
        f[3 * i] = -mass[i] * ag
        f[3 * i + 1] = -mass[i] * (g + av)
        load = half[i, 2]
        if load != 0.0:  # dead top load at the top's centre, (0, hh) in the body frame
            f[3 * i + 1] -= load
            f[3 * i + 2] += load * half[i, 1] * math.sin(qm[3 * i + 2])
    if col_a.size:
        work_before = 0.0
        for c in range(col_a.size):
            work_before += col_state[c, 2]
        collar_forces(qm, col_a, col_b, col_r, col_props, f, col_out, col_state, True)
        if not outcome_only:  # the dissipated energy: histories only
            for c in range(col_a.size):
                tallies[0] += col_state[c, 2]
            tallies[0] -= work_before
    for k in range(n_dof):
        vfree[k] = v[k] + h * minv[k] * f[k]
        vnew[k] = vfree[k]
    # active contacts at the midpoint
    n_act = 0
    closed = False
    v_impact = 4.0 * g * h  # slower closures are resting contacts settling back
    # a crack contact within the midpoint scheme's drift of a closed contact (g h^2) whose
    # free motion closes it is active too: the crack starts closed with no force across it,
    # and the drift's sign must not decide whether the halves press (touching_scale: another
    # step's drift; the tolerance sets how the halves' re-closing is caught, and its own
    # scaling with h^2 was most of the answers' change with the step)
    touching = g * h * h * settings.touching_scale
    _body_trig(qm, trig)
    for c in range(nc):
        gap, on_face = _contact_row(
            qm, trig, c, cand_a, cand_b, cand_pt, cand_face, G, n_act, n_dof
        )
        if on_face and (
            gap <= 0.0
            or (cand_b[c] >= 0 and gap <= touching and _normal_velocity(G, n_act, vfree) < 0.0)
        ):
            act[n_act] = c
            mu_act[n_act] = cand_mu[c]
            if not was_active[c] and _normal_velocity(G, n_act, v) < -v_impact:
                closed = True
            n_act += 1
    for k in range(forces.size):
        forces[k] = 0.0
    if n_act > 0:
        m2 = 2 * n_act
        _contact_problem(G, minv, vfree, v, act, cand_a, cand_b, n_act, nb, bvec, umin, W)
        for j in range(n_act):
            if e_n > 0.0 and umin[2 * j] < 0.0:
                bvec[2 * j] += e_n * umin[2 * j]
            c = act[j]
            P[2 * j] = P_prev[c, 0] if was_active[c] else 0.0
            P[2 * j + 1] = P_prev[c, 1] if was_active[c] else 0.0
        sweeps = FAST_GS_ITERATIONS if outcome_only else GS_ITERATIONS
        it = _solve_contacts(W, bvec, P, mu_act, n_act, settings.tol, sweeps)
        if it >= sweeps and not _active_set_work(
            W,
            bvec,
            P,
            mu_act,
            n_act,
            outcome_only,
            scratch.as_status,
            scratch.as_sign,
            scratch.as_A,
            scratch.as_rhs,
            scratch.as_x,
            scratch.as_lu,
        ):
            it += _solve_contacts(W, bvec, P, mu_act, n_act, settings.tol, settings.max_iter)
        tallies[3] = max(tallies[3], it)
        # vnew += M^-1 G^T P, each dof's sum over the rows in order, the rows' zero entries
        # (the dofs of bodies the contact does not touch) left out
        for k in range(n_dof):
            impulse_sum[k] = 0.0
        for r in range(m2):
            c = act[r // 2]
            for i in range(nb):
                if i == cand_a[c] or i == cand_b[c]:
                    for k in range(3 * i, 3 * i + 3):
                        impulse_sum[k] += G[r, k] * P[r]
        for k in range(n_dof):
            vnew[k] += minv[k] * impulse_sum[k]
        # the dissipated energy and the contact forces: histories only
        for j in range(0 if outcome_only else n_act):
            un = 0.0
            ut = 0.0
            for k in range(n_dof):
                un += G[2 * j, k] * vnew[k]
                ut += G[2 * j + 1, k] * vnew[k]
            tallies[0] -= 0.5 * (
                P[2 * j] * (un + umin[2 * j]) + P[2 * j + 1] * (ut + umin[2 * j + 1])
            )
            c = act[j]
            if cand_kind[c] == CONTACT_BASE:
                forces[2 + 2 * cand_a[c]] += P[2 * j] / h
                forces[3 + 2 * cand_a[c]] += P[2 * j + 1] / h
            else:
                forces[0] += P[2 * j] / h
                forces[1] += P[2 * j + 1] / h
    for i in range(nb):
        tallies[1] -= mass[i] * ag * 0.5 * (v[3 * i] + vnew[3 * i]) * h
        tallies[1] -= mass[i] * av * 0.5 * (v[3 * i + 1] + vnew[3 * i + 1]) * h
    # impacts: a base corner closing, approaching, on the other side of its body from the
    # corner it last pivoted on (the step whose impulse switches the pivot)
    for i in range(nb):
        n_base[i] = 0
    for j in range(n_act):
        c = act[j]
        if cand_kind[c] == CONTACT_BASE and P[2 * j] > 0.0:
            n_base[cand_a[c]] += 1
    for j in range(n_act):
        c = act[j]
        if cand_kind[c] != CONTACT_BASE or P[2 * j] <= 0.0:
            continue
        i = cand_a[c]
        side = 1 if cand_pt[c, 0] > 0.0 else -1
        if (
            not was_active[c]
            and umin[2 * j] < 0.0
            and armed[i]
            and pivot_side[i] != 0
            and side != pivot_side[i]
        ):
            n_imp = int(tallies[2])
            if n_imp < impacts.shape[0]:
                impacts[n_imp, 0] = tm
                impacts[n_imp, 1] = i
                impacts[n_imp, 2] = -v[3 * i + 2]
                impacts[n_imp, 3] = -vnew[3 * i + 2]
            tallies[2] += 1.0
            armed[i] = False
        if n_base[i] == 1 or not was_active[c]:
            pivot_side[i] = side
    for i in range(nb):
        if abs(qm[3 * i + 2]) > impact_tol:
            armed[i] = True
    for c in range(nc):
        was_active[c] = False
    for j in range(n_act):
        c = act[j]
        was_active[c] = True
        P_prev[c, 0] = P[2 * j]
        P_prev[c, 1] = P[2 * j + 1]
    for k in range(n_dof):
        q[k] = qm[k] + 0.5 * h * vnew[k]
        v[k] = vnew[k]
    if not closed:  # a contact that will be closed at the end of the step closes in it
        _body_trig(q, trig)
        for c in range(nc):
            if was_active[c]:
                continue
            gap, on_face = _contact_row(
                q, trig, c, cand_a, cand_b, cand_pt, cand_face, G, nc - 1, n_dof
            )
            if on_face and gap <= 0.0 and _normal_velocity(G, nc - 1, v) < -v_impact:
                closed = True
                break
    return closed


@njit(cache=True)
def simulate(q, v, bodies, contacts, collars, ground, settings, out, impacts):
    """Advance the bodies settings.n_steps of size settings.h from t = 0 (q, v updated in
    place) under ``ground`` (a :class:`Ground`): the column is ``bodies``, ``contacts`` and
    ``collars`` (:class:`Bodies`, :class:`Contacts`, :class:`Collars`), the run's settings a
    :class:`Settings`.

    A step in which a contact closes is done again as ``refine`` steps of h / refine: the
    impact then happens within h / refine of its time, on the geometry of that instant
    (Moreau-Jean alone is first order at impacts; between them it is second order).

    out rows every out_every steps (row 0: the initial state); impacts rows (t, body,
    theta' before, theta' after; theta = -phi) at each impact: a base corner that closes
    approaching the ground on the other side from the corner its body last pivoted on, once
    |theta| has exceeded impact_tol since the last impact.
    free_halves: judge each half alone for overturning (cracked column without collars).
    barrier: the least mechanical energy (J above rest) any part needs to overturn; with
    early_exit the run stops as settled once the ground is still (after ground.end), the
    energy is below it and every body stands within its toes.
    outcome_only: the contacts' active-set solve by Gaussian elimination (_active_set's gauss),
    tried after FAST_GS_ITERATIONS Gauss-Seidel sweeps; and a step is skipped (the positions
    kept, the velocities, the contact solver's round-off at rest, set to zero) while the
    column is at rest (:func:`_at_rest` after two steps in a row) and the ground
    acceleration at the step's midpoint lies within
    the range of those at which a full step has already taken it from rest to rest since it
    came to rest: the set of ground accelerations at which rest solves a step's contact problem
    (the impulses in their friction cones balancing gravity, collars and the ground's body
    force, all linear in it) is convex, an interval, so rest solves the skipped steps too;
    without vertical ground motion only. The skipped steps' contact forces are not updated
    (no history with it).
    stop_decided (with outcome_only): after the ground motion, every 64 steps, the run stops
    (status SETTLED) once no answer can change any more (:func:`_decided`: the peak |theta|,
    the collars' largest utilisation, the impacts (with impacts_needed) and overturning stay
    what they are).
    energy_scale: J, for the blow-up check. collars.limits[c] = (A, W, f_y, H or -1) of each
    collar (MultibodyColumn.col_limits): the largest utilisation (|N|/A + max|M|/W) / f_y, that
    stress capped at f_y + H alpha for a plastic collar, over the steps' midpoints is returned.

    Returns (status, steps done, rows written, impacts, overturn reason (UNSTABLE_STATE or
    UNSTABLE_COLLAR for an UNSTABLE run), overturn time, peak
    |theta| (rad) of each body as a 2-vector, most solver iterations in a step, largest collar
    utilisation, largest collar plastic strain, collar plastic work)."""
    mass, half = bodies.mass, bodies.half
    col_limits = collars.limits
    h, n_steps, refine = settings.h, settings.n_steps, settings.refine
    early_exit, impact_tol = settings.early_exit, settings.impact_tol
    nb = mass.size
    n_dof = 3 * nb
    scratch = new_scratch(nb, contacts.a.size, collars.a.size, collars.state_size)
    state = new_step_state(nb, contacts.a.size, impacts)
    col_out = scratch.col_out
    col_state = scratch.col_state
    P_prev, was_active, pivot_side, armed, tallies, forces, _ = state
    saved_col = col_state.copy()
    max_plastic = 0.0
    no_force = np.zeros(0)
    for i in range(nb):
        if abs(q[3 * i + 2]) > impact_tol:  # released tilted: pivoting on the low side
            pivot_side[i] = 1 if q[3 * i + 2] < 0.0 else -1
            armed[i] = True
    saved = (
        q.copy(),
        v.copy(),
        P_prev.copy(),
        was_active.copy(),
        pivot_side.copy(),
        armed.copy(),
        tallies.copy(),
    )
    peak = np.zeros(2)
    max_util = 0.0
    skip_rest = settings.outcome_only and ground.params[5] == 0.0
    stop_decided = settings.outcome_only and settings.stop_decided
    least, offset = _collar_least_energy(collars)
    if offset < 0.0:  # a collar that is not elastic: its energy is not a bound
        stop_decided = False
    base_corners = np.zeros(nb, dtype=np.int64)
    for c in range(contacts.a.size):
        if contacts.kind[c] == CONTACT_BASE:
            base_corners[contacts.a[c]] += 1
    rest_steps = 0  # full steps in a row that ended at rest
    rest_low = 1.0  # ground accelerations (m/s^2) at which a step went from rest to rest
    rest_high = -1.0
    n_rows = 0
    status = FINISHED
    reason = OVER_NONE
    t_over = -1.0
    if out.shape[0] < 1 or out.shape[1] != history_columns(nb, collars.a.size):
        # _write_row does not check its indices: a narrower out would corrupt the heap
        raise ValueError("simulate: out must have history_columns(bodies, collars) columns")
    _write_row(out, n_rows, 0.0, q, v, bodies, collars, col_out, no_force, state, col_state)
    n_rows += 1
    step = 0
    for step in range(1, n_steps + 1):
        t = (step - 1) * h
        a_mid = ground_acceleration(t + 0.5 * h, ground) if skip_rest else 0.0
        skipped = skip_rest and rest_steps >= 2 and rest_low <= a_mid <= rest_high
        if skipped:
            v[:] = 0.0  # rest: its velocities are the contact solver's round-off
        elif refine > 1:
            saved[0][:] = q
            saved[1][:] = v
            saved[2][:] = P_prev
            saved[3][:] = was_active
            saved[4][:] = pivot_side
            saved[5][:] = armed
            saved[6][:] = tallies
            saved_col[:] = col_state
        # the step whole, or again as refine substeps if a contact closed in it (or not at all
        # where rest solves it: outcome_only)
        substeps = 0 if skipped else 1
        sub = 0
        while sub < substeps:
            hs = h / substeps
            closed = _step(
                t + sub * hs, hs, q, v, bodies, contacts, collars, ground, settings, scratch, state
            )
            sub += 1
            if closed and substeps == 1 and refine > 1:
                q[:] = saved[0]
                v[:] = saved[1]
                P_prev[:] = saved[2]
                was_active[:] = saved[3]
                pivot_side[:] = saved[4]
                armed[:] = saved[5]
                tallies[:] = saved[6]
                col_state[:] = saved_col
                substeps = refine
                sub = 0
        if skip_rest and not skipped:
            if substeps == 1 and _at_rest(v, scratch.n_base, base_corners, half):
                if rest_steps == 1:
                    rest_low = rest_high = a_mid
                elif rest_steps > 1:
                    rest_low = min(rest_low, a_mid)
                    rest_high = max(rest_high, a_mid)
                rest_steps += 1
            else:
                rest_steps = 0
        t_new = step * h
        for c in range(col_limits.shape[0]):
            stress = (
                abs(col_out[c, 0]) / col_limits[c, 0]
                + max(abs(col_out[c, 1]), abs(col_out[c, 2])) / col_limits[c, 1]
            )
            if collars.props[c, 5 + LAW_KIND] == FIBRE:  # its largest fibre stress
                stress = col_state[c, FIBRE_STRESS]
            elif col_limits[c, 3] >= 0.0:  # a plastic collar: its fibres on the hardening line
                stress = min(stress, col_limits[c, 2] + col_limits[c, 3] * col_state[c, 1])
            max_util = max(max_util, stress / col_limits[c, 2])
            max_plastic = max(max_plastic, abs(col_out[c, 4]))
        finite = True
        for k in range(n_dof):
            if not math.isfinite(q[k]) or not math.isfinite(v[k]):
                finite = False
        if not finite:
            status = UNSTABLE
            reason = UNSTABLE_STATE
            for c in range(col_out.shape[0]):
                for k in range(col_out.shape[1]):
                    if not math.isfinite(col_out[c, k]):
                        reason = UNSTABLE_COLLAR
            break
        for i in range(nb):
            peak[min(i, 1)] = max(peak[min(i, 1)], abs(q[3 * i + 2]))
        if nb == 1:
            peak[1] = peak[0]
        # overturning
        for i in range(nb):
            if abs(q[3 * i + 2]) >= 0.5 * math.pi:
                reason = OVER_HALF_PI
        if reason == OVER_NONE and t_new > ground.end:
            reason = _falling(q, v, mass, half, settings.free_halves)
        if reason != OVER_NONE:
            status = OVERTURNED
            t_over = t_new
        write = status != FINISHED or step % settings.out_every == 0 or step == n_steps
        mech = 0.0
        if write or early_exit or step % 64 == 0:
            mech = _mechanical(q, v, bodies, collars, col_out, no_force, col_state)
            if not (abs(mech) <= 1e3 * settings.energy_scale + 1e3 * abs(tallies[1])):
                status = UNSTABLE
                reason = UNSTABLE_STATE
        if write and n_rows < out.shape[0]:
            _write_row(
                out, n_rows, t_new, q, v, bodies, collars, col_out, no_force, state, col_state
            )
            n_rows += 1
        if status != FINISHED:
            break
        if early_exit and t_new > ground.end and mech < settings.barrier and _upright(q, half):
            status = SETTLED
            break
        if (
            stop_decided
            and step % 64 == 0
            and t_new > ground.end
            and _decided(
                q,
                mech,
                max(peak[0], peak[1]),
                max_util,
                armed,
                bodies,
                collars,
                settings,
                least,
                offset,
            )
        ):
            status = SETTLED
            break
    plastic_work = 0.0
    for c in range(collars.a.size):
        plastic_work += col_state[c, 2]
    return (
        status,
        step,
        n_rows,
        int(tallies[2]),
        reason,
        t_over,
        peak,
        int(tallies[3]),
        max_util,
        max_plastic,
        plastic_work,
    )


@njit(cache=True)
def _potential(q, mass, half, g, i):
    """Gravity and top-load potential of body i above its rest (J): its centre of mass rests
    at half[i, 1], the top's centre (0, half[i, 1]) in its frame at 2 half[i, 1]."""
    hh = half[i, 1]
    e = mass[i] * g * (q[3 * i + 1] - hh)
    load = half[i, 2]
    if load != 0.0:
        e += load * (q[3 * i + 1] + hh * math.cos(q[3 * i + 2]) - 2.0 * hh)
    return e


@njit(cache=True)
def _mechanical(q, v, bodies, collars, col_out, no_force, col_state):
    """Kinetic + gravity and top load (above rest) + collar energy (J)."""
    mass, inertia, half, g = bodies.mass, bodies.inertia, bodies.half, bodies.g
    e = 0.0
    for i in range(mass.size):
        e += 0.5 * mass[i] * (v[3 * i] ** 2 + v[3 * i + 1] ** 2)
        e += 0.5 * inertia[i] * v[3 * i + 2] ** 2
        e += _potential(q, mass, half, g, i)
    if collars.a.size:
        e += collar_forces(
            q, collars.a, collars.b, collars.r, collars.props, no_force, col_out, col_state, False
        )
    return e


@njit(cache=True)
def _write_row(out, row, t, q, v, bodies, collars, col_out, no_force, state, col_state):
    """History row ``row`` at time t: the bodies' state, the energies, state's tallies and
    forces, and per collar its outputs and recorded plastic state (the columns of N_BODY_COLS,
    N_TAIL and N_COLLAR_COLS)."""
    mass, inertia, half, g = bodies.mass, bodies.inertia, bodies.half, bodies.g
    tallies, forces = state.tallies, state.forces
    nb = mass.size
    out[row, OUT_T] = t
    kinetic = 0.0
    gravity = 0.0
    for i in range(nb):
        for k in range(3):
            out[row, 1 + N_BODY_COLS * i + k] = q[3 * i + k]
            out[row, 1 + N_BODY_COLS * i + 3 + k] = v[3 * i + k]
        kinetic += 0.5 * mass[i] * (v[3 * i] ** 2 + v[3 * i + 1] ** 2)
        kinetic += 0.5 * inertia[i] * v[3 * i + 2] ** 2
        gravity += _potential(q, mass, half, g, i)
    collar = 0.0
    if collars.a.size:
        collar = collar_forces(
            q, collars.a, collars.b, collars.r, collars.props, no_force, col_out, col_state, False
        )
    k0 = 1 + N_BODY_COLS * nb
    out[row, k0] = kinetic
    out[row, k0 + 1] = gravity
    out[row, k0 + 2] = collar
    out[row, k0 + 3] = tallies[0]
    out[row, k0 + 4] = tallies[1]
    for k in range(forces.size):
        out[row, k0 + 5 + k] = forces[k]
    k1 = k0 + 5 + forces.size  # then per collar its outputs and its state's RECORDED entries
    for c in range(col_state.shape[0]):
        for k in range(OUT_SIZE):
            out[row, k1 + N_COLLAR_COLS * c + k] = col_out[c, k]
        for k in range(N_RECORDED):
            out[row, k1 + N_COLLAR_COLS * c + OUT_SIZE + k] = col_state[c, RECORDED[k]]


@njit(cache=True)
def _at_rest(v, n_base, base_corners, half):
    """Every body at rest on the ground: each of its base corners pushing (its impulse in the
    last step positive) and no point of it moving faster than REST_VELOCITY (a rocking body
    pivots on one corner; a swing's turning point has both corners down only at its impact)."""
    for i in range(half.shape[0]):
        if n_base[i] < base_corners[i]:
            return False
        reach = math.hypot(half[i, 0], half[i, 1])
        if (
            abs(v[3 * i]) + abs(v[3 * i + 2]) * reach > REST_VELOCITY
            or abs(v[3 * i + 1]) + abs(v[3 * i + 2]) * reach > REST_VELOCITY
        ):
            return False
    return True


DECIDED_MARGIN = 0.5
"""A run stops once its free energy is below DECIDED_MARGIN of every threshold of
:func:`_decided`: the factor covers what the continuous argument leaves out (the scheme's own
energy error, 1e-5 of the rocking energy over a whole run and 1e-10 J over a quiet tail,
measured)."""


@njit(cache=True)
def _collar_least_energy(collars):
    """Per elastic collar c, least[c] (J/Pa^2) such that its elastic energy plus
    P^2 / (2 EA/L) is at least least[c] (u f_y)^2 whenever its utilisation (|N|/A + max|M_i|/W)
    / f_y is u; and offset = sum of P^2 / (2 EA/L) (J), the most energy its pretensions P can
    give back. The resultant law's energy is (N^2 - P^2) / (2 EA/L) + (M1^2 - M1 M2 + M2^2) /
    (6 EI'/L0) (colonna.core.collar_law.resultant_local_law), whose least value at max|M_i| =
    M is M^2 / (8 EI'/L0) (M2 = M1 / 2); the least of N^2 / (2 k_a) + M^2 / (8 k_b) on |N| / A
    + M / W = s is s^2 / (2 (k_a / A^2 + 4 k_b / W^2)) (Lagrange). offset = -1 if a collar is
    not elastic (a fibre section or a plastic law: no such bound)."""
    n = collars.a.size
    least = np.zeros(n)
    offset = 0.0
    for c in range(n):
        ka = collars.props[c, 0]
        kb = collars.props[c, 1]
        area = collars.limits[c, 0]
        modulus = collars.limits[c, 1]
        if collars.props[c, 5 + LAW_KIND] == FIBRE or collars.limits[c, 3] >= 0.0 or ka <= 0.0:
            return least, -1.0
        least[c] = 0.5 / (ka / area**2 + 4.0 * kb / modulus**2)
        offset += 0.5 * collars.props[c, 2] ** 2 / ka
    return least, offset


@njit(cache=True)
def _least_potential(mass, half, g, i, x):
    """Body i's least gravity and top-load potential above rest (J) at |phi| = x (<= pi/2)
    with its base corners on or above the ground: its centroid stands at least h cos x +
    b sin x = R cos(alpha - x) high (the top load's point h cos x above it). It is 0 at x = 0,
    rises to the body's overturning energy at its critical angle and falls after it."""
    b = half[i, 0]
    hh = half[i, 1]
    y = hh * math.cos(x) + b * math.sin(x)
    return mass[i] * g * (y - hh) + half[i, 2] * (y + hh * math.cos(x) - 2.0 * hh)


@njit(cache=True)
def _decided(q, mech, peak, max_util, armed, bodies, collars, settings, least, offset):
    """After the ground motion: True once no answer of the run can change any more.

    The argument: with the ground still, the mechanical energy E = kinetic + gravity and top
    load + collars (``mech``, J above rest) does not grow (impacts and friction dissipate,
    elastic collars store). Its parts are bounded below: kinetic >= 0; a collar's energy >=
    -P^2 / (2 EA/L) (``offset`` sums these) and >= least[c] (u f_y)^2 - P^2 / (2 EA/L) at
    utilisation u (:func:`_collar_least_energy`); body i's potential >= V_i(|phi_i|)
    (:func:`_least_potential`), >= 0 while |phi_i| <= x for any x with V_i(x) >= 0 (V_i rises
    then falls). Let F = E + offset (plus twice the weight times the corners' present
    penetration of the ground: the scheme lets a contact drift in by g h^2 at most, which it
    could give back) and x = the largest |theta| so far. If F < V_i(x) for every body, no
    body reaches |phi| = x again (at the first time one did, every body would lie within x,
    every part of E be >= 0 and its potential alone >= V_i(x) > F): the peak |theta| stays.
    The same with x = impact_tol and no body armed: none is armed again, so no impact is
    counted (with settings.impacts_needed only: a caller that does not use the impact count,
    the fragility, leaves this threshold, the least of them by far on a slender column,
    1e-4 alpha, and the wait for no body to be armed out). If F < least[c] (u_max f_y)^2 for
    every collar, none reaches the largest utilisation so far. F below the least overturning
    barrier and every body within its toes (:func:`_upright`): nothing overturns (as
    early_exit). Each threshold is used with DECIDED_MARGIN."""
    mass, half, g = bodies.mass, bodies.half, bodies.g
    free = mech + offset
    limit = settings.barrier
    impacts = settings.impacts_needed
    for i in range(mass.size):
        if impacts and armed[i]:
            return False
        c = math.cos(q[3 * i + 2])
        s = math.sin(q[3 * i + 2])
        lowest = q[3 * i + 1] - half[i, 1] * c - half[i, 0] * abs(s)
        if lowest < 0.0:
            free -= 2.0 * (mass[i] * g + half[i, 2]) * lowest
        limit = min(limit, _least_potential(mass, half, g, i, peak))
        if impacts:
            limit = min(limit, _least_potential(mass, half, g, i, settings.impact_tol))
    for c in range(least.size):
        limit = min(limit, least[c] * (max_util * collars.limits[c, 2]) ** 2)
    return limit > 0.0 and free < DECIDED_MARGIN * limit and _upright(q, half)


@njit(cache=True)
def _upright(q, half):
    """Every body's centre of mass between its own base corners: with less energy than the
    least overturning barrier, no part can then reach a toe (one past its toe falls with
    less potential energy than the barrier)."""
    for i in range(half.shape[0]):
        c = math.cos(q[3 * i + 2])
        s = math.sin(q[3 * i + 2])
        x_a = q[3 * i] - c * half[i, 0] + s * half[i, 1]
        x_b = q[3 * i] + c * half[i, 0] + s * half[i, 1]
        if not min(x_a, x_b) < q[3 * i] < max(x_a, x_b):
            return False
    return True


@njit(cache=True)
def _falling(q, v, mass, half, free_halves):
    """After the ground motion: the column's centre of mass past its outer toe moving outward
    (nothing restores it: collars and crack contact are internal), or, for free halves, a
    half's past its own outer toe moving outward (the rule of the FEM model)."""
    nb = mass.size
    total = 0.0
    xc = 0.0
    vc = 0.0
    toe_left = 1e300
    toe_right = -1e300
    for i in range(nb):
        total += mass[i]
        xc += mass[i] * q[3 * i]
        vc += mass[i] * v[3 * i]
        c = math.cos(q[3 * i + 2])
        s = math.sin(q[3 * i + 2])
        for sx in (-1.0, 1.0):
            x = q[3 * i] + c * sx * half[i, 0] + s * half[i, 1]
            toe_left = min(toe_left, x)
            toe_right = max(toe_right, x)
    xc /= total
    vc /= total
    if (xc > toe_right and vc > 0.0) or (xc < toe_left and vc < 0.0):
        return OVER_COLUMN
    if free_halves and nb == 2:
        for i in range(2):
            c = math.cos(q[3 * i + 2])
            s = math.sin(q[3 * i + 2])
            sx = -1.0 if i == 0 else 1.0
            toe = q[3 * i] + c * sx * half[i, 0] + s * half[i, 1]
            if sx * (q[3 * i] - toe) > 0.0 and sx * v[3 * i] > 0.0:
                return OVER_HALF
    return OVER_NONE


@njit(cache=True, parallel=True)
def spectrum_modes(
    q0, bodies, contacts, collars, omegas, amplitudes, uplift, cosine, free_time, settings
):
    """Mode code (0 safe, 1 after impact, 2 without impact), the peak |theta| (rad) and the
    largest collar utilisation of every (amplitude, omega) pair: sine pulses phased to start
    rocking at t = 0 (or cosine pulses), amplitude a_p = amplitudes[i] * uplift (m/s^2),
    Omega = omegas[j] (rad/s), each run from rest at q0 to free_time (s) after its end.

    settings: those of :func:`simulate`, with h the largest step (a pulse's is at most 1/400 of
    its period); n_steps and out_every are each pulse's own (no history rows kept)."""
    na = amplitudes.size
    no = omegas.size
    codes = np.zeros((na, no), dtype=np.int8)
    peaks = np.zeros((na, no))
    status_out = np.zeros((na, no), dtype=np.int8)
    utilisation = np.zeros((na, no))
    nb = bodies.mass.size
    for idx in prange(na * no):
        i = idx // no
        j = idx % no
        amp = amplitudes[i] * uplift
        om = omegas[j]
        gpar = np.zeros(6)
        gpar[0] = amp
        gpar[1] = om
        if cosine:
            gpar[2] = 0.5 * math.pi
            gpar[3] = 2.0 * math.pi / om
        else:
            phase = math.asin(min(1.0, uplift / abs(amp)))
            gpar[2] = phase
            gpar[3] = (2.0 * math.pi - phase) / om
        t_end = gpar[3]
        h = min(settings.h, (2.0 * math.pi / om) / 400.0)
        n_steps = int(math.ceil((t_end + free_time) / h))
        run = Settings(
            h,
            n_steps,
            settings.refine,
            settings.e_n,
            n_steps + 1,
            settings.free_halves,
            settings.barrier,
            settings.early_exit,
            settings.impact_tol,
            settings.energy_scale,
            settings.tol,
            settings.max_iter,
            settings.outcome_only,
            settings.stop_decided,
            settings.impacts_needed,
            settings.touching_scale,
        )
        ground = Ground(GROUND_HARMONIC, gpar, np.zeros(1), np.zeros(1), t_end)
        q = q0.copy()
        v = np.zeros_like(q0)
        out = np.zeros((1, history_columns(nb, collars.a.size)))
        impacts = np.zeros((1, 4))
        status, steps, rows, n_imp, reason, t_over, peak, it, util, _pl, _pw = simulate(
            q, v, bodies, contacts, collars, ground, run, out, impacts
        )
        status_out[i, j] = status
        utilisation[i, j] = util
        if status == OVERTURNED:
            codes[i, j] = 1 if n_imp > 0 else 2
            peaks[i, j] = 0.5 * math.pi
        else:
            peaks[i, j] = max(peak[0], peak[1])
    return codes, peaks, status_out, utilisation
