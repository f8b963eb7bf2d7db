"""The collars' compiled frame element (numba), shared by the FEM's and the multibody model's
collars: the co-rotational element's local law (:func:`frame_local_law`) and its bilinear axial
law (:func:`axial_return_mapping`: elastic E A up to N_y = f_y A, then isotropic linear
hardening)."""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def axial_return_mapping(N_trial, ea_l, n_yield, ea, ha, state, c, commit):
    """Axial force of collar c from its trial N_trial = pretension + EA/L (stretch - s_p).

    n_yield = f_y A (0: elastic collar), ea = E A, ha = H A with H = E E_h / (E - E_h), ea_l =
    E A / L. state[c] = (plastic elongation s_p (m), accumulated plastic strain alpha, plastic
    work (J)); |N| <= n_yield + H A alpha, with the excess returned along EA/L and the surface
    grown by the plastic strain. Updates the state with commit. Returns (N, s_p / L)."""
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
def frame_local_law(stretch, th1, th2, ea_l, ei_l, pretension, n_yield, ea, ha, state, c, commit):
    """The collar's co-rotational Euler-Bernoulli frame element in its local frame, shared by
    the FEM's and the multibody model's collars.

    stretch = chord length - L0 (m), th1, th2 = end rotations relative to the chord (rad);
    ea_l = E A / L, ei_l = E I' / L0, pretension (N), and the axial law's n_yield, ea, ha
    (:func:`axial_return_mapping`, which updates state[c] with commit). End moments
    M1 = EI'/L0 (4 th1 + 2 th2), M2 = EI'/L0 (2 th1 + 4 th2); elastic energy
    U = P e + EA/L e^2 / 2 + EI'/L0 (2 th1^2 + 2 th1 th2 + 2 th2^2), e = stretch - s_p.
    Returns (N, M1, M2, U, plastic strain s_p / L)."""
    N, plastic_strain = axial_return_mapping(
        pretension + ea_l * (stretch - state[c, 0]), ea_l, n_yield, ea, ha, state, c, commit
    )
    elastic = stretch - plastic_strain * ea / ea_l
    M1 = ei_l * (4.0 * th1 + 2.0 * th2)
    M2 = ei_l * (2.0 * th1 + 4.0 * th2)
    energy = (
        pretension * elastic
        + 0.5 * ea_l * elastic * elastic
        + ei_l * (2.0 * th1 * th1 + 2.0 * th1 * th2 + 2.0 * th2 * th2)
    )
    return N, M1, M2, energy, plastic_strain
