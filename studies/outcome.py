"""What happens to the column, and the three answers: the part of summary.json that every
report opens with (``summary["outcome"]``).

``models``: per model, how the column moved (``overturned``, ``rocking``: it uplifted and stayed
up, ``no uplift``: :func:`colonna.rigid.solve.motion_word`), the time the run detected an
overturning (a stopping convention, named as such: the instant the centre of mass passed the
toe moving outward after the ground motion, not a collapse time) and, for the FEM ensemble, how
many replicas overturned.

``answers``: "Does the column stay up?" first (:func:`stays_up`: per model, from the
models' outcomes; the answer word is the model's whose stresses the other answers quote, the
first), then "Is the rigid-body assumption good enough?", "Do the collars yield?", "Does the
toe crush?", each yes / no / undecided / not assessed, with the number behind it (median and
band over the replicas), its limit, the relation between them (``stays below``, ``reaches``,
``straddles``) and the figure that shows it. The word and the relation come from one comparison
(:func:`limit_answer`), so the sentence can never contradict its number. A study that follows
the collars past f_y also answers "Do the collars hold?" (:func:`collars_hold`: did a plastic
collar's extreme fibre reach its fracture strain?): the cross-check always, the studies whose
FEM runs alone (:func:`fem_answers`) where a collar is plastic; the others leave it out.

A stress answer (collars, toe) of a model that overturns holds only up to the overturning:
its run stops there, and what the stone and the collars would carry as the column falls is not
computed. :func:`outcome` gives each such answer ``until_overturning`` (the time, and in how
many replicas or pulses) and a ``qualifier`` sentence, and the report never shows it as a pass.

Each model's ``alpha_block`` says whose slenderness its rotation is compared with: ``column``
(the whole column, 4b x 2h: collars and crack friction make the halves rock together) or
``half`` (one half block, 2b x 2h); the report writes alpha_column or alpha_half.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fem.ensemble import NO, UNDECIDED, YES, decide
from ..rigid.solve import collar_state, motion_word

NOT_ASSESSED = "not assessed"

QUESTIONS = {
    "stays_up": "Does the column stay up?",
    "rigid_assumption_ok": "Is the rigid-body assumption good enough?",
    "collars_yield": "Do the collars yield?",
    "collars_hold": "Do the collars hold?",
    "toe_crushes": "Does the toe crush?",
    "crack_grows": "Does the crack grow?",
}
# answered only by the studies that ask them (listed where given, left out otherwise): the
# collars' fracture where a collar is plastic, the crack's growth where it is partial
OPTIONAL_QUESTIONS = ("collars_hold", "crack_grows")
# the answers made from stresses, which hold only up to an overturning
# the answers read from the FEM run up to where it stops: where it overturns, each holds only
# until then (a crack that has not grown by then may grow as the column falls)
STRESS_QUESTIONS = ("collars_yield", "collars_hold", "toe_crushes", "crack_grows")
# the blocks whose slenderness alpha (and frequency parameter p) a model's rotation is given in
BLOCKS = {"column": "the whole column (4b x 2h)", "half": "one half block (2b x 2h)"}


def rocking_block(cracked: bool, collared: bool) -> str:
    """The block whose alpha a rotation history is compared with (as
    :func:`colonna.studies.fem_study.rocking_alpha`): ``half`` for a cracked column without
    collars (its halves rock apart), else ``column``."""
    return "half" if cracked and not collared else "column"


# why "Do the collars hold?" has no answer for elastic collars
ELASTIC_COLLARS_NOT_FOLLOWED = "elastic collars are not followed past f_y (set plastic = true)"

# how each answer word relates the band to its limit (the relation is the comparison's
# result, named; see limit_answer)
RELATIONS = {YES: "reaches", NO: "stays below", UNDECIDED: "straddles"}


@dataclass(frozen=True)
class ReplicaCount:
    """An ensemble's replicas: ``count`` run, ``overturned`` of them overturned, and
    ``overturn_time_range`` their earliest and latest overturning (s; None where none did)."""

    count: int
    overturned: int = 0
    overturn_time_range: tuple[float, float] | None = None


@dataclass(frozen=True)
class CollarOutcome:
    """A model's collars: ``utilisation``, the largest sigma / f_y of its collars (None: it has
    none), whose state (elastic / yielded, or fractured where ``fractured``: a plastic collar
    broke) is said beside the motion; ``elastic``, the words that say the model's collars never
    yield (e.g. "the SDOF's collars are elastic"), where they do not: a model that stays up on
    such collars past f_y rests on a strength they do not have, and its outcome carries that as
    its ``caveat`` (:func:`collar_caveat`)."""

    utilisation: float | None
    fractured: bool = False
    elastic: str | None = None


def model_outcome(
    model: str,
    overturned: bool,
    peak_rotation: float | None,
    alpha: float,
    overturn_time: float | None = None,
    *,
    replicas: ReplicaCount | None = None,
    collars: CollarOutcome | None = None,
    block: str = "column",
) -> dict:
    """One model's outcome. ``peak_rotation`` (rad) is the largest |theta| of a rocking half
    (None or the pi/2 convention of an overturned block are not reported as a rotation);
    ``alpha`` its slenderness (rad), of the ``block`` (a key of BLOCKS: ``column`` or
    ``half``); ``replicas``: an ensemble's (:class:`ReplicaCount`); ``collars``: the model's
    collars (:class:`CollarOutcome`; None: it has none)."""
    if block not in BLOCKS:
        raise ValueError(f"block {block!r}: one of {', '.join(BLOCKS)}")
    overturned_replicas = None if replicas is None else replicas.overturned
    collar_utilisation = None if collars is None else collars.utilisation
    motion = motion_word(bool(overturned), 0.0 if peak_rotation is None else peak_rotation, alpha)
    out = {
        "model": model,
        "motion": motion,
        "alpha": float(alpha),
        "alpha_block": block,
        # the overturning time of a model that overturns, or of an ensemble's replicas that do
        "overturn_time": float(overturn_time)
        if (overturned or overturned_replicas) and overturn_time is not None
        else None,
        "peak_rotation": None if overturned or peak_rotation is None else float(peak_rotation),
        "peak_rotation_over_alpha": None
        if overturned or peak_rotation is None
        else float(peak_rotation) / alpha,
    }
    if replicas is not None:
        out.update(replicas=int(replicas.count), overturned_replicas=int(overturned_replicas or 0))
        time_range = replicas.overturn_time_range
        if time_range is not None and None not in time_range:
            out["overturn_time_range"] = [float(v) for v in time_range]
    if collars is not None and collar_utilisation is not None:
        out.update(
            collar_state=collar_state(collar_utilisation, fractured=bool(collars.fractured)),
            collar_utilisation=float(collar_utilisation),
        )
        caveat = collar_caveat(motion, collar_utilisation, collars.elastic)
        if caveat:
            out["caveat"] = caveat
    return out


def collar_caveat(motion: str, utilisation: float, elastic_collars: str | None) -> str | None:
    """Why a model that stays up is outside its validity: its collars are elastic
    (``elastic_collars`` says so in words) and carry ``utilisation`` times f_y; None where the
    model overturns, its collars yield in the model, or they stay below f_y."""
    if elastic_collars is None or motion.startswith("overturned") or not utilisation > 1.0:
        return None
    return f"its collars would carry {utilisation:.3g} times f_y ({elastic_collars})"


def limit_answer(
    question: str,
    measure: str,
    band: dict | None,
    limit: float,
    unit: str,
    uncertainty: float = 0.0,
    figure: str | None = None,
) -> dict:
    """A yes / no / undecided answer to "does ``measure`` reach ``limit``?" from its band over
    the replicas (``median``, ``min``, ``max``, ``missing``: :func:`colonna.fem.ensemble.band`)
    widened by the relative ``uncertainty`` (the mesh's), and the relation that says why."""
    if band is None or band.get("median") is None:
        return not_assessed(question, f"no value of {measure}")
    answer = decide(band, limit, uncertainty)
    return {
        "question": question,
        "answer": answer,
        "measure": measure,
        "median": band["median"],
        "min": band["min"],
        "max": band["max"],
        "uncertainty": float(uncertainty),
        "limit": float(limit),
        "unit": unit,
        "relation": RELATIONS[answer],
        "figure": figure,
    }


def not_assessed(question: str, why: str) -> dict:
    """An answer this study does not give, and why (e.g. the study kind has no FEM run)."""
    return {"question": question, "answer": NOT_ASSESSED, "why": why}


def criteria_answer(
    question: str, answer: str, criteria: dict[str, str], figure: str | None = None
) -> dict:
    """An answer made of several counts, each answered over the replicas (yes / no /
    undecided, or ``not applicable``): ``answer`` is yes where every replica passes every
    applicable count, no where none does, undecided otherwise (the caller decides it per
    replica); the counts are listed by their own answer, and ``reason`` says which rule gave
    the word."""
    if answer not in (YES, NO, UNDECIDED):
        raise ValueError(f"answer {answer!r}: yes, no or undecided")
    by_word = {
        word: [name for name, w in criteria.items() if w == word] for word in (YES, NO, UNDECIDED)
    }
    reason = {
        YES: "every replica passes every count that applies",
        NO: "no replica passes every count that applies",
        UNDECIDED: "some replicas pass every count that applies, others do not",
    }[answer]
    return {
        "question": question,
        "answer": answer,
        "reason": reason,
        "passed": by_word[YES],
        "failed": by_word[NO],
        "undecided": by_word[UNDECIDED],
        "not_applicable": [name for name, w in criteria.items() if w not in (YES, NO, UNDECIDED)],
        "figure": figure,
    }


def none_assessed(why: str) -> dict:
    """summary["outcome"] of a study that assesses no column against a ground motion (no
    models to tell, each answer not assessed, for the reason ``why``)."""
    return outcome(
        [],
        {
            key: not_assessed(question, why)
            for key, question in QUESTIONS.items()
            if key not in OPTIONAL_QUESTIONS
        },
    )


def _model_stays_up(m: dict) -> dict:
    """Does this model's column stay up? yes / no, or for an ensemble (``replicas``) or a grid
    of pulses (``points``) undecided where some overturn and others do not; with the count and
    the overturning time (or the replicas' range of it)."""
    if "points" in m:  # a grid of pulses (grid_outcome)
        n, total = m["overturned_points"], m["points"]
    elif "replicas" in m:
        n, total = m["overturned_replicas"], m["replicas"]
    else:
        n, total = int(m["motion"].startswith("overturned")), 1
    word = YES if n == 0 else NO if n == total else UNDECIDED
    out = {"model": m["model"], "answer": word, "overturned": n, "of": total}
    if m.get("caveat"):
        out["caveat"] = m["caveat"]
    if m.get("overturn_time") is not None:
        out["overturn_time"] = m["overturn_time"]
    if m.get("overturn_time_range"):
        out["overturn_time_range"] = m["overturn_time_range"]
    return out


def stays_up(
    models: list[dict],
    why: str = "no model of the column under a ground motion",
    stress_model: int = 0,
) -> dict:
    """Does the column stay up? Per model (:func:`_model_stays_up`), in the models' order; the
    answer word is that of ``models[stress_model]``, the one whose stresses the other answers
    quote (the FEM where the study runs it)."""
    question = QUESTIONS["stays_up"]
    if not models:
        return not_assessed(question, why)
    per_model = [_model_stays_up(m) for m in models]
    out = {
        "question": question,
        "answer": per_model[stress_model]["answer"],
        "model": per_model[stress_model]["model"],
        "per_model": per_model,
    }
    if per_model[stress_model].get("caveat"):  # its word rests on what its caveat says
        out["caveat"] = per_model[stress_model]["caveat"]
    return out


def _until_overturning(model: dict) -> dict | None:
    """Where a stress answer of ``model``'s run holds only up to an overturning: the time (the
    median over the replicas that overturn, with their range) or, for a grid, the pulses; and
    the qualifier sentence. None where the model overturns in no replica and at no pulse."""
    up = _model_stays_up(model)
    if up["overturned"] == 0:
        return None
    until: dict = {"model": model["model"], "overturned": up["overturned"], "of": up["of"]}
    if "points" in model:
        until["qualifier"] = (
            f"until overturning, at the {up['overturned']} of {up['of']} pulses where the "
            "column overturns"
        )
        return until
    t = model.get("overturn_time")
    until["time"] = t
    when = "" if t is None else f" at t = {t:.4g} s"
    span = model.get("overturn_time_range")
    if span and span[1] > span[0]:
        when += f" (replicas {span[0]:.4g} to {span[1]:.4g} s)"
    if up["of"] == 1:
        where = ""
    elif up["overturned"] == up["of"]:
        where = f", in all {up['of']} replicas"
    else:
        where = f", in the {up['overturned']} of {up['of']} replicas that overturn"
    until["qualifier"] = f"until overturning{when}{where}"
    return until


def outcome(models: list[dict], answers: dict[str, dict], stress_model: int = 0) -> dict:
    """summary["outcome"]: the models' outcomes and the answers, in QUESTIONS' order (every
    question but the OPTIONAL_QUESTIONS, which are listed where ``answers`` has them).
    "Does the column stay up?" is made here from the models (:func:`stays_up`) unless
    ``answers`` gives it. A stress answer (STRESS_QUESTIONS) names the model its stresses are
    of, ``models[stress_model]``; where that model overturns, it carries
    ``until_overturning`` and its ``qualifier`` (:func:`_until_overturning`)."""
    answers = dict(answers)
    if "stays_up" not in answers or (models and answers["stays_up"]["answer"] == NOT_ASSESSED):
        answers["stays_up"] = stays_up(models, stress_model=stress_model)
    until = _until_overturning(models[stress_model]) if models else None
    listed = []
    for key in QUESTIONS:
        if key not in answers and key in OPTIONAL_QUESTIONS:
            continue
        a = dict(answers[key], key=key)
        if models and key in STRESS_QUESTIONS and a["answer"] != NOT_ASSESSED:
            a.setdefault("model", models[stress_model]["model"])
        if until is not None and key in STRESS_QUESTIONS and a["answer"] != NOT_ASSESSED:
            a["until_overturning"] = until
            a["qualifier"] = until["qualifier"]
        listed.append(a)
    return {"models": models, "answers": listed}


def collars_hold(fem: dict, collars, figure: str | None = None) -> dict:
    """Do the collars hold? From an FEM ensemble summary ``fem`` and the study's ``collars``:
    for plastic collars yes where no replica had a collar fracture (its extreme fibre reached
    eps_u), no where every replica had one, undecided otherwise (``collar_fractured_answer``,
    turned round), with the count of replicas behind it; not assessed without collars, or
    with elastic collars only (they are never followed past f_y, so they never break)."""
    question = QUESTIONS["collars_hold"]
    if not collars:
        return not_assessed(question, "the column has no collars")
    if not any(c.plastic for c in collars):
        return not_assessed(question, ELASTIC_COLLARS_NOT_FOLLOWED)
    fractured = fem.get("collar_fractured_answer")
    if fractured not in (YES, NO, UNDECIDED):
        return not_assessed(question, "no record of the collars' fracture in the FEM run")
    return {
        "question": question,
        "answer": {YES: NO, NO: YES, UNDECIDED: UNDECIDED}[fractured],
        "measure": "replicas in which a collar fractured (its extreme fibre reached eps_u)",
        "count": int(fem["collar_fractured_replicas"]),
        "points": int(fem.get("replicas", 1)),
        "figure": figure,
    }


def crack_grows(fem: dict, figure: str | None = None) -> dict:
    """Does the crack grow? From an FEM ensemble summary ``fem`` of a partial crack ([column]
    crack): yes where it grew (a pair of the intact mid-plane broke) in every replica, no in
    none, undecided otherwise (``crack_grew_answer``), with the count of replicas, the crack's
    length at the start and its final length's band (m), and the largest K_I / K_IC at a tip
    (band; :mod:`colonna.fem.partial_crack`); with a crack through part of the thickness, its
    depth and the band of its ligament's largest damage (the lengths are the through crack's:
    a broken ligament is the crack deepened there)."""
    question = QUESTIONS["crack_grows"]
    grew = fem.get("crack_grew_answer")
    if grew not in (YES, NO, UNDECIDED):
        return not_assessed(question, "no record of the crack's growth in the FEM run")
    bands = fem.get("bands", {})
    return {
        "question": question,
        "answer": grew,
        "measure": "replicas in which the crack grew (a pair of the intact mid-plane broke)",
        "count": int(fem["crack_grew_replicas"]),
        "points": int(fem.get("replicas", 1)),
        "length_initial": fem["crack_length_initial"],
        "length_final": bands.get("crack_length_final"),
        "ki_ratio": bands.get("crack_tip_KI_ratio"),
        # a crack through part of the thickness: its depth and its ligament's largest damage
        **(
            {"depth": fem["crack_depth"], "ligament_damage": bands.get("crack_ligament_damage_max")}
            if fem.get("crack_depth") is not None
            else {}
        ),
        "figure": figure,
    }


def grid_outcome(model: str, overturned: list[list]) -> dict:
    """A model's outcome over a grid of pulses: at how many it overturns."""
    flags = [bool(v) for row in overturned for v in row if v is not None]
    return {
        "model": model,
        "motion": "overturned at some pulses" if any(flags) else "stays up at every pulse",
        "overturned_points": sum(flags),
        "points": len(flags),
    }


def count_answer(question: str, measure: str, flags: list[list], figure: str | None = None) -> dict:
    """yes where it happens at one pulse of the grid or more, no where at none; the count."""
    flat = [bool(v) for row in flags for v in row if v is not None]
    if not flat:
        return not_assessed(question, f"no value of {measure}")
    return {
        "question": question,
        "answer": YES if any(flat) else NO,
        "measure": measure,
        "count": sum(flat),
        "points": len(flat),
        "figure": figure,
    }


def fem_answers(fem: dict, why_not_rigid: str, collars=()) -> dict[str, dict]:
    """The answers of a study whose FEM runs alone (an ensemble summary ``fem``; ``collars``
    the study's): the collars and the toe on the study mesh, and, where a collar is plastic
    (followed past f_y to fracture), whether the collars hold (:func:`collars_hold`); the
    rigid-body question left to the cross-check."""
    answers = {
        "rigid_assumption_ok": not_assessed(QUESTIONS["rigid_assumption_ok"], why_not_rigid),
        "collars_yield": limit_answer(
            QUESTIONS["collars_yield"],
            "largest collar stress / f_y",
            fem["bands"].get("collar_max_utilisation"),
            1.0,
            "-",
        )
        if collars
        else not_assessed(QUESTIONS["collars_yield"], "the column has no collars"),
        "toe_crushes": limit_answer(
            QUESTIONS["toe_crushes"],
            "toe stress (base contact pressure averaged over the toe window) / f_c, "
            "study-mesh peak (not refined)",
            fem["bands"].get("edge_stress_ratio"),
            1.0,
            "-",
        ),
    }
    if any(c.plastic for c in collars):
        answers["collars_hold"] = collars_hold(fem, collars)
    if "crack_grew_answer" in fem:  # a partial crack ([column] crack): does it grow?
        answers["crack_grows"] = crack_grows(fem)
    return answers


def fem_model(model: str, fem: dict, alpha: float, block: str = "column") -> dict:
    """:func:`model_outcome` of an FEM ensemble summary; its overturning time the median over
    the replicas that overturn (their run ends, ``t_end``, where they overturn), with their
    range."""
    times = _overturn_times(fem)
    return model_outcome(
        model,
        fem["overturned"],
        max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]),
        alpha,
        float(np.median(times)) if times else fem.get("t_end"),
        replicas=ReplicaCount(
            fem.get("replicas", 1),
            fem.get("overturned_replicas", int(bool(fem["overturned"]))),
            (min(times), max(times)) if times else None,
        ),
        block=block,
    )


