"""Run a set of independent cases through one executor, saving each as it completes.

Local processes by default (``concurrent.futures``), or an existing Dask distributed cluster
(``scheduler="tcp://..."``). Each case is a plain dict with a unique ``key``; its result (a
JSON-safe dict) is written atomically to ``<out>/cases/<key>/result.json`` the moment it
arrives, with ``inputs.json`` beside it: the hash of what it was computed from (the case dict,
the bytes of the files it reads, the colonna version) and those inputs themselves. A rerun loads
the cases already done from the same inputs and runs only the rest, so an interrupted sweep
loses nothing and finishes with the same results. A case saved from other inputs (or without a
record of them) is never reused: the run is refused before any computation
(:class:`~colonna.core.errors.StaleResultsError`), naming the first difference, unless ``force``
deletes such cases and computes them again.

A saved result is checked, not trusted: ``inputs.json`` also holds the SHA-256 of the bytes of
``result.json``, and a result that cannot be read or does not match it (damaged, edited by
hand, or its writing interrupted) is named on stderr and computed again, never used.

Stopping: Ctrl-C or SIGTERM (see ``colonna.studies.cli.main``) ends the worker processes and
raises :class:`StudyInterrupted` with the count of cases saved; workers also end when the main
process is killed outright (:func:`_worker_start`). A lost Dask scheduler is a
:class:`StudyStopped`. The cases saved are kept either way, and a rerun resumes from them.
"""

from __future__ import annotations

import contextlib
import contextvars
import ctypes
import hashlib
import importlib
import json
import logging
import multiprocessing
import os
import re
import shutil
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import CancelledError, ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tqdm import tqdm

from ..core.errors import ColonnaError, InputError, StaleResultsError
from .output import _atomic_write_bytes, _plain, json_bytes, write_json

# case keys that do not change what a case computes (left out of its inputs): how it reports
# progress, and where the study file was (the files it names are hashed by their bytes); and
# the keys of a study dict's [study] table that only name it (its title block's among them)
NOT_INPUTS = ("progress", "source", "base", "cost")  # cost: a scheduling hint (see _deal)
NOT_STUDY_INPUTS = (
    "name",
    "description",
    "project",
    "site",
    "client",
    "prepared_by",
    "checked_by",
    "revision",
)
# the files a case's study dict may name, relative to the case's "base" (key path: what it is)
INPUT_FILES = {
    ("ground", "record"): "record file",
    ("ground", "vertical_record"): "vertical record file",
    ("mesh", "file"): "mesh file",
}


# what runs before a run computes any case, after its inputs are checked (the command line says
# there that a first run compiles the kernels), for the callers inside a :func:`before_computing`
# block: state of the call (its context), not of the module, undone when the block ends
_BEFORE_COMPUTING: contextvars.ContextVar[tuple[Callable[[], None], ...]] = contextvars.ContextVar(
    "before_computing", default=()
)


@contextlib.contextmanager
def before_computing(callback: Callable[[], None]) -> Iterator[None]:
    """Within the block, ``callback()`` runs once before each :func:`run_cases` that computes a
    case (not when every case is already done, nor when the study is refused): the way to reach
    :func:`run_cases` through callers that do not pass its ``before_computing`` argument on."""
    token = _BEFORE_COMPUTING.set((*_BEFORE_COMPUTING.get(), callback))
    try:
        yield
    finally:
        _BEFORE_COMPUTING.reset(token)


@dataclass
class StudyClock:
    """A study's estimated wall time (s) and when it was started (monotonic s): None until the
    study starts computing (:meth:`start`, once its estimate is known)."""

    started: float | None = None
    estimate: float | None = None

    def start(self, estimate: float) -> None:
        self.started, self.estimate = time.monotonic(), estimate

    def reading(self) -> tuple[float, float] | None:
        """(started, estimate) once started, for :func:`time_left`."""
        if self.started is None or self.estimate is None:
            return None
        return self.started, self.estimate

    def revise(self, remaining: float, now: float | None = None) -> float | None:
        """Estimate the study again from here: ``remaining`` wall seconds left (once a stage
        whose work was a guess before it started is known). Returns the new estimate of the
        whole study (s), or None where the clock is not started."""
        if self.started is None:
            return None
        now = time.monotonic() if now is None else now
        self.estimate = (now - self.started) + remaining
        return self.estimate


