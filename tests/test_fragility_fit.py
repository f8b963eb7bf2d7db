"""Lognormal fragility fits (colonna.core.fragility): Baker (2015)'s worked example, recovery of a
known curve, the IDA moments and their censored likelihood, the bootstrap over records against
the sampling distribution of a mean, and the likelihood-ratio test's level under the null."""

import math

import numpy as np
import pytest
from scipy.stats import norm

from colonna.core.errors import InputError
from colonna.core.fragility import (
    Stripes,
    bootstrap_capacities,
    bootstrap_stripes,
    fit_capacities,
    fit_stripes,
    likelihood_ratio_test,
    stripes_of,
)

BAKER_IM = [0.2, 0.3, 0.4, 0.6, 0.7, 0.8, 0.9, 1.0]  # g, Baker (2015), section "MLE fitting"
BAKER_K = [0, 0, 0, 4, 6, 13, 12, 16]  # collapses of 40 records at each


def test_baker_2015_worked_example_to_three_digits():
    fit = fit_stripes(Stripes(BAKER_IM, [40] * 8, BAKER_K))
    assert round(fit.median, 3) == 1.076
    assert round(fit.beta, 3) == 0.429
    assert not fit.separated and fit.probability(fit.median) == pytest.approx(0.5)


def test_the_fit_is_the_likelihood_maximum():
    """No neighbour of (theta, beta) has a higher binomial likelihood (Baker's Eq. 11)."""
    s = Stripes(BAKER_IM, [40] * 8, BAKER_K)
    fit = fit_stripes(s)

    def loglik(theta, beta):
        p = norm.cdf(np.log(s.im / theta) / beta)
        return np.sum(s.k * np.log(p) + (s.n - s.k) * np.log1p(-p))

    best = loglik(fit.median, fit.beta)
    for dt, db in [(1e-3, 0), (-1e-3, 0), (0, 1e-3), (0, -1e-3), (1e-3, 1e-3), (-1e-3, -1e-3)]:
        assert loglik(fit.median * (1 + dt), fit.beta * (1 + db)) < best


def test_a_known_curve_is_recovered_from_many_records():
    rng = np.random.default_rng(37)
    im = np.linspace(0.1, 1.5, 12)
    n = np.full(im.size, 20_000)
    k = rng.binomial(n, norm.cdf(np.log(im / 0.6) / 0.35))
    fit = fit_stripes(Stripes(im, n, k))
    assert fit.median == pytest.approx(0.6, rel=0.01)
    assert fit.beta == pytest.approx(0.35, rel=0.02)


def test_the_median_scales_with_the_intensity_and_beta_does_not():
    """Changing the IM's unit (g -> m/s^2) multiplies theta and leaves beta."""
    a = fit_stripes(Stripes(BAKER_IM, [40] * 8, BAKER_K))
    b = fit_stripes(Stripes(np.array(BAKER_IM) * 9.81, [40] * 8, BAKER_K))
    assert b.median == pytest.approx(9.81 * a.median, rel=1e-9)
    assert b.beta == pytest.approx(a.beta, rel=1e-9)


def test_perfectly_separated_stripes_are_a_step():
    """Uplift of a rigid block against PGA: none below g tan(alpha), all above."""
    fit = fit_stripes(Stripes([0.1, 0.2, 0.3, 0.4], [10] * 4, [0, 0, 10, 10]))
    assert fit.separated and fit.beta == 0.0
    assert fit.median == pytest.approx(math.sqrt(0.2 * 0.3))
    assert list(fit.probability([0.2, 0.3])) == [0.0, 1.0]


def test_the_shifted_lognormal_is_recovered_with_its_origin():
    rng = np.random.default_rng(5)
    im = np.linspace(0.25, 2.0, 10)
    n = np.full(im.size, 20_000)
    k = rng.binomial(n, np.where(im > 0.2, norm.cdf(np.log((im - 0.2) / 0.5) / 0.4), 0.0))
    fit = fit_stripes(Stripes(im, n, k), origin=0.2)
    assert (fit.median, fit.beta) == (pytest.approx(0.5, rel=0.01), pytest.approx(0.4, rel=0.02))
    assert fit.im50 == pytest.approx(0.7, rel=0.01) and fit.probability(0.2) == 0.0
    with pytest.raises(InputError, match=r"at or below the origin 0.3, 1 records"):
        fit_stripes(Stripes([0.3, 0.5, 0.8], [5, 5, 5], [1, 2, 4]), origin=0.3)


