"""Numbers that depend on contact events, tested as statistics of a perturbed ensemble.

A rocking run is chaotic at its landings: a change of one unit in the last place (ulp) of an
input that starts the motion (a ground sample, the pulse's amplitude, the initial state, another
processor's rounding) can move every number after the first impact (peaks, collar
utilisation, impact counts, toe stress, an outcome near a boundary). Such a number is pinned
here through an ensemble of runs whose inputs differ by a few ulp, never through one sample or
the range of two or three:

* :func:`perturbed` is the 1-ulp perturbation of a ground motion: the lowest two bits of every
  nonzero sample (a record) or of the amplitude (a pulse) set from a seeded generator. It is
  idempotent (a motion perturbed twice with one seed is the motion perturbed once, so a record
  read back from a saved study is the one that ran) and seed 0 leaves the motion as it is.
* :func:`band` is the interval a further run of the same ensemble falls in with probability
  ``1 - FALSE_FAILURE``: the Student-t prediction interval of the sample, mean +- t s
  sqrt(1 + 1/n) (the scatter of a landing-dependent number over ulp perturbations is close
  to normal for these runs; docs/testing.md). A test that asserts a value inside the band of
  its ensemble fails falsely with probability ``FALSE_FAILURE`` = 1e-3 when the value is
  another draw of the same chaos (another machine's rounding is one).
* :func:`assert_in_band` (a value in an ensemble's band), :func:`assert_same_centre`,
  :func:`clearly_apart` and :func:`assert_mean_below_other` (two ensembles' means) and
  :func:`assert_mean_above` (a mean against a bound) are the assertions the ``chaotic`` tests
  make of numbers, each with the false-failure rate ``FALSE_FAILURE``.

The rounding stress mode (``make test-rounding``, tests/conftest.py) runs every test marked
``chaotic`` with every ground motion built in the run perturbed by :func:`perturbed` under the
seed given as ``--rounding-seed``: what another machine would see, on this one.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import zlib
from collections.abc import Sequence

import numpy as np
from scipy import stats

from colonna.core.ground import HarmonicPulse, Record

FALSE_FAILURE = 1e-3  # the probability that a draw of the same chaos falls outside its band
ENSEMBLE_SIZE = 16  # runs per ensemble: t(1 - 5e-4, 15) = 4.07, the band's half width 4.2 s
LOW_BITS = 2  # the bits set by the perturbation: up to 3 ulp, 3 in 4 values changed

# The rounding stress mode's seed (tests/conftest.py sets it from --rounding-seed for the whole
# run; 0: no perturbation). Every ground motion built in the run is perturbed with it, and an
# ensemble's member ``seed`` with the pair (ROUNDING_SEED, seed).
ROUNDING_SEED = 0
_inside_perturbed = False  # perturbed() is building a motion: the rounding hook leaves it


def _low_bits_set(values, seeds: tuple[int, int]) -> np.ndarray:
    """``values`` with their lowest ``LOW_BITS`` bits drawn from a generator seeded by
    ``seeds`` and the values themselves with those bits cleared (so that setting them again
    draws the same bits: idempotent); zeros stay zero (a subnormal ground would slow every
    kernel). The identity for seeds (0, 0)."""
    values = np.array(values, dtype=np.float64, copy=True)
    if seeds == (0, 0):
        return values
    bits = values.view(np.int64)
    mask = np.int64((1 << LOW_BITS) - 1)
    cleared = bits & ~mask
    salt = zlib.crc32(cleared.tobytes())
    rng = np.random.default_rng([seeds[0], seeds[1], salt])
    low = rng.integers(0, 1 << LOW_BITS, size=values.shape, dtype=np.int64)
    nonzero = values != 0.0
    bits[nonzero] = cleared[nonzero] | low[nonzero]
    return values


def _moved_fields(motion, seeds: tuple[int, int]) -> dict:
    """The fields of ``motion`` that the perturbation moves, moved (empty: nothing to move)."""
    if isinstance(motion, Record):
        return {"acceleration_values": _low_bits_set(motion.acceleration_values, seeds)}
    if isinstance(motion, HarmonicPulse):
        return {"amplitude": float(_low_bits_set(np.array([motion.amplitude]), seeds)[0])}
    return {}


def perturbed(motion, seed: int):
    """``motion`` with its samples (a :class:`Record`) or its amplitude (a
    :class:`HarmonicPulse`) moved by at most 3 ulp, as seeded by ``seed``, the rounding
    mode's seed and the motion's own values: idempotent; the identity for seed 0 outside the
    rounding mode, and for any other kind of motion."""
    global _inside_perturbed
    fields = _moved_fields(motion, (ROUNDING_SEED, int(seed)))
    if not fields or (ROUNDING_SEED, seed) == (0, 0):
        return motion
    _inside_perturbed = True
    try:
        return dataclasses.replace(motion, **fields)
    finally:
        _inside_perturbed = False


def perturb_on_construction(motion) -> None:
    """The rounding mode's hook, called as each ground motion is built: the motion moved in
    place as :func:`perturbed` with seed 0 would move it (a frozen dataclass: its fields set
    through ``object.__setattr__``)."""
    if ROUNDING_SEED == 0 or _inside_perturbed:
        return
    for name, value in _moved_fields(motion, (ROUNDING_SEED, 0)).items():
        object.__setattr__(motion, name, value)


def ensemble_seeds(size: int = ENSEMBLE_SIZE) -> range:
    """The seeds of an ensemble's members, 1 .. ``size`` (seed 0 is the unperturbed run: the
    value under test, not a member)."""
    return range(1, size + 1)


def log_uniform(seed: int, low: float, high: float) -> float:
    """A number drawn log-uniformly in [low, high] by member ``seed`` (and the rounding
    mode's seed): a solver tolerance or another setting the chaos should not depend on."""
    rng = np.random.default_rng([ROUNDING_SEED, int(seed), 7919])
    return float(math.exp(rng.uniform(math.log(low), math.log(high))))


@contextlib.contextmanager
def multibody_member(seed: int):
    """Inside, the multibody model's contact solver runs at a tolerance drawn log-uniformly
    within a decade of its own (1e-10) by member ``seed``: the multibody's chaos is its
    contact decisions, which a last-bit change of the ground alone flips only now and then
    (measured: the collars' utilisation of a rocked column scatters by 1e-11 over ground
    perturbations and jumps by 1e-3 in about one draw of eight); over solver tolerances it
    scatters by 0.1-0.3 %, the size of those jumps, so that the band holds them."""
    import colonna.rigid.multibody as multibody

    model_tolerance = multibody.SOLVER_TOLERANCE
    multibody.SOLVER_TOLERANCE = log_uniform(seed, 0.1 * model_tolerance, 10 * model_tolerance)
    try:
        yield
    finally:
        multibody.SOLVER_TOLERANCE = model_tolerance


def band(
    samples: Sequence[float], false_failure: float = FALSE_FAILURE, floor: float = 1e-9
) -> tuple[float, float]:
    """The two-sided prediction interval of a further draw: mean -+ t(1 - q/2, n - 1) s
    sqrt(1 + 1/n), q = ``false_failure``; s at least ``floor`` of the mean's size (a number
    that does not scatter is asserted to that relative accuracy, not bit for bit)."""
    samples = np.asarray(samples, dtype=float)
    n = samples.size
    if n < 3:
        raise ValueError(f"an ensemble of {n} runs has no scatter to speak of: use at least 3")
    mean = float(samples.mean())
    spread = max(float(samples.std(ddof=1)), floor * abs(mean), math.ulp(abs(mean)))
    half = float(stats.t.ppf(1.0 - 0.5 * false_failure, n - 1)) * spread * math.sqrt(1 + 1 / n)
    return mean - half, mean + half


def assert_in_band(
    value: float,
    samples: Sequence[float],
    name: str,
    false_failure: float = FALSE_FAILURE,
    floor: float = 1e-9,
) -> None:
    """``value`` inside :func:`band` of ``samples``; the message gives the band, the
    ensemble's mean and scatter, so that a failure says by how much."""
    low, high = band(samples, false_failure, floor)
    samples = np.asarray(samples, dtype=float)
    assert low <= value <= high, (
        f"{name} = {value:.7g} is outside its ensemble's band [{low:.7g}, {high:.7g}] "
        f"(n = {samples.size}, mean {samples.mean():.7g}, s {samples.std(ddof=1):.3g}, "
        f"false-failure rate {false_failure:g})"
    )


def _difference(samples, reference) -> tuple[float, float, float, int]:
    """(mean, reference's mean, standard error of their difference, degrees of freedom) of
    two ensembles' finite values: Welch's error, with the smaller ensemble's n - 1 degrees of
    freedom (Welch's are at least these, so the t quantile is conservative)."""
    a = np.asarray([v for v in samples if v is not None], dtype=float)
    b = np.asarray([v for v in reference if v is not None], dtype=float)
    error = math.sqrt(a.var(ddof=1) / a.size + b.var(ddof=1) / b.size)
    return float(a.mean()), float(b.mean()), error, min(a.size, b.size) - 1


def assert_same_centre(
    samples: Sequence[float],
    reference: Sequence[float],
    rel: float,
    name: str,
    false_failure: float = FALSE_FAILURE,
) -> None:
    """The means of two ensembles within ``rel`` of the reference's, up to their sampling
    error: |mean - mean_ref| <= rel |mean_ref| + t(1 - q/2, dof) sqrt(s^2/n + s_ref^2/m)
    (Welch's statistic, with the smaller ensemble's dof: :func:`_difference`), so that two
    draws of chaos with the same centre fail with probability below q = ``false_failure``."""
    mean, reference_mean, error, dof = _difference(samples, reference)
    t = float(stats.t.ppf(1.0 - 0.5 * false_failure, dof))
    allowed = rel * abs(reference_mean) + t * error
    assert abs(mean - reference_mean) <= allowed, (
        f"{name}: mean {mean:.7g} against {reference_mean:.7g} (standard error of the "
        f"difference {error:.3g}): apart by {abs(mean / reference_mean - 1):.3%}, allowed "
        f"{allowed / abs(reference_mean):.3%}"
    )


def clearly_apart(
    samples: Sequence[float], reference: Sequence[float], rel: float, q: float = FALSE_FAILURE
) -> bool:
    """Whether the means of two ensembles differ by more than ``rel`` of the reference's
    beyond their sampling error (the converse of :func:`assert_same_centre`)."""
    mean, reference_mean, error, dof = _difference(samples, reference)
    margin = float(stats.t.ppf(1.0 - 0.5 * q, dof)) * error
    return abs(mean - reference_mean) - margin > rel * abs(reference_mean)


def _mean_error(samples) -> tuple[float, float, int]:
    """(mean, standard error of the mean, n) of an ensemble's finite values."""
    a = np.asarray([v for v in samples if v is not None], dtype=float)
    return float(a.mean()), float(a.std(ddof=1) / math.sqrt(a.size)), a.size


def assert_mean_above(
    samples: Sequence[float], bound: float, name: str, q: float = FALSE_FAILURE
) -> None:
    """The ensemble's mean above ``bound`` by more than t(1 - q, n - 1) of its standard
    errors (one-sided): an ensemble whose true centre is at ``bound`` passes with
    probability below q."""
    mean, error, n = _mean_error(samples)
    margin = float(stats.t.ppf(1.0 - q, n - 1)) * error
    assert mean - margin > bound, (
        f"{name}: mean {mean:.6g} (n = {n}, standard error {error:.3g}) is not above "
        f"{bound:.6g} by t = {margin / error if error else math.inf:.2f} standard errors"
    )


def assert_mean_below_other(
    samples: Sequence[float], other: Sequence[float], name: str, q: float = FALSE_FAILURE
) -> None:
    """The ensemble's mean below the other ensemble's by more than t(1 - q) standard errors
    of their difference (one-sided, the smaller ensemble's degrees of freedom)."""
    mean, other_mean, error, dof = _difference(samples, other)
    margin = float(stats.t.ppf(1.0 - q, dof)) * error
    assert mean + margin < other_mean, (
        f"{name}: mean {mean:.6g} is not below {other_mean:.6g} by {margin:.3g}, "
        f"t(1 - {q:g}) standard errors of their difference"
    )