def revise_study_estimate(remaining: Callable[[], float], when: str, progress: bool = True) -> None:
    """Give the running study's clock (:func:`study_clock`) a new estimate, ``remaining()``
    wall seconds from now (the time spent so far and that: whatever the first estimate got
    wrong before now is out of it), at ``when`` (a clause: "as ... start"); with ``progress`` a
    changed estimate (by more than a tenth, and 10 s) is said on stderr. Without a running
    clock nothing, not even ``remaining()`` (it may build models to count their steps)."""
    from .units import duration_text

    clock = _STUDY_CLOCK.get()
    reading = None if clock is None else clock.reading()
    if clock is None or reading is None:
        return
    before = reading[1]
    after = clock.revise(remaining())
    if progress and after is not None and abs(after - before) > max(0.1 * before, 10.0):
        print(
            f"[study] estimated again {when}: {duration_text(after)} of wall time in all, "
            f"not {duration_text(before)}",
            file=sys.stderr,
            flush=True,
        )


# the study's clock for the progress bars of :func:`run_cases`, set by :func:`study_clock`
# around a study's run
_STUDY_CLOCK: contextvars.ContextVar[StudyClock | None] = contextvars.ContextVar(
    "study_clock", default=None
)


@contextlib.contextmanager
def study_clock(clock: StudyClock) -> Iterator[None]:
    """Within the block, the progress bars of :func:`run_cases` say the time left of the
    study's ``clock`` once it is started (:func:`time_left`)."""
    token = _STUDY_CLOCK.set(clock)
    try:
        yield
    finally:
        _STUDY_CLOCK.reset(token)


def time_left(clock: tuple[float, float], now: float | None = None) -> str:
    """The time left of a study started at ``clock[0]`` (monotonic s) and estimated at
    ``clock[1]`` wall seconds, or how far past the estimate it is."""
    from .units import duration_text

    start, estimate = clock
    left = estimate - ((time.monotonic() if now is None else now) - start)
    if left >= 0.0:
        return f"about {duration_text(left)} left of {duration_text(estimate)} estimated"
    return f"{duration_text(-left)} past the {duration_text(estimate)} estimated"


class StudyInterrupted(KeyboardInterrupt):
    """A run stopped by a signal, SIGINT (Ctrl-C) or SIGTERM (``signum``), with what it kept:
    ``saved`` of ``total`` cases (those known so far) in ``folder``; None where not counted
    (raised by the SIGTERM handler of ``colonna.studies.cli.main``, counted by
    :func:`run_cases`). A KeyboardInterrupt, so that no ``except Exception`` swallows it."""

    def __init__(
        self,
        signum: int = signal.SIGINT,
        saved: int | None = None,
        total: int | None = None,
        folder: Path | None = None,
    ):
        super().__init__(signum)
        self.signum, self.saved, self.total, self.folder = signum, saved, total, folder

    def __str__(self) -> str:
        if self.saved is None:
            return "interrupted"
        return (
            f"interrupted: {self.saved} of {self.total} cases saved in {self.folder}; "
            "run the same command again to resume"
        )


class StudyStopped(ColonnaError):
    """A run that cannot go on for a reason outside its inputs (the Dask scheduler was lost);
    the message says what, and that the cases saved are kept. One line on the command line,
    exit status 1."""


@dataclass(frozen=True)
class RunOptions:
    """How a study's cases run, whatever its kind (the command line's --workers, --scheduler,
    --force; progress bars): what the driver gives a kind's runner and the runner gives
    :func:`run_cases` (its ``run_options``)."""

    workers: int | None = None  # local worker processes (None: one)
    scheduler: str | None = None  # address of a Dask distributed scheduler
    progress: bool = True  # progress bars on stderr
    force: bool = False  # recompute the cases saved from other inputs


DEFAULT_RUN = RunOptions()  # one local worker, progress bars, saved cases reused


def case_dir(out: Path, key: str) -> Path:
    return Path(out) / "cases" / key


def _checked_result(folder: Path) -> tuple[bool, Any, str | None]:
    """(done, result, problem) of a case folder: done where result.json has the SHA-256 its
    record (inputs.json) holds; otherwise ``problem`` says why a result.json that is there is
    not used (None where there is none: never computed, or its writing was interrupted)."""
    path = folder / "result.json"
    if not path.exists():
        return False, None, None
    try:
        data = path.read_bytes()
    except OSError as exc:
        return False, None, f"cannot be read ({exc.strerror or exc})"
    saved = _load_inputs(folder)
    expected = saved.get("result_sha256") if saved is not None else None
    if not isinstance(expected, str) or hashlib.sha256(data).hexdigest() != expected:
        return False, None, "is damaged or was edited (checksum mismatch)"
    try:
        return True, json.loads(data), None
    except ValueError:  # matches its checksum yet is not JSON: written so by hand
        return False, None, "is damaged or was edited (not JSON)"


