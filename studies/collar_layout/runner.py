"""The collar-layout study: which collars does this column need, against its site's risk?

Each layout of the catalogue ([layout] counts x sections x grades x pretensions, the collars
evenly spaced) is
judged by the mean annual frequency of overturning at the site, lambda = int P[overturn | im]
|d lambda_IM(im)| (:mod:`colonna.core.risk`), P from the IDA capacities of the record suite
(each record's first exceedance on the ladder, :func:`studies.fragility.analysis.first_exceedance`)
through the rigid multibody model.

1. **Screening, elastic collars** (:func:`ladder_walk`): the collars' stiffness sets the
   elastic model's motion, not their grade, so each count x section (x pretension force) is
   run once per record,
   up the ladder to its first overturning, with the collars' largest stress at every level. A
   plastic collar follows the elastic one exactly until it first yields, so for each grade a
   record whose run overturned before any collar reached f_y has that capacity in the plastic
   model too; one whose collars yielded first has its capacity at or above the first level
   at which they did. That gives each layout a bracket of lambda (:func:`bracket`): the
   upper end with every such record's capacity at its first yield, the lower end with it
   never overturning. Layouts whose lower end misses the target fail here.
2. **Refinement, plastic collars** (:func:`ladder_walk`, :func:`judge`): the layouts in the
   catalogue's order, up to [layout] shortlist of them, have their open records run with
   plastic collars from their first yield up to the first overturning (a layout with no open
   record whose screening misses the target by less than its scatter, :func:`screened_miss`:
   every record from the ladder's foot): their lambda (with its bootstrap band) and the share
   of records that fracture a collar at the design intensity. A layout is chosen only where
   every layout before it is refined and fails or is screened to miss.
3. **Confirmation, FEM** (:func:`fem_stripe`): the chosen layout's FEM runs of every record at
   the design intensity (the hazard's at [layout] design_return_period), against the multibody
   model's runs there, record by record (:func:`stripe_agreement`: confirms, contradicts,
   undecided), and its fit's probability; where it does not confirm, the next heavier layout
   that meets the target (where no collar yielded in the stripe, the next with more collars
   or a larger bar: :func:`capacity_skip`), up to [layout] fem_attempts layouts
   (:func:`fem_attempts`).
4. **Cross-check** (:func:`run_crosscheck`): the chosen layout's cross-check (the cross-check
   kind, a study of its own in ``chosen-crosscheck/``) under the record of median capacity at
   the design intensity: FEM against the rigid models, collars, toe.
The lightest layout that meets the target, with no more records fracturing a collar at the
design intensity than [layout] fracture_fraction allows, and whose FEM stripe confirms it, is
the answer (where no attempt is confirmed: the one :func:`recommended`)."""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import time
from pathlib import Path

import numpy as np

from ...core import fragility as fits
from ...core import risk
from ...core.errors import InputError
from ...core.ground import is_esm
from ...core.hazard import HazardCurve, annual_frequency, log_annual_frequency
from ..executor import RunOptions, run_cases
from ..fem_study import FemStudy, case_of, study_of_case
from ..fragility import analysis
from ..fragility.models import FREE_TIME_P, multibody_runs
from ..fragility.runner import _unit, suite_column
from ..guard import check_fem_results
from ..kinds import kind_of_package
from ..output import write_json
from ..study import Study
from .schema import STEEL_GRADES, Layout

STEEL_DENSITY = 7850.0  # kg/m^3 (EN 1991-1-1, Table A.4)
FEWER = (
    ", fewer layout.counts, sections or grades, a shorter ladder, layout.fem = false or "
    "layout.crosscheck = false"
)


@dataclasses.dataclass(frozen=True)
class Candidate:
    """One layout of the catalogue: ``count`` collars of a t x h (m) flat bar of ``grade``,
    evenly spaced, each pretensioned to ``pretension`` times its yield force f_y t h; its steel
    mass (kg)."""

    count: int
    t: float
    h: float
    grade: str
    mass: float
    pretension: float = 0.0  # fraction of the yield force

    @property
    def pretension_force(self) -> float:
        """N: the pretension fraction times the yield force f_y t h (none without collars)."""
        return self.pretension * self.fy * self.t * self.h if self.count else 0.0

    @property
    def fy(self) -> float:
        """Pa (no collars: inf, nothing to yield)."""
        return STEEL_GRADES.get(self.grade, math.inf)

    @property
    def section(self) -> tuple:
        """What the elastic screening runs it as (the grade does not change an elastic
        collar's motion; its pretension force does): (count, t, h), and the force (N) where
        pretensioned."""
        force = self.pretension_force
        return (self.count, self.t, self.h, force) if force else (self.count, self.t, self.h)

    @property
    def label(self) -> str:
        if self.count == 0:
            return "no collars"
        text = f"{self.count} x {self.t * 1e3:g} x {self.h * 1e3:g} mm {self.grade}"
        if not self.pretension:
            return text
        return (
            f"{text} pretensioned to {self.pretension_force / 1e3:.3g} kN "
            f"({self.pretension:.0%} of f_y t h)"
        )


@dataclasses.dataclass(frozen=True)
class Setup:
    """What a collar-layout study runs, read once from the validated study."""

    spec: Layout
    column: FemStudy  # without collars
    suite: tuple
    records: tuple
    intensity: np.ndarray  # each record's IM
    levels: np.ndarray  # the ladder with the design intensity
    design: float  # the design intensity (the hazard's at the design return period)
    design_level: int  # its index in levels
    hazard: HazardCurve  # in the layout's measure
    years: float
    target: float  # the target mean annual frequency of overturning (1/year)
    heights: dict  # count -> the collars' heights (m)
    candidates: tuple  # Candidate, lightest first


def collar_heights(height: float, count: int, end_distance: float) -> list[float]:
    """The heights (m) of ``count`` evenly spaced collars: the lowest and highest
    ``end_distance`` from the shaft's ends, the others evenly between; one at mid-height."""
    if count == 0:
        return []
    if count == 1:
        return [0.5 * height]
    return list(np.linspace(end_distance, height - end_distance, count))


def catalogue(spec: Layout, ring_length: float) -> tuple[Candidate, ...]:
    """Every layout of the catalogue (no collars once, if counts holds 0), lightest first (of
    equal mass: fewer collars, the lower grade, the lower pretension first)."""
    found = []
    for count in sorted(set(spec.counts)):
        if count == 0:
            found.append(Candidate(0, 0.0, 0.0, "", 0.0))
            continue
        for t, h in spec.sections:
            for grade in spec.grades:
                mass = count * t * h * ring_length * STEEL_DENSITY
                for pretension in sorted(set(spec.pretensions)):
                    found.append(Candidate(count, t, h, grade, mass, pretension))
    return tuple(sorted(found, key=lambda c: (c.mass, c.count, c.fy, c.pretension)))


def intensity_at_return_period(hazard, period: float, ladder) -> float:
    """The intensity whose annual frequency of exceedance is 1 / ``period`` on the hazard curve
    (log-log, bisection on ln IM); an InputError where the curve does not reach it within a
    factor 1000 of the ladder."""
    target = -math.log(period)
    low, high = math.log(min(ladder) / 1e3), math.log(max(ladder) * 1e3)
    f_low, f_high = (float(log_annual_frequency(hazard, np.array([x]))[0]) for x in (low, high))
    if not f_high <= target <= f_low:
        raise InputError(
            f"layout.design_return_period = {period:g} years: the hazard's annual frequencies "
            f"span {math.exp(f_high):.3g} to {math.exp(f_low):.3g} per year over "
            f"{math.exp(low):.3g} to {math.exp(high):.3g}: 1 / {period:g} lies outside"
        )
    for _ in range(200):
        mid = 0.5 * (low + high)
        if float(log_annual_frequency(hazard, np.array([mid]))[0]) > target:
            low = mid
        else:
            high = mid
    return math.exp(0.5 * (low + high))


