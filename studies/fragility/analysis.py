"""Fragility from the runs of a record suite: limit states, IDA capacities, stripes and fits.

Every record i of the suite is scaled to every intensity level x_j of the study (its IM times
x_j / IM_i: the IMs offered scale linearly with the record), and each model ran it once. What a
run gives (:data:`RUN_KEYS`) becomes, per limit state, a records x levels table of booleans
(:func:`exceedances`):

* ``uplift``: the column left the ground (|theta| above :data:`UPLIFT_RATIO` alpha; the SDOF's
  exact event: any rotation at all); the rigid models only: the FEM's column sways on its bed
  past any such threshold long before it rocks;
* ``rotation``: |theta| / alpha reached the study's threshold, or the column overturned;
* ``overturning``: the column overturned;
* ``collar_yield``: a collar's extreme fibre reached f_y (with collars);
* ``collar_fracture``: a plastic collar reached its fracture strain (multibody and FEM with
  plastic collars: the SDOF's springs stay elastic);
* ``toe_crushing``: the FEM's toe stress reached the stone's f_c.

Incremental dynamic analysis (Vamvatsikos & Cornell 2002): a record's capacity is the level of
its FIRST exceedance on the ladder (:func:`first_exceedance`), as the rocking IDA literature
defines it (Lachanas, Vamvatsikos & Dimitrakopoulos): a rocking block can overturn at one scale
and survive a higher one, and the capacity is the first. A record that never exceeds on its
ladder is censored at the ladder's top. Multiple-stripe analysis (Baker 2015): the fraction of
records in the limit state at each level, fitted by binomial maximum likelihood. Both fits and
their bootstrap bands over records are :mod:`colonna.core.fragility`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...core import fragility as fits
from ...core import hazard as hazards
from ...core import risk
from ...core.errors import InputError

# the limit states, in the order a report lists them, with their words
LIMIT_STATES = {
    "uplift": "uplift",
    "rotation": "|theta| / alpha above the threshold",
    "overturning": "overturning",
    "collar_yield": "collar yield",
    "collar_fracture": "collar fracture",
    "toe_crushing": "toe crushing",
}
# what a run of any model gives (None where the model does not compute it)
RUN_KEYS = (
    "overturned",
    "peak_ratio",  # largest |theta| / alpha (pi / 2 / alpha once overturned)
    "uplift",
    "collar_utilisation",
    "collar_fractured",
    "toe_ratio",
)
UPLIFT_RATIO = 1e-4  # |theta| / alpha above this is uplift (the multibody's contact compliance)


def ladder(start: float, stop: float, steps: int) -> np.ndarray:
    """``steps`` intensity levels evenly spaced from ``start`` to ``stop`` (inclusive)."""
    if not (0.0 < start <= stop and math.isfinite(stop)) or steps < 1:
        raise InputError(
            f"fragility ladder [{start:g}, {stop:g}] with {steps} steps: need "
            "0 < start <= stop and steps >= 1"
        )
    return np.linspace(start, stop, steps) if steps > 1 else np.array([float(start)])


def scales_for(levels, record_im: float, name: str = "record") -> np.ndarray:
    """The factors that scale a record of intensity ``record_im`` to each of ``levels``."""
    if not (record_im > 0.0 and math.isfinite(record_im)):
        raise InputError(
            f"record {name!r}: its intensity measure is {record_im:g}: it cannot be scaled "
            "to an intensity level (a record of zero motion?)"
        )
    return np.asarray(levels, dtype=float) / record_im


def table(runs: list[list[dict]], key: str) -> np.ndarray:
    """The records x levels table of one run key (float; NaN where a run gives None)."""
    return np.array(
        [[np.nan if r.get(key) is None else float(r[key]) for r in row] for row in runs],
        dtype=float,
    )


def exceedances(runs: list[list[dict]], theta_ratio: float) -> dict[str, np.ndarray]:
    """Per limit state that the runs assess, the records x levels table of exceedances (bool).
    ``runs[i][j]``: the run of record i at level j (:data:`RUN_KEYS`). A limit state none of
    whose runs gives a number (collars without a collar, toe crushing without the FEM) is left
    out."""
    overturned = table(runs, "overturned") > 0.5
    peak = table(runs, "peak_ratio")
    found = {}
    uplift = table(runs, "uplift")
    if np.isfinite(uplift).all():  # the FEM does not assess it (studies.fragility.models)
        found["uplift"] = uplift > 0.5
    found["rotation"] = overturned | (peak >= theta_ratio)
    found["overturning"] = overturned
    utilisation = table(runs, "collar_utilisation")
    if np.isfinite(utilisation).all():
        found["collar_yield"] = utilisation >= 1.0
    fractured = table(runs, "collar_fractured")
    if np.isfinite(fractured).all():
        found["collar_fracture"] = fractured > 0.5
    toe = table(runs, "toe_ratio")
    if np.isfinite(toe).all():
        found["toe_crushing"] = toe >= 1.0
    return found


def first_exceedance(exceeded, levels) -> tuple[np.ndarray, np.ndarray]:
    """(capacity, censored) per record: the level of its FIRST exceedance on the ladder (a
    record that exceeds at one level and not at a higher one keeps the first), and, for one
    that never exceeds, the ladder's top with ``censored`` True."""
    exceeded = np.asarray(exceeded, dtype=bool)
    levels = np.asarray(levels, dtype=float)
    ever = exceeded.any(axis=1)
    first = np.argmax(exceeded, axis=1)
    capacity = np.where(ever, levels[first], levels[-1])
    return capacity, ~ever


