"""The fragility study (kind ``fragility``): how likely is each limit state at a given intensity?

The study file is a column file (column, stone, collars, contact, mesh, run, rigid) without a
ground motion of its own ([ground] pulse = "none": the suite's records are the motions) and a
[fragility] table (:class:`.schema.Fragility`):

    [fragility]
    suite = "suites/synthetic"      # a folder of records, or a TOML list (colonna.core.suite)
    intensity = "pgv_rocking"       # pga, pgv, sa (with period), pga_rocking, pgv_rocking
    analysis = "ida"                # ladder = [start, stop], steps; or "msa" with levels
    ladder = [0.5, 6.0]
    steps = 20
    models = ["sdof", "multibody"]  # and "fem"
    design_intensity = 2.0          # the report opens with the probabilities here

Every record (times its suite scale) is scaled to every level: its factor is level / its own
IM (the IMs offered scale linearly with the record). Each model runs each record at each level
once (:mod:`.models`); the cases go through :func:`studies.executor.run_cases` (saved as they
complete, resumable, local workers or Dask): one case per model and record for the rigid models
(its ladder in one worker), one per record and level for the FEM (batched on one kernel, as the
spectrum's grid points). ``summary.json`` holds the runs' tables (records x levels), each
limit state's fits (:mod:`.analysis`) and the likelihood-ratio tests of the rigid models against
the FEM (the cross-check in fragility terms).
"""

from __future__ import annotations

import copy
import dataclasses
import re
import time
from pathlib import Path
from typing import Any

import numpy as np

from ...core.errors import InputError
from ..executor import RunOptions, run_cases
from ..fem_study import FemStudy, case_of, column_of, study_of_case
from ..guard import check_fem_results
from ..output import write_json
from ..study import Study
from ..work import FemWork
from . import analysis
from .models import (
    FREE_TIME_P,
    MODEL_NAMES,
    collar_law,
    fem_point,
    multibody_runs,
    sdof_runs,
    unreachable,
)
from .schema import Fragility

FEM_TAIL = 1.5  # s of free motion the FEM follows after a record (as a study's default)
FEWER = ", fewer records, levels (fragility.steps, levels) or models (fragility.models)"


def defaults(data: dict) -> dict:
    """The study file's tables with this kind's defaults: [ground] pulse = "none" (the suite's
    records are the motions; a copy)."""
    data = copy.deepcopy(data)
    data.setdefault("ground", {"pulse": "none"})
    return data


@dataclasses.dataclass(frozen=True)
class Setup:
    """What a fragility study runs, read once from the validated study: its [fragility]
    table, the column without a motion (:func:`studies.fem_study.column_of`), the suite's
    records (each times its suite scale), every record's IMs and the one it is scaled by, and
    the intensity levels."""

    spec: Fragility
    column: FemStudy
    suite: tuple
    records: tuple
    ims: tuple
    intensity: np.ndarray
    levels: np.ndarray
    origin: float = 0.0  # the fits' origin x0 (IM unit): the uplift intensity with fit = "shifted"
    hazard: Any = None  # [hazard] in the intensity's measure (colonna.core.hazard.HazardCurve)
    years: float = 50.0  # [hazard] years: the probability's period


def setup(study: Study) -> Setup:
    """The :class:`Setup` of a fragility study (an InputError naming the key where it cannot
    be run)."""

    source = study.source
    spec = study.spec.fragility
    if spec is None:
        raise InputError(
            f"{source}: a fragility study needs a [fragility] table (suite, ladder or levels, "
            "design_intensity)"
        )
    column, suite, records, ims, intensity = suite_column(
        study, "fragility", spec.suite, spec.intensity, spec.period
    )
    block = column.rocking_block
    if spec.analysis == "ida":
        assert spec.ladder is not None  # the schema asks for it with analysis = "ida"
        levels = analysis.ladder(spec.ladder[0], spec.ladder[1], spec.steps)
    else:
        levels = np.array(spec.levels, dtype=float)
    for entry, value in zip(suite, intensity):
        analysis.scales_for(levels, value, entry.name)  # a record without motion: refused
    origin = 0.0
    if spec.fit == "shifted":
        pga = np.array([im.pga for im in ims])
        origin = uplift_intensity(spec.intensity, intensity, pga, block.uplift_acceleration())
    table = study.spec.hazard
    try:
        unit = _unit(spec.intensity)
        hazard = analysis.site_hazard(table, spec.intensity, spec.period, unit, block, study.base)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None
    years = table.years if table is not None else 50.0
    return Setup(spec, column, tuple(suite), records, ims, intensity, levels, origin, hazard, years)


