"""The mesh-convergence study: the FEM model on meshes h, h/r, h/r^2, ... ([convergence] sizes,
or levels and ratio from [mesh] size), one case each (:func:`studies.sweep.run_sweep`): peak
rotation, collar stress and toe stress with the observed order and a Richardson estimate."""

from __future__ import annotations

from pathlib import Path

from ...fem.convergence import convergence_table
from .. import schema
from ..fem_study import FemStudy
from ..outcome import fem_answers, fem_model, outcome
from ..sweep import case_base, run_sweep


def mesh_sizes(data: dict, study) -> list[float]:
    """The sizes of [convergence] (:class:`studies.schema.Convergence`): given, or levels
    from [mesh] size refined by ratio."""
    conv = schema.parse_table("convergence", data.get("convergence", {}), study.source)
    if conv.sizes is not None:
        return list(conv.sizes)
    return [study.mesh_size * conv.ratio ** (conv.levels - 1 - k) for k in range(conv.levels)]


def cases(data: dict, study: FemStudy, study_path: Path) -> list[dict]:
    """One FEM case per mesh size, the coarsest first."""
    found = []
    for k, size in enumerate(mesh_sizes(data, study)):
        variant = schema.variant(data, {"mesh.size": size}, str(study_path))
        found.append(
            dict(case_base(study_path), study=variant, key=f"mesh-{k + 1}", kind="fem", size=size)
        )
    return found


def summarise(study: FemStudy, cases: list[dict], results: dict) -> dict:
    quantities = {
        "peak_rotation": lambda s: max(s["max_abs_theta_left"], s["max_abs_theta_right"]),
        "collar_max_utilisation": lambda s: s["collar_max_utilisation"],
        "edge_stress_max": lambda s: s["edge_stress_max"],
    }
    sizes = [c["size"] for c in cases]
    ratio = sizes[0] / sizes[1]
    table = {}
    for name, get in quantities.items():
        values = [get(results[c["key"]]["summary"]) for c in cases]
        table[name] = convergence_table(values, ratio)
    finest = results[cases[-1]["key"]]["summary"]
    models = [
        fem_model(
            f"FEM, mesh size {c['size'] * 1e3:.4g} mm",
            results[c["key"]]["summary"],
            study.rocking_alpha,
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
        "fem": {c["key"]: results[c["key"]]["summary"] for c in cases},
    }


def run(study_path: Path, out: Path, **options) -> dict:
    """The mesh-convergence study: the FEM on a sequence of meshes."""
    return run_sweep(
        study_path, out, kind="mesh-convergence", cases=cases, summarise=summarise, **options
    )
