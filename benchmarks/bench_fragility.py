"""Cost of the fragility study (issue 37's targets, 2 cores): the SDOF over 100 records x 40
levels (target 30 s), the rigid multibody model over 20 records x 20 levels (target 60 s), and
the FEM on the spectrum cross-check's coarse mesh over 10 records of 20 s x 8 levels (target
15 minutes; the cost per state-step and per second of motion).

The suite is colonna's synthetic near-fault generator (colonna.core.synthetic, the shipped
suite's maker) with another seed: 100 records of 20 s at 100 Hz, written into a temporary
folder. Each model runs as the study runs it (colonna study: the executor's local worker
processes, one per core, the fits and the report included), on the default column (cracked,
three elastic collars; default.toml) and, for the SDOF, also on the free half block (the same
column without collars), whose runs end at overturning. The SDOF's tolerance is the study's
default (sdof_rtol 1e-6); the fraction of runs whose outcome (overturned or not, each limit
state) differs from rock()'s 1e-10 is measured over 20 records x 40 levels.

The multibody runs take the fragility's path (colonna.rigid.multibody.multibody_outcome: no
histories, the steps of a column at rest skipped, the contact problem's active set solved by
Gaussian elimination, the free tail stopped once no answer can change, the step where the
collars set it a quarter of their stability limit with a single run's crack tolerance:
[fragility] multibody_step); the same 20
levels of
two records are also run as rock_multibody runs them (the path before issue 37's speed-ups)
for its cost a run and how many outcomes differ, and on the fragility's path without the
stop (every answer the fragility reads must be the same: overturning, peak and utilisation;
the fragility keeps no impact count).

The FEM runs on the spectrum mesh as the study runs them (10 records x 8 levels of 20 s, the
issue's size; ``--fem-records N`` for fewer), with the workers' CPU and the cost a state-step;
what the same runs cost before the weak-tail stop is counted from where each run ended.

Run: .venv/bin/python benchmarks/bench_fragility.py [--fem] [--sdof-only] [--multibody-only]
[--fem-only] [--fem-records N] [--multibody-steps] (about 5 minutes on 2 cores; --fem adds the
FEM run, about 15 minutes more on 2 quiet cores; --multibody-steps the multibody fragility at
the single run's step and half of it, about 4 minutes more).
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from colonna.studies.executor import RunOptions

COLUMN = """
[column]
height = 4.0
width = 0.45
cracked = true

[stone]
E = 50e9
nu = 0.2
density = 2700.0
fc = 110e6

[contact]
friction = 0.7
damping = 0.05

[mesh]
size = 0.075
grading = 0.5

