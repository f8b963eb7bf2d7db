"""The collar as a fibre-section, force-based frame element (numba): the local law the FEM's and
the multibody model's co-rotational collars step when ``Collar.section == "fibre"``.

Element (Spacone, Filippou & Taucer 1996, "Fibre beam-column model for non-linear analysis of R/C
frames", Earthquake Eng. Struct. Dyn. 25; Neuenhofer & Filippou 1997, J. Struct. Eng. 123; as
OpenSees's forceBeamColumn): basic deformations v = (stretch, th1, th2) relative to the chord,
basic forces q = (N, M1, M2). The section forces follow from q by equilibrium, exactly:
N(x) = N, M(x) = (x/L - 1) M1 + (x/L) M2, i.e. s(x) = b(x) q; compatibility is
v = int_0^L b(x)^T e(x) dx with e = (axis strain, curvature), integrated at ``n_sections``
Gauss-Lobatto sections (the ends included: the end sections, where the moment is largest, are
integration points). The state determination iterates from the committed state each call
(element flexibility F = int b^T f_s b dx, residual deformations r = f_s (b q - s_R) carried, as
Spacone et al.) to a relative tolerance of 1e-12; the trial never touches the committed state
unless ``commit``. Where the plain iteration does not converge in ``MAX_ITERATIONS`` the step is
cut in 2, 4, ... 64 sub-steps. An iteration that stops improving below ``ROUND_OFF`` (1e-9) is
converged: the sums over every fibre's stress cannot do better in double precision (a run's
step otherwise stalls at a few 1e-12 and is cut for nothing). The iterations' fibre moduli are
floored at 1e-6 E (the stresses are not: the answer is the same), which keeps a perfectly
plastic section (E_h = 0) from a singular flexibility. A step that still does not converge
returns NaN and commits nothing: not an answer, which the solvers' checks for non-finite forces
report. (A backtracking line search on the compatibility error was tried and taken out: in a
multibody run of default-top-load it drove a collar's iteration to NaN.)

Section: the band's depth h cut into ``n_fibres`` equal layers (width t); plane sections,
fibre strain eps = eps_0 + e_axis + y kappa (eps_0 = P / (E A): the pretension an initial
strain). The layers sit at their mid-depths scaled by 1 / sqrt(1 - 1/n^2), which makes the
layered section's second moment exactly t h^3 / 12 (the elastic collar is exact, as the
resultant law); the plastic moment of an even layer count is then f_y t h^2 / 4 times
1 / sqrt(1 - 1/n^2) (+0.13 % at 20 layers). The extreme-fibre strain reported (and checked
against eps_u) is the plane-section strain at the band's surface y = +-h/2, and the stress
reported there that of the surface strain from the outer layer's history (exact while elastic:
the surface yields at M_y = f_y t h^2 / 6; the outer layer's mid-depth, where the first plastic
work is done, at M_y (h / 2) / y_1, 5 % later with 20 layers).

Fibre: bilinear steel (E, f_y, E_h) with linear kinematic (H_kin, the Bauschinger effect: a
reversal yields 2 f_y below the shifted centre) and isotropic (H_iso) hardening, H_kin + H_iso
= E E_h / (E - E_h); backward-Euler return mapping, algorithmic tangent E_h past yield. Or
(law steel MENEGOTTO_PINTO) :func:`menegotto_pinto_stress`, OpenSees's Steel02.

Energy: U = sum over the fibres of sigma^2 / (2 E) dV less the pretension's initial
P^2 L / (2 E A) (the elastic energy; the kinematic hardening's stored energy counts as plastic
work). On commit the plastic work grows by the trapezoid of q over dv less dU,
W_p += (q + q_n) / 2 . (v - v_n) - (U - U_n), so that q . dv = dU + dW_p closes step by step.

Fracture, and why it is objective: the collar fractures (carries nothing from that step on; its
elastic energy is released into the plastic work) when the surface strain of any section reaches
eps_u. The section forces are exact (equilibrium, whatever the number of sections) and the end
section's strain is a function of its own forces and history, so with positive hardening the
slip at which the end section's surface reaches eps_u converges as the sections are refined
(tested; docs/collars.md gives the table). Dropping the broken fibre one at a time and following
the section's softening is not done: a force-based element localises that softening into one
integration point, whose length L w_1 depends on the number of sections (Coleman & Spacone 2001,
J. Struct. Eng. 127), so the slip at which the last fibre breaks is not objective without a
fracture-energy regularisation; the band tearing from the edge fibre on is also the
conservative reading for "do the collars hold?".

The element's length L is the collar's span (E A / (E A / L)); its rotations are those of the
chord L0 (the model's attachment points) scaled by rho = sqrt(EI' L / (E I)) = L0 / L, the
moments by 1 / rho, as the resultant law's bending stiffness EI' = E I (L0 / L)^3 does (same
lateral stiffness 12 E I / L^3, same work).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import ensure_fresh

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)

MAX_SECTIONS = 30  # Gauss-Lobatto sections per element: 2 .. (colonna.core.collar's limit)
MAX_ITERATIONS = 60
TOLERANCE = 1e-12
ROUND_OFF = 1e-9
"""An iteration that stops improving (error above half the last) below this relative error is
converged: the sums over the fibres' stresses cannot do better in double precision."""

