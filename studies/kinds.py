"""The registry of study kinds: the one table a kind is added to.

Each kind is registered by name, with its runner and its report writer as ``"module:function"``
strings under ``colonna.studies``, imported only when a study of that kind runs. The study
file's ``[study] kind`` is checked against these names (:mod:`studies.schema`) and the driver
(:mod:`studies.driver`) runs them. Adding a kind is one module with a ``run`` function
(``run(study_path, out, *, workers, scheduler, progress, force, **options) -> summary``) and a
report writer (``write(out) -> index.html``), and one line here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class StudyKind:
    """A study kind: where its runner and its report writer live, and which summary keys the
    command line prints (``short``)."""

    run: str  # "module:function" under colonna.studies
    report: str  # "module:function" under colonna.studies
    short: tuple[str, ...] = ()
    ground_motion: bool = True  # its [ground] is one motion (not a grid of them, nor none)
    tables: tuple[str, ...] = ()  # the tables of its own it reads (of KIND_TABLES)


# tables that only some kinds read: in a study of another kind they would be read by nothing
KIND_TABLES = ("grid", "convergence", "free_rocking")


KINDS = {
    "cross-check": StudyKind("crosscheck:run", "crosscheck:write_report", ("outcome", "verdict")),
    "collar-design": StudyKind(
        "collar_design:run",
        "collar_design:write_report",
        ("outcome", "design_adequate", "fem_collar_max_utilisation"),
    ),
    "spectrum-crosscheck": StudyKind(
        "spectrum_crosscheck:run",
        "spectrum_crosscheck:write_report",
        ("outcome", "agreement_fem_multibody", "agreement_fem_sdof"),
        ground_motion=False,
        tables=("grid",),
    ),
    "free-rocking": StudyKind(
        "free_rocking:run",
        "free_rocking:write_report",
        ("outcome", "fem_ratio_study_stone", "multibody_ratio", "restitution_housner"),
        ground_motion=False,
        tables=("free_rocking",),
    ),
    "mesh-convergence": StudyKind(
        "sweeps:run_mesh_convergence",
        "report:write_convergence_report",
        ("outcome",),
        tables=("convergence",),
    ),
    "solid-vs-cracked": StudyKind(
        "sweeps:run_solid_vs_cracked", "report:write_variants_report", ("outcome",)
    ),
    "zhang-makris": StudyKind(
        "zhang_makris:run",
        "zhang_makris:write_report",
        ("outcome", "boundaries"),
        ground_motion=False,
    ),
}


def kind_of_package(package: str) -> str:
    """The name of the kind whose package is ``package`` (a kind's message that points to
    another kind finds its name here, so that renaming a kind is one line of this table)."""
    for name, kind in KINDS.items():
        if getattr(kind, "package", str(kind.run).split(":")[0]) == package:
            return name
    raise KeyError(package)
