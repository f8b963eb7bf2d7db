"""The registry of study kinds: the one table a kind is added to.

Each kind is registered by name with its package under ``colonna.studies`` (imported only when
a study of that kind runs) and what the rest of colonna must know of it without importing it:
the summary keys the command line prints, whether its [ground] is one motion, the tables of
its own it reads (each a model of its package's ``schema`` module), the command-line options it
takes. The study file's ``[study] kind`` is checked against these names, and its tables with
the shared ones (:func:`studies.schema.study_model`), and the driver (:mod:`studies.driver`)
runs them.

A kind's package (as meshio has one per format) provides
  ``run(study, out, options) -> summary``
      its runner: ``study`` is the :class:`studies.study.Study` of the file (read and
      validated once), ``options`` how its cases run
      (:class:`studies.executor.RunOptions`), ``summary.json`` written into ``out``;
  ``write_report(out) -> index.html``
      its report, from what the run left on disk;
and where it has them, ``defaults(data) -> data`` (its own defaults of the file's tables,
validated with them), ``fem_work(study) -> FemWork`` with ``FEWER`` (the FEM work it will ask
for, checked before anything runs, and its ways to ask for less) and ``expected_work(study) ->
FemWork`` (that work as it is expected to run, for the study's estimate of time: where its runs
are expected to stop early); its tables' models in its module ``schema`` (``[fragility]`` is
:class:`studies.fragility.schema.Fragility`) and its command in its module ``command``
(``add_arguments(parser)``, ``run_command(args)``). Adding a kind is that package and one line
here, or one call of :func:`register` for a kind outside colonna (docs/contributing.md;
tests/test_kinds.py adds both).
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import ModuleType


@dataclass(frozen=True)
class StudyKind:
    """A study kind: its package under ``colonna.studies``, what of its summary the command line
    prints (``short``: "outcome", the report's questions and answers, or "design", the
    fragility's probabilities at the design intensity; studies.cli.short_summary), whether its
    [ground] is one motion (``ground_motion``; not a grid of them, nor none), the tables of
    its own it reads (``tables``: the table's name -> its model, a class of the package's module
    ``schema``; a study of another kind may not give them), the options of ``colonna study``
    it takes (``options``: the option's name -> its help; its package's ``parse_option(name,
    text)``, where it has one, reads its value: :func:`take_options`), whether it needs a
    [column] (``column``) and whether it sets the pulse's
    amplitude and frequency itself (``sets_pulse``: a study file gives only its shape);
    ``command``: the help line of a
    command of its own, ``colonna <kind>``, whose options its package's ``add_arguments(parser)``
    adds and whose ``run_command(args)`` runs it (its package's module ``command``); ``home``:
    the package its package is in ("": a top-level package, a kind outside colonna)."""

    package: str
    short: tuple[str, ...] = ()
    ground_motion: bool = True
    tables: Mapping[str, str] = field(default_factory=dict)
    options: Mapping[str, str] = field(default_factory=dict)
    column: bool = True
    sets_pulse: bool = False
    command: str = ""  # the help of a fast command of its own (colonna <kind>), if it has one
    per_case: tuple[tuple[str, str], ...] = ()  # inputs its cases set: (table.key, the rule)
    home: str = __package__ or ""

    def per_case_rules(self) -> dict[str, str]:
        """The ``table.key`` inputs the kind's cases set themselves, each with its rule: the
        record of the inputs gives the rule, not the file's value that no case used."""
        return dict(self.per_case)

    def module(self) -> ModuleType:
        """The kind's package (imported on first use)."""
        return importlib.import_module(f"{self.home}.{self.package}" if self.home else self.package)

    def table_models(self) -> dict:
        """Its tables' models (:attr:`tables`), from its package's module ``schema`` (imported
        here: the package with it)."""
        if not self.tables:
            return {}
        module = importlib.import_module(f"{self.module().__name__}.schema")
        return {name: getattr(module, model) for name, model in self.tables.items()}

    def command_module(self) -> ModuleType | None:
        """The module of its command (``colonna <kind>``; :attr:`command`), None without one."""
        if not self.command:
            return None
        return importlib.import_module(f"{self.module().__name__}.command")


KINDS = {
    "cross-check": StudyKind("crosscheck", ("outcome",)),
    "collar-design": StudyKind("collar_design", ("outcome",)),
    "spectrum-crosscheck": StudyKind(
        "spectrum_crosscheck",
        ("outcome",),
        ground_motion=False,
        tables={"grid": "Grid"},
        options={
            "grid": "NxM: the spectrum cross-check's grid, N omega ratios by M amplitude "
            "ratios (overrides [grid] points)"
        },
        sets_pulse=True,
    ),
    "free-rocking": StudyKind(
        "free_rocking",
        ("outcome",),
        ground_motion=False,
        tables={"free_rocking": "FreeRocking"},
        per_case=(("run.initial_tilt", "free_rocking.tilt_fractions x alpha, one per case"),),
    ),
    "mesh-convergence": StudyKind(
        "mesh_convergence", ("outcome",), tables={"convergence": "Convergence"}
    ),
    "solid-vs-cracked": StudyKind("solid_vs_cracked", ("outcome",)),
    "crack-extent": StudyKind("crack_extent", ("outcome",), tables={"crack_extent": "CrackExtent"}),
    "zhang-makris": StudyKind("zhang_makris", ("outcome",), ground_motion=False, column=False),
    "fragility": StudyKind(
        "fragility",
        ("design",),
        ground_motion=False,
        tables={"fragility": "Fragility"},
        command="fragility of the SDOF alone over a record suite (IDA or stripes), fast: the fits",
    ),
    "collar-layout": StudyKind(
        "collar_layout", ("answer",), ground_motion=False, tables={"layout": "Layout"}
    ),
}

DEFAULT_KIND = "cross-check"  # a study file without [study] kind


def register(name: str, kind: StudyKind) -> None:
    """Add the kind ``kind`` named ``name`` (its ``[study] kind``): what a line of
    :data:`KINDS` does, for a kind whose package is outside colonna (``home=""``). The schema
    of a study file follows (:func:`studies.schema.study_model`)."""
    if name in KINDS:
        raise ValueError(f"a study kind {name!r} is registered already")
    KINDS[name] = kind


def study_options() -> dict[str, str]:
    """The options of ``colonna study`` that kinds take (``--grid``): name -> its help, in the
    order of the registry."""
    found: dict[str, str] = {}
    for kind in KINDS.values():
        for name, text in kind.options.items():
            found.setdefault(name, text)
    return found


def take_options(name: str, given: dict) -> dict:
    """The options ``given`` to a study of kind ``name`` (option -> the command line's text, or
    a value from Python), each read by the kind's ``parse_option(option, text)`` where it is a
    text and the package has one (``--grid 8x8`` -> (8, 8)); an InputError for an option that
    the kind does not take, naming the kinds that do."""
    from ..core.errors import InputError

    kind = KINDS[name]
    values = {}
    for option, value in given.items():
        if option not in kind.options:
            takers = [other for other, k in KINDS.items() if option in k.options]
            raise InputError(
                f"--{option} applies to studies of kind {' or '.join(takers)}, not {name!r}"
            )
        parse = getattr(kind.module(), "parse_option", None)
        values[option] = parse(option, value) if parse and isinstance(value, str) else value
    return values


def kind_tables() -> tuple[str, ...]:
    """The tables that only some kinds read, in the order of the registry: in a study of another
    kind they would be read by nothing."""
    return tuple(dict.fromkeys(table for kind in KINDS.values() for table in kind.tables))


def kind_of_package(package: str) -> str:
    """The name of the kind whose package is ``package`` (a kind's message that points to
    another kind finds its name here, so that renaming a kind is one line of this table)."""
    for name, kind in KINDS.items():
        if kind.package == package:
            return name
    raise KeyError(package)
