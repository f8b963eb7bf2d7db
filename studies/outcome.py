"""What happens to the column, and the three answers: the part of summary.json that every
report opens with (``summary["outcome"]``).

``models``: per model, how the column moved (``overturned``, ``rocking``: it uplifted and stayed
up, ``no uplift``: :func:`colonna.rigid.solve.motion_word`), the time the run detected an
overturning (a stopping convention, named as such: the instant the centre of mass passed the
toe moving outward after the ground motion, not a collapse time) and, for the FEM ensemble, how
many replicas overturned.

``answers``: "Is the rigid-body assumption good enough?", "Do the collars yield?", "Does the
toe crush?", each yes / no / undecided / not assessed, with the number behind it (median and
band over the replicas), its limit, the relation between them (``stays below``, ``reaches``,
``straddles``) and the figure that shows it. The word and the relation come from one comparison
(:func:`limit_answer`), so the sentence can never contradict its number. A study that follows
the collars past f_y also answers "Do the collars hold?" (:func:`collars_hold`: did a plastic
collar's extreme fibre reach its fracture strain?): the cross-check always, the studies whose
FEM runs alone (:func:`fem_answers`) where a collar is plastic; the others leave it out.
"""

from __future__ import annotations

from ..fem.ensemble import NO, UNDECIDED, YES, decide
from ..rigid.solve import collar_state, motion_word

NOT_ASSESSED = "not assessed"

QUESTIONS = {
    "rigid_assumption_ok": "Is the rigid-body assumption good enough?",
    "collars_yield": "Do the collars yield?",
    "collars_hold": "Do the collars hold?",
    "toe_crushes": "Does the toe crush?",
}
# answered only by the studies that ask them (listed where given, left out otherwise)
OPTIONAL_QUESTIONS = ("collars_hold",)

# why "Do the collars hold?" has no answer for elastic collars
ELASTIC_COLLARS_NOT_FOLLOWED = "elastic collars are not followed past f_y (set plastic = true)"

# how each answer word relates the band to its limit (the relation is the comparison's
# result, named; see limit_answer)
RELATIONS = {YES: "reaches", NO: "stays below", UNDECIDED: "straddles"}


def model_outcome(
    model: str,
    overturned: bool,
    peak_rotation: float | None,
    alpha: float,
    overturn_time: float | None = None,
    replicas: int | None = None,
    overturned_replicas: int | None = None,
    collar_utilisation: float | None = None,
    collar_fractured: bool = False,
) -> dict:
    """One model's outcome. ``peak_rotation`` (rad) is the largest |theta| of a rocking half
    (None or the pi/2 convention of an overturned block are not reported as a rotation);
    ``alpha`` its slenderness (rad); ``collar_utilisation`` the largest sigma / f_y of its
    collars, whose state (elastic / yielded, or fractured where ``collar_fractured``: a
    plastic collar broke) is then said beside the motion."""
    motion = motion_word(bool(overturned), 0.0 if peak_rotation is None else peak_rotation, alpha)
    out = {
        "model": model,
        "motion": motion,
        "overturn_time": float(overturn_time) if overturned and overturn_time is not None else None,
        "peak_rotation": None if overturned or peak_rotation is None else float(peak_rotation),
        "peak_rotation_over_alpha": None
        if overturned or peak_rotation is None
        else float(peak_rotation) / alpha,
    }
    if replicas is not None:
        out.update(replicas=int(replicas), overturned_replicas=int(overturned_replicas or 0))
    if collar_utilisation is not None:
        out.update(
            collar_state=collar_state(collar_utilisation, fractured=bool(collar_fractured)),
            collar_utilisation=float(collar_utilisation),
        )
    return out


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


def outcome(models: list[dict], answers: dict[str, dict]) -> dict:
    """summary["outcome"]: the models' outcomes and the answers, in QUESTIONS' order (every
    question but the OPTIONAL_QUESTIONS, which are listed where ``answers`` has them)."""
    return {
        "models": models,
        "answers": [
            dict(answers[key], key=key)
            for key in QUESTIONS
            if key in answers or key not in OPTIONAL_QUESTIONS
        ],
    }


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
            "largest toe stress / f_c (study mesh, not refined)",
            fem["bands"].get("edge_stress_ratio"),
            1.0,
            "-",
        ),
    }
    if any(c.plastic for c in collars):
        answers["collars_hold"] = collars_hold(fem, collars)
    return answers


def fem_model(model: str, fem: dict, alpha: float) -> dict:
    """:func:`model_outcome` of an FEM ensemble summary."""
    return model_outcome(
        model,
        fem["overturned"],
        max(fem["max_abs_theta_left"], fem["max_abs_theta_right"]),
        alpha,
        fem.get("t_end"),
        fem.get("replicas", 1),
        fem.get("overturned_replicas", int(bool(fem["overturned"]))),
    )
