"""The collar-design study: the corrected design chart (Eq. 22-24) for the column, the design
numbers for the study's collar section at the study's pulse peak, and the check of the chosen
collars against the collar stress of the FEM run."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...core.constants import DUCTILITY_LIMIT
from ...core.errors import InputError
from ...core.ground import peak_acceleration
from ...rigid.design import (
    FLAT_BAR_THICKNESSES,
    collar_trial,
    design_chart,
    design_collars,
    thinnest_passing,
)
from ..crosscheck.runner import fem_case
from ..executor import RunOptions, run_cases
from ..fem_study import case_of, study_of_case
from ..guard import check_fem_results, halved_steps
from ..models import run_multibody
from ..outcome import (
    fem_answers,
    fem_model,
    fem_stop,
    outcome,
    rocking_block,
    unless_stopped,
)
from ..output import write_csv, write_json
from ..study import Study
from ..work import FemWork
from ..work import fem_work as estimate_work

ALPHAS = np.linspace(0.03, 0.4, 38)
RATIOS = np.linspace(0.05, 1.0, 39)


FEWER = ", fewer [run] replicas"  # its way to ask for less FEM work (besides [run], [mesh])


def fem_work(study: Study) -> FemWork:
    """The FEM work of the collar design (:func:`studies.driver.check_work`): the study's run
    with its replicas (its band trials are rigid multibody runs)."""
    return estimate_work(study.fem, study.fem.replicas)


def run(given: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) the collar design of a study (:func:`studies.study.load`) into ``out``:
    the FEM run of the study's collars, the rigid multibody trials of flat bars, the design
    chart and ``summary.json``."""
    study = given.fem  # fails early
    if not study.collars:
        raise InputError(f"{given.source}: a collar-design study needs at least one [[collar]]")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    # the FEM case first: a case saved from other inputs is refused before anything is written
    thicknesses = sorted({*FLAT_BAR_THICKNESSES, study.collars[0].t})
    trial_cases = [
        case_of(study, key=f"band_{1e3 * t:g}mm", kind="band", t=t, ductility_limit=DUCTILITY_LIMIT)
        for t in thicknesses
    ]
    results = run_cases(
        fem_case,
        [case_of(study, key="fem", kind="fem")],
        out,
        run_options=options,
    )
    check_fem_results(results, out)
    trials = run_cases(
        band_case,
        trial_cases,
        out,
        run_options=options,
    )
    block = study.rocking_block
    collar = study.collars[0]
    a_g = peak_acceleration(study.ground)  # a pulse's amplitude or a record's peak
    design = design_collars(block, collar, a_g).to_dict()
    provided = sum(c.lateral_stiffness(block.b) for c in study.collars)
    chart = design_chart(
        block.b, study.stone.density, study.thickness, collar, ALPHAS, RATIOS, block.g
    )
    (out / "figures").mkdir(exist_ok=True)
    write_csv(
        out / "figures" / "design_chart.csv",
        {
            "alpha": np.repeat(ALPHAS, RATIOS.size),
            "ag_over_g": np.tile(RATIOS, ALPHAS.size),
            "required_stiffness": chart.ravel(),
        },
    )
    fem = results["fem"]["summary"]
    summary = {
        "study": study.name,
        "kind": given.kind,
        "design": design,
        "design_alpha": block.alpha,
        "design_ag_over_g": a_g / block.g,
        "collars_provided": len(study.collars),
        "lateral_stiffness_provided": provided,
        "design_adequate": bool(provided >= design["required_stiffness"]),
        "fem_collar_max_utilisation": fem["collar_max_utilisation"],
        "fem_collar_first_yield_time": fem["collar_first_yield_time"],
        "fem_overturned": fem["overturned"],
        # an FEM run that overturned stopped at its overturning angle: no rotation it reached
        "fem_max_rotation": unless_stopped(
            max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]), fem_stop("the FEM", fem)
        ),
        "fem_max_rotation_over_yield_rotation": unless_stopped(
            max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]) / design["yield_rotation"],
            fem_stop("the FEM", fem),
        ),
        "ductile_design": ductile_design(study, thicknesses, trial_cases, trials),
        "halved_steps": halved_steps([("the FEM run", fem)]),
        "wall_seconds": time.perf_counter() - start,
        "outcome": outcome(
            [
                fem_model(
                    "FEM, deformable halves",
                    fem,
                    study.rocking_alpha,
                    rocking_block(study.cracked, bool(study.collars)),
                )
            ],
            fem_answers(
                fem,
                "the collar-design study runs the FEM alone; the "
                "cross-check study compares it with the rigid models",
                study.collars,
            ),
        ),
    }
    write_json(out / "summary.json", summary)
    return summary


def band_case(case: dict, directory: str) -> dict:
    """The study's column and pulse in the rigid multibody model with every collar's band
    ``case["t"]`` thick (m) and plastic (N-M hinges, fracture at eps_u): its outcome
    (:func:`colonna.rigid.design.collar_trial`)."""
    from dataclasses import replace

    from ...rigid.multibody import history_columns

    study = study_of_case(case)
    collars = tuple(replace(c, t=case["t"], plastic=True) for c in study.collars)
    result = run_multibody(replace(study, collars=collars))
    write_csv(Path(directory) / "history.csv", history_columns(result))
    return {"t": case["t"], **collar_trial(result.summary(), case["ductility_limit"])}


def ductile_design(study, thicknesses, cases, trials) -> dict:
    """Beside the first-yield design: over flat-bar thicknesses of the study's band (its height
    h, heights and steel kept, collars plastic), the thinnest band whose fibres never reach f_y
    in the multibody run ("never yields"), and the thinnest with which no collar breaks and
    the ductility demand stays within the limit ("yields but holds"); each the thinnest from
    which every thicker band tried also passes. Whether the column stands is reported per
    band: collars tie the halves, they do not stop a pulse that overturns the whole column."""
    rows = [trials[c["key"]] for c in cases]
    t = np.array(thicknesses)
    return {
        "model": "rigid multibody, plastic collars (N-M hinges, fracture at eps_u)",
        "ductility_limit": DUCTILITY_LIMIT,
        "ductility_limit_source": "EN 1993-1-1:2005, 3.2.2(1): eps_u >= 15 eps_y",
        "eps_u": study.collars[0].eps_u,
        "band_height": study.collars[0].h,
        "study_t": study.collars[0].t,
        "trials": rows,
        "never_yields_t": thinnest_passing(t, [r["never_yields"] for r in rows]),
        "holds_t": thinnest_passing(t, [r["holds"] for r in rows]),
    }