def setup(study: Study) -> Setup:
    """The :class:`Setup` of a collar-layout study (an InputError naming the key where it cannot
    be run)."""
    source = study.source
    spec = study.spec.layout
    if spec is None:
        raise InputError(
            f"{source}: a collar-layout study needs a [layout] table (suite, a target, the "
            "catalogue)"
        )
    if study.spec.collar:
        raise InputError(
            f"{source}: a collar-layout study chooses the collars itself: leave [[collar]] out "
            "(the catalogue is [layout] counts, sections and grades)"
        )
    if study.spec.hazard is None:
        raise InputError(
            f"{source}: a collar-layout study needs the site's [hazard] (file, or k0 and k with "
            "intensity): its target is a risk at the site"
        )
    column, suite, records, _, intensity = suite_column(
        study, "layout", spec.suite, spec.intensity, None, least=3
    )
    block = column.rocking_block
    table = study.spec.hazard
    try:
        hazard = analysis.site_hazard(
            table, spec.intensity, None, _unit(spec.intensity), block, study.base
        )
    except InputError as exc:
        raise InputError(f"{source}: {str(exc).replace('fragility.', 'layout.')}") from None
    years = table.years
    design = intensity_at_return_period(hazard, spec.design_return_period, spec.ladder)
    ladder = analysis.ladder(spec.ladder[0], spec.ladder[1], spec.steps)
    if not ladder[0] <= design <= ladder[-1]:
        raise InputError(
            f"{source}: the design intensity, {design:.4g} {_unit(spec.intensity)} (the "
            f"hazard's at layout.design_return_period = {spec.design_return_period:g} years), "
            f"lies outside layout.ladder = {spec.ladder}: extend the ladder to reach it"
        )
    levels = np.unique(np.concatenate([ladder, [design]]))
    for entry, value in zip(suite, intensity):
        analysis.scales_for(levels, value, entry.name)  # a record without motion: refused
    if spec.target_frequency is not None:
        target = spec.target_frequency
    else:
        target = -math.log1p(-spec.target_probability) / years
    end = spec.end_distance if spec.end_distance is not None else column.height / 8.0
    if not 0.0 < end <= 0.5 * column.height:
        raise InputError(
            f"{source}: layout.end_distance = {end:g} m must be in (0, height / 2 = "
            f"{0.5 * column.height:g}] m"
        )
    heights = {n: collar_heights(column.height, n, end) for n in set(spec.counts)}
    ring = spec.ring_length if spec.ring_length is not None else math.pi * column.width
    return Setup(
        spec,
        column,
        tuple(suite),
        records,
        intensity,
        levels,
        design,
        int(np.argmin(np.abs(levels - design))),
        hazard,
        years,
        target,
        heights,
        catalogue(spec, ring),
    )


def layout_column(
    column: FemStudy,
    heights,
    t: float,
    h: float,
    fy: float,
    plastic: bool,
    pretension: float = 0.0,
):
    """The column with collars of t x h (m) at ``heights``, yield stress ``fy`` (Pa), each
    pretensioned to ``pretension`` (N)."""
    from ...core.collar import Collar

    collars = tuple(
        Collar(y=float(y), t=t, h=h, fy=fy, plastic=plastic, pretension=pretension) for y in heights
    )
    return dataclasses.replace(column, collars=collars)


def candidate_column(column: FemStudy, s: Setup, c: Candidate, plastic: bool = True):
    """The column with candidate ``c``'s collars (plastic: as the refinement and the FEM run
    them)."""
    return layout_column(
        column, s.heights[c.count], c.t, c.h, c.fy, plastic, pretension=c.pretension_force
    )


# f_y of the collars of the elastic screening: any value serves (an elastic collar's stress
# does not depend on it; a pretensioned one's at least its pretension over its area, as the
# collar requires); the runs' utilisations are read back as stresses with it
SCREEN_FY = STEEL_GRADES["S235"]


def screen_fy(t: float, h: float, force: float) -> float:
    """f_y (Pa) of the elastic screening's collars of t x h (m) pretensioned to ``force`` (N)."""
    return max(SCREEN_FY, force / (t * h)) if force else SCREEN_FY


def ladder_walk(case: dict, directory: str) -> dict:
    """One record up the ladder (``case["scales"]``, from level ``case["first"]``, else 0)
    to its first overturning: per level run, overturned, the collars' largest stress (Pa,
    read back from the utilisation at the collars' f_y; None without collars) and whether one
    fractured (plastic collars)."""
    study = study_of_case(case)
    fy = study.collars[0].fy if study.collars else math.nan
    start = time.perf_counter()
    walk = []
    for scale in case["scales"][case.get("first", 0) :]:
        run = multibody_runs(study, study.ground, [scale])[0]
        utilisation = run["collar_utilisation"]
        walk.append(
            {
                "overturned": run["overturned"],
                "stress": None if utilisation is None else utilisation * fy,
                "fractured": bool(run["collar_fractured"]),
            }
        )
        if run["overturned"]:
            break
    return {"walk": walk, "seconds": time.perf_counter() - start}


def screening_key(section: tuple, i: int) -> str:
    """The case key of the elastic walk of a count x section (x pretension force) and record
    ``i``."""
    count, t, h = section[:3]
    force = f"-P{section[3]:.6g}" if len(section) > 3 else ""
    return f"elastic-{count}x{t * 1e3:g}x{h * 1e3:g}{force}-{i:03d}"


def screening(s: Setup, out: Path, options: RunOptions) -> dict:
    """The elastic walks of every count x section and record: {section: [walk per record]}."""
    scales = [analysis.scales_for(s.levels, im).tolist() for im in s.intensity]
    cases = []
    sections = sorted({c.section for c in s.candidates})
    for section in sections:
        count, t, h = section[:3]
        force = section[3] if len(section) > 3 else 0.0
        one = layout_column(
            s.column, s.heights[count], t, h, screen_fy(t, h, force), False, pretension=force
        )
        for i, record in enumerate(s.records):
            duration = record.end_time + FREE_TIME_P / one.rocking_block.p
            cases.append(
                case_of(
                    dataclasses.replace(one, ground=record, duration=duration),
                    key=screening_key(section, i),
                    section=list(section),
                    record=i,
                    scales=scales[i],
                    cost=len(scales[i]),
                )
            )
    results = run_cases(
        ladder_walk, cases, out, run_options=options, stage="screening (elastic collars)"
    )
    walks: dict = {section: [None] * len(s.records) for section in sections}
    for case in cases:
        walks[tuple(case["section"])][case["record"]] = results[case["key"]]["walk"]
    seconds = float(sum(results[c["key"]]["seconds"] for c in cases))
    return {
        "walks": walks,
        "seconds": seconds,
        "runs": sum(len(w["walk"]) for w in results.values()),
    }


def first_levels(walk: list[dict], fy: float) -> tuple[int | None, int | None]:
    """(first overturning level, first level whose collars reached ``fy``) of an elastic walk,
    None where none."""
    overturn = next((j for j, run in enumerate(walk) if run["overturned"]), None)
    yielded = next(
        (j for j, run in enumerate(walk) if run["stress"] is not None and run["stress"] >= fy),
        None,
    )
    return overturn, yielded


def record_bounds(walk: list[dict], fy: float) -> dict:
    """A record's overturning capacity (a level index) with collars of yield stress ``fy``:
    ``exact`` where the elastic walk settles it (it overturned before they yielded, or it
    reached the top with neither), else open: between the first yield, ``from`` (where the
    plastic walk starts), and never."""
    overturn, yielded = first_levels(walk, fy)
    if yielded is None or (overturn is not None and overturn < yielded):
        return {"exact": overturn}  # None: never overturned up to the top
    return {"exact": "open", "from": yielded}


def frequency_of(capacities: list[int | None], s: Setup, band: bool = False) -> dict:
    """lambda of overturning from per-record capacities (level indices; None: never up to the
    ladder's top, censored there): the IDA fit's risk at the site; with fewer than two records
    overturning, no fit: the bound lambda <= lambda_IM(lowest capacity, or the ladder's top)."""
    levels = s.levels
    exact = [c for c in capacities if c is not None]
    if len(exact) < 2:
        return _bound(capacities, s, f"{len(exact)} of {len(capacities)} records overturned")
    capacity = np.array([levels[c] if c is not None else levels[-1] for c in capacities])
    censored = np.array([c is None for c in capacities])
    spec = s.spec
    try:
        fit = fits.fit_capacities(capacity, censored=censored)
    except InputError as exc:  # no dispersion: every record overturned at one level
        return _bound(capacities, s, str(exc).removeprefix("capacities: "))
    if not band:
        value = risk.limit_state_frequency(s.hazard, fit.median, fit.beta).value
        return {"frequency": value, "bound": False, "median": fit.median, "beta": fit.beta}
    found = fits.bootstrap_capacities(
        capacity,
        censored=censored,
        draws=spec.bootstrap,
        seed=spec.seed,
        level=spec.confidence,
        at=[s.design],
    )
    entry = analysis.risk_entry(found, s.hazard, s.years, levels)
    return {
        "frequency": entry["frequency"],
        "bound": False,
        "median": found.fit.median,
        "beta": found.fit.beta,
        "risk": entry,
        "probability_at_design": float(found.fit.probability(s.design)),
        "probability_at_design_interval": [float(found.low[0]), float(found.high[0])],
    }


