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
"rad/s", "m/s^2", "Pa m^0.5"; "-" for a plain ratio and "" for counts, yes/no and words. The
units of every registered class's keys are :func:`declared_units`, the one table the display
units are found from (``colonna.studies.units.unit_of``).

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
    {
        "",
        "-",
        "rad",
        "rad/s",
        "m",
        "s",
        "Pa",
        "N",
        "N m",
        "N/m",
        "N/m^3",
        "J",
        "kg",
        "m/s^2",
        "Pa m^0.5",  # a stress intensity
    }
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


# The quantities the model runs' summaries share (the rigid SDOF block's RockingSummary, the
# multibody model's MultibodySummary, the FEM's FemRunSummary), each unit and meaning declared
# once here; a summary class declares its field (name, type, place, presence) with shared(key).
SHARED: dict[str, tuple[str, str]] = {
    "verdict": ("", "the motion and, with collars, their state, in words"),
    "overturned": ("", "whether the column (or block) overturned"),
    "mode": ("", "safe, after-impact or without-impact (overturning)"),
    "motion": ("", "no uplift, rocking or overturned"),
    "status": ("", "how the run ended, in words: completed, overturned: ..., or a blow-up"),
    "impacts": ("", "impacts (a body's rotation through zero)"),
    "max_abs_theta": ("rad", "largest |theta| reached (pi/2: overturned)"),
    "max_abs_theta_over_alpha": ("-", "largest |theta| over alpha"),
    "max_abs_theta_left": ("rad", "largest |theta| of the left half (or column)"),
    "max_abs_theta_right": ("rad", "largest |theta| of the right half (or column)"),
    "overturn_time": ("s", "time of overturning (None: it stands)"),
    "p": ("rad/s", "frequency parameter p = sqrt(m g R / J0)"),
    "alpha": ("rad", "slenderness angle alpha = atan(b / h)"),
    "restitution_housner": ("-", "Housner's nu = 1 - 1.5 sin^2 alpha"),
    "top_load": ("N", "dead load on the capital (the top of the block)"),
    "collar_max_utilisation": ("-", "largest utilisation of any collar (0: no collars)"),
    "collar_first_yield_time": (
        "s",
        "first time any collar reached f_y (None: none did; the FEM's: an output time)",
    ),
    "collar_state": ("", "elastic, yielded or fractured (any collar's)"),
    "collar_max_plastic_strain": ("-", "largest |plastic strain| of any collar"),
    "collar_plastic_work": ("J", "work done yielding the collars"),
    "collar_max_fibre_strain": ("-", "largest extreme-fibre strain of any collar"),
    "collar_ductility_demand": ("-", "largest fibre strain over f_y / E of any collar"),
    "collar_fractured": ("", "whether a collar broke"),
    "collar_fracture_time": (
        "s",
        "time the first collar broke (None: none did; the FEM's: an output time)",
    ),
    "energy_error_max": ("-", "largest energy balance error / energy scale"),
    "dt": ("s", "time step"),
    "steps": ("", "time steps taken"),
    "wall_seconds": ("s", "wall-clock time of the run"),
}


def shared(
    key: str,
    *,
    omit_when_none: bool = False,
    present_with: str | None = None,
    default: Any = dataclasses.MISSING,
) -> Any:
    """The :func:`quantity` of a key the models' summaries share (:data:`SHARED`: its unit and
    meaning), with this summary's presence rule and default."""
    unit, doc = SHARED[key]
    return quantity(
        unit, doc, omit_when_none=omit_when_none, present_with=present_with, default=default
    )


@dataclasses.dataclass(frozen=True, kw_only=True)
class CollarPeaks:
    """What a rigid model's per-collar summary opens with (the SDOF block's springs, the
    multibody model's frame collars), in this order."""

    y: float = quantity("m", "height of the collar above the base")
    max_stress: float = quantity("Pa", "largest extreme-fibre stress of the collar")
    max_utilisation: float = quantity("-", "largest extreme-fibre stress over f_y")
    first_yield_time: float | None = quantity(
        "s", "first time the stress reached f_y (None: never)"
    )


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
