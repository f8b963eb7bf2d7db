"""One driver for every study kind: load the study (:func:`studies.study.load`: the file read
and validated once), run its kind (the kind's package ``run`` writes ``summary.json``), put the
inputs on record beside the results, then write the report from what is on disk.

The kinds are registered in :data:`studies.kinds.KINDS` (the one table the study file's
``[study] kind`` is checked against too).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..core.errors import InputError
from .kinds import KINDS
from .output import record_inputs, write_csv
from .study import Study, load

if TYPE_CHECKING:
    from .fem_study import FemStudy


def _transitional(spec):  # TRANSITIONAL: until the kinds are packages
    if not isinstance(spec, str):
        return spec
    import importlib

    module, name = spec.split(":")
    return getattr(importlib.import_module(f"{__package__}.{module}"), name)


def study_kind(study_path: Path) -> str:
    """The ``[study] kind`` of a study file, checked whole first (:func:`check_study_file`)."""
    return check_study_file(study_path).kind


def check_study_file(study_path: Path) -> Study:
    """The study of a file, validated against :mod:`studies.schema` as its kind runs it (a
    free-rocking study with its own defaults), before anything is run or written: every error
    of the file at once, one line each, in one :class:`InputError`."""
    return load(study_path)


def run_study_file(
    study: Study | Path,
    out: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    force: bool = False,
    grid: tuple[int, int] | None = None,
    long: bool = False,
) -> dict:
    """Run (or resume) a study (a :class:`Study`, or the path of its file, then read and
    validated once: :func:`studies.study.load`) into ``out`` and write its report; returns the
    summary. Options that only some kinds take (``grid``) are refused for the others. A study
    whose FEM runs ask for more than the work limit is refused before anything is written
    (:func:`check_work`), unless ``long``."""
    given = {k: v for k, v in {"grid": grid}.items() if v is not None}
    if not isinstance(study, Study):
        study = load(study, given)
    elif given:
        study = replace(study, options={**study.options, **given})
    kind = KINDS[study.kind]
    for option in study.options:
        if option not in getattr(kind, "options", ("grid",)):  # TRANSITIONAL
            takers = [name for name, k in KINDS.items() if option in k.options]
            raise InputError(
                f"--{option} applies to studies of kind {' or '.join(takers)}, not {study.kind!r}"
            )
    check_work(study, long=long)
    out = Path(out)
    runner = _transitional(kind.run)
    import inspect  # TRANSITIONAL

    first = next(iter(inspect.signature(runner).parameters.values()))
    summary = runner(
        study if first.annotation == "Study" else study.path,
        out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        force=force,
        **({} if first.annotation == "Study" else study.options),
    )
    # the inputs on record beside the results they gave, once they are all there (a refused
    # or interrupted run leaves the record of the results in out as it was)
    record_inputs(out, study)
    if kind.ground_motion:
        write_ground_motion(out, study.fem)
    _transitional(kind.report)(out)
    if progress:
        print(f"[study] report: {out / 'index.html'}", file=sys.stderr, flush=True)
    return summary


def check_work(study: Study, *, long: bool = False) -> None:
    """Refuse, before anything runs or is written, a study whose FEM runs ask for more work
    than :data:`studies.fem_study.WORK_LIMIT_SECONDS` of CPU (unless ``long``) or more memory
    than one run may have (:func:`studies.fem_study.require_bounded_work`). The work is the
    kind's own estimate (its package's ``fem_work(study)``, with ``FEWER``: its ways to ask for
    less); a study its kind would refuse for another reason is left to the kind, which says
    why in its own words."""
    from .fem_study import require_bounded_work

    if not hasattr(KINDS[study.kind], "module"):  # TRANSITIONAL
        return
    module = KINDS[study.kind].module()
    estimate = getattr(module, "fem_work", None)
    if estimate is None:  # a kind without FEM runs
        return
    try:
        work = estimate(study)
    except InputError:
        return
    require_bounded_work(
        work, long=long, what=f"{study.source}: this study", fewer=getattr(module, "FEWER", "")
    )


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
