"""The runs of a fragility study: one record at the levels of its ladder through each model.

What each run gives is :data:`studies.fragility.analysis.RUN_KEYS`, the same for every model:

* SDOF (:func:`sdof_runs`): the paper's half block with its collar springs, nonlinear, from
  rest, as :func:`studies.models.run_sdof` runs it (:func:`colonna.rigid.solve.rock`'s
  kernel, the same parameters from :func:`colonna.rigid.solve.kernel_params`), without the
  history (:func:`studies.models.sdof_outcome`): a fragility needs a run's outcome, its
  largest |theta| and the collars' largest stress, and the springs' stress grows with |theta|
  (:func:`colonna.rigid.collars.collar_yield_rotation`), so the largest stress is the stress
  at the largest |theta|. Each run lasts the record plus 20 / p (rock's default): the largest
  |theta| after the motion is the swing in progress when it ends (each later swing starts
  from an impact with less energy).
  With collars a run ends once, after the record, it can no longer overturn (the kernel's
  early exit, which takes that swing's peak from its turning point: the same answer, 37 %
  less time); without collars it runs the whole tail (the kernel's early exit there may stop
  before the turning point of the swing in progress). ``rtol`` is the study's
  (:data:`SDOF_RTOL`, recorded; rock's 1e-10 is available). A record whose peak only reaches
  the uplift level (a level of PGA / (g tan alpha) = 1) does not rock the block: rocking
  needs the ground to exceed it.
* multibody (:func:`multibody_runs`): the study's column under the scaled record from rest, its
  duration the record plus 20 / p, through :func:`colonna.rigid.multibody.multibody_outcome`
  (rock_multibody's model without histories, the steps at rest skipped, the contact
  problem's exact solve by Gaussian elimination: the answers within the contact solver's own
  scatter, docs/fragility.md); with plastic collars, vertical motion or an initial tilt,
  :func:`studies.models.run_multibody` itself. Its step, where the collars set it, is the
  study's ``multibody_step`` of their stability limit (:func:`multibody_steps`: by default a
  quarter, twice the single run's eighth), the crack contacts' touching tolerance the single
  run's (the fits at an eighth and a sixteenth are within a few % of it, docs/fragility.md).
* FEM (:func:`fem_point`): :func:`studies.models.iter_fem` on the study's mesh, settled-stop
  (a run ends once it can no longer overturn), one run per record and level, the runs of one
  model batched on one kernel.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...core.ground import Record
from .analysis import UPLIFT_RATIO

MODEL_NAMES = {
    "sdof": "SDOF half block",
    "multibody": "rigid multibody",
    "fem": "FEM",
}
SDOF_RTOL = 1e-6  # the SDOF runs' relative tolerance (measured against 1e-10: docs/fragility.md)
SDOF_ATOL = 1e-12  # rad, as rock's
FREE_TIME_P = 20.0  # s x p: how long the rigid runs follow free rocking after the record


def sdof_runs(study, record: Record, scales, *, rtol: float = SDOF_RTOL) -> list[dict]:
    """The SDOF runs of ``record`` times each of ``scales`` (:mod:`module notes <.models>`)."""
    from ...rigid.collars import collar_response
    from ..models import sdof_outcome

    block = study.rocking_block
    collars = study.collars
    alpha = block.alpha
    duration = record.end_time + FREE_TIME_P / block.p
    runs = []
    for scale in scales:
        ground = record.scaled(float(scale))
        overturned, n_imp, max_theta, t_over = sdof_outcome(
            study, ground, duration, rtol=rtol, atol=SDOF_ATOL
        )
        peak = 0.5 * math.pi if overturned else float(max_theta)
        utilisation = None
        if collars:
            utilisation = max(
                float(collar_response(np.array([peak]), block.b, c)["utilisation"][0])
                for c in collars
            )
        runs.append(
            {
                "overturned": bool(overturned),
                "peak_ratio": peak / alpha,
                "uplift": bool(overturned or peak > 0.0 or n_imp > 0),
                "collar_utilisation": utilisation,
                "collar_fractured": None,
                "toe_ratio": None,
                "impacts": int(n_imp),
                "overturned_at": t_over,
            }
        )
    return runs


def multibody_runs(study, record: Record, scales, collar_step: float | None = None) -> list[dict]:
    """The multibody runs of ``record`` times each of ``scales``: with elastic collars (or
    none) :func:`colonna.rigid.multibody.multibody_outcome` (no histories, the steps at rest
    skipped), else :func:`studies.models.run_multibody`'s full run (a plastic collar's
    fracture is read from its history). ``collar_step``: the step where the collars set it,
    as a fraction of their stability limit 2/omega, with the single run's crack tolerance
    (:func:`multibody_steps`; None: the single run's step)."""
    from ..models import run_multibody

    block = study.rocking_block
    duration = record.end_time + FREE_TIME_P / block.p
    dt, touching_dt = multibody_steps(study, record, collar_step)
    plastic = any(c.plastic for c in study.collars)
    from_rest = study.initial_tilt == 0.0 and study.initial_angular_velocity == 0.0
    if not plastic and not study.vertical.moves and from_rest:
        return [
            multibody_point(
                study, outcome_run(study, record, s, duration, dt=dt, touching_dt=touching_dt)
            )
            for s in scales
        ]
    runs = []
    for scale in scales:
        variant = dataclasses.replace(study, ground=record.scaled(float(scale)), duration=duration)
        s = run_multibody(variant, dt, touching_dt).summary()
        alpha = block.alpha  # the SDOF's block's, as every model's here
        runs.append(
            {
                "overturned": bool(s["overturned"]),
                "peak_ratio": 0.5 * math.pi / alpha
                if s["overturned"]
                else s["max_abs_theta"] / alpha,
                "uplift": bool(s["overturned"] or s["max_abs_theta"] > UPLIFT_RATIO * alpha),
                "collar_utilisation": s.get("collar_max_utilisation") if study.collars else None,
                "collar_fractured": bool(s.get("collar_fractured")) if plastic else None,
                "toe_ratio": None,
                "impacts": int(s["impacts"]),
                "overturned_at": s.get("overturn_time") if s["overturned"] else None,
            }
        )
    return runs


def multibody_steps(
    study, record: Record, collar_step: float | None
) -> tuple[float | None, float | None]:
    """(dt, touching_dt) of the multibody runs of ``record`` (any scale: a record's step does
    not depend on its size): the step, :func:`colonna.rigid.multibody.default_step` with the
    collars' step at ``collar_step`` of their stability limit 2/omega, and the single run's
    default step, whose midpoint drift stays the crack contacts' touching tolerance
    (:func:`colonna.rigid.multibody.touching_scale`). (None, None) where ``collar_step`` is
    None: the single run's step and tolerance."""
    from ...rigid.multibody import build_column, default_step

    if collar_step is None:
        return None, None
    column = build_column(
        study.rocking_block,
        cracked=study.cracked,
        collars=study.collars,
        friction=study.contact.friction,
    )
    return default_step(column, record, collar_fraction=collar_step), default_step(column, record)


def outcome_run(
    study,
    record: Record,
    scale: float,
    duration: float,
    *,
    stop_when_decided: bool = True,
    dt: float | None = None,
    touching_dt: float | None = None,
):
    """:func:`colonna.rigid.multibody.multibody_outcome` of the study's column under ``record``
    times ``scale`` from rest (the settings of :func:`studies.models.run_multibody`);
    ``stop_when_decided``: as multibody_outcome's (False runs the free tail to its end); ``dt``
    and ``touching_dt``: its step and the crack's tolerance (s; None: the single run's,
    :func:`multibody_steps`). The
    fragility's limit states do not use the impact count: the run does not keep it
    (impacts_needed False: its stop need not wait for the last impact; impacts None). Run
    through the gateway, :func:`studies.models.run_multibody_outcome`."""
    from ..models import run_multibody_outcome

    return run_multibody_outcome(
        study,
        record.scaled(float(scale)),
        duration,
        stop_when_decided=stop_when_decided,
        dt=dt,
        touching_dt=touching_dt,
    )


def multibody_point(study, outcome) -> dict:
    """A :class:`colonna.rigid.multibody.MultibodyOutcome` as a run of the fragility."""
    alpha = study.rocking_block.alpha
    return {
        "overturned": outcome.overturned,
        "peak_ratio": outcome.max_abs_theta / alpha,
        "uplift": bool(outcome.overturned or outcome.max_abs_theta > UPLIFT_RATIO * alpha),
        "collar_utilisation": outcome.collar_max_utilisation if study.collars else None,
        "collar_fractured": None,
        "toe_ratio": None,
        "impacts": outcome.impacts,
        "overturned_at": outcome.overturned_at,
    }


def fem_point(study, fem) -> dict:
    """A FEM run (:class:`colonna.fem.solver.FemResult`) of one record and level as a run of
    the fragility: its rotation over the alpha of the SDOF's block (a half of a cracked
    column), as the SDOF's and the multibody's are, so that one threshold means one rotation
    in every model."""
    s = fem.summary
    alpha = study.rocking_block.alpha
    peak = max(s["max_abs_theta_left"], s["max_abs_theta_right"])
    plastic = any(c.plastic for c in study.collars)
    return {
        "overturned": bool(s["overturned"]),
        "peak_ratio": 0.5 * math.pi / alpha if s["overturned"] else peak / alpha,
        # not assessed: on its bed the deformable column sways (up to about 0.03 alpha_b per
        # g tan alpha_b of ground, docs/fragility.md) long before it rocks, so |theta| passes
        # any uplift threshold of the rigid models' kind at every level; the rotation limit
        # state is its rocking answer
        "uplift": None,
        "collar_utilisation": s["collar_max_utilisation"] if study.collars else None,
        "collar_fractured": bool(s.get("collar_fractured")) if plastic else None,
        "toe_ratio": s["edge_stress_ratio"],
        # where it overturned: its run's stop (the overturning rule), as fem_stop reads it
        "overturned_at": s["t_end"] if s["overturned"] else None,
        # what the guard reads (studies.guard.fem_runs): a run that is not an answer stops
        "status_fem": s["status"],
        "energy_error_fem": s["energy_error_max"],
        "fem_seconds": s["wall_seconds"],
        "fem_steps": s["steps"],
    }


ELASTIC_SPRINGS = (
    "elastic springs (the paper's axial E A / l and lateral 12 E I / l^3 at each collar's "
    "height): they never yield nor fracture, whatever [[collar]] plastic says; their stress "
    "is the elastic one at the largest |theta|"
)
FRAMES = {
    "multibody": "co-rotational frame elements between the collars' attachment points on the "
    "two rigid halves (the FEM's element)",
    "fem": "co-rotational frame (Euler-Bernoulli) elements attached to the outer faces of "
    "the two meshed halves",
}
RIGID_TOE = "rigid bodies: no stress at the toe, the FEM's answer"


def collar_law(study, model: str) -> dict:
    """What a model's collars are, in words (``words``; ``short`` for a legend) with
    whether they can yield and fracture: the SDOF's are always elastic springs; the
    multibody's and the FEM's frame elements, elastic or plastic by each [[collar]] plastic
    key (plastic: the fibre section or the resultant law, :attr:`colonna.core.collar.Collar.
    local_law`, breaking at eps_u)."""
    collars = tuple(study.collars)
    if not collars:
        return {
            "law": "none",
            "short": "no collars",
            "words": "no collars",
            "yields": False,
            "fractures": False,
        }
    if model == "sdof":
        return {
            "law": "elastic springs",
            "short": "elastic collar springs",
            "words": ELASTIC_SPRINGS,
            "yields": False,
            "fractures": False,
        }
    laws = [_frame_law(c) for c in collars]
    plastic = [c.plastic for c in collars]
    if len(set(laws)) == 1:
        law = laws[0]
        words = f"{FRAMES[model]}, {law}"
    else:
        law = "mixed"
        words = (
            FRAMES[model]
            + "; "
            + "; ".join(
                f"collar {k} (y = {c.y:g} m) {w}" for k, (c, w) in enumerate(zip(collars, laws), 1)
            )
        )
    if not any(plastic):
        short = "elastic frame collars"
    elif all(plastic) and len({c.local_law for c in collars}) == 1:
        short = f"plastic frame collars, {collars[0].local_law} law"
    else:
        short = "elastic and plastic frame collars"
    return {
        "law": law,
        "short": short,
        "words": words,
        "yields": any(plastic),
        "fractures": any(plastic),
    }


def _frame_law(collar) -> str:
    """A frame collar's law in words."""
    if not collar.plastic:
        return "elastic (plastic = false): they never yield nor fracture"
    if collar.local_law == "fibre":
        return (
            f"plastic, fibre section ({collar.n_fibres} layers x {collar.n_sections} sections, "
            f"{collar.steel} steel), fracture at an extreme-fibre strain of {collar.eps_u:g}"
        )
    return (
        "plastic, resultant law (bilinear axial, end hinges on |M| / M_p + (N / N_p)^2 = 1), "
        f"fracture at an extreme-fibre strain of {collar.eps_u:g}"
    )


def unreachable(study, model: str) -> dict[str, str]:
    """The limit states a model cannot reach, each with why: toe crushing in the rigid models
    (no stress at the toe), collar fracture where its collars cannot break (the SDOF's
    springs, elastic frames). A report says "cannot be reached by this model", never a
    probability of zero."""
    found = {}
    law = collar_law(study, model)
    if study.collars and not law["fractures"]:
        found["collar_fracture"] = (
            "elastic collar springs: they never fracture"
            if model == "sdof"
            else "elastic frame collars (plastic = false): they never fracture"
        )
    if model in ("sdof", "multibody"):
        found["toe_crushing"] = RIGID_TOE
    return found
