"""Compiled (numba) kernels of the rocking solvers. Private: use :mod:`rigid.solve`.

Everything is written per unit of the half block's inertia J0 and with the ground acceleration
divided by g. For rocking on the side ``s = sign(theta)`` (s = +1 or -1):

nonlinear   theta'' = -p^2 [sin(s alpha - theta) + (ug''/g) cos(s alpha - theta)] + M_c / (2 J0)
                      - p^2 lambda [sin(s alpha - theta) - cos(alpha) sin(theta)]   (top load)
linear      theta'' =  p^2 theta - p^2 (s alpha + ug''/g)                         + M_c / (2 J0)

(lambda = top load / m g, see rigid.block; the linear model takes a top load through the
equivalent free block of :func:`rigid.solve.kernel_params`, so P_LOAD is 0 there)

with the collar moment M_c / (2 J0) = -k_a (r - 1) sin(theta) cos(theta) / (2 r) - k_l sin(theta)
cos(theta) / 2, r = sqrt(1 + sin^2(theta) / 4) (exact, see rigid.collars) or -k_l theta / 2
(linear model). An impact at theta = 0 maps
theta' -> nu theta'.

Parameter vector ``P`` layout is given by the ``P_*`` indices below.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..core.jit_cache import ensure_fresh
from ..core.tables import table_value

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)

(
    P_P2,
    P_ALPHA,
    P_NONLINEAR,
    P_GROUND,
    P_AG,
    P_OMEGA,
    P_PHASE,
    P_TEND,
    P_KA,
    P_KL,
    P_NU,
    P_UPLIFT,
    P_TH0,
    P_OM0,
    P_LOAD,
    P_NHREC,
    P_VERT,
    P_TRAP_E,
    P_TRAP_TH,
    P_SIN_ALPHA,
    P_COS_ALPHA,
) = range(21)
N_PARAMS = 21  # P_TH0, P_OM0: initial rotation (rad) and angular velocity (rad/s), 0: at rest
# P_LOAD: lambda = top load / (m g). P_NHREC: how many of the rows of (rec_t, rec_a) are the
# horizontal record; P_VERT = 1: the rows after them are the vertical ground acceleration / g
# (piecewise linear, zero outside), 0: no vertical motion. P_TRAP_E, P_TRAP_TH: with collars,
# collar_barrier's (V_max, theta_max), 0 until computed (by rk_run when first needed, or once
# for a whole spectrum: they depend on the block and the collars, not on the pulse).
# P_SIN_ALPHA, P_COS_ALPHA: sin and cos of alpha, so that the equation of motion takes the
# sine and cosine of s alpha - theta from those of theta (two transcendentals a stage less)

GROUND_NONE, GROUND_HARMONIC, GROUND_RECORD = 0, 1, 2

# run status
RUNNING, OVERTURNED, AT_REST, REACHED_END = 0, 1, 2, 3
# spectrum mode codes
SAFE, AFTER_IMPACT, WITHOUT_IMPACT = 0, 1, 2

HALF_PI = 0.5 * math.pi
MAX_IMPACTS = 100_000
# a post-impact hop shorter than this fraction of 1/p counts as coming to rest
REST_HOP = 1e-9


@njit(cache=True)
def make_params(
    p, alpha, nonlinear, ground_kind, ag, omega, phase, t_end, ka, kl, nu, uplift, load
):
    P = np.zeros(N_PARAMS)
    P[P_LOAD] = load
    P[P_P2] = p * p
    P[P_ALPHA] = alpha
    P[P_SIN_ALPHA] = math.sin(alpha)
    P[P_COS_ALPHA] = math.cos(alpha)
    P[P_NONLINEAR] = 1.0 if nonlinear else 0.0
    P[P_GROUND] = ground_kind
    P[P_AG] = ag
    P[P_OMEGA] = omega
    P[P_PHASE] = phase
    P[P_TEND] = t_end
    P[P_KA] = ka
    P[P_KL] = kl
    P[P_NU] = nu
    P[P_UPLIFT] = uplift
    return P


# ------------------------------------------------------------------------------------------
# ground motion and equation of motion
# ------------------------------------------------------------------------------------------


@njit(cache=True)
def ground_over_g(t, P, rec_t, rec_a):
    kind = P[P_GROUND]
    if kind == GROUND_HARMONIC:
        if t < 0.0 or t > P[P_TEND]:
            return 0.0
        return P[P_AG] * math.sin(P[P_OMEGA] * t + P[P_PHASE])
    if kind == GROUND_RECORD:
        n = int(P[P_NHREC])
        return table_value(t, rec_t[:n], rec_a[:n])
    return 0.0


@njit(cache=True)
def vertical_over_g(t, P, rec_t, rec_a):
    """Vertical ground acceleration / g (upward positive) at t."""
    if P[P_VERT] == 0.0:
        return 0.0
    n = int(P[P_NHREC])
    return table_value(t, rec_t[n:], rec_a[n:])


@njit(cache=True)
def angular_acceleration(t, theta, s, P, rec_t, rec_a):
    """theta'' at time t of the block at theta rocking on side s."""
    ug = ground_over_g(t, P, rec_t, rec_a)
    weight = 1.0 + vertical_over_g(t, P, rec_t, rec_a)  # (g + vg'') / g
    return angular_acceleration_given_ground(ug, weight, theta, s, P)


@njit(cache=True)
def angular_acceleration_given_ground(ug, weight, theta, s, P):
    """theta'' of the block at theta on side s under the ground's ug''/g and (g + vg'')/g: the
    equation of motion without the ground's clock, so that stages sharing a time share it."""
    p2 = P[P_P2]
    lam = P[P_LOAD]
    if P[P_NONLINEAR] > 0.5:
        sn = math.sin(theta)
        cs = math.cos(theta)
        # sin and cos of s alpha - theta, by the angle-difference formulas
        s_sin_alpha = s * P[P_SIN_ALPHA]
        sin_arg = s_sin_alpha * cs - P[P_COS_ALPHA] * sn
        cos_arg = P[P_COS_ALPHA] * cs + s_sin_alpha * sn
        acc = -p2 * (weight * sin_arg + ug * cos_arg)
        if lam != 0.0:
            acc -= p2 * lam * (sin_arg - P[P_COS_ALPHA] * sn)
        if P[P_KA] != 0.0 or P[P_KL] != 0.0:
            sc = sn * cs
            root = math.sqrt(1.0 + 0.25 * sn * sn)
            acc -= P[P_KA] * (root - 1.0) * sc / (2.0 * root) + 0.5 * P[P_KL] * sc
    else:
        acc = (
            p2 * (weight + 2.0 * lam) * theta
            - p2 * ((weight + lam) * s * P[P_ALPHA] + ug)
            - 0.5 * P[P_KL] * theta
        )
    return acc


