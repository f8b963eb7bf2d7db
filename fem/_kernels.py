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
from llvmlite import ir
from numba import carray, njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from ..core.collar_law import frame_local_law
from ..core.jit_cache import ensure_fresh
from .cohesive import onset_and_final, traction

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)

# Strict IEEE arithmetic everywhere (no fast-math): the one-state path and the group path are
# different compiled code, and only without contraction (FMA) and reassociation do they round
# alike, so that a state's trajectory is the same bits alone or in any batch (measured: no cost)


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _penalty_contact(gap, vn, vt, kn, kt, cn, mu, dt, ft, fc, blend):
    """One closed contact (gap < 0, normal velocity vn, tangential vt; penalties kn, kt,
    damping cn): damped penalty normal force (never tensile), Coulomb friction on the filtered
    cone. ft: the tangential force of the last step; fc: the normal force low-pass filtered for
    the cone (exponential, blend = dt / tau; 0: the contact was open, and the filter starts at
    the force itself, so an impact gets its full friction at once). Returns (normal force,
    tangential force, filtered normal force, elastic energy, dissipated power, and of it the
    friction's and the damping's (with the clipped tensile part) power)."""
    fn_el = -kn * gap
    fn = max(fn_el - cn * vn, 0.0)
    cone = fn if fc == 0.0 else fc + blend * (fn - fc)
    trial, friction = _coulomb(ft, kt, vt, dt, mu * cone)
    damping = (fn - fn_el) * (-vn)  # damping, or the clipped tensile part
    power = friction + damping
    energy = 0.5 * kn * gap * gap + 0.5 * trial * trial / kt
    return fn, trial, cone, energy, power, friction, damping


@njit(cache=True, inline="always")
def _bed_contact(depth, vn, vt, kn, kt, cn, fy, mu, dt, ft, fc, blend):
    """One node of an elastic-plastic bed pressed ``depth`` below the bottom of its
    indentation (> 0; depth = -gap - indentation), normal velocity vn, tangential vt; penalties
    kn, kt, damping cn, yield force fy (the bed's yield pressure over the node's area; inf for
    an elastic bed). The spring's force kn depth is capped at fy: past it the indentation grows
    by the excess depth - fy / kn (plastic work fy times that), and the damped force too is
    capped at fy (the pressure never exceeds the bed's yield). With fy = inf the arithmetic is
    _penalty_contact's, bit for bit. Returns its values and, last, the plastic indentation's
    increment (m) and work (J)."""
    flow = 0.0
    fn_el = kn * depth
    if fn_el > fy:
        flow = depth - fy / kn
        depth = fy / kn
        fn_el = fy
    fn = min(max(fn_el - cn * vn, 0.0), fy)
    cone = fn if fc == 0.0 else fc + blend * (fn - fc)
    trial, friction = _coulomb(ft, kt, vt, dt, mu * cone)
    damping = (fn - fn_el) * (-vn)  # damping, or the clipped tensile part
    power = friction + damping
    energy = 0.5 * kn * depth * depth + 0.5 * trial * trial / kt
    work = fy * flow if flow > 0.0 else 0.0  # (inf x 0 on an elastic bed)
    return fn, trial, cone, energy, power, friction, damping, flow, work


@njit(cache=True, inline="always")
def _release(ft, normal_force, fn_filtered, r, k):
    """Contact k of state r is open: no forces, and the friction cone's filter starts afresh."""
    ft[r, k] = 0.0
    normal_force[r, k] = 0.0
    fn_filtered[r, k] = 0.0


@njit(cache=True)
def base_contact(
    x,
    v,
    f,
    running,
    states,
    nodes,
    kn,
    kt,
    cn,
    fy,
    mu,
    dt,
    ft,
    normal_force,
    fn_filtered,
    indentation,
    blend,
    out,
):
    """Base nodes against the bed on the rigid ground y = 0, for the running columns of a
    group.

    x, v, f: positions, velocities and forces (n_dofs, columns), column j holding state
    states[j] if running[j]. ft, normal_force, fn_filtered, indentation (states, nodes):
    tangential force, normal force, the normal force low-pass filtered for the friction cone
    (blend = dt / tau, 1 for no filter), and the bed's plastic indentation under the node (m,
    > 0 downward: where the node is above its bottom, y > -indentation, it is open). fy: each
    node's yield force (N; inf: an elastic bed; _bed_contact). out[0, j], out[1, j]: the
    elastic contact energy and dissipated power (friction and damping) of column j; out[2, j],
    out[3, j]: of that power the friction's and the damping's (diagnostics only: nothing reads
    them back into the motion); out[4, j]: the bed's plastic work this step (J). Node by node
    with the columns innermost, so that a node's rows are read once for the group (a state's
    sums still run over the nodes in order: the same bits alone or in a group)."""
    for j in range(states.size):
        out[0, j] = 0.0
        out[1, j] = 0.0
        out[2, j] = 0.0
        out[3, j] = 0.0
        out[4, j] = 0.0
    for k in range(nodes.size):
        i = nodes[k]
        for j in range(states.size):
            if not running[j]:
                continue
            r = states[j]
            depth = -x[2 * i + 1, j] - indentation[r, k]
            if depth <= 0.0:
                _release(ft, normal_force, fn_filtered, r, k)
                continue
            fn, trial, cone, e, p, p_friction, p_damping, flow, w_plastic = _bed_contact(
                depth,
                v[2 * i + 1, j],
                v[2 * i, j],
                kn[k],
                kt[k],
                cn[k],
                fy[k],
                mu,
                dt,
                ft[r, k],
                fn_filtered[r, k],
                blend,
            )
            indentation[r, k] += flow
            ft[r, k] = trial
            normal_force[r, k] = fn
            fn_filtered[r, k] = cone
            f[2 * i, j] += trial
            f[2 * i + 1, j] += fn
            out[0, j] += e
            out[1, j] += p
            out[2, j] += p_friction
            out[3, j] += p_damping
            out[4, j] += w_plastic


@njit(cache=True, inline="always")
def _strides(single, n_dofs):
    """The strides in Scratch.work between two components of a dof and between the two dofs of
    a node: for one state (single, a compile-time constant) n_dofs and 1, for a group GROUP and
    COMPONENTS * GROUP (constants: the index arithmetic folds)."""
    if single:
        return n_dofs, 1
    return GROUP, COMPONENTS * GROUP


@njit(cache=True, inline="always", error_model="numpy")
def _project(grid, sx, sy, masters, m, node, offset, dof):
    """Whether the slave at (sx, sy) projects onto master segment m (within 1e-12 of its ends),
    and the projection's local coordinate clamped to [0, 1]. grid, node, offset (the state's
    position column), dof as in crack_contact."""
    a = node * masters[m] + offset
    b = node * masters[m + 1] + offset
    dx = grid[b] - grid[a]
    dy = grid[b + dof] - grid[a + dof]
    t = ((sx - grid[a]) * dx + (sy - grid[a + dof]) * dy) / (dx * dx + dy * dy)
    return -1e-12 <= t <= 1.0 + 1e-12, min(max(t, 0.0), 1.0)


