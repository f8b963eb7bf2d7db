"""Lognormal fragility curves: fits to multiple-stripe and IDA data, bootstrap bands over records,
and a likelihood-ratio test whether two models' data fit one curve.

A fragility curve is ``P[limit state | IM = x] = Phi(ln(x / theta) / beta)`` (median theta, in the
IM's unit; dispersion beta), or the shifted form ``Phi(ln((x - x0) / theta) / beta)`` for
x > x0 and 0 at and below an origin x0 (e.g. the uplift intensity, below which a rocking block
does nothing).

* Multiple-stripe analysis (:func:`fit_stripes`), Baker (2015), Eq. 11: with k_j of n_j records
  in the limit state at IM x_j, theta and beta maximise the binomial log-likelihood
  ``sum_j ln C(n_j, k_j) + k_j ln P_j + (n_j - k_j) ln(1 - P_j)``,
  ``P_j = Phi(ln(x_j / theta) / beta)``: a probit regression on ln x, concave in
  (-ln theta / beta, 1 / beta), solved by Newton's method.
  Stripes that separate perfectly (none below some IM, all above it) have no finite maximum:
  the fit is the step there (beta = 0, theta the geometric mean of the two stripes that bound
  it), marked ``separated``.
* Incremental dynamic analysis (:func:`fit_capacities`), Baker (2015), Eqs. 1-2: each record's
  capacity c_i (its IM at the first exceedance on its ladder); ``ln theta = mean ln c_i``,
  ``beta = std ln c_i`` (n - 1 in the denominator). Records that never exceed on their ladder
  are censored at their ladder's top: then the censored maximum likelihood
  ``sum_uncensored ln phi(.)/(beta c_i) + sum_censored ln(1 - Phi(ln(c_i / theta) / beta))``
  (a Tobit model, concave in Olsen (1978)'s 1 / beta, ln theta / beta: Newton's method).
* Bootstrap over records (:func:`bootstrap_stripes`, :func:`bootstrap_capacities`): records
  drawn with replacement (seeded, numpy's PCG64), refitted; percentile intervals of theta, beta
  and of the curve at chosen IMs (Efron & Tibshirani 1993, ch. 13).
* Same curve? (:func:`likelihood_ratio_test`): ``Lambda = 2 (ln L_a + ln L_b - ln L_joint)``, each
  at its maximum, against chi-square with 2 degrees of freedom (Wilks 1938): the probability of a
  Lambda this large if both data sets came from one (theta, beta). It assumes independent data;
  the same records through two models are positively correlated, which makes the test
  conservative (it rejects less often than its level says).

Reference: J. W. Baker (2015), Efficient analytical fragility function fitting using dynamic
structural analysis, Earthquake Spectra 31(1), 579-599.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError

__all__ = [
    "Band",
    "LikelihoodRatio",
    "LognormalFit",
    "Stripes",
    "bootstrap_capacities",
    "bootstrap_stripes",
    "fit_capacities",
    "fit_stripes",
    "likelihood_ratio_test",
    "stripes_of",
]


@dataclass(frozen=True)
class LognormalFit:
    """A fitted lognormal fragility: ``median`` theta (IM unit; of IM - origin in the shifted
    form, whose 50 % IM is :attr:`im50`), dispersion ``beta``, ``origin`` x0 of the shifted form
    (0: the plain lognormal), the maximised ``log_likelihood``, the
    ``method`` ('stripes MLE', 'capacity moments', 'censored capacity MLE'); ``separated``: the
    stripes separate perfectly and the fit is the step at ``median`` (beta = 0)."""

    median: float
    beta: float
    origin: float = 0.0
    log_likelihood: float = 0.0
    method: str = "stripes MLE"
    separated: bool = False

    @property
    def im50(self) -> float:
        """The IM at which the probability is 1/2: ``origin + median``."""
        return self.origin + self.median

    def probability(self, im):
        """P[limit state | IM = im] (array or scalar)."""
        x = np.asarray(im, dtype=float) - self.origin
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.beta == 0.0:
                p = np.where(x >= self.median, 1.0, 0.0)
            else:
                from scipy.special import ndtr

                p = ndtr(np.log(np.where(x > 0.0, x, 1.0) / self.median) / self.beta)
        p = np.where(x > 0.0, p, 0.0)
        return float(p) if np.ndim(p) == 0 else p

    def to_dict(self) -> dict:
        return {
            "median": self.median,
            "beta": self.beta,
            "origin": self.origin,
            "log_likelihood": self.log_likelihood,
            "method": self.method,
            "separated": self.separated,
        }


@dataclass(frozen=True)
class Stripes:
    """Multiple-stripe data: at each IM level ``im[j]``, ``k[j]`` of ``n[j]`` records reached the
    limit state."""

    im: np.ndarray
    n: np.ndarray
    k: np.ndarray

    def __post_init__(self):
        im = np.atleast_1d(np.asarray(self.im, dtype=float))
        n = np.atleast_1d(np.asarray(self.n))
        k = np.atleast_1d(np.asarray(self.k))
        if not (im.shape == n.shape == k.shape) or im.ndim != 1 or im.size == 0:
            raise InputError(
                f"stripes: im, n and k must be equal-length lists (got {im.size}, {n.size}, "
                f"{k.size})"
            )
        if not np.all(np.isfinite(im)) or np.any(im <= 0.0):
            raise InputError("stripes: every intensity im must be > 0 and finite")
        for name, v in (("n", n), ("k", k)):
            if np.any(v != np.round(v)) or np.any(v < 0):
                raise InputError(f"stripes: every {name} must be a whole number >= 0")
        if np.any(k > n):
            j = int(np.flatnonzero(k > n)[0])
            raise InputError(f"stripes: at im = {im[j]:g}, k = {k[j]} exceeds n = {n[j]}")
        if np.all(n == 0):
            raise InputError("stripes: no records (every n is 0)")
        object.__setattr__(self, "im", im)
        object.__setattr__(self, "n", n.astype(np.int64))
        object.__setattr__(self, "k", k.astype(np.int64))

    @property
    def fractions(self) -> np.ndarray:
        """k / n at each stripe (nan where n = 0)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.k / self.n


