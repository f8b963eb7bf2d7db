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

from .crosscheck.runner import fem_case, rigid_case
from .executor import RunOptions, run_cases
from .fem_study import FemStudy
from .guard import check_fem_results
from .output import write_json
from .study import Study

# a sweep's cases from its study (:class:`studies.study.Study`)
Cases = Callable[[Study], list[dict]]
# a sweep's summary from its study, its cases and their results by key
Summarise = Callable[[FemStudy, list[dict], dict], dict]


def _runner(case: dict, directory: str) -> dict:
    return fem_case(case, directory) if case["kind"] == "fem" else rigid_case(case, directory)


def run_sweep(
    study: Study,
    out: Path,
    *,
    cases: Cases,
    summarise: Summarise,
    options: RunOptions,
) -> dict:
    """Run (or resume) a sweep of a study (:func:`studies.study.load`) into ``out``:
    ``cases(study)`` gives its cases (each ``kind`` "fem" or "rigid"), which run, are checked
    (:func:`studies.guard.check_fem_results`) and summarised by ``summarise(study.fem, cases,
    results)``; ``summary.json`` is that summary with its wall time and the study's kind."""
    fem = study.fem  # fails early
    out = Path(out)
    start = time.perf_counter()
    variants = cases(study)
    out.mkdir(parents=True, exist_ok=True)
    results = run_cases(
        _runner,
        variants,
        out,
        run_options=options,
    )
    check_fem_results(results, out)
    summary = summarise(fem, variants, results)
    summary["wall_seconds"] = time.perf_counter() - start
    summary["kind"] = study.kind
    write_json(out / "summary.json", summary)
    return summary
