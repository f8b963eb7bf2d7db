"""Typed results: a model run's summary as a frozen dataclass whose every field declares its SI
unit, and the plain dict (summary.json, the command line's ``--json``) made from it.

A summary class is a frozen, keyword-only dataclass registered with :func:`typed_result`, each
field a :func:`quantity` (the dataclass decorator written out, so that a type checker that
cannot follow an import still reads the class as a dataclass)::

    @typed_result
    @dataclass(frozen=True, kw_only=True)
    class RockingSummary:
        max_abs_theta: float = quantity("rad", "largest |theta| reached")
        collar_note: str | None = quantity("", "...", omit_when_none=True, default=None)

Units are SI symbols (:data:`SI_UNITS`): "rad", "m", "s", "Pa", "N", "N m", "N/m", "J", "kg",
"rad/s", "m/s^2"; "-" for a plain ratio and "" for counts, yes/no and words. The units of every
registered class's keys are :func:`declared_units`, the one table the display units are found
from (``colonna.studies.units.unit_of``).

:func:`to_dict` gives the summary as the models always gave it (keys in field order, Python
numbers, a NaN kept as NaN), :func:`to_json` the same with NaN and inf as None (JSON has
neither), as summary.json holds it. A key can be left out of the dict: ``omit_when_none`` leaves
a field out while it is None, ``present_with="name"`` writes a field (None or not) exactly when
the field ``name`` is written (e.g. a first-yield time, None where no collar yields, present
whenever the collars are).

Nothing here knows a physics package: the summaries live with the models (rigid, fem) and
register themselves when their module is imported.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, TypeVar

import numpy as np

# the units a field may declare: SI symbols, "-" a plain ratio, "" counts, yes/no and words
SI_UNITS = frozenset(
    {"", "-", "rad", "rad/s", "m", "s", "Pa", "N", "N m", "N/m", "N/m^3", "J", "kg", "m/s^2"}
)

UNIT = "unit"
DOC = "doc"
OMIT_WHEN_NONE = "omit_when_none"
PRESENT_WITH = "present_with"

_Class = TypeVar("_Class", bound=type)

# the registered summary classes, in the order their modules were imported
_RESULTS: list[type] = []


def quantity(
    unit: str,
    doc: str,
    *,
    omit_when_none: bool = False,
    present_with: str | None = None,
    default: Any = dataclasses.MISSING,
) -> Any:
    """A field of a typed result: its SI ``unit`` (one of :data:`SI_UNITS`) and what it is
    (``doc``). ``omit_when_none``: the key is left out of the dict while the value is None;
    ``present_with``: the key is written exactly when that other field's key is."""
    if unit not in SI_UNITS:
        raise ValueError(f"unit {unit!r} is not one of {sorted(SI_UNITS)}")
    if not doc:
        raise ValueError("a quantity says what it is (doc)")
    metadata = {UNIT: unit, DOC: doc, OMIT_WHEN_NONE: omit_when_none, PRESENT_WITH: present_with}
    return dataclasses.field(default=default, metadata=metadata)


def typed_result(cls: _Class) -> _Class:
    """Register the units of ``cls``, a frozen dataclass whose every field is a
    :func:`quantity` (a key of two registered classes has one unit, or this raises TypeError)."""
    if not dataclasses.is_dataclass(cls) or not cls.__dataclass_params__.frozen:  # type: ignore[attr-defined]
        raise TypeError(f"{cls.__name__} is not a frozen dataclass")
    fields = dataclasses.fields(cls)
    names = {f.name for f in fields}
    for f in fields:
        if UNIT not in f.metadata:
            raise TypeError(f"{cls.__name__}.{f.name} declares no unit: use quantity()")
        other = f.metadata[PRESENT_WITH]
        if other is not None and other not in names:
            raise TypeError(f"{cls.__name__}.{f.name} is present with {other!r}: not a field")
    known = declared_units()
    for key, unit in units_of(cls).items():
        if known.get(key, unit) != unit:
            raise TypeError(
                f"{cls.__name__}.{key} in {unit!r}, but a registered result has it in "
                f"{known[key]!r}: one key, one unit"
            )
    if cls not in _RESULTS:
        _RESULTS.append(cls)
    return cls


def registered() -> tuple[type, ...]:
    """The typed-result classes registered so far (their modules imported)."""
    return tuple(_RESULTS)


def units_of(cls: type) -> dict[str, str]:
    """Key -> SI unit of every field of a typed result class, in field order."""
    return {f.name: f.metadata[UNIT] for f in dataclasses.fields(cls)}


def docs_of(cls: type) -> dict[str, str]:
    """Key -> what the field is, in field order."""
    return {f.name: f.metadata[DOC] for f in dataclasses.fields(cls)}


def declared_units() -> dict[str, str]:
    """Key -> SI unit of every key of every registered class (one unit per key)."""
    units: dict[str, str] = {}
    for cls in _RESULTS:
        units.update(units_of(cls))
    return units


def to_dict(obj: Any) -> dict[str, Any]:
    """The summary dict of a typed result: keys in field order, those left out that the
    fields' ``omit_when_none`` / ``present_with`` leave out; numpy scalars as Python numbers,
    tuples as lists, nested typed results as dicts; NaN and inf kept."""
    return _written(obj, finite=False)


def to_json(obj: Any) -> dict[str, Any]:
    """:func:`to_dict` as plain JSON: NaN and inf as None (as summary.json holds them)."""
    return _written(obj, finite=True)


def selected(summary: Any, cls: type, keys: tuple[str, ...]) -> dict[str, Any]:
    """The ``keys`` of a summary (a typed result of ``cls`` or its dict, e.g. read back from
    disk), in that order, a key the summary leaves out None. Each key must be a quantity of
    ``cls`` (a KeyError naming the others): a report's selection cannot name a key no run
    gives."""
    names = [f.name for f in dataclasses.fields(cls)]
    unknown = [key for key in keys if key not in names]
    if unknown:
        raise KeyError(f"not quantities of {cls.__name__}: {unknown}")
    data = summary if isinstance(summary, Mapping) else to_dict(summary)
    return {key: data.get(key) for key in keys}


def _written(obj: Any, finite: bool) -> dict[str, Any]:
    fields = dataclasses.fields(obj)
    values = {f.name: getattr(obj, f.name) for f in fields}
    present: dict[str, bool] = {}

    def is_present(f: dataclasses.Field) -> bool:
        if f.name not in present:
            other = f.metadata[PRESENT_WITH]
            if other is not None:
                present[f.name] = is_present(next(g for g in fields if g.name == other))
            else:
                present[f.name] = not (f.metadata[OMIT_WHEN_NONE] and values[f.name] is None)
        return present[f.name]

    return {f.name: _plain(values[f.name], finite) for f in fields if is_present(f)}


def _plain(value: Any, finite: bool) -> Any:
    """Python data from a field's value (numpy scalars and arrays, tuples, nested results)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return _written(value, finite)
    if isinstance(value, Mapping):
        return {str(k): _plain(v, finite) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, finite) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist(), finite)
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        number = float(value)
        return None if finite and not math.isfinite(number) else number
    return value
