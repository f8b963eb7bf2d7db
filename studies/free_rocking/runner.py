"""The free-rocking study: the energy lost at impact, measured cleanly.

The column is released from rest at a few tilts (no ground motion) and rocks freely. At every
impact the angular-velocity ratio is measured from the rotation peaks on either side through the
free-rocking energy (:mod:`colonna.rigid.impacts`), for the FEM model and the rigid multibody
model, beside Housner's 1 - 1.5 sin^2(alpha). The FEM is also run with other contact dampings and
meshes at the first tilt, to show what its value depends on.

    [free_rocking]
    tilt_fractions = [0.3, 0.6]     # release tilts, fractions of alpha (default [0.5])
    damping = [0.0, 0.2]            # extra contact dampings to try (default [0.0, 0.2])
    mesh_sizes = [0.075]            # extra mesh sizes to try, m (default: twice the study's)

alpha is that of the body that rocks: the whole column when it is solid or held by collars
(the halves then lock together), one half when a cracked column has no collars. The study's
[ground] must be pulse = "none" or left out; [run] duration defaults to 3 s.
"""

from __future__ import annotations

import copy
import math
import re
import statistics
import time
from dataclasses import replace
from pathlib import Path

from ...core.errors import InputError
from ...rigid.block import Block
from ...rigid.impacts import impact_ratios_from_peaks
from ..executor import RunOptions, run_cases
from ..fem_study import FemStudy, case_of, from_spec, study_of_case
from ..guard import check_fem_results, halved_steps, reliability
from ..models import run_multibody
from ..outcome import none_assessed, not_applicable, overturned_at
from ..output import write_csv, write_json
from ..study import Study
from ..work import FemWork
from ..work import fem_work as estimate_work


def defaults(data: dict) -> dict:
    """The study file's tables with this kind's own defaults (:func:`studies.study.load`
    validates a free-rocking study with them): [ground] pulse = "none" and [run] duration =
    3 s (a copy)."""
    data = copy.deepcopy(data)
    data.setdefault("ground", {"pulse": "none"})
    data.setdefault("run", {}).setdefault("duration", 3.0)
    return data


def free_rocking_case(case: dict, directory: str) -> dict:
    study = study_of_case(case)
    alpha = case["alpha"]
    tilt = case["tilt_fraction"] * alpha
    if case["kind"] == "fem":
        from ...fem.ensemble import band
        from ..models import run_fem

        replicas = run_fem(replace(study, initial_tilt=tilt))
        result = replicas[0]
        t, theta = result.history["t"], result.history["theta_left"]
        write_csv(
            Path(directory) / "history.csv",
            {"t": t, "theta_left": theta, "theta_right": result.history["theta_right"]},
        )
        # the first landing is chaotic: the ratio is a band over the replicas
        firsts, means = [], []
        for r in replicas:
            measured = impact_ratios_from_peaks(r.history["t"], r.history["theta_left"], alpha)
            firsts.append(float(measured.ratios[0]) if measured.ratios.size else None)
            means.append(measured.mean)
        first, mean = band(firsts), band(means)
        plain = impact_ratios_from_peaks(t, theta, alpha)  # replica 0, for the figure
        return {
            "tilt": tilt,
            "damping": case.get("damping"),
            "mesh_size": case.get("mesh_size"),
            "impact_times": plain.times.tolist(),
            "ratios": plain.ratios.tolist(),
            "ratio_first": first["median"],
            "ratio_first_band": first,
            "ratio_mean": mean["median"],
            "ratio_mean_band": mean,
            "replicas": len(replicas),
            "status": result.summary["status"],
            "energy_error_max": max(r.summary["energy_error_max"] for r in replicas),
            "fem_runs": [reliability(r.summary) for r in replicas],
            # the ensemble's step, and whether it was halved (run_ensemble's reruns)
            "dt": result.summary["dt"],
            "step_halvings": result.summary.get("step_halvings", 0),
            "step_note": result.summary.get("step_note"),
            "wall_seconds": result.summary["wall_seconds"],
        }
    result = run_multibody(replace(study, initial_tilt=tilt))
    t, theta = result.time, result.theta[:, 0]
    write_csv(
        Path(directory) / "history.csv",
        {"t": t, "theta_left": theta, "theta_right": result.theta[:, -1]},
    )
    measured = impact_ratios_from_peaks(t, theta, alpha)
    return {
        "tilt": tilt,
        "damping": case.get("damping"),
        "mesh_size": case.get("mesh_size"),
        "impact_times": measured.times.tolist(),
        "ratios": measured.ratios.tolist(),
        "ratio_first": float(measured.ratios[0]) if measured.ratios.size else None,
        "ratio_mean": measured.mean,
        "status": result.status,
        "impulse_ratios": result.impact_velocity_ratios(0)[:10].tolist(),
        "energy_error_max": result.summary()["energy_error_max"],
    }