def suite_column(study: Study, table: str, given: str, intensity: str, period, least: int = 2):
    """What a kind that runs a record suite on a column reads of its study: the column
    (:func:`studies.fem_study.column_of`), the suite ``given`` in ``[table] suite`` (each record
    times its suite scale), every record's IMs and its ``intensity``; InputErrors naming the
    keys where [ground] is given (the suite's records are the motions) or the suite holds fewer
    than ``least`` records."""
    from ...core.intensity import intensity_measures
    from ...core.suite import load_suite

    source = study.source
    ground = study.data.get("ground", {})
    if set(ground) - {"pulse"} or ground.get("pulse", "none") != "none":
        raise InputError(
            f"{source}: [ground] of a {study.kind} study is the suite's records "
            f"({table}.suite): leave [ground] out or set pulse = 'none'"
        )
    column = column_of(study.spec, source, study.base)
    try:
        suite = load_suite(study.base / given)
    except InputError as exc:
        raise InputError(f"{source}: {table}.suite = {given!r}: {exc}") from None
    if len(suite) < least:
        raise InputError(
            f"{source}: {table}.suite = {given!r} holds {len(suite)} record"
            f"{'' if len(suite) == 1 else 's'}: a fragility needs {least} or more"
        )
    records = tuple(entry.scaled for entry in suite)
    periods = [period] if intensity == "sa" else []
    block = column.rocking_block
    ims = tuple(intensity_measures(r, periods=periods, block=block) for r in records)
    values = np.array([intensity_of(im, intensity, period) for im in ims])
    return column, tuple(suite), records, ims, values


def uplift_intensity(name: str, intensity, pga, uplift: float) -> float:
    """The shifted fits' origin: the least level of IM ``name`` at which a record of the suite
    lifts the rocking block (its scaled PGA reaches the uplift acceleration ``uplift``, g tan
    alpha (1 + lambda), m/s^2): min_i IM_i uplift / PGA_i; below it no record rocks the block.
    For pga_rocking (PGA / uplift) it is 1."""
    if name == "pga_rocking":
        return 1.0
    return float(np.min(np.asarray(intensity) * uplift / np.asarray(pga)))


def intensity_of(ims, name: str, period: float | None = None) -> float:
    """The IM ``name`` of a record's :class:`colonna.core.intensity.IntensityMeasures`."""
    if name == "sa":
        return float(ims.sa[period])
    return float(getattr(ims, name))


def _slug(name: str) -> str:
    """A record's name as a folder name."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)[:40] or "record"


def rigid_case(case: dict, directory: str) -> dict:
    """One rigid model (sdof or multibody) through one record's ladder."""
    study = study_of_case(case)
    record = study.ground
    scales = case["scales"]
    start = time.perf_counter()
    if case["model"] == "sdof":
        runs = sdof_runs(study, record, scales, rtol=case["rtol"])
    else:
        runs = multibody_runs(study, record, scales, collar_step=case["collar_step"])
    return {"runs": runs, "seconds": time.perf_counter() - start}


