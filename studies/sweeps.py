"""Studies that sweep a column over variants: mesh convergence, and solid vs cracked.

Each variant is a case of :mod:`studies.executor` (saved as it completes, resumable, local or
Dask). ``[study] kind`` in the study file picks the study:

  mesh-convergence   the FEM model on meshes h, h/r, h/r^2, ... ([convergence] sizes, or levels
                     and ratio from [mesh] size): peak rotation, collar stress and toe stress with
                     the observed order and a Richardson estimate
  solid-vs-cracked   the same column uncracked, cracked without collars and cracked with its
                     collars, FEM and rigid for each, all under the study's ground motion (its
                     ratios refer to the half column of the cracked study)
"""

from __future__ import annotations

import time
from pathlib import Path

from ..core.errors import read_toml
from ..fem.convergence import convergence_table
from . import schema
from .crosscheck.runner import fem_case, rigid_case
from .executor import run_cases
from .fem_study import from_dict, rocking_alpha
from .guard import check_fem_results
from .outcome import fem_answers, fem_model, model_outcome, outcome
from .output import write_json

SWEEP_KINDS = ("mesh-convergence", "solid-vs-cracked")


def _runner(case: dict, directory: str) -> dict:
    return fem_case(case, directory) if case["kind"] == "fem" else rigid_case(case, directory)


def _base(data: dict, study_path: Path) -> dict:
    return {"source": str(study_path), "base": str(study_path.parent.resolve())}


def mesh_sizes(data: dict, study) -> list[float]:
    """The sizes of [convergence] (:class:`studies.schema.Convergence`): given, or levels
    from [mesh] size refined by ratio."""
    conv = schema.parse_table("convergence", data.get("convergence", {}), study.source)
    if conv.sizes is not None:
        return list(conv.sizes)
    return [study.mesh_size * conv.ratio ** (conv.levels - 1 - k) for k in range(conv.levels)]


def run_sweep_study(
    kind: str,
    study_path: Path,
    out: Path,
    *,
    workers=None,
    scheduler=None,
    progress: bool = True,
    force: bool = False,
) -> dict:
    study_path = Path(study_path)
    data = read_toml(study_path, "study file")
    study = from_dict(data, source=str(study_path), base=study_path.parent)  # fails early
    out = Path(out)
    start = time.perf_counter()
    if kind == "mesh-convergence":
        sizes = mesh_sizes(data, study)
        out.mkdir(parents=True, exist_ok=True)
        cases = []
        for k, size in enumerate(sizes):
            variant = schema.variant(data, {"mesh.size": size}, str(study_path))
            cases.append(
                dict(
                    _base(data, study_path),
                    study=variant,
                    key=f"mesh-{k + 1}",
                    kind="fem",
                    size=size,
                )
            )
        results = run_cases(
            _runner,
            cases,
            out,
            workers=workers,
            scheduler=scheduler,
            progress=progress,
            force=force,
        )
        check_fem_results(results, out)
        summary = _convergence_summary(study, cases, results)
    else:
        out.mkdir(parents=True, exist_ok=True)
        variants = {
            "solid": (False, False),
            "cracked": (True, False),
            "cracked-collars": (True, True),
        }
        cases = []
        for name, (cracked, collars) in variants.items():
            variant = schema.variant(
                data,
                {"column.cracked": cracked, **({} if collars else {"collar": schema.REMOVED})},
                str(study_path),
            )
            for kind_ in ("fem", "rigid"):
                cases.append(
                    dict(
                        _base(data, study_path),
                        study=variant,
                        ground_study=data,
                        key=f"{name}-{kind_}",
                        kind=kind_,
                        variant=name,
                    )
                )
        results = run_cases(
            _runner,
            cases,
            out,
            workers=workers,
            scheduler=scheduler,
            progress=progress,
            force=force,
        )
        check_fem_results(results, out)
        summary = _variants_summary(study, variants, results)
    summary["wall_seconds"] = time.perf_counter() - start
    summary["kind"] = kind
    write_json(out / "summary.json", summary)
    return summary


def _convergence_summary(study, cases, results) -> dict:
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


def _variants_summary(study, variants, results) -> dict:
    rows = {}
    for name in variants:
        fem = results[f"{name}-fem"]["summary"]
        rigid = results[f"{name}-rigid"]
        rows[name] = {
            "fem_peak_rotation": max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]),
            "fem_overturned": fem["overturned"],
            "rigid_peak_rotation": rigid["max_abs_theta"],
            "rigid_overturned": rigid["overturned"],
            "rigid_mode": rigid["mode"],
            "collar_max_utilisation": fem["collar_max_utilisation"],
            "edge_stress_ratio": fem["edge_stress_ratio"],
            "status": fem["status"],
        }
    models = []
    for name in variants:
        fem = results[f"{name}-fem"]["summary"]
        rigid = results[f"{name}-rigid"]
        label = name.replace("-", " with ").replace("cracked with collars", "cracked, with collars")
        cracked, collared = variants[name]
        alpha = rocking_alpha(study.width, study.height, cracked, collared and bool(study.collars))
        models.append(fem_model(f"FEM, {label}", fem, alpha))
        models.append(
            model_outcome(
                f"SDOF, {label}",
                rigid["overturned"],
                rigid["max_abs_theta"],
                rigid["alpha"],
                rigid.get("overturn_time"),
            )
        )
    as_built = results[f"{list(variants)[-1]}-fem"]["summary"]  # cracked, with collars
    answers = fem_answers(
        as_built,
        "this study compares the solid and cracked columns; the "
        "cross-check study compares the FEM with the rigid models",
        collars=study.collars,
    )
    return {"study": study.name, "outcome": outcome(models, answers), "variants": rows}


def run_mesh_convergence(study_path: Path, out: Path, **options) -> dict:
    """The mesh-convergence study: the FEM on a sequence of meshes."""
    return run_sweep_study("mesh-convergence", study_path, out, **options)


def run_solid_vs_cracked(study_path: Path, out: Path, **options) -> dict:
    """The solid / cracked / cracked-with-collars variants of one column."""
    return run_sweep_study("solid-vs-cracked", study_path, out, **options)