def load_done(out: Path, key: str) -> Any | None:
    """The saved result of a case, or None where it is to be computed: none saved, or one
    that does not match its record's checksum, which is named in one line on stderr (a
    damaged or edited result is never used, nor a reason to stop)."""
    done, result, problem = _checked_result(case_dir(out, key))
    if problem is not None:
        where = case_dir(out, key) / "result.json"
        print(f"[study] {where} {problem}: computing it again", file=sys.stderr, flush=True)
    return result if done else None


def saved_cases(out: Path) -> set[str]:
    """The keys of the cases in ``out/cases`` whose result matches its record's checksum."""
    folder = Path(out) / "cases"
    if not folder.is_dir():
        return set()
    return {d.name for d in folder.iterdir() if d.is_dir() and _checked_result(d)[0]}


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


def _load_inputs(folder: Path) -> dict | None:
    """A case folder's record (inputs.json), or None where it is missing or unreadable."""
    try:
        saved = json.loads((folder / "inputs.json").read_text())
    except (OSError, ValueError):
        return None
    return saved if isinstance(saved, dict) and isinstance(saved.get("sha256"), str) else None


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


def _changed_record(old, new) -> str | None:
    """A case's study (:meth:`studies.fem_study.FemStudy.to_json`) whose recorded motion has
    other samples, in words: its samples hold the record file times its scales, so any of
    them may have changed."""
    if not (isinstance(old, dict) and isinstance(new, dict)):
        return None
    for motion in ("ground", "vertical"):
        a, b = old.get(motion), new.get(motion)
        if (
            isinstance(a, dict)
            and isinstance(b, dict)
            and a.get("type") == b.get("type") == "record"
            and a != b
        ):
            return (
                f"the {motion} motion, record {b.get('name')}, changed: its file, its scale "
                "or its time scale"
            )
    return None


# The study-file key each field of a case's study (studies.fem_study.FemStudy.to_json) comes
# from, so that a changed input is named as the file spells it (run.safety, collar[2].t): a
# table's fields keep their names after it (stone.E); the motions' and the bed's by their maps.
STUDY_FILE_KEYS = {
    "height": "column.height",
    "width": "column.width",
    "thickness": "column.thickness",
    "cracked": "column.cracked",
    "crack": "column.crack",
    "crack_depth": "column.crack_depth",
    "top_load": "column.top_load",
    "stone": "stone",
    "collars": "collar",
    "contact": "contact",
    "rigid": "rigid",
    "bed": "base",
    "mesh_size": "mesh.size",
    "grading": "mesh.grading",
    "mesh_file": "mesh.file",
    "edge_length": "mesh.edge_length",
    "edge_time": "mesh.edge_time",
    "toe_size": "mesh.toe_size",
    "toe_refinements": "mesh.toe_refinements",
    "duration": "run.duration",
    "output_interval": "run.output_interval",
    "dt": "run.dt",
    "safety": "run.safety",
    "initial_tilt": "run.initial_tilt",
    "initial_angular_velocity": "run.initial_angular_velocity",
    "replicas": "run.replicas",
    "ground": "ground",
    "vertical": "ground",
    "stop_when_settled": "[study] kind (whether a run stops once settled)",
}
# the [base] key each field of fem.bed.Bed comes from
BED_KEYS = {
    "stiffness": "stiffness",
    "low": "stiffness_range",
    "high": "stiffness_range",
    "source": "bed",
    "yield_pressure": "yield_pressure",
    "yield_source": "bed",
}
# the [ground] keys a harmonic pulse's JSON fields come from (horizontal, vertical)
MOTION_KEYS = {
    "type": ("pulse", "vertical_amplitude or vertical_record"),
    "kind": ("pulse", "vertical_amplitude or vertical_record"),
    "amplitude": ("amplitude or ground.amplitude_ratio (a_p, m/s^2)", "vertical_amplitude"),
    "omega": ("period or ground.omega_ratio (Omega, rad/s)", "vertical_period (Omega, rad/s)"),
    "phase": ("amplitude or ground.amplitude_ratio (the pulse's phase, rad)", "vertical_phase"),
    "duration": ("period or ground.omega_ratio (the pulse's duration, s)", "vertical_duration"),
}
# the fields of a case's study that may be defaults that follow from others (a pulse from the
# column's uplift, the run's duration from the motion, the thickness from the width): compared
# after the others, so that the input changed is named, not what follows from it
DERIVED_FIELDS = ("ground", "vertical", "duration", "thickness", "mesh_size", "edge_length")


