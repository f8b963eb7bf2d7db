"""The machinery of the studies that sweep a column over variants (mesh convergence, solid vs
cracked): the variants are cases of :mod:`studies.executor` (saved as each completes, resumable,
local or Dask), each one FEM ensemble or one SDOF run of the cross-check's
(:func:`studies.crosscheck.runner.fem_case`, :func:`~studies.crosscheck.runner.rigid_case`),
run, checked and summarised. What differs from one such kind to another, the cases and the
summary, is its package's, given to :func:`run_sweep` as arguments.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from ..core.errors import read_toml
from .crosscheck.runner import fem_case, rigid_case
from .executor import run_cases
from .fem_study import FemStudy, from_dict
from .guard import check_fem_results
from .output import write_json

# a sweep's cases from the study file's tables, its study and its path
Cases = Callable[[dict, FemStudy, Path], list[dict]]
# a sweep's summary from its study, its cases and their results by key
Summarise = Callable[[FemStudy, list[dict], dict], dict]


def _runner(case: dict, directory: str) -> dict:
    return fem_case(case, directory) if case["kind"] == "fem" else rigid_case(case, directory)


def case_base(study_path: Path) -> dict:
    """What every case of a sweep of the study file ``study_path`` carries: where it came from
    (``source``) and the folder its file names are relative to (``base``)."""
    return {"source": str(study_path), "base": str(study_path.parent.resolve())}


def run_sweep(
    study_path: Path,
    out: Path,
    *,
    kind: str,
    cases: Cases,
    summarise: Summarise,
    workers=None,
    scheduler=None,
    progress: bool = True,
    force: bool = False,
) -> dict:
    """Run (or resume) a sweep of the study file ``study_path`` into ``out``: ``cases(data,
    study, study_path)`` gives its cases (each ``kind`` "fem" or "rigid"), which run, are
    checked (:func:`studies.guard.check_fem_results`) and summarised by ``summarise(study,
    cases, results)``; ``summary.json`` is that summary with its wall time and ``kind``."""
    study_path = Path(study_path)
    data = read_toml(study_path, "study file")
    study = from_dict(data, source=str(study_path), base=study_path.parent)  # fails early
    out = Path(out)
    start = time.perf_counter()
    variants = cases(data, study, study_path)
    out.mkdir(parents=True, exist_ok=True)
    results = run_cases(
        _runner,
        variants,
        out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        force=force,
    )
    check_fem_results(results, out)
    summary = summarise(study, variants, results)
    summary["wall_seconds"] = time.perf_counter() - start
    summary["kind"] = kind
    write_json(out / "summary.json", summary)
    return summary
