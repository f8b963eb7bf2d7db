"""The collars' bilinear axial law, shared by the FEM's and the multibody model's compiled
frame elements (numba): elastic E A up to N_y = f_y A, then isotropic linear hardening."""

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
