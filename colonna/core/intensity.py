"""Intensity measures (IMs) of a ground-acceleration record, for fragility curves.

The record is taken as it is stored, piecewise linear between its samples (t_i, a_i), and every
integral below is exact for that line (no further discretisation error):

* velocity and displacement: on a step of length h, ``v_{i+1} = v_i + h (a_i + a_{i+1}) / 2`` and
  ``u_{i+1} = u_i + h v_i + h^2 (2 a_i + a_{i+1}) / 6``, from rest. Baseline correction
  (``baseline=True``, the default): the line ``c0 + c1 t`` is taken off the acceleration so
  that the ground ends at rest where it started, ``v(T) = u(T) = 0`` (two linear equations in
  c0, c1); it removes an offset or a linear drift of the acceleration exactly, and leaves a
  record that already ends at rest in place. A record with a permanent offset (fling step)
  loses it: pass ``baseline=False`` for the raw integrals.
* PGA = max |a|, PGV = max |v|, PGD = max |u|.
* Arias intensity ``I_A = pi / (2 g) int a^2 dt`` (m/s; Arias 1970), with
  ``int_step a^2 = h (a_i^2 + a_i a_{i+1} + a_{i+1}^2) / 3``.
* Cumulative absolute velocity ``CAV = int |a| dt`` (m/s; EPRI 1988), the line's |a| split at
  its zero where the sign changes.
* Significant duration D5-95 (s; Trifunac & Brady 1975): the time between 5 % and 95 % of
  I_A on the Husid curve (its exact values at the samples, linear between them).
* Spectral acceleration Sa(T, zeta) of the linear oscillator ``x'' + 2 zeta w x' + w^2 x = -a``
  (w = 2 pi / T): Nigam & Jennings (1969)'s exact recurrence for piecewise-linear input,
  ``z_{i+1} = Phi z_i + p a_i + q a_{i+1}`` with z = (x, x'), Phi, p, q from the matrix
  exponential of the augmented system over one step, from rest (z_0 = 0); run as the
  second-order IIR filter it is (``scipy.signal.lfilter``, started from z_0 and z_1) for each
  period, then free vibration (the ground at rest after its last sample, as
  :class:`~colonna.core.ground.Record` has it) for one longest period, so that a peak after the
  record's end is kept. ``kind="pseudo"`` (default):
  ``PSa = w^2 max |x|``; ``"absolute"``: ``max |x'' + a|``.
* Rocking-normalised: PGA / a_up (1 is the uplift of a free block) and PGV p / a_up
  (Dimitrakopoulos & DeJong 2012's velocity scale), a_up the block's uplift acceleration
  g tan(alpha) (1 + lambda), lambda = P / (m g) its top load (0 without one), for any object with
  ``alpha`` (rad), ``p`` (rad/s) and ``g`` (m/s^2) (a :class:`colonna.rigid.Block`).

numpy and scipy here, not a library such as eqsig (MIT): these are a few exact formulas, tested
against closed forms (tests/test_intensity.py), with no dependency to follow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .constants import STANDARD_GRAVITY
from .errors import InputError

__all__ = [
    "IntensityMeasures",
    "arias_intensity",
    "cumulative_absolute_velocity",
    "ground_velocity_displacement",
    "husid",
    "intensity_measures",
    "peak_ground",
    "significant_duration",
    "spectral_acceleration",
]

SA_DAMPING = 0.05  # ratio of critical damping of the spectral acceleration


def _table(record) -> tuple[np.ndarray, np.ndarray]:
    """(t (s), a (m/s^2)) of a record (or any ground motion with an acceleration table)."""
    table = record.acceleration_table()
    if table is None:
        raise InputError("intensity measures need a ground motion (got no motion)")
    t, a = (np.asarray(x, dtype=float) for x in table)
    return t, a


def ground_velocity_displacement(record, *, baseline: bool = True):
    """(t, a, v, u): the acceleration (m/s^2; baseline-corrected where ``baseline``), the ground
    velocity (m/s) and displacement (m) at the record's samples, exact for the
    piecewise-linear acceleration, from rest."""
    t, a = _table(record)

    def integrate(acc):
        h = np.diff(t)
        v = np.concatenate([[0.0], np.cumsum(h * (acc[:-1] + acc[1:]) / 2.0)])
        du = h * v[:-1] + h**2 * (2.0 * acc[:-1] + acc[1:]) / 6.0
        return v, np.concatenate([[0.0], np.cumsum(du)])

    v, u = integrate(a)
    if baseline:
        span = t - t[0]
        T = span[-1]
        # the line c0 + c1 s (s = t - t0) ends with velocity c0 T + c1 T^2/2 and displacement
        # c0 T^2/2 + c1 T^3/6: take off the one that matches v(T), u(T)
        c0, c1 = np.linalg.solve([[T, T**2 / 2.0], [T**2 / 2.0, T**3 / 6.0]], [v[-1], u[-1]])
        a = a - c0 - c1 * span
        v, u = integrate(a)
    return t, a, v, u


def _step_square_integrals(t: np.ndarray, a: np.ndarray) -> np.ndarray:
    """int a^2 dt over each step of the piecewise-linear a."""
    return np.diff(t) * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3.0


def husid(record) -> tuple[np.ndarray, np.ndarray]:
    """(t (s), H(t)): the Husid curve, int_0^t a^2 / int_0^T a^2, at the record's samples."""
    t, a = _table(record)
    cumulative = np.concatenate([[0.0], np.cumsum(_step_square_integrals(t, a))])
    if cumulative[-1] <= 0.0:
        raise InputError("the record's acceleration is zero everywhere: no Husid curve")
    return t, cumulative / cumulative[-1]