def _bound(capacities: list[int | None], s: Setup, why: str) -> dict:
    """lambda <= lambda_IM(the lowest capacity, or the ladder's top): P[overturn | im] <= 1
    above it, and no record overturned below it; for capacities that hold no fit."""
    exact = [c for c in capacities if c is not None]
    x = s.levels[min(exact)] if exact else s.levels[-1]
    return {
        "frequency": float(annual_frequency(s.hazard, np.array([x]))[0]),
        "bound": True,
        "why": f"{why}: no lognormal fit; lambda is at most the hazard's frequency at the "
        f"lowest capacity, {x:.3g}",
    }


def bracket(candidate: Candidate, walks: dict, s: Setup) -> dict:
    """The layout's lambda bracket from the elastic screening (:mod:`module notes <.runner>`)
    and the records the plastic refinement must run (``open``)."""
    per = [record_bounds(walk, candidate.fy) for walk in walks[candidate.section]]
    open_records = [i for i, b in enumerate(per) if b["exact"] == "open"]
    upper = [b["from"] if b["exact"] == "open" else b["exact"] for b in per]
    lower = [None if b["exact"] == "open" else b["exact"] for b in per]
    high = frequency_of(upper, s)
    low = frequency_of(lower, s) if open_records else high
    return {"upper": high, "lower": low, "open": open_records, "records": per}


def refine(
    candidates: list[Candidate], brackets: dict, s: Setup, out, options, full: bool = False
) -> dict:
    """The plastic walks of the open records of ``candidates`` from their first yield
    (``full``: of every record from the ladder's foot): {label: [walk or None]}."""
    scales = [analysis.scales_for(s.levels, im).tolist() for im in s.intensity]
    cases = []
    for c in candidates:
        one = candidate_column(s.column, s, c)
        runs = range(len(s.records)) if full else brackets[c.label]["open"]
        for i in runs:
            record = s.records[i]
            duration = record.end_time + FREE_TIME_P / one.rocking_block.p
            first = 0 if full else brackets[c.label]["records"][i]["from"]
            cases.append(
                case_of(
                    dataclasses.replace(one, ground=record, duration=duration),
                    key=refinement_key(c, i),
                    label=c.label,
                    record=i,
                    scales=scales[i],
                    first=first,
                    cost=len(scales[i]) - first,
                )
            )
    if not cases:
        return {c.label: [None] * len(s.records) for c in candidates}
    results = run_cases(
        ladder_walk, cases, out, run_options=options, stage="refinement (plastic collars)"
    )
    walks: dict[str, list[dict | None]] = {c.label: [None] * len(s.records) for c in candidates}
    for case in cases:
        walks[case["label"]][case["record"]] = {
            "first": case["first"],
            "walk": results[case["key"]]["walk"],
            "seconds": results[case["key"]]["seconds"],
        }
    return walks


def refinement_key(c: Candidate, i: int) -> str:
    """The case key of the plastic walk of layout ``c`` and record ``i``."""
    if c.count == 0:
        return f"plastic-no-collars-{i:03d}"
    force = f"-P{c.pretension:g}" if c.pretension else ""
    return f"plastic-{c.count}x{c.t * 1e3:g}x{c.h * 1e3:g}-{c.grade}{force}-{i:03d}"


def plastic_capacities(candidate: Candidate, found: dict, plastic: list, s: Setup):
    """The layout's capacities (level indices, None: never) with plastic collars (a record's
    plastic walk where it was run, else the screening's exact capacity), and the records
    whose collars fracture at the design level (True/False; None where the run overturned
    below it)."""
    capacities, fractured = [], []
    d = s.design_level
    for i, b in enumerate(found["records"]):
        if plastic[i] is None:
            capacities.append(b["exact"])
            fractured.append(False if b["exact"] is None or b["exact"] >= d else None)
            continue
        run = plastic[i]
        walk, first = run["walk"], run["first"]
        over = next((first + j for j, r in enumerate(walk) if r["overturned"]), None)
        capacities.append(over)
        if d < first:
            fractured.append(False)  # elastic up to the design level: no yield, no fracture
        elif d - first < len(walk):
            fractured.append(walk[d - first]["fractured"])
        else:
            fractured.append(None)  # overturned below the design level
    return capacities, fractured


def decide(s: Setup, screened: dict, out: Path, options: RunOptions) -> dict:
    """Every layout, the lightest first, until one meets the target: its lambda from the
    elastic screening where no collar yields before the column overturns (exact: a plastic
    collar follows the elastic one until it yields), else from the plastic refinement of its
    open records, up to [layout] shortlist refined layouts (:func:`judge`); the chosen layout,
    the first that meets the target with every layout before it refined and failing or
    screened to miss (:func:`screened_miss`). The screening's range (:func:`bracket`) is
    shown, never used to decide: a lognormal fit's lambda is not monotonic in the capacities
    (a censored record changes its dispersion). :func:`next_meeting` goes on from a layout
    the FEM does not confirm."""
    brackets = {c.label: bracket(c, screened["walks"], s) for c in s.candidates}
    rows = []
    for c in s.candidates:
        b = brackets[c.label]
        rows.append(
            {
                "label": c.label,
                "count": c.count,
                "t": c.t,
                "h": c.h,
                "grade": c.grade,
                "fy": c.fy if c.count else None,
                "pretension": c.pretension,  # fraction of the yield force f_y t h
                "pretension_force": c.pretension_force,  # N
                "mass": c.mass,
                "heights": s.heights[c.count],
                "upper": b["upper"]["frequency"],
                "lower": b["lower"]["frequency"],
                "upper_is_bound": b["upper"]["bound"],
                "open_records": len(b["open"]),
            }
        )
    decided = {
        "rows": rows,
        "brackets": brackets,
        "chosen": None,
        "refined": 0,
        "plastic_seconds": 0.0,
        "plastic_runs": 0,
    }
    decided["chosen"] = next_meeting(s, decided, -1, out, options)
    beyond = "heavier than the chosen layout" if decided["chosen"] else NOT_JUDGED
    for row in rows:
        row.setdefault("decision", beyond)
        row.setdefault("decided_by", None)
    return decided


NOT_JUDGED = "not judged"  # after a layout that meets the target but is not chosen


def next_meeting(
    s: Setup,
    decided: dict,
    after: int,
    out: Path,
    options: RunOptions,
    skip=None,
):
    """The first layout after row ``after`` (an index of the catalogue, lightest first) that
    meets the target by the multibody model (:func:`judge`), or None; each row on the way
    judged ("fails", "not refined" beyond [layout] shortlist refined layouts in this search),
    the one found "chosen". A layout is chosen only where no row before it in the search was
    left "not refined" (one the screening cannot rule out): else it is NOT_CHOSEN, with why,
    and None is returned. ``skip(candidate)``: why the search passes a layout over without
    judging it (the FEM attempts' step to more capacity, :func:`capacity_skip`), or None."""
    refined = 0
    unrefined: list[dict] = []
    for index in range(after + 1, len(s.candidates)):
        row = decided["rows"][index]
        row.pop("decision", None)
        why = skip(s.candidates[index]) if skip is not None else None
        if why:
            row.update(decision=SKIPPED, why=why, decided_by=None)
            continue
        if judge(s, s.candidates[index], row, decided, refined, out, options):
            refined += 1
        if row["decision"] == "not refined":
            unrefined.append(row)
        if row["decision"] == "chosen":
            if not unrefined:
                return row
            names = ", ".join(r["label"] for r in unrefined)
            row["decision"] = NOT_CHOSEN
            row["why"] = (
                f"meets the target by the multibody model (lambda = {row['frequency']:.4g} per "
                f"year), but {_unrefined(len(unrefined), 'lighter ')} ({names}; "
                f"layout.shortlist = {s.spec.shortlist}): raise the shortlist to decide "
                f"{_them(len(unrefined))}"
            )
            return None
    return None


def _unrefined(n: int, which: str = "") -> str:
    """``n`` layouts left unrefined, in words: "1 lighter layout that the screening cannot
    rule out was not refined", or "2 lighter layouts ... were"."""
    return f"{n} {which}{_layouts(n)} that the screening cannot rule out {_were(n)} not refined"


