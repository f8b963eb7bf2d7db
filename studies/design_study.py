"""The collar-design study: the corrected design chart (Eq. 22-24) for the column, the design
numbers for the study's collar section at the study's pulse peak, and the check of the chosen
collars against the collar stress of the FEM run."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..core.errors import read_toml
from ..core.ground import peak_acceleration
from ..rigid.design import design_chart, design_collars
from .crosscheck import fem_case
from .executor import run_cases
from .fem_study import from_dict
from .outcome import fem_answers, fem_model, outcome
from .output import write_csv, write_json

ALPHAS = np.linspace(0.03, 0.4, 38)
RATIOS = np.linspace(0.05, 1.0, 39)


def run_design_study(
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
    if not study.collars:
        from ..core.errors import InputError

        raise InputError(f"{study_path}: a collar-design study needs at least one [[collar]]")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    # the FEM case first: a case saved from other inputs is refused before anything is written
    base = {"study": data, "source": str(study_path), "base": str(study_path.parent.resolve())}
    results = run_cases(
        fem_case,
        [dict(base, key="fem", kind="fem")],
        out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        force=force,
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
        "kind": "collar-design",
        "design": design,
        "design_alpha": block.alpha,
        "design_ag_over_g": a_g / block.g,
        "collars_provided": len(study.collars),
        "lateral_stiffness_provided": provided,
        "design_adequate": bool(provided >= design["required_stiffness"]),
        "fem_collar_max_utilisation": fem["collar_max_utilisation"],
        "fem_collar_first_yield_time": fem["collar_first_yield_time"],
        "fem_overturned": fem["overturned"],
        "fem_max_rotation": max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]),
        "fem_max_rotation_over_yield_rotation": max(
            fem["max_abs_theta_left"], fem["max_abs_theta_right"]
        )
        / design["yield_rotation"],
        "wall_seconds": time.perf_counter() - start,
        "outcome": outcome(
            [fem_model("FEM, deformable halves", fem, study.rocking_alpha)],
            fem_answers(
                fem,
                "the collar-design study runs the FEM alone; the "
                "cross-check study compares it with the rigid models",
            ),
        ),
    }
    write_json(out / "summary.json", summary)
    return summary
