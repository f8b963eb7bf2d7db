"""The compiled crack contact against a plain-Python statement of its law, bit for bit.

The kernel takes shortcuts that must not change a decision: it tries the segment used last step
first, and it calls a slave open from a cross product before it computes the normal (square root,
divisions). The reference below computes every slave the long way: the projection onto each
segment in the kernel's search order, the unit normal, the gap, the damped penalty force and the
incremental Coulomb friction. Same IEEE operations in the same order, so the two must agree to
the last bit, on slaves at, just inside and just outside the face.
"""

import math

import numpy as np
import pytest

from colonna.fem import _kernels as K


def reference_crack_contact(x, v, f, slaves, masters, sign, kn, kt, cn, mu, dt, blend, state):
    """One state (x, v, f flat, 2 per node); state: dict of seg, ft, fn, fc (per slave),
    updated. Returns (elastic energy, dissipated power)."""
    energy = power = 0.0
    n_seg = masters.size - 1
    for k, s in enumerate(slaves):
        sx, sy = x[2 * s], x[2 * s + 1]
        first = max(int(state["seg"][k]), 0)
        found, xi = -1, 0.0
        for step in range(2 * n_seg):
            m = first + (step + 1) // 2 if step % 2 == 0 else first - (step + 1) // 2
            if not 0 <= m < n_seg:
                if first + step // 2 >= n_seg and first - step // 2 < 0:
                    break
                continue
            a, b = masters[m], masters[m + 1]
            dx = x[2 * b] - x[2 * a]
            dy = x[2 * b + 1] - x[2 * a + 1]
            t = ((sx - x[2 * a]) * dx + (sy - x[2 * a + 1]) * dy) / (dx * dx + dy * dy)
            if -1e-12 <= t <= 1.0 + 1e-12:
                found, xi = m, min(max(t, 0.0), 1.0)
                break
        state["seg"][k] = found
        if found < 0:
            state["ft"][k] = state["fn"][k] = state["fc"][k] = 0.0
            continue
        a, b = masters[found], masters[found + 1]
        dx = x[2 * b] - x[2 * a]
        dy = x[2 * b + 1] - x[2 * a + 1]
        length = math.sqrt(dx * dx + dy * dy)
        tx, ty = dx / length, dy / length
        nx, ny = sign * ty, -sign * tx
        px = x[2 * a] + xi * dx
        py = x[2 * a + 1] + xi * dy
        gap = (sx - px) * nx + (sy - py) * ny
        if gap >= 0.0:
            state["ft"][k] = state["fn"][k] = state["fc"][k] = 0.0
            continue
        rvx = v[2 * s] - ((1.0 - xi) * v[2 * a] + xi * v[2 * b])
        rvy = v[2 * s + 1] - ((1.0 - xi) * v[2 * a + 1] + xi * v[2 * b + 1])
        vn = rvx * nx + rvy * ny
        vt = rvx * tx + rvy * ty
        fn_el = -kn[k] * gap
        fn = max(fn_el - cn[k] * vn, 0.0)
        fc = state["fc"][k]
        cone = fn if fc == 0.0 else fc + blend * (fn - fc)
        trial = state["ft"][k] - kt[k] * vt * dt
        limit = mu * cone
        slip = 0.0
        if abs(trial) > limit:
            cone_force = limit if trial > 0.0 else -limit
            slip = cone_force * (trial - cone_force) / (kt[k] * dt)
            trial = cone_force
        energy += 0.5 * kn[k] * gap * gap + 0.5 * trial * trial / kt[k]
        power += slip + (fn - fn_el) * (-vn)
        state["ft"][k], state["fn"][k], state["fc"][k] = trial, fn, cone
        fx = fn * nx + trial * tx
        fy = fn * ny + trial * ty
        f[2 * s] += fx
        f[2 * s + 1] += fy
        f[2 * a] -= (1.0 - xi) * fx
        f[2 * a + 1] -= (1.0 - xi) * fy
        f[2 * b] -= xi * fx
        f[2 * b + 1] -= xi * fy
    return energy, power


def crack_face(rng, n_master=6, height=0.3):
    """A slightly bent master face (nodes 0 .. n_master - 1, x near 0, rising) and slaves
    (the following nodes) at, just inside, just outside and well off the face, some of them
    at master heights (as on the conforming crack) and two beyond its ends."""
    ys = np.linspace(0.0, height, n_master)
    master_xy = np.column_stack([rng.normal(scale=1e-4, size=n_master), ys])
    # offsets normal to the face (m): exact contact, round-off either side, small and large
    offsets = [0.0, 0.0, 1e-17, -1e-17, 1e-15, -1e-15, 1e-12, -1e-12, 1e-7, -1e-7, 1e-4, -1e-4]
    slave_xy = []
    for g in offsets:
        m = rng.integers(0, n_master - 1)
        t = rng.choice([0.0, 1.0, rng.uniform()])  # master heights and between
        p = master_xy[m] + t * (master_xy[m + 1] - master_xy[m])
        d = master_xy[m + 1] - master_xy[m]
        normal = np.array([d[1], -d[0]]) / np.hypot(*d)
        slave_xy.append(p + g * normal)
    slave_xy += [master_xy[0] - [0.0, 0.01], master_xy[-1] + [0.0, 0.01]]
    xy = np.vstack([master_xy, slave_xy])
    masters = np.arange(n_master, dtype=np.int64)
    slaves = np.arange(n_master, len(xy), dtype=np.int64)
    return xy.ravel(), masters, slaves


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_crack_contact_kernel_is_the_node_to_segment_law_to_the_bit(sign):
    rng = np.random.default_rng(7 if sign > 0 else 11)
    x, masters, slaves = crack_face(rng)
    n_dofs = x.size
    n = slaves.size
    kn = rng.uniform(1e9, 2e9, n)
    kt = rng.uniform(0.5e9, 1e9, n)
    cn = rng.uniform(1e3, 1e4, n)
    mu, dt, blend = 0.6, 6e-6, 0.05
    # one state in the one-state layout of Scratch.work: positions, velocities, forces, ...
    work = np.zeros(K.COMPONENTS * n_dofs)
    state = {"seg": -np.ones(n, np.int64), "ft": np.zeros(n), "fn": np.zeros(n), "fc": np.zeros(n)}
    seg, ft, fn, fc = (state[key].reshape(1, n).copy() for key in ("seg", "ft", "fn", "fc"))
    out = np.zeros((4, 1))  # energy, power, and of it the friction and damping power
    decided_open = decided_closed = 0
    for step in range(25):  # contact history: friction, filtered cone, segment memory
        moved = x + rng.normal(scale=1e-9, size=n_dofs) * step
        velocity = rng.normal(scale=1e-3, size=n_dofs)
        work[:n_dofs] = moved
        work[n_dofs : 2 * n_dofs] = velocity
        work[2 * n_dofs : 3 * n_dofs] = 0.0
        K.crack_contact(
            work,
            True,
            np.ones(1, np.bool_),
            np.zeros(1, np.int64),
            slaves,
            masters,
            sign,
            kn,
            kt,
            cn,
            mu,
            dt,
            seg,
            ft,
            fn,
            fc,
            blend,
            out,
        )
        forces = np.zeros(n_dofs)
        energy, power = reference_crack_contact(
            moved, velocity, forces, slaves, masters, sign, kn, kt, cn, mu, dt, blend, state
        )
        np.testing.assert_array_equal(work[2 * n_dofs : 3 * n_dofs], forces)
        np.testing.assert_array_equal(seg[0], state["seg"])
        for kernel, reference in ((ft, "ft"), (fn, "fn"), (fc, "fc")):
            np.testing.assert_array_equal(kernel[0], state[reference])
        assert (out[0, 0], out[1, 0]) == (energy, power)
        assert out[2, 0] + out[3, 0] == pytest.approx(power, rel=1e-12, abs=1e-300)
        decided_closed += int((state["fn"] > 0.0).sum())
        decided_open += int(((state["fn"] == 0.0) & (state["seg"] >= 0)).sum())
    # the cases exercised: slaves found open and slaves pressed, over the steps
    assert decided_open > 0 and decided_closed > 0