def stripes_of(im, outcomes) -> Stripes:
    """Stripes from per-record outcomes: ``outcomes[i, j]`` True where record i reached the
    limit state at stripe j (IM ``im[j]``); NaN (a float array) where record i was not run
    there (it counts in neither n nor k)."""
    out = np.asarray(outcomes, dtype=float)
    if out.ndim != 2 or out.shape[1] != np.size(im):
        raise InputError(
            f"outcomes must be a records x stripes table with {np.size(im)} columns "
            f"(got shape {out.shape})"
        )
    ran = ~np.isnan(out)
    return Stripes(im, ran.sum(axis=0), np.where(ran, out, 0.0).sum(axis=0))


def _log_binomial(n: np.ndarray, k: np.ndarray) -> np.ndarray:
    from scipy.special import gammaln

    return gammaln(n + 1.0) - gammaln(k + 1.0) - gammaln(n - k + 1.0)


def _stripes_log_likelihood(x: np.ndarray, n, k, ln_theta: float, beta: float) -> float:
    from scipy.special import log_ndtr

    z = (np.log(x) - ln_theta) / beta
    return float(np.sum(_log_binomial(n, k) + k * log_ndtr(z) + (n - k) * log_ndtr(-z)))


def _separation(x: np.ndarray, n: np.ndarray, k: np.ndarray) -> tuple[float, float] | None:
    """(largest IM with none, smallest IM with all) where the stripes separate perfectly (every
    stripe below has k = 0, every one above k = n, both kinds present), else None."""
    used = n > 0
    x, n, k = x[used], n[used], k[used]
    none, every = k == 0, k == n
    if not np.all(none | every) or not none.any() or not every.any():
        return None
    below, above = float(x[none].max()), float(x[every].min())
    return (below, above) if below < above else None


def fit_stripes(stripes: Stripes, *, origin: float = 0.0) -> LognormalFit:
    """The lognormal (shifted by ``origin`` where > 0) that maximises the binomial likelihood of
    ``stripes`` (Baker 2015, Eq. 11). InputError where the data hold no information on it: no
    stripe with a record in the limit state, or none with a record out of it, or a stripe at or
    below the origin with one in it."""
    x = stripes.im - origin
    n, k = stripes.n.astype(float), stripes.k.astype(float)
    if origin < 0.0 or not math.isfinite(origin):
        raise InputError(f"origin = {origin:g} must be >= 0 and finite")
    at_origin = (x <= 0.0) & (n > 0)
    if np.any(stripes.k[at_origin] > 0):
        j = int(np.flatnonzero(at_origin & (stripes.k > 0))[0])
        raise InputError(
            f"stripes: at im = {stripes.im[j]:g}, at or below the origin {origin:g}, "
            f"{stripes.k[j]} records are in the limit state: the shifted curve is 0 there"
        )
    keep = (x > 0.0) & (n > 0)
    x, n, k = x[keep], n[keep], k[keep]
    if k.sum() == 0 or (n - k).sum() == 0:
        state = "none" if k.sum() == 0 else "every record"
        raise InputError(
            f"stripes: {state} reached the limit state at every intensity above the origin: "
            "no curve can be fitted (add stripes above or below)"
        )
    step = _separation(x, n, k)
    if step is not None:
        return LognormalFit(
            math.sqrt(step[0] * step[1]), 0.0, origin, 0.0, "stripes MLE", separated=True
        )
    if np.unique(x).size < 2:
        raise InputError(
            "stripes: data at one intensity only: a median and a dispersion need two or more"
        )
    intercept, slope = _probit_newton(np.log(x), n, k)
    if not slope > 0.0:
        raise InputError(
            "stripes: the fraction in the limit state falls as the intensity rises: a "
            "fragility curve (rising with the IM) does not fit these data"
        )
    beta, ln_theta = 1.0 / slope, -intercept / slope
    ll = _stripes_log_likelihood(x, n, k, ln_theta, beta)
    return LognormalFit(math.exp(ln_theta), beta, origin, ll)


def _probit_newton(z: np.ndarray, n: np.ndarray, k: np.ndarray) -> tuple[float, float]:
    """(a, b) maximising ``sum k ln Phi(a + b z) + (n - k) ln Phi(-(a + b z))``: probit
    regression, whose log-likelihood is concave in (a, b), by Newton's method with step halving
    (Baker's lognormal: b = 1 / beta, a = -ln(theta) / beta)."""
    from scipy.special import log_ndtr

    def loglik(a, b):
        eta = a + b * z
        return float(np.sum(k * log_ndtr(eta) + (n - k) * log_ndtr(-eta)))

    def mills(eta):  # phi(eta) / Phi(eta), stable in both tails
        return np.exp(-0.5 * eta**2 - 0.5 * math.log(2.0 * math.pi) - log_ndtr(eta))

    def derivatives(a, b):
        eta = a + b * z
        up, down = mills(eta), mills(-eta)
        g = k * up - (n - k) * down  # d loglik / d eta
        h = -k * up * (eta + up) - (n - k) * down * (down - eta)  # d2 loglik / d eta2 (< 0)
        grad = np.array([g.sum(), (g * z).sum()])
        hess = np.array([[h.sum(), (h * z).sum()], [(h * z).sum(), (h * z * z).sum()]])
        return grad, hess

    # P = 1/2 everywhere: a start inside the concave region's basin
    a, b = _newton_ascent(
        loglik, derivatives, (0.0, 0.0), "stripes: the likelihood has no unique maximum"
    )
    return float(a), float(b)


def _newton_ascent(loglik, derivatives, start, singular: str | None = None):
    """The maximum of a concave two-parameter ``loglik`` by Newton's method, each step halved
    until the likelihood does not fall; ``derivatives(x0, x1)`` gives (gradient, Hessian).
    ``singular``: the InputError's message where a Hessian cannot be solved (None: numpy's
    error as it is)."""
    x0, x1 = start
    current = loglik(x0, x1)
    for _ in range(100):
        grad, hess = derivatives(x0, x1)
        try:
            step = np.linalg.solve(hess, -grad)
        except np.linalg.LinAlgError:
            if singular is None:
                raise
            raise InputError(singular) from None
        t = 1.0
        while t > 1e-12:
            trial = loglik(x0 + t * step[0], x1 + t * step[1])
            if trial >= current - 1e-15 * abs(current):
                break
            t *= 0.5
        x0, x1, current = x0 + t * step[0], x1 + t * step[1], trial
        if abs(t * step[0]) + abs(t * step[1]) < 1e-13 * (1.0 + abs(x0) + abs(x1)):
            break
    return x0, x1


def _capacity_log_likelihood(lc, censored, mu: float, beta: float) -> float:
    from scipy.special import log_ndtr

    z = (lc - mu) / beta
    exact = -0.5 * z[~censored] ** 2 - math.log(beta * math.sqrt(2.0 * math.pi)) - lc[~censored]
    return float(exact.sum() + log_ndtr(-z[censored]).sum())


def fit_capacities(capacities, *, censored=None, origin: float = 0.0) -> LognormalFit:
    """The lognormal of IDA capacities (IM at each record's first exceedance, > ``origin``):
    ``ln theta = mean ln (c - x0)``, ``beta = std ln (c - x0)`` (n - 1; Baker 2015, Eqs. 1-2).
    ``censored[i]`` True: record i never exceeded up to ``capacities[i]`` (its ladder's top);
    the fit is then the censored maximum likelihood. ``log_likelihood``: the lognormal density's
    log-likelihood at the fit (with the censored terms)."""
    c = np.atleast_1d(np.asarray(capacities, dtype=float))
    cens = np.zeros(c.shape, bool) if censored is None else np.asarray(censored, dtype=bool)
    if c.ndim != 1 or cens.shape != c.shape:
        raise InputError("capacities and censored must be equal-length lists")
    if not np.all(np.isfinite(c)) or np.any(c <= origin):
        raise InputError(f"capacities must be finite and > the origin {origin:g}")
    lc = np.log(c - origin)
    exact = ~cens
    if exact.sum() < 2:
        raise InputError(
            f"capacities: {int(exact.sum())} records exceeded the limit state on their ladder: "
            "at least 2 are needed to fit a dispersion"
        )
    mu, beta = float(lc[exact].mean()), float(lc[exact].std(ddof=1))
    if np.ptp(lc[exact]) == 0.0:  # the mean of equal logs can differ from them by an ulp
        raise InputError("capacities: every record's capacity is the same: no dispersion")
    if not cens.any():
        ll = _capacity_log_likelihood(lc, cens, mu, beta)
        return LognormalFit(math.exp(mu), beta, origin, ll, "capacity moments")
    mu, beta = _tobit_newton(lc, cens, mu, beta)
    if not (math.isfinite(mu) and math.isfinite(beta) and beta > 0.0):
        raise InputError(
            "capacities: the censored fit has no finite maximum (the records that exceeded "
            "hold too little dispersion beside the censored ones)"
        )
    return LognormalFit(
        math.exp(mu),
        beta,
        origin,
        _capacity_log_likelihood(lc, cens, mu, beta),
        "censored capacity MLE",
    )


