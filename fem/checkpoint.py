"""Checkpoints of a batch of FEM runs, so that an interrupted run goes on where it was saved.

A long FEM case (a record, a fine mesh) is minutes to hours of work. :func:`colonna.fem.solver.
iter_batch` saves its state every :data:`CHECKPOINT_SECONDS` of wall time, at an output time,
as one *part* in a folder: the kernel's arrays of every run in progress (positions, half-step
velocities, contact and collar history, the toe averages), what its recorder holds since the
previous part (the rows and frames), the batch's counters, and each run that ended since.
Parts are written atomically (a temporary file, then a rename), so a run killed while writing
one keeps the parts before it. A rerun with the same ``key`` (a hash of what the runs compute
from, given by the caller) reads the parts in order and goes on from the last one: the state
is restored bit for bit and the ground read from the step count, so the runs end with the same
numbers as uninterrupted ones. Parts of another key are stale, and deleted.

The folder is the caller's to remove once the result is saved (:func:`clear`).
"""

from __future__ import annotations

import os
import pickle
import shutil
from dataclasses import dataclass, field
from pathlib import Path

# s of wall time between two parts (a run shorter than this writes its last part only);
# the environment variable COLONNA_CHECKPOINT_SECONDS sets another
CHECKPOINT_SECONDS = 120.0


def checkpoint_seconds() -> float:
    """The wall time between two parts (s): COLONNA_CHECKPOINT_SECONDS where set (a positive
    number), else :data:`CHECKPOINT_SECONDS`."""
    given = os.environ.get("COLONNA_CHECKPOINT_SECONDS")
    if given is None:
        return CHECKPOINT_SECONDS
    try:
        seconds = float(given)
    except ValueError:
        seconds = -1.0
    if not seconds > 0.0:
        from ..core.errors import InputError

        raise InputError(
            f"COLONNA_CHECKPOINT_SECONDS = {given!r} must be a positive number of seconds"
        )
    return seconds


@dataclass
class Checkpoint:
    """Where a batch of runs saves its parts (``folder``), under which ``key`` (what the runs
    compute from: a part of another key is never used), every ``interval`` s of wall time."""

    folder: Path
    key: str
    interval: float = field(default_factory=checkpoint_seconds)
    written: int = 0  # parts written by this process

    def sub(self, name: str, key: str) -> Checkpoint:
        """A checkpoint of its own for another batch under this one's folder (the reruns of an
        ensemble at a halved step), its key this one's and ``key``."""
        return Checkpoint(Path(self.folder) / name, f"{self.key}/{key}", self.interval)


def _part_path(folder: Path, index: int) -> Path:
    return Path(folder) / f"part-{index:05d}.pkl"


def write_part(checkpoint: Checkpoint, index: int, data: dict) -> None:
    """Part ``index`` of the checkpoint, written atomically with its key."""
    folder = Path(checkpoint.folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = _part_path(folder, index)
    partial = path.with_name(path.name + ".tmp")
    with open(partial, "wb") as handle:
        pickle.dump(
            {"key": checkpoint.key, "index": index, **data},
            handle,
            protocol=pickle.HIGHEST_PROTOCOL,
        )
        handle.flush()
        os.fsync(handle.fileno())
    os.replace(partial, path)
    checkpoint.written += 1


def read_parts(checkpoint: Checkpoint) -> list[dict]:
    """The parts saved under the checkpoint's key, in order, up to the first missing or
    unreadable one (the rest is dropped: a run goes on from the last whole part). Parts of
    another key are deleted and none is returned."""
    folder = Path(checkpoint.folder)
    parts: list[dict] = []
    while True:
        path = _part_path(folder, len(parts))
        if not path.is_file():
            break
        part = _read_part(path)
        if part is None:
            break
        if part.get("key") != checkpoint.key or part.get("index") != len(parts):
            clear(checkpoint)
            return []
        parts.append(part)
    for stale in sorted(folder.glob("part-*.pkl"))[len(parts) :]:
        stale.unlink()
    return parts


def clear(checkpoint: Checkpoint) -> None:
    """Remove the checkpoint's folder (its result is saved, or its parts are stale)."""
    shutil.rmtree(checkpoint.folder, ignore_errors=True)


def _read_part(path: Path) -> dict | None:
    """The part saved at ``path``, or None where it cannot be read (cut short, or not one)."""
    try:
        with open(path, "rb") as handle:
            return pickle.load(handle)
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ValueError):
        return None


def _last_part(folder: Path) -> dict | None:
    """The last readable part in ``folder`` (any key), or None."""
    for path in sorted(Path(folder).glob("part-*.pkl"), reverse=True):
        part = _read_part(path)
        if part is not None:
            return part
    return None


def remaining_work(folder: Path, steps: float) -> float | None:
    """What is left of a batch of FEM runs each expected to take ``steps`` steps (at the step
    of its first attempt; fewer than its duration's where it is expected to stop early) that
    saves its parts under ``folder`` (a FEM case's checkpoint, where
    :func:`colonna.fem.solver.run_ensemble` keeps one folder ``dt-N`` per attempt, the step
    halved N times), as a fraction of that work, read from the last part (the counters of
    :func:`colonna.fem.solver.iter_batch`): a run in progress at step n of attempt N has
    2^N steps - n left (none once past them), a run not started 2^N steps, a run ended none.
    None where nothing was saved.

    For the estimate of a resumed study's time, which must not count again what was done
    before it was interrupted. The key is not checked: parts of other inputs are dropped when
    the case runs (the estimate was then low)."""
    folder = Path(folder)
    attempts = sorted(
        (int(d.name.removeprefix("dt-")), d)
        for d in folder.glob("dt-*")
        if d.is_dir() and d.name.removeprefix("dt-").isdigit()
    )
    halvings, parts = attempts[-1] if attempts else (0, folder)
    part = _last_part(parts)
    if part is None:  # a rerun at a halved step that has saved nothing yet: all of it
        return float(2**halvings) if halvings > 0 else None
    try:
        done = part["counters"]["steps_done"]
        pending = set(part["counters"]["pending"])
        live = set(part["live"])
    except (KeyError, TypeError):
        return None
    if not steps > 0.0 or not done:
        return None
    expected = 2.0**halvings * steps
    left = sum(
        expected if k in pending else max(0.0, expected - n) if k in live else 0.0
        for k, n in enumerate(done)
    )
    return left / (len(done) * steps)
