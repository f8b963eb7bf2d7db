"""Compiled (numba) kernels of the explicit contact model. Private: use :mod:`fem.solver`.

State: current nodal positions x and velocities v (interleaved, 2 per node), in the ground frame.

Elastic forces use a co-rotational frame per body: the stone bodies are stiff, so their motion is a
large rigid rotation plus a small strain. With the body's mass-weighted centroid c and best-fit
rotation phi (2D polar decomposition), the local displacement is u = R(-phi)(x - c) - (X - C) and
the force is f = R(phi) K u. Linear small-strain elasticity applied to the raw displacement would
see a rocking rotation theta as a strain of theta^2 / 2 (250 MPa at 0.1 rad in marble).

Contact is penalty based with Coulomb friction in incremental form (trial tangential force, then
return to the cone |f_t| <= mu f_n) and a contact damping on the normal approach velocity. The cone
uses the normal force low-pass filtered over ~1 ms: with the instantaneous force, friction couples
the contact's vertical vibration to the horizontal motion and near the slip limit the base flutters
(a mode-coupling instability of penalty contact with friction).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..core.collar_law import frame_local_law

# fast-math without the no-NaN / no-Inf assumptions: the blow-up check must keep its meaning
SAFE_FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


@njit(cache=True)
def _filter(state, k, value, blend):
    """Exponential low-pass filter of a contact's normal force, started at the force itself
    when the contact closes (so an impact gets its full friction at once)."""
    if state[k] == 0.0:
        state[k] = value
    else:
        state[k] += blend * (value - state[k])
    return state[k]


@njit(cache=True)
def _coulomb(force, kt, vt, dt, limit):
    """Incremental Coulomb friction: the trial force force - k_t v_t dt, returned to the cone
    |f| <= limit. Returns (tangential force, dissipated power): the cone force times the
    plastic slip (trial - cone force) / k_t, per unit time."""
    trial = force - kt * vt * dt
    if abs(trial) <= limit:
        return trial, 0.0
    slip_force = limit if trial > 0.0 else -limit
    power = slip_force * (trial - slip_force) / (kt * dt) if dt > 0.0 else 0.0
    return slip_force, power


@njit(cache=True, fastmath=SAFE_FASTMATH)
def _penalty_contact(k, gap, vn, vt, kn, kt, cn, mu, dt, ft, normal_force, fn_filtered, blend):
    """One closed contact (gap < 0, normal velocity vn, tangential vt): damped penalty normal
    force (never tensile), Coulomb friction on the filtered cone. Updates the state of contact
    k; returns (normal force, tangential force, elastic energy, dissipated power)."""
    fn_el = -kn[k] * gap
    fn = max(fn_el - cn[k] * vn, 0.0)
    normal_force[k] = fn
    cone = _filter(fn_filtered, k, fn, blend)
    trial, power = _coulomb(ft[k], kt[k], vt, dt, mu * cone)
    ft[k] = trial
    power += (fn - fn_el) * (-vn)  # damping, or the clipped tensile part
    energy = 0.5 * kn[k] * gap * gap + 0.5 * trial * trial / kt[k]
    return fn, trial, energy, power


@njit(cache=True, fastmath=SAFE_FASTMATH)
def base_contact(x, v, nodes, kn, kt, cn, mu, dt, ft, f, normal_force, fn_filtered, blend):
    """Base nodes against the rigid ground y = 0. ft: tangential force per node (state);
    fn_filtered: the normal force low-pass filtered for the friction cone (state; blend =
    dt / tau, 1 for no filter). Returns (elastic contact energy, dissipated power)."""
    energy = 0.0
    power = 0.0
    for k in range(nodes.size):
        i = nodes[k]
        gap = x[2 * i + 1]
        if gap >= 0.0:
            ft[k] = 0.0
            normal_force[k] = 0.0
            fn_filtered[k] = 0.0
            continue
        fn, trial, e, p = _penalty_contact(
            k, gap, v[2 * i + 1], v[2 * i], kn, kt, cn, mu, dt, ft, normal_force, fn_filtered, blend
        )
        f[2 * i] += trial
        f[2 * i + 1] += fn
        energy += e
        power += p
    return energy, power


@njit(cache=True, fastmath=SAFE_FASTMATH)
def crack_contact(
    x,
    v,
    slaves,
    masters,
    outward_sign,
    kn,
    kt,
    cn,
    mu,
    dt,
    seg,
    ft,
    f,
    normal_force,
    fn_filtered,
    blend,
):
    """Node-to-segment contact of the slave face's nodes on the master face (ordered by height).

    outward_sign: +1 if the master face's outward normal is the segment direction turned
    clockwise (the left body's crack face), -1 otherwise. seg[k]: master segment last used by
    slave k (state, -1: none). Returns (elastic energy, dissipated power)."""
    energy = 0.0
    power = 0.0
    n_seg = masters.size - 1
    for k in range(slaves.size):
        s = slaves[k]
        sx = x[2 * s]
        sy = x[2 * s + 1]
        j0 = seg[k] if seg[k] >= 0 else 0
        # the segment used last step nearly always still holds the projection; else search
        # outward from it, alternating up and down
        found = -1
        xi = 0.0
        for step in range(2 * n_seg):
            j = j0 + (step + 1) // 2 if step % 2 == 0 else j0 - (step + 1) // 2
            if j < 0 or j >= n_seg:
                if j0 + step // 2 >= n_seg and j0 - step // 2 < 0:
                    break
                continue
            a = masters[j]
            b = masters[j + 1]
            dx = x[2 * b] - x[2 * a]
            dy = x[2 * b + 1] - x[2 * a + 1]
            t = ((sx - x[2 * a]) * dx + (sy - x[2 * a + 1]) * dy) / (dx * dx + dy * dy)
            if -1e-12 <= t <= 1.0 + 1e-12:
                found = j
                xi = min(max(t, 0.0), 1.0)
                break
        if found < 0:
            seg[k] = -1
            ft[k] = 0.0
            normal_force[k] = 0.0
            fn_filtered[k] = 0.0
            continue
        seg[k] = found
        a = masters[found]
        b = masters[found + 1]
        dx = x[2 * b] - x[2 * a]
        dy = x[2 * b + 1] - x[2 * a + 1]
        length = math.sqrt(dx * dx + dy * dy)
        tx = dx / length
        ty = dy / length
        nx = outward_sign * ty
        ny = -outward_sign * tx
        px = x[2 * a] + xi * dx
        py = x[2 * a + 1] + xi * dy
        gap = (sx - px) * nx + (sy - py) * ny
        if gap >= 0.0:
            ft[k] = 0.0
            normal_force[k] = 0.0
            fn_filtered[k] = 0.0
            continue
        rvx = v[2 * s] - ((1.0 - xi) * v[2 * a] + xi * v[2 * b])
        rvy = v[2 * s + 1] - ((1.0 - xi) * v[2 * a + 1] + xi * v[2 * b + 1])
        fn, trial, e, p = _penalty_contact(
            k,
            gap,
            rvx * nx + rvy * ny,
            rvx * tx + rvy * ty,
            kn,
            kt,
            cn,
            mu,
            dt,
            ft,
            normal_force,
            fn_filtered,
            blend,
        )
        energy += e
        power += p
        fx = fn * nx + trial * tx
        fy = fn * ny + trial * ty
        f[2 * s] += fx
        f[2 * s + 1] += fy
        f[2 * a] -= (1.0 - xi) * fx
        f[2 * a + 1] -= (1.0 - xi) * fy
        f[2 * b] -= xi * fx
        f[2 * b + 1] -= xi * fy
    return energy, power


@njit(cache=True)
def _face_angle(x, below, above):
    return math.atan2(x[2 * above + 1] - x[2 * below + 1], x[2 * above] - x[2 * below])


@njit(cache=True, fastmath=SAFE_FASTMATH)
def collar_forces(x, collars, props, out, f, state, commit):
    """Co-rotational Euler-Bernoulli frame elements, elastic or elastoplastic (N and M).

    collars[c] = (left node, left face below, left face above, right node, right below, right
    above); props[c] = (EA/L, EI'/L0, pretension, L0, chord angle0, left face angle0,
    right face angle0, then the law row of colonna.core.collar.Collar.law: N_y, E A, H A, M_p,
    1 / (E W), h / (2 L_p), eps_u).
    out[c] = (N, M1, M2, elastic energy, plastic strain, extreme-fibre strain, end rotations
    th1, th2 relative to the chord). End rotations are the rotations of the face segments
    (below -> above); their moments enter as force couples on those nodes.

    Plasticity (colonna.core.collar_law.frame_local_law: axial with isotropic linear hardening,
    end hinges on the N-M interaction surface): state[c] = (plastic elongation s_p (m),
    accumulated plastic strain, plastic work (J), hinge rotations (rad), largest fibre
    strain, fractured); N = pretension +
    EA/L (stretch - s_p), |N| <= N_y + H A alpha. With commit the state is updated (a time step);
    otherwise the forces are those of the trial state. Returns (elastic energy, plastic work
    of this call)."""
    energy = 0.0
    work = 0.0
    for c in range(collars.shape[0]):
        n1 = collars[c, 0]
        n2 = collars[c, 3]
        dx = x[2 * n2] - x[2 * n1]
        dy = x[2 * n2 + 1] - x[2 * n1 + 1]
        length = math.sqrt(dx * dx + dy * dy)
        beta = math.atan2(dy, dx) - props[c, 4]
        phi1 = _face_angle(x, collars[c, 1], collars[c, 2]) - props[c, 5]
        phi2 = _face_angle(x, collars[c, 4], collars[c, 5]) - props[c, 6]
        th1 = phi1 - beta
        th2 = phi2 - beta
        work_before = state[c, 2]
        N, M1, M2, e, plastic_strain, fibre = frame_local_law(
            length - props[c, 3],
            th1,
            th2,
            props[c, 0],
            props[c, 1],
            props[c, 2],
            props[c, 7:],
            state,
            c,
            commit,
        )
        work += state[c, 2] - work_before
        out[c, 5] = fibre
        out[c, 6] = th1
        out[c, 7] = th2
        out[c, 4] = plastic_strain
        out[c, 0] = N
        out[c, 1] = M1
        out[c, 2] = M2
        out[c, 3] = e
        energy += e
        ex = dx / length
        ey = dy / length
        nx = -ey
        ny = ex
        shear = (M1 + M2) / length
        # internal force on node 1: -N e + shear n; on node 2 the opposite (f gets minus these)
        f[2 * n1] -= -N * ex + shear * nx
        f[2 * n1 + 1] -= -N * ey + shear * ny
        f[2 * n2] -= N * ex - shear * nx
        f[2 * n2 + 1] -= N * ey - shear * ny
        for side in range(2):
            M = M1 if side == 0 else M2
            below = collars[c, 1 + 3 * side]
            above = collars[c, 2 + 3 * side]
            sx = x[2 * above] - x[2 * below]
            sy = x[2 * above + 1] - x[2 * below + 1]
            ss = sx * sx + sy * sy
            # d(phi) = (-sy, sx) . d(s) / |s|^2
            f[2 * above] -= M * (-sy) / ss
            f[2 * above + 1] -= M * sx / ss
            f[2 * below] += M * (-sy) / ss
            f[2 * below + 1] += M * sx / ss
    return energy, work


# --- the explicit step, batched over states that share the model -----------------------------
#
# The arrays travel in bundles (named tuples, which numba compiles as records of arrays):
# the model's, read-only and shared by every state of a batch, and the states', one row per
# state (B rows). A batch is replicas of one run perturbed at round-off level (an ensemble, see
# fem.solver.run_ensemble) or different ground motions on one mesh: one pass through the
# stiffness serves all of them.

Stiffness = namedtuple("Stiffness", ["indptr", "indices", "blocks"])
"""The stone's stiffness in block-sparse-row form, 2 x 2 blocks (one block per node pair)."""

Bodies = namedtuple(
    "Bodies", ["X", "mass", "node_body", "centroid_ref", "gravity", "order", "offsets"]
)
"""Reference positions, lumped mass per dof, body of each node, body centroids (n_bodies, 2),
gravity load per dof, and the nodes grouped by body: body b's nodes are
order[offsets[b]:offsets[b + 1]]."""

ContactPass = namedtuple("ContactPass", ["nodes", "masters", "sign", "kn", "kt", "cn"])
"""A contact pass: the base (nodes against the ground; masters and sign unused) or one crack
pass (slave nodes on the master face; see crack_contact); penalty, tangential penalty and
damping per contact node."""

ContactState = namedtuple("ContactState", ["seg", "ft", "fn", "fc"])
"""Per state (rows) and contact node: master segment last used (crack), tangential force,
normal force and its filtered value for the friction cone."""

Collars = namedtuple("Collars", ["nodes", "props"])
"""collar_forces' node table and properties."""

CollarState = namedtuple("CollarState", ["out", "plastic"])
"""Per state: collar_forces' outputs (B, n_collars, collar_law.OUT_SIZE) and plastic state
(B, n_collars, collar_law.STATE_SIZE)."""

EdgeAverage = namedtuple("EdgeAverage", ["weights", "buffer", "position", "sums", "peak"])
"""The toe resultants weights . base_fn (weights (n_edges, n_base), shared) averaged over the
last buffer.shape[2] steps: per state a ring buffer (B, n_edges, n_avg), its position (B,),
running sums (B, n_edges) and the peak of the average since the last record (B, n_edges)."""

Motion = namedtuple("Motion", ["x", "v", "frames", "tallies", "energies", "alive", "done"])
"""Per state: positions and velocities (B, n_dofs), body frames (B, n_bodies, 3: centroid x,
y and rotation), tallies (B, 2: dissipated energy, external work), energies (B, 6: strain,
base contact, crack contact, collar, gravity, kinetic), alive (B,: False stops a state) and
done (B,: steps done by the last call)."""

Scratch = namedtuple("Scratch", ["u_loc", "f_loc", "f"])
"""Work arrays: local displacements and elastic forces (n_dofs, B: a state per column, so
the block mat-vec reads each block once for all states) and external forces (B, n_dofs)."""


@njit(cache=True)
def bsr_matmat(indptr, indices, blocks, x, out):
    """out = A x for A in block-sparse-row form with 2 x 2 blocks and x of shape (n, B): one
    read of each block serves the B columns (the loop over them vectorises). One column (a
    plain run) keeps its sums in registers. Strict IEEE arithmetic (no fast-math)."""
    batch = x.shape[1]
    if batch == 1:
        for i in range(indptr.size - 1):
            a0 = 0.0
            a1 = 0.0
            for k in range(indptr[i], indptr[i + 1]):
                j = indices[k]
                x0 = x[2 * j, 0]
                x1 = x[2 * j + 1, 0]
                a0 += blocks[k, 0, 0] * x0 + blocks[k, 0, 1] * x1
                a1 += blocks[k, 1, 0] * x0 + blocks[k, 1, 1] * x1
            out[2 * i, 0] = a0
            out[2 * i + 1, 0] = a1
        return
    for i in range(indptr.size - 1):
        for r in range(batch):
            out[2 * i, r] = 0.0
            out[2 * i + 1, r] = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            a00 = blocks[k, 0, 0]
            a01 = blocks[k, 0, 1]
            a10 = blocks[k, 1, 0]
            a11 = blocks[k, 1, 1]
            for r in range(batch):
                x0 = x[2 * j, r]
                x1 = x[2 * j + 1, r]
                out[2 * i, r] += a00 * x0 + a01 * x1
                out[2 * i + 1, r] += a10 * x0 + a11 * x1


@njit(cache=True, fastmath=SAFE_FASTMATH)
def _edge_average(edge, r, base_fn):
    """Push the toe resultants of state r into its averaging buffer; keep the peak average."""
    n_avg = edge.buffer.shape[2]
    slot = edge.position[r]
    for e in range(edge.peak.shape[1]):
        resultant = 0.0
        for k in range(base_fn.size):
            resultant += edge.weights[e, k] * base_fn[k]
        edge.sums[r, e] += resultant - edge.buffer[r, e, slot]
        edge.buffer[r, e, slot] = resultant
        if slot == n_avg - 1:  # resum once per lap: no drift of the running sum
            edge.sums[r, e] = 0.0
            for j in range(n_avg):
                edge.sums[r, e] += edge.buffer[r, e, j]
        average = edge.sums[r, e] / n_avg
        if average > edge.peak[r, e]:
            edge.peak[r, e] = average
    edge.position[r] = (slot + 1) % n_avg


@njit(cache=True, fastmath=SAFE_FASTMATH)
def advance(
    n_steps,
    dt,
    mu,
    blend,
    stiffness,
    bodies,
    base,
    cracks,
    collars,
    ground_acc,
    ground_vacc,
    motion,
    base_state,
    crack_states,
    collar_state,
    edge,
    scratch,
):
    """n_steps of central differences (velocities at half steps, lumped mass) for every live
    state of a batch (motion.alive); a state whose motion stops being finite is stopped there.

    ground_acc[r, k], ground_vacc[r, k]: horizontal and vertical (upward) ground acceleration
    (m/s^2) of state r during step k, applied as the body forces -m ug'' in x and -m vg'' in y
    (ground frame). motion.tallies += (dissipated energy, external work); motion.energies gets
    (strain, base contact, crack contact, collar, gravity, kinetic) of the last step, all at
    time n (kinetic as m v(n-1/2) . v(n+1/2) / 2, the energy central differences conserve).
    cracks: two contact passes (empty ones for a solid column). The toe resultants are averaged
    over the last steps and their peak kept over every step (EdgeAverage), so that an impact
    shorter than an output interval is not missed and penalty-contact chatter faster than the
    averaging time is not taken for stress. motion.done[r]: the steps state r did.

    Per step and state: one pass for the body frames, one for the local displacements; then
    one block mat-vec for the whole batch; then per state the contact and collar forces and one
    fused pass that rotates the elastic forces back, updates velocity and position and loads
    gravity and ground force for the next step."""
    x, v, frames = motion.x, motion.v, motion.frames
    X, mass, node_body, centroid_ref, gravity = (
        bodies.X,
        bodies.mass,
        bodies.node_body,
        bodies.centroid_ref,
        bodies.gravity,
    )
    u_loc, f_loc, f = scratch.u_loc, scratch.f_loc, scratch.f
    batch = x.shape[0]
    n_nodes = node_body.size
    n_bodies = centroid_ref.shape[0]
    # reference positions relative to their body's centroid, and inverse masses
    rel = np.empty(2 * n_nodes)
    inv_mass = np.empty(n_nodes)
    for i in range(n_nodes):
        b = node_body[i]
        rel[2 * i] = X[2 * i] - centroid_ref[b, 0]
        rel[2 * i + 1] = X[2 * i + 1] - centroid_ref[b, 1]
        inv_mass[i] = 1.0 / mass[2 * i]
    cos_b = np.ones((batch, n_bodies))
    sin_b = np.zeros((batch, n_bodies))
    for r in range(batch):
        motion.done[r] = 0
        ag = ground_acc[r, 0]
        av = ground_vacc[r, 0]
        for i in range(n_nodes):
            f[r, 2 * i] = gravity[2 * i] - mass[2 * i] * ag
            f[r, 2 * i + 1] = gravity[2 * i + 1] - mass[2 * i] * av
    for step in range(n_steps):
        for r in range(batch):
            if not motion.alive[r]:
                continue
            # body frames: centroid and best-fit rotation in one pass (sum m (X - C) = 0),
            # body by body so that the sums stay in registers
            for b in range(n_bodies):
                s0 = 0.0
                s1 = 0.0
                s2 = 0.0
                s3 = 0.0
                s4 = 0.0
                for k in range(bodies.offsets[b], bodies.offsets[b + 1]):
                    i = bodies.order[k]
                    m = mass[2 * i]
                    xi = x[r, 2 * i]
                    yi = x[r, 2 * i + 1]
                    px = rel[2 * i]
                    py = rel[2 * i + 1]
                    s0 += m
                    s1 += m * xi
                    s2 += m * yi
                    s3 += m * (px * xi + py * yi)
                    s4 += m * (px * yi - py * xi)
                cx = s1 / s0
                cy = s2 / s0
                phi = math.atan2(s4, s3)
                frames[r, b, 0] = cx
                frames[r, b, 1] = cy
                frames[r, b, 2] = phi
                c = math.cos(phi)
                s = math.sin(phi)
                cos_b[r, b] = c
                sin_b[r, b] = s
                # local displacements (a column per state)
                for k in range(bodies.offsets[b], bodies.offsets[b + 1]):
                    i = bodies.order[k]
                    qx = x[r, 2 * i] - cx
                    qy = x[r, 2 * i + 1] - cy
                    u_loc[2 * i, r] = c * qx + s * qy - rel[2 * i]
                    u_loc[2 * i + 1, r] = -s * qx + c * qy - rel[2 * i + 1]
        bsr_matmat(stiffness.indptr, stiffness.indices, stiffness.blocks, u_loc, f_loc)
        for r in range(batch):
            if not motion.alive[r]:
                continue
            ag = ground_acc[r, step]
            av = ground_vacc[r, step]
            xr, vr, fr = x[r], v[r], f[r]
            # contact and collars
            e_base, p_base = base_contact(
                xr,
                vr,
                base.nodes,
                base.kn,
                base.kt,
                base.cn,
                mu,
                dt,
                base_state.ft[r],
                fr,
                base_state.fn[r],
                base_state.fc[r],
                blend,
            )
            _edge_average(edge, r, base_state.fn[r])
            e_crack = 0.0
            p_crack = 0.0
            for p in range(2):
                crack = cracks[p]
                if crack.nodes.size == 0:
                    continue
                state = crack_states[p]
                e1, p1 = crack_contact(
                    xr,
                    vr,
                    crack.nodes,
                    crack.masters,
                    crack.sign,
                    crack.kn,
                    crack.kt,
                    crack.cn,
                    mu,
                    dt,
                    state.seg[r],
                    state.ft[r],
                    fr,
                    state.fn[r],
                    state.fc[r],
                    blend,
                )
                e_crack += e1
                p_crack += p1
            e_collar, w_plastic = collar_forces(
                xr,
                collars.nodes,
                collars.props,
                collar_state.out[r],
                fr,
                collar_state.plastic[r],
                True,
            )
            # fused: elastic forces back to the ground frame, update, next step's loads
            ag_next = ground_acc[r, step + 1] if step + 1 < n_steps else ag
            av_next = ground_vacc[r, step + 1] if step + 1 < n_steps else av
            e_strain = 0.0
            e_grav = 0.0
            e_kin = 0.0
            work = 0.0
            vv = 0.0
            for i in range(n_nodes):
                b = node_body[i]
                c = cos_b[r, b]
                s = sin_b[r, b]
                fx = f_loc[2 * i, r]
                fy = f_loc[2 * i + 1, r]
                e_strain += 0.5 * (u_loc[2 * i, r] * fx + u_loc[2 * i + 1, r] * fy)
                m = mass[2 * i]
                e_grav -= gravity[2 * i + 1] * (xr[2 * i + 1] - X[2 * i + 1])
                dt_m = dt * inv_mass[i]
                vx = vr[2 * i] + dt_m * (fr[2 * i] - (c * fx - s * fy))
                vy = vr[2 * i + 1] + dt_m * (fr[2 * i + 1] - (s * fx + c * fy))
                # kinetic energy conserved by central differences: m v(n-1/2) . v(n+1/2) / 2
                e_kin += 0.5 * m * (vr[2 * i] * vx + vr[2 * i + 1] * vy)
                vr[2 * i] = vx
                vr[2 * i + 1] = vy
                xr[2 * i] += dt * vx
                xr[2 * i + 1] += dt * vy
                work -= m * (ag * vx + av * vy) * dt
                vv += vx * vx + vy * vy
                fr[2 * i] = gravity[2 * i] - m * ag_next
                fr[2 * i + 1] = gravity[2 * i + 1] - m * av_next
            motion.tallies[r, 0] += (p_base + p_crack) * dt + w_plastic
            motion.tallies[r, 1] += work
            energies = motion.energies[r]
            energies[0] = e_strain
            energies[1] = e_base
            energies[2] = e_crack
            energies[3] = e_collar
            energies[4] = e_grav
            energies[5] = e_kin
            motion.done[r] = step + 1
            if not (math.isfinite(vv) and math.isfinite(e_strain)):
                motion.alive[r] = False