def _layouts(n: int) -> str:
    return "layout" if n == 1 else "layouts"


def _were(n: int) -> str:
    return "was" if n == 1 else "were"


def _them(n: int) -> str:
    return "it" if n == 1 else "them"


NOT_CHOSEN = "meets the target, not chosen"
SKIPPED = "skipped by the FEM attempts"
# The screening's fast path against the full plastic runs of the same layout, no collar
# yielding (docs/studies.md, "Collar layout"): 8 of 10 records overturn first at the same
# level, 2 one level lower; a miss the screening shows must outlast a scatter of this many
# levels in every record's capacity
SCREENING_SCATTER_LEVELS = 1


def shifted(capacities: list[int | None], levels: int, by: int) -> list[int | None]:
    """Each capacity (a level index; None: never up to the top) ``by`` levels higher, past
    the top of ``levels`` levels: never; ``by`` < 0 lower, a record that never overturned
    then overturning at the top level, none below the ladder's foot."""
    if by < 0:
        return [max(0, (levels if k is None else k) + by) for k in capacities]
    return [None if k is None or k + by >= levels else k + by for k in capacities]


def screened_meet(b: dict, s: Setup) -> dict | None:
    """Where the screening alone shows that a layout meets the target: its lambda and, with
    every record's overturning :data:`SCREENING_SCATTER_LEVELS` levels lower (the fast path
    overturns at the plastic run's level or one above it: a screened meet must outlast the
    scatter downward, as a screened miss must upward), both at or below the target; else
    None. Only for a layout none of whose collars yields before the column overturns."""
    fits = _screened_fits(b, s, -SCREENING_SCATTER_LEVELS)
    if fits is None or max(fits) > s.target:
        return None
    return {"frequency": fits[0], "shifted": fits[1]}


def screened_miss(b: dict, s: Setup) -> dict | None:
    """Where the screening alone shows that a layout misses the target: {"frequency", the
    screening's lambda, "shifted", with every record's overturning
    :data:`SCREENING_SCATTER_LEVELS` levels higher}, both fits (not bounds) above the target;
    else None. Only a layout none of whose collars yields before the column overturns, in
    any record, has its capacities from the screening (a plastic collar is the elastic one
    until it yields: the same model), up to the fast path's scatter, which the shift covers.
    A layout with open records never: elastic collars carry forces a plastic one cannot
    (holding the halves more, which tends to lower the screening's risk), but a yielding
    collar also dissipates energy, so the bias has no sure sign; and the lognormal fit's
    lambda is not monotonic in the capacities (the shipped run's 1 x 10 x 80 mm S235:
    1.16e-3 per year with its open records never overturning, 1.03e-3 with them at their
    first yield), so no capacity of its open records bounds its lambda: it is refined."""
    fits = _screened_fits(b, s, SCREENING_SCATTER_LEVELS)
    if fits is None or min(fits) <= s.target:
        return None
    return {"frequency": fits[0], "shifted": fits[1]}


def _screened_fits(b: dict, s: Setup, by: int) -> tuple[float, float] | None:
    """A layout's screened lambda and the one with every record's overturning ``by`` ladder
    levels higher (lower where negative: :func:`shifted`), both fits; None where a record is
    open or either is only a bound."""
    if b["open"]:
        return None
    exact = [r["exact"] for r in b["records"]]
    one = frequency_of(exact, s)
    moved = frequency_of(shifted(exact, len(s.levels), by), s)
    if one["bound"] or moved["bound"]:
        return None
    return one["frequency"], moved["frequency"]


def judge(s: Setup, c: Candidate, row: dict, decided: dict, refined: int, out, options) -> bool:
    """Decide layout ``c``'s ``row`` (its frequency, the records that fracture a collar at the
    design intensity, "fails", "not refined" or "chosen", with why and ``decided_by``, the
    model: "screening" or "refinement"), refining it with plastic collars unless ``refined``
    has reached [layout] shortlist: its open records from their first yield, or, where it has
    none and the screening neither meets the target nor misses it by more than its scatter
    (:func:`screened_miss`), every record over the whole ladder; whether it was refined."""
    spec = s.spec
    b = decided["brackets"][c.label]
    n = len(s.records)
    miss = screened_miss(b, s)
    screened = None
    if not b["open"]:
        screened = frequency_of([r["exact"] for r in b["records"]], s)
    lam = None if screened is None else screened["frequency"]  # the screening's, all exact
    meet = screened_meet(b, s)
    # neither a sure miss nor a sure meet by the screening: the plastic runs, whole ladder
    full = lam is not None and miss is None and meet is None
    plastic: list = [None] * n
    if b["open"] or full:
        if refined >= spec.shortlist:
            row["decision"] = "not refined"
            row["decided_by"] = None
            reason = (
                f"its collars yield before it overturns in {len(b['open'])} records, which the "
                "screening cannot decide"
                if b["open"]
                else f"the screening's lambda, {lam:.4g} per year, {_narrowly(lam, s)}"
            )
            row["why"] = f"not refined, beyond the shortlist of {spec.shortlist} ({reason})"
            return False
        decided["refined"] += 1
        plastic = refine([c], decided["brackets"], s, out, options, full=full)[c.label]
    for run in plastic:
        if run is not None:
            decided["plastic_seconds"] += run["seconds"]
            decided["plastic_runs"] += len(run["walk"])
    capacities, fractured = plastic_capacities(c, b, plastic, s)
    frequency = frequency_of(capacities, s, band=True)
    counted = [f for f in fractured if f is not None]
    share = sum(counted) / len(fractured)
    by = "refinement" if (b["open"] or full) else "screening"
    row.update(
        frequency=frequency["frequency"],
        frequency_entry=frequency,
        capacities=[None if k is None else float(s.levels[k]) for k in capacities],
        fractured_at_design=fractured,
        fracture_share=share,
        decided_by=by,
    )
    if b["open"]:
        how = f"with plastic collars (refined: its collars yield first in {len(b['open'])} records)"
    elif full:
        how = (
            "with plastic collars over the whole ladder (refined: the screening's "
            f"{lam:.4g} {_narrowly(lam, s)})"
        )
    else:
        how = "by the screening (no collar yields before the column overturns)"
        if meet is not None:
            how += (
                f"; {meet['shifted']:.4g} with every record's overturning one ladder level "
                "lower (the screening's scatter)"
            )
    if frequency["frequency"] > s.target:
        row["decision"] = "fails"
        row["why"] = (
            f"lambda = {frequency['frequency']:.4g} per year {how}, above the target {s.target:.4g}"
        )
        if miss is not None:
            row["why"] += (
                f", and {miss['shifted']:.4g} with every record's overturning one ladder level "
                "higher (the screening's scatter)"
            )
    elif share > spec.fracture_fraction:
        row["decision"] = "fails"
        row["why"] = (
            f"{sum(counted)} of {len(fractured)} records fracture a collar at the design "
            f"intensity with plastic collars (at most {spec.fracture_fraction:.0%} allowed)"
        )
    else:
        row["decision"] = "chosen"
    return bool(b["open"] or full)


def _narrowly(lam: float | None, s: Setup) -> str:
    """Why a screened layout (with no open record: ``lam``, its screened lambda, is known) is
    refined over the whole ladder, in words."""
    assert lam is not None
    side = "misses" if lam > s.target else "meets"
    return f"{side} the target by less than its scatter of one ladder level"


NOT_CONFIRMED = "not confirmed by the FEM"