# state row of a fibre collar (the first 7 entries mean what the resultant law's do)
S_P, ALPHA, WORK, HINGE1, HINGE2, FIBRE_STRAIN, FRACTURED = range(7)
V_COMMITTED = 7  # committed basic deformations (stretch m, th1, th2 rad): 7, 8, 9
Q_COMMITTED = 10  # committed basic forces (N - pretension, M1, M2: N, N m): 10, 11, 12
U_COMMITTED = 13  # committed elastic energy (J)
STRESS = 14  # the largest |stress| at the sections' surfaces, committed (Pa)
SURFACE = 15  # the largest surface strain |eps| of the committed state
FLEXIBILITY = 16  # the committed element flexibility F00, F01, F02, F11, F12, F22: 16 .. 21
HEADER = 22  # then SECTION_SIZE per section, then PER_FIBRE per fibre
SECTION_SIZE = 6  # axis strain, curvature, flexibility f11, f12, f22, yielded (0 or 1)
PER_FIBRE = 3  # bilinear: plastic strain, back stress (Pa), accumulated plastic strain
PER_FIBRE_MP = 10  # Menegotto-Pinto: Steel02's history (eps_min, eps_max, eps_pl, eps_0,
# sigma_0, eps_r, sigma_r, kon) and the committed strain and stress
BILINEAR, MENEGOTTO_PINTO = 0, 1  # the law row's steel
TOTALS = 7  # _solve's totals: energy, mean plastic strain, plastic rotations 1, 2 (element
# axes), largest accumulated plastic strain, largest surface strain, largest surface stress


def fibre_state_size(n_sections: int, n_fibres: int, steel: int = BILINEAR) -> int:
    """Numbers in the state row of a fibre collar of n_sections sections of n_fibres fibres of
    the steel law ``steel`` (BILINEAR or MENEGOTTO_PINTO)."""
    per = PER_FIBRE if steel == BILINEAR else PER_FIBRE_MP
    return HEADER + SECTION_SIZE * n_sections + per * n_sections * n_fibres


def _lobatto_tables():
    """Gauss-Lobatto points and weights on [0, 1] for 2 .. MAX_SECTIONS points: the ends and
    the roots of P'_{n-1}; weights 2 / (n (n-1) P_{n-1}(x)^2) on [-1, 1], halved."""
    points = np.zeros((MAX_SECTIONS + 1, MAX_SECTIONS))
    weights = np.zeros((MAX_SECTIONS + 1, MAX_SECTIONS))
    legendre = np.polynomial.legendre.Legendre
    for n in range(2, MAX_SECTIONS + 1):
        p = legendre.basis(n - 1)
        inner = np.sort(p.deriv().roots().real) if n > 2 else np.zeros(0)
        x = np.concatenate(([-1.0], inner, [1.0]))
        w = 2.0 / (n * (n - 1) * p(x) ** 2)
        points[n, :n] = 0.5 * (x + 1.0)
        weights[n, :n] = 0.5 * w
    return points, weights