@njit(cache=True, inline="always", error_model="numpy")
def _segment_search(grid, sx, sy, masters, first, node, offset, dof):
    """The master segment onto which the slave at (sx, sy) projects, searched outward from
    segment `first`, alternating up and down: (segment, local coordinate in [0, 1]) or (-1,
    0.0) for none (arguments as in _project)."""
    n_seg = masters.size - 1
    for step in range(2 * n_seg):
        m = first + (step + 1) // 2 if step % 2 == 0 else first - (step + 1) // 2
        if m < 0 or m >= n_seg:
            if first + step // 2 >= n_seg and first - step // 2 < 0:
                break
            continue
        inside, xi = _project(grid, sx, sy, masters, m, node, offset, dof)
        if inside:
            return m, xi
    return -1, 0.0


@njit(cache=True, error_model="numpy")
def crack_contact(
    grid,
    single,
    running,
    states,
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
    normal_force,
    fn_filtered,
    blend,
    out,
):
    """Node-to-segment contact of the slave face's nodes on the master face (ordered by height),
    for the running columns of a group (running, states, out as in base_contact).

    grid: the work array of Scratch (positions, velocities and forces of the group's states,
    in the layout of a group, or of one state if single, a compile-time constant: the strides
    are then constants and the index arithmetic folds). outward_sign: +1 if the master face's
    outward normal is the segment direction turned clockwise (the left body's crack face), -1
    otherwise. seg[r, k]: master segment last used by slave k in state r (-1: none).

    The segment used last step nearly always still holds the slave: it is tried first, and
    only where it does not is the face searched. A slave clearly on the open side of its
    segment (the cross product of the segment and the slave's offset from its projection has
    the open sign by a margin far above rounding) is open without the normal's square root and
    divisions: the same decisions, and so the same bits, as the full gap test. Degenerate
    (zero-length) segments give inf or nan rather than raising (error_model numpy), which the
    run's finiteness check stops."""
    component, dof = _strides(single, grid.size // COMPONENTS)
    node = 2 * dof
    x0 = POSITION * component
    v0 = VELOCITY * component
    f0 = FORCE * component
    for j in range(states.size):
        out[0, j] = 0.0
        out[1, j] = 0.0
        out[2, j] = 0.0
        out[3, j] = 0.0
    for k in range(slaves.size):
        s = node * slaves[k]
        for j in range(states.size):
            if not running[j]:
                continue
            r = states[j]
            sx = grid[s + x0 + j]
            sy = grid[s + x0 + dof + j]
            first = max(seg[r, k], 0)
            inside, xi = _project(grid, sx, sy, masters, first, node, x0 + j, dof)
            found = first
            if not inside:
                found, xi = _segment_search(grid, sx, sy, masters, first, node, x0 + j, dof)
            seg[r, k] = found
            if found < 0:
                _release(ft, normal_force, fn_filtered, r, k)
                continue
            a = node * masters[found] + j
            b = node * masters[found + 1] + j
            ax = grid[a + x0]
            ay = grid[a + x0 + dof]
            dx = grid[b + x0] - ax
            dy = grid[b + x0 + dof] - ay
            qx = sx - (ax + xi * dx)
            qy = sy - (ay + xi * dy)
            cross_x = qx * dy
            cross_y = qy * dx
            if outward_sign * (cross_x - cross_y) > 1e-13 * (abs(cross_x) + abs(cross_y)):
                _release(ft, normal_force, fn_filtered, r, k)
                continue
            length = math.sqrt(dx * dx + dy * dy)
            tx = dx / length
            ty = dy / length
            nx = outward_sign * ty
            ny = -outward_sign * tx
            gap = qx * nx + qy * ny
            if gap >= 0.0:
                _release(ft, normal_force, fn_filtered, r, k)
                continue
            sj = s + j
            rvx = grid[sj + v0] - ((1.0 - xi) * grid[a + v0] + xi * grid[b + v0])
            rvy = grid[sj + v0 + dof] - ((1.0 - xi) * grid[a + v0 + dof] + xi * grid[b + v0 + dof])
            fn, trial, cone, e, p, p_friction, p_damping = _penalty_contact(
                gap,
                rvx * nx + rvy * ny,
                rvx * tx + rvy * ty,
                kn[k],
                kt[k],
                cn[k],
                mu,
                dt,
                ft[r, k],
                fn_filtered[r, k],
                blend,
            )
            ft[r, k] = trial
            normal_force[r, k] = fn
            fn_filtered[r, k] = cone
            out[0, j] += e
            out[1, j] += p
            out[2, j] += p_friction
            out[3, j] += p_damping
            fx = fn * nx + trial * tx
            fy = fn * ny + trial * ty
            grid[sj + f0] += fx
            grid[sj + f0 + dof] += fy
            grid[a + f0] -= (1.0 - xi) * fx
            grid[a + f0 + dof] -= (1.0 - xi) * fy
            grid[b + f0] -= xi * fx
            grid[b + f0 + dof] -= xi * fy


@njit(cache=True, inline="always")
def _predicted_velocity(grid, i, j, node, dof, v0, f0, k0, node_body, cos_b, sin_b, inv_mass, dt):
    """The velocity v(n+1/2) of node i in column j without the crack's forces: v + dt / m (f -
    R(phi) K u), the external and base forces f and the elastic ones K u rotated by its body's
    frame (what the fused pass of _advance_group will do)."""
    b = node_body[i]
    c = cos_b[b, j]
    s = sin_b[b, j]
    at = node * i + j
    kx = grid[at + k0]
    ky = grid[at + k0 + dof]
    scale = dt * inv_mass[i]
    vx = grid[at + v0] + scale * (grid[at + f0] - (c * kx - s * ky))
    vy = grid[at + v0 + dof] + scale * (grid[at + f0 + dof] - (s * kx + c * ky))
    return vx, vy


@njit(cache=True, error_model="numpy")
def crack_lagrange(
    grid,
    single,
    running,
    states,
    cracks,
    crack_states,
    node_body,
    cos_b,
    sin_b,
    inv_mass,
    mu,
    dt,
    iterations,
    tolerance,
    table,
    predicted,
    out,
):
    """Exact (hard) crack contact with Coulomb friction: forward-increment Lagrange multipliers
    (Carpenter, Taylor & Katona 1991), for the running columns of a group (grid, single,
    running, states as in crack_contact; both node-to-segment passes of ``cracks`` at once).

    Called once every other force of the step is in (external, base contact, collars in the
    FORCE component, the elastic forces in ELASTIC): with them each crack node's velocity
    v*(n+1/2) is predicted, and the multipliers (normal lambda_n >= 0, tangential |lambda_t|
    <= mu lambda_n) are the forces at step n for which the slaves' gaps at n+1, g(n) + dt
    v_rel(n+1/2) . n, are not negative and, where they touch, their tangential velocity
    v_rel(n+1/2) . t vanishes unless the cone is reached. The constraint of slave s on segment
    (a, b) at local coordinate xi moves its relative velocity by dt lambda w, w = 1 / m_s + (1 -
    xi)^2 / m_a + xi^2 / m_b; coupled constraints (shared master nodes, the two passes) are
    solved by projected Gauss-Seidel, warm started from the last step's multipliers
    (crack_states' fn, ft), until no multiplier moves a gap by more than ``tolerance`` (m) or
    after ``iterations`` sweeps. Normal and tangential (n, t) are those of the segment at step
    n. No penalty, no stored energy, no stable-step limit; the work of the multipliers over
    the step, -lambda . (v_rel(n-1/2) + v_rel(n+1/2)) dt / 2, is dissipated (impacts are
    plastic, slip dissipates mu lambda_n |slip|).

    table (2, slaves, 6): per pass and slave the segment's xi, n, t and w (scratch);
    predicted (2 n_nodes): the crack nodes' predicted velocities (scratch). out rows as in
    crack_contact (energy 0; of the power the friction's, and the normal multipliers' in the
    damping's row). With dt = 0 no force (_advance_group takes the penalty's forces then)."""
    component, dof = _strides(single, grid.size // COMPONENTS)
    node = 2 * dof
    x0 = POSITION * component
    v0 = VELOCITY * component
    f0 = FORCE * component
    k0 = ELASTIC * component
    for j in range(states.size):
        out[0, j] = 0.0
        out[1, j] = 0.0
        out[2, j] = 0.0
        out[3, j] = 0.0
    if dt <= 0.0:
        return
    for j in range(states.size):
        if not running[j]:
            continue
        r = states[j]
        # predicted velocities of every crack node, the segments and the warm start
        for p in range(2):
            slaves = cracks[p].nodes
            for k in range(slaves.size):
                i = slaves[k]
                vx, vy = _predicted_velocity(
                    grid, i, j, node, dof, v0, f0, k0, node_body, cos_b, sin_b, inv_mass, dt
                )
                predicted[2 * i] = vx
                predicted[2 * i + 1] = vy
        for p in range(2):
            crack = cracks[p]
            state = crack_states[p]
            slaves, masters = crack.nodes, crack.masters
            for k in range(slaves.size):
                s = node * slaves[k]
                sx = grid[s + x0 + j]
                sy = grid[s + x0 + dof + j]
                first = max(state.seg[r, k], 0)
                inside, xi = _project(grid, sx, sy, masters, first, node, x0 + j, dof)
                found = first
                if not inside:
                    found, xi = _segment_search(grid, sx, sy, masters, first, node, x0 + j, dof)
                state.seg[r, k] = found
                if found < 0:
                    state.fn[r, k] = 0.0
                    state.ft[r, k] = 0.0
                    table[p, k, 5] = 0.0
                    continue
                a = node * masters[found] + j
                b = node * masters[found + 1] + j
                ax = grid[a + x0]
                ay = grid[a + x0 + dof]
                dx = grid[b + x0] - ax
                dy = grid[b + x0 + dof] - ay
                length = math.sqrt(dx * dx + dy * dy)
                tx = dx / length
                ty = dy / length
                nx = crack.sign * ty
                ny = -crack.sign * tx
                gap = (sx - (ax + xi * dx)) * nx + (sy - (ay + xi * dy)) * ny
                ia = masters[found]
                ib = masters[found + 1]
                w = (
                    inv_mass[slaves[k]]
                    + (1.0 - xi) * (1.0 - xi) * inv_mass[ia]
                    + xi * xi * inv_mass[ib]
                )
                table[p, k, 0] = xi
                table[p, k, 1] = nx
                table[p, k, 2] = ny
                table[p, k, 3] = gap
                table[p, k, 4] = w
                table[p, k, 5] = 1.0
                # warm start: last step's multipliers, applied to the predicted velocities
                ln = state.fn[r, k]
                lt = state.ft[r, k]
                if ln > 0.0 or lt != 0.0:
                    _apply_multiplier(
                        predicted,
                        slaves[k],
                        ia,
                        ib,
                        xi,
                        ln * nx + lt * tx,
                        ln * ny + lt * ty,
                        inv_mass,
                        dt,
                    )
        # projected Gauss-Seidel over both passes' constraints
        for _sweep in range(iterations):
            moved = 0.0
            for p in range(2):
                crack = cracks[p]
                state = crack_states[p]
                slaves, masters = crack.nodes, crack.masters
                for k in range(slaves.size):
                    if table[p, k, 5] == 0.0:
                        continue
                    i = slaves[k]
                    ia = masters[state.seg[r, k]]
                    ib = masters[state.seg[r, k] + 1]
                    xi = table[p, k, 0]
                    nx = table[p, k, 1]
                    ny = table[p, k, 2]
                    tx = -crack.sign * ny
                    ty = crack.sign * nx
                    w = table[p, k, 4]
                    rvx = predicted[2 * i] - (
                        (1.0 - xi) * predicted[2 * ia] + xi * predicted[2 * ib]
                    )
                    rvy = predicted[2 * i + 1] - (
                        (1.0 - xi) * predicted[2 * ia + 1] + xi * predicted[2 * ib + 1]
                    )
                    gap_next = table[p, k, 3] + dt * (rvx * nx + rvy * ny)
                    ln_old = state.fn[r, k]
                    ln = max(ln_old - gap_next / (dt * dt * w), 0.0)
                    lt_old = state.ft[r, k]
                    # the tangential velocity once the normal change is in (it has none along t)
                    vt = rvx * tx + rvy * ty
                    lt = lt_old - vt / (dt * w)
                    limit = mu * ln
                    lt = min(max(lt, -limit), limit)
                    dn = ln - ln_old
                    dtg = lt - lt_old
                    if dn != 0.0 or dtg != 0.0:
                        _apply_multiplier(
                            predicted,
                            i,
                            ia,
                            ib,
                            xi,
                            dn * nx + dtg * tx,
                            dn * ny + dtg * ty,
                            inv_mass,
                            dt,
                        )
                        state.fn[r, k] = ln
                        state.ft[r, k] = lt
                        moved = max(moved, dt * dt * w * max(abs(dn), abs(dtg)))
            if moved <= tolerance:
                break
        # the multipliers as forces of the step, and their work
        for p in range(2):
            crack = cracks[p]
            state = crack_states[p]
            slaves, masters = crack.nodes, crack.masters
            for k in range(slaves.size):
                if table[p, k, 5] == 0.0:
                    continue
                ln = state.fn[r, k]
                lt = state.ft[r, k]
                state.fc[r, k] = ln
                if ln == 0.0 and lt == 0.0:
                    continue
                i = slaves[k]
                ia = masters[state.seg[r, k]]
                ib = masters[state.seg[r, k] + 1]
                xi = table[p, k, 0]
                nx = table[p, k, 1]
                ny = table[p, k, 2]
                tx = -crack.sign * ny
                ty = crack.sign * nx
                fx = ln * nx + lt * tx
                fy = ln * ny + lt * ty
                s = node * i + j
                a = node * ia + j
                b = node * ib + j
                # relative velocities before (n - 1/2) and after (n + 1/2) the step
                old_x = grid[s + v0] - ((1.0 - xi) * grid[a + v0] + xi * grid[b + v0])
                old_y = grid[s + v0 + dof] - (
                    (1.0 - xi) * grid[a + v0 + dof] + xi * grid[b + v0 + dof]
                )
                new_x = predicted[2 * i] - ((1.0 - xi) * predicted[2 * ia] + xi * predicted[2 * ib])
                new_y = predicted[2 * i + 1] - (
                    (1.0 - xi) * predicted[2 * ia + 1] + xi * predicted[2 * ib + 1]
                )
                mid_x = 0.5 * (old_x + new_x)
                mid_y = 0.5 * (old_y + new_y)
                normal_power = -ln * (mid_x * nx + mid_y * ny)
                friction_power = -lt * (mid_x * tx + mid_y * ty)
                out[1, j] += normal_power + friction_power
                out[2, j] += friction_power
                out[3, j] += normal_power
                grid[s + f0] += fx
                grid[s + f0 + dof] += fy
                grid[a + f0] -= (1.0 - xi) * fx
                grid[a + f0 + dof] -= (1.0 - xi) * fy
                grid[b + f0] -= xi * fx
                grid[b + f0 + dof] -= xi * fy


@njit(cache=True, inline="always")
def _apply_multiplier(predicted, i, ia, ib, xi, fx, fy, inv_mass, dt):
    """Add a force (fx, fy) on slave i and its reaction on master nodes ia, ib (weights 1 -
    xi, xi) to the predicted velocities over one step."""
    predicted[2 * i] += dt * inv_mass[i] * fx
    predicted[2 * i + 1] += dt * inv_mass[i] * fy
    predicted[2 * ia] -= dt * inv_mass[ia] * (1.0 - xi) * fx
    predicted[2 * ia + 1] -= dt * inv_mass[ia] * (1.0 - xi) * fy
    predicted[2 * ib] -= dt * inv_mass[ib] * xi * fx
    predicted[2 * ib + 1] -= dt * inv_mass[ib] * xi * fy


@njit(cache=True, inline="always")
def _released(d, K, d0, df):
    """The energy per unit area a bilinear law has dissipated at damage d (onset and final
    separations d0, df): K d0 delta d / 2 at the separation delta = df d0 / (df - d (df - d0))
    of that damage (the area under the law less the secant's elastic energy); G = K d0 df / 2
    at d = 1. Exact along a path of one mode mixity whatever the step, where the energy
    release rate times the damage increment, K delta^2 / 2 x (d - d_old), overshoots by about
    (delta - delta_old) / delta: several times at the onset, delta_0 being tiny."""
    return 0.5 * K * d0 * d0 * df * d / (df - d * (df - d0))


@njit(cache=True)
def cohesive_forces(x, f, cohesive, damage, c, s):
    """The cohesive mid-plane's forces (fem.partial_crack) on the positions x of one state
    (flat), added to f; damage (pairs,) is the state's, updated. c, s: cosine and sine of the
    halves' mean rotation, whose frame measures the separation of each pair: delta_n along
    (c, s) (> 0 opens), delta_s along (-s, c). Broken pairs (d = 1) are skipped; compression
    is the contact's (t_n = 0 there), friction too (mu = 0 in the law). Returns (the springs'
    elastic energy, the energy dissipated by this call's damage increments, _released) (J)."""
    energy = 0.0
    dissipated = 0.0
    law = cohesive.law
    for k in range(cohesive.left.size):
        d_old = damage[k]
        if d_old >= 1.0:
            continue
        i = cohesive.left[k]
        j = cohesive.right[k]
        dx = x[2 * j] - x[2 * i]
        dy = x[2 * j + 1] - x[2 * i + 1]
        dn = c * dx + s * dy
        ds = -s * dx + c * dy
        K = cohesive.stiffness[k]
        t_n, t_s, d, _slip = traction(
            dn, ds, d_old, 0.0, K, law[0], law[1], law[2], law[3], law[4], 0.0
        )
        opening = dn if dn > 0.0 else 0.0
        if dn <= 0.0:
            t_n = 0.0
        area = cohesive.area[k]
        energy += (1.0 - d) * 0.5 * K * (opening * opening + ds * ds) * area
        if d > d_old:
            d0, df = onset_and_final(dn, ds, K, law[0], law[1], law[2], law[3], law[4])
            dissipated += area * (_released(d, K, d0, df) - _released(d_old, K, d0, df))
        damage[k] = d
        fn = area * t_n
        fs = area * t_s
        fx = fn * c - fs * s
        fy = fn * s + fs * c
        f[2 * i] += fx
        f[2 * i + 1] += fy
        f[2 * j] -= fx
        f[2 * j + 1] -= fy
    return energy, dissipated


@njit(cache=True)
def _face_angle(x, below, above):
    return math.atan2(x[2 * above + 1] - x[2 * below + 1], x[2 * above] - x[2 * below])


@njit(cache=True)
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
"""The stone's stiffness in block-sparse-row form, 2 x 2 blocks (one block per node pair), each
block stored by columns: blocks[k, c, r] is row r, column c of block k (so that a column is two
adjacent doubles: one 2-wide vector in the one-state mat-vec)."""

Bodies = namedtuple(
    "Bodies", ["X", "mass", "node_body", "centroid_ref", "gravity", "order", "offsets"]
)
"""Reference positions, lumped mass per dof, body of each node, body centroids (n_bodies, 2),
gravity load per dof, and the nodes grouped by body: body b's nodes are
order[offsets[b]:offsets[b + 1]]."""

ContactPass = namedtuple("ContactPass", ["nodes", "masters", "sign", "kn", "kt", "cn", "fy"])
"""A contact pass: the base (nodes against the ground; masters and sign unused) or one crack
pass (slave nodes on the master face; see crack_contact); penalty, tangential penalty,
damping and yield force (the base's elastic-plastic bed, inf where elastic; a crack's unused)
per contact node."""

ContactState = namedtuple("ContactState", ["seg", "ft", "fn", "fc", "indentation"])
"""Per state (rows) and contact node: master segment last used (crack), tangential force,
normal force, its filtered value for the friction cone, and the bed's plastic indentation (m;
the base's)."""

Cohesive = namedtuple("Cohesive", ["left", "right", "area", "stiffness", "law"])
"""A partial crack's intact mid-plane (fem.partial_crack.CohesiveInterface): node pairs,
their area and penalty, the law's (f_t, s, G_I, G_II, eta); no pairs for a full crack."""

CohesiveState = namedtuple("CohesiveState", ["damage", "energy"])
"""Per state: each pair's damage (B, pairs; its history: it never decreases) and (B, 2) the
springs' elastic energy at the last step and the energy their damage has dissipated."""

Collars = namedtuple("Collars", ["nodes", "props"])
"""collar_forces' node table and properties."""

CollarState = namedtuple("CollarState", ["out", "plastic"])
"""Per state: collar_forces' outputs (B, n_collars, collar_law.OUT_SIZE) and plastic state
(B, n_collars, Model.collar_state_size: the largest row the collars' laws need)."""

EdgeAverage = namedtuple("EdgeAverage", ["weights", "buffer", "position", "sums", "peak"])
"""The toe resultants weights . base_fn (weights (n_edges, n_base), shared) averaged over the
last buffer.shape[2] steps: per state a ring buffer (B, n_edges, n_avg), its position (B,),
running sums (B, n_edges) and the peak of the average since the last record (B, n_edges)."""

Motion = namedtuple("Motion", ["x", "v", "frames", "tallies", "energies", "alive", "done"])
"""Per state: positions and velocities (B, n_dofs), body frames (B, n_bodies, 3: centroid x,
y and rotation), tallies (B, 6: dissipated energy, external work, and of the dissipated the
base's friction work, the crack's friction work, the contact damping work, the bed's plastic
work), energies (B, 6: strain,
base contact, crack contact, collar, gravity, kinetic), alive (B,: False stops a state) and
done (B,: steps done by the last call)."""

Scratch = namedtuple("Scratch", ["work"])
"""advance's work array, flat and 64-byte aligned (make it with new_scratch; one serves any
batch size). For a group of up to GROUP states, state j of the group in column j: per dof d and
component c (position, velocity, external force, local displacement, elastic force) the entry
(COMPONENTS d + c) GROUP + j, so that a node's data for all the states of a group lie together,
each row of GROUP states in one cache line. One state has the plain layout: the components one
after the other, each n_dofs long."""


# States per group of advance (see _advance_group): a compile-time constant, so that the rows a
# loop over a group's states touches lie at fixed offsets from each other and the loops have a
# fixed trip count: they vectorise (4 doubles a vector; GROUP is a multiple of 4)
GROUP = 8
# most projected Gauss-Seidel sweeps of the exact crack contact per step (crack_lagrange); warm
# started, a step usually needs a few
LAGRANGE_SWEEPS = 200
# per dof and state in Scratch.work: position, velocity, external force, local displacement,
# elastic force
COMPONENTS = 5
POSITION, VELOCITY, FORCE, LOCAL, ELASTIC = range(COMPONENTS)


def new_scratch(n_dofs):
    """A Scratch for a model of n_dofs dofs (any batch size), its work array 64-byte aligned
    (a row of a group's GROUP states fills one cache line)."""
    size = COMPONENTS * GROUP * n_dofs
    buffer = np.zeros(size + 8)
    start = (-buffer.ctypes.data % 64) // 8
    return Scratch(buffer[start : start + size])


@intrinsic
def _stack_rows(typingctx, rows):
    """Work buffer of `rows` x GROUP float64 (rows a constant) on the stack, as a pointer for
    numba.carray: the per-state sums of a pass. The compiler knows that it overlaps no array,
    so a loop over the states that sums into it vectorises without run-time overlap checks."""
    if not isinstance(rows, types.IntegerLiteral):
        return None

    def codegen(context, builder, signature, args):
        size = context.get_constant(types.intp, rows.literal_value * GROUP)
        return cgutils.alloca_once(builder, context.get_value_type(types.float64), size=size)

    return types.CPointer(types.float64)(rows), codegen


@njit(cache=True)
def _span(array, start, length, single):
    """array[start : start + length] as (view, offset of start in it): for a group of states a
    view, inside which the rows a loop over the states touches are at fixed offsets (so that it
    vectorises); for one state (single, a compile-time constant) the array itself and start,
    no view to build per node."""
    if single:
        return array, start
    return array[start : start + length], 0


def _contiguous(array_type):
    """Whether a numba type is a contiguous 1-d float64 array (what _madd4 and _copy4 take)."""
    return (
        isinstance(array_type, types.Array)
        and array_type.ndim == 1
        and array_type.layout == "C"
        and array_type.dtype == types.float64
    )


def _vector_at(context, builder, array_type, array, index, lanes=4):
    """Pointer to array[index : index + lanes] as one vector of `lanes` doubles."""
    data = context.make_array(array_type)(context, builder, array).data
    pointer = builder.gep(data, [index])
    return builder.bitcast(pointer, ir.PointerType(ir.VectorType(ir.DoubleType(), lanes)))


def _splat(builder, value, lanes=4):
    """A vector of `lanes` doubles, each value."""
    vector = ir.VectorType(ir.DoubleType(), lanes)
    lane = builder.insert_element(
        ir.Constant(vector, ir.Undefined), value, ir.Constant(ir.IntType(32), 0)
    )
    zeros = ir.Constant(ir.VectorType(ir.IntType(32), lanes), [0] * lanes)
    return builder.shuffle_vector(lane, ir.Constant(vector, ir.Undefined), zeros)


@intrinsic
def _madd4(typingctx, acc, at, a, x, xt, b, yt):
    """acc[at : at + 4] += a * x[xt : xt + 4] + b * x[yt : yt + 4] (acc, x: contiguous 1-d
    float64 arrays, unchecked bounds) as 4-wide vector operations, in strict IEEE arithmetic:
    the same operations, in the same order, as the scalar acc[at + r] += a * x[xt + r] + b *
    x[yt + r]. Explicit, because numba runs only the loop vectoriser, and a loop over the 8
    states of a group with a fixed count is unrolled into scalar code before it is vectorised:
    with these a row's sums stay in vector registers."""
    if not (_contiguous(acc) and _contiguous(x)):
        return None

    def codegen(context, builder, signature, args):
        acc_type, _, _, x_type, _, _, _ = signature.args
        acc_value, at_value, a_value, x_value, xt_value, b_value, yt_value = args
        target = _vector_at(context, builder, acc_type, acc_value, at_value)
        first = builder.load(_vector_at(context, builder, x_type, x_value, xt_value), align=8)
        second = builder.load(_vector_at(context, builder, x_type, x_value, yt_value), align=8)
        terms = builder.fadd(
            builder.fmul(_splat(builder, a_value), first),
            builder.fmul(_splat(builder, b_value), second),
        )
        builder.store(builder.fadd(builder.load(target, align=8), terms), target, align=8)
        return context.get_dummy_value()

    return types.void(acc, at, a, x, xt, b, yt), codegen


@intrinsic
def _copy4(typingctx, target, tt, source, st):
    """target[tt : tt + 4] = source[st : st + 4] (source None: zeros) as one 4-wide vector
    (target, source: contiguous 1-d float64 arrays, unchecked bounds)."""
    if not (_contiguous(target) and (isinstance(source, types.NoneType) or _contiguous(source))):
        return None

    def codegen(context, builder, signature, args):
        target_type, _, source_type, _ = signature.args
        pointer = _vector_at(context, builder, target_type, args[0], args[1])
        if isinstance(source_type, types.NoneType):
            value = ir.Constant(ir.VectorType(ir.DoubleType(), 4), [0.0] * 4)
        else:
            value = builder.load(
                _vector_at(context, builder, source_type, args[2], args[3]), align=8
            )
        builder.store(value, pointer, align=8)
        return context.get_dummy_value()

    return types.void(target, tt, source, st), codegen


@intrinsic
def _madd2(typingctx, acc, columns, ct, x0, x1):
    """acc[0 : 2] += columns[ct : ct + 2] * x0 + columns[ct + 2 : ct + 4] * x1 (acc, columns:
    contiguous 1-d float64 arrays, unchecked bounds) as 2-wide vector operations, in strict
    IEEE arithmetic: lane r is the scalar acc[r] += K[r, 0] * x0 + K[r, 1] * x1 of a 2 x 2
    block stored by columns, the same operations in the same order."""
    if not (_contiguous(acc) and _contiguous(columns)):
        return None

    def codegen(context, builder, signature, args):
        acc_type, columns_type = signature.args[0], signature.args[1]
        acc_value, columns_value, ct_value, x0_value, x1_value = args
        second_at = builder.add(ct_value, context.get_constant(types.intp, 2))
        first = builder.load(
            _vector_at(context, builder, columns_type, columns_value, ct_value, 2), align=8
        )
        second = builder.load(
            _vector_at(context, builder, columns_type, columns_value, second_at, 2), align=8
        )
        terms = builder.fadd(
            builder.fmul(first, _splat(builder, x0_value, 2)),
            builder.fmul(second, _splat(builder, x1_value, 2)),
        )
        zero = context.get_constant(types.intp, 0)
        target = _vector_at(context, builder, acc_type, acc_value, zero, 2)
        builder.store(builder.fadd(builder.load(target, align=8), terms), target, align=8)
        return context.get_dummy_value()

    return types.void(acc, columns, ct, x0, x1), codegen


@njit(cache=True)
def bsr_matmat(indptr, indices, blocks, work, single):
    """The elastic forces K u of a group of states: K in block-sparse-row form with 2 x 2
    blocks (one per node pair) applied to the LOCAL component of Scratch.work, the result in
    its ELASTIC component (single, a compile-time constant: one state, in its layout). One read
    of each block serves all the states. A row's sums stay in registers: for one state the
    node's two rows as one 2-wide vector (_madd2: a block's columns are adjacent), for a group
    as 4-wide vectors (_madd4 on a stack buffer the compiler keeps in registers), all GROUP
    columns at once. Every state gets the sums of the one-state path, in the same order.
    Strict IEEE arithmetic (no fast-math)."""
    if single:
        n = work.size // COMPONENTS
        u = work[LOCAL * n : (LOCAL + 1) * n]
        out = work[ELASTIC * n : (ELASTIC + 1) * n]
        columns = blocks.reshape(blocks.size)
        row = carray(_stack_rows(1), (GROUP,))
        for i in range(indptr.size - 1):
            row[0] = 0.0
            row[1] = 0.0
            for k in range(indptr[i], indptr[i + 1]):
                j = indices[k]
                _madd2(row, columns, 4 * k, u[2 * j], u[2 * j + 1])
            out[2 * i] = row[0]
            out[2 * i + 1] = row[1]
        return
    node = 2 * COMPONENTS * GROUP
    u0 = LOCAL * GROUP
    u1 = u0 + COMPONENTS * GROUP
    k0 = ELASTIC * GROUP
    k1 = k0 + COMPONENTS * GROUP
    acc = carray(_stack_rows(2), (2 * GROUP,))
    for i in range(indptr.size - 1):
        for h in range(0, 2 * GROUP, 4):
            _copy4(acc, h, None, 0)
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            b00 = blocks[k, 0, 0]
            b01 = blocks[k, 1, 0]
            b10 = blocks[k, 0, 1]
            b11 = blocks[k, 1, 1]
            u = work[node * j : node * (j + 1)]
            for h in range(0, GROUP, 4):
                _madd4(acc, h, b00, u, u0 + h, b01, u1 + h)
                _madd4(acc, GROUP + h, b10, u, u0 + h, b11, u1 + h)
        out = work[node * i : node * (i + 1)]
        for h in range(0, GROUP, 4):
            _copy4(out, k0 + h, acc, h)
            _copy4(out, k1 + h, acc, GROUP + h)


@njit(cache=True)
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


@njit(cache=True)
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
    lagrange,
    lagrange_tolerance,
    cohesive,
    cohesive_state,
):
    """n_steps of central differences (velocities at half steps, lumped mass) for every live
    state of a batch (motion.alive); a state whose motion stops being finite is stopped there.

    ground_acc[r, k], ground_vacc[r, k]: horizontal and vertical (upward) ground acceleration
    (m/s^2) of state r during step k, applied as the body forces -m ug'' in x and -m vg'' in y
    (ground frame). motion.tallies += (dissipated energy, external work, base friction work,
    crack friction work, contact damping work); motion.energies gets
    (strain, base contact, crack contact, collar, gravity, kinetic) of the last step, all at
    time n (kinetic as m v(n-1/2) . v(n+1/2) / 2, the energy central differences conserve).
    cracks: two contact passes (empty ones for a solid column). The toe resultants are averaged
    over the last steps and their peak kept over every step (EdgeAverage), so that an impact
    shorter than an output interval is not missed and penalty-contact chatter faster than the
    averaging time is not taken for stress. motion.done[r]: the steps state r did. lagrange:
    the crack's contact exact (crack_lagrange) instead of penalty (crack_contact), its
    Gauss-Seidel solved until no multiplier moves a gap by more than lagrange_tolerance (m).

    The live states go through _advance_group in groups of GROUP, a group of one state in the
    one-state layout (a version of _advance_group compiled for it: a plain run keeps its speed).
    """
    X, mass, node_body, centroid_ref = bodies.X, bodies.mass, bodies.node_body, bodies.centroid_ref
    n_nodes = node_body.size
    live = np.empty(motion.alive.size, dtype=np.int64)
    n_live = 0
    for r in range(motion.alive.size):
        motion.done[r] = 0
        if motion.alive[r]:
            live[n_live] = r
            n_live += 1
    # reference positions relative to their body's centroid, inverse masses, body masses
    rel = np.empty(2 * n_nodes)
    inv_mass = np.empty(n_nodes)
    for i in range(n_nodes):
        b = node_body[i]
        rel[2 * i] = X[2 * i] - centroid_ref[b, 0]
        rel[2 * i + 1] = X[2 * i + 1] - centroid_ref[b, 1]
        inv_mass[i] = 1.0 / mass[2 * i]
    body_mass = np.zeros(centroid_ref.shape[0])
    for b in range(body_mass.size):
        for k in range(bodies.offsets[b], bodies.offsets[b + 1]):
            body_mass[b] += mass[2 * bodies.order[k]]
    # what every group shares, passed as one tuple (the group's states and `single` apart)
    shared = (
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
        scratch.work,
        rel,
        inv_mass,
        body_mass,
        lagrange,
        lagrange_tolerance,
        cohesive,
        cohesive_state,
    )
    for first in range(0, n_live, GROUP):
        states = live[first : min(first + GROUP, n_live)]
        # single, a literal at each call, is a compile-time constant of _advance_group: a
        # version for one state, in the one-state layout, and one for GROUP states
        if states.size == 1:
            _advance_group(shared, states, True)
        else:
            _advance_group(shared, states, False)


@njit(cache=True)
def _advance_group(shared, states, single):
    """advance for the live states `states` (at most GROUP; one if single, a compile-time
    constant). shared: advance's arguments that every group shares, in the order unpacked
    below (scratch.work as work), and rel: reference positions relative to their body's
    centroid; inv_mass per node; body_mass per body.

    Layout (Scratch): the states' positions and velocities are copied into the work array at
    entry and back at exit (or when a state stops), state states[j] in column j. The per-node
    passes run over the nodes with the states innermost: a node's shared data (mass, reference
    position, stiffness blocks) is read once for all the states, and the loop over them is
    contiguous, at fixed offsets from the node's start, with its sums in stack buffers
    (_stack_rows): it vectorises. The mat-vec and the fused pass run over all GROUP columns (a
    fixed count), the other passes over the states' columns; the columns past the states (and
    a stopped state's) are parked at rest at the reference positions, their results unread.
    The contact functions get the group's columns (node by node, the columns innermost), the
    collar function a state's columns as strided views. One state has the plain layout and
    scalar loops.

    Per step: body by body, the body frames from the sums left by the last update and one pass
    for the local displacements; one block mat-vec for all the states (bsr_matmat); the base and
    crack contact for all the states; per state the toe averages and the collar forces; one
    fused pass, body by body, that rotates the elastic forces back, updates velocity and
    position, loads gravity and ground force for the next step and sums the next step's frame
    sums."""
    (
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
        work,
        rel,
        inv_mass,
        body_mass,
        lagrange,
        lagrange_tolerance,
        cohesive,
        cohesive_state,
    ) = shared

    x, v, frames = motion.x, motion.v, motion.frames
    X, mass, gravity, order, offsets = (
        bodies.X,
        bodies.mass,
        bodies.gravity,
        bodies.order,
        bodies.offsets,
    )
    n_dofs = x.shape[1]
    n_bodies = body_mass.size
    width = states.size
    # the strides in the work array; the columns of a group (compile-time) and the states' (a
    # number known only at run time)
    component, dof = _strides(single, n_dofs)
    group = 1 if single else GROUP
    lanes = 1 if single else width
    node = 2 * dof
    x0 = POSITION * component
    v0 = VELOCITY * component
    f0 = FORCE * component
    u0 = LOCAL * component
    k0 = ELASTIC * component
    grid = work[: COMPONENTS * group * n_dofs]
    if single:
        columns = grid.reshape((COMPONENTS, n_dofs, 1)).transpose((1, 0, 2))
    else:
        columns = grid.reshape((n_dofs, COMPONENTS, GROUP))
    running = np.zeros(group, dtype=np.bool_)
    for j in range(group):
        if j < width:
            running[j] = True
            columns[:, POSITION, j] = x[states[j]]
            columns[:, VELOCITY, j] = v[states[j]]
        else:
            columns[:, POSITION, j] = X
            columns[:, VELOCITY, j] = 0.0
        columns[:, LOCAL, j] = 0.0
        columns[:, ELASTIC, j] = 0.0
    # per state: body rotations (n_bodies of them); on the stack: the frame sums of a body, its
    # centroid and rotation, the fused pass' sums, this and the next step's ground
    # accelerations, the contact and collar results
    cos_b = np.ones((n_bodies, group))
    sin_b = np.zeros((n_bodies, group))
    sums = carray(_stack_rows(4), (4, GROUP))
    frame = carray(_stack_rows(4), (4, GROUP))
    totals = carray(_stack_rows(5), (5, GROUP))
    ground = carray(_stack_rows(4), (4, GROUP))
    results = carray(_stack_rows(8), (8, GROUP))
    contact = carray(_stack_rows(17), (17, GROUP))
    collar_results = carray(_stack_rows(2), (2, GROUP))
    cohesive_results = carray(_stack_rows(2), (2, GROUP))
    # the exact crack contact's scratch (crack_lagrange); its tolerance (m) is the caller's
    # (fem.solver.LAGRANGE_TOLERANCE says how it is chosen)
    n_slaves = max(cracks[0].nodes.size, cracks[1].nodes.size)
    lagrange_table = np.zeros((2, n_slaves if lagrange else 0, 6))
    lagrange_velocity = np.zeros(n_dofs if lagrange else 0)
    positions = columns[:, POSITION, :]
    velocities = columns[:, VELOCITY, :]
    forces = columns[:, FORCE, :]
    for j in range(group):
        ground[0, j] = ground_acc[states[j], 0] if j < width else 0.0
        ground[1, j] = ground_vacc[states[j], 0] if j < width else 0.0
    for k in range(order.size):
        i = order[k]
        w, o = _span(grid, node * i, node, single)
        for j in range(group):
            w[o + f0 + j] = gravity[2 * i] - mass[2 * i] * ground[0, j]
            w[o + f0 + dof + j] = gravity[2 * i + 1] - mass[2 * i] * ground[1, j]
    # the body frames' sums of the positions, per body and state: here for the first step, then
    # by the fused pass for the next
    body_sums = np.zeros((n_bodies, 4, group))
    for b in range(n_bodies):
        for k in range(offsets[b], offsets[b + 1]):
            i = order[k]
            m = mass[2 * i]
            px = rel[2 * i]
            py = rel[2 * i + 1]
            w, o = _span(grid, node * i, node, single)
            for j in range(group):
                xj = w[o + x0 + j]
                yj = w[o + x0 + dof + j]
                body_sums[b, 0, j] += m * xj
                body_sums[b, 1, j] += m * yj
                body_sums[b, 2, j] += m * (px * xj + py * yj)
                body_sums[b, 3, j] += m * (px * yj - py * xj)
    for step in range(n_steps):
        # body frames: centroid and best-fit rotation from the sums (sum m (X - C) = 0), then the
        # local displacements, body by body
        for b in range(n_bodies):
            for j in range(lanes):
                cx = body_sums[b, 0, j] / body_mass[b]
                cy = body_sums[b, 1, j] / body_mass[b]
                phi = math.atan2(body_sums[b, 3, j], body_sums[b, 2, j])
                c = math.cos(phi)
                s = math.sin(phi)
                frame[0, j] = cx
                frame[1, j] = cy
                frame[2, j] = c
                frame[3, j] = s
                cos_b[b, j] = c
                sin_b[b, j] = s
                if running[j]:
                    frames[states[j], b, 0] = cx
                    frames[states[j], b, 1] = cy
                    frames[states[j], b, 2] = phi
            for k in range(offsets[b], offsets[b + 1]):
                i = order[k]
                px = rel[2 * i]
                py = rel[2 * i + 1]
                w, o = _span(grid, node * i, node, single)
                for j in range(lanes):
                    qx = w[o + x0 + j] - frame[0, j]
                    qy = w[o + x0 + dof + j] - frame[1, j]
                    w[o + u0 + j] = frame[2, j] * qx + frame[3, j] * qy - px
                    w[o + u0 + dof + j] = -frame[3, j] * qx + frame[2, j] * qy - py
        bsr_matmat(stiffness.indptr, stiffness.indices, stiffness.blocks, grid, single)
        # this and the next step's ground accelerations
        for j in range(group):
            if not running[j]:
                ground[0, j] = 0.0
                ground[1, j] = 0.0
                ground[2, j] = 0.0
                ground[3, j] = 0.0
                continue
            r = states[j]
            ground[0, j] = ground_acc[r, step]
            ground[1, j] = ground_vacc[r, step]
            ground[2, j] = ground_acc[r, step + 1] if step + 1 < n_steps else ground[0, j]
            ground[3, j] = ground_vacc[r, step + 1] if step + 1 < n_steps else ground[1, j]
        # contact, node by node for the whole group (a node's rows are read once), then the
        # toe averages and the collars state by state
        base_contact(
            positions,
            velocities,
            forces,
            running,
            states,
            base.nodes,
            base.kn,
            base.kt,
            base.cn,
            base.fy,
            mu,
            dt,
            base_state.ft,
            base_state.fn,
            base_state.fc,
            base_state.indentation,
            blend,
            contact[12:17],
        )
        # per state the toe averages and the collars (their forces join the external ones:
        # the exact crack contact predicts with every other force in)
        for j in range(width):
            if not running[j]:
                continue
            r = states[j]
            _edge_average(edge, r, base_state.fn[r])
            if single:  # contiguous
                xr = grid[x0 : x0 + n_dofs]
                fr = grid[f0 : f0 + n_dofs]
            else:
                xr = columns[:, POSITION, j]
                fr = columns[:, FORCE, j]
            e_collar, w_plastic = collar_forces(
                xr,
                collars.nodes,
                collars.props,
                collar_state.out[r],
                fr,
                collar_state.plastic[r],
                True,
            )
            collar_results[0, j] = e_collar
            collar_results[1, j] = w_plastic
            # the intact mid-plane's springs, in the frame of the halves' mean rotation
            cohesive_results[0, j] = 0.0
            cohesive_results[1, j] = 0.0
            if cohesive.left.size > 0:
                mc = cos_b[0, j] + cos_b[1, j]
                ms = sin_b[0, j] + sin_b[1, j]
                norm = math.sqrt(mc * mc + ms * ms)
                e_cohesive, w_cohesive = cohesive_forces(
                    xr, fr, cohesive, cohesive_state.damage[r], mc / norm, ms / norm
                )
                cohesive_results[0, j] = e_cohesive
                cohesive_results[1, j] = w_cohesive
                cohesive_state.energy[r, 0] = e_cohesive
                cohesive_state.energy[r, 1] += w_cohesive
        # without a step (dt = 0: the forces of a state) the crack's springs measure them
        if lagrange and dt > 0.0 and cracks[0].nodes.size > 0:
            crack_lagrange(
                grid,
                single,
                running,
                states,
                cracks,
                crack_states,
                bodies.node_body,
                cos_b,
                sin_b,
                inv_mass,
                mu,
                dt,
                LAGRANGE_SWEEPS,
                lagrange_tolerance,
                lagrange_table,
                lagrange_velocity,
                contact[4:8],
            )
            contact[8:12, :] = 0.0
        else:
            for p in range(2):
                crack = cracks[p]
                if crack.nodes.size == 0:
                    contact[4 + 4 * p : 8 + 4 * p, :] = 0.0
                    continue
                state = crack_states[p]
                crack_contact(
                    grid,
                    single,
                    running,
                    states,
                    crack.nodes,
                    crack.masters,
                    crack.sign,
                    crack.kn,
                    crack.kt,
                    crack.cn,
                    mu,
                    dt,
                    state.seg,
                    state.ft,
                    state.fn,
                    state.fc,
                    blend,
                    contact[4 + 4 * p : 8 + 4 * p],
                )
        for j in range(width):
            if not running[j]:
                continue
            e_collar = collar_results[0, j]
            w_plastic = collar_results[1, j]
            e_crack = 0.0
            p_crack = 0.0
            friction_crack = 0.0
            damping = contact[15, j]
            for p in range(2):
                e_crack += contact[4 + 4 * p, j]
                p_crack += contact[5 + 4 * p, j]
                friction_crack += contact[6 + 4 * p, j]
                damping += contact[7 + 4 * p, j]
            results[0, j] = contact[12, j]
            results[1, j] = e_crack + cohesive_results[0, j]
            results[2, j] = e_collar
            results[3, j] = (
                (contact[13, j] + p_crack) * dt
                + w_plastic
                + contact[16, j]
                + cohesive_results[1, j]
            )
            results[4, j] = contact[14, j] * dt
            results[5, j] = friction_crack * dt
            results[6, j] = damping * dt
            results[7, j] = contact[16, j]
        # fused, body by body: elastic forces back to the ground frame, update, next step's
        # loads; per state the sums of strain, gravity and kinetic energy, external work, |v|^2
        # and the next step's frame sums (of the new positions)
        for j in range(group):
            for e in range(5):
                totals[e, j] = 0.0
        for b in range(n_bodies):
            for j in range(group):
                frame[2, j] = cos_b[b, j]
                frame[3, j] = sin_b[b, j]
                sums[0, j] = 0.0
                sums[1, j] = 0.0
                sums[2, j] = 0.0
                sums[3, j] = 0.0
            for k in range(offsets[b], offsets[b + 1]):
                i = order[k]
                m = mass[2 * i]
                dt_m = dt * inv_mass[i]
                gx = gravity[2 * i]
                gy = gravity[2 * i + 1]
                y_ref = X[2 * i + 1]
                px = rel[2 * i]
                py = rel[2 * i + 1]
                w, o = _span(grid, node * i, node, single)
                for j in range(group):
                    c = frame[2, j]
                    s = frame[3, j]
                    fx = w[o + k0 + j]
                    fy = w[o + k0 + dof + j]
                    totals[0, j] += 0.5 * (w[o + u0 + j] * fx + w[o + u0 + dof + j] * fy)
                    totals[1, j] -= gy * (w[o + x0 + dof + j] - y_ref)
                    vx0 = w[o + v0 + j]
                    vy0 = w[o + v0 + dof + j]
                    vx = vx0 + dt_m * (w[o + f0 + j] - (c * fx - s * fy))
                    vy = vy0 + dt_m * (w[o + f0 + dof + j] - (s * fx + c * fy))
                    # kinetic energy conserved by central differences: m v(n-1/2) . v(n+1/2) / 2
                    totals[2, j] += 0.5 * m * (vx0 * vx + vy0 * vy)
                    w[o + v0 + j] = vx
                    w[o + v0 + dof + j] = vy
                    xj = w[o + x0 + j] + dt * vx
                    yj = w[o + x0 + dof + j] + dt * vy
                    w[o + x0 + j] = xj
                    w[o + x0 + dof + j] = yj
                    totals[3, j] -= m * (ground[0, j] * vx + ground[1, j] * vy) * dt
                    totals[4, j] += vx * vx + vy * vy
                    w[o + f0 + j] = gx - m * ground[2, j]
                    w[o + f0 + dof + j] = gy - m * ground[3, j]
                    # the next step's frame sums
                    sums[0, j] += m * xj
                    sums[1, j] += m * yj
                    sums[2, j] += m * (px * xj + py * yj)
                    sums[3, j] += m * (px * yj - py * xj)
            for j in range(group):
                body_sums[b, 0, j] = sums[0, j]
                body_sums[b, 1, j] = sums[1, j]
                body_sums[b, 2, j] = sums[2, j]
                body_sums[b, 3, j] = sums[3, j]
        for j in range(width):
            if not running[j]:
                continue
            r = states[j]
            motion.tallies[r, 0] += results[3, j]
            motion.tallies[r, 1] += totals[3, j]
            motion.tallies[r, 2] += results[4, j]
            motion.tallies[r, 3] += results[5, j]
            motion.tallies[r, 4] += results[6, j]
            motion.tallies[r, 5] += results[7, j]
            energies = motion.energies[r]
            energies[0] = totals[0, j]
            energies[1] = results[0, j]
            energies[2] = results[1, j]
            energies[3] = results[2, j]
            energies[4] = totals[1, j]
            energies[5] = totals[2, j]
            motion.done[r] = step + 1
            if not (math.isfinite(totals[4, j]) and math.isfinite(totals[0, j])):
                motion.alive[r] = False
                running[j] = False
                x[r] = columns[:, POSITION, j]
                v[r] = columns[:, VELOCITY, j]
                columns[:, POSITION, j] = X
                columns[:, VELOCITY, j] = 0.0
                body_sums[:, :, j] = 0.0
    for j in range(width):
        if running[j]:
            x[states[j]] = columns[:, POSITION, j]
            v[states[j]] = columns[:, VELOCITY, j]