def arias_intensity(record, *, g: float = STANDARD_GRAVITY) -> float:
    """Arias intensity ``pi / (2 g) int a^2 dt`` (m/s)."""
    t, a = _table(record)
    return float(math.pi / (2.0 * g) * _step_square_integrals(t, a).sum())


def cumulative_absolute_velocity(record) -> float:
    """CAV = int |a| dt (m/s), exact for the piecewise-linear record (split at sign changes)."""
    t, a = _table(record)
    h, left, right = np.diff(t), np.abs(a[:-1]), np.abs(a[1:])
    same = a[:-1] * a[1:] >= 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        crossing = (left**2 + right**2) / (2.0 * (left + right))
    return float(np.sum(h * np.where(same, (left + right) / 2.0, crossing)))


def significant_duration(record, start: float = 0.05, end: float = 0.95) -> float:
    """D5-95 (s): the time from ``start`` to ``end`` of the Husid curve (linear between its
    exact values at the samples)."""
    if not 0.0 <= start < end <= 1.0:
        raise InputError(f"significant duration: need 0 <= start < end <= 1 (got {start}, {end})")
    t, h = husid(record)
    rising = np.maximum.accumulate(h)
    first = np.searchsorted(rising, [start, end])
    times = []
    for level, j in zip((start, end), first, strict=True):
        j = int(min(max(j, 1), t.size - 1))
        h0, h1 = rising[j - 1], rising[j]
        w = 0.0 if h1 == h0 else (level - h0) / (h1 - h0)
        times.append(t[j - 1] + w * (t[j] - t[j - 1]))
    return float(times[1] - times[0])


