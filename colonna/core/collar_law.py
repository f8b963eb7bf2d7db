"""The collars' compiled frame element (numba), shared by the FEM's and the multibody model's
collars: the co-rotational element's local law :func:`frame_local_law`, which dispatches on the
collar's law row to the fibre-section element (:func:`colonna.core.fibre.fibre_local_law`, the
default of a plastic collar) or to the resultant law (:func:`resultant_local_law`: its bilinear
axial law :func:`axial_return_mapping`, elastic E A up to N_y = f_y A, then isotropic linear
hardening, and its end hinges :func:`hinge_return_mapping`, the end moments bounded by the
rectangle's N-M interaction surface |M| / M_p + (N / N_p)^2 <= 1; an elastic collar's law).

A collar's law is a row of ``LAW_SIZE`` numbers (:meth:`colonna.core.collar.Collar.law`), its
state a row of :func:`state_size` numbers (the largest a set of collars needs; zeros at rest).
The first entries mean the same for both laws: plastic elongation s_p (m; the fibre law's mean
axial plastic strain times L), accumulated plastic strain alpha (the fibre law's largest fibre
value), plastic work (J, with the energy a fracture releases), the plastic rotations of the two
ends (rad; the fibre law's integral of the plastic curvature against b(x)), the largest
extreme-fibre strain reached, and 1 once the collar has fractured (0 before); then the committed
basic deformations (stretch, th1, th2), basic forces (N - pretension, M1, M2), elastic energy,
largest fibre stress and surface strain (the fibre law's; the resultant law leaves them 0), then
the fibre law's section deformations and fibre histories (colonna.core.fibre)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .fibre import HEADER, fibre_local_law, fibre_state_size
from .jit_cache import ensure_fresh

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)

STATE_SIZE = HEADER
"""The state row of resultant-law collars (16 numbers; a fibre collar needs
:func:`state_size`): (s_p, alpha, plastic work, hinge 1, hinge 2, largest fibre strain,
fractured, then the fibre law's committed stretch, th1, th2, N - P, M1, M2, U, largest fibre
stress, surface strain)."""

RECORDED = (0, 1, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
"""The state entries a history records to rebuild the collar's forces (all of the header but
the work). The resultant law rebuilds them from s_p and the hinges; the fibre law, whose state is
its fibres' histories, returns its committed forces (entries 10-13) when called at its committed
deformations (entries 7-9), as a history's replay at the recorded positions does."""

LAW_KIND = 7
"""Place in the law row of the law's kind: RESULTANT (0) or FIBRE (1); then (fibre law) the
number of sections, of fibres, E (Pa), f_y (Pa), H_kin, H_iso (Pa; Menegotto-Pinto: E_h, 0), the
depth h and thickness t (m), the steel (0: bilinear, 1: Menegotto-Pinto), and the
Menegotto-Pinto steel's R0, cR1, cR2, a1, a2, a3, a4 (zeros for the bilinear)."""
RESULTANT, FIBRE = 0, 1

LAW_SIZE = 24
"""Numbers in a collar's law row: (N_y = f_y A (0: elastic), E A, H A, M_p (0: elastic in
bending), 1 / (E W), h / (2 L_p), eps_u (0: never fractures)), then the kind (LAW_KIND), the
fibre law's n_sections, n_fibres, E, f_y, H_kin, H_iso, h, t, steel, and 7 zeros."""

FIBRE_STRAIN, FRACTURED = 5, 6  # their places in the state

OUT_SIZE = 8
"""Outputs per collar of the models' collar_forces: (N, M1, M2, elastic energy, plastic strain
s_p / L, extreme-fibre strain, end rotations th1, th2 relative to the chord)."""


def law_state_size(law) -> int:
    """Numbers in the state row of a collar of law row ``law``."""
    if int(law[LAW_KIND]) == FIBRE:
        return fibre_state_size(int(law[8]), int(law[9]), int(law[16]))
    return STATE_SIZE


