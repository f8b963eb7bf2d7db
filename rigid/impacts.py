"""Energy lost at impact, measured on a sampled rotation history of any model (rigid or FEM).

Two measures of the angular-velocity ratio nu = |theta' after| / |theta' before| at each impact
(each change of sign of theta):

* from the rotation peaks on either side of the impact, through the free-rocking energy. Between
  impacts a free rigid block conserves J0 theta'^2 / 2 + m g R (cos(alpha - |theta|) - cos alpha),
  so the speed at theta = 0 after rising to a peak theta_p is p sqrt(2 (cos(alpha - theta_p) -
  cos alpha)), and

      nu = sqrt((cos(alpha - theta_after) - cos alpha) / (cos(alpha - theta_before) - cos alpha))

  (theta_after / theta_before to first order). Exact for free rocking, where no ground motion
  acts between the peaks; the clean measure.
* from a local fit: the slopes of straight lines through ``window`` samples either side of the
  crossing. This works under a pulse too, but a deformable body's vibration enters the slopes.

>>> import numpy as np
>>> from colonna.rigid import Block, Motion, Release, SdofSettings, rock
>>> blk = Block.from_dimensionless(p=2.0, alpha=0.2)
>>> r = rock(blk, Motion(duration=4.0), model="nonlinear", release=Release(tilt=0.1),
...          settings=SdofSettings(dt_out=1e-4))
>>> m = impact_ratios_from_peaks(r.time, r.theta, blk.alpha)
>>> bool(np.allclose(m.ratios, blk.restitution_housner, rtol=1e-3))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError


@dataclass(frozen=True)
class ImpactMeasure:
    """Per impact: time (s, the sample after the change of sign), the peaks |theta| before and
    after it (rad), and the velocity ratio."""

    times: np.ndarray
    peak_before: np.ndarray
    peak_after: np.ndarray
    ratios: np.ndarray

    @property
    def mean(self) -> float | None:
        return float(np.mean(self.ratios)) if self.ratios.size else None


def half_cycles(theta, threshold_fraction: float = 0.02):
    """Indices where theta changes sign, ignoring wiggles: a crossing counts once |theta| has
    exceeded ``threshold_fraction`` of its largest value since the last one."""
    theta = np.asarray(theta, dtype=float)
    level = threshold_fraction * np.max(np.abs(theta), initial=0.0)
    crossings = []
    sign = 0
    for k, value in enumerate(theta):
        if abs(value) <= level:
            continue
        s = 1 if value > 0 else -1
        if sign and s != sign:
            # the crossing: last sample before the sign changed
            j = k - 1
            while j > 0 and np.sign(theta[j]) == s:
                j -= 1
            crossings.append(j + 1)
        sign = s
    return np.array(crossings, dtype=int)


def impact_ratios_from_peaks(
    t, theta, alpha: float, *, threshold_fraction: float = 0.02, min_peak_fraction: float = 0.05
) -> ImpactMeasure:
    """Velocity ratio at every impact from the peaks either side (free rocking; see module).

    alpha: slenderness of the rocking body (rad). Impacts whose peak before is below
    ``min_peak_fraction`` of the largest are left out (noise and settling)."""
    t = np.asarray(t, dtype=float)
    theta = np.asarray(theta, dtype=float)
    if t.shape != theta.shape or t.ndim != 1:
        raise InputError("t and theta must be 1D arrays of the same length")
    if not 0.0 < alpha < 0.5 * np.pi:
        raise InputError(f"alpha = {alpha:g} is outside (0, pi/2)")
    crossings = half_cycles(theta, threshold_fraction)
    bounds = np.concatenate(([0], crossings, [theta.size]))
    peak_at = [a + int(np.argmax(np.abs(theta[a:b]))) for a, b in zip(bounds[:-1], bounds[1:])]
    peaks = np.abs(theta[peak_at])
    # a peak is one if the history goes on past it (the release at t = 0 is one too)
    genuine = [k == 0 or at < b - 1 for k, (at, b) in enumerate(zip(peak_at, bounds[1:]))]
    largest = np.max(peaks, initial=0.0)
    times, before, after = [], [], []
    for k, index in enumerate(crossings):
        if genuine[k] and genuine[k + 1] and peaks[k] >= min_peak_fraction * largest:
            times.append(t[index])
            before.append(peaks[k])
            after.append(peaks[k + 1])
    peak_before, peak_after = np.array(before), np.array(after)
    energy = lambda peak: np.cos(alpha - np.minimum(peak, alpha)) - np.cos(alpha)  # noqa: E731
    ratios = np.sqrt(energy(peak_after) / energy(peak_before)) if peak_before.size else np.zeros(0)
    return ImpactMeasure(np.array(times), peak_before, peak_after, ratios)


def impact_ratios_from_fit(t, theta, *, window: int = 4, threshold_fraction: float = 0.02):
    """|theta' after / theta' before| at each change of sign of theta, the slopes from straight
    lines through ``window`` samples either side. Returns (times, ratios)."""
    t = np.asarray(t, dtype=float)
    theta = np.asarray(theta, dtype=float)
    times, ratios = [], []
    scale = np.max(np.abs(theta), initial=0.0)
    for k in half_cycles(theta, threshold_fraction) - 1:
        lo, hi = k - window + 1, k + 1 + window
        if lo < 0 or hi > t.size:
            continue
        before = np.polyfit(t[lo : k + 1], theta[lo : k + 1], 1)[0]
        after = np.polyfit(t[k + 1 : hi], theta[k + 1 : hi], 1)[0]
        if abs(before) * (t[1] - t[0]) * window < 1e-3 * scale:
            continue
        times.append(t[k + 1])
        ratios.append(abs(after / before))
    return np.array(times), np.array(ratios)