LOBATTO_POINTS, LOBATTO_WEIGHTS = _lobatto_tables()


@njit(cache=True)
def bilinear_stress(eps, eps_p, back, alpha, E, fy, h_kin, h_iso):
    """Bilinear steel with linear kinematic and isotropic hardening, backward Euler from the
    committed (eps_p, back stress, accumulated plastic strain alpha) to the total strain eps:
    the trial sigma = E (eps - eps_p) is returned to |sigma - back| <= f_y + H_iso alpha.
    Returns (sigma (Pa), tangent (Pa), eps_p, back, alpha) of the trial."""
    trial = E * (eps - eps_p)
    xi = trial - back
    excess = abs(xi) - (fy + h_iso * alpha)
    if excess <= 0.0:
        return trial, E, eps_p, back, alpha
    sign = 1.0 if xi > 0.0 else -1.0
    h = h_kin + h_iso
    dg = excess / (E + h)
    return (
        trial - E * sign * dg,
        E * h / (E + h),
        eps_p + sign * dg,
        back + h_kin * sign * dg,
        (alpha + dg),
    )


@njit(cache=True)
def menegotto_pinto_stress(eps, base, k, E0, fy, b, R0, cR1, cR2, a1, a2, a3, a4):
    """Menegotto-Pinto steel with Filippou's isotropic hardening, as OpenSees's Steel02 (the
    FEDEAS Steel_2 of Mohd Yassin 1993; Filippou, Popov & Bertero 1983): from the committed
    history base[k : k + 10] (zeros: virgin) to the total strain eps. Between reversals
    sigma* = b eps* + (1 - b) eps* / (1 + |eps*|^R)^(1/R), eps* and sigma* normalised between
    the last reversal (eps_r, sigma_r) and the intersection (eps_0, sigma_0) of the elastic
    and hardening (slope b E0) asymptotes; R = R0 (1 - cR1 xi / (cR2 + xi)), xi the plastic
    excursion in yield strains; a reversal shifts the hardening asymptote by a1 (a3) times f_y
    times (the strain range / (2 a2 (a4) eps_y))^0.8. Returns (sigma, tangent, and the new
    history: eps_min, eps_max, eps_pl, eps_0, sigma_0, eps_r, sigma_r, kon, eps, sigma)."""
    epsmin, epsmax, epspl = base[k], base[k + 1], base[k + 2]
    epss0, sigs0, epsr, sigr = base[k + 3], base[k + 4], base[k + 5], base[k + 6]
    kon, eps_n, sig_n = base[k + 7], base[k + 8], base[k + 9]
    esh = b * E0
    epsy = fy / E0
    deps = eps - eps_n
    if kon == 0.0:
        if abs(deps) < 10.0 * 2.220446049250313e-16:
            sig = sig_n + E0 * deps
            return sig, E0, epsmin, epsmax, epspl, epss0, sigs0, epsr, sigr, kon, eps, sig
        epsmax = epsy
        epsmin = -epsy
        if deps < 0.0:
            kon = 2.0
            epss0 = epsmin
            sigs0 = -fy
            epspl = epsmin
        else:
            kon = 1.0
            epss0 = epsmax
            sigs0 = fy
            epspl = epsmax
    if kon == 2.0 and deps > 0.0:  # reversal to loading: tension side
        kon = 1.0
        epsr = eps_n
        sigr = sig_n
        epsmin = min(epsmin, eps_n)
        shift = 1.0 + a3 * ((epsmax - epsmin) / (2.0 * a4 * epsy)) ** 0.8
        epss0 = (fy * shift - esh * epsy * shift - sigr + E0 * epsr) / (E0 - esh)
        sigs0 = fy * shift + esh * (epss0 - epsy * shift)
        epspl = epsmax
    elif kon == 1.0 and deps < 0.0:  # reversal to unloading: compression side
        kon = 2.0
        epsr = eps_n
        sigr = sig_n
        epsmax = max(epsmax, eps_n)
        shift = 1.0 + a1 * ((epsmax - epsmin) / (2.0 * a2 * epsy)) ** 0.8
        epss0 = (-fy * shift + esh * epsy * shift - sigr + E0 * epsr) / (E0 - esh)
        sigs0 = -fy * shift + esh * (epss0 + epsy * shift)
        epspl = epsmin
    xi = abs((epspl - epss0) / epsy)
    R = R0 * (1.0 - cR1 * xi / (cR2 + xi))
    ratio = (eps - epsr) / (epss0 - epsr)
    dum1 = 1.0 + abs(ratio) ** R
    dum2 = dum1 ** (1.0 / R)
    sig = (b * ratio + (1.0 - b) * ratio / dum2) * (sigs0 - sigr) + sigr
    tangent = (b + (1.0 - b) / (dum1 * dum2)) * (sigs0 - sigr) / (epss0 - epsr)
    return sig, tangent, epsmin, epsmax, epspl, epss0, sigs0, epsr, sigr, kon, eps, sig