def state_size(laws) -> int:
    """Numbers per collar in the state array of a set of collars of law rows ``laws`` (an
    iterable of rows, or a 2D array): the largest one of them needs, at least STATE_SIZE."""
    return max([STATE_SIZE] + [law_state_size(law) for law in np.atleast_2d(laws) if len(law)])


@njit(cache=True)
def axial_return_mapping(N_trial, ea_l, n_yield, ea, ha, state, c, commit):
    """Axial force of collar c from its trial N_trial = pretension + EA/L (stretch - s_p).

    n_yield = f_y A (0: elastic collar), ea = E A, ha = H A with H = E E_h / (E - E_h), ea_l =
    E A / L. state[c] = (plastic elongation s_p (m), accumulated plastic strain alpha, plastic
    work (J), ...); |N| <= n_yield + H A alpha, with the excess returned along EA/L and the
    surface grown by the plastic strain. Updates the state with commit. Returns (N, s_p / L)."""
    s_p = state[c, 0]
    if n_yield <= 0.0:
        return N_trial, 0.0
    span = ea / ea_l
    limit = n_yield + ha * state[c, 1]
    N = N_trial
    if abs(N) > limit:
        ds = (abs(N) - limit) / (ea_l + ha / span)
        sgn = 1.0 if N > 0.0 else -1.0
        N -= sgn * ea_l * ds
        s_p += sgn * ds
        if commit:
            state[c, 0] = s_p
            state[c, 1] += ds / span
            state[c, 2] += abs(N) * ds
    return N, s_p / span


@njit(cache=True)
def hinge_return_mapping(M1_trial, M2_trial, ei_l, cap1, cap2):
    """End moments of the frame element with rigid-plastic hinges at its ends, from the trial
    (elastic) moments M_trial = EI'/L0 [[4, 2], [2, 4]] (theta - theta_p,n) and the hinges'
    moment capacities cap1, cap2 >= 0.

    The closest point of the box |M_i| <= cap_i to the trial in the element's complementary
    energy norm, (M - M_trial)^T C (M - M_trial) with C = [[4, -2], [-2, 4]] / (12 EI'/L0)
    (backward Euler with normality: the box is convex and its closest point is the one of the
    candidates, the trial itself, a hinge on its face with the other moment relaxed, or a
    corner, that is admissible and nearest). Returns (M1, M2, dtheta_p1, dtheta_p2), the
    plastic rotation increments dtheta_p = C (M_trial - M); M . dtheta_p >= 0 (dissipative)."""
    if abs(M1_trial) <= cap1 and abs(M2_trial) <= cap2:
        return M1_trial, M2_trial, 0.0, 0.0
    best = 1e300
    M1 = M2 = 0.0
    for candidate in range(8):
        sign = 1.0 if candidate % 2 == 0 else -1.0
        if candidate < 2:  # hinge 1 on a face: M2 changes by half as much (C12 / C22 = -1/2)
            m1 = sign * cap1
            m2 = M2_trial + 0.5 * (m1 - M1_trial)
        elif candidate < 4:  # hinge 2 on a face
            m2 = sign * cap2
            m1 = M1_trial + 0.5 * (m2 - M2_trial)
        else:  # a corner: both hinges
            m1 = sign * cap1
            m2 = cap2 if candidate < 6 else -cap2
        if abs(m1) > cap1 * (1.0 + 1e-12) or abs(m2) > cap2 * (1.0 + 1e-12):
            continue
        d1 = m1 - M1_trial
        d2 = m2 - M2_trial
        distance = d1 * d1 - d1 * d2 + d2 * d2  # proportional to d^T C d
        if distance < best:
            best, M1, M2 = distance, m1, m2
    d1 = M1_trial - M1
    d2 = M2_trial - M2
    scale = 1.0 / (12.0 * ei_l)
    return M1, M2, scale * (4.0 * d1 - 2.0 * d2), scale * (-2.0 * d1 + 4.0 * d2)