def test_stripes_from_per_record_outcomes_skip_runs_not_made():
    out = np.array([[0, 1, 1], [0, 0, 1], [np.nan, 0, 1]])
    s = stripes_of([0.1, 0.2, 0.3], out)
    assert list(s.n) == [2, 3, 3] and list(s.k) == [0, 1, 3]


def test_ida_capacities_by_the_moments_of_their_logarithm():
    """Capacities exp(mu + beta z_i), z_i symmetric normal quantiles: theta = e^mu exactly, and
    beta is the sample standard deviation (n - 1) of ln c."""
    z = norm.ppf((np.arange(1, 12) - 0.5) / 11)
    c = np.exp(math.log(0.8) + 0.3 * z)
    fit = fit_capacities(c)
    assert fit.median == pytest.approx(0.8, rel=1e-12)
    assert fit.beta == pytest.approx(0.3 * np.std(z, ddof=1), rel=1e-12)
    assert fit.method == "capacity moments"


def test_censored_capacities_are_fitted_by_their_likelihood():
    """Records that never overturn up to the ladder's top (1.0) are censored there: their
    likelihood recovers the curve, while the moments of the others alone fall short."""
    rng = np.random.default_rng(11)
    c = np.exp(math.log(0.8) + 0.5 * rng.standard_normal(4000))
    censored = c > 1.0
    fit = fit_capacities(np.minimum(c, 1.0), censored=censored)
    assert fit.method == "censored capacity MLE"
    assert fit.median == pytest.approx(0.8, rel=0.03) and fit.beta == pytest.approx(0.5, rel=0.04)
    naive = fit_capacities(c[~censored])
    assert naive.median < 0.7 and naive.beta < 0.4


def test_equal_exceeded_capacities_beside_censored_ones_have_no_fit_and_a_resample_of_them_fails():
    """Records that exceeded all at one level, the others censored at the ladder's top: the
    likelihood grows without bound as beta -> 0, so there is no fit; the mean of the equal logs
    may differ from them by an ulp, which must not pass for a dispersion (found on a granite
    column of my own: a bootstrap resample of [4, 9, 4, 12, 9, 4, None, 4, 6, 4] on a collar
    layout's ladder drew seven 2.545 and three censored, its Newton steps overflowed and
    the study ended with 'fragility median = nan'). Its resamples count as failed."""
    level = 2.545454545454545
    assert math.log(level) != np.log(np.full(7, level)).mean()  # the ulp, in this case
    c = np.array([8.0, level, level, 8.0, level, level, 8.0, level, level, level])
    censored = c == 8.0
    with pytest.raises(InputError, match="no dispersion"):
        fit_capacities(c, censored=censored)
    whole = np.array([8.0, 5.27, level, 8.0, 5.27, level, 8.0, level, 3.9, level])
    band = bootstrap_capacities(whole, censored=whole == 8.0, draws=200, seed=0, level=0.9)
    assert band.failed > 0 and np.all(np.isfinite(band.medians) & np.isfinite(band.betas))


def test_the_bootstrap_interval_of_the_median_is_the_mean_logs_interval():
    """Capacities: ln theta is a mean of n logs, so its 90 % interval is about
    ln theta +- 1.645 beta / sqrt(n); the bootstrap reproduces its width, and the same seed the
    same draws."""
    rng = np.random.default_rng(2)
    c = np.exp(math.log(0.8) + 0.4 * rng.standard_normal(60))
    band = bootstrap_capacities(c, draws=2000, seed=4, level=0.9)
    low, high = band.median_interval
    expected = 2 * 1.645 * band.fit.beta / math.sqrt(c.size)
    assert math.log(high / low) == pytest.approx(expected, rel=0.12)
    assert low < band.fit.median < high
    again = bootstrap_capacities(c, draws=2000, seed=4, level=0.9)
    np.testing.assert_array_equal(band.medians, again.medians)
    assert np.all(band.low <= band.high)


