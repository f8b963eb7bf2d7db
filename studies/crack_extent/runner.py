"""The crack-extent study: the column's FEM with its crack over a range of extents and as found,
with its two rigid limits (:func:`studies.sweep.run_sweep`), all under the study's ground
motion (its ratios refer to the study's rocking body)."""

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
from .schema import DEFAULT_FRACTIONS

# the crack's extents swept by default, fractions of the column's height (0: no crack, 1: the
# full height): [crack_extent] fractions
FRACTIONS = DEFAULT_FRACTIONS
AS_FOUND = "as-found"  # the variant of the study's own crack
# the rigid limits: (name, cracked, in words)
LIMITS = (
    ("solid", False, "the solid column (SDOF, whole column)"),
    ("split", True, "the fully split column with its collars (SDOF half block, the paper's)"),
)


def from_base(study: FemStudy) -> bool:
    """Whether the study's crack starts at the base (then the sweep's cracks run from the base
    up; otherwise from the top down, as a crack under the capital)."""
    crack = study.crack
    return crack is not None and crack[0] <= 0.0 < crack[1] < study.height


def extent(study: FemStudy, fraction: float) -> tuple[float, float]:
    """The crack (from, to) (m) over ``fraction`` of the height, from the base or the top."""
    H = study.height
    return (0.0, fraction * H) if from_base(study) else (H - fraction * H, H)


def variants(study: Study) -> dict[str, FemStudy]:
    """The FEM variants by name: each extent of [crack_extent] fractions (``crack-<percent>``)
    at the study's crack depth, except the full height, which is the paper's hypothesis: a
    crack through the whole thickness; and, where the study's own crack is not one of them,
    ``as-found``; each with the study's own ground motion."""
    fem = study.fem
    found = {}
    for f in study.spec.crack_extent.fractions:
        depth = 1.0 if f >= 1.0 else fem.crack_depth
        found[f"crack-{round(100 * f)}"] = replace(
            fem, cracked=True, crack=extent(fem, f), crack_depth=depth
        )
    own = fem.crack if fem.crack is not None else (0.0, fem.height)
    if all(v.crack != own or v.crack_depth != fem.crack_depth for v in found.values()):
        found[AS_FOUND] = replace(fem, crack=own)
    return found


def _limit(study: Study, cracked: bool) -> FemStudy:
    """A rigid limit: the study's column solid (without collars) or fully split (with them)."""
    spec = study.spec
    assert spec.column is not None  # the kind needs a column (studies.kinds)
    column = spec.column.model_copy(update={"cracked": cracked, "crack": None, "crack_depth": 1.0})
    changed = spec.model_copy(update={"column": column, "collar": spec.collar if cracked else []})
    varied = from_spec(changed, study.source, study.base)
    return replace(varied, ground=study.fem.ground, vertical=study.fem.vertical)


def cases(study: Study) -> list[dict]:
    """A FEM case per extent, and the two rigid limits."""
    found = [
        case_of(varied, key=f"{name}-fem", kind="fem", variant=name)
        for name, varied in variants(study).items()
    ]
    for name, cracked, _ in LIMITS:
        found.append(case_of(_limit(study, cracked), key=f"{name}-rigid", kind="rigid"))
    return found


FEWER = ", fewer [run] replicas"  # its way to ask for less FEM work (besides [run], [mesh])


def fem_work(study: Study) -> FemWork:
    """The FEM work of the study (:func:`studies.driver.check_work`): each extent's run with
    its replicas."""
    return ensembles_work(variants(study).values())


