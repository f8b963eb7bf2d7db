"""Independent reference: scipy solve_ivp (DOP853, tight tolerances) with terminal events.

Deliberately written from the equations of docs/theory.md (sections 3-6: equation of motion,
impact rule, collar moment) without using the package's kernels, so that the tests compare two
implementations.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def reference_rocking(
    p,
    alpha,
    nu,
    ground_over_g,
    t_ground_end,
    *,
    nonlinear,
    t_stop,
    collar_ka=0.0,
    collar_kl=0.0,
    rtol=1e-12,
    atol=1e-14,
    uplift=None,
    max_impacts=2000,
    settle=True,
):
    """Return (overturned, impacts, max_abs_theta, impact_times, (t, theta, omega) pieces)."""
    p2 = p * p
    if uplift is None:
        uplift = math.tan(alpha) if nonlinear else alpha

    def rhs(s):
        def f(t, y):
            th, om = y
            ug = ground_over_g(t)
            if nonlinear:
                arg = s * alpha - th
                acc = -p2 * (math.sin(arg) + ug * math.cos(arg))
                # collar moment from U = k_a (sqrt(1 + sin^2/4) - 1)^2 + k_l sin^2 / 4
                sn, cs = math.sin(th), math.cos(th)
                r = math.sqrt(1 + 0.25 * sn * sn)
                acc += -collar_ka * (r - 1) * sn * cs / (2 * r) - 0.5 * collar_kl * sn * cs
            else:
                acc = p2 * th - p2 * (s * alpha + ug) - 0.5 * collar_kl * th
            return [om, acc]

        return f

    # start: first time the ground reaches the uplift level (sampled, then refined)
    ts = np.linspace(0.0, t_ground_end, 20001)
    ug = np.array([ground_over_g(t) for t in ts])
    idx = np.nonzero(np.abs(ug) >= uplift * (1 - 1e-12))[0]
    if idx.size == 0:
        return False, 0, 0.0, [], []
    t = ts[idx[0]]
    s = -math.copysign(1.0, ground_over_g(t))
    y = [0.0, 0.0]
    impacts = []
    pieces = []
    max_theta = 0.0

    def hit_zero(t, y):
        return y[0]

    hit_zero.terminal = True

    def fall(t, y):
        return abs(y[0]) - math.pi / 2

    fall.terminal = True

    while t < t_stop and len(impacts) < max_impacts:
        # integrate in two legs so that the pulse end is a step boundary
        t_next = t_ground_end if t < t_ground_end else t_stop
        hit_zero.direction = 1.0 if s < 0 else -1.0
        sol = solve_ivp(
            rhs(s),
            (t, t_next),
            y,
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=(hit_zero, fall),
            dense_output=True,
            first_step=1e-6,
        )
        pieces.append(sol)
        max_theta = max(max_theta, float(np.max(np.abs(sol.y[0]))))
        if sol.t_events[1].size:
            return True, len(impacts), math.pi / 2, impacts, pieces
        if sol.t_events[0].size and sol.t_events[0][0] > t:
            te = sol.t_events[0][0]
            om = sol.y_events[0][0][1]
            impacts.append(te)
            t = te
            y = [0.0, nu * om]
            s = -s
            # after the ground stops, a block upright with less kinetic energy than the gravity
            # barrier at |theta| = alpha can never overturn
            barrier = p2 * (1 - math.cos(alpha)) if nonlinear else 0.5 * p2 * alpha**2
            if settle and t >= t_ground_end and 0.5 * y[1] ** 2 < barrier:
                return False, len(impacts), max_theta, impacts, pieces
            if abs(nu * om) < 1e-9 * p:
                # at rest: wait for the ground to lift it again
                later = ts[(ts > t) & (np.abs(ug) >= uplift)]
                if later.size == 0:
                    return False, len(impacts), max_theta, impacts, pieces
                t = later[0]
                s = -math.copysign(1.0, ground_over_g(t))
                y = [0.0, 0.0]
            continue
        t = sol.t[-1]
        y = list(sol.y[:, -1])
        if t >= t_ground_end and collar_ka == 0.0 and collar_kl == 0.0:
            if s * y[0] > alpha and y[0] * y[1] > 0:
                return True, len(impacts), max_theta, impacts, pieces
    return False, len(impacts), max_theta, impacts, pieces


def sine_pulse_over_g(amplitude_over_g, omega, phase, t_end):
    def f(t):
        return amplitude_over_g * math.sin(omega * t + phase) if 0.0 <= t <= t_end else 0.0

    return f