# a case's velocity ratios: measured from the rotation peaks either side of each impact
RATIO_KEYS = (
    "ratios",
    "ratio_first",
    "ratio_first_band",
    "ratio_mean",
    "ratio_mean_band",
    "impulse_ratios",
)


def case_stop(key: str, result: dict) -> str | None:
    """Where a case's run overturned (:func:`studies.outcome.overturned_at`, the time from its
    status), None where it did not: an FEM case's replicas, a multibody case's one run."""
    statuses = (
        [r["status"] for r in result["fem_runs"]] if "fem_runs" in result else [result["status"]]
    )
    over = [str(s) for s in statuses if str(s).startswith("overturned")]
    times = [float(m.group(1)) for s in over if (m := re.search(r"t = ([-+0-9.eE]+) s", s))]
    name = "the FEM" if key.startswith("fem") else "the multibody model"
    return overturned_at(
        name, len(over), float(statistics.median(times)) if times else None, len(statuses)
    )


def without_stopped_ratios(key: str, result: dict) -> dict:
    """A case's result whose velocity ratios (:data:`RATIO_KEYS`) say not applicable where its
    run overturned: the rotation peak after its last impact is then the angle it stopped at."""
    note = not_applicable(case_stop(key, result))
    if note is None:
        return result
    return {k: (note if k in RATIO_KEYS else v) for k, v in result.items()}


def _base_study(study: Study) -> FemStudy:
    """The column released from rest: the study's FEM study, its tilt 0.01 rad where the file
    gives none (each case sets its own)."""
    spec = study.spec
    if study.data["ground"] != {"pulse": "none"}:
        raise InputError(
            f"{study.source}: a free-rocking study has no ground motion: "
            "ground.pulse = 'none' (or leave [ground] out)"
        )
    if "initial_tilt" not in study.data["run"]:  # replaced per case
        spec = spec.model_copy(update={"run": spec.run.model_copy(update={"initial_tilt": 0.01})})
    return from_spec(spec, study.source, study.base)


def _mesh_sizes(study: Study, fem: FemStudy) -> list[float]:
    """The mesh sizes (m) of its mesh variants: [free_rocking] mesh_sizes, default 2h."""
    body_width = fem.width / (2.0 if fem.cracked else 1.0)
    sizes = study.spec.free_rocking.mesh_sizes or [min(2.0 * fem.mesh_size, body_width)]
    if max(sizes) > body_width * (1.0 + 1e-9):
        raise InputError(
            f"{study.source}: free_rocking.mesh_sizes = {sizes!r} m: each must be at "
            f"most {body_width:g} m (the width of one half)"
        )
    return sizes


FEWER = ", fewer [free_rocking] variants, fewer [run] replicas"  # its ways to ask for less


def fem_work(study: Study) -> FemWork:
    """The FEM work of a free-rocking study (:func:`studies.driver.check_work`): a run per
    tilt, per damping variant and per mesh variant, each with the study's replicas."""
    fem = _base_study(study)
    models: dict = {}  # the model of each mesh, built once
    table = study.spec.free_rocking
    work = estimate_work(fem, fem.replicas * len(table.tilt_fractions), models=models)
    for damping in table.damping:
        varied = replace(fem, contact=replace(fem.contact, damping=damping))
        work += estimate_work(varied, fem.replicas, models=models)
    for size in _mesh_sizes(study, fem):
        work += estimate_work(replace(fem, mesh_size=size), fem.replicas, models=models)
    return work