def _overturn_times(fem: dict) -> list[float]:
    """The run ends (s) of the replicas whose status says they overturned."""
    statuses = fem.get("statuses") or ()
    ends = fem.get("bands", {}).get("t_end", {}).get("values") or ()
    return [
        float(t)
        for t, status in zip(ends, statuses)
        if t is not None and str(status).startswith("overturned")
    ]


# --- numbers of a stopped run (issue 48) ---------------------------------------------------------
# A run stops where its column overturns (a stopping convention): its largest rotation is then
# the angle it stopped at, a ratio of two such angles compares two stopping rules, and a
# velocity ratio from the rotation peaks takes the stopping angle for a peak. Such a number is
# never a result: summary.json carries, in its place, the words saying why.
NOT_APPLICABLE = "not applicable"
# the keys of a run's summary that hold its stopping angle where it overturned: its rotations,
# and the velocity ratio measured from its rotation peaks
STOPPED_KEYS = (
    "max_abs_theta_left",
    "max_abs_theta_right",
    "max_abs_theta",
    "restitution_after_motion",
)


def overturned_at(name: str, overturned: int | bool, t: float | None, of: int = 1) -> str | None:
    """'<name> overturned at t = ... s' (with 'in n of N replicas' for an ensemble), None where
    it did not overturn."""
    if not overturned:
        return None
    when = "" if t is None else f" at t = {t:.4g} s"
    replicas = f" in {int(overturned)} of {of} replicas" if of > 1 else ""
    return f"{name} overturned{when}{replicas}".strip()


