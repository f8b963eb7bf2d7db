"""One driver for every study kind: read the study file, run its cases (each kind's ``run``
validates and writes ``summary.json``), put the inputs on record beside the results, then write
the report from what is on disk.

The kinds are registered in :data:`studies.kinds.KINDS` (the one table the study file's
``[study] kind`` is checked against too).
"""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np

from ..core.errors import InputError, read_toml
from ..core.ground import HarmonicPulse, Record
from .kinds import KINDS
from .output import record_inputs, write_csv


def _function(spec: str):
    module, name = spec.split(":")
    return getattr(importlib.import_module(f"{__package__}.{module}"), name)


def study_kind(study_path: Path) -> str:
    """The ``[study] kind`` of a study file, checked whole first (:func:`check_study_file`)."""
    return check_study_file(study_path).study.kind


def check_study_file(study_path: Path):
    """The study file validated against :mod:`studies.schema` as its kind runs it (a
    free-rocking study with its own defaults), before anything is run or written: every error
    of the file at once, one line each, in one :class:`InputError`."""
    from .free_rocking import as_run
    from .schema import parse

    return parse(as_run(read_toml(study_path, "study file")), str(study_path))


def run_study_file(
    study_path: Path,
    out: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    force: bool = False,
    grid: tuple[int, int] | None = None,
) -> dict:
    """Run (or resume) the study of a file into ``out`` and write its report; returns the
    summary. Options that only one kind takes (``grid``) are refused for the others."""
    study_path = Path(study_path)
    kind_name = study_kind(study_path)
    kind = KINDS[kind_name]
    options = {}
    if grid is not None:
        if kind_name != "spectrum-crosscheck":
            raise InputError(
                f"--grid applies to studies of kind spectrum-crosscheck, not {kind_name!r}"
            )
        options["grid"] = grid
    out = Path(out)
    summary = _function(kind.run)(
        study_path,
        out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        force=force,
        **options,
    )
    # the inputs on record beside the results they gave, once they are all there (a refused
    # or interrupted run leaves the record of the results in out as it was)
    record_inputs(out, study_path, {"grid": "x".join(map(str, grid)) if grid else None})
    if kind.ground_motion:
        write_ground_motion(out, study_path)
    _function(kind.report)(out)
    if progress:
        print(f"[study] report: {out / 'index.html'}", file=sys.stderr, flush=True)
    return summary


def write_ground_motion(out: Path, study_path: Path, samples_per_period: int = 200) -> None:
    """``out/ground_motion.csv``: the horizontal and vertical ground accelerations (m/s^2) the
    study applied, on one time axis from 0 to the end of the run (a record's own samples, a
    pulse ``samples_per_period`` times per period), for the report's plot of the input."""
    from .fem_study import load

    study = load(study_path)
    motions = [study.ground, study.vertical]
    end = max([study.duration] + [m.end_time for m in motions])
    times = [np.linspace(0.0, end, 2001)]
    for motion in motions:
        if isinstance(motion, Record):  # a record: its samples
            times.append(np.asarray(motion.time, dtype=float))
        elif isinstance(motion, HarmonicPulse):  # a pulse: fine enough for its shape
            n = math.ceil(samples_per_period * motion.end_time * motion.omega / (2 * math.pi))
            times.append(np.linspace(0.0, motion.end_time, max(n, 2) + 1))
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