@njit(cache=True)
def _fibre(mat, eps, base, k, write, keep):
    """A fibre of the steel of mat (the law row from its E: E, f_y, H_kin or E_h, H_iso, h, t,
    steel, R0, cR1, cR2, a1 .. a4) at the total strain eps from its history base[k:]; with
    keep its new history goes into write[k:]. Returns (sigma, tangent, plastic strain,
    accumulated plastic strain (Menegotto-Pinto: |sigma / E - eps|))."""
    E = mat[0]
    if mat[6] == BILINEAR:
        sig, tangent, ep, bk, al = bilinear_stress(
            eps, base[k], base[k + 1], base[k + 2], E, mat[1], mat[2], mat[3]
        )
        if keep:
            write[k] = ep
            write[k + 1] = bk
            write[k + 2] = al
        return sig, tangent, ep, al
    r = menegotto_pinto_stress(
        eps, base, k, E, mat[1], mat[2] / E, mat[7], mat[8], mat[9], mat[10], mat[11],
        mat[12], mat[13]
    )  # fmt: skip
    if keep:
        for m in range(PER_FIBRE_MP):
            write[k + m] = r[2 + m]
    ep = eps - r[0] / E
    return r[0], r[1], ep, abs(ep)


@njit(cache=True)
def _section(i, e_axis, kappa, eps0, ys, area, base, mat, per, floor, result, write):
    """Section i at deformation (e_axis, kappa), its fibres from their histories in base (their
    new ones written into write): result = (N, M, flexibility f11, f12, f22 of the tangent, its
    fibre moduli floored at ``floor``, energy per length sum sigma^2 A / (2E), 0, mean plastic
    strain, plastic curvature, largest accumulated plastic strain)."""
    n_f = ys.size
    E, fy, h_kin, h_iso = mat[0], mat[1], mat[2], mat[3]
    bilinear = mat[6] == BILINEAR
    N = M = k11 = k12 = k22 = energy = mean_p = curv_p = amax = yy = 0.0
    for j in range(n_f):
        y = ys[j]
        eps = eps0 + e_axis + y * kappa
        k = (i * n_f + j) * per
        if bilinear:  # inline: the common case
            sig, tangent, ep, bk, al = bilinear_stress(
                eps, base[k], base[k + 1], base[k + 2], E, fy, h_kin, h_iso
            )
            write[k] = ep
            write[k + 1] = bk
            write[k + 2] = al
        else:
            sig, tangent, ep, al = _fibre(mat, eps, base, k, write, True)
        tangent = max(tangent, floor)
        N += sig * area
        M += sig * y * area
        k11 += tangent * area
        k12 += tangent * y * area
        k22 += tangent * y * y * area
        energy += sig * sig * area
        mean_p += ep
        curv_p += ep * y
        yy += y * y
        amax = max(amax, al)
    det = k11 * k22 - k12 * k12
    result[0] = N
    result[1] = M
    result[2] = k22 / det
    result[3] = -k12 / det
    result[4] = k11 / det
    result[5] = energy / (2.0 * E)
    result[6] = 0.0
    result[7] = mean_p / n_f
    result[8] = curv_p / yy
    result[9] = amax