@njit(cache=True)
def mechanical_energy(theta, omega, P):
    """Kinetic + gravity + collar potential energy per J0 (rad^2/s^2), zero at rest upright."""
    p2 = P[P_P2]
    a = P[P_ALPHA]
    x = abs(theta)
    if P[P_NONLINEAR] > 0.5:
        e = 0.5 * omega * omega + potential_energy(math.sin(x), math.cos(x), P)
    else:
        e = 0.5 * omega * omega + p2 * (a * x - 0.5 * x * x) + 0.25 * P[P_KL] * theta * theta
    return e


@njit(cache=True)
def potential_energy(sin_x, cos_x, P):
    """Nonlinear model: gravity + top load + collar potential per J0 (rad^2/s^2) at |theta| = x,
    from sin x and cos x (zero upright; cos(alpha - x) by the angle-difference formula)."""
    p2 = P[P_P2]
    ca = P[P_COS_ALPHA]
    sa = P[P_SIN_ALPHA]
    e = p2 * (ca * (cos_x - 1.0) + sa * sin_x)
    # the top load's potential: its height 2h cos(theta) + b sin|theta| above its rest
    e += p2 * P[P_LOAD] * (2.0 * ca * (cos_x - 1.0) + sa * sin_x)
    root = math.sqrt(1.0 + 0.25 * sin_x * sin_x)
    return e + P[P_KA] * (root - 1.0) ** 2 + 0.25 * P[P_KL] * sin_x * sin_x


@njit(cache=True)
def energy_barrier(P):
    """Gravity potential at the unstable equilibrium (|theta| = alpha without a top load):
    below it the free block can never overturn."""
    a = P[P_ALPHA]
    if P[P_NONLINEAR] > 0.5:
        lam = P[P_LOAD]
        tc = critical_angle(P)
        return P[P_P2] * (
            math.cos(a - tc)
            - math.cos(a)
            + lam * (2.0 * math.cos(a) * (math.cos(tc) - 1.0) + math.sin(a) * math.sin(tc))
        )
    return 0.5 * P[P_P2] * a * a


@njit(cache=True)
def collar_barrier(P):
    """With collars: (V_max, theta_max), the largest potential V(theta) = gravity + top load +
    collar springs on [0, pi/2] (mechanical_energy at rest, symmetric in theta) and where it is
    (sampled at 2048 points: a little low at worst, so a trap it declares is a trap). A free
    block with less energy can never reach pi/2, where overturning is declared."""
    n = 2048
    best = 0.0
    where = HALF_PI
    for k in range(1, n + 1):
        th = HALF_PI * k / n
        v = mechanical_energy(th, 0.0, P)
        if v > best:
            best = v
            where = th
    return best, where


@njit(cache=True)
def turning_point(theta, energy, P):
    """The first |theta'| >= |theta| where the free block of mechanical energy ``energy``
    stops (V(theta') = energy), found by stepping out by pi/4096 and refining the root in the
    step that gets there; pi/2 if none before. The steps rotate (sin, cos) of the angle instead
    of evaluating them (rounding drift ~1e-13 over the quarter turn: it can only move the
    bracketing step when V is that close to the energy at a step's end)."""
    x0 = abs(theta)
    step = HALF_PI / 2048
    cos_step = math.cos(step)
    sin_step = math.sin(step)
    sn = math.sin(x0)
    cs = math.cos(x0)
    x1 = x0
    while x1 < HALF_PI:
        if x1 + step < HALF_PI:
            x1 += step
            sn, cs = sn * cos_step + cs * sin_step, cs * cos_step - sn * sin_step
        else:
            x1 = HALF_PI
            sn = math.sin(x1)
            cs = math.cos(x1)
        if _potential(x1, sn, cs, P) >= energy:
            return _potential_root(energy, max(x0, x1 - step), x1, P)
    return HALF_PI


@njit(cache=True)
def _potential(x, sin_x, cos_x, P):
    """V at |theta| = x of the model at hand (the nonlinear one from sin x and cos x)."""
    if P[P_NONLINEAR] > 0.5:
        return potential_energy(sin_x, cos_x, P)
    return mechanical_energy(x, 0.0, P)