def fem_attempts(s: Setup, decided: dict, out: Path, options: RunOptions) -> dict:
    """FEM-check the chosen layout (:func:`fem_stripe`) and, while its stripe does not confirm
    it (contradicts, or undecided: docs/studies.md, "Collar layout"), the next heavier layout
    that meets the target by the multibody model (:func:`next_meeting`; where no collar
    yielded in the stripe, passing over the layouts :func:`capacity_skip` names), up to
    [layout] fem_attempts layouts. The first one confirmed is chosen; where none is, the attempt
    :func:`recommended` is. ``decided`` is updated: its chosen row, each other attempt's
    decision NOT_CONFIRMED with why. Returns the attempts (label, mass, frequency, stripe),
    the first choice, the confirmed layout (or None), why the attempts stopped and why the
    chosen one is."""
    row = decided["chosen"]
    first = row["label"]
    rows = decided["rows"]
    attempts: list[dict] = []
    stopped = ""
    while True:
        stripe = fem_stripe(s, row, out, options, attempt=len(attempts))
        attempts.append({"row": row, "fem": stripe})
        if stripe["agreement"] == "confirms":
            stopped = "confirmed"
            break
        if len(attempts) >= s.spec.fem_attempts:
            stopped = f"layout.fem_attempts = {s.spec.fem_attempts} reached"
            break
        index = next(i for i, r in enumerate(rows) if r is row)
        base = s.candidates[index]
        skip = None if stripe_yielded(stripe) else functools.partial(capacity_skip, base)
        row = next_meeting(s, decided, index, out, options, skip=skip)
        if row is None:
            stopped = search_stopped(s, decided, index, base if skip else None)
            break
    confirmed = attempts[-1] if stopped == "confirmed" else None
    final, why = (
        (confirmed, "the first layout the FEM confirms") if confirmed else recommended(attempts)
    )
    for a in attempts:
        r = a["row"]
        if a is final:
            r["decision"] = "chosen"
            r.pop("why", None)
            continue
        r["decision"] = NOT_CONFIRMED
        r["why"] = (
            f"meets the target by the multibody model (lambda = {r['frequency']:.4g} per year), "
            f"but its FEM stripe at the design intensity {AGREEMENT_WORDS[a['fem']['agreement']]}"
            f" it ({stripe_differences(a['fem'])})"
        )
    decided["chosen"] = final["row"]
    return {
        "first": first,
        "confirmed": None if confirmed is None else confirmed["row"]["label"],
        "chosen": final["row"]["label"],
        "allowed": s.spec.fem_attempts,
        "stopped": stopped,
        # the layouts the attempts passed over, in the catalogue's order, with why
        "skipped": [
            {"label": r["label"], "why": r["why"]} for r in rows if r["decision"] == SKIPPED
        ],
        "why": why,
        "attempts": [
            {
                "label": a["row"]["label"],
                "mass": a["row"]["mass"],
                "frequency": a["row"]["frequency"],
                "agreement": a["fem"]["agreement"],
                "fem": a["fem"],
            }
            for a in attempts
        ],
        "fem": final["fem"],
    }


def stripe_yielded(stripe: dict) -> bool:
    """Whether a collar yielded (utilisation 1: rigid/design.py's never_yields) or fractured in
    any FEM run of a stripe."""
    return any(stripe["fractured"]) or any(
        r["collar_utilisation"] is not None and r["collar_utilisation"] >= 1.0
        for r in stripe["runs"]
    )


def capacity_skip(base: Candidate, c: Candidate) -> str | None:
    """Why the FEM attempt after ``base`` (its stripe did not confirm it, and no collar yielded
    in it) passes layout ``c`` over, or None where ``c`` adds capacity the stripe could use:
    more collars or a larger bar (count, t and h each at least ``base``'s, one of them
    more). The same bars in another grade are passed over: a plastic collar is the elastic
    one until it yields, so collars that stayed below f_y in every run stay below a higher
    one (the catalogue puts the higher grades after) and the runs are the stripe's."""
    bars = (c.count, c.t, c.h)
    if bars + (c.pretension,) == (base.count, base.t, base.h, base.pretension):
        return (
            f"{c.grade} skipped: no collar yielded in the FEM stripe of {base.label}, so the "
            "grade cannot change its runs"
        )
    if bars != (base.count, base.t, base.h) and all(
        x >= y for x, y in zip(bars, (base.count, base.t, base.h))
    ):
        return None
    if c.count < base.count:
        less = f"fewer collars than {base.label}"
    elif c.t < base.t or c.h < base.h:
        less = f"a thinner or lower bar than {base.label}'s"
    else:
        less = f"the bars of {base.label}, pretensioned otherwise"
    return (
        f"skipped: {less}, in whose FEM stripe no collar yielded (the attempts step to more "
        "collars or a larger bar)"
    )


def search_stopped(s: Setup, decided: dict, index: int, base: Candidate | None) -> str:
    """Why a FEM attempts' search after row ``index`` found no layout (``base``: the layout
    whose capacity it had to exceed, None where it went in the catalogue's order)."""
    later = decided["rows"][index + 1 :]
    if any(r["decision"] == NOT_CHOSEN for r in later):
        return (
            "a heavier layout meets the target by the multibody model, but lighter ones the "
            f"screening cannot rule out were not refined (layout.shortlist = {s.spec.shortlist})"
        )
    if base is not None:
        return (
            "no heavier layout of the catalogue with more collars or a larger bar than "
            f"{base.label} meets the target by the multibody model"
        )
    return "no heavier layout of the catalogue meets the target by the multibody model"


AGREEMENT_WORDS = {
    "confirms": "confirms",
    "contradicts": "contradicts",
    "undecided": "neither confirms nor contradicts",
}


def stripe_differences(fem: dict) -> str:
    """How a FEM stripe differs from the multibody runs, in words."""
    n = len(fem["overturned"])
    differ = len(fem["fem_only"]) + len(fem["multibody_only"])
    text = (
        f"{differ} of {n} records differ: FEM only {', '.join(fem['fem_only']) or 'none'}, "
        f"multibody only {', '.join(fem['multibody_only']) or 'none'}; "
        f"McNemar p = {fem['mcnemar_p']:.2g}"
    )
    if fem["fracture_share"] > fem["fracture_allowed"]:
        text += (
            f"; {fem['fracture_share']:.0%} of the records fracture a collar, above the "
            f"{fem['fracture_allowed']:.0%} allowed"
        )
    return text


def recommended(attempts: list[dict]) -> tuple[dict, str]:
    """Of FEM-checked layouts none of which the FEM confirms, the one recommended and why: the
    FEM's own evidence first, i.e. collars that fracture within the allowance, then the fewest
    records the FEM overturns at the design intensity, then the least steel (more steel that
    does not lower the FEM's overturnings buys nothing the FEM can show)."""

    def rank(a: dict) -> tuple:
        fem = a["fem"]
        beyond = fem["fracture_share"] > fem["fracture_allowed"]
        return (beyond, sum(fem["overturned"]), a["row"]["mass"])

    best = min(attempts, key=rank)
    fem = best["fem"]
    fewest = sum(fem["overturned"])
    n = len(fem["overturned"])
    ties = [a for a in attempts if rank(a)[:2] == rank(best)[:2]]
    same_mass = [a for a in ties if a["row"]["mass"] == best["row"]["mass"]]
    why = f"its FEM stripe overturns {fewest} of {n} records at the design intensity, " + (
        "the fewest of the attempts"
        if len(ties) == 1
        else "as few as any attempt, with the least steel"
        if len(same_mass) == 1
        else "as few as any attempt, with the least steel, the first in the catalogue's order "
        "of those of its mass"
    )
    if rank(best)[0]:
        why += ", although its collars fracture in more records than allowed, as in every attempt"
    return best, why


def fem_key(attempt: int, i: int) -> str:
    """The case key of the FEM run of record ``i`` in FEM attempt ``attempt`` (0: the first
    choice's, saved as before attempts existed)."""
    return f"fem-{i:03d}" if attempt == 0 else f"fem{attempt + 1}-{i:03d}"