@njit(cache=True)
def _solve(v, q, e, flex, yielded, base, write, xs, ws, span, eps0, ys, area, mat, per, floor,
           depth, F, totals, section, residual):  # fmt: skip
    """Iterate the element from (q, e) (updated in place; flex: the sections' flexibilities
    for the updates, refreshed by each pass) to compatibility with the basic deformations v,
    the fibres from their histories in base (their trial histories into write). A section
    that never yielded (yielded[i] == 0) and stays elastic is done in closed form (its layers'
    sums: A, 0, I). The converged pass leaves its element flexibility in F (F00, F01, F02, F11,
    F12, F22), yielded set where a section's fibres have yielded, and the TOTALS in totals.
    section (10) and residual (n_s, 4): work arrays.
    Returns 0 when converged, else the compatibility error relative to the deformations'
    scale (inf: a singular update)."""
    n_s = xs.size
    n_f = ys.size
    E, fy = mat[0], mat[1]
    bilinear = mat[6] == BILINEAR
    ea = area * n_f * E
    ei = E * depth**3 * area * n_f / (12.0 * depth)
    y1 = ys[n_f - 1]
    scale = fy / E + abs(v[0]) / span + abs(v[1]) + abs(v[2])
    previous = np.inf  # the error before the last update
    for _ in range(MAX_ITERATIONS):
        F00 = F01 = F02 = F11 = F12 = F22 = 0.0
        vr0 = vr1 = vr2 = 0.0
        worst = energy = mean_p = hinge1 = hinge2 = amax = surface = smax = 0.0
        for i in range(n_s):
            x = xs[i]
            w = ws[i] * span
            axis = eps0 + e[i, 0]
            elastic = bilinear and yielded[i] == 0.0 and E * (abs(axis) + y1 * abs(e[i, 1])) <= fy
            if elastic:  # closed form; its fibres' histories stay zero
                section[0] = ea * axis
                section[1] = ei * e[i, 1]
                section[2] = 1.0 / ea
                section[3] = 0.0
                section[4] = 1.0 / ei
                section[5] = 0.5 * (ea * axis * axis + ei * e[i, 1] * e[i, 1])
                section[7] = section[8] = section[9] = 0.0
                start = i * n_f * per
                for k in range(start, start + n_f * per):  # an earlier pass's trial
                    write[k] = base[k]
            else:
                _section(i, e[i, 0], e[i, 1], eps0, ys, area, base, mat, per, floor, section,
                         write)  # fmt: skip
            f11, f12, f22 = section[2], section[3], section[4]
            flex[i, 0] = f11
            flex[i, 1] = f12
            flex[i, 2] = f22
            sN = q[0] - section[0]
            sM = (x - 1.0) * q[1] + x * q[2] - section[1]
            r0 = f11 * sN + f12 * sM
            r1 = f12 * sN + f22 * sM
            residual[i, 0] = r0
            residual[i, 1] = r1
            worst = max(worst, abs(r0), abs(r1) * span)
            a = e[i, 0] + r0
            kap = e[i, 1] + r1
            vr0 += w * a
            vr1 += w * (x - 1.0) * kap
            vr2 += w * x * kap
            # F += w b^T f b, b = [[1, 0, 0], [0, x - 1, x]]
            F00 += w * f11
            F01 += w * f12 * (x - 1.0)
            F02 += w * f12 * x
            F11 += w * f22 * (x - 1.0) * (x - 1.0)
            F12 += w * f22 * (x - 1.0) * x
            F22 += w * f22 * x * x
            # the section's share of the totals (used from the converged pass)
            energy += w * section[5]
            mean_p += ws[i] * section[7]
            hinge1 += w * (x - 1.0) * section[8]
            hinge2 += w * x * section[8]
            amax = max(amax, section[9])
            half = 0.5 * depth * e[i, 1]
            for side in range(2):  # surfaces y = -h/2, +h/2 with their outer layers' history
                eps = axis + (2 * side - 1) * half
                surface = max(surface, abs(eps))
                if elastic:
                    smax = max(smax, E * abs(eps))
                else:
                    k = (i * n_f + side * (n_f - 1)) * per
                    sig = _fibre(mat, eps, base, k, write, False)[0]
                    smax = max(smax, abs(sig))
        d0 = v[0] - vr0
        d1 = v[1] - vr1
        d2 = v[2] - vr2
        error = max(abs(d0) / span, abs(d1), abs(d2), worst / span) / scale
        # converged; or stalled at round-off (sums over every fibre) within ROUND_OFF of it
        if error <= TOLERANCE or (error <= ROUND_OFF and error >= 0.5 * previous):
            F[0], F[1], F[2], F[3], F[4], F[5] = F00, F01, F02, F11, F12, F22
            totals[0] = energy
            totals[1] = mean_p
            totals[2] = hinge1
            totals[3] = hinge2
            totals[4] = amax
            totals[5] = surface
            totals[6] = smax
            for i in range(n_s):
                if bilinear and yielded[i] == 0.0:
                    first = i * n_f * per
                    for k in range(n_f):
                        if write[first + k * per + 2] > 0.0:
                            yielded[i] = 1.0
                            break
            return 0.0
        previous = error
        dq0, dq1, dq2 = _solve3(F00, F01, F02, F11, F12, F22, d0, d1, d2)
        if not (abs(dq0) < np.inf and abs(dq1) < np.inf and abs(dq2) < np.inf):
            return np.inf
        q[0] += dq0
        q[1] += dq1
        q[2] += dq2
        for i in range(n_s):
            x = xs[i]
            dM = (x - 1.0) * dq1 + x * dq2
            residual[i, 2] = residual[i, 0] + flex[i, 0] * dq0 + flex[i, 1] * dM
            residual[i, 3] = residual[i, 1] + flex[i, 1] * dq0 + flex[i, 2] * dM
            e[i, 0] += residual[i, 2]
            e[i, 1] += residual[i, 3]
    return error