@njit(cache=True, inline="always")
def _secant(lo, hi, flo, fhi):
    """The regula falsi point of the bracket [lo, hi], or its midpoint where that falls outside."""
    mid = (lo * fhi - hi * flo) / (fhi - flo)
    return mid if lo < mid < hi else 0.5 * (lo + hi)


@njit(cache=True, inline="always")
def _illinois(lo, hi, flo, fhi, mid, fm, upper, side):
    """One Illinois update of the bracket [lo, hi] (values flo, fhi) with the point mid (value
    fm): it replaces hi where ``upper`` (mid lies on hi's side of the root), else lo, and halves
    the value kept at the other end when the same end moved last time (``side``: -1 hi, 1 lo,
    0 neither). Returns (lo, hi, flo, fhi, side). The root finders below share it and keep their
    own loops: a finder taking the function as an argument stops numba from caching."""
    if upper:
        if side == -1:
            flo *= 0.5
        return lo, mid, flo, fm, -1
    if side == 1:
        fhi *= 0.5
    return mid, hi, fm, fhi, 1


@njit(cache=True)
def _potential_root(energy, lo, hi, P):
    """x in [lo, hi] where V(x) = energy, V(lo) < energy <= V(hi) (Illinois); the end of the
    final bracket on the V >= energy side."""
    flo = _potential(lo, math.sin(lo), math.cos(lo), P) - energy
    fhi = _potential(hi, math.sin(hi), math.cos(hi), P) - energy
    if flo >= 0.0:
        return lo
    side = 0
    for _ in range(200):
        if hi - lo <= 4e-16 * max(1.0, abs(hi)) or fhi == flo:
            break
        mid = _secant(lo, hi, flo, fhi)
        fm = _potential(mid, math.sin(mid), math.cos(mid), P) - energy
        lo, hi, flo, fhi, side = _illinois(lo, hi, flo, fhi, mid, fm, fm >= 0.0, side)
    return hi


@njit(cache=True)
def critical_angle(P):
    """The free block's unstable equilibrium: atan((1 + lambda) / (1 + 2 lambda) tan alpha)
    (alpha without a top load; the linear model's alpha is already the equivalent block's)."""
    lam = P[P_LOAD]
    if lam == 0.0 or P[P_NONLINEAR] < 0.5:
        return P[P_ALPHA]
    return math.atan((1.0 + lam) / (1.0 + 2.0 * lam) * math.tan(P[P_ALPHA]))


@njit(cache=True)
def _released(P):
    return P[P_TH0] != 0.0 or P[P_OM0] != 0.0


@njit(cache=True)
def _release_state(P):
    """(t, theta, omega, side) of a block released at t = 0 from the initial state of P."""
    th = P[P_TH0]
    om = P[P_OM0]
    s = 1.0 if (th > 0.0 or (th == 0.0 and om > 0.0)) else -1.0
    return 0.0, th, om, s


@njit(cache=True)
def ground_end(P, rec_t):
    """When the ground is still for good: the end of the horizontal motion or of the vertical
    one, whichever is later."""
    end = 0.0
    n = int(P[P_NHREC])
    if P[P_GROUND] == GROUND_HARMONIC:
        end = P[P_TEND]
    elif P[P_GROUND] == GROUND_RECORD:
        end = rec_t[n - 1]
    if P[P_VERT] != 0.0:
        end = max(end, rec_t[rec_t.size - 1])
    return end


@njit(cache=True)
def next_uplift(t, P, rec_t, rec_a):
    """Earliest time >= t at which |ug''/g| reaches the uplift level, and the sign of ug'' there.

    Returns (-1, 0) when the ground never gets there again.
    """
    thr = P[P_UPLIFT]
    kind = P[P_GROUND]
    if P[P_VERT] != 0.0:
        return _next_uplift_scan(t, P, rec_t, rec_a)
    if kind == GROUND_HARMONIC:
        ag = abs(P[P_AG])
        # rocking needs the ground to exceed the uplift level, touching it is not enough
        if ag <= thr * (1.0 + 1e-12) or t > P[P_TEND]:
            return -1.0, 0.0
        r = thr / ag
        psi1 = math.asin(r)
        psi_now = P[P_OMEGA] * max(t, 0.0) + P[P_PHASE]
        base = math.floor(psi_now / math.pi) * math.pi
        x = psi_now - base
        if x < psi1:
            psi = base + psi1
        elif x < math.pi - psi1 - 1e-12:
            psi = psi_now
        else:
            psi = base + math.pi + psi1
        t_up = (psi - P[P_PHASE]) / P[P_OMEGA]
        if t_up > P[P_TEND]:
            return -1.0, 0.0
        # sign of sin on the half period that contains psi
        k = math.floor(psi / math.pi)
        sgn = 1.0 if (k % 2 == 0) else -1.0
        if P[P_AG] < 0.0:
            sgn = -sgn
        return max(t_up, t), sgn
    if kind == GROUND_RECORD:
        n = int(P[P_NHREC])
        if t > rec_t[n - 1]:
            return -1.0, 0.0
        # as for a pulse, the ground must exceed the level: a record that only touches it
        # would start a rocking that ends at once, at that same instant, again and again
        exceeds = thr * (1.0 + 1e-12)
        ug = ground_over_g(t, P, rec_t, rec_a)
        if abs(ug) > exceeds:
            return t, 1.0 if ug > 0.0 else -1.0
        i0 = np.searchsorted(rec_t, t)
        prev_t = t
        prev_a = ug
        for i in range(i0, n):
            ai = rec_a[i]
            if abs(ai) > exceeds:
                level = thr if ai > 0.0 else -thr
                if ai == prev_a:
                    return rec_t[i], 1.0 if ai > 0.0 else -1.0
                w = (level - prev_a) / (ai - prev_a)
                w = min(max(w, 0.0), 1.0)
                return prev_t + w * (rec_t[i] - prev_t), 1.0 if ai > 0.0 else -1.0
            prev_t = rec_t[i]
            prev_a = ai
        return -1.0, 0.0
    return -1.0, 0.0


