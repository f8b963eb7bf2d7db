"""Record suites: the ground motions of a fragility study, each with its scale and its file's
SHA-256 (so that results name the exact records they came from).

A suite is either

* a folder of record files, read in name order: ``.AT2`` (PEER NGA, units from its header),
  ``.ASC`` or any file starting ``EVENT_NAME:`` (ESM ASCII, units from its header), and
  two-column ``.txt``/``.csv``/``.dat`` files, whose units are not in the file and must be
  given (``load_suite(folder, units="g")``); other files are left out. A folder that holds a
  ``suite.toml`` is that list instead;
* a TOML list, paths relative to the TOML file::

      [[record]]
      file = "records/MRN_HNE.ASC"   # required
      scale = 1.5                    # optional, default 1 (multiplies the acceleration); or
      # scale_to_pga = 3.0 (m/s^2) or scale_to_pgv = 0.4 (m/s): the factor that gives it
      name = "MRN-E"                 # optional, default the file's stem; names are unique
      units = "g"                    # two-column files only: g, cm/s2 (gal), m/s2, mm/s2

      [record.parameters]            # optional: how the record was made (the synthetic
      Tp = 1.2                       # generator writes its drawn parameters here)

  and an optional ``[suite]`` table of free notes (how the suite was made), kept in the file
  and not read;

Every mistake is one :class:`~colonna.core.errors.InputError` naming the entry (its number
and file) and what is allowed.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .constants import STANDARD_GRAVITY
from .errors import InputError, read_toml
from .ground import UNITS, Record, is_esm, read_esm_file, read_peer_at2, read_two_column

__all__ = ["SuiteRecord", "load_suite", "suite_toml"]

SUITE_FILE = "suite.toml"  # a folder's list, where it has one
TWO_COLUMN_SUFFIXES = (".txt", ".csv", ".dat")
RECORD_KEYS = ("file", "scale", "scale_to_pga", "scale_to_pgv", "name", "units", "parameters")
SCALE_KEYS = ("scale", "scale_to_pga", "scale_to_pgv")  # one of them sets the factor


@dataclass(frozen=True)
class SuiteRecord:
    """One record of a suite: its ``name``, the ``record`` as read (m/s^2, not scaled), its
    ``scale`` (the study multiplies the acceleration by it), the file's ``path`` and
    ``sha256``, and the ``parameters`` it was made with (a synthetic record's; else empty)."""

    name: str
    record: Record = field(repr=False)
    scale: float
    path: Path
    sha256: str
    parameters: dict[str, Any] = field(default_factory=dict, repr=False)

    @property
    def scaled(self) -> Record:
        """The record times its scale."""
        return self.record if self.scale == 1.0 else self.record.scaled(self.scale)


def _sha256(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError as exc:
        raise InputError(f"record file {path} cannot be read: {exc.strerror}") from None


def _read(path: Path, units: str | None, where: str, g: float) -> Record:
    """A record file by its format; ``units`` only for two-column files (where it is needed)."""
    suffix = path.suffix.lower()
    described = suffix in (".at2", ".asc") or is_esm(path)
    if described and units is not None:
        raise InputError(
            f"{where}: units = {units!r} is given, but the file's header states its units "
            "(AT2, ESM): remove units"
        )
    if suffix == ".at2":
        return read_peer_at2(path, g=g)
    if described:
        return read_esm_file(path, g=g)[0]
    if units is None:
        raise InputError(
            f"{where}: a two-column file does not state its units: give units = one of "
            f"{', '.join(UNITS)}"
        )
    return read_two_column(path, units=units, g=g)


def _entry(index: int, data: Any, base: Path, g: float) -> SuiteRecord:
    if not isinstance(data, dict):
        raise InputError(f"suite record {index}: must be a [[record]] table")
    where = f"suite record {index} ({data.get('file', 'no file')})"
    unknown = sorted(set(data) - set(RECORD_KEYS))
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r} (allowed: {', '.join(RECORD_KEYS)})")
    file = data.get("file")
    if not isinstance(file, str) or not file:
        raise InputError(
            f"suite record {index}: file = ... (a path relative to the list) is required"
        )
    given = [key for key in SCALE_KEYS if key in data]
    if len(given) > 1:
        raise InputError(f"{where}: give only one of {', '.join(given)} (each sets the factor)")
    key = given[0] if given else "scale"
    scale = data.get(key, 1.0)
    if (
        isinstance(scale, bool)
        or not isinstance(scale, int | float)
        or not (0.0 < scale < math.inf)
    ):
        raise InputError(f"{where}: {key} = {scale!r} must be a number > 0")
    units = data.get("units")
    if units is not None and units not in UNITS:
        raise InputError(f"{where}: units = {units!r} is not one of {', '.join(UNITS)}")
    name = data.get("name", Path(file).stem)
    if not isinstance(name, str) or not name:
        raise InputError(f"{where}: name = {name!r} must be a non-empty string")
    parameters = data.get("parameters", {})
    if not isinstance(parameters, dict):
        raise InputError(f"{where}: parameters must be a table ([record.parameters])")
    path = (base / file).resolve()
    if not path.is_file():
        raise InputError(f"{where}: no such file {path}")
    record = _read(path, units, where, g)
    if key != "scale":  # the factor that gives the record that peak (the study's PGA, PGV)
        from .intensity import peak_ground

        peak = peak_ground(record, key.removeprefix("scale_to_"))
        if not peak > 0.0:
            raise InputError(f"{where}: {key}: the record never moves")
        scale = scale / peak
    return SuiteRecord(name, record, float(scale), path, _sha256(path), dict(parameters))


def _from_toml(path: Path, g: float) -> tuple[SuiteRecord, ...]:
    data = read_toml(path, "suite list")
    unknown = sorted(set(data) - {"record", "suite"})
    if unknown:
        raise InputError(
            f"suite list {path}: unknown table {unknown[0]!r} (a list has [[record]] entries "
            "and an optional [suite] table)"
        )
    entries = data.get("record")
    if not isinstance(entries, list) or not entries:
        raise InputError(f"suite list {path}: no [[record]] entries")
    return tuple(_entry(i, entry, path.parent, g) for i, entry in enumerate(entries, start=1))


def _from_folder(folder: Path, units: str | None, g: float) -> tuple[SuiteRecord, ...]:
    if (folder / SUITE_FILE).is_file():
        return _from_toml(folder / SUITE_FILE, g)
    if units is not None and units not in UNITS:
        raise InputError(f"units = {units!r} is not one of {', '.join(UNITS)}")
    records = []
    for path in sorted(folder.iterdir()):
        suffix = path.suffix.lower()
        if path.name.startswith(".") or not path.is_file():
            continue
        if suffix in (".at2", ".asc") or is_esm(path):
            record = _read(path, None, f"suite file {path.name}", g)
        elif suffix in TWO_COLUMN_SUFFIXES:
            record = _read(path, units, f"suite file {path.name}", g)
        else:
            continue
        records.append(SuiteRecord(path.stem, record, 1.0, path.resolve(), _sha256(path)))
    if not records:
        raise InputError(
            f"suite folder {folder}: no record files (.AT2, .ASC, or two-column "
            f"{'/'.join(TWO_COLUMN_SUFFIXES)} with units given)"
        )
    return tuple(records)


def load_suite(path, *, units: str | None = None, g: float = STANDARD_GRAVITY):
    """The records of a suite (a folder or a TOML list, see the module notes), in order, as a
    tuple of :class:`SuiteRecord`. ``units``: of the two-column files of a folder without a
    list. Names are unique (an InputError names the two entries)."""
    path = Path(path)
    if path.is_dir():
        records = _from_folder(path, units, g)
    elif path.is_file():
        if units is not None:
            raise InputError(
                f"suite list {path}: units are given per record in the list (units = ...)"
            )
        records = _from_toml(path, g)
    else:
        raise InputError(f"suite {path}: no such folder or file")
    seen: dict[str, int] = {}
    for i, entry in enumerate(records, start=1):
        if entry.name in seen:
            raise InputError(
                f"suite {path}: records {seen[entry.name]} and {i} are both named "
                f"{entry.name!r} (give each a name = ...)"
            )
        seen[entry.name] = i
    return records


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value!r} has no TOML form here")
        return repr(value)  # the shortest string that reads back to the same float
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    raise TypeError(f"{type(value).__name__} is not written to a suite list")


def suite_toml(entries, *, comment: str = "") -> str:
    """The text of a suite list: ``entries`` are dicts of :data:`RECORD_KEYS` (``parameters``
    a flat dict), written as ``[[record]]`` tables in order; floats to the digit that reads
    back exactly. ``comment``: lines put first, each prefixed ``# ``."""
    lines = [f"# {line}".rstrip() for line in comment.splitlines()]
    for entry in entries:
        lines += ["", "[[record]]"]
        for key in RECORD_KEYS[:-1]:
            if key in entry:
                lines.append(f"{key} = {_toml_value(entry[key])}")
        parameters = entry.get("parameters")
        if parameters:
            lines.append("[record.parameters]")
            lines += [f"{key} = {_toml_value(value)}" for key, value in parameters.items()]
    return "\n".join(lines).lstrip("\n") + "\n"