@njit(cache=True)
def _solve3(F00, F01, F02, F11, F12, F22, d0, d1, d2):
    """x = F^-1 d for a symmetric 3 x 3 F (cofactors); nan where F is singular."""
    c00 = F11 * F22 - F12 * F12
    c01 = F02 * F12 - F01 * F22
    c02 = F01 * F12 - F02 * F11
    c11 = F00 * F22 - F02 * F02
    c12 = F01 * F02 - F00 * F12
    c22 = F00 * F11 - F01 * F01
    det = F00 * c00 + F01 * c01 + F02 * c02
    if not abs(det) > 0.0:
        return np.nan, np.nan, np.nan
    return (
        (c00 * d0 + c01 * d1 + c02 * d2) / det,
        (c01 * d0 + c11 * d1 + c12 * d2) / det,
        (c02 * d0 + c12 * d1 + c22 * d2) / det,
    )


@njit(cache=True)
def _predict(v, v_n, q, e, flex, xs, F):
    """The tangent predictor from the committed state: q += F^-1 (v - v_n), each section's
    e += f_s b dq (F, f_s: the committed element's and sections' flexibilities)."""
    dq0, dq1, dq2 = _solve3(F[0], F[1], F[2], F[3], F[4], F[5], v[0] - v_n[0], v[1] - v_n[1],
                            v[2] - v_n[2])  # fmt: skip
    if not (abs(dq0) < np.inf and abs(dq1) < np.inf and abs(dq2) < np.inf):
        return
    q[0] += dq0
    q[1] += dq1
    q[2] += dq2
    for i in range(xs.size):
        dM = (xs[i] - 1.0) * dq1 + xs[i] * dq2
        e[i, 0] += flex[i, 0] * dq0 + flex[i, 1] * dM
        e[i, 1] += flex[i, 1] * dq0 + flex[i, 2] * dM