def run(given: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) a free-rocking study (:func:`studies.study.load`) into ``out``: the
    column released from each tilt in the FEM and the rigid multibody model, the FEM's damping
    and mesh variants, and ``summary.json``."""
    study = _base_study(given)  # fails early
    table = given.spec.free_rocking
    alpha = study.rocking_alpha
    tilts, dampings = table.tilt_fractions, table.damping
    sizes = _mesh_sizes(given, study)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cases = []
    for k, fraction in enumerate(tilts):
        for kind in ("fem", "multibody"):
            cases.append(
                case_of(
                    study,
                    alpha=alpha,
                    key=f"{kind}-tilt{k + 1}",
                    kind=kind,
                    tilt_fraction=fraction,
                    damping=study.contact.damping,
                    mesh_size=study.mesh_size,
                )
            )
    for k, damping in enumerate(dampings):
        cases.append(
            case_of(
                replace(study, contact=replace(study.contact, damping=damping)),
                alpha=alpha,
                key=f"fem-damping{k + 1}",
                kind="fem",
                tilt_fraction=tilts[0],
                damping=damping,
                mesh_size=study.mesh_size,
            )
        )
    for k, size in enumerate(sizes):
        cases.append(
            case_of(
                replace(study, mesh_size=size),
                alpha=alpha,
                key=f"fem-mesh{k + 1}",
                kind="fem",
                tilt_fraction=tilts[0],
                damping=study.contact.damping,
                mesh_size=size,
            )
        )
    start = time.perf_counter()
    results = run_cases(
        free_rocking_case,
        cases,
        out,
        run_options=options,
    )
    check_fem_results(results, out)
    results = {key: without_stopped_ratios(key, r) for key, r in results.items()}
    housner = Block(b=1.0, h=1.0 / math.tan(alpha)).restitution_housner
    base_fem = results["fem-tilt1"]
    summary = {
        "study": study.name,
        "kind": given.kind,
        "alpha": alpha,
        "restitution_housner": housner,
        "E": study.stone.E,
        "fem_ratio_study_stone": base_fem["ratio_first"],
        "fem_ratio_study_stone_band": base_fem["ratio_first_band"],
        "replicas": base_fem["replicas"],
        "fem_ratio_study_stone_mean": base_fem["ratio_mean"],
        "multibody_ratio": results["multibody-tilt1"]["ratio_first"],
        "tilts": [
            {
                "tilt_fraction": f,
                "tilt": f * alpha,
                "fem": results[f"fem-tilt{k + 1}"],
                "multibody": results[f"multibody-tilt{k + 1}"],
            }
            for k, f in enumerate(tilts)
        ],
        "damping_variants": [results[f"fem-damping{k + 1}"] for k in range(len(dampings))],
        "mesh_variants": [results[f"fem-mesh{k + 1}"] for k in range(len(sizes))],
        "damping": study.contact.damping,
        "mesh_size": study.mesh_size,
        "outcome": none_assessed(
            "a free-rocking study measures the velocity ratio at the "
            "impacts of a column released from a tilt (below); the "
            "cross-check study answers this for a ground motion"
        ),
    }
    summary["halved_steps"] = halved_steps(
        [
            (f"the FEM run released at a tilt of {f * alpha:.3g} rad", results[f"fem-tilt{k + 1}"])
            for k, f in enumerate(tilts)
        ]
        + [
            (f"the FEM run with contact damping {d:g} of critical", results[f"fem-damping{k + 1}"])
            for k, d in enumerate(dampings)
        ]
        + [
            (f"the FEM run on the mesh of size {size * 1e3:.4g} mm", results[f"fem-mesh{k + 1}"])
            for k, size in enumerate(sizes)
        ]
    )
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    return summary