def _oscillator_filters(omega: np.ndarray, damping: float, dt: float):
    """For each circular frequency, the lfilter (b_x, b_v, a) coefficients of the exact
    recurrence of ``x'' + 2 zeta w x' + w^2 x = -a`` over a step dt with a linear between
    samples (Nigam & Jennings 1969): the matrix exponential of the system augmented with the
    input and its slope."""
    from scipy.linalg import expm

    m = np.zeros((omega.size, 4, 4))
    m[:, 0, 1] = 1.0
    m[:, 1, 0] = -(omega**2)
    m[:, 1, 1] = -2.0 * damping * omega
    m[:, 1, 2] = -1.0  # the input a(t) = a_i + s (t - t_i) drives x'' with -1
    m[:, 2, 3] = 1.0  # d(input)/dt = s
    e = expm(m * dt)
    phi = e[:, :2, :2]
    gamma0, gamma1 = e[:, :2, 2], e[:, :2, 3] / dt  # per a_i, per (a_{i+1} - a_i)
    p, q = gamma0 - gamma1, gamma1
    a11, a12, a21, a22 = phi[:, 0, 0], phi[:, 0, 1], phi[:, 1, 0], phi[:, 1, 1]
    den = np.stack([np.ones_like(a11), -(a11 + a22), a11 * a22 - a12 * a21], axis=1)
    bx = np.stack(
        [q[:, 0], p[:, 0] - a22 * q[:, 0] + a12 * q[:, 1], -a22 * p[:, 0] + a12 * p[:, 1]],
        axis=1,
    )
    bv = np.stack(
        [q[:, 1], a21 * q[:, 0] + p[:, 1] - a11 * q[:, 1], a21 * p[:, 0] - a11 * p[:, 1]],
        axis=1,
    )
    return bx, bv, den, p, q, phi


def spectral_acceleration(
    record, periods, *, damping: float = SA_DAMPING, kind: str = "pseudo"
) -> np.ndarray:
    """Sa(T) (m/s^2) at ``periods`` (s) of the oscillator with ``damping`` (ratio of critical):
    ``kind="pseudo"``, w^2 max|x|; ``"absolute"``, max|x'' + a_g|. The record must be sampled
    uniformly (the readers ensure it)."""
    from scipy.signal import lfilter, lfiltic

    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    if periods.size == 0 or not np.all(np.isfinite(periods)) or np.any(periods <= 0.0):
        raise InputError("spectral acceleration: every period must be > 0 s and finite")
    if not 0.0 <= damping < 1.0:
        raise InputError(f"damping = {damping:g} must be in [0, 1)")
    if kind not in ("pseudo", "absolute"):
        raise InputError(f"kind = {kind!r} must be 'pseudo' or 'absolute'")
    t, a = _table(record)
    steps = np.diff(t)
    dt = float(steps.mean())
    if np.max(np.abs(steps - dt)) > 1e-6 * dt:
        raise InputError("spectral acceleration needs a uniformly sampled record")
    if a.size < 2:
        raise InputError("spectral acceleration needs a record of two samples or more")
    omega = 2.0 * math.pi / periods
    bx, bv, den, p, q, phi = _oscillator_filters(omega, damping, dt)

    def response(b, den, first):
        """The state component whose filter is b/den: 0 at t_0, ``first`` at t_1, then the
        recurrence's second-order difference equation from its two past values."""
        zi = lfiltic(b, den, [first, 0.0], [a[1], a[0]])
        rest, _ = lfilter(b, den, a[2:], zi=zi)
        return np.concatenate([[0.0, first], rest])

    def free(den, last, following):
        """The free vibration after the record (the ground at rest: zero input): ``following``
        one step after ``last``, then the homogeneous difference equation."""
        zi = lfiltic([1.0], den, [following, last])
        rest, _ = lfilter([1.0], den, np.zeros(tail), zi=zi)
        return np.concatenate([[following], rest])

    tail = int(math.ceil(periods.max() / dt))  # the free peak comes within half a period
    result = np.empty(periods.size)
    for j in range(periods.size):
        x = response(bx[j], den[j], p[j, 0] * a[0] + q[j, 0] * a[1])
        v = response(bv[j], den[j], p[j, 1] * a[0] + q[j, 1] * a[1])
        (f11, f12), (f21, f22) = phi[j]
        x_free = free(den[j], x[-1], f11 * x[-1] + f12 * v[-1])
        if kind == "pseudo":
            result[j] = omega[j] ** 2 * max(np.max(np.abs(x)), np.max(np.abs(x_free)))
        else:
            v_free = free(den[j], v[-1], f21 * x[-1] + f22 * v[-1])
            absolute = 2.0 * damping * omega[j] * np.concatenate([v, v_free]) + omega[j] ** 2 * (
                np.concatenate([x, x_free])
            )
            result[j] = np.max(np.abs(absolute))
    return result