@njit(cache=True)
def fibre_local_law(stretch, th1, th2, ea_l, ei_l, pretension, law, state, c, commit):
    """The collar's fibre-section frame element in its local frame (the module's docstring):
    the same call and returns as colonna.core.collar_law.resultant_local_law.

    stretch = chord length - L0 (m), th1, th2 = end rotations relative to the chord (rad);
    ea_l = E A / L, ei_l = E I' / L0, pretension P (N); law = the collar's law row
    (colonna.core.collar_law: fibre entries from LAW_KIND on); state[c] = this collar's state
    (fibre_state_size numbers; zeros: unstressed but for P), updated only with commit.
    Returns (N, M1, M2, elastic energy U (J), axial plastic strain (the mean over the section
    and the span), largest surface strain of the sections)."""
    span = law[1] / ea_l
    if state[c, FRACTURED] != 0.0:
        return 0.0, 0.0, 0.0, 0.0, state[c, S_P] / span, 0.0
    if (
        stretch == state[c, V_COMMITTED]
        and th1 == state[c, V_COMMITTED + 1]
        and th2 == state[c, V_COMMITTED + 2]
    ):  # the committed state itself (a history's replay records only the header)
        return (
            state[c, Q_COMMITTED] + pretension,
            state[c, Q_COMMITTED + 1],
            state[c, Q_COMMITTED + 2],
            state[c, U_COMMITTED],
            state[c, S_P] / span,
            state[c, SURFACE],
        )
    n_s = int(law[8])
    n_f = int(law[9])
    E, depth, width = law[10], law[14], law[15]
    eps_u = law[6]
    inertia = width * depth**3 / 12.0
    rho = math.sqrt(ei_l * span / (E * inertia))
    eps0 = pretension / law[1]
    area = width * depth / n_f
    spread = 1.0 / math.sqrt(1.0 - 1.0 / (n_f * n_f))
    xs = LOBATTO_POINTS[n_s, :n_s]
    ws = LOBATTO_WEIGHTS[n_s, :n_s]
    floor = 1e-6 * E  # the iterations' least fibre modulus (E_h = 0: no singular section)
    sections = HEADER + SECTION_SIZE * n_s
    mat = law[10:24]
    per = PER_FIBRE if law[16] == BILINEAR else PER_FIBRE_MP
    size = per * n_s * n_f
    if state.shape[1] < sections + size:
        raise ValueError("a fibre collar's state row is short: size it with state_size(laws)")
    # one work array (an allocation costs as much as a section), cut into the trial's arrays
    work = np.empty(n_f + 37 + TOTALS + 15 * n_s + size)
    ys = work[:n_f]
    o = n_f
    F0, F, q0, q, v_n, v, last = (
        work[o : o + 6],
        work[o + 6 : o + 12],
        work[o + 12 : o + 15],
        work[o + 15 : o + 18],
        work[o + 18 : o + 21],
        work[o + 21 : o + 24],
        work[o + 24 : o + 27],
    )
    o += 27
    section = work[o : o + 10]
    o += 10
    totals = work[o : o + TOTALS]
    o += TOTALS
    e0 = work[o : o + 2 * n_s].reshape((n_s, 2))
    e = work[o + 2 * n_s : o + 4 * n_s].reshape((n_s, 2))
    residual = work[o + 4 * n_s : o + 8 * n_s].reshape((n_s, 4))
    o += 8 * n_s
    flex0 = work[o : o + 3 * n_s].reshape((n_s, 3))
    flex = work[o + 3 * n_s : o + 6 * n_s].reshape((n_s, 3))
    o += 6 * n_s
    yielded = work[o : o + n_s]
    o += n_s
    write = work[o : o + size]
    for j in range(n_f):
        ys[j] = (-0.5 * depth + (j + 0.5) * depth / n_f) * spread
    committed = state[c, HEADER:sections].reshape((n_s, SECTION_SIZE))
    base = state[c, sections : sections + size]
    F0[:] = state[c, FLEXIBILITY : FLEXIBILITY + 6]
    for i in range(n_s):
        e0[i, 0] = committed[i, 0]
        e0[i, 1] = committed[i, 1]
        flex0[i, 0] = committed[i, 2]
        flex0[i, 1] = committed[i, 3]
        flex0[i, 2] = committed[i, 4]
        yielded[i] = committed[i, 5]
    if F0[0] == 0.0:  # the unstressed collar: elastic
        F0[0] = span / (E * width * depth)
        F0[1] = F0[2] = 0.0
        F0[3] = span / (3.0 * E * inertia)
        F0[4] = -span / (6.0 * E * inertia)
        F0[5] = F0[3]
        for i in range(n_s):
            flex0[i, 0] = 1.0 / (E * width * depth)
            flex0[i, 1] = 0.0
            flex0[i, 2] = 1.0 / (E * inertia)
    q0[0] = state[c, Q_COMMITTED] + pretension
    q0[1] = state[c, Q_COMMITTED + 1] / rho
    q0[2] = state[c, Q_COMMITTED + 2] / rho
    v_n[0] = state[c, V_COMMITTED]
    v_n[1] = rho * state[c, V_COMMITTED + 1]
    v_n[2] = rho * state[c, V_COMMITTED + 2]
    v[0] = stretch
    v[1] = rho * th1
    v[2] = rho * th2
    q[:] = q0
    e[:] = e0
    flex[:] = flex0
    _predict(v, v_n, q, e, flex, xs, F0)
    error = _solve(v, q, e, flex, yielded, base, write, xs, ws, span, eps0, ys, area, mat,
                   per, floor, depth, F, totals, section, residual)  # fmt: skip
    converged = error <= TOLERANCE
    steps = 1
    while not converged and steps < 64:  # cut the step: sub-steps along the straight path
        steps *= 2
        q[:] = q0
        e[:] = e0
        flex[:] = flex0
        for i in range(n_s):
            yielded[i] = committed[i, 5]
        F[:] = F0
        base = state[c, sections : sections + size].copy()  # sub-steps advance it
        last[:] = v_n
        converged = True
        for k in range(1, steps + 1):
            target = v_n + (v - v_n) * (k / steps)
            _predict(target, last, q, e, flex, xs, F)
            error = _solve(target, q, e, flex, yielded, base, write, xs, ws, span, eps0, ys,
                           area, mat, per, floor, depth, F, totals, section,
                           residual)  # fmt: skip
            if error > TOLERANCE:
                converged = False
                break
            last[:] = target
            if k < steps:
                base[:] = write
    if not converged:  # not an answer: say so (the solvers stop on a non-finite force)
        return np.nan, np.nan, np.nan, np.nan, np.nan, np.nan
    energy = totals[0] - 0.5 * pretension * eps0 * span
    mean_p = totals[1]
    surface = totals[5]
    N = q[0]
    M1 = q[1] * rho
    M2 = q[2] * rho
    if commit:
        work = (
            0.5 * (N + state[c, Q_COMMITTED] + pretension) * (stretch - state[c, V_COMMITTED])
            + 0.5 * (M1 + state[c, Q_COMMITTED + 1]) * (th1 - state[c, V_COMMITTED + 1])
            + 0.5 * (M2 + state[c, Q_COMMITTED + 2]) * (th2 - state[c, V_COMMITTED + 2])
            - (energy - state[c, U_COMMITTED])
        )
        state[c, WORK] += work
        state[c, S_P] = mean_p * span
        state[c, ALPHA] = totals[4]
        state[c, HINGE1] = totals[2] / rho
        state[c, HINGE2] = totals[3] / rho
        state[c, V_COMMITTED] = stretch
        state[c, V_COMMITTED + 1] = th1
        state[c, V_COMMITTED + 2] = th2
        state[c, Q_COMMITTED] = N - pretension
        state[c, Q_COMMITTED + 1] = M1
        state[c, Q_COMMITTED + 2] = M2
        state[c, U_COMMITTED] = energy
        state[c, STRESS] = totals[6]
        state[c, SURFACE] = surface
        state[c, FLEXIBILITY : FLEXIBILITY + 6] = F
        for i in range(n_s):
            committed[i, 0] = e[i, 0]
            committed[i, 1] = e[i, 1]
            committed[i, 2] = flex[i, 0]
            committed[i, 3] = flex[i, 1]
            committed[i, 4] = flex[i, 2]
            committed[i, 5] = yielded[i]
        state[c, sections : sections + size] = write
        if surface > state[c, FIBRE_STRAIN]:
            state[c, FIBRE_STRAIN] = surface
        if eps_u > 0.0 and surface >= eps_u:
            state[c, FRACTURED] = 1.0
            state[c, WORK] += energy  # released: the broken band's ends spring back
            return 0.0, 0.0, 0.0, 0.0, mean_p, surface
    return N, M1, M2, energy, mean_p, surface