def study_file_key(path: str) -> str:
    """A key path of a case's study JSON ('study.safety', 'study.collars[1].t') as the study
    file spells it ('run.safety', 'collar[1].t'); a path outside it as it is."""
    match = re.fullmatch(r"study\.([a-z_]+)(.*)", path)
    if match is None:
        return path
    if match.group(1) not in STUDY_FILE_KEYS:  # a study dict shaped as the file: its table's key
        from .schema import table_names

        return path[len("study.") :] if match.group(1) in table_names() else path
    field, rest = match.groups()
    sub = rest.lstrip(".").split(".")[0]
    if field == "bed" and sub:
        return f"base.{BED_KEYS.get(sub, 'bed')}"
    if field in ("ground", "vertical") and sub:
        words = MOTION_KEYS.get(sub)
        return f"ground.{words[field == 'vertical']}" if words else f"ground ({sub})"
    if field == "mesh_file" and sub:
        return "mesh.file (its path or contents)"
    return STUDY_FILE_KEYS[field] + rest


def _in_order(old: dict, new: dict, path: str):
    """(path, old, new) of each key of two dicts, sorted, the :data:`DERIVED_FIELDS` last and
    a motion's fields in :data:`MOTION_KEYS`' order (its type, amplitude, then what follows)."""
    keys = sorted(set(old) | set(new))
    for key in [k for k in keys if k not in DERIVED_FIELDS] + list(DERIVED_FIELDS):
        a, b = old.get(key, _MISSING), new.get(key, _MISSING)
        if key in ("ground", "vertical") and isinstance(a, dict) and isinstance(b, dict):
            subs = sorted(set(a) | set(b))
            subs = [k for k in MOTION_KEYS if k in subs] + [k for k in subs if k not in MOTION_KEYS]
            for sub in subs:
                yield f"{path}.{key}.{sub}", a.get(sub, _MISSING), b.get(sub, _MISSING)
        else:
            yield f"{path}.{key}", a, b


_MISSING = object()


def _study_difference(old, new) -> str | None:
    """The first difference of two cases' studies (:func:`_in_order`), the key named as the
    study file spells it (:func:`study_file_key`); a changed bed by its preset."""
    if not (isinstance(old, dict) and isinstance(new, dict)):
        return _first_difference(old, new, "study")
    old_bed, new_bed = old.get("bed"), new.get("bed")
    if isinstance(old_bed, dict) and isinstance(new_bed, dict):
        if old_bed.get("source") != new_bed.get("source"):
            before, after = (_value_text(b.get("source"), False) for b in (old_bed, new_bed))
            return f"base.bed: {before} -> {after}"
    for where, a, b in _in_order(old, new, "study"):
        found: str | None
        if a is _MISSING and b is _MISSING:
            continue
        if a is _MISSING or b is _MISSING:
            found = f"{where}: {_value_text(a, a is _MISSING)} -> {_value_text(b, b is _MISSING)}"
        else:
            found = _first_difference(a, b, where)
        if found:
            place, change = found.split(": ", 1)
            return f"{study_file_key(place)}: {change}"
    return None


