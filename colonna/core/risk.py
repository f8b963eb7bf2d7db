"""Risk: the mean annual frequency of a limit state at a site, from its fragility and the site's
hazard (:mod:`colonna.core.hazard`), and the probability of it in T years.

The total probability theorem over the intensity (Cornell et al. 2002, Eq. 4):

    lambda_LS = int P[LS | IM = x] |d lambda_IM(x)| = int lambda_IM(x) dP[LS | IM = x]

(integrated by parts: P lambda_IM vanishes at 0 and at infinity for a lognormal fragility). The
second form is the one computed: the expectation of the hazard at the capacity C, a lognormal
variable C = x0 + theta exp(beta Z), Z standard normal (x0 the shifted fit's origin, 0 for the
plain lognormal):

    lambda_LS = int lambda_IM(x0 + theta e^(beta z)) phi(z) dz,

by the trapezoidal rule on a uniform grid of z (a uniform grid of ln(x - x0)): z from
-(12 + k beta) to 12 (k the hazard's steepest log-log slope: for a power law the integrand
phi(z) e^(-k beta z) peaks at z = -k beta), :data:`POINTS` points. The integrand is smooth
and decays like a Gaussian, so that the rule converges faster than any power of dz (the
power law's closed form to 1e-9). It is computed in logs (ln lambda_IM - z^2 / 2, then exp):
a wide fit over a power law, which grows without bound at low intensities, stays finite
(inf only past the largest double).
A step fragility (beta = 0, stripes that separate) gives lambda_IM(x0 + theta).

For a power-law hazard k0 x^-k and a plain lognormal fragility the closed form is
lambda_LS = k0 theta^-k exp(k^2 beta^2 / 2) (Cornell et al. 2002, Eq. 11), which the tests pin.
In T years (Poisson occurrences): P = 1 - exp(-lambda_LS T).

Reference: C. A. Cornell, F. Jalayer, R. O. Hamburger, D. A. Foutch (2002), Journal of
Structural Engineering 128(4), 526-533.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .hazard import HazardCurve, annual_frequency, log_annual_frequency

__all__ = [
    "POINTS",
    "LimitStateFrequency",
    "limit_state_frequency",
    "probability_in",
]

POINTS = 4001  # trapezoid points over z
Z_TOP = 12.0  # standard normals: phi beyond 12 is below 1e-31


@dataclass(frozen=True)
class LimitStateFrequency:
    """The mean annual frequency ``value`` (1/year) of a limit state, with the shares of it that
    come from capacities below the hazard table's lowest intensity (``below``) and above its
    highest (``above``): the parts read where the table is held or extrapolated or truncated
    (0 for a power law); and those from capacities below and above a range ``within`` (e.g.
    the levels the fragility was fitted over: the parts read on its fit's extrapolation),
    ``below_within``, ``above_within``."""

    value: float
    below: float = 0.0
    above: float = 0.0
    below_within: float = 0.0
    above_within: float = 0.0


def limit_state_frequency(
    hazard: HazardCurve,
    median: float,
    beta: float,
    origin: float = 0.0,
    within: tuple[float, float] | None = None,
) -> LimitStateFrequency:
    """lambda_LS of the fragility Phi(ln((x - origin) / median) / beta) (x > origin; the plain
    lognormal with origin 0) at the site of ``hazard`` (in the fragility's measure: see
    :func:`colonna.core.hazard.in_measure`), by the module's integral; with ``within``, the
    shares of it from capacities outside that range too."""
    for name, value in (("median", median), ("origin", origin)):
        if not (math.isfinite(value) and value >= (0.0 if name == "origin" else 1e-300)):
            raise InputError(f"fragility {name} = {value:g}: must be finite and > 0 (>= 0)")
    if not (math.isfinite(beta) and beta >= 0.0):
        raise InputError(f"fragility beta = {beta:g}: must be finite and >= 0")
    low, high = hazard.range
    first, last = within if within is not None else (0.0, math.inf)
    if beta == 0.0:
        step = origin + median
        value = float(annual_frequency(hazard, step))
        s = 1.0 if value > 0.0 else 0.0
        return LimitStateFrequency(
            value, s * (step < low), s * (step > high), s * (step < first), s * (step > last)
        )
    k = max(float(np.max(np.abs(hazard.slopes()))), 0.0)
    z = np.linspace(-(Z_TOP + k * beta), Z_TOP, POINTS)
    if origin > 0.0:
        x = origin + median * np.exp(beta * z)
        lx = np.log(x)
    else:  # ln x exactly, also where x itself would underflow
        lx = math.log(median) + beta * z
        x = np.exp(lx)
    with np.errstate(over="ignore"):  # (a fit whose lambda is past the largest double: inf)
        f = np.exp(log_annual_frequency(hazard, lx) - 0.5 * z * z - 0.5 * math.log(2 * math.pi))
        value = float(np.trapezoid(f, z))
    if not value > 0.0 or math.isinf(value):
        return LimitStateFrequency(value if value > 0.0 else 0.0)

    def share(outside):
        return float(np.trapezoid(np.where(outside, f, 0.0), z)) / value

    return LimitStateFrequency(
        value, share(x < low), share(x > high), share(x < first), share(x > last)
    )


def probability_in(frequency, years: float):
    """The probability of at least one occurrence in ``years`` of an event of mean annual
    ``frequency`` (Poisson): 1 - exp(-lambda T)."""
    return -np.expm1(-np.asarray(frequency, dtype=float) * years)