@njit(cache=True)
def _uplift_margin(t, P, rec_t, rec_a):
    """|ug''|/g - (uplift level at (g + vg'')): > 0 where the ground lifts the block (Eq. 2,
    the level being slope (1 + lambda + vg''/g), slope = P_UPLIFT / (1 + lambda))."""
    slope = P[P_UPLIFT] / (1.0 + P[P_LOAD])
    weight = 1.0 + vertical_over_g(t, P, rec_t, rec_a)
    return abs(ground_over_g(t, P, rec_t, rec_a)) - slope * (weight + P[P_LOAD])


@njit(cache=True)
def _next_uplift_scan(t, P, rec_t, rec_a):
    """next_uplift with vertical motion: the uplift level moves with vg'', so the first time
    the margin turns positive is found by scanning (steps of 1/4000 of the pulse period, or a
    quarter of the finest table spacing) and bisection."""
    end = ground_end(P, rec_t)
    if P[P_GROUND] == GROUND_HARMONIC:
        step = 2.0 * math.pi / P[P_OMEGA] / 4000.0
    else:
        step = 1e-3
    for i in range(1, rec_t.size):
        if rec_t[i] > rec_t[i - 1]:
            step = min(step, 0.25 * (rec_t[i] - rec_t[i - 1]))
    step = max(step, 1e-7)
    a = t
    if _uplift_margin(a, P, rec_t, rec_a) > 0.0:
        return a, 1.0 if ground_over_g(a, P, rec_t, rec_a) > 0.0 else -1.0
    while a < end:
        b = min(a + step, end)
        if _uplift_margin(b, P, rec_t, rec_a) > 0.0:
            for _ in range(60):
                m = 0.5 * (a + b)
                if _uplift_margin(m, P, rec_t, rec_a) > 0.0:
                    b = m
                else:
                    a = m
            return b, 1.0 if ground_over_g(b, P, rec_t, rec_a) > 0.0 else -1.0
        a = b
    return -1.0, 0.0


# ------------------------------------------------------------------------------------------
# DOPRI5 (Dormand-Prince 5(4)) with 4th-order dense output and exact event location
# ------------------------------------------------------------------------------------------

