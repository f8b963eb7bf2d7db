"""Keep numba's on-disk cache of colonna's kernels consistent with their sources.

numba keys a cached kernel (``cache=True``: ``.nbi``/``.nbc`` files in the module's
``__pycache__``) on its own module file only. A kernel that calls one in another module (the
FEM's and the multibody model's collar forces call :mod:`colonna.core.collar_law`, which calls
:mod:`colonna.core.fibre`) keeps the callee's machine code compiled into it: edit or upgrade the
callee alone and the caller's cache is loaded as it was, running the old law without a word
(numba issue #6845). So the kernel modules are one unit here: :func:`ensure_fresh`, called by
each of them on import, hashes all of their sources and, where the hash differs from the one
stamped beside the cache, removes their cached kernels, which then compile again on first call.

With ``NUMBA_CACHE_DIR`` set the cache is elsewhere, managed by whoever set it: nothing is done.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
from pathlib import Path

KERNEL_MODULES = (
    ("colonna.core", "tables"),
    ("colonna.core", "collar_law"),
    ("colonna.core", "fibre"),
    ("colonna.fem", "_kernels"),
    ("colonna.fem", "cohesive"),
    ("colonna.rigid", "_kernels"),
    ("colonna.rigid", "_multibody"),
)
"""The modules with numba kernels, (package, module): one unit for the cache (any may call
into another)."""

STAMP = "colonna-kernels.sha256"
"""The file beside the cached kernels that records the sources they were compiled from."""

_checked = False


def kernel_sources() -> list[Path]:
    """The source files of :data:`KERNEL_MODULES`, found through their packages' folders (only
    ``colonna`` itself is imported: a kernel module calls this while it is being imported)."""
    files = []
    for package, module in KERNEL_MODULES:
        spec = importlib.util.find_spec(package)
        for folder in (spec.submodule_search_locations or []) if spec else []:
            path = Path(folder) / f"{module}.py"
            if path.is_file():
                files.append(path)
                break
    return files


def sources_digest(files) -> str:
    """SHA-256 over the files' names and bytes, in a fixed order."""
    digest = hashlib.sha256()
    for path in sorted(Path(f) for f in files):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def refresh(files, digest: str) -> list[Path]:
    """Remove the cached kernels of ``files`` from each ``__pycache__`` whose stamp is not
    ``digest``, and stamp it. Returns the removed cache files. A folder that cannot be read or
    written is left as it is (numba then caches elsewhere, or not at all)."""
    removed: list[Path] = []
    by_folder: dict[Path, set[str]] = {}
    for path in files:
        path = Path(path)
        by_folder.setdefault(path.parent / "__pycache__", set()).add(path.stem)
    for folder, stems in by_folder.items():
        stamp = folder / STAMP
        try:
            if stamp.is_file() and stamp.read_text().strip() == digest:
                continue
            if folder.is_dir():
                for cached in folder.iterdir():
                    stem = cached.name.split(".", 1)[0]
                    if cached.suffix in (".nbi", ".nbc") and stem in stems:
                        cached.unlink(missing_ok=True)
                        removed.append(cached)
            folder.mkdir(exist_ok=True)
            stamp.write_text(digest + "\n")
        except OSError:
            continue
    return removed


def ensure_fresh() -> None:
    """Once per process: drop cached kernels compiled from other sources than today's."""
    global _checked
    if _checked:
        return
    _checked = True
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    files = kernel_sources()
    try:
        digest = sources_digest(files)
    except OSError:
        return
    refresh(files, digest)