@dataclass(frozen=True)
class Bootstrap:
    """How the fits' bands are drawn: ``draws`` bootstrap resamples from the random ``seed``,
    the bands at confidence ``level`` (e.g. 0.9: the 5 % and 95 % quantiles of the draws; the
    fractions' Clopper-Pearson intervals at the same level)."""

    draws: int
    seed: int
    level: float


def fit_limit_state(
    exceeded,
    levels,
    design: float,
    *,
    bootstrap: Bootstrap,
    ida: bool,
    origin: float = 0.0,
    hazard: hazards.HazardCurve | None = None,
    years: float = 50.0,
) -> dict:
    """The fits of one limit state's exceedances (records x levels): the multiple-stripe
    binomial MLE with its bootstrap band (always), and with ``ida`` the IDA capacities' fit
    (first exceedance, censored at the top) and its band; each with P at the ``design``
    intensity and its interval, and with a ``hazard`` (in the fits' measure) its ``risk``
    (:func:`risk_entry`). A limit state no run reached (or every run did) has no
    curve: its fractions are given and its fit is None, with the reason. ``origin`` > 0: both
    fits are the shifted lognormal of IM - origin (0 up to the origin). ``bootstrap``: the
    bands' draws, seed and confidence level (:class:`Bootstrap`)."""
    draws, seed, level = bootstrap.draws, bootstrap.seed, bootstrap.level
    exceeded = np.asarray(exceeded, dtype=bool)
    levels = np.asarray(levels, dtype=float)
    counts = exceeded.sum(axis=0)
    n = exceeded.shape[0]
    entry: dict = {
        "fractions": (counts / n).tolist(),
        "fraction_intervals": clopper_pearson(counts, n, level).tolist(),
        "counts": counts.astype(int).tolist(),
        "records": n,
    }
    if counts.sum() == 0:
        entry.update(stripes=None, ida=None, why="no run reached it")
        return entry
    if levels.size < 2:
        entry.update(stripes=None, ida=None, why="one intensity level: no curve")
        return entry
    at = np.concatenate([[design], curve_grid(levels, design)])
    entry["stripes"] = outside_levels(
        _band_entry(
            lambda: fits.bootstrap_stripes(
                levels,
                exceeded.astype(float),
                draws=draws,
                seed=seed,
                level=level,
                origin=origin,
                at=at,
            ),
            hazard,
            years,
            levels,
        ),
        levels,
    )
    if ida:
        capacity, censored = first_exceedance(exceeded, levels)
        entry["capacities"] = capacity.tolist()
        entry["censored"] = censored.tolist()
        entry["ida"] = (
            None
            if censored.all()
            else outside_levels(
                _band_entry(
                    lambda: fits.bootstrap_capacities(
                        capacity,
                        censored=censored,
                        draws=draws,
                        seed=seed,
                        level=level,
                        origin=origin,
                        at=at,
                    ),
                    hazard,
                    years,
                    levels,
                ),
                levels,
            )
        )
    return entry


def outside_levels(band: dict | None, levels) -> dict | None:
    """A fit (:func:`_band_entry`) with what of it is read outside the levels run flagged:
    ``curve["extrapolated"]``, per point of its curve, whether it lies below the lowest level
    or above the highest; ``extrapolated``, in words, its median (the IM of P = 1/2) or an end
    of the median's interval outside them (empty where none is). A fit's curve beyond its
    data is the lognormal's shape, not the records' answer."""
    if band is None or band.get("fit") is None:
        return band
    low, high = float(np.min(levels)), float(np.max(levels))
    im = np.asarray(band["curve"]["im"], dtype=float)
    band["curve"]["extrapolated"] = ((im < low) | (im > high)).tolist()
    origin = band["fit"].get("origin", 0.0)
    median = "the median" if origin == 0.0 else "x0 + the median"
    words = []
    for name, value in (
        (median, origin + band["fit"]["median"]),
        (f"{median} interval's lower end", origin + band["median_interval"][0]),
        (f"{median} interval's upper end", origin + band["median_interval"][1]),
    ):
        if value > high:
            words.append(f"{name}, {value:.4g}, lies above the highest level run, {high:.4g}")
        elif value < low:
            words.append(f"{name}, {value:.4g}, lies below the lowest level run, {low:.4g}")
    band["extrapolated"] = words
    return band


def clopper_pearson(k, n: int, level: float) -> np.ndarray:
    """The exact two-sided ``level`` interval of a binomial fraction k / n (Clopper & Pearson
    1934), per k: rows (low, high)."""
    from scipy.stats import beta

    k = np.asarray(k, dtype=float)
    tail = 0.5 * (1.0 - level)
    low = np.where(k > 0, beta.ppf(tail, k, n - k + 1), 0.0)
    high = np.where(k < n, beta.ppf(1.0 - tail, k + 1, n - k), 1.0)
    return np.column_stack([low, high])


def curve_grid(levels, design: float, points: int = 60) -> np.ndarray:
    """The intensities a fitted curve and its band are drawn at: from 0 (excluded) to past the
    highest level and the design intensity."""
    top = 1.1 * max(float(np.max(levels)), design)
    return np.linspace(0.0, top, points + 1)[1:]


def _band_entry(
    make,
    hazard: hazards.HazardCurve | None = None,
    years: float = 50.0,
    levels=None,
) -> dict | None:
    """A fit with its bootstrap band as plain data: the fit, its intervals, P at the design
    intensity (the band's first IM) with its interval, and the curve and band at the rest
    (:func:`curve_grid`); with a ``hazard``, its ``risk`` over the ``levels`` run
    (:func:`risk_entry`); ``fit`` None where the data hold no curve."""
    try:
        band = make()
    except InputError as exc:
        return {"fit": None, "why": str(exc)}
    fit = band.fit
    found = {} if hazard is None else {"risk": risk_entry(band, hazard, years, levels)}
    return {
        **found,
        "fit": fit.to_dict(),
        "median_interval": list(band.median_interval),
        "beta_interval": list(band.beta_interval),
        "probability": float(fit.probability(band.im[0])),
        "probability_interval": [float(band.low[0]), float(band.high[0])],
        "curve": {
            "im": band.im[1:].tolist(),
            "probability": np.asarray(fit.probability(band.im[1:])).tolist(),
            "low": band.low[1:].tolist(),
            "high": band.high[1:].tolist(),
        },
        "level": band.level,
        "draws": band.draws,
        "failed": band.failed,
        "seed": band.seed,
    }


def same_curve(first, second, levels, *, origin: float = 0.0) -> dict | None:
    """The likelihood-ratio test (:func:`colonna.core.fragility.likelihood_ratio_test`) whether
    two models' stripes of one limit state fit one curve; None where it does not apply (a step,
    or no exceedance), with the reason."""
    try:
        a = fits.stripes_of(levels, np.asarray(first, dtype=float))
        b = fits.stripes_of(levels, np.asarray(second, dtype=float))
        test = fits.likelihood_ratio_test(a, b, origin=origin)
    except InputError as exc:
        return {"p_value": None, "why": str(exc)}
    return {
        "statistic": test.statistic,
        "dof": test.dof,
        "p_value": test.p_value,
        "one_curve": not test.rejects(0.05),
        "joint": test.joint.to_dict(),
    }


# the limit states whose "not reached" rests on the collars' response after they yield
AFTER_YIELD = ("rotation", "overturning", "toe_crushing")


def past_yield(runs: list[list[dict]]) -> dict | None:
    """Where elastic collars carried more than f_y in runs the column survived (its survival
    there rests on collars past their strength; an overturned run's stress is the stop's):
    the count of such runs, of the runs that survived, the largest utilisation over them, and
    per level whether any run there did. None without collar stresses or where none did."""
    utilisation = table(runs, "collar_utilisation")
    if not np.isfinite(utilisation).all():
        return None
    survived = ~(table(runs, "overturned") > 0.5)
    past = survived & (utilisation >= 1.0)
    if not past.any():
        return None
    return {
        "runs": int(past.sum()),
        "of": int(survived.sum()),
        "largest_utilisation": float(np.max(utilisation[survived])),
        "levels": past.any(axis=0).tolist(),
    }


# --- risk: the fits against the site's hazard ([hazard], colonna.core.risk) ---------------------

# the hazard measure each fragility intensity is (a multiple of): colonna.core.hazard.in_measure
HAZARD_MEASURE = {
    "pga": "pga",
    "pga_rocking": "pga",
    "pgv": "pgv",
    "pgv_rocking": "pgv",
    "sa": "sa",
}
BEYOND_SHARE = 0.01  # a part of lambda (or of the capacities) beyond the table said in words


def site_hazard(table, intensity: str, period: float | None, unit: str, block, base: Path):
    """The study's [hazard] (:class:`studies.schema.Hazard`, None: none) as a hazard curve in
    the fragility's ``intensity`` (unit ``unit``): the file's table or the power law, its
    intensity times 1 / a_up for pga_rocking and p / a_up for pgv_rocking (a_up the rocking
    ``block``'s uplift acceleration, as the records' IMs are normalised); an InputError naming
    both keys where the hazard's measure is not the fragility's."""
    if table is None:
        return None
    if table.file is not None:
        curve = hazards.read_hazard(Path(base) / table.file, beyond=table.beyond)
        key = f"hazard.file = {table.file!r}"
    else:
        curve = hazards.power_law(table.k0, table.k, table.intensity, period=table.period)
        key = f"hazard.intensity = {table.intensity!r}"
    measure = HAZARD_MEASURE[intensity]
    uplift = block.uplift_acceleration()
    factor = {"pga_rocking": 1.0 / uplift, "pgv_rocking": block.p / uplift}.get(intensity, 1.0)
    try:
        return hazards.in_measure(curve, intensity, measure, factor, unit, period=period)
    except InputError as exc:
        same = [name for name, m in HAZARD_MEASURE.items() if m == curve.intensity]
        raise InputError(
            f"{key} and fragility.intensity = {intensity!r}: {exc}: give a hazard of "
            f"{measure.upper()}{f'({period:g} s)' if measure == 'sa' else ''}, or set "
            f"fragility.intensity to {' or '.join(repr(n) for n in same)}"
        ) from None