def test_the_stripes_bootstrap_brackets_the_fit_and_narrows_with_records():
    rng = np.random.default_rng(8)
    im = np.array([0.2, 0.4, 0.6, 0.8, 1.0, 1.2])

    def outcomes(records):
        capacity = np.exp(math.log(0.7) + 0.4 * rng.standard_normal(records))
        return (im[None, :] >= capacity[:, None]).astype(float)

    few = bootstrap_stripes(im, outcomes(40), draws=200, seed=1, at=[0.7])
    many = bootstrap_stripes(im, outcomes(640), draws=200, seed=1, at=[0.7])
    for band in (few, many):
        low, high = band.median_interval
        assert low < band.fit.median < high
        assert band.low[0] <= band.fit.probability(0.7) <= band.high[0]
    width = [math.log(b.median_interval[1] / b.median_interval[0]) for b in (few, many)]
    assert width[0] / width[1] == pytest.approx(4.0, rel=0.35)  # sqrt(640 / 40)


def test_the_likelihood_ratio_test_tells_two_curves_from_one():
    im = np.array(BAKER_IM)
    same = likelihood_ratio_test(
        Stripes(im, [40] * 8, BAKER_K), Stripes(im, [40] * 8, [0, 0, 1, 3, 7, 12, 13, 15])
    )
    assert not same.rejects() and same.dof == 2
    shifted = Stripes(im, [40] * 8, [0, 4, 12, 27, 31, 35, 37, 39])  # median about 0.5
    assert likelihood_ratio_test(Stripes(im, [40] * 8, BAKER_K), shifted).p_value < 1e-6


def test_the_likelihood_ratio_test_holds_its_level_under_one_curve():
    """Data sets drawn from one curve: the statistic is chi-square with 2 degrees of freedom, so
    about 10 % of pairs are rejected at 0.10 (a binomial count of 200 pairs: 20 +- 3 sd)."""
    rng = np.random.default_rng(99)
    im = np.array([0.3, 0.5, 0.7, 0.9, 1.2, 1.6])
    p = norm.cdf(np.log(im / 0.8) / 0.4)
    rejected = sum(
        likelihood_ratio_test(
            Stripes(im, [30] * 6, rng.binomial(30, p)), Stripes(im, [30] * 6, rng.binomial(30, p))
        ).rejects(0.10)
        for _ in range(200)
    )
    assert 8 <= rejected <= 32


def test_capacity_sets_are_compared_by_their_lognormal_likelihood():
    rng = np.random.default_rng(3)
    a = np.exp(math.log(0.8) + 0.4 * rng.standard_normal(50))
    b = np.exp(math.log(0.4) + 0.4 * rng.standard_normal(50))
    assert likelihood_ratio_test(a, b).p_value < 1e-6
    assert not likelihood_ratio_test(a, a * 1.01).rejects()
    with pytest.raises(InputError, match="two Stripes or two capacity lists"):
        likelihood_ratio_test(a, Stripes([0.5, 1.0], [2, 2], [0, 2]))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: Stripes([0.2, 0.3], [10, 10], [0, 11]), r"at im = 0.3, k = 11 exceeds n = 10"),
        (lambda: Stripes([0.2, -0.3], [10, 10], [0, 1]), r"im must be > 0"),
        (lambda: Stripes([0.2, 0.3], [10, 10.5], [0, 1]), r"every n must be a whole number"),
        (lambda: fit_stripes(Stripes([0.2, 0.3], [10, 10], [0, 0])), r"none reached"),
        (lambda: fit_stripes(Stripes([0.2, 0.3], [10, 10], [8, 2])), r"falls as the intensity"),
        (lambda: fit_stripes(Stripes([0.2], [10], [4])), r"one intensity only"),
        (lambda: fit_capacities([0.5]), r"at least 2 are needed"),
        (lambda: fit_capacities([0.5, -1.0]), r"finite and > the origin 0"),
        (lambda: bootstrap_capacities([0.5, 0.7, 0.9], draws=3), r"draws = 3 must be"),
    ],
)
def test_bad_data_is_one_input_error(call, message):
    with pytest.raises(InputError, match=message):
        call()
