"""A cohesive law for the intact stone of a partially cracked column's mid-plane (issue 51).

Scalar functions (floats in, floats out, ``math`` only, no Python objects), compiled with
``numba.njit`` and cached with the other kernel modules (one unit:
``colonna.core.jit_cache.KERNEL_MODULES``), so that a compiled kernel calls them per interface
node pair and Python gets the same numbers. Inputs are checked once, in Python, by
:func:`check_parameters`; the scalar functions trust them.

**The law: bilinear, with the mixed-mode interaction of Camanho & Davila** (Camanho, Davila & de
Moura, J. Compos. Mater. 37 (2003) 1415-1438; Camanho & Davila, NASA/TM-2002-211737). Bilinear
rather than exponential: it has a finite penalty stiffness K before the peak (the explicit step
depends on it, :func:`stable_step`), a finite separation at which the interface is fully
damaged (then the crack is open and the crack faces' contact takes over), and its peak traction
and fracture energy are its two parameters exactly (the exponential law reaches zero traction
only asymptotically and its initial stiffness is set by f_t and G_f, not chosen).

With the opening delta_n (> 0 opens) and the sliding delta_s, <x> = max(x, 0):

* effective separation  delta_m = sqrt(<delta_n>^2 + delta_s^2);
  mode mixity           B = delta_s^2 / (<delta_n>^2 + delta_s^2)  (G_II / (G_I + G_II));
* onset                 delta_m0 = sqrt(dn0^2 + (ds0^2 - dn0^2) B^eta),  dn0 = f_t / K,
                        ds0 = s / K  (delta_m0 = ds0 in contact, delta_n <= 0);
* full damage           delta_mf = 2 [G_I + (G_II - G_I) B^eta] / (K delta_m0)
                        (Benzeggagh-Kenane: G_c = G_I + (G_II - G_I) B^eta; 2 G_II / s in
                        contact);
* damage                d = delta_mf (delta_m - delta_m0) / (delta_m (delta_mf - delta_m0)) in
                        [0, 1], and never less than before (irreversible: unloading follows
                        the damaged secant (1 - d) K back to the origin);
* tractions             t_n = (1 - d) K delta_n opening, K delta_n in contact (the penalty holds
                        the faces apart whatever the damage);
                        t_s = (1 - d) K delta_s + d t_f: the damaged fraction d of the area
                        carries Coulomb friction t_f (Alfano & Sacco, Int. J. Numer. Meth. Engng
                        68 (2006) 542-582), regularised stick with the same K and a return
                        mapping to |t_f| <= mu <-t_n>, its plastic slip the history variable.

In pure mode I the law is the bilinear softening of Hillerborg et al. (Cem. Concr. Res. 6 (1976)
773-781): peak f_t at delta_n0 = f_t / K, zero at delta_nf = 2 G_I / f_t, the area under it
G_I. Where the stone's mode-II properties are unknown, s = f_t and G_II = G_I make the law an
effective-separation law independent of B (and of eta); stones' shear strength exceeds their
tensile strength, so this under-rates the interface in shear.

>>> K, ft, G = 1e12, 8e6, 100.0
>>> t_n, t_s, d, slip = traction(ft / K, 0.0, 0.0, 0.0, K, ft, ft, G, G, 2.0, 0.6)
>>> round(t_n / 1e6, 6), d  # the peak, undamaged
(8.0, 0.0)
>>> t_n, t_s, d, slip = traction(2 * G / ft, 0.0, 0.0, 0.0, K, ft, ft, G, G, 2.0, 0.6)
>>> t_n, d  # at delta_nf = 2 G / f_t: fully damaged, no traction
(0.0, 1.0)
"""

from __future__ import annotations

import math

from numba import njit

from ..core.errors import InputError, require_non_negative, require_positive, require_range
from ..core.jit_cache import ensure_fresh

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)


@njit(cache=True)
def onset_and_final(
    delta_n: float,
    delta_s: float,
    K: float,
    f_t: float,
    s: float,
    G_I: float,
    G_II: float,
    eta: float,
) -> tuple[float, float]:
    """(delta_m0, delta_mf): the effective separations at the peak and at full damage for the
    present mode mixity (Camanho & Davila 2003 with the B-K criterion; module docstring)."""
    ds0 = s / K
    if delta_n <= 0.0:  # contact: mode II only
        return ds0, 2.0 * G_II / s
    dn0 = f_t / K
    dm2 = delta_n * delta_n + delta_s * delta_s
    if dm2 <= 0.0:  # an opening so small that its square underflows: mode I
        return dn0, 2.0 * G_I / f_t
    B = delta_s * delta_s / dm2
    Beta = B**eta
    d0 = math.sqrt(dn0 * dn0 + (ds0 * ds0 - dn0 * dn0) * Beta)
    return d0, 2.0 * (G_I + (G_II - G_I) * Beta) / (K * d0)


