"""The solid-vs-cracked study: the same column uncracked, cracked without collars and cracked
with its collars, FEM and rigid for each (:func:`studies.sweep.run_sweep`), all under the
study's ground motion (its ratios refer to the half column of the cracked study)."""

from __future__ import annotations

from pathlib import Path

from .. import schema
from ..fem_study import FemStudy, rocking_alpha
from ..outcome import fem_answers, fem_model, model_outcome, outcome
from ..sweep import case_base, run_sweep

# each variant: (cracked, with the study's collars)
VARIANTS = {
    "solid": (False, False),
    "cracked": (True, False),
    "cracked-collars": (True, True),
}


def cases(data: dict, study: FemStudy, study_path: Path) -> list[dict]:
    """A FEM and a rigid case per variant, each shaken by the study's own ground motion."""
    found = []
    for name, (cracked, collars) in VARIANTS.items():
        variant = schema.variant(
            data,
            {"column.cracked": cracked, **({} if collars else {"collar": schema.REMOVED})},
            str(study_path),
        )
        for model in ("fem", "rigid"):
            found.append(
                dict(
                    case_base(study_path),
                    study=variant,
                    ground_study=data,
                    key=f"{name}-{model}",
                    kind=model,
                    variant=name,
                )
            )
    return found


def summarise(study: FemStudy, cases: list[dict], results: dict) -> dict:
    variants = VARIANTS
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


def run(study_path: Path, out: Path, **options) -> dict:
    """The solid / cracked / cracked-with-collars variants of one column."""
    return run_sweep(
        study_path, out, kind="solid-vs-cracked", cases=cases, summarise=summarise, **options
    )
