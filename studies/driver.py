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
    long: bool = False,
) -> dict:
    """Run (or resume) the study of a file into ``out`` and write its report; returns the
    summary. Options that only one kind takes (``grid``) are refused for the others. A study
    whose FEM runs ask for more than the work limit is refused before anything is written
    (:func:`check_work`), unless ``long``."""
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
    check_work(study_path, kind_name, grid, long=long)
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


def check_work(
    study_path: Path, kind_name: str, grid: tuple[int, int] | None = None, *, long: bool = False
) -> None:
    """Refuse, before anything runs or is written, a study whose FEM runs ask for more work
    than :data:`studies.fem_study.WORK_LIMIT_SECONDS` of CPU (unless ``long``) or more memory
    than one run may have (:func:`studies.fem_study.require_bounded_work`). A study its kind
    would refuse for another reason is left to the kind, which says why in its own words."""
    from .fem_study import require_bounded_work

    try:
        work = fem_work_of(study_path, kind_name, grid)
    except InputError:
        return
    fewer = {
        "spectrum-crosscheck": ", fewer grid points (--grid)",
        "mesh-convergence": ", fewer or coarser [convergence] sizes",
        "free-rocking": ", fewer [free_rocking] variants",
    }.get(kind_name, "")
    if kind_name != "spectrum-crosscheck":
        fewer += ", fewer [run] replicas"
    require_bounded_work(work, long=long, what=f"{study_path}: this study", fewer=fewer)


def fem_work_of(study_path: Path, kind_name: str, grid: tuple[int, int] | None = None):
    """The FEM work (:class:`studies.fem_study.FemWork`) of a study file: every FEM run its
    kind makes, as its runner makes them (the replicas of each, its variants, the grid's
    points), over their whole durations. Not counted: the cross-check's toe windows (a few
    hundredths of a second on refined meshes: a few per cent of its work) and the time that
    runs stopping early (overturned, settled) save."""
    from dataclasses import replace

    from . import schema
    from .fem_study import FemWork, fem_work, from_dict

    data = read_toml(study_path, "study file")
    source, base = str(study_path), study_path.parent
    models: dict = {}  # the model of each mesh, built once

    def runs(study, states=None, **options):
        return fem_work(
            study, study.replicas if states is None else states, models=models, **options
        )

    if kind_name == "zhang-makris":
        return FemWork()
    if kind_name == "spectrum-crosscheck":
        return _grid_work(data, study_path, grid, models)
    if kind_name == "free-rocking":
        from .free_rocking import with_defaults

        table = schema.parse_table("free_rocking", data.get("free_rocking", {}), source)
        study_data = with_defaults({k: v for k, v in data.items() if k != "free_rocking"})
        study_data["run"].setdefault("initial_tilt", 0.01)
        study = from_dict(study_data, source=source, base=base)
        half = study.width / (2.0 if study.cracked else 1.0)
        sizes = table.mesh_sizes or [min(2.0 * study.mesh_size, half)]
        work = runs(study, study.replicas * len(table.tilt_fractions))
        for damping in table.damping:
            work += runs(replace(study, contact=replace(study.contact, damping=damping)))
        for size in sizes:
            work += runs(replace(study, mesh_size=size))
        return work
    study = from_dict(data, source=source, base=base)
    if kind_name == "mesh-convergence":
        from .sweeps import mesh_sizes

        work = FemWork()
        for size in mesh_sizes(data, study):
            work += runs(replace(study, mesh_size=size))
        return work
    if kind_name == "solid-vs-cracked":
        work = FemWork()
        for changes in (
            {"column.cracked": False, "collar": schema.REMOVED},
            {"column.cracked": True, "collar": schema.REMOVED},
            {"column.cracked": True},
        ):
            work += runs(from_dict(schema.variant(data, changes, source), source, base))
        return work
    work = runs(study)  # cross-check and collar-design: the study's run with its replicas
    half = study.width / (2.0 if study.cracked else 1.0)
    if kind_name == "cross-check" and study.mesh_file is None and 4.0 * study.mesh_size <= half:
        for factor in (2, 4):  # its mesh-convergence uncertainty: meshes 2h and 4h
            work += runs(replace(study, mesh_size=factor * study.mesh_size))
    return work


def _grid_work(data: dict, study_path: Path, grid, models: dict):
    """The FEM work of a spectrum cross-check: one run per grid point, its duration that of
    its pulse (the amplitude does not change it). A grid too large even at the shortest
    point's duration is given as that (a lower bound), without building every column of it."""
    from ..fem.solver import BATCH_SLOTS
    from . import schema
    from .fem_study import WORK_LIMIT_SECONDS, FemStudy, FemWork, fem_work, from_dict
    from .spectrum_crosscheck import grid_of

    source = str(study_path)
    base_data = {k: v for k, v in data.items() if k != "grid"}
    ground = dict(base_data.get("ground", {}))
    record = ground.get("pulse") == "record"
    if grid is None:
        grid = tuple(schema.parse_table("grid", data.get("grid", {}), source).points)
    counts = grid[0] * grid[1]

    def point(x: float) -> FemStudy:
        if record:
            motion = {"pulse": "record", "record": ground.get("record"), "time_scale": x}
        else:
            motion = {"pulse": ground.get("pulse", "sine"), "amplitude_ratio": 2.0}
            motion["omega_ratio"] = x
        changed = schema.variant(base_data, {"ground": motion}, source)
        return from_dict(changed, source=source, base=study_path.parent)

    x_range = grid_of(data, (2, 2), record=record, source=source)[0]  # [first, last]
    shortest = point(float(max(x_range)))  # the fastest pulse: the shortest run
    bound = fem_work(shortest, counts, held=BATCH_SLOTS, models=models)
    if bound.seconds > WORK_LIMIT_SECONDS:
        return bound
    work = FemWork()
    for x in grid_of(data, grid, record=record, source=source)[0]:
        work += fem_work(point(float(x)), grid[1], held=BATCH_SLOTS, models=models)
    return work


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