def fem_stripe(s: Setup, chosen: dict, out: Path, options: RunOptions, attempt: int = 0) -> dict:
    """The layout's FEM runs of every record at the design intensity (settled-stop, plastic
    collars), against its multibody stripe there; the runs saved under
    :func:`fem_key` of ``attempt``."""
    from ..fragility.runner import _fem_study, _interval, fem_cases

    one = layout_column(
        s.column,
        chosen["heights"],
        chosen["t"],
        chosen["h"],
        chosen["fy"],
        plastic=True,
        pretension=chosen["pretension_force"],
    )
    interval = _interval(one, s.records)
    cases = []
    for i, record in enumerate(s.records):
        scale = float(analysis.scales_for(np.array([s.design]), s.intensity[i])[0])
        study = _fem_study(one, record, scale, interval)
        cases.append(
            case_of(study, cost=study.duration, key=fem_key(attempt, i), record=i, level=0)
        )
    stage = "FEM" if attempt == 0 else f"FEM, attempt {attempt + 1} ({chosen['label']})"
    results = run_cases(fem_cases, cases, out, run_options=options, batched=True, stage=stage)
    check_fem_results(results, out)
    runs = [results[c["key"]] for c in cases]
    overturned = [bool(r["overturned"]) for r in runs]
    fractured = [bool(r.get("collar_fractured")) for r in runs]
    n = len(runs)
    k = sum(overturned)
    interval_ = analysis.clopper_pearson(np.array([k]), n, s.spec.confidence)[0].tolist()
    multibody = chosen["frequency_entry"]
    p_mb = multibody.get("probability_at_design")
    band = multibody.get("probability_at_design_interval")
    fracture_share = sum(fractured) / n
    # record by record: the multibody's IDA overturns a record at the design intensity where
    # its capacity (first overturning on the ladder) is at or below it
    stripe = [c is not None and c <= s.design for c in chosen["capacities"]]
    agreement = stripe_agreement(overturned, stripe, s.spec.confidence)
    if fracture_share > s.spec.fracture_fraction:
        agreement = "contradicts"  # the FEM fractures collars the multibody model spared
    fem_only = [s.suite[i].name for i in range(n) if overturned[i] and not stripe[i]]
    multibody_only = [s.suite[i].name for i in range(n) if stripe[i] and not overturned[i]]
    return {
        "overturned": overturned,
        "fractured": fractured,
        "fraction": k / n,
        "fraction_interval": interval_,
        "multibody_probability": p_mb,
        "multibody_probability_interval": band,
        "multibody_overturned": stripe,
        "mcnemar_p": mcnemar_p(len(fem_only), len(multibody_only)),
        # the fit's probability in the FEM fraction's interval (the fit, not the runs, compared)
        "fit_in_interval": None if p_mb is None else bool(interval_[0] <= p_mb <= interval_[1]),
        "fem_only": fem_only,
        "multibody_only": multibody_only,
        "fracture_share": fracture_share,
        "fracture_allowed": s.spec.fracture_fraction,
        "agreement": agreement,
        "confirmed": agreement == "confirms",
        "seconds": float(sum(r.get("fem_seconds", 0.0) for r in runs)),
        # an overturned run's peak is where it stopped (a convention, not a rotation): none
        "runs": [
            {
                "overturned": r["overturned"],
                "overturned_at": r.get("overturned_at"),
                "peak_ratio": None if r["overturned"] else r.get("peak_ratio"),
                "collar_utilisation": r.get("collar_utilisation"),
            }
            for r in runs
        ],
    }


def mcnemar_p(b: int, c: int) -> float:
    """Exact two-sided McNemar p-value of ``b`` records that only one model overturns against
    ``c`` that only the other does: 2 P[Bin(b + c, 1/2) <= min(b, c)], at most 1 (McNemar
    1947; the exact binomial form); 1 where no record differs."""
    n = b + c
    tail = sum(math.comb(n, j) for j in range(min(b, c) + 1)) / 2.0**n
    return min(1.0, 2.0 * tail)


def stripe_agreement(fem: list[bool], multibody: list[bool], confidence: float) -> str:
    """Whether the FEM stripe at the design intensity (each record overturned or not)
    confirms the multibody runs the choice rests on (the same records overturned at the
    design intensity in its IDA), record by record: "confirms" where every record agrees;
    "contradicts" where the records that differ lean to one model beyond chance (exact
    McNemar p-value below 1 - ``confidence``); "undecided" otherwise (some records differ,
    too few to say which model the column follows)."""
    b = sum(f and not m for f, m in zip(fem, multibody))
    c = sum(m and not f for f, m in zip(fem, multibody))
    if b + c == 0:
        return "confirms"
    return "contradicts" if mcnemar_p(b, c) < 1.0 - confidence else "undecided"


CROSSCHECK_FILE = "chosen-crosscheck.toml"
# the study file's tables a cross-check of the chosen layout keeps (the column as studied, on
# the mesh and with the run settings of the study's FEM runs)
KEPT_TABLES = ("column", "stone", "base", "contact", "rigid", "mesh", "run")