def describe_difference(old: dict, new: dict) -> str:
    """The first difference between the saved inputs of a case and the present ones, in
    words: a key path of the case, a changed file, or the colonna version."""
    old_case, new_case = old.get("case"), new["case"]
    old_case = old_case if isinstance(old_case, dict) else {}
    changed = _changed_record(old_case.get("study"), new_case.get("study"))
    if changed:
        return changed
    found = _study_difference(old_case.get("study"), new_case.get("study"))
    if found:
        return found
    found = _first_difference(old_case, new_case)
    if found:
        return found
    old_files = old.get("files")
    old_files = old_files if isinstance(old_files, dict) else {}
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
    without a record of them or of their result's checksum (an older colonna saved them): key
    -> what is wrong with it, in words (the first difference)."""
    stale = {}
    for case in cases:
        key = case["key"]
        folder = case_dir(out, key)
        if not (folder / "result.json").exists():
            continue
        saved = _load_inputs(folder)
        if saved is None:
            stale[key] = (
                "has no record of the inputs it was computed from (an older colonna saved it)"
                if not (folder / "inputs.json").exists()
                else "has a record of its inputs (inputs.json) that cannot be read"
            )
        elif saved["sha256"] != inputs_hash(inputs[key]):
            old = saved.get("inputs")
            stale[key] = (
                "was computed from other inputs ("
                + describe_difference(old if isinstance(old, dict) else {}, inputs[key])
                + ")"
            )
        elif "result_sha256" not in saved:
            stale[key] = "has no checksum of its result on record (an older colonna saved it)"
    return stale


def run_cases(
    function: Callable[..., Any],
    cases: list[dict],
    out: Path,
    *,
    run_options: RunOptions = DEFAULT_RUN,
    batched: bool = False,
    stage: str = "cases",
    before_computing: Callable[[], None] | None = None,
) -> dict:
    """Results keyed by case key. ``function(case, case_directory)`` runs one case in a worker
    and returns its result; it may write files into its case directory. ``run_options``: the
    workers, the Dask scheduler, the progress bars and ``force`` (:class:`RunOptions`).

    ``batched``: ``function(cases, case_directories)`` runs several cases in one worker and
    yields (index in cases, result) as each completes (cases that share a model advancing
    together, as the spectrum's grid points on the batched FEM kernel). The cases to run are
    dealt into one share per worker (per thread of a Dask cluster), of about equal total
    ``case["cost"]`` (an optional estimate, not an input of the case); the worker
    saves each result as it completes, so an interrupted share loses nothing already computed.

    A saved case is reused only when it was computed from the same inputs
    (:func:`case_inputs`). One saved from other inputs is a
    :class:`~colonna.core.errors.StaleResultsError` naming the first difference, before anything
    runs; with ``run_options.force`` such cases are deleted and run again.

    ``before_computing``: called once after the inputs are checked, before the first case is
    computed (not when every case is already done); without it, the callbacks of the
    :func:`before_computing` blocks around the call.

    Ctrl-C or SIGTERM (any KeyboardInterrupt) ends the local worker processes and is raised
    again as a :class:`StudyInterrupted` counting the cases saved; a lost Dask scheduler is a
    :class:`StudyStopped`. Either way the cases saved are kept for a rerun. ``stage``: what
    the progress bar calls the cases (a study that runs them in stages names each)."""
    if not isinstance(run_options, RunOptions):
        raise InputError(f"run_options = {run_options!r} is not a RunOptions")
    announce = (before_computing,) if before_computing is not None else _BEFORE_COMPUTING.get()
    try:
        return _run_cases(
            function,
            cases,
            Path(out),
            run_options.workers,
            run_options.scheduler,
            run_options.progress,
            run_options.force,
            batched,
            stage,
            announce,
        )
    except (KeyboardInterrupt, SystemError) as exc:
        interrupt = signal_interrupt(exc)
        if interrupt is None:
            raise
        signum = getattr(interrupt, "signum", signal.SIGINT)
        saved = saved_cases(out)
        total = len(saved | {c["key"] for c in cases})
        raise StudyInterrupted(signum, len(saved), total, Path(out) / "cases") from None


def signal_interrupt(exc: BaseException) -> KeyboardInterrupt | None:
    """The Ctrl-C or SIGTERM behind ``exc``: itself, or the KeyboardInterrupt a compiled
    kernel's call returned as a SystemError ("returned a result with an exception set": the
    signal's handler raised while numba's parallel threads ran); None for any other error."""
    if isinstance(exc, KeyboardInterrupt):
        return exc
    if isinstance(exc, SystemError) and isinstance(exc.__context__, KeyboardInterrupt):
        return exc.__context__
    return None


def _clear_stale(cases, out, force) -> dict:
    """Each case's inputs record by key (unique keys); the cases in ``out`` saved from other
    inputs are deleted with ``force`` and refused without it."""
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
        raise StaleResultsError(
            f"{case_dir(out, key)} {why}{more}: pass --force to delete and "
            f"recompute {'them' if n else 'it'}, or choose another --out"
        )
    for key in stale:
        shutil.rmtree(case_dir(out, key))
    return inputs


def _split_done(cases, out) -> tuple[dict, list]:
    """The results of the cases already saved in ``out`` by key, and the cases still to run."""
    results = {}
    todo = []
    for case in cases:
        done = load_done(out, case["key"])
        if done is not None:
            results[case["key"]] = done
        else:
            todo.append(case)
    return results, todo


def _progress_bar(total: int, initial: int, stage: str, progress: bool):
    """A progress bar on a terminal, nothing in a log (cases already done count as done). A
    terminal that reports no size (a pseudo-terminal nobody sized: ``script``, some CI and
    editor consoles) gets a bar 100 columns wide on a screen of 24 rows: tqdm draws nothing on
    a screen of 0 rows."""
    try:
        size = os.get_terminal_size(sys.stderr.fileno())
        sized = size.columns > 0 and size.lines > 0
    except (OSError, ValueError):  # not a terminal, or no file number
        sized = False
    return tqdm(
        total=total,
        initial=initial,
        desc=f"[study] {stage}",
        unit="case",
        disable=not (progress and sys.stderr.isatty()),
        dynamic_ncols=sized,
        ncols=None if sized else 100,
        nrows=None if sized else 24,
        # the time left is the study's (its postfix), not this stage's rate of cases
        bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]",
    )


def _run_here(function, todo, out, batched, finish) -> None:
    """The cases ``todo`` in this process, each saved as it completes."""
    if batched:
        folders = [str(case_dir(out, c["key"])) for c in todo]
        for index, result in function(todo, folders):
            finish(todo[index], result)
    else:
        for case in todo:
            finish(case, function(case, str(case_dir(out, case["key"]))))


def _run_in_pool(function, todo, out, workers, batched, saving, finish_all) -> None:
    """The cases ``todo`` in ``workers`` local processes; an interrupt or a case's error
    stops every worker."""
    forkserver = multiprocessing.get_start_method() == "forkserver"
    pool = ProcessPoolExecutor(
        max_workers=workers,
        initializer=_worker_start,
        initargs=(None if forkserver else os.getpid(),),
    )
    try:
        if batched:
            shares = _deal(todo, workers or 1)
            futures = {
                pool.submit(_run_share, function, share, saving(share)): share for share in shares
            }
        else:
            futures = {
                pool.submit(function, case, str(case_dir(out, case["key"]))): [case]
                for case in todo
            }
        for future in as_completed(futures):
            # a share's worker saved each of its cases already (same machine)
            finish_all(futures[future], future.result(), batched, saved=batched)
    except BaseException:  # an interrupt, or a case's error: no worker goes on
        _stop_pool(pool)
        raise
    pool.shutdown()


def _run_cases(
    function, cases, out, workers, scheduler, progress, force, batched, stage="cases", announce=()
) -> dict:
    """:func:`run_cases` without its translation of an interrupt."""
    inputs = _clear_stale(cases, out, force)
    results, todo = _split_done(cases, out)
    if not todo:
        return results
    client = _connect(scheduler) if scheduler else None  # before any folder is made
    for callback in announce:
        callback()
    for case in todo:
        case_dir(out, case["key"]).mkdir(parents=True, exist_ok=True)
    bar = _progress_bar(len(cases), len(results), stage, progress)

    clock = _STUDY_CLOCK.get()
    last_key = [""]

    def postfix() -> str:  # the case saved last, and the study's time left
        reading = None if clock is None else clock.reading()
        parts = [last_key[0]] + ([time_left(reading)] if reading is not None else [])
        return "; ".join(p for p in parts if p)

    ticking = threading.Event()
    if clock is not None and not bar.disable:  # the time left, once a second

        def tick() -> None:
            while not ticking.wait(1.0):
                bar.set_postfix_str(postfix(), refresh=True)

        threading.Thread(target=tick, daemon=True).start()

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
        last_key[0] = key
        bar.set_postfix_str(postfix(), refresh=False)
        bar.update(1)

    def finish_all(share, outcome, batched, saved=False):
        for case, result in zip(share, outcome if batched else [outcome]):
            finish(case, result, saved)

    def saving(share):
        """Per case of a share: its folder and the inputs record it is saved with."""
        return [(str(case_dir(out, c["key"])), record(c["key"])) for c in share]

    try:
        if client is not None:
            _run_on_dask(client, scheduler, function, todo, out, batched, saving, finish_all)
        elif (workers or 1) <= 1 or len(todo) == 1:
            _run_here(function, todo, out, batched, finish)
        else:
            _run_in_pool(function, todo, out, workers, batched, saving, finish_all)
    finally:
        ticking.set()
        bar.close()
    return results


def _run_on_dask(client, scheduler, function, todo, out, batched, saving, finish_all) -> None:
    """The cases ``todo`` run on a Dask cluster, each saved here as it arrives. A scheduler
    lost on the way (its futures cancelled, its connection closed) is a :class:`StudyStopped`
    naming it, rather than distributed's traceback; the client's own log of the loss (a
    failed reconnection) is silenced, the one line saying it all."""
    from distributed import as_completed as dask_completed
    from distributed.comm import CommClosedError

    client_log = logging.getLogger("distributed.client")
    level = client_log.level
    try:
        with client:
            try:
                if batched:
                    shares = _deal(todo, sum(client.nthreads().values()))
                    futures = {
                        client.submit(_run_share, function, share, saving(share), pure=False): (
                            share
                        )
                        for share in shares
                    }
                else:
                    futures = {
                        client.submit(
                            function, case, str(case_dir(out, case["key"])), pure=False
                        ): [case]
                        for case in todo
                    }
                for future in dask_completed(futures):
                    finish_all(futures[future], future.result(), batched)
            except (CancelledError, CommClosedError):
                client_log.setLevel(logging.CRITICAL)  # its closing logs a failed reconnection
                raise
    except (CancelledError, CommClosedError) as exc:
        saved = saved_cases(out)
        total = len(saved | {c["key"] for c in todo})
        reason = getattr(exc, "reason", None)
        what = (
            "was lost"
            if reason in (None, "scheduler-connection-lost")
            else f"cancelled the cases ({reason})"
        )
        raise StudyStopped(
            f"the Dask scheduler {scheduler} {what} after {len(saved)} of {total} cases: the "
            "cases saved are kept; run the same command again to resume"
        ) from None
    finally:
        client_log.setLevel(level)


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
    """A case's files, each written atomically: its record first (inputs.json: ``record`` and
    the SHA-256 of the result's bytes), then result.json. The one place a case is saved (here,
    in a local worker or on a Dask worker). Stopped between the two, the record names a result
    that is not there, or not those bytes: the case is computed again, never taken as done."""
    data = json_bytes(result)
    write_json(
        folder / "inputs.json", {**record, "result_sha256": hashlib.sha256(data).hexdigest()}
    )
    _atomic_write_bytes(folder / "result.json", data)


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


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system says it)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


def default_workers() -> int:
    return max(1, min(available_cores(), 8))


PR_SET_PDEATHSIG = 1  # linux/prctl.h


def _worker_start(parent: int | None) -> None:
    """Run first in each local worker process: Ctrl-C is left to the main process (which
    ends the workers; a terminal sends it to the whole process group), SIGTERM ends the
    worker (not the handler a forked worker inherits from the command line), and the worker
    ends when its parent does, even killed outright (SIGKILL): on Linux the kernel sends it
    SIGTERM (prctl PR_SET_PDEATHSIG, on the exit of the thread that started it: the main
    thread, which submits the cases); elsewhere a thread looks for its parent every second.
    ``parent``: the main process's pid (None where a fork server, which ends with the main
    process, starts the workers); a parent already gone by then (the race) ends it at once."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    # a note on the inputs (a record too weak to uplift the column) was the main process's
    # to give, once, when it checked them: each worker reading them again stays quiet
    from ..core.ground import RecordNote

    warnings.simplefilter("ignore", RecordNote)
    parent = os.getppid() if parent is None else parent
    watched = False
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            watched = libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) == 0
        except (OSError, AttributeError):
            watched = False
    if os.getppid() != parent:  # ended before the kernel watched it: this is an orphan
        os._exit(1)
    if not watched:
        threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def _watch_parent(parent: int) -> None:
    """End this worker when its parent has ended (it is then another's child)."""
    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


def _stop_pool(pool: ProcessPoolExecutor) -> None:
    """End a local pool now: its queued cases cancelled, its running ones killed (SIGTERM,
    then SIGKILL after 5 s), its processes reaped. concurrent.futures has no way to stop a
    running task, so this reaches into ``pool._processes`` (CPython's name for them, there
    since 3.2); where it is missing, the workers still end with the main process."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.terminate()
    for process in processes:
        process.join(5.0)
        if process.is_alive():
            process.kill()
            process.join(5.0)
    if manager is not None:
        manager.join(5.0)