def fem_stop(name: str, fem: dict) -> str | None:
    """:func:`overturned_at` of an FEM ensemble summary: any replica that overturned stops the
    ensemble's rotation numbers (its median mixes stopping angles), the time the median of
    the overturned replicas' run ends."""
    replicas = int(fem.get("replicas", 1))
    n = int(fem.get("overturned_replicas", int(bool(fem["overturned"]))))
    times = _overturn_times(fem)
    return overturned_at(name, n, float(np.median(times)) if times else fem.get("t_end"), replicas)


def not_applicable(*stops: str | None) -> str | None:
    """'not applicable: <the stops>' where a run stopped, None where none did."""
    said = [s for s in stops if s]
    return f"{NOT_APPLICABLE}: {'; '.join(said)}" if said else None


def unless_stopped(value, *stops: str | None):
    """``value``, or where one of the runs behind it stopped (:func:`overturned_at`), the
    sentence that says so in its place (:func:`not_applicable`)."""
    note = not_applicable(*stops)
    return value if note is None else note


def is_stopped(value) -> bool:
    """Whether a summary value is the words of :func:`not_applicable` (not a number)."""
    return isinstance(value, str) and value.startswith(NOT_APPLICABLE)


def without_stopping_angles(summary: dict, stop: str | None) -> dict:
    """A copy of a run's summary whose keys of :data:`STOPPED_KEYS` (and their bands)
    say :func:`not_applicable` where the run stopped (``stop``); the summary itself where it
    did not."""
    note = not_applicable(stop)
    if note is None:
        return summary
    out = {k: (note if k in STOPPED_KEYS else v) for k, v in summary.items()}
    if isinstance(summary.get("bands"), dict):
        out["bands"] = {k: (note if k in STOPPED_KEYS else v) for k, v in summary["bands"].items()}
    return out