def median_record(capacities: list) -> int:
    """The index of the record whose capacity is the suite's median (upper median; None, never
    overturned on the ladder, counts as the highest)."""
    order = sorted(
        range(len(capacities)),
        key=lambda i: math.inf if capacities[i] is None else capacities[i],
    )
    return order[len(order) // 2]


def crosscheck_study(study: Study, s: Setup, chosen: dict, i: int) -> tuple[str, str]:
    """The text of a cross-check study file of the chosen layout (plastic collars) under
    record ``i`` (the one whose capacity with the chosen collars is the suite's median) scaled
    to the design intensity, on the study's column, mesh and run settings (the cross-check's
    defaults where the study gives none: its replicas), and the record's name. A [ground]
    record reads a two-column file in m/s^2: the scale then carries the suite's units too (the
    file's peak as the suite read it over its peak read in m/s^2)."""
    from ...core.ground import read_two_column
    from ...core.suite import _toml_value

    entry = s.suite[i]
    units = 1.0
    if entry.path.suffix.lower() not in (".at2", ".asc") and not is_esm(entry.path):
        raw = read_two_column(entry.path, units="m/s2")
        units = entry.record.peak_acceleration / raw.peak_acceleration
    scale = units * entry.scale * s.design / float(s.intensity[i])
    lines = [
        f"# The cross-check of the layout chosen by the collar-layout study {s.column.name!r}:",
        f"# {chosen['label']}, under {entry.name} (the record of median capacity) scaled to "
        f"the design intensity {s.design:.4g}.",
        "",
        "[study]",
        f"name = {_toml_value(s.column.name + '-chosen')}",
        f"kind = {_toml_value(kind_of_package('crosscheck'))}",
    ]
    for table in KEPT_TABLES:
        values = study.data.get(table)
        if values:
            lines += ["", f"[{table}]"]
            lines += [f"{k} = {_toml_value(v)}" for k, v in values.items()]
    for y in chosen["heights"]:
        lines += [
            "",
            "[[collar]]",
            f"y = {_toml_value(float(y))}",
            f"t = {_toml_value(chosen['t'])}",
            f"h = {_toml_value(chosen['h'])}",
            f"fy = {_toml_value(chosen['fy'])}",
            "plastic = true",
            f"pretension = {_toml_value(float(chosen['pretension_force']))}",
        ]
    lines += [
        "",
        "[ground]",
        'pulse = "record"',
        f"record = {_toml_value(str(entry.path))}",
        f"scale = {_toml_value(scale)}",
    ]
    return "\n".join(lines) + "\n", entry.name


CROSSCHECK_DIR = "chosen-crosscheck"  # the sub-study's folder in the study's output
CROSSCHECK_STAGE = 3  # its stages follow the screening's, the refinement's and the FEM stripe's
# the cross-check's answers the report quotes, in its order
CROSSCHECK_ANSWERS = (
    "stays_up",
    "rigid_assumption_ok",
    "collars_yield",
    "collars_hold",
    "toe_crushes",
)


def crosscheck_of(text: str, path: Path) -> Study:
    """The cross-check :class:`Study` of a study file's ``text`` as if read from ``path``
    (:func:`studies.study.load` without the file: the estimate builds it before it exists)."""
    import tomllib

    from .. import schema
    from ..study import with_kind_defaults

    data = with_kind_defaults(tomllib.loads(text))
    return Study(path, text.encode(), data, schema.parse(data, str(path)))


def run_crosscheck(study: Study, s: Setup, chosen: dict, out: Path, options: RunOptions) -> dict:
    """Run (or resume) the chosen layout's cross-check into ``out/chosen-crosscheck`` as a study
    of its own (its cases saved there, its inputs on record, its report), from the study file
    ``out/chosen-crosscheck.toml``; its headline answers (:func:`crosscheck_section`), or why it
    gave none (a FEM run of it the guard refuses, or a study the cross-check kind refuses: a
    record scaled below the column's uplift, ...)."""
    from ..driver import write_ground_motion
    from ..guard import UnreliableRun
    from ..kinds import KINDS
    from ..output import record_inputs

    i = median_record(chosen["capacities"])
    text, record = crosscheck_study(study, s, chosen, i)
    path = out / CROSSCHECK_FILE
    path.write_text(text)
    folder = out / CROSSCHECK_DIR
    head = {
        "file": CROSSCHECK_FILE,
        "folder": CROSSCHECK_DIR,
        "record": record,
        "record_index": i,
        "refused": None,
    }
    started = time.time()
    try:
        sub = crosscheck_of(text, path)
        module = KINDS[sub.kind].module()
        module.run(sub, folder, options)
    except (UnreliableRun, InputError) as exc:
        return {**head, "refused": str(exc)}
    record_inputs(folder, sub, started)
    write_ground_motion(folder, sub.fem)
    module.write_report(folder)
    found = json.loads((folder / "summary.json").read_text())
    inputs = json.loads((folder / "inputs.json").read_text())
    # the collars it ran, as its inputs on record say (SI: m, Pa, N)
    collars = [
        {k: c[k] for k in ("y", "t", "h", "fy", "plastic", "pretension")}
        for c in inputs.get("collar", [])
    ]
    return {
        **head,
        "report": f"{CROSSCHECK_DIR}/index.html",
        "collars": collars,
        **crosscheck_section(found),
    }


def _replica_peaks(fem: dict) -> list[float] | None:
    """The FEM replicas' peak rotations (rad, the larger of the two halves'), None where a
    replica overturned (its peak is where it stopped: the band is then not given)."""
    bands = fem.get("bands", {})
    left, right = bands.get("max_abs_theta_left"), bands.get("max_abs_theta_right")
    if not isinstance(left, dict) or not isinstance(right, dict):
        return None
    peaks = [max(a, b) for a, b in zip(left["values"], right["values"]) if None not in (a, b)]
    return peaks if len(peaks) == len(left["values"]) and peaks else None


def crosscheck_section(found: dict) -> dict:
    """What the collar-layout report quotes of the cross-check's summary.json ``found``: each
    model's peak rotation (rad; the FEM's median over its replicas with their range; a model
    that overturned: where it stopped, no rotation), the FEM's peak over the multibody's with
    its band and tolerance, the answers (:data:`CROSSCHECK_ANSWERS`: word, measure, median and
    range, what bounds them) with their caveats and the verdict."""
    answers = {a["key"]: a for a in found["outcome"]["answers"]}
    peaks = []
    for m in found["outcome"]["models"]:
        row = {
            "model": m["model"],
            "motion": m["motion"],
            "peak_rotation": m.get("peak_rotation"),
            "peak_over_alpha": m.get("peak_rotation_over_alpha"),
            "overturn_time": m.get("overturn_time"),
            "band": None,
        }
        if m["model"].startswith("FEM"):
            band = _replica_peaks(found["fem"])
            row["band"] = None if band is None else [min(band), max(band)]
        peaks.append(row)
    ratio = found["verdict_criteria"]["bands"]["peak_ratio"]
    quoted = []
    for key in CROSSCHECK_ANSWERS:
        a = answers.get(key)
        if a is None:
            continue
        quoted.append(
            {
                k: a[k]
                for k in (
                    "key",
                    "question",
                    "answer",
                    "measure",
                    "median",
                    "min",
                    "max",
                    "limit",
                    "unit",
                    "qualifier",
                    "caveat",
                    "why",
                    "reason",
                )
                if a.get(k) is not None
            }
        )
    caveats = list(found.get("verdict_caveats", {}).values())
    caveats += [a["caveat"] for a in quoted if a.get("caveat") and a["caveat"] not in caveats]
    return {
        "verdict": found["verdict"],
        "rotations": peaks,
        # FEM peak over the multibody's over the replicas (null where a run stopped)
        "peak_ratio": {"median": ratio["median"], "min": ratio["min"], "max": ratio["max"]},
        "peak_tolerance": found["verdict_criteria"]["tolerances"]["peak"],
        "answers": quoted,
        "caveats": caveats,
        "stone_fc": found["stone_fc"],
    }


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) a collar-layout study into ``out``: ``summary.json``."""
    s = setup(study)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    screened = screening(s, out, options)
    decided = decide(s, screened, out, options)
    attempts = None
    if s.spec.fem and decided["chosen"] is not None:
        attempts = fem_attempts(s, decided, out, options)
    summary = assemble(study, s, screened, decided, attempts)
    summary["crosscheck"] = None
    if s.spec.crosscheck and decided["chosen"] is not None:
        summary["crosscheck"] = run_crosscheck(study, s, decided["chosen"], out, options)
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    return summary


def assemble(study: Study, s: Setup, screened: dict, decided: dict, attempts: dict | None) -> dict:
    """summary.json of the collar-layout study (``attempts``: :func:`fem_attempts`'s, None
    without FEM). ``fem`` is the chosen layout's stripe; ``fem_choice`` every attempt's."""
    chosen = decided["chosen"]
    fem = None if attempts is None else attempts["fem"]
    # the layouts before the chosen one in the catalogue's order (lightest first; of equal
    # mass, fewer collars, the lower grade, the lower pretension first)
    rows = decided["rows"]
    lighter = rows if chosen is None else rows[: next(i for i, r in enumerate(rows) if r is chosen)]
    fem_choice = None
    if attempts is not None:
        fem_choice = {k: v for k, v in attempts.items() if k != "fem"}
    return {
        "study": s.column.name,
        "kind": study.kind,
        "answer": answer_text(s, chosen, fem, decided["rows"], fem_choice),
        "chosen": chosen,
        "target": {
            "frequency": s.target,
            "probability": s.spec.target_probability,
            "years": s.years,
            "given": "probability" if s.spec.target_probability is not None else "frequency",
        },
        "intensity": s.spec.intensity,
        "intensity_unit": _unit(s.spec.intensity),
        "levels": s.levels.tolist(),
        "design_intensity": s.design,
        "design_return_period": s.spec.design_return_period,
        "hazard": {**s.hazard.to_dict(), "years": s.years},
        "layouts": decided["rows"],
        "pareto": pareto_front(decided["rows"]),
        "lighter_all_fail": all(r["decision"] == "fails" for r in lighter),
        # every lighter layout fails, or meets the target by the multibody model but not the FEM
        "lighter_all_fail_or_not_confirmed": all(
            r["decision"] in ("fails", NOT_CONFIRMED) for r in lighter
        ),
        # ... or was passed over by the FEM attempts (capacity_skip)
        "lighter_all_fail_not_confirmed_or_skipped": all(
            r["decision"] in ("fails", NOT_CONFIRMED, SKIPPED) for r in lighter
        ),
        # every layout before the multibody model's choice (the first FEM attempt's) fails, by
        # the screening or refined: none left unrefined that the screening cannot rule out
        "before_first_choice_all_fail": first_choice_all_fail(rows, fem_choice),
        "catalogue_size": len(s.candidates),
        "confidence": s.spec.confidence,
        "refined": decided["refined"],
        "fem": fem,
        "fem_choice": fem_choice,
        "records": [
            {"name": entry.name, "sha256": entry.sha256, "intensity": float(value)}
            for entry, value in zip(s.suite, s.intensity)
        ],
        "model_seconds": {
            "screening": screened["seconds"],
            "refinement": decided["plastic_seconds"],
            "fem": None
            if attempts is None
            else sum(a["fem"]["seconds"] for a in attempts["attempts"]),
        },
        "runs": {"screening": screened["runs"], "refinement": decided["plastic_runs"]},
    }


def first_choice_all_fail(rows: list[dict], fem_choice: dict | None) -> bool | None:
    """Whether every layout before the multibody model's choice (the first FEM attempt's, else
    the chosen one) fails; None where there is none."""
    label = fem_choice["first"] if fem_choice else None
    if label is None:
        label = next((r["label"] for r in rows if r["decision"] == "chosen"), None)
    if label is None:
        return None
    index = next(i for i, r in enumerate(rows) if r["label"] == label)
    return all(r["decision"] == "fails" for r in rows[:index])


def pareto_front(rows: list[dict]) -> list[str]:
    """The labels of the layouts no lighter (or equally heavy) layout beats on overturning
    frequency, among those whose frequency was decided (exact or refined, not a bound),
    lightest first: the trade-off of risk against steel."""
    front: list[str] = []
    best = math.inf
    decided = [r for r in rows if r.get("frequency") is not None]
    for r in sorted(decided, key=lambda r: (r["mass"], r["frequency"])):
        if r["frequency_entry"].get("bound"):
            continue
        if r["frequency"] < best:
            front.append(r["label"])
            best = r["frequency"]
    return front


def answer_text(
    s: Setup,
    chosen: dict | None,
    fem: dict | None,
    rows: list[dict],
    fem_choice: dict | None = None,
) -> str:
    """The study's answer in one sentence (the report's first line); ``fem_choice``: the FEM
    attempts (:func:`fem_attempts`) where more than the chosen layout was checked, or why no
    other was."""
    years = s.years
    target = f"target {s.target:.2g} per year"
    if s.spec.target_probability is not None:
        target = f"target {s.spec.target_probability:.2%} in {years:g} years"
    blocked = next((r for r in rows if r.get("decision") == NOT_CHOSEN), None)
    if chosen is None and blocked is not None:
        unrefined = [r for r in rows if r["decision"] == "not refined"]
        return (
            f"No layout is chosen: {blocked['label']} meets the {target} by the multibody model "
            f"(overturning {blocked['frequency']:.2g} per year), but "
            f"{_unrefined(len(unrefined), 'lighter ')} (beyond layout.shortlist = "
            f"{s.spec.shortlist}): raise it to decide {_them(len(unrefined))}."
        )
    if chosen is None:
        skipped = sum(1 for r in rows if r["decision"] == "not refined")
        decided = [r for r in rows if r.get("frequency") is not None]
        text = f"No layout of the catalogue meets the {target}"
        if decided:
            best = min(decided, key=lambda r: (r["frequency"], r["mass"]))
            text += (
                f": the lowest overturning frequency decided is {best['frequency']:.2g} per "
                f"year ({best['label']})"
            )
        return text + (
            f"; {skipped} {_layouts(skipped)} {_were(skipped)} not refined "
            f"(beyond layout.shortlist = {s.spec.shortlist}): raise it to decide "
            f"{_them(skipped)}."
            if skipped
            else "; every layout misses it (see the trade-off)."
        )
    lam = chosen["frequency"]
    p = 1.0 - math.exp(-lam * years)
    heights = ", ".join(f"{y:.2f}" for y in chosen["heights"])
    layout = f"{chosen['label']} at {heights} m" if chosen["count"] else "No collars are needed"
    text = f"{layout}: overturning {lam:.2g} per year, {p:.2%} in {years:g} years, {target}"
    if fem_choice is not None and len(fem_choice["attempts"]) > 1:
        return text + fem_attempts_text(fem_choice) + "."
    if fem is not None:
        text += {
            "confirms": "; the FEM stripe at the design intensity confirms it",
            "contradicts": "; the FEM stripe at the design intensity contradicts it (see the "
            "FEM check)",
            "undecided": "; the FEM stripe at the design intensity neither confirms nor "
            "contradicts it (see the FEM check)",
        }[fem["agreement"]]
        if fem_choice is not None and fem_choice["confirmed"] is None:
            text += f"; no other layout was FEM-checked: {fem_choice['stopped']}"
    return text + "."


CHECKED = {"confirms": "confirmed", "contradicts": "contradicted", "undecided": "undecided"}


def fem_attempts_text(fem_choice: dict) -> str:
    """The answer's clause on more than one FEM attempt: the layout confirmed after the
    lighter ones were not, or none confirmed and why the chosen one is recommended."""
    attempts = fem_choice["attempts"]
    each = "; ".join(f"{a['label']}: {CHECKED[a['agreement']]}" for a in attempts)
    if fem_choice["confirmed"] is not None:
        lighter = [a for a in attempts if a["label"] != fem_choice["confirmed"]]
        names = ", ".join(f"{a['label']} ({CHECKED[a['agreement']]})" for a in lighter)
        return (
            f"; the FEM stripe at the design intensity confirms it, not the lighter {names} "
            "that met the target by the multibody model (see the FEM check)"
        )
    return (
        f"; the FEM stripes at the design intensity confirm none of the {len(attempts)} "
        f"layouts checked ({each}; {fem_choice['stopped']}): recommended as {fem_choice['why']}"
    )


# CPU seconds of a multibody run of the screening (elastic collars, the fragility's fast path,
# a 20 s record and its free tail: docs/speed.md, the multibody fragility) and of the
# refinement (plastic collars: the full run with its history, about ten times as long), per
# simulated second; a walk is taken to climb half the ladder, a refined record three levels
ELASTIC_SECONDS_PER_SECOND = 0.008
PLASTIC_SECONDS_PER_SECOND = 0.1
PLASTIC_LEVELS = 3


def fem_work(study: Study):
    """The FEM work of the study (:func:`studies.driver.check_work`): the confirmation's one run
    per record at the design intensity for each of [layout] fem_attempts layouts (an upper
    bound: it stops at the first the FEM confirms), with the catalogue's most collars (their
    nodes and step are the chosen layout's within a few %), none with layout.fem = false;
    and the chosen layout's cross-check (:func:`_crosscheck_work`)."""
    from ..work import FemWork

    spec = study.spec.layout
    if spec is None or not (spec.fem or spec.crosscheck):
        return FemWork()
    s = setup(study)
    return _fem_stripe_work(s) + _crosscheck_work(study, s, expected=False)


