"""The registry of study kinds: the one table a kind is added to.

Each kind is registered by name with its package under ``colonna.studies`` (imported only when
a study of that kind runs) and what the rest of colonna must know of it without importing it:
the summary keys the command line prints, whether its [ground] is one motion, the tables of
its own it reads, the command-line options it takes. The study file's ``[study] kind`` is
checked against these names (:mod:`studies.schema`) and the driver (:mod:`studies.driver`)
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
are expected to stop early). Adding a kind is that package
and one line here (docs/contributing.md; tests/test_kinds.py adds one).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from types import ModuleType


@dataclass(frozen=True)
class StudyKind:
    """A study kind: its package under ``colonna.studies``, what of its summary the command line
    prints (``short``: "outcome", the report's questions and answers, or "design", the
    fragility's probabilities at the design intensity; studies.cli.short_summary), whether its
    [ground] is one motion (``ground_motion``; not a grid of them, nor none), the tables of
    its own it reads (``tables``, of :data:`KIND_TABLES`), the command-line options it takes
    (``options``), whether it needs a [column] (``column``) and whether it sets the pulse's
    amplitude and frequency itself (``sets_pulse``: a study file gives only its shape);
    ``command``: the help line of a
    command of its own, ``colonna <kind>``, whose options its package's ``add_arguments(parser)``
    adds and whose ``run_command(args)`` runs it."""

    package: str
    short: tuple[str, ...] = ()
    ground_motion: bool = True
    tables: tuple[str, ...] = ()
    options: tuple[str, ...] = ()
    column: bool = True
    sets_pulse: bool = False
    command: str = ""  # the help of a fast command of its own (colonna <kind>), if it has one
    per_case: tuple[tuple[str, str], ...] = ()  # inputs its cases set: (table.key, the rule)

    def per_case_rules(self) -> dict[str, str]:
        """The ``table.key`` inputs the kind's cases set themselves, each with its rule: the
        record of the inputs gives the rule, not the file's value that no case used."""
        return dict(self.per_case)

    def module(self) -> ModuleType:
        """The kind's package (imported on first use)."""
        return importlib.import_module(f"{__package__}.{self.package}")


# tables that only some kinds read: in a study of another kind they would be read by nothing
KIND_TABLES = ("grid", "convergence", "free_rocking", "fragility")


KINDS = {
    "cross-check": StudyKind("crosscheck", ("outcome",)),
    "collar-design": StudyKind("collar_design", ("outcome",)),
    "spectrum-crosscheck": StudyKind(
        "spectrum_crosscheck",
        ("outcome",),
        ground_motion=False,
        tables=("grid",),
        options=("grid",),
        sets_pulse=True,
    ),
    "free-rocking": StudyKind(
        "free_rocking",
        ("outcome",),
        ground_motion=False,
        tables=("free_rocking",),
        per_case=(("run.initial_tilt", "free_rocking.tilt_fractions x alpha, one per case"),),
    ),
    "mesh-convergence": StudyKind("mesh_convergence", ("outcome",), tables=("convergence",)),
    "solid-vs-cracked": StudyKind("solid_vs_cracked", ("outcome",)),
    "zhang-makris": StudyKind("zhang_makris", ("outcome",), ground_motion=False, column=False),
    "fragility": StudyKind(
        "fragility",
        ("design",),
        ground_motion=False,
        tables=("fragility",),
        command="fragility of the SDOF alone over a record suite (IDA or stripes), fast: the fits",
    ),
}

DEFAULT_KIND = "cross-check"  # a study file without [study] kind


def kind_of_package(package: str) -> str:
    """The name of the kind whose package is ``package`` (a kind's message that points to
    another kind finds its name here, so that renaming a kind is one line of this table)."""
    for name, kind in KINDS.items():
        if kind.package == package:
            return name
    raise KeyError(package)