[run]
output_interval = 0.01
"""
COLLARS = "".join(f"\n[[collar]]\ny = {y}\nt = 0.008\nh = 0.06\n" for y in (0.5, 2.0, 3.5))


def write_suite(folder: Path, count: int, seed: int = 2037) -> None:
    from colonna.studies.suites.make_synthetic_suite import suite_files

    folder.mkdir(parents=True)
    for name, text in suite_files(count, seed).items():
        (folder / name).write_text(text)


def study_text(
    suite: Path, models, steps: int, ladder=(0.5, 8.0), collars=True, extra: str = ""
) -> str:
    return (
        '[study]\nname = "bench"\nkind = "fragility"\n'
        + COLUMN
        + (COLLARS if collars else "")
        + '\n[ground]\npulse = "none"\n\n[fragility]\n'
        + f'suite = "{suite}"\nintensity = "pgv_rocking"\nladder = [{ladder[0]}, {ladder[1]}]\n'
        + f"steps = {steps}\nmodels = {json.dumps(list(models))}\ndesign_intensity = 2.0\n"
        + "bootstrap = 200\n"
        + extra
    )


def run_study(folder: Path, name: str, text: str, cores: int) -> tuple[float, dict]:
    from colonna.studies.driver import run_study_file

    path = folder / f"{name}.toml"
    path.write_text(text)
    start = time.perf_counter()
    summary = run_study_file(
        path, folder / name, run_options=RunOptions(workers=cores, progress=False)
    )
    return time.perf_counter() - start, summary


def tolerance_check(suite: Path, records: int = 20, steps: int = 40) -> str:
    """How many SDOF outcomes change from rtol 1e-6 (the study's) to 1e-10 (rock's)."""
    from colonna.core.intensity import intensity_measures
    from colonna.core.suite import load_suite
    from colonna.studies.fem_study import column_of
    from colonna.studies.fragility import analysis
    from colonna.studies.fragility.models import sdof_runs
    from colonna.studies.study import load

    study = load(suite.parent / "sdof.toml")
    column = column_of(study.spec, study.source, study.base)
    block = column.rocking_block
    levels = analysis.ladder(0.5, 8.0, steps)
    entries = [e.scaled for e in load_suite(suite)][:records]
    outcomes = {}
    for rtol in (1e-6, 1e-10):
        runs = [
            sdof_runs(
                column,
                r,
                analysis.scales_for(levels, intensity_measures(r, block=block).pgv_rocking),
                rtol=rtol,
            )
            for r in entries
        ]
        outcomes[rtol] = analysis.exceedances(runs, 0.5)
    lines = []
    for state, table in outcomes[1e-6].items():
        differ = int(np.sum(table != outcomes[1e-10][state]))
        lines.append(f"{state} {differ} of {table.size}")
    return "; ".join(lines)


def multibody_check(suite: Path, records: int = 2, steps: int = 20) -> str:
    """CPU a run of rock_multibody (the full run with its histories: the path before the
    speed-ups) and of the fragility's path, over ``records`` x ``steps`` levels, and how many
    limit-state outcomes differ between them."""
    from colonna.studies.fragility import analysis
    from colonna.studies.fragility.models import multibody_point, multibody_steps, outcome_run
    from colonna.studies.fragility.runner import setup
    from colonna.studies.study import load

    s = setup(load(suite.parent / "multibody.toml"))
    column = s.column
    full_runs, fast_runs = [], []
    cpu = {"full": 0.0, "fast": 0.0, "unstopped": 0.0}
    stopped = differ = 0
    for i in range(records):
        record = s.records[i]
        scales = analysis.scales_for(s.levels, s.intensity[i])
        duration = record.end_time + 20.0 / column.rocking_block.p
        dt, touching_dt = multibody_steps(column, record, s.spec.multibody_step)
        start = time.process_time()
        full_runs.append(_full_runs(column, record, scales, duration))
        cpu["full"] += time.process_time() - start
        start = time.process_time()
        outcomes = [
            outcome_run(column, record, x, duration, dt=dt, touching_dt=touching_dt) for x in scales
        ]
        cpu["fast"] += time.process_time() - start
        fast_runs.append([multibody_point(column, o) for o in outcomes])
        start = time.process_time()
        whole = [
            outcome_run(
                column,
                record,
                x,
                duration,
                stop_when_decided=False,
                dt=dt,
                touching_dt=touching_dt,
            )
            for x in scales
        ]
        cpu["unstopped"] += time.process_time() - start
        for a, b in zip(outcomes, whole):
            stopped += a.decided_at is not None
            differ += _answers(a) != _answers(b)
    full = analysis.exceedances(full_runs, 0.5)
    fast = analysis.exceedances(fast_runs, 0.5)
    peaks = np.abs(
        analysis.table(fast_runs, "peak_ratio") - analysis.table(full_runs, "peak_ratio")
    )
    runs = records * steps
    lines = [
        f"CPU a run: rock_multibody {cpu['full'] / runs:.2f} s, the fragility's path "
        f"{cpu['fast'] / runs:.2f} s ({cpu['full'] / cpu['fast']:.1f} x)",
        "outcomes that differ: "
        + "; ".join(f"{k} {int(np.sum(full[k] != fast[k]))} of {runs}" for k in full),
        f"|peak ratio| difference: median {np.median(peaks):.2g}, largest {np.max(peaks):.2g}",
        f"the free tail stopped once decided: {stopped} of {runs} runs; CPU a run without the "
        f"stop {cpu['unstopped'] / runs:.3f} s, with it {cpu['fast'] / runs:.3f} s; runs whose "
        f"answers (overturning, peak, utilisation) differ: {differ}",
    ]
    return "\n  ".join(lines)


def _answers(outcome) -> tuple:
    """What the fragility reads of a run (it keeps no impact count: impacts_needed=False)."""
    return (
        outcome.overturned,
        outcome.max_abs_theta,
        outcome.collar_max_utilisation,
    )


def _full_runs(column, record, scales, duration) -> list[dict]:
    """rock_multibody's runs of ``record`` times each of ``scales`` as fragility runs."""
    import dataclasses
    import math

    from colonna.studies.models import run_multibody

    alpha = column.rocking_block.alpha
    runs = []
    for x in scales:
        variant = dataclasses.replace(column, ground=record.scaled(float(x)), duration=duration)
        r = run_multibody(variant).summary()
        peak = 0.5 * math.pi if r["overturned"] else r["max_abs_theta"]
        runs.append(
            {
                "overturned": r["overturned"],
                "peak_ratio": peak / alpha,
                "uplift": bool(r["overturned"] or peak > 1e-4 * alpha),
                "collar_utilisation": r["collar_max_utilisation"],
                "collar_fractured": None,
                "toe_ratio": None,
            }
        )
    return runs


