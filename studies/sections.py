"""Typed sections of a study's summary.json, as its report reads them: each section a frozen
dataclass whose fields are the section's keys, each a :func:`colonna.core.quantities.quantity`
with its SI unit; a nested section a :func:`section` field. summary.json stays the file format
(the study writes it, these classes read it): :func:`read` builds a summary's sections from its
dict, and a key a section declares that the file lacks fails there, named (a field whose default
is :data:`ABSENT` may be left out: a collar note where no collar passed f_y, the fibre strains of
a column without collars). The values are kept as summary.json holds them: a number, None (JSON
null: NaN, or nothing to give) or the words that say where a run stopped ("not applicable: ...",
:data:`Stoppable`).

A report's table names its numbers by attribute, so that a type checker and the import check
both see a wrong name::

    ROWS = [("toe stress, study mesh", Ref(CrosscheckSummary, lambda s: s.fem.edge_stress_max),
             "MPa")]

:class:`Ref` walks its getter once over the declared classes (a name that is not a field raises
AttributeError when the report module is imported) to find the dotted key the page names
(``data-key="fem.edge_stress_max"``), and reads the value by attribute from the typed summary.
mypy checks the attribute chain too, except through the fields a section inherits from a class
of fem/ or rigid/ (mypy reads ``from ...fem`` as an unresolved import: those names are checked
when the Ref is made).

The study side writes from the same declarations: a section built as its class and turned into
the file's dict by :func:`written` (its keys in field order, those left out that the class
leaves out), or a dict checked by :func:`keyed` (its keys the class's, in its order).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import Any, Final, Generic, TypeVar

from ..core.errors import StaleResultsError
from ..core.quantities import OMIT_WHEN_NONE, PRESENT_WITH, UNIT, quantity

SECTION = "section"  # a field's metadata: the class of the nested section it holds
MANY = "many"  # a field's metadata: it holds a list (or a table by name) of such sections


class _Absent:
    """A key summary.json leaves out (None is JSON null, a value)."""

    _instance: _Absent | None = None

    def __new__(cls) -> _Absent:
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "ABSENT"

    def __bool__(self) -> bool:
        return False


ABSENT: Final = _Absent()

# a number of a run that may have stopped: the words saying where (studies.outcome.unless_stopped)
Stoppable = float | str | None

_Section = TypeVar("_Section")


def section(cls: type, doc: str, *, optional: bool = False, many: bool = False) -> Any:
    """A field holding a nested section of class ``cls`` (JSON null read as None where
    ``optional``: a section a run may not give, e.g. the toe refinement's); ``many``: a list of
    such sections (one per release tilt, ...) or a table of them by name (one per variant)."""
    metadata = {SECTION: cls, "doc": doc, "optional": optional, MANY: many}
    return dataclasses.field(default=None if optional else dataclasses.MISSING, metadata=metadata)


def absent(unit: str, doc: str) -> Any:
    """A quantity summary.json may leave out (read as :data:`ABSENT` where it does)."""
    return quantity(unit, doc, default=ABSENT)


def read(cls: type[_Section], data: Mapping[str, Any], where: str = "summary.json") -> _Section:
    """The section ``cls`` of a summary dict: every declared key read as it is (extra keys
    ignored: a section types what a report reads), a nested section read likewise. A declared
    key the dict lacks raises StaleResultsError naming it and the section (a summary of another
    version: run the study again), unless it may be left out (its default :data:`ABSENT`, or a
    run's quantity written only with another): then it reads as :data:`ABSENT`."""
    if not isinstance(data, Mapping):
        raise StaleResultsError(f"{where}: a table expected, found {type(data).__name__}")
    values: dict[str, Any] = {}
    for f in dataclasses.fields(cls):  # type: ignore[arg-type]
        name = f"{where}.{f.name}" if where != "summary.json" else f.name
        if f.name not in data:
            if _may_be_left_out(f):
                values[f.name] = ABSENT
                continue
            raise StaleResultsError(
                f"summary.json has no {name!r}: written by another version of colonna "
                "(run the study again with --force)"
            )
        value = data[f.name]
        nested = f.metadata.get(SECTION)
        if nested is not None and not (value is None and f.metadata.get("optional")):
            if f.metadata.get(MANY) and isinstance(value, Mapping):
                value = {k: read(nested, item, f"{name}.{k}") for k, item in value.items()}
            elif f.metadata.get(MANY):
                value = [read(nested, item, f"{name}.{k}") for k, item in enumerate(value)]
            else:
                value = read(nested, value, name)
        values[f.name] = value
    return cls(**values)


def _may_be_left_out(f: dataclasses.Field) -> bool:
    """A key summary.json may leave out: default ABSENT, or a run's quantity written only
    with another (quantities' omit_when_none, present_with)."""
    return (
        f.default is ABSENT
        or bool(f.metadata.get(OMIT_WHEN_NONE))
        or f.metadata.get(PRESENT_WITH) is not None
    )


def _field_names(cls: type) -> dict[str, dataclasses.Field]:
    return {f.name: f for f in dataclasses.fields(cls)}


class _Probe:
    """Stands for a section while a :class:`Ref`'s getter is walked: each attribute must be a
    declared field (AttributeError naming the class otherwise)."""

    def __init__(self, cls: type | None, parts: tuple[str, ...], unit: str | None = None):
        self._cls = cls
        self._parts = parts
        self._unit = unit

    def __getattr__(self, name: str) -> _Probe:
        if name.startswith("_"):
            raise AttributeError(name)
        where = ".".join(self._parts) or "the summary"
        if self._cls is None:
            raise AttributeError(f"{where} is a quantity, not a section: no {name!r} in it")
        fields = _field_names(self._cls)
        if name not in fields:
            raise AttributeError(
                f"{self._cls.__name__} ({where}) declares no {name!r}: one of {sorted(fields)}"
            )
        f = fields[name]
        nested = None if f.metadata.get(MANY) else f.metadata.get(SECTION)  # a list: no attribute
        return _Probe(nested, (*self._parts, name), f.metadata.get(UNIT))


class Ref(Generic[_Section]):
    """A quantity of a summary named by attribute: ``Ref(CrosscheckSummary, lambda s:
    s.fem.edge_stress_max)``. ``key`` is its dotted key in summary.json (checked against the
    declared sections when the Ref is made), ``unit`` the SI unit its field declares;
    :meth:`of` reads it from a typed summary, :meth:`present` says whether the summary has it
    (its section there, the key not left out)."""

    def __init__(self, cls: type[_Section], get: Callable[[_Section], Any]):
        probe = get(_Probe(cls, ()))  # type: ignore[arg-type]
        if not isinstance(probe, _Probe) or not probe._parts:
            raise TypeError(f"a Ref's getter reads an attribute of {cls.__name__}")
        self.key = ".".join(probe._parts)
        self.unit = probe._unit  # the SI unit its field declares (None: a section)
        self._get = get

    def of(self, summary: _Section) -> Any:
        """The value as summary.json holds it (AttributeError where its section is None)."""
        return self._get(summary)

    def present(self, summary: _Section) -> bool:
        """Whether ``summary`` has the quantity: its sections there, its key not left out."""
        node: Any = summary
        for part in self.key.split("."):
            if node is None:
                return False
            node = getattr(node, part)
        return node is not ABSENT

    def __repr__(self) -> str:
        return f"Ref({self.key!r})"

    def __str__(self) -> str:
        """Its dotted key: a template joins it into the page's keys (``"variants." ~ n ~ "."
        ~ ref``)."""
        return self.key


class Resolved(str):
    """A row's dotted key with the value read by attribute from the typed summary: the page's
    ``num`` shows ``value`` (studies.report.num) and names ``key`` in its ``data-key``."""

    value: Any

    def __new__(cls, key: str, value: Any) -> Resolved:
        made = super().__new__(cls, key)
        made.value = value
        return made


def table(
    rows: list[tuple[str, Ref[_Section], str]], summary: _Section
) -> list[tuple[str, Resolved, str]]:
    """A Numbers table's rows for the page: (label, key with its value, unit) for each row whose
    quantity the summary has (:meth:`Ref.present`), in order."""
    return [
        (label, Resolved(ref.key, ref.of(summary)), unit)
        for label, ref, unit in rows
        if ref.present(summary)
    ]


def like(cls: type, name: str, *, left_out: bool = False) -> Any:
    """A field declared as ``cls``'s field ``name`` (its unit and what it is: one declaration),
    for a section that keeps a selection of a run's summary; ``left_out``: summary.json may
    leave it out (read as :data:`ABSENT`), as it may any key the run writes only with another."""
    f = _field_names(cls)[name]
    return dataclasses.field(
        default=ABSENT if left_out else dataclasses.MISSING, metadata=f.metadata
    )


def keys_of(cls: type) -> tuple[str, ...]:
    """The keys a section declares, in order (what a study writes of a run's summary)."""
    return tuple(f.name for f in dataclasses.fields(cls))


def written(value: Any) -> Any:
    """A section as summary.json holds it: its keys in field order, those left out that are
    :data:`ABSENT` or that the quantities' rules leave out (``omit_when_none`` while None,
    ``present_with`` a key left out), nested sections likewise (the inverse of :func:`read`);
    any other value as it is."""
    if isinstance(value, list):
        return [written(item) for item in value]
    if isinstance(value, dict):
        return {k: written(item) for k, item in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = dataclasses.fields(value)
        left_out = {
            f.name
            for f in fields
            if getattr(value, f.name) is ABSENT
            or (f.metadata.get(OMIT_WHEN_NONE) and getattr(value, f.name) is None)
        }
        left_out |= {f.name for f in fields if f.metadata.get(PRESENT_WITH) in left_out}
        return {f.name: written(getattr(value, f.name)) for f in fields if f.name not in left_out}
    return value


def keyed(cls: type, data: dict[str, Any]) -> dict[str, Any]:
    """``data``, a summary dict a study writes, checked against the section ``cls`` that reads
    it: its keys are the declared fields, in their order, none missing but those that may be
    left out (ValueError naming the difference): the writer and the reader share one list of
    keys."""
    names = [f.name for f in dataclasses.fields(cls)]
    undeclared = [key for key in data if key not in names]
    missing = [
        f.name for f in dataclasses.fields(cls) if f.name not in data and not _may_be_left_out(f)
    ]
    if undeclared or missing:
        raise ValueError(
            f"{cls.__name__}: keys written but not declared {undeclared}, declared but not "
            f"written {missing}"
        )
    if list(data) != [name for name in names if name in data]:
        raise ValueError(f"{cls.__name__}: keys written out of the declared order: {list(data)}")
    return data