def _tobit_newton(y: np.ndarray, censored: np.ndarray, mu: float, beta: float):
    """(mu, beta) of the normal that maximises the likelihood of ``y`` (``censored``: known only
    to lie above), by Newton's method in Olsen (1978)'s parameters gamma = 1 / beta,
    delta = mu / beta, in which the log-likelihood is concave; from (mu, beta)."""
    from scipy.special import log_ndtr

    exact = ~censored
    ye, yc = y[exact], y[censored]

    def loglik(g, d):
        if not g > 0.0:
            return -math.inf
        ze, zc = g * ye - d, g * yc - d
        return float(ye.size * math.log(g) - 0.5 * np.sum(ze**2) + np.sum(log_ndtr(-zc)))

    def derivatives(g, d):
        ze, zc = g * ye - d, g * yc - d
        m = np.exp(-0.5 * zc**2 - 0.5 * math.log(2.0 * math.pi) - log_ndtr(-zc))  # phi/(1-Phi)
        w = m * (m - zc)
        grad = np.array([ye.size / g - np.sum(ze * ye) - np.sum(m * yc), np.sum(ze) + np.sum(m)])
        hess = np.array(
            [
                [-ye.size / g**2 - np.sum(ye**2) - np.sum(w * yc**2), np.sum(ye) + np.sum(w * yc)],
                [np.sum(ye) + np.sum(w * yc), -ye.size - np.sum(w)],
            ]
        )
        return grad, hess

    g, d = _newton_ascent(loglik, derivatives, (1.0 / beta, mu / beta))
    return float(d / g), float(1.0 / g)


@dataclass(frozen=True)
class Band:
    """A bootstrap over records: the fits of ``draws`` resamples (``medians``, ``betas``; the
    ``failed`` resamples that held no information are left out and counted), the two-sided
    ``level`` percentile intervals, and the curve's interval at ``im`` (``low``, ``high``)."""

    fit: LognormalFit
    medians: np.ndarray = field(repr=False)
    betas: np.ndarray = field(repr=False)
    level: float
    seed: int
    draws: int
    failed: int
    im: np.ndarray = field(repr=False)
    low: np.ndarray = field(repr=False)
    high: np.ndarray = field(repr=False)

    @property
    def median_interval(self) -> tuple[float, float]:
        return _interval(self.medians, self.level)

    @property
    def beta_interval(self) -> tuple[float, float]:
        return _interval(self.betas, self.level)


def _interval(values: np.ndarray, level: float) -> tuple[float, float]:
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(values, [tail, 100.0 - tail])
    return float(low), float(high)


def _check_bootstrap(draws: int, level: float) -> None:
    if draws < 10 or draws != int(draws):
        raise InputError(f"draws = {draws} must be a whole number >= 10")
    if not 0.0 < level < 1.0:
        raise InputError(f"level = {level:g} must be in (0, 1)")


def _band(fit, fits, level, seed, draws, im) -> Band:
    ok = [f for f in fits if f is not None]
    if len(ok) < 2:
        raise InputError(f"bootstrap: {draws - len(ok)} of {draws} resamples could not be fitted")
    grid = fit.median * np.exp(np.linspace(-2.5, 2.5, 41) * max(fit.beta, 0.1)) + fit.origin
    grid = np.asarray(im, dtype=float) if im is not None else grid
    curves = np.array([f.probability(grid) for f in ok])
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(curves, [tail, 100.0 - tail], axis=0)
    return Band(
        fit,
        np.array([f.median for f in ok]),
        np.array([f.beta for f in ok]),
        level,
        seed,
        draws,
        draws - len(ok),
        grid,
        low,
        high,
    )


def bootstrap_stripes(
    im,
    outcomes,
    *,
    draws: int = 1000,
    seed: int = 0,
    level: float = 0.9,
    origin: float = 0.0,
    at=None,
) -> Band:
    """Bootstrap over records of a multiple-stripe fit: ``outcomes[i, j]`` as in
    :func:`stripes_of`; each draw takes the records (rows) with replacement and refits.
    ``at``: the IMs where the curve's interval is wanted (default: 41 points about the
    median)."""
    _check_bootstrap(draws, level)
    out = np.asarray(outcomes, dtype=float)
    fit = fit_stripes(stripes_of(im, out), origin=origin)
    rng = np.random.default_rng(seed)
    fits: list[LognormalFit | None] = []
    for _ in range(draws):
        rows = rng.integers(0, out.shape[0], out.shape[0])
        try:
            fits.append(fit_stripes(stripes_of(im, out[rows]), origin=origin))
        except InputError:
            fits.append(None)
    return _band(fit, fits, level, seed, draws, at)


