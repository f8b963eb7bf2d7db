"""Synthetic near-fault accelerograms: a Mavroeidis & Papageorgiou (2003) velocity pulse on a
Rezaeian & Der Kiureghian (2008) stochastic background, seeded, with the drawn parameters on
record. For record suites when no recorded motions are at hand.

**Pulse** (Mavroeidis & Papageorgiou 2003, Eq. 1; f_p = 1 / T_p):

    v(t) = (V_p / 2) [1 + cos(2 pi f_p (t - t0) / gamma)] cos(2 pi f_p (t - t0) + nu)
    for |t - t0| <= gamma / (2 f_p), zero outside,

gamma > 1 the number of half cycles under the envelope, nu the phase. Its acceleration is the
exact derivative (:func:`pulse_acceleration`). |v| <= V_p, with V_p reached at t0 where
nu = 0 (or pi); the carrier's zeros are T_p / 2 apart.

**Background** (Rezaeian & Der Kiureghian 2008): a modulated, filtered white noise,

    a(t_k) = q(t_k) sum_{i<k} h(t_k - t_i; w_f(t_i)) u_i / sqrt(sum_{i<k} h(t_k - t_i; w_f(t_i))^2),

u_i independent standard normal at the samples, h the unit-impulse response of an oscillator
of frequency w_f(t) = w_mid + w' (t - t_mid) and damping zeta_f,
h(s; w) = w / sqrt(1 - zeta_f^2) exp(-zeta_f w s) sin(w sqrt(1 - zeta_f^2) s), and the gamma
modulating function q(t) = alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t). The sum, normalised, has
unit variance at every sample, so E[a(t)^2] = q(t)^2: the expected Arias intensity is
pi / (2 g) int q^2 dt. The alphas come from the model's physical parameters: the Arias
intensity I_A, the significant duration D5-95 and t_mid, the time at 45 % of I_A. The
cumulative of q^2 is a gamma distribution of shape 2 alpha_2 - 1 and scale 1 / (2 alpha_3), so
its shape solves (t95 - t5) / t45 = D5-95 / t_mid and its scale t45 = t_mid
(:func:`modulation`); alpha_1 then gives I_A.

**Record** = background + pulse, baseline-corrected as :mod:`colonna.core.intensity` does (the
line c0 + c1 t taken off the acceleration so that the ground ends at rest where it started).

**Drawn parameters** (:func:`draw_parameters`): uniform (log-uniform for T_p and I_A) over
ranges chosen to span near-fault pulse-like motions: T_p 0.5-3 s, V_p 0.2-0.8 m/s,
gamma 1.5-3, nu 0-2 pi, t0 within 1.5 s of t_mid (and the pulse inside the record); I_A
0.05-0.5 m/s, D5-95 5-12 s, t_mid 4-7 s, w_mid / 2 pi 2-8 Hz, w' / 2 pi -0.15-0.05 Hz/s,
zeta_f 0.1-0.5. They are the generator's stated choice, not a fitted distribution (Rezaeian &
Der Kiureghian 2010 fit one to the NGA records; Shahi & Baker 2011 relate T_p to magnitude).
Each record draws from its own stream, ``SeedSequence(seed).spawn(count)``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .constants import STANDARD_GRAVITY
from .errors import InputError
from .ground import Record

__all__ = [
    "SyntheticParameters",
    "background",
    "draw_parameters",
    "modulation",
    "pulse_acceleration",
    "pulse_velocity",
    "synthetic_record",
    "synthetic_suite",
]

MIN_FILTER_FREQUENCY = 2.0 * math.pi * 0.1  # rad/s: w_f(t) is held above it


@dataclass(frozen=True)
class SyntheticParameters:
    """One synthetic record's parameters (SI): pulse ``Tp`` (s), ``Vp`` (m/s), ``gamma``,
    ``nu`` (rad), ``t0`` (s); background ``arias`` (m/s), ``d5_95`` (s), ``t_mid`` (s),
    ``f_mid`` (Hz), ``f_slope`` (Hz/s), ``zeta_f``; ``noise_seed``: the integer that seeds its
    white noise."""

    Tp: float
    Vp: float
    gamma: float
    nu: float
    t0: float
    arias: float
    d5_95: float
    t_mid: float
    f_mid: float
    f_slope: float
    zeta_f: float
    noise_seed: int

    def to_dict(self) -> dict:
        return asdict(self)


def _pulse_phase(t, Tp: float, gamma: float, t0: float):
    s = np.asarray(t, dtype=float) - t0
    inside = np.abs(s) <= gamma * Tp / 2.0
    return 2.0 * math.pi * s / Tp, inside


def pulse_velocity(t, Tp: float, Vp: float, gamma: float, nu: float, t0: float):
    """The Mavroeidis & Papageorgiou (2003) velocity pulse (m/s) at times t (s)."""
    _check_pulse(Tp, gamma)
    phase, inside = _pulse_phase(t, Tp, gamma, t0)
    v = 0.5 * Vp * (1.0 + np.cos(phase / gamma)) * np.cos(phase + nu)
    return np.where(inside, v, 0.0)


def pulse_acceleration(t, Tp: float, Vp: float, gamma: float, nu: float, t0: float):
    """d/dt of :func:`pulse_velocity` (m/s^2):
    -(pi f_p V_p / gamma) [sin(2 pi f_p s / gamma) cos(2 pi f_p s + nu)
    + gamma sin(2 pi f_p s + nu) (1 + cos(2 pi f_p s / gamma))], s = t - t0."""
    _check_pulse(Tp, gamma)
    phase, inside = _pulse_phase(t, Tp, gamma, t0)
    a = -(math.pi * Vp / (gamma * Tp)) * (
        np.sin(phase / gamma) * np.cos(phase + nu)
        + gamma * np.sin(phase + nu) * (1.0 + np.cos(phase / gamma))
    )
    return np.where(inside, a, 0.0)


def _check_pulse(Tp: float, gamma: float) -> None:
    if not 0.0 < Tp < math.inf:
        raise InputError(f"Tp = {Tp:g} s must be > 0")
    if not 1.0 < gamma < math.inf:
        raise InputError(f"gamma = {gamma:g} must be > 1 (Mavroeidis & Papageorgiou 2003)")


def modulation(t, arias: float, d5_95: float, t_mid: float, g: float = STANDARD_GRAVITY):
    """(q(t) (m/s^2), (alpha_1, alpha_2, alpha_3)): the gamma modulating function of Rezaeian &
    Der Kiureghian (2008) whose q^2 holds ``arias`` (m/s) = pi / (2 g) int q^2 dt, with 5-95 %
    of it over ``d5_95`` (s) and 45 % reached at ``t_mid`` (s)."""
    from scipy.optimize import brentq
    from scipy.special import gammaln
    from scipy.stats import gamma as gamma_law

    for name, value in (("arias", arias), ("d5_95", d5_95), ("t_mid", t_mid)):
        if not 0.0 < value < math.inf:
            raise InputError(f"{name} = {value:g} must be > 0")
    ratio = d5_95 / t_mid

    def spread(log_shape):
        q05, q45, q95 = gamma_law.ppf([0.05, 0.45, 0.95], math.exp(log_shape))
        return (q95 - q05) / max(q45, 1e-300) - ratio

    try:
        shape = math.exp(brentq(spread, math.log(1e-3), math.log(1e4), xtol=1e-14))
    except ValueError:
        raise InputError(
            f"d5_95 / t_mid = {ratio:.3g} cannot be reached by the gamma modulating function"
        ) from None
    scale = t_mid / float(gamma_law.ppf(0.45, shape))
    alpha2, alpha3 = (shape + 1.0) / 2.0, 1.0 / (2.0 * scale)
    # int_0^inf t^(k-1) e^(-t / scale) dt = Gamma(k) scale^k, k = 2 alpha_2 - 1
    integral = math.exp(gammaln(shape) + shape * math.log(scale))
    alpha1 = math.sqrt(arias * 2.0 * g / math.pi / integral)
    t = np.asarray(t, dtype=float)
    with np.errstate(divide="ignore"):
        q = alpha1 * np.where(t > 0.0, np.abs(t) ** (alpha2 - 1.0), 0.0) * np.exp(-alpha3 * t)
    return q, (alpha1, alpha2, alpha3)


def background(t, q, f_mid: float, f_slope: float, zeta_f: float, t_mid: float, rng):
    """The modulated filtered white noise of Rezaeian & Der Kiureghian (2008) at the samples t
    (uniform, s), with modulating function values ``q``, filter frequency f_mid + f_slope
    (t - t_mid) (Hz, held above 0.1 Hz) and damping ``zeta_f``; u_i from ``rng``. a(t_0) = 0."""
    if not 0.0 < zeta_f < 1.0:
        raise InputError(f"zeta_f = {zeta_f:g} must be in (0, 1)")
    t = np.asarray(t, dtype=float)
    u = rng.standard_normal(t.size)
    omega = np.maximum(2.0 * math.pi * (f_mid + f_slope * (t - t_mid)), MIN_FILTER_FREQUENCY)
    damped = omega * math.sqrt(1.0 - zeta_f**2)
    gain = omega / math.sqrt(1.0 - zeta_f**2)
    a = np.zeros(t.size)
    chunk = 256
    for start in range(1, t.size, chunk):
        stop = min(start + chunk, t.size)
        # s = t_k - t_i for the rows k of this chunk and the columns i < stop; s <= 0 (i >= k)
        # gives sin(0) = 0, so only the past sums
        s = np.maximum(t[start:stop, None] - t[None, :stop], 0.0)
        h = gain[:stop] * np.exp(-zeta_f * omega[:stop] * s) * np.sin(damped[:stop] * s)
        norm = np.sqrt(np.einsum("ij,ij->i", h, h))
        a[start:stop] = (h @ u[:stop]) / np.where(norm > 0.0, norm, np.inf)
    return np.asarray(q) * a


def synthetic_record(
    parameters: SyntheticParameters,
    *,
    dt: float = 0.01,
    duration: float = 20.0,
    name: str = "synthetic",
    g: float = STANDARD_GRAVITY,
    parts: bool = False,
):
    """The record (m/s^2) of ``parameters``: pulse plus background, baseline-corrected.
    ``parts``: also return a dict of the uncorrected ``pulse`` and ``background``
    accelerations and the pulse's ``velocity``."""
    from .intensity import ground_velocity_displacement

    if not 0.0 < dt <= 0.02:
        raise InputError(f"dt = {dt:g} s must be in (0, 0.02]")
    p = parameters
    t = np.arange(int(round(duration / dt)) + 1) * dt
    q, _ = modulation(t, p.arias, p.d5_95, p.t_mid, g)
    noise = background(
        t, q, p.f_mid, p.f_slope, p.zeta_f, p.t_mid, np.random.default_rng(p.noise_seed)
    )
    pulse = pulse_acceleration(t, p.Tp, p.Vp, p.gamma, p.nu, p.t0)
    raw = Record(t, noise + pulse, name)
    _, corrected, _, _ = ground_velocity_displacement(raw)
    record = Record(t, corrected, name)
    if not parts:
        return record
    velocity = pulse_velocity(t, p.Tp, p.Vp, p.gamma, p.nu, p.t0)
    return record, {"pulse": pulse, "background": noise, "velocity": velocity}