def main() -> None:
    print(f"load average before: {os.getloadavg()[0]:.1f} (other work on the machine slows it)")
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    cores = cores or 1
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        write_suite(folder / "suite", 100)
        # numba caches and imports: a tiny run first
        run_study(folder, "warm", study_text(folder / "suite", ["sdof"], 2), 1)
        print(f"cores: {cores}; suite: 100 synthetic near-fault records of 20 s at 100 Hz")
        if "--multibody-only" in sys.argv:
            multibody(folder, cores)
            return
        if "--fem-only" in sys.argv:
            fem(folder, cores)
            return

        wall, s = run_study(folder, "sdof", study_text(folder / "suite", ["sdof"], 40), cores)
        runs = 100 * 40
        cpu = s["model_seconds"]["sdof"]
        print(
            f"SDOF, default column (three elastic collars), 100 records x 40 levels: {wall:.1f} s "
            f"wall on {cores} cores (target 30 s; runs and fits {s['wall_seconds']:.1f} s, the "
            f"rest the report), {cpu / runs * 1e3:.1f} ms of CPU a run"
        )
        wall, s = run_study(
            folder, "free", study_text(folder / "suite", ["sdof"], 40, collars=False), cores
        )
        cpu = s["model_seconds"]["sdof"]
        print(
            f"SDOF, free half block (no collars), 100 records x 40 levels: {wall:.1f} s wall "
            f"on {cores} cores (runs and fits {s['wall_seconds']:.1f} s), "
            f"{cpu / runs * 1e3:.1f} ms of CPU a run"
        )
        print("SDOF outcomes at rtol 1e-6 that differ at 1e-10 (20 records x 40 levels): ")
        print("  " + tolerance_check(folder / "suite"))

        if "--sdof-only" in sys.argv:
            return
        multibody(folder, cores)

        if "--fem" in sys.argv:
            fem(folder, cores)


def fem(folder: Path, cores: int) -> None:
    """The FEM on the spectrum mesh as the study runs it (the executor's workers, each
    batching its share of runs on one kernel, settled-stop in the records' weak tails): 10
    records of 20 s x 8 levels of PGV p / (g tan alpha) from 0.5 to 8 (``--fem-records N``
    for fewer). Wall, the workers' CPU, the cost a state-step and a second of motion, and the
    runs' ends: what the same runs would have cost before the weak-tail stop (a run that did
    not overturn ran on to at least the record's end, 20 s, at most its 1.5 s tail more) is
    counted from them at the measured cost a state-step."""
    records = 10
    if "--fem-records" in sys.argv:
        records = int(sys.argv[sys.argv.index("--fem-records") + 1])
    suite = folder / f"suite-fem{records}"
    write_suite(suite, records)
    print(f"load average before the FEM run: {os.getloadavg()[0]:.1f}")
    cpu_start = _children_cpu()
    wall, s = run_study(folder, "fem", study_text(suite, ["fem"], 8, ladder=(0.5, 8.0)), cores)
    cpu = _children_cpu() - cpu_start
    results = [json.loads(p.read_text()) for p in (folder / "fem" / "cases").glob("*/result.json")]
    dt = _fem_dt(folder / "fem.toml")
    steps = sum(r["fem_steps"] for r in results)
    motion = steps * dt
    ended = [r["status_fem"].split(":")[0] for r in results]
    weak = sum("weak tail" in r["status_fem"] for r in results)
    kept = [r["fem_steps"] for r in results if r["status_fem"].startswith("overturned")]
    others = len(results) - len(kept)
    before_low = sum(kept) + others * math.ceil(20.0 / dt)
    before_high = sum(kept) + others * math.ceil(21.5 / dt)
    per_step = cpu / steps
    print(
        f"FEM, spectrum mesh, {records} records of 20 s x 8 levels: {wall:.0f} s wall on "
        f"{cores} cores (target 15 min; runs and fits {s['wall_seconds']:.0f} s); the workers' "
        f"CPU {cpu:.0f} s, {per_step * 1e6:.1f} us a state-step, {cpu / motion:.2f} s per "
        f"second of motion ({motion:.0f} s of motion in {len(results)} runs); load average "
        f"after {os.getloadavg()[0]:.1f}"
    )
    print(
        f"  runs: {sum(e.startswith('overturned') for e in ended)} overturned, {weak} stopped "
        f"in the weak tail, {sum(e.startswith('settled') for e in ended) - weak} settled "
        f"after the record, {sum(e == 'completed' for e in ended)} ran to the end"
    )
    print(
        f"  before the weak-tail stop the same runs took {before_low * dt:.0f}-"
        f"{before_high * dt:.0f} s of motion: {before_low * per_step:.0f}-"
        f"{before_high * per_step:.0f} s of CPU at this cost a state-step "
        f"({steps / before_high:.2f}-{steps / before_low:.2f} of it now)"
    )