@njit(cache=True)
def frame_local_law(stretch, th1, th2, ea_l, ei_l, pretension, law, state, c, commit):
    """The collar's local law, shared by the FEM's and the multibody model's collars: the
    fibre-section element (colonna.core.fibre.fibre_local_law) if law[LAW_KIND] is FIBRE, else
    the resultant law (:func:`resultant_local_law`); the same arguments and returns (N, M1, M2,
    U, plastic strain, largest fibre strain)."""
    if law[LAW_KIND] == FIBRE:
        return fibre_local_law(stretch, th1, th2, ea_l, ei_l, pretension, law, state, c, commit)
    return resultant_local_law(stretch, th1, th2, ea_l, ei_l, pretension, law, state, c, commit)


@njit(cache=True)
def resultant_local_law(stretch, th1, th2, ea_l, ei_l, pretension, law, state, c, commit):
    """The collar's co-rotational Euler-Bernoulli frame element in its local frame with the
    resultant law (an elastic collar's, and a plastic one's with ``section = "resultant"``).

    stretch = chord length - L0 (m), th1, th2 = end rotations relative to the chord (rad);
    ea_l = E A / L, ei_l = E I' / L0, pretension (N); law = the collar's law row (LAW_SIZE:
    n_yield, ea, ha of :func:`axial_return_mapping`, which updates state[c] with commit, then
    m_plastic, strain_per_moment, strain_per_hinge_rotation, ultimate_strain). End moments
    M1 = EI'/L0 (4 a1 + 2 a2), M2 = EI'/L0 (2 a1 + 4 a2) of the elastic end rotations
    a_i = th_i - theta_p,i; elastic energy U = P e + EA/L e^2 / 2 + EI'/L0 (2 a1^2 + 2 a1 a2 +
    2 a2^2), e = stretch - s_p.

    m_plastic = M_p = f_y t h^2 / 4 (0: elastic in bending): the end hinges yield on the
    rectangle's N-M interaction surface |M| / (g M_p) + (N / (g N_p))^2 = 1, with the axial
    law's isotropic hardening g = 1 + H alpha / f_y. The axial plastic flow is the axial law's
    (the hinges rotate, they do not lengthen: the surface is exact, the flow rule decoupled).
    Hinge work W_M = M . dtheta_p counts in the plastic work and hardens the section by the
    work-equivalent plastic strain W_M / (g N_p L) (as axial flow does: d alpha = ds_p / L).

    Extreme-fibre strain (lumped plasticity): the axial strain N / (E A) + s_p / L plus, at the
    more strained end, the elastic bending strain |M_i| / (E W) and the hinge's plastic
    rotation spread over the hinge length, |theta_p,i| h / (2 L_p). Its largest value is kept
    in state[c, FIBRE_STRAIN]; a plastic collar whose fibre strain reaches ultimate_strain
    fractures (state[c, FRACTURED] = 1): from that step on it carries nothing, and the elastic
    energy it held is released into the plastic work (the energy balance stays closed).
    Returns (N, M1, M2, U, plastic strain s_p / L, fibre strain)."""
    if state[c, FRACTURED] != 0.0:
        return 0.0, 0.0, 0.0, 0.0, state[c, 0] * ea_l / law[1], 0.0
    n_yield, ea, ha, m_plastic = law[0], law[1], law[2], law[3]
    N, plastic_strain = axial_return_mapping(
        pretension + ea_l * (stretch - state[c, 0]), ea_l, n_yield, ea, ha, state, c, commit
    )
    elastic = stretch - plastic_strain * ea / ea_l
    a1 = th1 - state[c, 3]
    a2 = th2 - state[c, 4]
    M1 = ei_l * (4.0 * a1 + 2.0 * a2)
    M2 = ei_l * (2.0 * a1 + 4.0 * a2)
    if m_plastic > 0.0 and n_yield > 0.0:
        g = 1.0 + ha * state[c, 1] / n_yield
        ratio = N / (g * n_yield)
        capacity = max(0.0, g * m_plastic * (1.0 - ratio * ratio))
        M1, M2, dp1, dp2 = hinge_return_mapping(M1, M2, ei_l, capacity, capacity)
        if dp1 != 0.0 or dp2 != 0.0:
            a1 -= dp1
            a2 -= dp2
            if commit:
                work = M1 * dp1 + M2 * dp2
                state[c, 3] += dp1
                state[c, 4] += dp2
                state[c, 2] += work
                state[c, 1] += work / (g * n_yield * ea / ea_l)
    energy = (
        pretension * elastic
        + 0.5 * ea_l * elastic * elastic
        + ei_l * (2.0 * a1 * a1 + 2.0 * a1 * a2 + 2.0 * a2 * a2)
    )
    bending = max(
        abs(M1) * law[4] + abs(state[c, 3]) * law[5], abs(M2) * law[4] + abs(state[c, 4]) * law[5]
    )
    fibre = abs(N / ea + plastic_strain) + bending
    if commit:
        if fibre > state[c, FIBRE_STRAIN]:
            state[c, FIBRE_STRAIN] = fibre
        if n_yield > 0.0 and law[6] > 0.0 and fibre >= law[6]:
            state[c, FRACTURED] = 1.0
            state[c, 2] += energy  # released: the broken band's ends spring back
            return 0.0, 0.0, 0.0, 0.0, plastic_strain, fibre
    return N, M1, M2, energy, plastic_strain, fibre