def fem_cases(cases: list[dict], directories: list[str]):
    """FEM runs of records at levels (one each), those of one model batched on one kernel
    (:func:`studies.models.iter_fem`, settled-stop, also in a record's weak tail:
    :func:`colonna.fem.solver.iter_batch`'s ``stop_in_weak_tail``). Yields (index in cases,
    result)."""
    from ..models import iter_fem

    studies = [study_of_case(case) for case in cases]
    for index, fem in iter_fem(studies, stop_in_weak_tail=True):
        yield index, fem_point(studies[index], fem)


def _fem_study(column: FemStudy, record, scale: float, interval: float) -> FemStudy:
    """The FEM run of ``record`` times ``scale``: to its end + FEM_TAIL, settled-stop."""
    return dataclasses.replace(
        column,
        ground=record.scaled(float(scale)),
        duration=column.duration or record.end_time + FEM_TAIL,
        output_interval=interval,
        stop_when_settled=True,
        replicas=1,
    )


def _interval(column: FemStudy, records) -> float:
    """One output interval for every FEM run (a batch shares it): the study's, else 1/400 of
    the shortest run."""
    if column.output_interval is not None:
        return column.output_interval
    return min(column.duration or r.end_time + FEM_TAIL for r in records) / 400.0


def fem_work(study: Study) -> FemWork:
    """The FEM work of a fragility study (:func:`studies.driver.check_work`): one run per
    record and level, each the record's duration (a settled-stop run costs less)."""
    from ...fem.solver import BATCH_SLOTS
    from ..work import fem_work as estimate_work

    spec = study.spec.fragility
    if spec is not None and "fem" not in spec.models:
        return FemWork()  # (the suite is read when the study runs)
    s = setup(study)
    interval = _interval(s.column, s.records)
    models: dict = {}
    work = FemWork()
    for record in s.records:
        one = _fem_study(s.column, record, 1.0, interval)
        work += estimate_work(one, s.levels.size, held=BATCH_SLOTS, models=models)
    return work


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) a fragility study into ``out``: ``summary.json``."""
    s = setup(study)
    spec = s.spec
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    scales = [analysis.scales_for(s.levels, im).tolist() for im in s.intensity]
    names = [_slug(entry.name) for entry in s.suite]
    rigid = [m for m in spec.models if m != "fem"]
    cases = []
    for model in rigid:
        for i, record in enumerate(s.records):
            duration = record.end_time + FREE_TIME_P / s.column.rocking_block.p
            one = dataclasses.replace(s.column, ground=record, duration=duration)
            cases.append(
                case_of(
                    one,
                    key=f"{model}-{i:03d}-{names[i]}",
                    model=model,
                    record=i,
                    scales=scales[i],
                    rtol=spec.sdof_rtol if model == "sdof" else None,
                    collar_step=spec.multibody_step if model == "multibody" else None,
                )
            )
    runs: dict[str, list] = {}
    seconds: dict[str, float] = {}
    if cases:
        results = run_cases(rigid_case, cases, out, run_options=options, stage="rigid runs")
        for model in rigid:
            mine = [c for c in cases if c["model"] == model]
            runs[model] = [results[c["key"]]["runs"] for c in mine]
            seconds[model] = float(sum(results[c["key"]]["seconds"] for c in mine))
    if "fem" in spec.models:
        interval = _interval(s.column, s.records)
        fem = []
        for i, record in enumerate(s.records):
            for j, scale in enumerate(scales[i]):
                one = _fem_study(s.column, record, scale, interval)
                fem.append(
                    case_of(
                        one,
                        cost=one.duration,
                        key=f"fem-{i:03d}-{j:03d}-{names[i]}",
                        record=i,
                        level=j,
                    )
                )
        results = run_cases(
            fem_cases, fem, out, run_options=options, batched=True, stage="FEM runs"
        )
        check_fem_results(results, out)
        table: list[list[dict]] = [[{} for _ in s.levels] for _ in s.records]
        for c in fem:
            table[c["record"]][c["level"]] = results[c["key"]]
        runs["fem"] = table
        seconds["fem"] = float(sum(results[c["key"]]["fem_seconds"] for c in fem))
    summary = assemble(study, s, runs, seconds)
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    return summary


RUN_TABLES = (
    "overturned",
    "peak_ratio",
    "uplift",
    "collar_utilisation",
    "toe_ratio",
    "overturned_at",
)


def assemble(study: Study, s: Setup, runs: dict, seconds: dict) -> dict:
    """summary.json from the runs: per model the records x levels tables, per model and limit
    state the fits and P at the design intensity, and the likelihood-ratio tests."""
    spec = s.spec
    block = s.column.rocking_block
    design = spec.design_intensity
    states: dict[str, dict] = {}
    exceeded: dict[str, dict] = {}
    for model, table in runs.items():
        exceeded[model] = analysis.exceedances(table, spec.theta_ratio)
        states[model] = limit_state_fits(
            exceeded[model], s.levels, spec, s.origin, s.hazard, s.years
        )
    tests: dict[str, dict] = {}
    if "fem" in exceeded:
        for model in exceeded:
            if model == "fem":
                continue
            for name, value in exceeded[model].items():
                if name in exceeded["fem"]:
                    tests.setdefault(name, {})[f"{model}_fem"] = analysis.same_curve(
                        value, exceeded["fem"][name], s.levels, origin=s.origin
                    )
    probability: dict[str, float | None] = {}
    frequency: dict[str, float | None] = {}
    for model, fitted in states.items():
        for name, entry in fitted.items():
            best = answer_fit(entry)
            probability[f"P({name})_{model}"] = None if best is None else best["probability"]
            if s.hazard is not None:
                found = None if best is None else best["risk"]["frequency"]
                frequency[f"lambda({name})_{model}"] = found
    return {
        "study": s.column.name,
        "kind": study.kind,
        "intensity": spec.intensity,
        "intensity_unit": _unit(spec.intensity),
        "period": spec.period,
        "analysis": spec.analysis,
        "levels": s.levels.tolist(),
        "design_intensity": design,
        "theta_ratio": spec.theta_ratio,
        "fit": spec.fit,
        "origin": s.origin,
        "confidence": spec.confidence,
        "bootstrap": spec.bootstrap,
        "models": list(runs),
        "block": {
            "alpha": block.alpha,
            "p": block.p,
            "uplift_acceleration": block.uplift_acceleration("nonlinear"),
        },
        "records": [
            {
                "name": entry.name,
                "file": str(entry.path.name),
                "sha256": entry.sha256,
                "suite_scale": entry.scale,
                "intensity": float(value),
                "duration": float(record.end_time),
                "ims": ims.to_dict(),
            }
            for entry, record, ims, value in zip(s.suite, s.records, s.ims, s.intensity)
        ],
        "spectra": suite_spectra(s.records),
        "runs": {model: run_tables(model, table) for model, table in runs.items()},
        "limit_states": states,
        "design": probability,
        "hazard": None if s.hazard is None else {**s.hazard.to_dict(), "years": s.years},
        "risk": frequency if s.hazard is not None else None,
        "collars": collar_summary(s.column, runs, probability),
        "unreachable": {model: unreachable(s.column, model) for model in runs},
        "same_curve": tests,
        "sdof_rtol": spec.sdof_rtol if "sdof" in runs else None,
        "multibody_step": spec.multibody_step if "multibody" in runs else None,
        "model_seconds": seconds,
        "layout": "runs[model][key][i][j]: i indexes records, j indexes levels; null where a "
        "run gives none, and a run that overturned has no peak_ratio (its peak is where the run "
        "stopped), nor an SDOF's collar_utilisation (computed at that angle), but overturned_at "
        "(s; null where it stood)",
    }


def run_tables(model: str, runs: list[list[dict]]) -> dict:
    """The records x levels tables of :data:`RUN_TABLES` for summary.json, None where a run
    gives no number: an overturned run's peak rotation is where it stopped (the SDOF's pi/2,
    the others' stop at 45 degrees), and the SDOF's collar utilisation is computed at that
    angle, so neither is a result (issue 48; the analysis reads the runs themselves, where an
    overturned run exceeds the rotation limit states)."""
    overturned = analysis.table(runs, "overturned") > 0.5
    tables = {}
    for key in RUN_TABLES:
        values = analysis.table(runs, key)
        if key == "peak_ratio" or (key == "collar_utilisation" and model == "sdof"):
            values = np.where(overturned, np.nan, values)
        tables[key] = [[None if np.isnan(v) else float(v) for v in row] for row in values]
    return tables


def collar_summary(column: FemStudy, runs: dict, probability: dict) -> dict:
    """Per model, what its collars are (:func:`.models.collar_law`) and, where they are
    elastic and carried more than f_y in runs the column survived (:func:`.analysis.
    past_yield`), ``past_fy`` and a ``note`` that says so: those survivals rest on collars
    past their strength (the limit states :data:`.analysis.AFTER_YIELD`, ``rests``)."""
    found = {}
    for model, table in runs.items():
        law = collar_law(column, model)
        past = None if law["yields"] else analysis.past_yield(table)
        law["past_fy"] = past
        law["rests"] = []
        law["note"] = None
        if past is not None:
            law["rests"] = list(analysis.AFTER_YIELD)
            u = past["largest_utilisation"]
            note = (
                f"its collars ({law['short']}) never yield: in {past['runs']} of the "
                f"{past['of']} runs it survived their stress passed f_y, up to "
                f"sigma / f_y = {u:.3g}, so its survival there rests on collars carrying up to "
                f"{u:.3g} times their strength"
            )
            if not any(r["overturned"] for row in table for r in row):
                others = [
                    f"the {MODEL_NAMES[m]} does (P = {probability[f'P(overturning)_{m}']:.2g} "
                    "at the design intensity)"
                    for m in runs
                    if m != model and probability.get(f"P(overturning)_{m}") is not None
                ]
                note += "; it never overturns over the suite" + (
                    f", while {', '.join(others)}" if others else ""
                )
            law["note"] = note
        found[model] = law
    return found


SPECTRUM_PERIODS = np.geomspace(0.05, 5.0, 30)  # s, the suite's spectra in the report


def suite_spectra(records) -> dict:
    """The 5 %-damped pseudo-spectral acceleration (m/s^2) of every record of the suite (times
    its suite scale) at :data:`SPECTRUM_PERIODS`."""
    from ...core.intensity import spectral_acceleration

    return {
        "periods": SPECTRUM_PERIODS.tolist(),
        "sa": [spectral_acceleration(r, SPECTRUM_PERIODS).tolist() for r in records],
    }


def limit_state_fits(
    exceeded: dict,
    levels,
    spec: Fragility,
    origin: float = 0.0,
    hazard=None,
    years: float = 50.0,
) -> dict:
    """Per limit state, its fits (:func:`.analysis.fit_limit_state`) with the [fragility]
    table's design intensity, bootstrap and analysis, shifted by ``origin`` (IM unit) where
    > 0, and with a ``hazard`` (in its measure) each fit's risk in ``years``."""
    return {
        name: analysis.fit_limit_state(
            value,
            levels,
            spec.design_intensity,
            bootstrap=analysis.Bootstrap(spec.bootstrap, spec.seed, spec.confidence),
            ida=spec.analysis == "ida",
            origin=origin,
            hazard=hazard,
            years=years,
        )
        for name, value in exceeded.items()
    }


def answer_fit(entry: dict) -> dict | None:
    """The fit a limit state's probability at the design intensity is read from: the IDA
    capacities' where the study ran IDA and it has one, else the stripes'."""
    for name in ("ida", "stripes"):
        fit = entry.get(name)
        if fit is not None and fit.get("fit") is not None:
            return fit
    return None


def _unit(intensity: str) -> str:
    from .schema import INTENSITY_MEASURES

    return INTENSITY_MEASURES[intensity]
