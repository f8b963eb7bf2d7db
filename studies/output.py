"""Writing results: CSV tables and JSON, each written atomically (temp file, then rename), so an
interrupted run never leaves a half-written file behind."""

from __future__ import annotations

import io
import json
import math
import os
import platform
import time
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from ..core.errors import ColonnaError


def _atomic_write_text(path: Path, text: str) -> None:
    _atomic_write_bytes(path, text.encode())


def _atomic_write_bytes(path: Path, data: bytes) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".part")
    tmp.write_bytes(data)
    os.replace(tmp, path)


LOCK_NAME = ".colonna.lock"


class FolderInUse(ColonnaError):
    """Another colonna run is writing the same output folder; the message names it."""


@contextmanager
def output_lock(out: Path) -> Iterator[None]:
    """Hold ``out`` for this run alone while it computes and writes: an exclusive lock on
    ``out/.colonna.lock`` (``flock``, released by the system when the process ends, even
    killed), a file that names the run and is removed as the run ends. A second run on the
    same folder stops at once with :class:`FolderInUse`, naming the run that holds it,
    instead of the two overwriting each other's cases. A folder this call made and left
    empty (a refused study) is removed again. Where ``fcntl`` is missing (Windows) the folder
    is not locked."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on the platforms CI runs
        yield
        return
    out = Path(out)
    made = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    path = out / LOCK_NAME
    while True:  # a lock file its holder removed as we opened it is no lock: open it again
        handle = open(path, "a+")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.seek(0)
            holder = handle.read().strip() or "another process"
            handle.close()
            raise FolderInUse(
                f"{out} is being written by another colonna run ({holder}): wait for it to "
                "end, or give this one another --out"
            ) from None
        try:
            if os.path.samestat(os.stat(path), os.fstat(handle.fileno())):
                break
        except FileNotFoundError:
            pass
        handle.close()
    try:
        handle.seek(0)
        handle.truncate()
        handle.write(f"pid {os.getpid()}, started {_utc(time.time())}\n")
        handle.flush()
        yield
    finally:
        path.unlink()  # while still held, so no other run takes the file being removed
        handle.close()
        if made and not any(out.iterdir()):
            out.rmdir()


def json_bytes(data) -> bytes:
    """The bytes :func:`write_json` writes for ``data`` (what a case's result checksum is of)."""
    return (json.dumps(_plain(data), indent=2) + "\n").encode()


def write_json(path, data) -> None:
    _atomic_write_bytes(Path(path), json_bytes(data))


CSV_FORMAT = "%.17g"  # round-trips every double


def write_csv(path, columns: dict) -> None:
    """Write equal-length 1D columns with a header line, full double precision
    (``numpy.savetxt``)."""
    names = list(columns)
    arrays = [np.asarray(columns[n], dtype=float) for n in names]
    n = {a.shape[0] for a in arrays}
    if len(n) != 1:
        raise ValueError(f"columns of different lengths: {sorted(n)}")
    table = np.column_stack(arrays) if arrays else np.zeros((0, 0))
    buffer = io.StringIO()
    np.savetxt(buffer, table, fmt=CSV_FORMAT, delimiter=",", header=",".join(names), comments="")
    _atomic_write_text(Path(path), buffer.getvalue())


def record_inputs(out: Path, study, started: float | None = None) -> dict:
    """The inputs of a study (:class:`studies.study.Study`) on record beside its results:
    ``out/study.toml``, the study file byte for byte, and ``out/inputs.json``, the study's
    :meth:`to_json <studies.study.Study.to_json>` (the tables as the run used them, each value
    the file's, its default or the one resolved for the run, the model as built, the ground
    motion as applied, the colonna version, the SHA-256 of the study file and the command-line
    options that change what is computed) with ``run_record``: the run's date and time (UTC, ISO
    8601), its wall time from ``started`` (a :func:`time.time`) and the machine
    (:func:`machine`). Returns inputs.json."""
    inputs = study.to_json()
    finished = time.time()
    inputs["run_record"] = {
        "colonna_version": inputs["colonna_version"],
        "finished_utc": _utc(finished),
        **(
            {"started_utc": _utc(started), "wall_seconds": finished - started}
            if started is not None
            else {}
        ),
        "machine": machine(),
    }
    _atomic_write_bytes(Path(out) / "study.toml", study.text)
    write_json(Path(out) / "inputs.json", inputs)
    return inputs


def machine() -> dict:
    """The machine a study ran on: its platform, processor, the cores this process may use
    and the Python and NumPy versions."""
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return {
        "platform": platform.platform(),
        "processor": platform.machine(),
        "cores": cores,
        "python": platform.python_version(),
        "numpy": np.__version__,
    }


def _utc(seconds: float) -> str:
    """A time (seconds since the epoch) as ISO 8601 in UTC, to the second."""
    return datetime.fromtimestamp(seconds, UTC).isoformat(timespec="seconds")


def read_csv(path) -> dict:
    """Inverse of :func:`write_csv`."""
    with open(path) as fh:
        names = fh.readline().strip().split(",")
        data = np.loadtxt(fh, delimiter=",", ndmin=2)
    return {name: data[:, i] for i, name in enumerate(names)}


def _plain(obj):
    """JSON-safe copy: numpy scalars/arrays to Python, NaN/inf to None."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj
