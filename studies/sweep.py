"""Run a set of independent cases through one executor, saving each as it completes.

Local processes by default (``concurrent.futures``), or an existing Dask distributed cluster
(``scheduler="tcp://..."``). Each case is a plain dict with a unique ``key``; its result (a
JSON-safe dict) is written atomically to ``<out>/cases/<key>/result.json`` the moment it
arrives. A rerun loads the cases already done and runs only the rest, so an interrupted sweep
loses nothing and finishes with the same results.
"""

from __future__ import annotations

import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Callable

from tqdm import tqdm

from .output import write_json


def case_dir(out: Path, key: str) -> Path:
    return Path(out) / "cases" / key


def load_done(out: Path, key: str) -> dict | None:
    path = case_dir(out, key) / "result.json"
    if path.is_file():
        return json.loads(path.read_text())
    return None


def run_cases(function: Callable[[dict, str], dict], cases: list[dict], out: Path, *,
              workers: int | None = None, scheduler: str | None = None,
              progress: bool = True) -> dict:
    """Results keyed by case key. ``function(case, case_directory)`` runs one case in a worker
    and returns its result; it may write files into its case directory."""
    out = Path(out)
    keys = [c["key"] for c in cases]
    if len(set(keys)) != len(keys):
        raise ValueError("case keys must be unique")
    results = {}
    todo = []
    for case in cases:
        done = load_done(out, case["key"])
        if done is not None:
            results[case["key"]] = done
        else:
            todo.append(case)
    if not todo:
        return results
    for case in todo:
        case_dir(out, case["key"]).mkdir(parents=True, exist_ok=True)
    # a progress bar on a terminal, nothing in a log (cases already done count as done)
    bar = tqdm(total=len(cases), initial=len(results), desc="[study] cases", unit="case",
               disable=not (progress and sys.stderr.isatty()), dynamic_ncols=True)

    def finish(case, result):
        write_json(case_dir(out, case["key"]) / "result.json", result)
        results[case["key"]] = result
        bar.set_postfix_str(case["key"], refresh=False)
        bar.update(1)

    if scheduler:
        from distributed import Client, as_completed as dask_completed
        with Client(scheduler) as client:
            futures = {client.submit(function, case, str(case_dir(out, case["key"])),
                                     pure=False): case for case in todo}
            for future in dask_completed(futures):
                finish(futures[future], future.result())
    elif (workers or 1) <= 1 or len(todo) == 1:
        for case in todo:
            finish(case, function(case, str(case_dir(out, case["key"]))))
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = {pool.submit(function, case, str(case_dir(out, case["key"]))): case
                       for case in todo}
            for future in as_completed(futures):
                finish(futures[future], future.result())
    bar.close()
    return results


def default_workers() -> int:
    return max(1, min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                      else os.cpu_count() or 1, 8))

