"""One driver for every study kind: load the study (:func:`studies.study.load`: the file read
and validated once), run its kind (the kind's package ``run`` writes ``summary.json``), put the
inputs on record beside the results, then write the report from what is on disk.

The kinds are registered in :data:`studies.kinds.KINDS` (the one table the study file's
``[study] kind`` is checked against too).
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..core.errors import InputError
from .executor import DEFAULT_RUN, RunOptions, StudyClock, before_computing, study_clock
from .kinds import KINDS, take_options
from .output import output_lock, record_inputs, write_csv
from .study import Study, load

if TYPE_CHECKING:
    from .fem_study import FemStudy


def check_study_file(study_path: Path) -> Study:
    """The study of a file, validated against :mod:`studies.schema` as its kind runs it (a
    free-rocking study with its own defaults), before anything is run or written: every error
    of the file at once, one line each, in one :class:`InputError`."""
    return load(study_path)


def run_study_file(
    study: Study | Path,
    out: Path,
    *,
    run_options: RunOptions = DEFAULT_RUN,
    grid: tuple[int, int] | None = None,
    long: bool = False,
    options: dict | None = None,
) -> dict:
    """Run (or resume) a study (a :class:`Study`, or the path of its file, then read and
    validated once: :func:`studies.study.load`) into ``out`` and write its report; returns the
    summary. ``run_options``: the workers, the Dask scheduler, the progress bars and whether
    cases saved from other inputs are recomputed (:class:`studies.executor.RunOptions`).
    Options that only some kinds take (``grid``; ``options``: any of them, as values or as the
    command line's texts) are refused for the others. A study whose FEM runs ask for more than
    the work limit is refused before anything is written (:func:`check_work`), unless
    ``long``."""
    given = {k: v for k, v in {"grid": grid, **(options or {})}.items() if v is not None}
    if not isinstance(study, Study):
        study = load(study, given)
    elif given:
        study = replace(study, options={**study.options, **given})
    kind = KINDS[study.kind]
    if study.options:  # each read by its kind, or refused for another kind's
        study = replace(study, options=take_options(study.kind, study.options))
    work = check_work(study, long=long)
    clock = StudyClock()
    workers, progress = run_options.workers, run_options.progress

    def tell_the_work():  # once, as the first case is computed (not for a refused study)
        if clock.started is not None:
            return
        expected = expected_work_of(study, work, out)
        clock.start(wall_estimate(expected, workers))
        if progress and work.seconds > 0.0:
            print(f"[study] {work_estimate(expected, workers)}", file=sys.stderr, flush=True)

    out = Path(out)
    module = kind.module()
    started = time.time()  # the run's date and wall time go on record with its inputs
    with output_lock(out):  # one run at a time writes a folder
        with before_computing(tell_the_work), study_clock(clock):
            summary = module.run(study, out, run_options)
        # the inputs on record beside the results they gave, once they are all there (a
        # refused or interrupted run leaves the record of the results in out as it was)
        record_inputs(out, study, started)
        if kind.ground_motion:
            write_ground_motion(out, study.fem)
        module.write_report(out)
    if progress:
        print(f"[study] report: {out / 'index.html'}", file=sys.stderr, flush=True)
    return summary


# s of a study's wall time besides its cases: starting, its workers' start, the report
STUDY_OVERHEAD_SECONDS = 8.0


def wall_estimate(work, workers: int | None) -> float:
    """The wall seconds a study of this work takes on ``workers`` local workers (one where
    None): its cases dealt to the workers stage by stage (:meth:`FemWork.wall_seconds`, at
    this machine's cost model), and :data:`STUDY_OVERHEAD_SECONDS`."""
    from .executor import available_cores

    share = max(1, min(workers or 1, available_cores()))
    return work.wall_seconds(share) + STUDY_OVERHEAD_SECONDS


def work_estimate(work, workers: int | None) -> str:
    """One line for the user as the work starts: the study's CPU and wall time on this
    machine's ``workers`` (:func:`wall_estimate`), from its cost model (calibrated here by
    ``colonna warmup``, or not: the line says which), and the FEM work behind it."""
    from .cost import cost_model
    from .units import duration_text as _hours

    share = max(1, workers or 1)
    source = (
        "the cost model calibrated on this machine"
        if cost_model().calibrated
        else "a cost model not calibrated on this machine: run colonna warmup"
    )
    return (
        f"estimated {_hours(wall_estimate(work, workers))} of wall time on {share} "
        f"worker{'s' if share > 1 else ''} ({_hours(work.cpu_seconds)} of CPU; "
        f"{work.state_steps:.2g} FEM state-steps on up to {work.nodes:,} nodes; {source}; "
        "runs that overturn or settle end sooner)"
    )


def check_work(study: Study, *, long: bool = False):
    """Refuse, before anything runs or is written, a study whose FEM runs ask for more work
    than :data:`studies.work.WORK_LIMIT_SECONDS` of CPU (unless ``long``) or more memory
    than one run may have (:func:`studies.work.require_bounded_work`). The work is the
    kind's own estimate (its package's ``fem_work(study)``, with ``FEWER``: its ways to ask for
    less); a study its kind would refuse for another reason is left to the kind, which says
    why in its own words. Returns the work (none where the kind left it)."""
    from .work import FemWork, require_bounded_work

    try:
        work = fem_work_of(study)
    except InputError:
        return FemWork()
    fewer = getattr(KINDS[study.kind].module(), "FEWER", "")
    require_bounded_work(work, long=long, what=f"{study.source}: this study", fewer=fewer)
    return work


def expected_work_of(study: Study, work, out: Path | None = None):
    """The work of a study as it is expected to run, for its estimate of time: its kind's
    ``expected_work(study)`` where it has one (the cross-check expects its FEM runs to stop
    where its rigid model overturns), else ``work`` (:func:`fem_work_of`'s, an upper bound),
    less the runs of the cases already saved in ``out`` (a resumed run:
    :func:`without_saved`). Computed as the study starts computing, not when its work is
    checked (the check stays cheap)."""
    expected = getattr(KINDS[study.kind].module(), "expected_work", None)
    found = work if expected is None else expected(study)
    return found if out is None else without_saved(found, Path(out))


def without_saved(work, out: Path):
    """``work`` less its runs whose case (:attr:`FemRun.case <studies.work.FemRun.case>`, a
    case key; ``sub/key`` for a case of a study run in ``out/sub``) is saved
    (:func:`studies.executor.saved_cases`), and less what an interrupted case's checkpoint
    had done (:func:`colonna.fem.checkpoint.remaining_work`: the case goes on from there)."""
    from ..fem.checkpoint import remaining_work
    from .executor import saved_cases

    saved: dict[str, set[str]] = {}

    def done(case: str) -> bool:
        folder, _, key = case.rpartition("/")
        if folder not in saved:
            saved[folder] = saved_cases(out / folder) if folder else saved_cases(out)
        return key in saved[folder]

    def left(run):
        folder, _, key = run.case.rpartition("/")
        fraction = remaining_work(out / folder / "cases" / key / "checkpoint", run.steps)
        if fraction is None:
            return run
        return replace(run, steps=fraction * run.steps, outputs=fraction * run.outputs)

    return replace(work, runs=tuple(left(r) for r in work.runs if not done(r.case)))


def fem_work_of(study: Study):
    """The FEM work (:class:`studies.work.FemWork`) of a study: its kind's own estimate
    (its package's ``fem_work``: every FEM run it makes, as its runner makes them), nothing
    for a kind without FEM runs."""
    from .work import FemWork

    estimate = getattr(KINDS[study.kind].module(), "fem_work", None)
    return FemWork() if estimate is None else estimate(study)


def write_ground_motion(out: Path, study: FemStudy, samples_per_period: int = 200) -> None:
    """``out/ground_motion.csv``: the horizontal and vertical ground accelerations (m/s^2) the
    study applied, on one time axis from 0 to the end of the run (each motion's own
    ``sample_times``: a record's samples, a pulse ``samples_per_period`` times per period), for
    the report's plot of the input."""
    motions = [study.ground, study.vertical]
    end = max([study.duration] + [m.end_time for m in motions])
    times = [np.linspace(0.0, end, 2001)]
    times += [np.asarray(m.sample_times(samples_per_period), dtype=float) for m in motions]
    t = np.unique(np.concatenate(times))
    t = t[(t >= 0.0) & (t <= end)]
    write_csv(
        Path(out) / "ground_motion.csv",
        {
            "t": t,
            "horizontal_acceleration": study.ground.acceleration(t),
            "vertical_acceleration": study.vertical.acceleration(t),
        },
    )
