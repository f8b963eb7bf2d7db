"""The statistics the tests of chaotic numbers rest on (tests/chaos.py): the perturbation is a
few ulp, seeded and idempotent; the band's false-failure rate is the one it states; a value
shifted by a few of the ensemble's scatters is caught."""

import math

import chaos
import numpy as np
import pytest

from colonna.core.ground import HarmonicPulse, Record


def _record() -> Record:
    t = np.linspace(0.0, 2.0, 401)
    return Record(t, 3.0 * np.sin(7.0 * t) * (t < 1.5), "sine")


def test_the_perturbation_moves_each_sample_by_at_most_three_ulp_and_leaves_zeros():
    record = _record()
    moved = chaos.perturbed(record, 5).acceleration_values
    before = record.acceleration_values
    ulps = np.abs(moved.view(np.int64) - before.view(np.int64))
    assert ulps.max() <= 3 and np.count_nonzero(ulps) > 0.6 * np.count_nonzero(before)
    assert np.all(moved[before == 0.0] == 0.0)
    pulse = HarmonicPulse("sine", 2.5, 9.0, 0.3, 0.7)
    amplitudes = {chaos.perturbed(pulse, seed).amplitude for seed in range(1, 9)}
    assert len(amplitudes) > 1
    assert all(abs(a - 2.5) <= 3 * math.ulp(2.5) for a in amplitudes)


def test_the_perturbation_is_seeded_idempotent_and_the_identity_for_seed_zero():
    record = _record()
    once = chaos.perturbed(record, 3)
    assert np.array_equal(chaos.perturbed(once, 3).acceleration_values, once.acceleration_values)
    again = chaos.perturbed(_record(), 3)
    assert np.array_equal(again.acceleration_values, once.acceleration_values)
    other = chaos.perturbed(record, 4)
    assert not np.array_equal(other.acceleration_values, once.acceleration_values)
    assert chaos.perturbed(record, 0) is record


def test_the_band_fails_a_draw_of_the_same_distribution_at_its_stated_rate():
    """Ensembles of 16 normal draws and one more draw each, 200,000 times: the share of
    draws outside their ensemble's band is 1e-3 (binomial sd 7e-5)."""
    rng = np.random.default_rng(46)
    trials, n = 200_000, chaos.ENSEMBLE_SIZE
    samples = rng.normal(1.0, 0.01, size=(trials, n))
    draws = rng.normal(1.0, 0.01, size=trials)
    from scipy import stats

    t = stats.t.ppf(1.0 - 0.5 * chaos.FALSE_FAILURE, n - 1)
    half = t * samples.std(axis=1, ddof=1) * math.sqrt(1.0 + 1.0 / n)
    outside = np.abs(draws - samples.mean(axis=1)) > half
    assert outside.mean() == pytest.approx(chaos.FALSE_FAILURE, abs=3.5e-4)
    low, high = chaos.band(samples[0])
    assert (low, high) == pytest.approx((samples[0].mean() - half[0], samples[0].mean() + half[0]))


def test_a_value_shifted_by_five_scatters_is_outside_and_one_inside():
    rng = np.random.default_rng(7)
    samples = rng.normal(0.62, 0.001, size=chaos.ENSEMBLE_SIZE)
    chaos.assert_in_band(0.62 + 0.001, samples, "one scatter off")
    with pytest.raises(AssertionError, match="outside its ensemble's band"):
        chaos.assert_in_band(0.62 + 0.006, samples, "six scatters off")


def test_two_ensembles_are_the_same_centre_within_their_tolerance_and_apart_beyond_it():
    rng = np.random.default_rng(11)
    a = rng.normal(1.000, 0.002, size=16)
    b = rng.normal(1.009, 0.002, size=16)
    chaos.assert_same_centre(b, a, 1e-2, "0.9 % apart, 1 % allowed")
    with pytest.raises(AssertionError, match="apart by"):
        chaos.assert_same_centre(b * 1.02, a, 1e-2, "2.9 % apart, 1 % allowed")
    assert chaos.clearly_apart(b * 1.02, a, 1e-2)
    assert not chaos.clearly_apart(b, a, 1e-2)


def test_the_rounding_mode_perturbs_the_motions_of_a_chaotic_test_only(request):
    """Outside --rounding-seeds (this test is not marked chaotic), a motion is what it was
    built with."""
    assert request.node.get_closest_marker("chaotic") is None
    assert Record(np.array([0.0, 1.0]), np.array([0.1, 0.3])).acceleration_values[1] == 0.3


@pytest.mark.chaotic
def test_under_a_rounding_seed_every_motion_a_chaotic_test_builds_is_perturbed(rounding_seed):
    """make test-rounding runs this once per seed: the record and the pulse built here are
    moved by at most 3 ulp (and not at all without a seed), as tests/chaos.py seeds them."""
    values = 3.0 * np.sin(np.linspace(0.1, 5.0, 50))
    record = Record(np.linspace(0.0, 1.0, 50), values)
    pulse = HarmonicPulse("sine", 2.5, 9.0, 0.3, 0.7)
    ulps = np.abs(record.acceleration_values.view(np.int64) - values.view(np.int64))
    if rounding_seed == 0:
        assert ulps.max() == 0 and pulse.amplitude == 2.5
    else:
        assert 0 < ulps.max() <= 3
        assert abs(pulse.amplitude - 2.5) <= 3 * math.ulp(2.5)
        assert np.array_equal(
            chaos.perturbed(record, 0).acceleration_values, record.acceleration_values
        )