def risk_entry(band: fits.Band, hazard: hazards.HazardCurve, years: float, levels=None) -> dict:
    """A fit's risk at the site (:func:`colonna.core.risk.limit_state_frequency`): the mean
    annual frequency of the limit state, its return period and its probability in ``years``
    (1 - exp(-lambda T)), each with the bootstrap's interval (lambda of every replica's fit,
    the band's percentiles: P and the return period are monotonic in lambda); the shares of
    lambda from capacities below and above a hazard table (``below``, ``above``) and below and
    above the ``levels`` run (``below_levels``, ``above_levels``: read on the fit's
    extrapolation), and what is read beyond either in words (``beyond``)."""
    fit = band.fit
    within = None if levels is None else (float(np.min(levels)), float(np.max(levels)))
    best = risk.limit_state_frequency(hazard, fit.median, fit.beta, fit.origin, within)
    replicas = np.array(
        [
            risk.limit_state_frequency(hazard, m, b, fit.origin).value
            for m, b in zip(band.medians, band.betas)
        ]
    )
    tail = 50.0 * (1.0 - band.level)
    ends = [tail, 100.0 - tail]
    if np.isfinite(replicas).all():
        low, high = (float(v) for v in np.percentile(replicas, ends))
    else:  # (a replica's lambda past the largest double is inf: no interpolation with it)
        low, high = (float(v) for v in np.percentile(replicas, ends, method="inverted_cdf"))
    p, p_low, p_high = (float(v) for v in risk.probability_in([best.value, low, high], years))
    return {
        "frequency": best.value,
        "frequency_interval": [low, high],
        "return_period": _period(best.value),
        "return_period_interval": [_period(high), _period(low)],
        "years": years,
        "probability": p,
        "probability_interval": [p_low, p_high],
        "below": best.below,
        "above": best.above,
        "below_levels": best.below_within,
        "above_levels": best.above_within,
        "beyond": beyond_words(hazard, fit, best, within),
        "level": band.level,
        "draws": int(replicas.size),
    }


def _period(frequency: float) -> float | None:
    """1 / lambda (years); None where lambda is 0 (never)."""
    return 1.0 / frequency if frequency > 0.0 else None


def beyond_words(
    hazard: hazards.HazardCurve,
    fit: fits.LognormalFit,
    best: risk.LimitStateFrequency,
    within: tuple[float, float] | None = None,
) -> list[str]:
    """What of a fit's lambda (``best``) is read beyond the levels run (``within``: on the
    fit's extrapolation) or beyond a hazard table, in words (more than :data:`BEYOND_SHARE` of
    it): outside the levels, its share; below the table, the share of lambda from capacities
    there, whose frequency is held at the lowest point's (a lower bound); above it,
    extrapolated, the share of lambda from capacities there and the power law used; truncated,
    the fraction of capacities above it, never exceeded (a lower bound)."""
    words = []
    if within is not None:
        for share, where, at in (
            (best.below_within, "below the lowest", within[0]),
            (best.above_within, "above the highest", within[1]),
        ):
            if share > BEYOND_SHARE:
                words.append(
                    f"{100 * share:.0f} % of lambda comes from capacities {where} level run, "
                    f"{at:.4g}: the fitted curve's extrapolation there, not the records' answer"
                )
    if not hazard.tabulated:
        return words
    low, high = hazard.range
    if best.below > BEYOND_SHARE:
        words.append(
            f"{100 * best.below:.0f} % of lambda comes from capacities below the hazard "
            f"table's lowest intensity, {low:.4g}, where its frequency is held at the lowest "
            "point's (the table gives none below it): lambda is a lower bound"
        )
    if hazard.beyond == "extrapolate" and best.above > BEYOND_SHARE:
        words.append(
            f"{100 * best.above:.0f} % of lambda comes from capacities above the hazard "
            f"table's highest intensity, {high:.4g}: extrapolated there by the power law of "
            f"its last segment (k = {hazard.slopes()[-1]:.3g})"
        )
    above = 1.0 - float(fit.probability(high))
    if hazard.beyond == "truncate" and above > BEYOND_SHARE:
        words.append(
            f"{100 * above:.0f} % of the capacities lie above the hazard table's highest "
            f"intensity, {high:.4g}: truncated, never exceeded (lambda is a lower bound)"
        )
    return words