def bootstrap_capacities(
    capacities,
    *,
    censored=None,
    draws: int = 1000,
    seed: int = 0,
    level: float = 0.9,
    origin: float = 0.0,
    at=None,
) -> Band:
    """Bootstrap over records of an IDA fit (:func:`fit_capacities`): capacities drawn with
    replacement (with their censoring) and refitted."""
    _check_bootstrap(draws, level)
    c = np.atleast_1d(np.asarray(capacities, dtype=float))
    cens = np.zeros(c.shape, bool) if censored is None else np.asarray(censored, dtype=bool)
    fit = fit_capacities(c, censored=cens, origin=origin)
    rng = np.random.default_rng(seed)
    fits: list[LognormalFit | None] = []
    for _ in range(draws):
        rows = rng.integers(0, c.size, c.size)
        try:
            fits.append(fit_capacities(c[rows], censored=cens[rows], origin=origin))
        except InputError:
            fits.append(None)
    return _band(fit, fits, level, seed, draws, at)


@dataclass(frozen=True)
class LikelihoodRatio:
    """The likelihood-ratio test of one curve for two data sets: ``statistic`` Lambda =
    2 (ln L_a + ln L_b - ln L_joint), ``dof`` 2, ``p_value`` P[chi2_2 >= Lambda], and the fits."""

    statistic: float
    dof: int
    p_value: float
    first: LognormalFit
    second: LognormalFit
    joint: LognormalFit

    def rejects(self, significance: float = 0.05) -> bool:
        """True where one curve is rejected at ``significance``."""
        return self.p_value < significance


def likelihood_ratio_test(first, second, *, origin: float = 0.0) -> LikelihoodRatio:
    """Whether two data sets fit one lognormal curve: both :class:`Stripes` (multiple-stripe,
    binomial likelihood) or both capacity lists (IDA without censoring, lognormal likelihood
    at the maximum, i.e. beta with n in the denominator)."""
    from scipy.stats import chi2

    if isinstance(first, Stripes) and isinstance(second, Stripes):
        a = fit_stripes(first, origin=origin)
        b = fit_stripes(second, origin=origin)
        joined = Stripes(
            np.concatenate([first.im, second.im]),
            np.concatenate([first.n, second.n]),
            np.concatenate([first.k, second.k]),
        )
        joint = fit_stripes(joined, origin=origin)
        if a.separated or b.separated or joint.separated:
            raise InputError(
                "likelihood-ratio test: a data set separates perfectly (a step, beta = 0): its "
                "likelihood has no maximum and the test does not apply"
            )
    elif not isinstance(first, Stripes) and not isinstance(second, Stripes):
        a, b = _capacity_mle(first, origin), _capacity_mle(second, origin)
        joint = _capacity_mle(np.concatenate([np.ravel(first), np.ravel(second)]), origin)
    else:
        raise InputError("likelihood-ratio test: give two Stripes or two capacity lists")
    statistic = max(0.0, 2.0 * (a.log_likelihood + b.log_likelihood - joint.log_likelihood))
    return LikelihoodRatio(statistic, 2, float(chi2.sf(statistic, 2)), a, b, joint)


def _capacity_mle(capacities, origin: float) -> LognormalFit:
    """The lognormal maximum likelihood of uncensored capacities (std with n)."""
    c = np.atleast_1d(np.asarray(capacities, dtype=float))
    moments = fit_capacities(c, origin=origin)
    lc = np.log(c - origin)
    mu, beta = float(lc.mean()), float(lc.std())
    ll = _capacity_log_likelihood(lc, np.zeros(c.shape, bool), mu, beta)
    return LognormalFit(moments.median, beta, origin, ll, "capacity MLE")
