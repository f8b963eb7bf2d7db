"""The mesh-convergence study: the FEM model on meshes h, h/r, h/r^2, ... ([convergence] sizes,
or levels and ratio from [mesh] size), one case each (:func:`studies.sweep.run_sweep`): peak
rotation, collar stress and toe stress with the observed order and a Richardson estimate."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ...fem.convergence import convergence_table
from ..executor import RunOptions
from ..fem_study import FemStudy, case_of
from ..guard import halved_steps
from ..outcome import (
    fem_answers,
    fem_model,
    fem_stop,
    not_applicable,
    outcome,
    rocking_block,
    unless_stopped,
    without_stopping_angles,
)
from ..study import Study
from ..sweep import run_sweep
from ..work import FemWork, ensembles_work


def mesh_sizes(study: Study) -> list[float]:
    """The sizes (m) of [convergence] (:class:`.schema.Convergence`): given, or levels
    from [mesh] size refined by ratio."""
    conv = study.spec.convergence
    if conv.sizes is not None:
        return list(conv.sizes)
    size = study.fem.mesh_size
    return [size * conv.ratio ** (conv.levels - 1 - k) for k in range(conv.levels)]


def cases(study: Study) -> list[dict]:
    """One FEM case per mesh size, the coarsest first."""
    return [
        case_of(replace(study.fem, mesh_size=size), key=f"mesh-{k + 1}", kind="fem", size=size)
        for k, size in enumerate(mesh_sizes(study))
    ]


FEWER = ", fewer or coarser [convergence] sizes, fewer [run] replicas"  # its ways to ask less


def fem_work(study: Study) -> FemWork:
    """The FEM work of the study (:func:`studies.driver.check_work`): its run with its replicas
    on every mesh."""
    return ensembles_work(replace(study.fem, mesh_size=size) for size in mesh_sizes(study))


def summarise(study: FemStudy, cases: list[dict], results: dict) -> dict:
    quantities = {
        "peak_rotation": lambda s: max(s["max_abs_theta_left"], s["max_abs_theta_right"]),
        "collar_max_utilisation": lambda s: s["collar_max_utilisation"],
        "edge_stress_max": lambda s: s["edge_stress_max"],
        "toe_pressure_winkler": lambda s: s["toe_pressure_winkler"],
    }
    sizes = [c["size"] for c in cases]
    ratio = sizes[0] / sizes[1]
    table = {}
    for name, get in quantities.items():
        values = [get(results[c["key"]]["summary"]) for c in cases]
        table[name] = convergence_table(values, ratio)
    # a run that overturned stopped at its overturning angle: its peak rotation is no value of
    # the mesh, and no order is observed from it
    stops = [fem_stop("the FEM on this mesh", results[c["key"]]["summary"]) for c in cases]
    if any(stops):
        note = not_applicable(*(s for s in stops if s))
        table["peak_rotation"] = {
            **{k: note for k in table["peak_rotation"]},
            "values": [
                unless_stopped(v, s) for v, s in zip(table["peak_rotation"]["values"], stops)
            ],
        }
    finest = results[cases[-1]["key"]]["summary"]
    models = [
        fem_model(
            f"FEM, mesh size {c['size'] * 1e3:.4g} mm",
            results[c["key"]]["summary"],
            study.rocking_alpha,
            rocking_block(study.cracked, bool(study.collars)),
        )
        for c in cases
    ]
    answers = fem_answers(
        finest,
        "the mesh-convergence study runs the FEM alone; the "
        "cross-check study compares it with the rigid models",
        collars=study.collars,
    )
    return {
        "study": study.name,
        "outcome": outcome(models, answers),
        "sizes": sizes,
        "ratio": ratio,
        "convergence": table,
        "dofs": [results[c["key"]]["summary"]["dofs"] for c in cases],
        # the bed: its stiffness per unit area the same on every mesh (issue 38)
        "bed": {"stiffness": study.bed.stiffness, "source": study.bed.source},
        "fem": {
            c["key"]: without_stopping_angles(results[c["key"]]["summary"], s)
            for c, s in zip(cases, stops)
        },
        "halved_steps": halved_steps(
            [
                (
                    f"the FEM run on the mesh of size {c['size'] * 1e3:.4g} mm",
                    results[c["key"]]["summary"],
                )
                for c in cases
            ]
        ),
    }


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """The mesh-convergence study (:func:`studies.study.load`): the FEM on a sequence of
    meshes."""
    return run_sweep(study, out, cases=cases, summarise=summarise, options=options)