def _fem_dt(study: Path) -> float:
    """The FEM's time step (s) of a study file's column."""
    from colonna.fem.model import stable_time_step
    from colonna.studies.fragility.runner import setup
    from colonna.studies.models import build
    from colonna.studies.study import load

    column = setup(load(study)).column
    return stable_time_step(build(column), column.safety).dt


def multibody(folder: Path, cores: int) -> None:
    """The multibody model over 20 records x 20 levels as the study runs it, then the check
    against rock_multibody's runs."""
    twenty = folder / "suite20"
    write_suite(twenty, 20)
    print(f"load average before the multibody run: {os.getloadavg()[0]:.1f}")
    cpu_start = _children_cpu()
    wall, s = run_study(folder, "multibody", study_text(twenty, ["multibody"], 20), cores)
    cpu = _children_cpu() - cpu_start
    print(
        f"multibody, default column, 20 records x 20 levels: {wall:.1f} s wall on {cores} "
        f"cores (target 60 s; runs and fits {s['wall_seconds']:.1f} s); the workers' CPU "
        f"{cpu:.0f} s, {cpu / 400:.2f} s a run; load average after "
        f"{os.getloadavg()[0]:.1f}"
    )
    print("  " + multibody_check(twenty))
    if "--multibody-steps" in sys.argv:
        step_check(folder, twenty, cores, s)


def step_check(folder: Path, suite: Path, cores: int, study_step: dict) -> None:
    """The same fragility at the single run's step (an eighth of the collars' stability limit)
    and at half of it: each limit state's multiple-stripe median and dispersion (with the
    bootstrap band of the median) at each step, the CPU, and how many runs' outcomes differ
    from the study's step."""
    from colonna.studies.fragility import analysis

    found = {0.25: study_step}
    for fraction in (0.125, 0.0625):
        cpu_start = _children_cpu()
        wall, found[fraction] = run_study(
            folder,
            f"multibody-{fraction}",
            study_text(suite, ["multibody"], 20, extra=f"multibody_step = {fraction}\n"),
            cores,
        )
        print(
            f"  at multibody_step {fraction}: {wall:.1f} s wall, the workers' CPU "
            f"{_children_cpu() - cpu_start:.0f} s"
        )
    exceeded = {}
    for fraction, s in found.items():
        runs = s["runs"]["multibody"]
        table = [
            [{key: runs[key][i][j] for key in runs} for j in range(len(runs["overturned"][0]))]
            for i in range(len(runs["overturned"]))
        ]
        exceeded[fraction] = analysis.exceedances(table, 0.5)
        words = []
        for name, entry in s["limit_states"]["multibody"].items():
            fit = (entry.get("stripes") or {}).get("fit")
            if fit is None:
                continue
            low, high = entry["stripes"]["median_interval"]
            words.append(f"{name} {fit['median']:.3f} [{low:.2f}, {high:.2f}] b {fit['beta']:.3f}")
        print(f"  fits at multibody_step {fraction}: " + "; ".join(words))
    for fraction in (0.125, 0.0625):
        differ = {k: int(np.sum(v != exceeded[0.25][k])) for k, v in exceeded[fraction].items()}
        print(f"  outcomes at {fraction} that differ from 0.25's: {differ}")


def _children_cpu() -> float:
    """CPU seconds (user + system) of the finished worker processes."""
    import resource

    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


if __name__ == "__main__":
    main()