@njit(cache=True)
def damage(
    delta_n: float,
    delta_s: float,
    d_old: float,
    K: float,
    f_t: float,
    s: float,
    G_I: float,
    G_II: float,
    eta: float,
) -> float:
    """The damage after a separation (delta_n, delta_s), never less than ``d_old``."""
    pos = delta_n if delta_n > 0.0 else 0.0
    dm = math.sqrt(pos * pos + delta_s * delta_s)
    d0, df = onset_and_final(delta_n, delta_s, K, f_t, s, G_I, G_II, eta)
    if dm <= d0:
        return d_old
    d = 1.0 if dm >= df else df * (dm - d0) / (dm * (df - d0))
    return d if d > d_old else d_old


@njit(cache=True)
def traction(
    delta_n: float,
    delta_s: float,
    d_old: float,
    slip_old: float,
    K: float,
    f_t: float,
    s: float,
    G_I: float,
    G_II: float,
    eta: float,
    mu: float,
) -> tuple[float, float, float, float]:
    """(t_n, t_s, d, slip): the tractions (Pa; t_n > 0 pulls the faces together against an
    opening) at the separation (delta_n, delta_s) (m), the damage d and the friction's plastic
    slip (m) after it, from those before it (module docstring)."""
    d = damage(delta_n, delta_s, d_old, K, f_t, s, G_I, G_II, eta)
    if delta_n > 0.0:
        t_n = (1.0 - d) * K * delta_n
        pressure = 0.0
    else:
        t_n = K * delta_n
        pressure = -t_n
    # Coulomb friction on the damaged fraction: elastic predictor, return to the cone
    slip = slip_old
    t_f = K * (delta_s - slip_old)
    cap = mu * pressure
    if abs(t_f) > cap:
        t_f = math.copysign(cap, t_f)
        slip = delta_s - t_f / K
    t_s = (1.0 - d) * K * delta_s + d * t_f
    return t_n, t_s, d, slip


def stable_step(K: float, area: float, mass_a: float, mass_b: float) -> float:
    """The central-difference limit 2 / omega of one interface node pair: a spring K * area
    (N/m) between the lumped masses m_a and m_b (kg), omega^2 = K A (1/m_a + 1/m_b) (s).

    >>> round(stable_step(1e12, 1e-4, 1.0, 1.0), 9)  # 2 / sqrt(1e8 * 2)
    0.000141421
    """
    return 2.0 / math.sqrt(K * area * (1.0 / mass_a + 1.0 / mass_b))


def penalty_stiffness(E: float, h: float, alpha: float = 1.0) -> float:
    """K = alpha E / h (Pa/m): the interface adds a compliance 1 / K, that of a layer of stone
    h / alpha thick (Turon, Davila, Camanho & Costa, Eng. Fract. Mech. 74 (2007) 1665-1682,
    advise alpha >= 50 for laminates). alpha = 1 is the crack faces' contact penalty of the FEM
    (fem/model.py); its node pair's stable step is then h / c with c = sqrt(E / rho), and
    sqrt(alpha) times shorter for a stiffer one (docs/physics.md)."""
    return alpha * E / h


def cohesive_zone_length(E: float, G_I: float, f_t: float, M: float = 1.0) -> float:
    """M E G_I / f_t^2 (m): Hillerborg's characteristic length for M = 1, the length of the
    softening zone ahead of a growing crack (M between 0.2 and 1 by the model: Turon et al.
    2007); a mesh resolves the law with a few interface elements within it.

    >>> round(cohesive_zone_length(50e9, 100.0, 8e6), 4)  # 50e9 * 100 / 8e6^2
    0.0781
    """
    return M * E * G_I / (f_t * f_t)


def check_parameters(
    K: float, f_t: float, s: float, G_I: float, G_II: float, eta: float, mu: float
) -> None:
    """InputError naming the first parameter out of its range; the peak must come before full
    damage in both modes (K > f_t^2 / (2 G_I) and K > s^2 / (2 G_II))."""
    require_positive("cohesive penalty stiffness K (Pa/m)", K)
    require_positive("cohesive tensile strength f_t (Pa)", f_t)
    require_positive("cohesive shear strength s (Pa)", s)
    require_positive("cohesive mode-I fracture energy G_I (N/m)", G_I)
    require_positive("cohesive mode-II fracture energy G_II (N/m)", G_II)
    require_range("cohesive B-K exponent eta", eta, 0.5, 5.0, closed_low=True, closed_high=True)
    require_non_negative("cohesive friction coefficient mu", mu)
    for mode, strength, energy in (("I", f_t, G_I), ("II", s, G_II)):
        if not K > strength**2 / (2.0 * energy):
            raise InputError(
                f"cohesive penalty stiffness K = {K:g} Pa/m is not allowed: with the mode-{mode} "
                f"strength {strength:g} Pa and energy {energy:g} N/m it must exceed "
                f"{strength**2 / (2.0 * energy):g} Pa/m (strength^2 / (2 G)), or the peak "
                "separation passes the final one"
            )


__all__ = [
    "check_parameters",
    "cohesive_zone_length",
    "damage",
    "onset_and_final",
    "penalty_stiffness",
    "stable_step",
    "traction",
]