@dataclass(frozen=True)
class IntensityMeasures:
    """The IMs of one record (SI: m/s^2, m/s, m, s; Arias and CAV in m/s). ``sa``: period (s) ->
    5 %-damped pseudo-spectral acceleration (m/s^2); the rocking-normalised ones are None
    without a block."""

    pga: float
    pgv: float
    pgd: float
    arias: float
    cav: float
    d5_95: float
    sa: dict[float, float] = field(default_factory=dict)
    pga_rocking: float | None = None  # PGA / (g tan alpha)
    pgv_rocking: float | None = None  # PGV p / (g tan alpha)

    def to_dict(self) -> dict[str, Any]:
        """Flat: ``sa`` as ``sa(T=0.5 s)`` keys."""
        data: dict[str, Any] = {
            "pga": self.pga,
            "pgv": self.pgv,
            "pgd": self.pgd,
            "arias": self.arias,
            "cav": self.cav,
            "d5_95": self.d5_95,
        }
        data.update({f"sa(T={period:g} s)": value for period, value in self.sa.items()})
        if self.pga_rocking is not None:
            data["pga_rocking"] = self.pga_rocking
            data["pgv_rocking"] = self.pgv_rocking
        return data


def _uplift_acceleration(block) -> float:
    """The ground acceleration that uplifts ``block`` (m/s^2): g tan(alpha) (1 + lambda) with a
    top load lambda = P / (m g) (:meth:`colonna.rigid.Block.uplift_acceleration`), g tan(alpha)
    for a bare (alpha, p, g)."""
    uplift = getattr(block, "uplift_acceleration", None)
    return float(uplift()) if callable(uplift) else block.g * math.tan(block.alpha)


def peak_ground(record, measure: str) -> float:
    """The record's PGA (m/s^2, ``measure`` "pga") or PGV (m/s, "pgv") as
    :func:`intensity_measures` gives them: of the motion as the solvers apply it (no baseline
    correction). The peak a record is scaled to (``[ground] scale_to_pga``, ``scale_to_pgv``,
    and a suite record's)."""
    if measure == "pga":
        return float(np.max(np.abs(_table(record)[1])))
    if measure == "pgv":
        return float(np.max(np.abs(ground_velocity_displacement(record, baseline=False)[2])))
    raise ValueError(f"peak_ground: measure {measure!r} is not 'pga' or 'pgv'")


def intensity_measures(
    record,
    *,
    periods=(),
    block=None,
    damping: float = SA_DAMPING,
    g: float | None = None,
    baseline: bool = False,
) -> IntensityMeasures:
    """Every IM of ``record``; Sa at ``periods`` (s); the rocking-normalised PGA and PGV for
    ``block`` (alpha, p, g). ``g``: for Arias (default the block's, else 9.81 m/s^2).

    PGV and PGD are those of the motion as the solvers apply it (``baseline=False``): a
    one-sine acceleration pulse A sin(w t) has PGV = 2 A / w and keeps its residual
    displacement. ``baseline=True`` takes them from the baseline-corrected record instead
    (:func:`ground_velocity_displacement`), for a raw record whose integration drifts; correct
    such a record before it is applied (as the shipped suite's script does), so that the IMs
    describe the motion the column feels."""
    g = g if g is not None else (block.g if block is not None else STANDARD_GRAVITY)
    _, a, v, u = ground_velocity_displacement(record, baseline=baseline)
    pga = peak_ground(record, "pga")
    pgv, pgd = float(np.max(np.abs(v))), float(np.max(np.abs(u)))
    periods = [float(x) for x in np.atleast_1d(np.asarray(periods, dtype=float))]
    sa: Any = spectral_acceleration(record, periods, damping=damping) if periods else []
    rocking: dict[str, float] = {}
    if block is not None:
        uplift = _uplift_acceleration(block)
        rocking = {"pga_rocking": pga / uplift, "pgv_rocking": pgv * block.p / uplift}
    return IntensityMeasures(
        pga=pga,
        pgv=pgv,
        pgd=pgd,
        arias=arias_intensity(record, g=g),
        cav=cumulative_absolute_velocity(record),
        d5_95=significant_duration(record),
        sa=dict(zip(periods, (float(x) for x in sa), strict=True)),
        **rocking,
    )
