"""Run a set of independent cases through one executor, saving each as it completes.

Local processes by default (``concurrent.futures``), or an existing Dask distributed cluster
(``scheduler="tcp://..."``). Each case is a plain dict with a unique ``key``; its result (a
JSON-safe dict) is written atomically to ``<out>/cases/<key>/result.json`` the moment it
arrives, with ``inputs.json`` beside it: the hash of what it was computed from (the case dict,
the bytes of the files it reads, the colonna version) and those inputs themselves. A rerun loads
the cases already done from the same inputs and runs only the rest, so an interrupted sweep
loses nothing and finishes with the same results. A case saved from other inputs (or without a
record of them) is never reused: the run is refused before any computation, naming the first
difference, unless ``force`` deletes such cases and computes them again.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib
import json
import os
import shutil
import sys
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from tqdm import tqdm

from ..core.errors import InputError
from .output import _plain, write_json

# case keys that do not change what a case computes (left out of its inputs): how it reports
# progress, and where the study file was (the files it names are hashed by their bytes); and
# the keys of a study dict's [study] table that only name it
NOT_INPUTS = ("progress", "source", "base", "cost")  # cost: a scheduling hint (see _deal)
NOT_STUDY_INPUTS = ("name", "description")
# the files a case's study dict may name, relative to the case's "base" (key path: what it is)
INPUT_FILES = {
    ("ground", "record"): "record file",
    ("ground", "vertical_record"): "vertical record file",
    ("mesh", "file"): "mesh file",
}


# called once before a run computes any case, after its inputs are checked (the command line
# says here that a first run compiles the kernels); see :func:`before_computing`
BEFORE_COMPUTING: list[Callable[[], None]] = []


@contextlib.contextmanager
def before_computing(callback: Callable[[], None]):
    """Within the block, ``callback()`` runs once before :func:`run_cases` computes any case
    (not when every case is already done, nor when the study is refused)."""
    BEFORE_COMPUTING.append(callback)
    try:
        yield
    finally:
        BEFORE_COMPUTING.remove(callback)


def case_dir(out: Path, key: str) -> Path:
    return Path(out) / "cases" / key


def load_done(out: Path, key: str) -> dict | None:
    path = case_dir(out, key) / "result.json"
    if path.is_file():
        return json.loads(path.read_text())
    return None


def colonna_version() -> str:
    return importlib.import_module("colonna").__version__


def canonical_json(data) -> str:
    """One text for one value: sorted keys, no spaces (what is hashed)."""
    return json.dumps(_plain(data), sort_keys=True, separators=(",", ":"), default=str)


def case_inputs(case: dict, file_hashes: dict | None = None) -> dict:
    """What a case is computed from: the case dict without :data:`NOT_INPUTS` (nor the name
    and description of its study dicts), the SHA-256 of each file its study dicts name
    (resolved against ``case["base"]``; None for a missing file), and the colonna version.
    ``file_hashes``: a cache by resolved path."""
    file_hashes = {} if file_hashes is None else file_hashes
    files = {}
    base = Path(case.get("base", "."))
    for name in ("study", "ground_study"):
        study = case.get(name)
        if not isinstance(study, dict):
            continue
        for table, key in INPUT_FILES:
            given = (study.get(table) or {}).get(key)
            if given is None:
                continue
            path = (base / str(given)).resolve()
            if path not in file_hashes:
                file_hashes[path] = (
                    hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None
                )
            files[f"{name}.{table}.{key}"] = {"path": str(given), "sha256": file_hashes[path]}
    kept = {k: v for k, v in case.items() if k not in NOT_INPUTS}
    for name in ("study", "ground_study"):
        if isinstance(kept.get(name), dict) and isinstance(kept[name].get("study"), dict):
            kept[name] = {
                **kept[name],
                "study": {
                    k: v for k, v in kept[name]["study"].items() if k not in NOT_STUDY_INPUTS
                },
            }
    return {
        "case": json.loads(canonical_json(kept)),
        "files": files,
        "colonna_version": colonna_version(),
    }


def inputs_hash(inputs: dict) -> str:
    return hashlib.sha256(canonical_json(inputs).encode()).hexdigest()


def _load_inputs(out: Path, key: str) -> dict | None:
    try:
        saved = json.loads((case_dir(out, key) / "inputs.json").read_text())
    except (OSError, ValueError):
        return None
    return saved if isinstance(saved, dict) and "sha256" in saved else None


def _value_text(value, missing: bool) -> str:
    if missing:
        return "(not given)"
    text = json.dumps(value, sort_keys=True, default=str)
    return text if len(text) <= 40 else text[:37] + "..."


def _first_difference(old, new, path: str = "") -> str | None:
    """The first key path where two JSON values differ, as 'path: old -> new' (list items
    counted from 1, as collar[2] in a study file)."""
    if isinstance(old, dict) and isinstance(new, dict):
        for key in sorted(set(old) | set(new)):
            where = f"{path}.{key}" if path else str(key)
            if key not in old or key not in new:
                return (
                    f"{where}: {_value_text(old.get(key), key not in old)} -> "
                    f"{_value_text(new.get(key), key not in new)}"
                )
            found = _first_difference(old[key], new[key], where)
            if found:
                return found
        return None
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        for i, (a, b) in enumerate(zip(old, new)):
            found = _first_difference(a, b, f"{path}[{i + 1}]")
            if found:
                return found
        return None
    if old != new or type(old) is not type(new):
        return f"{path}: {_value_text(old, False)} -> {_value_text(new, False)}"
    return None


def describe_difference(old: dict, new: dict) -> str:
    """The first difference between the saved inputs of a case and the present ones, in
    words: a key path of the case, a changed file, or the colonna version."""
    old_case, new_case = old.get("case", {}), new["case"]
    found = _first_difference(
        old_case.get("study"), new_case.get("study"), "study"
    ) or _first_difference(old_case, new_case)
    if found:
        return found
    old_files = old.get("files", {})
    for where, file in new["files"].items():
        before = old_files.get(where)
        if before is None or before.get("sha256") != file["sha256"]:
            what = INPUT_FILES[tuple(where.split(".")[1:])]
            return f"{what} {file['path']} changed"
    for where in old_files:
        if where not in new["files"]:
            return f"{where}: {old_files[where].get('path')} -> (not given)"
    if old.get("colonna_version") != new["colonna_version"]:
        return f"colonna version {old.get('colonna_version')} -> {new['colonna_version']}"
    return "the inputs differ"


def stale_cases(cases: list[dict], out: Path, inputs: dict) -> dict:
    """Cases of ``out`` saved (result.json) from other inputs than ``inputs`` (by key), or
    without a record of them: key -> what is wrong with it, in words (the first difference)."""
    stale = {}
    for case in cases:
        key = case["key"]
        if not (case_dir(out, key) / "result.json").is_file():
            continue
        saved = _load_inputs(out, key)
        if saved is None:
            stale[key] = (
                "has no record of the inputs it was computed from (an older colonna saved it)"
            )
        elif saved["sha256"] != inputs_hash(inputs[key]):
            stale[key] = (
                "was computed from other inputs ("
                + describe_difference(saved.get("inputs", {}), inputs[key])
                + ")"
            )
    return stale


def run_cases(
    function: Callable[..., Any],
    cases: list[dict],
    out: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    force: bool = False,
    batched: bool = False,
) -> dict:
    """Results keyed by case key. ``function(case, case_directory)`` runs one case in a worker
    and returns its result; it may write files into its case directory.

    ``batched``: ``function(cases, case_directories)`` runs several cases in one worker and
    yields (index in cases, result) as each completes (cases that share a model advancing
    together, as the spectrum's grid points on the batched FEM kernel). The cases to run are
    dealt into one share per worker (per thread of a Dask cluster), of about equal total
    ``case["cost"]`` (an optional estimate, not an input of the case); the worker
    saves each result as it completes, so an interrupted share loses nothing already computed.

    A saved case is reused only when it was computed from the same inputs
    (:func:`case_inputs`). One saved from other inputs is an :class:`InputError` naming the
    first difference, before anything runs; ``force``: such cases are deleted and run again."""
    out = Path(out)
    keys = [c["key"] for c in cases]
    if len(set(keys)) != len(keys):
        raise ValueError("case keys must be unique")
    file_hashes: dict = {}
    inputs = {c["key"]: case_inputs(c, file_hashes) for c in cases}
    stale = stale_cases(cases, out, inputs)
    if stale and not force:
        key, why = next(iter(stale.items()))
        n = len(stale) - 1
        more = f" (and {n} more case{'s' if n > 1 else ''})" if n else ""
        raise InputError(
            f"{case_dir(out, key)} {why}{more}: pass --force to delete and "
            f"recompute {'them' if n else 'it'}, or choose another --out"
        )
    for key in stale:
        shutil.rmtree(case_dir(out, key))
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
    client = _connect(scheduler) if scheduler else None  # before any folder is made
    for announce in BEFORE_COMPUTING:
        announce()
    for case in todo:
        case_dir(out, case["key"]).mkdir(parents=True, exist_ok=True)
    # a progress bar on a terminal, nothing in a log (cases already done count as done)
    bar = tqdm(
        total=len(cases),
        initial=len(results),
        desc="[study] cases",
        unit="case",
        disable=not (progress and sys.stderr.isatty()),
        dynamic_ncols=True,
    )

    def record(key):
        """What a case's inputs.json holds: the hash of its inputs, and the inputs."""
        return {"sha256": inputs_hash(inputs[key]), "inputs": inputs[key]}

    def finish(case, result, saved=False):
        """Keep a case's result; write its files, unless a worker on this machine has
        (``saved``: a share run in a local process)."""
        key = case["key"]
        if not saved:
            save_case(case_dir(out, key), record(key), result)
        results[key] = result
        bar.set_postfix_str(key, refresh=False)
        bar.update(1)

    def finish_all(share, outcome, batched, saved=False):
        for case, result in zip(share, outcome if batched else [outcome]):
            finish(case, result, saved)

    def saving(share):
        """Per case of a share: its folder and the inputs record it is saved with."""
        return [(str(case_dir(out, c["key"])), record(c["key"])) for c in share]

    if client is not None:
        from distributed import as_completed as dask_completed

        with client:
            if batched:
                shares = _deal(todo, sum(client.nthreads().values()))
                futures = {
                    client.submit(_run_share, function, share, saving(share), pure=False): share
                    for share in shares
                }
            else:
                futures = {
                    client.submit(function, case, str(case_dir(out, case["key"])), pure=False): [
                        case
                    ]
                    for case in todo
                }
            for future in dask_completed(futures):
                finish_all(futures[future], future.result(), batched)
    elif (workers or 1) <= 1 or len(todo) == 1:
        if batched:  # in this process: each case saved as it completes
            folders = [str(case_dir(out, c["key"])) for c in todo]
            for index, result in function(todo, folders):
                finish(todo[index], result)
        else:
            for case in todo:
                finish(case, function(case, str(case_dir(out, case["key"]))))
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            if batched:
                shares = _deal(todo, workers or 1)
                futures = {
                    pool.submit(_run_share, function, share, saving(share)): share
                    for share in shares
                }
            else:
                futures = {
                    pool.submit(function, case, str(case_dir(out, case["key"]))): [case]
                    for case in todo
                }
            for future in as_completed(futures):
                # a share's worker saved each of its cases already (same machine)
                finish_all(futures[future], future.result(), batched, saved=batched)
    bar.close()
    return results


def _connect(scheduler: str):
    """A Dask client of the scheduler at ``scheduler``, or an InputError naming it."""
    from distributed import Client

    try:
        return Client(scheduler)
    except (OSError, ValueError, TypeError) as exc:  # a malformed address, or none answers
        raise InputError(
            f"--scheduler {scheduler!r}: no Dask scheduler could be reached there ({exc})"
        ) from None


def save_case(folder: Path, record: dict, result) -> None:
    """A case's files: its inputs record first, so that a result always has its inputs."""
    write_json(folder / "inputs.json", record)
    write_json(folder / "result.json", result)


def _deal(cases: list, shares: int) -> list[list]:
    """The cases dealt into at most ``shares`` non-empty shares of about equal cost: the
    costliest first, each to the share with the least cost so far (longest processing time
    first). A case's ``"cost"`` (any unit, default 1: then the deal is round-robin) is an
    estimate, for instance the simulated duration of a grid point; each share lists its cases
    costliest first."""
    shares = max(1, min(shares, len(cases)))
    costs = [float(case.get("cost", 1.0)) for case in cases]
    dealt: list[list] = [[] for _ in range(shares)]
    load = [0.0] * shares
    for i in sorted(range(len(cases)), key=lambda i: -costs[i]):
        share = min(range(shares), key=lambda k: (load[k], k))
        dealt[share].append(cases[i])
        load[share] += costs[i]
    return dealt


def _run_share(function, cases: list[dict], saving: list) -> list[dict]:
    """Run a share of cases through a batched ``function`` in a worker, saving each result
    (inputs.json first, then result.json) the moment it is yielded; the results in the order
    of ``cases``."""
    results: list = [None] * len(cases)
    for index, result in function(cases, [folder for folder, _ in saving]):
        folder, record = saving[index]
        save_case(Path(folder), record, result)
        results[index] = result
    missing = [c["key"] for c, r in zip(cases, results) if r is None]
    if missing:
        raise RuntimeError(f"batched case function gave no result for {missing}")
    return results


def default_workers() -> int:
    return max(
        1,
        min(
            len(os.sched_getaffinity(0))
            if hasattr(os, "sched_getaffinity")
            else os.cpu_count() or 1,
            8,
        ),
    )