def _crosscheck_work(study: Study, s: Setup, expected: bool):
    """The chosen layout's cross-check's work (its kind's ``fem_work``, or ``expected_work``
    where ``expected``), after the study's other stages: on the catalogue's heaviest layout
    under the suite's longest record (the chosen layout and its record of median capacity are
    known only once the study has run); none with layout.crosscheck = false."""
    from ..kinds import KINDS
    from ..work import FemWork

    if not s.spec.crosscheck or not s.candidates:
        return FemWork()
    heaviest = s.candidates[-1]
    chosen = {
        "label": heaviest.label,
        "heights": s.heights[heaviest.count],
        "t": heaviest.t,
        "h": heaviest.h,
        "fy": heaviest.fy,
        "pretension_force": heaviest.pretension_force,
    }
    longest = int(np.argmax([r.end_time for r in s.records]))
    text, _ = crosscheck_study(study, s, chosen, longest)
    try:
        sub = crosscheck_of(text, study.base / CROSSCHECK_FILE)
        module = KINDS[sub.kind].module()
        work = module.expected_work(sub) if expected else module.fem_work(sub)
    except InputError:  # a cross-check it refuses: the study says why once it is run
        return FemWork()
    # its cases are saved in the sub-study's folder (studies.driver.without_saved)
    later = tuple(
        dataclasses.replace(r, stage=r.stage + CROSSCHECK_STAGE, case=f"{CROSSCHECK_DIR}/{r.case}")
        for r in work.runs
    )
    return dataclasses.replace(work, runs=later)


def _fem_stripe_work(s: Setup):
    """:func:`fem_work` of a study's :class:`Setup`."""
    from ..fragility.runner import _fem_study, _interval
    from ..work import FemWork
    from ..work import fem_work as estimate_work

    if not s.spec.fem:
        return FemWork()
    heaviest = s.candidates[-1]
    one = candidate_column(s.column, s, heaviest)
    interval = _interval(one, s.records)
    models: dict = {}
    work = FemWork()
    # every attempt counted (an upper bound: the attempts stop at the first layout the FEM
    # confirms), each on the heaviest layout
    for attempt in range(s.spec.fem_attempts):
        for i, record in enumerate(s.records):
            work += estimate_work(
                _fem_study(one, record, 1.0, interval),
                1,
                models=models,
                case=fem_key(attempt, i),
                stage=2,
            )
    return work


def expected_work(study: Study):
    """The study's work as it is expected to run, for its estimate of time: the screening's
    walks (stage 0), the refinement of the shortlist (stage 1), the FEM confirmation
    (stage 2; :func:`fem_work`) and the chosen layout's cross-check (stage 3 on). Each run's
    case is the key it is saved under, so that a resumed run's estimate leaves the saved ones
    out (studies.driver.without_saved); the refinement's are taken as the shortlist's lightest
    layouts with collars, each with all its records (which layouts and records it refines is
    known only from the screening), a shortlist more for each further FEM attempt's search
    (:func:`next_meeting`): with the FEM attempts all counted, an upper bound."""
    from ..work import FemRun, FemWork

    s = setup(study)
    runs = []
    sections = {c.section for c in s.candidates}
    # the refinement takes the lightest layouts with collars (those whose records are open)
    searches = s.spec.fem_attempts if s.spec.fem else 1
    refined = [c for c in s.candidates if c.count][: s.spec.shortlist * searches]
    for i, record in enumerate(s.records):
        seconds = record.end_time + FREE_TIME_P / s.column.rocking_block.p
        for section in sections:
            runs.append(
                FemRun(
                    0,
                    0,
                    0,
                    0,
                    screening_key(section, i),
                    other_seconds=0.5 * len(s.levels) * ELASTIC_SECONDS_PER_SECOND * seconds,
                )
            )
        for c in refined:
            runs.append(
                FemRun(
                    0,
                    0,
                    0,
                    0,
                    refinement_key(c, i),
                    stage=1,
                    other_seconds=PLASTIC_LEVELS * PLASTIC_SECONDS_PER_SECOND * seconds,
                )
            )
    return FemWork(runs=tuple(runs)) + _fem_stripe_work(s) + _crosscheck_work(study, s, True)