_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0])
_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [1 / 5, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
    ]
)
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = np.array([-71 / 57600, 0.0, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40])
_PD = np.array(
    [
        [1.0, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0.0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [0.0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
        [0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ]
)


@njit(cache=True)
def _dense(sigma, h, y0, y1, K0, K1):
    """DOPRI5 continuous extension at t + sigma h: returns (theta, omega)."""
    s1 = sigma
    s2 = s1 * sigma
    s3 = s2 * sigma
    s4 = s3 * sigma
    q0 = 0.0
    q1 = 0.0
    for j in range(7):
        w = _PD[j, 0] * s1 + _PD[j, 1] * s2 + _PD[j, 2] * s3 + _PD[j, 3] * s4
        q0 += K0[j] * w
        q1 += K1[j] * w
    return y0 + h * q0, y1 + h * q1


@njit(cache=True)
def _dense_root(component, level, h, y0, y1, K0, K1, lo, hi):
    """Root sigma in [lo, hi] of dense component (0: theta, 1: omega) == level (Illinois)."""
    flo = _dense(lo, h, y0, y1, K0, K1)[component] - level
    fhi = _dense(hi, h, y0, y1, K0, K1)[component] - level
    side = 0
    for _ in range(200):
        if fhi == flo:
            break
        mid = _secant(lo, hi, flo, fhi)
        fm = _dense(mid, h, y0, y1, K0, K1)[component] - level
        if fm == 0.0:
            return mid
        lo, hi, flo, fhi, side = _illinois(
            lo, hi, flo, fhi, mid, fm, (fm > 0.0) == (fhi > 0.0), side
        )
        if hi - lo <= 4e-16 * max(1.0, abs(hi)):
            break
    return lo if abs(flo) < abs(fhi) else hi


@njit(cache=True)
def rk_run(P, rec_t, rec_a, t_stop, rtol, atol, early_exit, dt_out, out, impacts):
    """Integrate from rest at t = 0 to t_stop (or an earlier end).

    out:      (max_out, 3) array filled with (t, theta, omega) every dt_out (dt_out <= 0: none).
    impacts:  (max_imp, 3) array filled with (t, omega_before, omega_after).
    Returns (status, n_impacts, max_abs_theta, t_end, n_out, t_overturn).
    """
    K0 = np.zeros(7)
    K1 = np.zeros(7)
    p = math.sqrt(P[P_P2])
    alpha = P[P_ALPHA]
    nu = P[P_NU]
    t_free = ground_end(P, rec_t)
    has_collars = P[P_KA] != 0.0 or P[P_KL] != 0.0
    barrier = energy_barrier(P)
    # with collars the springs raise the barrier (a swing past alpha may be held): the largest
    # potential on the way to pi/2, and the free block's peak taken from its turning point
    if has_collars and P[P_TRAP_E] == 0.0:
        P[P_TRAP_E], P[P_TRAP_TH] = collar_barrier(P)
    trap_energy, trap_angle = P[P_TRAP_E], P[P_TRAP_TH]
    # linear model: the free block diverges once beyond its unstable equilibrium moving outward,
    # at alpha p^2 / (p^2 - k_l / 2) with collars (none if the collars make it stable)
    theta_c = critical_angle(P)
    theta_unstable = theta_c
    if has_collars:
        theta_unstable = HALF_PI
        lam = P[P_P2] - 0.5 * P[P_KL]
        if P[P_NONLINEAR] < 0.5 and lam > 0.0:
            theta_unstable = min(HALF_PI, alpha * P[P_P2] / lam)
    max_out = out.shape[0]
    n_out = 0
    next_out = 0.0
    n_imp = 0
    max_theta = 0.0
    t_over = -1.0

    if _released(P):  # released at t = 0, tilted or spinning
        t, th, om, s = _release_state(P)
    else:
        t, s_up = next_uplift(0.0, P, rec_t, rec_a)
        if t < 0.0:
            return AT_REST, 0, 0.0, t_stop, _fill_rest(out, 0, 0.0, t_stop, dt_out), -1.0
        # the block sits upright until it lifts
        n_out = _fill_rest(out, 0, 0.0, t, dt_out)
        if dt_out > 0.0:
            next_out = n_out * dt_out
        s = -s_up
        th = 0.0
        om = 0.0
    h = 1e-3 / max(p, P[P_OMEGA])
    # the largest step: a tenth of the shortest period at hand, the pulse's while the ground
    # moves, the block's own once it is still (free rocking, as for a record)
    h_max_free = 0.1 / p
    h_max = 0.1 / max(p, P[P_OMEGA]) if P[P_GROUND] == GROUND_HARMONIC else h_max_free
    status = RUNNING
    steps = 0
    # first same as last: the acceleration at (t, th, s) is kept between steps, so a step after an
    # accepted or a rejected one costs six evaluations instead of seven (same numbers: it is the
    # very evaluation the step would repeat); NaN: to be evaluated (start, impact, lift-off)
    acc_now = math.nan
    while status == RUNNING:
        if t >= t_stop:
            status = REACHED_END
            break
        steps += 1
        if steps > 50_000_000:
            status = REACHED_END
            break
        h = min(h, h_max if t < t_free else h_max_free, t_stop - t)
        if t < t_free < t + h:
            h = t_free - t  # land on the end of the ground motion (a kink in the forcing)
        # --- one DOPRI5 step ---------------------------------------------------------------
        if math.isnan(acc_now):
            acc_now = angular_acceleration(t, th, s, P, rec_t, rec_a)
        K0[0] = om
        K1[0] = acc_now
        ug = 0.0
        weight = 1.0
        for i in range(1, 6):
            y0 = th
            y1 = om
            for j in range(i):
                y0 += h * _A[i, j] * K0[j]
                y1 += h * _A[i, j] * K1[j]
            K0[i] = y1
            t_stage = t + _C[i] * h
            ug = ground_over_g(t_stage, P, rec_t, rec_a)
            weight = 1.0 + vertical_over_g(t_stage, P, rec_t, rec_a)
            K1[i] = angular_acceleration_given_ground(ug, weight, y0, s, P)
        n0 = th
        n1 = om
        for j in range(6):
            n0 += h * _B[j] * K0[j]
            n1 += h * _B[j] * K1[j]
        K0[6] = n1
        # the last stage is at t + h too (_C[5] = 1): its ground is the one just evaluated
        K1[6] = angular_acceleration_given_ground(ug, weight, n0, s, P)
        e0 = 0.0
        e1 = 0.0
        for j in range(7):
            e0 += h * _E[j] * K0[j]
            e1 += h * _E[j] * K1[j]
        sc0 = atol + rtol * max(abs(th), abs(n0))
        sc1 = atol * p + rtol * max(abs(om), abs(n1))
        err = math.sqrt(0.5 * ((e0 / sc0) ** 2 + (e1 / sc1) ** 2))
        if err > 1.0:
            h *= max(0.2, 0.9 * err**-0.2)
            continue
        # --- accepted: events inside [t, t + h] ----------------------------------------------
        sigma_end = 1.0
        impact = s * n0 < 0.0 or (n0 == 0.0 and n1 * s < 0.0)
        if impact:
            sigma_end = _dense_root(0, 0.0, h, th, om, K0, K1, 0.0, 1.0)
        over = abs(n0) >= HALF_PI and not impact
        if over:
            sigma_end = _dense_root(
                0, HALF_PI * (1.0 if n0 > 0.0 else -1.0), h, th, om, K0, K1, 0.0, 1.0
            )
        # extreme rotation where omega changes sign
        om_end = _dense(sigma_end, h, th, om, K0, K1)[1]
        if om * om_end < 0.0:
            sig = _dense_root(1, 0.0, h, th, om, K0, K1, 0.0, sigma_end)
            max_theta = max(max_theta, abs(_dense(sig, h, th, om, K0, K1)[0]))
        # output samples
        t_event = t + sigma_end * h
        if dt_out > 0.0:
            while n_out < max_out and next_out <= t_event:
                y = _dense((next_out - t) / h, h, th, om, K0, K1)
                out[n_out, 0] = next_out
                out[n_out, 1] = y[0]
                out[n_out, 2] = y[1]
                n_out += 1
                next_out = n_out * dt_out
        if over:
            t = t_event
            th = HALF_PI * (1.0 if n0 > 0.0 else -1.0)
            max_theta = HALF_PI
            status = OVERTURNED
            t_over = t
            break
        if impact:
            om_before = _dense(sigma_end, h, th, om, K0, K1)[1]
            t = t_event
            th = 0.0
            om = nu * om_before
            s = -s
            if n_imp < impacts.shape[0]:
                impacts[n_imp, 0] = t
                impacts[n_imp, 1] = om_before
                impacts[n_imp, 2] = om
            n_imp += 1
            acc0 = angular_acceleration(t, 0.0, s, P, rec_t, rec_a)
            acc_now = acc0
            resting = n_imp >= MAX_IMPACTS or om == 0.0
            if not resting and om * acc0 < 0.0:
                resting = 2.0 * abs(om / acc0) * p < REST_HOP
            if resting:
                t_up, s_up = next_uplift(t, P, rec_t, rec_a)
                if t_up < 0.0:
                    status = AT_REST
                    n_out = _fill_rest(out, n_out, next_out, t_stop, dt_out)
                    break
                n_out = _fill_rest(out, n_out, next_out, min(t_up, t_stop), dt_out)
                if dt_out > 0.0:
                    next_out = n_out * dt_out
                t = t_up
                om = 0.0
                s = -s_up
                acc_now = math.nan
            elif early_exit and not has_collars and t >= t_free and 0.5 * om * om < barrier:
                status = AT_REST
                break
            elif early_exit and has_collars and t >= t_free and 0.5 * om * om < trap_energy:
                # the swing that starts here is the largest left: its turning point is the peak
                max_theta = max(max_theta, turning_point(0.0, 0.5 * om * om, P))
                status = AT_REST
                break
            h = max(h, 1e-6 / p)
            continue
        # plain step
        t = t + h
        th = n0
        om = n1
        acc_now = K1[6]
        max_theta = max(max_theta, abs(th))
        if t >= t_free:
            if (
                s * th > theta_unstable
                and th * om > 0.0
                and (not has_collars or P[P_NONLINEAR] < 0.5)
            ):
                status = OVERTURNED  # beyond the unstable equilibrium, moving outward
                t_over = t
                max_theta = HALF_PI
                break
            # trapped in the well: inside |theta| < alpha without the energy to reach alpha;
            # a swing still going out peaks at its turning point (no loss before it)
            if (
                early_exit
                and not has_collars
                and abs(th) < theta_c
                and mechanical_energy(th, om, P) < barrier
            ):
                if th * om > 0.0:
                    max_theta = max(max_theta, turning_point(th, mechanical_energy(th, om, P), P))
                status = AT_REST
                break
            # with collars: swinging out below the largest potential on the way to pi/2; the
            # swing's turning point (no loss before it) is the peak, later swings are smaller
            if (
                early_exit
                and has_collars
                and th * om > 0.0
                and abs(th) < trap_angle
                and mechanical_energy(th, om, P) < trap_energy
            ):
                max_theta = max(max_theta, turning_point(th, mechanical_energy(th, om, P), P))
                status = AT_REST
                break
        h *= min(5.0, 0.9 * max(err, 1e-10) ** -0.2)
    return status, n_imp, max_theta, t, n_out, t_over


@njit(cache=True)
def _fill_rest(out, n_out, t_from, t_to, dt_out):
    """Fill output rows with the block at rest from t_from to t_to."""
    if dt_out <= 0.0:
        return n_out
    while n_out < out.shape[0] and n_out * dt_out <= t_to:
        out[n_out, 0] = n_out * dt_out
        out[n_out, 1] = 0.0
        out[n_out, 2] = 0.0
        n_out += 1
    return n_out


# ------------------------------------------------------------------------------------------
# Linear model, free block (no collars), harmonic pulse: exact closed form between events
# ------------------------------------------------------------------------------------------
#
# On side s, with tau = t - t0 and C = (a_p/g) / (1 + Omega^2/p^2) (Eq. 8-9, for a piece that
# starts at t0 instead of 0):
#   pulse: theta = s alpha + C sin(Omega t + phi) + A cosh(p tau) + (B/p) sinh(p tau)
#   free:  theta = s alpha + A cosh(p tau) + (B/p) sinh(p tau)            (corrected Eq. 11)
# with A = theta0 - s alpha - C sin(Omega t0 + phi), B = theta0' - C Omega cos(Omega t0 + phi).


@njit(cache=True)
def _lin_state(t, seg, P):
    """(theta, omega) of the closed-form segment seg = (t0, s, A, B, C) at time t."""
    p = math.sqrt(P[P_P2])
    tau = t - seg[0]
    ch = math.cosh(p * tau)
    sh = math.sinh(p * tau)
    psi = P[P_OMEGA] * t + P[P_PHASE]
    th = seg[1] * P[P_ALPHA] + seg[4] * math.sin(psi) + seg[2] * ch + seg[3] / p * sh
    om = seg[4] * P[P_OMEGA] * math.cos(psi) + seg[2] * p * sh + seg[3] * ch
    return th, om


@njit(cache=True)
def _lin_segment(t0, th0, om0, s, pulse_on, P, seg):
    p2 = P[P_P2]
    C = 0.0
    if pulse_on:
        C = P[P_AG] / (1.0 + P[P_OMEGA] ** 2 / p2)
    psi = P[P_OMEGA] * t0 + P[P_PHASE]
    seg[0] = t0
    seg[1] = s
    seg[2] = th0 - s * P[P_ALPHA] - C * math.sin(psi)
    seg[3] = om0 - C * P[P_OMEGA] * math.cos(psi)
    seg[4] = C


@njit(cache=True)
def _lin_root(component, level, seg, P, a, b):
    """Root in [a, b] of the closed-form theta (0) or omega (1) minus level (Illinois), as
    :func:`_dense_root`."""
    lo, hi = a, b
    flo = _lin_state(lo, seg, P)[component] - level
    fhi = _lin_state(hi, seg, P)[component] - level
    side = 0
    for _ in range(200):
        if fhi == flo:
            break
        mid = _secant(lo, hi, flo, fhi)
        fm = _lin_state(mid, seg, P)[component] - level
        if fm == 0.0:
            return mid
        lo, hi, flo, fhi, side = _illinois(
            lo, hi, flo, fhi, mid, fm, (fm > 0.0) == (fhi > 0.0), side
        )
        if hi - lo <= 4e-16 * max(1.0, abs(hi)):
            break
    return lo if abs(flo) < abs(fhi) else hi


@njit(cache=True)
def linear_run(P, t_stop, early_exit, segs, impacts):
    """Exact event-driven response of the linearised free block to a harmonic pulse.

    segs:    (max_seg, 6) array receiving (t0, s, A, B, C, t1) for every closed-form piece.
    impacts: (max_imp, 3) array receiving (t, omega_before, omega_after).
    Returns (status, n_impacts, max_abs_theta, t_end, n_segs, t_overturn).
    """
    p = math.sqrt(P[P_P2])
    alpha = P[P_ALPHA]
    nu = P[P_NU]
    t_pulse = P[P_TEND]
    seg = np.zeros(5)
    h_max = 0.05 / max(p, P[P_OMEGA])
    n_seg = 0
    n_imp = 0
    max_theta = 0.0
    empty = np.zeros(1)

    if _released(P):  # released at t = 0, tilted or spinning
        t, th, om, s = _release_state(P)
    else:
        t, s_up = next_uplift(0.0, P, empty, empty)
        if t < 0.0:
            return AT_REST, 0, 0.0, t_stop, 0, -1.0
        s = -s_up
        th = 0.0
        om = 0.0
    status = RUNNING
    t_over = -1.0
    while status == RUNNING:
        if t >= t_stop:
            status = REACHED_END
            break
        pulse_on = t < t_pulse
        _lin_segment(t, th, om, s, pulse_on, P, seg)
        t_seg_end = t_stop
        event = 0  # 0: segment end reached, 1: impact, 2: overturn
        if pulse_on:
            # --- sample the closed form for the first event before the pulse ends ---------
            t_lim = min(t_pulse, t_stop)
            acc0 = P[P_P2] * th - P[P_P2] * (
                s * alpha + P[P_AG] * math.sin(P[P_OMEGA] * t + P[P_PHASE])
            )
            h = h_max
            if om * acc0 < 0.0:
                h = min(h_max, 0.125 * abs(2.0 * om / acc0))
            else:
                h = h_max / 64.0
            ta = t
            oma = om
            while True:
                tb = min(ta + h, t_lim)
                thb, omb = _lin_state(tb, seg, P)
                if oma * omb < 0.0:
                    te = _lin_root(1, 0.0, seg, P, ta, tb)
                    max_theta = max(max_theta, abs(_lin_state(te, seg, P)[0]))
                if s * thb < 0.0:
                    t_seg_end = _lin_root(0, 0.0, seg, P, ta, tb)
                    event = 1
                    break
                if abs(thb) >= HALF_PI:
                    t_seg_end = _lin_root(0, HALF_PI * s, seg, P, ta, tb)
                    event = 2
                    break
                max_theta = max(max_theta, abs(thb))
                if tb >= t_lim:
                    t_seg_end = t_lim
                    break
                ta, oma = tb, omb
                h = min(2.0 * h, h_max)
        else:
            # --- free rocking: next zero in closed form ---------------------------------------
            A = seg[2]
            Bp = seg[3] / p
            a2 = A + Bp
            a1 = 2.0 * s * alpha
            a0 = A - Bp
            x = -1.0
            if th == 0.0:
                if a2 != 0.0:
                    x = a0 / a2  # the other root of the quadratic (x = 1 is the start)
            else:
                disc = a1 * a1 - 4.0 * a2 * a0
                if disc >= 0.0 and a2 != 0.0:
                    sq = math.sqrt(disc)
                    r1 = (-a1 - sq) / (2.0 * a2)
                    r2 = (-a1 + sq) / (2.0 * a2)
                    lo, hi = min(r1, r2), max(r1, r2)
                    if lo > 1.0:
                        x = lo
                    elif hi > 1.0:
                        x = hi
            # extreme rotation where omega = 0: tanh(p tau) = -B / (p A)
            ratio = -Bp / A if A != 0.0 else 2.0
            if abs(ratio) < 1.0:
                tau_e = math.atanh(ratio) / p
                if tau_e > 0.0 and (x <= 1.0 or tau_e < math.log(x) / p):
                    max_theta = max(max_theta, abs(_lin_state(t + tau_e, seg, P)[0]))
            if x > 1.0:
                t_seg_end = t + math.log(x) / p
                event = 1
            else:
                # never returns: diverges past the unstable equilibrium (overturning). The
                # history is continued to about |theta| = pi/2 (dominant term a2 x / 2).
                x_fall = 2.0 * (HALF_PI + alpha) / max(abs(a2), 1e-300)
                t_seg_end = t + max(math.log(max(x_fall, 1.0)), 0.0) / p
                event = 2
            if t_seg_end > t_stop and event == 1:
                t_seg_end = t_stop
                event = 0
        if n_seg < segs.shape[0]:
            for k in range(5):
                segs[n_seg, k] = seg[k]
            segs[n_seg, 5] = t_seg_end
        n_seg += 1
        th_end, om_end = _lin_state(t_seg_end, seg, P)
        if event == 2:
            status = OVERTURNED
            t_over = t_seg_end
            max_theta = HALF_PI
            t = t_seg_end
            break
        if event == 0:
            t = t_seg_end
            th, om = th_end, om_end
            continue
        # impact
        t = t_seg_end
        om_after = nu * om_end
        if n_imp < impacts.shape[0]:
            impacts[n_imp, 0] = t
            impacts[n_imp, 1] = om_end
            impacts[n_imp, 2] = om_after
        n_imp += 1
        th = 0.0
        om = om_after
        s = -s
        ug = P[P_AG] * math.sin(P[P_OMEGA] * t + P[P_PHASE]) if t < t_pulse else 0.0
        acc0 = -P[P_P2] * (s * alpha + ug)
        resting = n_imp >= MAX_IMPACTS or om == 0.0
        if not resting and om * acc0 < 0.0:
            resting = 2.0 * abs(om / acc0) * p < REST_HOP
        if resting:
            t_up, s_up = next_uplift(t, P, empty, empty)
            if t_up < 0.0:
                status = AT_REST
                break
            t = t_up
            om = 0.0
            s = -s_up
        elif early_exit and t >= t_pulse and 0.5 * om * om < energy_barrier(P):
            status = AT_REST
            break
    return status, n_imp, max_theta, t, n_seg, t_over


# ------------------------------------------------------------------------------------------
# Overturning spectra
# ------------------------------------------------------------------------------------------


@njit(cache=True)
def _mode(status, n_imp):
    if status == OVERTURNED:
        return AFTER_IMPACT if n_imp > 0 else WITHOUT_IMPACT
    return SAFE


@njit(cache=True)
def spread_stride(n):
    """A stride coprime with n near n / golden ratio: k -> (k * stride) % n visits every one of
    n cells once, and any run of consecutive k lands on cells spread over the whole grid."""
    stride = max(1, int(0.6180339887498949 * n))
    while True:
        a, b = stride, n
        while b != 0:
            a, b = b, a % b
        if a == 1:
            return stride
        stride += 1


@njit(parallel=True, cache=True)
def spectrum_modes(
    p,
    alpha,
    nu,
    nonlinear,
    cosine,
    ka,
    kl,
    uplift,
    load,
    omega_ratios,
    amplitude_ratios,
    t_after,
    rtol,
    atol,
):
    """Mode map and peak |theta| (up to the moment the fate is settled): rows follow
    amplitude_ratios, columns omega_ratios (codes SAFE, AFTER_IMPACT, WITHOUT_IMPACT). The linear
    free block uses the closed form, all else DOPRI5."""
    n_a = amplitude_ratios.size
    n_w = omega_ratios.size
    modes = np.zeros((n_a, n_w), dtype=np.int8)
    max_theta = np.zeros((n_a, n_w))
    closed_form = (not nonlinear) and ka == 0.0 and kl == 0.0
    empty = np.zeros(1)
    # the collars' trap (block and collars only): once for the whole map
    trap = (0.0, 0.0)
    if ka != 0.0 or kl != 0.0:
        trap = collar_barrier(
            make_params(
                p, alpha, nonlinear, GROUND_HARMONIC, 0.0, 1.0, 0.0, 0.0, ka, kl, nu, uplift, load
            )
        )
    # prange hands each thread one block of consecutive k; a pulse's cost depends on where it is
    # on the grid (long pulses at low omega ratios, more rocking at high amplitudes), so k is
    # mapped to a cell spread over the grid and each thread gets a fair share of the work
    n_cells = n_a * n_w
    stride = spread_stride(n_cells)
    for k in prange(n_cells):
        cell = (k * stride) % n_cells
        i = cell // n_w
        j = cell % n_w
        ratio = amplitude_ratios[i]
        omega = omega_ratios[j] * p
        ag = ratio * uplift
        if cosine:
            phase = HALF_PI
            t_end = 2.0 * math.pi / omega
        else:
            phase = math.asin(min(1.0, 1.0 / abs(ratio)))
            t_end = (2.0 * math.pi - phase) / omega
        P = make_params(
            p, alpha, nonlinear, GROUND_HARMONIC, ag, omega, phase, t_end, ka, kl, nu, uplift, load
        )
        P[P_TRAP_E] = trap[0]
        P[P_TRAP_TH] = trap[1]
        t_stop = t_end + t_after
        segs = np.zeros((1, 6))
        imps = np.zeros((1, 3))
        if closed_form:
            res = linear_run(P, t_stop, True, segs, imps)
        else:
            res = rk_run(P, empty, empty, t_stop, rtol, atol, True, 0.0, segs[:, :3], imps)
        modes[i, j] = _mode(res[0], res[1])
        max_theta[i, j] = res[2]
    return modes, max_theta