def _row(study: FemStudy, crack: tuple, depth: float, fem: dict) -> dict:
    """One extent's numbers: where the crack runs, its length, its fraction of the height and
    the fraction of the thickness it runs through (``depth``),
    the FEM's peak rotation (median, and the range over the replicas that stood) and
    overturning, the crack's growth and K_I / K_IC (medians over the replicas, with their
    range), the collars' utilisation (with its range and whether the collars yield) and the
    toe stress."""
    stop = fem_stop("the FEM", fem)
    stood = _stood_peaks(fem)
    bands = fem.get("bands", {})
    return {
        "crack_from": crack[0],
        "crack_to": crack[1],
        "extent_fraction": (crack[1] - crack[0]) / study.height,
        "crack_depth": depth,
        "crack_length_initial": fem.get("crack_length_initial", crack[1] - crack[0]),
        "fem_peak_rotation": unless_stopped(
            max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]), stop
        ),
        "fem_peak_rotation_min": min(stood) if stood else None,
        "fem_peak_rotation_max": max(stood) if stood else None,
        "replicas": int(fem.get("replicas", 1)),
        "fem_overturned_replicas": int(
            fem.get("overturned_replicas", int(bool(fem["overturned"])))
        ),
        "fem_overturned": fem.get("overturned_answer", "yes" if fem["overturned"] else "no"),
        "collars_yield": fem_answers(fem, "", collars=study.collars)["collars_yield"]["answer"],
        "crack_grows": fem.get("crack_grew_answer", "no"),
        "crack_length_final": fem.get("crack_length_final", crack[1] - crack[0]),
        "crack_tip_KI_ratio": fem.get("crack_tip_KI_ratio"),
        "crack_tip_KI_ratio_min": bands.get("crack_tip_KI_ratio", {}).get("min"),
        "crack_tip_KI_ratio_max": bands.get("crack_tip_KI_ratio", {}).get("max"),
        "collar_max_utilisation": fem["collar_max_utilisation"],
        "collar_max_utilisation_min": bands.get("collar_max_utilisation", {}).get("min"),
        "collar_max_utilisation_max": bands.get("collar_max_utilisation", {}).get("max"),
        "edge_stress_ratio": fem["edge_stress_ratio"],
        "status": fem["status"],
    }


def _stood_peaks(fem: dict) -> list[float]:
    """The largest |theta| (rad, either half) of each replica whose run stood (a run that
    overturned stopped: its largest rotation is the stopping angle, no peak)."""
    bands = fem.get("bands", {})
    left = bands.get("max_abs_theta_left", {}).get("values") or [fem["max_abs_theta_left"]]
    right = bands.get("max_abs_theta_right", {}).get("values") or [fem["max_abs_theta_right"]]
    statuses = fem.get("statuses") or [fem["status"]]
    return [
        max(a, b)
        for a, b, status in zip(left, right, statuses)
        if a is not None and b is not None and not str(status).startswith("overturned")
    ]


def summarise(study: FemStudy, cases: list[dict], results: dict) -> dict:
    names = [c["variant"] for c in cases if c["kind"] == "fem"]
    cracks = {c["variant"]: tuple(c["study"]["crack"]) for c in cases if c["kind"] == "fem"}
    depths = {c["variant"]: c["study"].get("crack_depth", 1.0) for c in cases if c["kind"] == "fem"}
    rows = {n: _row(study, cracks[n], depths[n], results[f"{n}-fem"]["summary"]) for n in names}
    models = []
    for n in names:
        fem = results[f"{n}-fem"]["summary"]
        # joined by intact stone the halves rock as one; split full height, as the cracked column
        full = cracks[n][1] - cracks[n][0] >= study.height and depths[n] >= 1.0
        collared = bool(study.collars)
        alpha = rocking_alpha(study.width, study.height, full, collared)
        models.append(fem_model(f"FEM, {n}", fem, alpha, rocking_block(full, collared)))
    limits = {}
    for name, cracked, words in LIMITS:
        rigid = results[f"{name}-rigid"]
        block = "half" if cracked else "column"
        models.append(
            model_outcome(
                f"SDOF, {words}",
                rigid["overturned"],
                rigid["max_abs_theta"],
                rigid["alpha"],
                rigid.get("overturn_time"),
                block=block,
            )
        )
        limits[name] = {
            "peak_rotation": unless_stopped(
                rigid["max_abs_theta"],
                overturned_at("the SDOF", rigid["overturned"], rigid.get("overturn_time")),
            ),
            "overturned": "yes" if rigid["overturned"] else "no",
            "block": block,
        }
    found = AS_FOUND if AS_FOUND in names else _as_found(study, cracks, depths)
    answers = fem_answers(
        results[f"{found}-fem"]["summary"],
        "this study sweeps the crack's extent; the cross-check study compares the FEM with "
        "the rigid models",
        collars=study.collars,
    )
    return {
        "study": study.name,
        "outcome": outcome(models, answers, names.index(found)),
        "as_found": found,
        "from_base": from_base(study),
        "variants": rows,
        "limits": limits,
        "halved_steps": halved_steps(
            [(f"the FEM run with {n}", results[f"{n}-fem"]["summary"]) for n in names]
        ),
    }


def _as_found(study: FemStudy, cracks: dict, depths: dict) -> str:
    """The swept extent that is the study's own crack (the full height where it gives none, at
    its depth)."""
    own = study.crack if study.crack is not None else (0.0, study.height)
    return next(n for n, c in cracks.items() if c == tuple(own) and depths[n] == study.crack_depth)


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """The crack-extent sweep of one column (:func:`studies.study.load`)."""
    return run_sweep(study, out, cases=cases, summarise=summarise, options=options)