def draw_parameters(rng, duration: float = 20.0) -> SyntheticParameters:
    """One record's parameters drawn from ``rng`` over the ranges of the module notes."""

    def log_uniform(low, high):
        return float(math.exp(rng.uniform(math.log(low), math.log(high))))

    Tp = log_uniform(0.5, 3.0)
    Vp = float(rng.uniform(0.2, 0.8))
    gamma = float(rng.uniform(1.5, 3.0))
    nu = float(rng.uniform(0.0, 2.0 * math.pi))
    arias = log_uniform(0.05, 0.5)
    d5_95 = float(rng.uniform(5.0, 12.0))
    t_mid = float(rng.uniform(4.0, 7.0))
    half = gamma * Tp / 2.0
    low, high = max(t_mid - 1.5, half), min(t_mid + 1.5, duration - half)
    if low > high:
        raise InputError(f"a pulse of {2 * half:.3g} s does not fit a record of {duration:g} s")
    t0 = float(rng.uniform(low, high))
    f_mid = float(rng.uniform(2.0, 8.0))
    f_slope = float(rng.uniform(-0.15, 0.05))
    zeta_f = float(rng.uniform(0.1, 0.5))
    noise_seed = int(rng.integers(0, 2**63 - 1))
    return SyntheticParameters(
        Tp, Vp, gamma, nu, t0, arias, d5_95, t_mid, f_mid, f_slope, zeta_f, noise_seed
    )


def synthetic_suite(
    count: int,
    seed: int,
    *,
    dt: float = 0.01,
    duration: float = 20.0,
    prefix: str = "synth",
    g: float = STANDARD_GRAVITY,
) -> list[tuple[Record, SyntheticParameters]]:
    """``count`` records and their parameters, record i drawn from the i-th of
    ``SeedSequence(seed).spawn(count)`` and named ``{prefix}{i:02d}`` (from 1)."""
    if count < 1 or count != int(count):
        raise InputError(f"count = {count} must be a whole number >= 1")
    suite = []
    for i, child in enumerate(np.random.SeedSequence(seed).spawn(count), start=1):
        parameters = draw_parameters(np.random.default_rng(child), duration)
        name = f"{prefix}{i:02d}"
        record = synthetic_record(parameters, dt=dt, duration=duration, name=name, g=g)
        suite.append((record, parameters))
    return suite
