"""The solid-vs-cracked study: the same column uncracked, cracked without collars and cracked
with its collars, FEM and rigid for each (:func:`studies.sweep.run_sweep`), all under the
study's ground motion (its ratios refer to the half column of the cracked study)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ..executor import RunOptions
from ..fem_study import FemStudy, case_of, from_spec, rocking_alpha
from ..guard import halved_steps
from ..outcome import (
    fem_answers,
    fem_model,
    fem_stop,
    model_outcome,
    outcome,
    overturned_at,
    rocking_block,
    unless_stopped,
)
from ..study import Study
from ..sweep import run_sweep
from ..work import FemWork, ensembles_work

# each variant: (cracked, with the study's collars)
VARIANTS = {
    "solid": (False, False),
    "cracked": (True, False),
    "cracked-collars": (True, True),
}
# each variant's column in words
COLUMNS = {
    "solid": "the solid column",
    "cracked": "the cracked column without collars",
    "cracked-collars": "the cracked column with collars",
}


def variant(study: Study, cracked: bool, collars: bool) -> FemStudy:
    """The study's column cracked or not, with or without its collars, shaken by the study's
    own ground motion (its ratios refer to the study's rocking body)."""
    spec = study.spec
    assert spec.column is not None  # the kind needs a column (studies.kinds)
    column = spec.column.model_copy(update={"cracked": cracked})
    changed = spec.model_copy(update={"column": column, "collar": spec.collar if collars else []})
    varied = from_spec(changed, study.source, study.base)
    return replace(varied, ground=study.fem.ground, vertical=study.fem.vertical)


def cases(study: Study) -> list[dict]:
    """A FEM and a rigid case per variant, each shaken by the study's own ground motion."""
    found = []
    for name, (cracked, collars) in VARIANTS.items():
        varied = variant(study, cracked, collars)
        for model in ("fem", "rigid"):
            found.append(case_of(varied, key=f"{name}-{model}", kind=model, variant=name))
    return found


FEWER = ", fewer [run] replicas"  # its way to ask for less FEM work (besides [run], [mesh])


def fem_work(study: Study) -> FemWork:
    """The FEM work of the study (:func:`studies.driver.check_work`): each variant's run with
    its replicas."""
    return ensembles_work(
        variant(study, cracked, collars) for cracked, collars in VARIANTS.values()
    )


def summarise(study: FemStudy, cases: list[dict], results: dict) -> dict:
    variants = VARIANTS
    rows = {}
    for name in variants:
        fem = results[f"{name}-fem"]["summary"]
        rigid = results[f"{name}-rigid"]
        rows[name] = {
            # a run that overturned stopped at its overturning angle (pi/2 for the SDOF)
            "fem_peak_rotation": unless_stopped(
                max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]),
                fem_stop("the FEM", fem),
            ),
            "fem_overturned": fem["overturned"],
            "rigid_peak_rotation": unless_stopped(
                rigid["max_abs_theta"],
                overturned_at("the SDOF", rigid["overturned"], rigid.get("overturn_time")),
            ),
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
        block = rocking_block(cracked, collared and bool(study.collars))
        models.append(fem_model(f"FEM, {label}", fem, alpha, block))
        models.append(
            model_outcome(
                f"SDOF, {label}",
                rigid["overturned"],
                rigid["max_abs_theta"],
                rigid["alpha"],
                rigid.get("overturn_time"),
                block="half" if cracked else "column",
            )
        )
    as_built = results[f"{list(variants)[-1]}-fem"]["summary"]  # cracked, with collars
    answers = fem_answers(
        as_built,
        "this study compares the solid and cracked columns; the "
        "cross-check study compares the FEM with the rigid models",
        collars=study.collars,
    )
    # the answers are the as-built column's: its FEM model, the last variant's first
    stress_model = len(models) - 2
    return {
        "study": study.name,
        "outcome": outcome(models, answers, stress_model),
        "variants": rows,
        "halved_steps": halved_steps(
            [
                (f"the FEM run of {COLUMNS[name]}", results[f"{name}-fem"]["summary"])
                for name in variants
            ]
        ),
    }


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """The solid / cracked / cracked-with-collars variants of one column
    (:func:`studies.study.load`)."""
    return run_sweep(study, out, cases=cases, summarise=summarise, options=options)