RESPONSE_SIZE = 15
"""Columns of :func:`history_response`'s output, per step: the end forces and moments that hold
the collar's ends, in its initial axes (F1x, F1y, M1, F2x, F2y, M2: N, N m), the axial force N,
the largest surface strain now, the largest fibre stress now (Pa; 0 from the resultant law,
whose caller estimates it), the plastic work (J), fractured (0 or 1), the elastic energy (J),
the axial plastic strain, the largest surface strain reached so far and the accumulated
plastic strain alpha (state entry 1)."""


@njit(cache=True)
def history_response(history, span, ea_l, ei_l, pretension, law, state, out):
    """Step one collar through imposed end displacements and rotations, committing each row: a
    test bench with the models' own kinematics (fem._kernels.collar_forces', replicated).

    history[k] = (u1, v1, r1, u2, v2, r2) in the collar's initial axes (end 1 at the origin,
    end 2 at (span, 0): m, rad); the chord's stretch and the end rotations relative to it go to
    :func:`frame_local_law` (state row 0 of ``state``); out[k] gets RESPONSE_SIZE numbers. End 1
    is held by -N e + V n and the moment M1, end 2 by N e - V n and M2, with e the chord's unit
    vector, n its normal and V = (M1 + M2) / chord (the element's internal forces, as
    collar_forces subtracts them from the nodes' forces)."""
    for k in range(history.shape[0]):
        u1, v1, r1, u2, v2, r2 = (
            history[k, 0],
            history[k, 1],
            history[k, 2],
            history[k, 3],
            history[k, 4],
            history[k, 5],
        )
        dx = span + u2 - u1
        dy = v2 - v1
        length = math.sqrt(dx * dx + dy * dy)
        beta = math.atan2(dy, dx)
        th1 = r1 - beta
        th2 = r2 - beta
        N, M1, M2, energy, plastic_strain, fibre = frame_local_law(
            length - span, th1, th2, ea_l, ei_l, pretension, law, state, 0, True
        )
        ex = dx / length
        ey = dy / length
        shear = (M1 + M2) / length
        out[k, 0] = -N * ex - shear * ey
        out[k, 1] = -N * ey + shear * ex
        out[k, 2] = M1
        out[k, 3] = N * ex + shear * ey
        out[k, 4] = N * ey - shear * ex
        out[k, 5] = M2
        out[k, 6] = N
        out[k, 7] = fibre
        out[k, 8] = state[0, 14] if law[LAW_KIND] == FIBRE and state[0, FRACTURED] == 0.0 else 0.0
        out[k, 9] = state[0, 2]
        out[k, 10] = state[0, FRACTURED]
        out[k, 11] = energy
        out[k, 12] = plastic_strain
        out[k, 13] = state[0, FIBRE_STRAIN]
        out[k, 14] = state[0, 1]
